// SPDX-License-Identifier: GPL-3.0-or-later
// The saved scan binding (.ckb, sdk/multires/binding_file.h): a reloaded binding equals the
// saved one bit for bit (foot points, displacements, rows, compact table) and deforms the same;
// damaged files are refused with an Error, never a crash.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "core/status.h"
#include "fit/surface_fitter.h"
#include "multires/binding_file.h"
#include "multires/cpu_deformer.h"
#include "subdiv/uniform_refinement.h"
#include "test_support.h"

using namespace cagekit;

namespace {

// A bumpy sphere and a fitted cube cage (refined once), optionally with the cube's 12 edges
// (their level-1 halves) tagged sharp, so Gregory end caps and crease patches are exercised.
struct BoundScan {
  PolygonMesh scan;
  Cage cage;
};

BoundScan make_setup(bool creased) {
  BoundScan s;
  s.scan = cagekit_test::triangle_sphere(4);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> bump(-0.01, 0.01);
  for (Vec3& p : s.scan.positions) p = p * (1.0 + bump(rng) + 0.05 * p.x * p.y);
  Cage cube = cagekit_test::creased_unit_cube();
  if (!creased) cube.creases.clear();
  for (Vec3& p : cube.mesh.positions) p = (p - Vec3{0.5, 0.5, 0.5}) * 1.2;
  RefineOptions once;
  once.levels = 1;
  FitOptions fit;
  fit.max_passes = 2;
  s.cage = fit_cage_to_mesh(refine_uniform(cube, once), s.scan, fit);
  return s;
}

void expect_same(const ScanBinding& a, const ScanBinding& b) {
  ASSERT_EQ(a.num_vertices(), b.num_vertices());
  EXPECT_EQ(a.num_control_vertices, b.num_control_vertices);
  EXPECT_EQ(a.mode, b.mode);
  for (size_t i = 0; i < a.num_vertices(); ++i) {
    const FootPoint &x = a.foot_points[i], &y = b.foot_points[i];
    ASSERT_TRUE(x.ptex_face == y.ptex_face && x.u == y.u && x.v == y.v && x.distance == y.distance &&
                x.position.x == y.position.x && x.position.y == y.position.y && x.position.z == y.position.z &&
                x.steps == y.steps && x.converged == y.converged)
        << "foot point " << i;
  }
  EXPECT_EQ(a.displacement, b.displacement);
  EXPECT_EQ(a.tangent_offset, b.tangent_offset);
  EXPECT_EQ(a.normal_coefficients, b.normal_coefficients);
  EXPECT_EQ(a.displacement_gradient, b.displacement_gradient);
  EXPECT_EQ(a.row_offsets, b.row_offsets);
  EXPECT_EQ(a.control_index, b.control_index);
  EXPECT_EQ(a.phi, b.phi);
  EXPECT_EQ(a.phi_u, b.phi_u);
  EXPECT_EQ(a.phi_v, b.phi_v);
  EXPECT_EQ(a.phi_uu, b.phi_uu);
  EXPECT_EQ(a.phi_uv, b.phi_uv);
  EXPECT_EQ(a.phi_vv, b.phi_vv);
  EXPECT_EQ(a.max_sideways_residual, b.max_sideways_residual);
  EXPECT_EQ(a.vertices_with_sideways_residual, b.vertices_with_sideways_residual);
  EXPECT_EQ(a.bbox_diagonal, b.bbox_diagonal);
  const PatchDeformerTable &p = a.compact, &q = b.compact;
  EXPECT_EQ(p.cell_vertex_offsets, q.cell_vertex_offsets);
  EXPECT_EQ(p.cell_term_offsets, q.cell_term_offsets);
  EXPECT_EQ(p.term_control, q.term_control);
  EXPECT_EQ(p.term_coefficients, q.term_coefficients);
  EXPECT_EQ(p.vertex, q.vertex);
  EXPECT_EQ(p.s, q.s);
  EXPECT_EQ(p.t, q.t);
  EXPECT_EQ(p.displacement, q.displacement);
  EXPECT_EQ(p.irregular_vertex, q.irregular_vertex);
  EXPECT_EQ(p.irregular_w, q.irregular_w);
}

}  // namespace

TEST(BindingFile, reloaded_binding_is_identical_and_deforms_the_same) {
  for (bool creased : {false, true}) {
    const BoundScan s = make_setup(creased);
    for (DisplacementMode mode : {DisplacementMode::normal, DisplacementMode::local_frame})
      for (bool exact : {false, true}) {
        BindOptions options;
        options.mode = mode;
        options.exact_normals = exact;
        const ScanBinding bound = bind_scan_to_cage(s.cage, s.scan, options);
        const std::vector<uint8_t> bytes = write_binding(bound, s.cage, options);
        const SavedBinding loaded = read_binding(bytes.data(), bytes.size(), "test.ckb");
        std::printf("%s cage, %s mode%s: %zu vertices -> %zu bytes (%.1f per vertex), %zu cells\n",
                    creased ? "creased" : "smooth", mode == DisplacementMode::normal ? "normal" : "local-frame",
                    exact ? ", exact normals" : "", bound.num_vertices(), bytes.size(),
                    double(bytes.size()) / double(bound.num_vertices()), loaded.binding.compact.num_cells());
        EXPECT_EQ(loaded.cage.mesh.positions.size(), s.cage.mesh.positions.size());
        for (size_t j = 0; j < s.cage.mesh.positions.size(); ++j) {
          EXPECT_EQ(loaded.cage.mesh.positions[j].x, s.cage.mesh.positions[j].x);
          EXPECT_EQ(loaded.cage.mesh.positions[j].y, s.cage.mesh.positions[j].y);
          EXPECT_EQ(loaded.cage.mesh.positions[j].z, s.cage.mesh.positions[j].z);
        }
        EXPECT_EQ(loaded.cage.mesh.face_vertices, s.cage.mesh.face_vertices);
        EXPECT_EQ(loaded.cage.creases.size(), s.cage.creases.size());
        EXPECT_EQ(loaded.options.mode, mode);
        EXPECT_EQ(loaded.options.exact_normals, exact);
        expect_same(bound, loaded.binding);
        // Same deformation for moved control points.
        std::vector<Vec3> control = s.cage.mesh.positions;
        for (size_t j = 0; j < control.size(); j += 5) control[j] += Vec3{0.05, -0.02, 0.03};
        CpuDeformer d0(bound, 1), d1(loaded.binding, 2);
        std::vector<Vec3> p0(bound.num_vertices()), n0(p0.size()), p1(p0.size()), n1(p0.size());
        d0.deform(control, p0.data(), n0.data());
        d1.deform(control, p1.data(), n1.data());
        double worst = 0;
        for (size_t i = 0; i < p0.size(); ++i) worst = std::max({worst, norm(p0[i] - p1[i]), norm(n0[i] - n1[i])});
        EXPECT_EQ(worst, 0.0);
        // Writing the reloaded binding gives the same bytes.
        EXPECT_EQ(write_binding(loaded.binding, loaded.cage, loaded.options), bytes);
      }
  }
}

TEST(BindingFile, sector_split_round_trips) {
  // A refined creased cube: a box with sharp edges, bound with one vertex per smooth sector.
  const Cage cube = cagekit_test::creased_unit_cube();
  RefineOptions two;
  two.levels = 2;
  const PolygonMesh box = refine_uniform(cube, two).mesh;
  BindOptions options;
  options.sharp_angle_degrees = 30;
  const ScanBinding bound = bind_scan_to_cage(cube, box, options);
  ASSERT_GT(bound.num_vertices(), box.num_vertices());
  const std::vector<uint8_t> bytes = write_binding(bound, cube, options);
  const SavedBinding loaded = read_binding(bytes.data(), bytes.size(), "box.ckb");
  expect_same(bound, loaded.binding);
  EXPECT_EQ(loaded.binding.source_vertex, bound.source_vertex);
  EXPECT_EQ(loaded.binding.face_offsets, bound.face_offsets);
  EXPECT_EQ(loaded.binding.face_vertices, bound.face_vertices);
  EXPECT_EQ(loaded.binding.scan_vertex_count, box.num_vertices());
  EXPECT_EQ(loaded.options.sharp_angle_degrees, 30.0);
  EXPECT_EQ(write_binding(loaded.binding, loaded.cage, loaded.options), bytes);
  // A copy that points at a later vertex is refused.
  std::vector<uint8_t> bad = bytes;
  const char sect[4] = {'S', 'E', 'C', 'T'};
  size_t at = 16;
  for (;;) {
    uint64_t n;
    std::memcpy(&n, &bad[at + 4], 8);
    if (std::memcmp(&bad[at], sect, 4) == 0) break;
    at += 12 + size_t(n);
  }
  const size_t last_source = at + 12 + 8 + 4 * (bound.num_vertices() - 1);
  const uint32_t later = uint32_t(bound.num_vertices());
  std::memcpy(&bad[last_source], &later, 4);
  EXPECT_THROW(read_binding(bad.data(), bad.size(), "bad.ckb"), Error);
}

TEST(BindingFile, damaged_files_are_refused_without_a_crash) {
  const BoundScan s = make_setup(true);
  BindOptions options;
  options.mode = DisplacementMode::local_frame;
  const ScanBinding bound = bind_scan_to_cage(s.cage, s.scan, options);
  const std::vector<uint8_t> bytes = write_binding(bound, s.cage, options);
  auto refused = [](const std::vector<uint8_t>& data, Status* status = nullptr) {
    try {
      read_binding(data.data(), data.size(), "bad.ckb", 1);
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("bad.ckb"), std::string::npos) << e.what();
      if (status) *status = e.status();
      return true;
    }
    return false;
  };
  // Every truncation of the header and the first sections, then a stride through the rest.
  size_t truncations = 0;
  for (size_t len = 0; len < bytes.size(); len += len < 4096 ? 1 : 997, ++truncations)
    EXPECT_TRUE(refused(std::vector<uint8_t>(bytes.begin(), bytes.begin() + long(len)))) << "length " << len;
  // Seeded single-byte corruptions: refused or read, never a crash (ASan/UBSan in CI).
  std::mt19937 rng(11);
  size_t refused_count = 0;
  for (int k = 0; k < 300; ++k) {
    std::vector<uint8_t> bad = bytes;
    bad[std::uniform_int_distribution<size_t>(0, bad.size() - 1)(rng)] ^= uint8_t(1 + rng() % 255);
    refused_count += refused(bad);
  }
  std::printf("%zu truncations refused; %zu of 300 corruptions refused (the rest decode to another valid binding)\n",
              truncations, refused_count);
  // Specific damage, with the status it must give.
  Status status{};
  std::vector<uint8_t> bad = bytes;
  bad[0] = 'X';
  EXPECT_TRUE(refused(bad, &status));
  EXPECT_EQ(status, Status::parse_error);
  bad = bytes;
  bad[8] = 2;  // version
  EXPECT_TRUE(refused(bad, &status));
  EXPECT_EQ(status, Status::unsupported_format);
  // The first foot point's u: NaN, then 1.5.
  auto vert_payload = [&]() {
    size_t at = 16;
    for (;;) {
      uint32_t t;
      uint64_t n;
      std::memcpy(&t, &bytes[at], 4), std::memcpy(&n, &bytes[at + 4], 8);
      if (std::memcmp(&bytes[at], "VERT", 4) == 0) return at + 12;
      at += 12 + size_t(n);
    }
  };
  const size_t vert = vert_payload(), n = bound.num_vertices();
  const size_t first_u = vert + 8 + 12 * n;
  for (double value : {std::nan(""), 1.5, -0.25}) {
    bad = bytes;
    std::memcpy(&bad[first_u], &value, 8);
    EXPECT_TRUE(refused(bad, &status));
    EXPECT_EQ(status, Status::parse_error);
  }
  // A ptex face beyond the surface's.
  bad = bytes;
  const uint32_t far = 1u << 30;
  std::memcpy(&bad[vert + 8], &far, 4);
  EXPECT_TRUE(refused(bad, &status));
  EXPECT_EQ(status, Status::parse_error);
  // A hostile vertex count.
  bad = bytes;
  const uint64_t huge = uint64_t(1) << 40;
  std::memcpy(&bad[vert], &huge, 8);
  EXPECT_TRUE(refused(bad, &status));
  EXPECT_EQ(status, Status::limit_exceeded);
}
