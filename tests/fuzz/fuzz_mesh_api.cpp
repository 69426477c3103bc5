// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer harness: the C API on arbitrary mesh content. The bytes are read as
//   [nv] [nf] [flags] [weld] then 3*nv position codes, then per face a size code and indices,
//   then optional tag bytes;
// (positions include NaN, +-Inf, huge and denormal values; indices may be out of range; faces
// may have 0..2 vertices), capped so that sizes stay small. Then:
//   cagekit_mesh_create -> validate -> info -> repair -> validate -> cage_create (when valid)
//   -> tags -> subdivide 1 level -> limit points -> release everything.
// Must never crash, trip a sanitizer or leak; INVALID_INTERNAL is treated as a bug.
#include <cagekit/cagekit.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace {

class Input {
 public:
  Input(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  bool empty() const { return pos_ >= size_; }
  uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
};

double coordinate(uint8_t code) {
  switch (code) {
    case 255: return std::numeric_limits<double>::quiet_NaN();
    case 254: return std::numeric_limits<double>::infinity();
    case 253: return -std::numeric_limits<double>::infinity();
    case 252: return 1e300;
    case 251: return -1e300;
    case 250: return std::numeric_limits<double>::denorm_min();
    case 249: return 1e-12;
    default: return (static_cast<int>(code) - 124) / 16.0;
  }
}

#define FUZZ_CHECK(cond) \
  do {                   \
    if (!(cond)) __builtin_trap(); \
  } while (0)

// A status the API may return for hostile input; INTERNAL is a bug.
void check_status(cagekit_status s) { FUZZ_CHECK(s != CAGEKIT_ERROR_INTERNAL); }

void exercise_cage(cagekit_cage cage, Input& in, uint32_t nv, uint32_t nf, uint8_t flags) {
  // Tags from the remaining bytes (may be invalid: the setters must refuse them cleanly).
  const uint32_t ncrease = in.byte() % 5, ncorner = in.byte() % 4, nhole = in.byte() % 3;
  std::vector<uint32_t> pairs, corners, holes;
  std::vector<float> crease_sharp, corner_sharp;
  for (uint32_t i = 0; i < ncrease; ++i) {
    pairs.push_back(in.byte() % (nv + 1));
    pairs.push_back(in.byte() % (nv + 1));
    const uint8_t s = in.byte();
    crease_sharp.push_back(s == 255 ? NAN : s == 254 ? -1.0f : static_cast<float>(s % 24) * 0.5f);
  }
  for (uint32_t i = 0; i < ncorner; ++i) {
    corners.push_back(in.byte() % (nv + 1));
    corner_sharp.push_back(static_cast<float>(in.byte() % 24) * 0.5f);
  }
  for (uint32_t i = 0; i < nhole; ++i) holes.push_back(in.byte() % (nf + 1));
  if (ncrease) check_status(cagekit_cage_set_creases(cage, ncrease, pairs.data(), crease_sharp.data()));
  if (ncorner) check_status(cagekit_cage_set_corners(cage, ncorner, corners.data(), corner_sharp.data()));
  if (nhole) check_status(cagekit_cage_set_holes(cage, nhole, holes.data()));
  check_status(cagekit_cage_set_boundary_rule(
      cage, (flags & 0x20) ? CAGEKIT_BOUNDARY_EDGES_AND_CORNERS : CAGEKIT_BOUNDARY_EDGES_ONLY));

  cagekit_mesh_info info = {};
  info.struct_size = sizeof info;
  check_status(cagekit_cage_get_info(cage, &info));

  cagekit_subdivide_options sub = CAGEKIT_SUBDIVIDE_OPTIONS_INIT;
  sub.levels = 1;
  sub.limit_positions = (flags & 0x40) ? 1 : 0;
  cagekit_cage refined = nullptr;
  const cagekit_status s = cagekit_cage_subdivide(cage, &sub, &refined);
  check_status(s);
  if (CAGEKIT_SUCCEEDED(s)) {
    FUZZ_CHECK(refined != nullptr);
    uint32_t count = 0;
    check_status(cagekit_cage_get_limit_points(refined, 0, &count, nullptr, nullptr));
    cagekit_cage_release(refined);
  }
  if (flags & 0x80) {
    std::vector<double> pos(3 * static_cast<size_t>(nv) + 3), nrm(3 * static_cast<size_t>(nv) + 3);
    uint32_t count = 0;
    check_status(cagekit_cage_get_limit_points(cage, nv + 1, &count, pos.data(), nrm.data()));
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Input in(data, size);
  const uint32_t nv = in.byte() % 41;   // <= 40 vertices
  const uint32_t nf = in.byte() % 33;   // <= 32 faces
  const uint8_t flags = in.byte();
  const uint8_t weld = in.byte();

  std::vector<double> positions64(3 * static_cast<size_t>(nv));
  for (double& x : positions64) x = coordinate(in.byte());
  std::vector<float> positions32(positions64.begin(), positions64.end());

  static const uint32_t kSizes[16] = {3, 3, 3, 3, 4, 4, 4, 4, 5, 6, 3, 4, 0, 1, 2, 8};
  std::vector<uint32_t> sizes(nf), indices;
  for (uint32_t f = 0; f < nf; ++f) {
    sizes[f] = kSizes[in.byte() % 16];
    for (uint32_t c = 0; c < sizes[f]; ++c) {
      const uint8_t b = in.byte();
      // Mostly in range; 1 in 32 is out of range (nv, or a huge index).
      indices.push_back(b >= 248 ? (b == 255 ? 0xffffffffu : nv + (b & 3)) : (nv ? b % nv : b));
    }
  }

  cagekit_context_desc cdesc = CAGEKIT_CONTEXT_DESC_INIT;
  cagekit_context context = nullptr;
  if (CAGEKIT_FAILED(cagekit_context_create(&cdesc, &context))) __builtin_trap();

  cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
  desc.vertex_count = nv;
  const bool use_float = flags & 1;
  desc.positions = nv ? (use_float ? static_cast<const void*>(positions32.data()) : positions64.data()) : nullptr;
  desc.position_type = use_float ? CAGEKIT_SCALAR_FLOAT32 : CAGEKIT_SCALAR_FLOAT64;
  desc.face_count = nf;
  const bool uniform = (flags & 2) && nf > 0;
  desc.face_sizes = uniform ? nullptr : (nf ? sizes.data() : nullptr);
  desc.uniform_face_size = uniform ? sizes[0] : 3;
  if (uniform) {  // re-cut the index list to the uniform size
    indices.resize(static_cast<size_t>(nf) * sizes[0], 0);
    for (uint32_t& i : indices)
      if (nv && i >= nv && i != 0xffffffffu) i %= nv;
  }
  desc.face_indices = indices.empty() ? nullptr : indices.data();

  cagekit_mesh mesh = nullptr;
  cagekit_status s = cagekit_mesh_create(context, &desc, &mesh);
  check_status(s);
  if (CAGEKIT_SUCCEEDED(s)) {
    cagekit_validation_report report = {};
    report.struct_size = sizeof report;
    const cagekit_status valid = cagekit_mesh_validate(mesh, &report);
    check_status(valid);

    cagekit_mesh_info info = {};
    info.struct_size = sizeof info;
    check_status(cagekit_mesh_get_info(mesh, &info));

    cagekit_repair_options ropt = CAGEKIT_REPAIR_OPTIONS_INIT;
    ropt.steps = (flags & 4) ? CAGEKIT_REPAIR_DEFAULT : ((flags >> 3) & 0x3) | CAGEKIT_REPAIR_DEFAULT;
    if (flags & 0x10) ropt.steps = weld & 0x7f;  // any subset of the steps
    ropt.weld_tolerance = (weld & 0x80) ? (weld & 0x7f) / 64.0 : 0.0;
    cagekit_repair_report rrep = {};
    rrep.struct_size = sizeof rrep;
    cagekit_mesh repaired = nullptr;
    s = cagekit_mesh_repair(mesh, &ropt, &repaired, &rrep);
    check_status(s);

    cagekit_mesh cage_source = CAGEKIT_SUCCEEDED(valid) ? mesh : nullptr;
    if (CAGEKIT_SUCCEEDED(s)) {
      FUZZ_CHECK(repaired != nullptr);
      cagekit_validation_report rreport = {};
      rreport.struct_size = sizeof rreport;
      const cagekit_status rvalid = cagekit_mesh_validate(repaired, &rreport);
      check_status(rvalid);
      // With every step enabled, the repaired mesh is valid.
      if (ropt.steps == CAGEKIT_REPAIR_DEFAULT) FUZZ_CHECK(CAGEKIT_SUCCEEDED(rvalid));
      if (CAGEKIT_SUCCEEDED(rvalid) && !(flags & 0x08)) cage_source = repaired;
    }

    if (cage_source) {
      uint32_t cnv = 0, cnf = 0;
      check_status(cagekit_mesh_get_counts(cage_source, &cnv, &cnf, nullptr));
      cagekit_cage cage = nullptr;
      const cagekit_status cs = cagekit_cage_create(cage_source, &cage);
      check_status(cs);
      if (CAGEKIT_SUCCEEDED(cs)) {
        exercise_cage(cage, in, cnv, cnf, flags);
        cagekit_cage_release(cage);
      }
    }
    if (repaired) cagekit_mesh_release(repaired);
    cagekit_mesh_release(mesh);
  }
  cagekit_context_release(context);
  return 0;
}
