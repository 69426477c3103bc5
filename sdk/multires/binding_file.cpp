// SPDX-License-Identifier: GPL-3.0-or-later
#include "multires/binding_file.h"

#include <cmath>
#include <cstring>
#include <memory>

#include "core/io/mesh_io.h"
#include "core/memory_budget.h"
#include "core/parallel_for.h"
#include "core/status.h"
#include "multires/basis_rows.h"
#include "subdiv/subdivision_surface.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

constexpr char kMagic[8] = {'C', 'A', 'G', 'E', 'K', 'I', 'T', 'B'};
constexpr uint32_t kVersion = 1;
constexpr uint32_t tag(const char (&s)[5]) {
  return uint32_t(uint8_t(s[0])) | uint32_t(uint8_t(s[1])) << 8 | uint32_t(uint8_t(s[2])) << 16 |
         uint32_t(uint8_t(s[3])) << 24;
}
constexpr uint32_t kCage = tag("CAGE"), kOptions = tag("OPTS"), kVertices = tag("VERT"), kSectors = tag("SECT");
constexpr uint64_t kMaxVertices = uint64_t(1) << 28;

class Writer {
 public:
  void u32(uint32_t v) {
    for (int k = 0; k < 4; ++k) out.push_back(uint8_t(v >> (8 * k)));
  }
  void u64(uint64_t v) {
    for (int k = 0; k < 8; ++k) out.push_back(uint8_t(v >> (8 * k)));
  }
  void f64(double d) {
    uint64_t v;
    std::memcpy(&v, &d, 8);
    u64(v);
  }
  void bytes(const uint8_t* p, size_t n) { out.insert(out.end(), p, p + n); }
  // A section: tag, payload size (patched when the section ends), payload.
  size_t begin(uint32_t t) {
    u32(t);
    const size_t at = out.size();
    u64(0);
    return at;
  }
  void end(size_t at) {
    const uint64_t n = out.size() - at - 8;
    for (int k = 0; k < 8; ++k) out[at + size_t(k)] = uint8_t(n >> (8 * k));
  }
  std::vector<uint8_t> out;
};

class Reader {
 public:
  Reader(const uint8_t* data, size_t size, const std::string& source, size_t base = 0)
      : data_(data), size_(size), source_(source), base_(base) {}
  [[noreturn]] void error(Status status, const std::string& message) const {
    fail(status, source_ + ": byte " + std::to_string(base_ + at_) + ": " + message);
  }
  size_t remaining() const { return size_ - at_; }
  size_t offset() const { return base_ + at_; }
  void need(uint64_t n, const char* what) const {
    if (n > remaining()) error(Status::parse_error, std::string("truncated ") + what);
  }
  // A little-endian unsigned integer of sizeof(T) bytes.
  template <class T>
  T little_endian(const char* what) {
    need(sizeof(T), what);
    T v = 0;
    for (size_t k = 0; k < sizeof(T); ++k) v |= T(data_[at_ + k]) << (8 * k);
    at_ += sizeof(T);
    return v;
  }
  uint32_t u32(const char* what) { return little_endian<uint32_t>(what); }
  uint64_t u64(const char* what) { return little_endian<uint64_t>(what); }
  double f64(const char* what) {
    const uint64_t v = u64(what);
    double d;
    std::memcpy(&d, &v, 8);
    if (!std::isfinite(d)) {
      at_ -= 8;
      error(Status::parse_error, std::string(what) + " is not finite");
    }
    return d;
  }
  const uint8_t* take(size_t n, const char* what) {
    need(n, what);
    const uint8_t* p = data_ + at_;
    at_ += n;
    return p;
  }

 private:
  const uint8_t* data_;
  size_t size_, at_ = 0;
  const std::string& source_;
  size_t base_;
};

}  // namespace

std::vector<uint8_t> write_binding(const ScanBinding& b, const Cage& cage, const BindOptions& options) {
  const size_t n = b.num_vertices();
  const bool local = b.mode == DisplacementMode::local_frame, exact = !b.displacement_gradient.empty();
  if (cage.mesh.num_vertices() != b.num_control_vertices || b.displacement.size() != n ||
      b.normal_coefficients.size() != 6 * n || (local && b.tangent_offset.size() != 2 * n) ||
      (exact && b.displacement_gradient.size() != 2 * n))
    fail(Status::invalid_argument, "write binding: the binding does not match its cage or is incomplete");
  const bool sectors = !b.source_vertex.empty();
  if (sectors && (b.source_vertex.size() != n || b.face_offsets.empty() || b.face_offsets.back() != b.face_vertices.size()))
    fail(Status::invalid_argument, "write binding: inconsistent sector split");
  Writer w;
  w.bytes(reinterpret_cast<const uint8_t*>(kMagic), sizeof(kMagic));
  w.u32(kVersion);
  w.u32(sectors ? 4 : 3);
  {
    WriteOptions obj;
    obj.format = FileFormat::obj;
    obj.obj_precision = 17;  // %.17g: every double round-trips exactly
    const std::vector<uint8_t> text = write_cage_to_memory(cage, obj);
    const size_t at = w.begin(kCage);
    w.bytes(text.data(), text.size());
    w.end(at);
  }
  {
    const size_t at = w.begin(kOptions);
    w.u32(local ? 1 : 0);
    w.u32(exact ? 1 : 0);
    w.u32(options.compact_table ? 1 : 0);
    w.u32(uint32_t(options.surface.isolation_level));
    w.u32(uint32_t(options.surface.sharp_extraordinary_isolation_level));
    w.u32(uint32_t(options.patch_table.max_depth));
    w.u32(options.patch_table.min_split_vertices);
    w.f64(options.patch_table.tolerance);
    w.u32(b.num_control_vertices);
    w.f64(b.bbox_diagonal);
    w.f64(b.max_sideways_residual);
    w.u64(b.vertices_with_sideways_residual);
    w.f64(sectors ? options.sharp_angle_degrees : -1.0);
    w.end(at);
  }
  if (sectors) {
    const size_t at = w.begin(kSectors);
    w.u64(b.scan_vertex_count);
    for (uint32_t v : b.source_vertex) w.u32(v);
    w.u64(b.face_offsets.size() - 1);
    for (uint32_t o : b.face_offsets) w.u32(o);
    for (uint32_t v : b.face_vertices) w.u32(v);
    w.end(at);
  }
  {
    const size_t at = w.begin(kVertices);
    w.u64(n);
    for (const FootPoint& t : b.foot_points) w.u32(t.ptex_face);
    for (const FootPoint& t : b.foot_points) w.u32(t.steps);
    for (const FootPoint& t : b.foot_points) w.u32(t.converged ? 1 : 0);
    for (const FootPoint& t : b.foot_points) w.f64(t.u), w.f64(t.v), w.f64(t.distance);
    for (const FootPoint& t : b.foot_points) w.f64(t.position.x), w.f64(t.position.y), w.f64(t.position.z);
    for (double d : b.displacement) w.f64(d);
    for (double d : b.normal_coefficients) w.f64(d);
    if (local)
      for (double d : b.tangent_offset) w.f64(d);
    if (exact)
      for (double d : b.displacement_gradient) w.f64(d);
    w.end(at);
  }
  return std::move(w.out);
}

SavedBinding read_binding(const uint8_t* data, size_t size, const std::string& source_name, int threads,
                          const TaskMonitor& monitor) {
  if (!data && size > 0) fail(Status::invalid_argument, "read binding: data is null");
  if (threads < 0) fail(Status::invalid_argument, "read binding: threads must be >= 0");
  Reader r(data, size, source_name);
  if (size < sizeof(kMagic) || std::memcmp(data, kMagic, sizeof(kMagic)) != 0)
    fail(Status::parse_error, source_name + ": not a CageKit binding file (no CAGEKITB magic)");
  r.take(sizeof(kMagic), "magic");
  const uint32_t version = r.u32("version");
  if (version != kVersion)
    r.error(Status::unsupported_format, "binding file version " + std::to_string(version) + " (this library reads " +
                                            std::to_string(kVersion) + ")");
  const uint32_t sections = r.u32("section count");
  if (sections > 64) r.error(Status::limit_exceeded, "more than 64 sections");

  SavedBinding saved;
  BindOptions& options = saved.options;
  ScanBinding& b = saved.binding;
  bool have_cage = false, have_options = false, have_vertices = false, have_sectors = false, local = false,
       exact = false;
  const uint8_t* sector_data = nullptr;
  size_t sector_size = 0, sector_offset = 0;
  const uint8_t* vertex_data = nullptr;
  size_t vertex_size = 0, vertex_offset = 0;
  for (uint32_t s = 0; s < sections; ++s) {
    const uint32_t t = r.u32("section tag");
    const uint64_t length = r.u64("section size");
    r.need(length, "section");
    const size_t payload_offset = r.offset();
    const uint8_t* payload = r.take(size_t(length), "section");
    Reader p(payload, size_t(length), source_name, payload_offset);
    auto once = [&](bool& seen, const char* name) {
      if (seen) p.error(Status::parse_error, std::string("second ") + name + " section");
      seen = true;
    };
    if (t == kCage) {
      once(have_cage, "CAGE");
      saved.cage = read_cage_from_memory(payload, size_t(length), FileFormat::obj, source_name + " (cage)");
    } else if (t == kOptions) {
      once(have_options, "OPTS");
      const uint32_t mode = p.u32("mode"), exact_flag = p.u32("exact_normals"), compact = p.u32("compact_table");
      if (mode > 1 || exact_flag > 1 || compact > 1) p.error(Status::parse_error, "option flag not 0 or 1");
      local = mode == 1, exact = exact_flag == 1;
      options.mode = local ? DisplacementMode::local_frame : DisplacementMode::normal;
      options.exact_normals = exact;
      options.compact_table = compact == 1;
      const uint32_t iso = p.u32("isolation level"), sharp_iso = p.u32("sharp isolation level");
      if (iso < 1 || iso > uint32_t(kMaxIsolationLevel) || sharp_iso < 1 || sharp_iso > uint32_t(kMaxIsolationLevel))
        p.error(Status::parse_error, "isolation levels must be in [1, " + std::to_string(kMaxIsolationLevel) + "]");
      options.surface.isolation_level = int(iso);
      options.surface.sharp_extraordinary_isolation_level = int(sharp_iso);
      const uint32_t depth = p.u32("patch table depth");
      if (depth > 20) p.error(Status::parse_error, "patch table depth above 20");
      options.patch_table.max_depth = int(depth);
      options.patch_table.min_split_vertices = p.u32("patch table split size");
      options.patch_table.tolerance = p.f64("patch table tolerance");
      if (!(options.patch_table.tolerance > 0)) p.error(Status::parse_error, "patch table tolerance must be > 0");
      b.num_control_vertices = p.u32("control vertex count");
      b.bbox_diagonal = p.f64("bbox diagonal");
      b.max_sideways_residual = p.f64("sideways residual");
      const uint64_t sideways = p.u64("sideways vertex count");
      if (b.bbox_diagonal < 0 || b.max_sideways_residual < 0 || sideways > kMaxVertices)
        p.error(Status::parse_error, "negative or oversized summary figures");
      b.vertices_with_sideways_residual = size_t(sideways);
      const double angle = p.f64("sharp angle");
      if (!(angle < 0) && !(angle <= 180)) p.error(Status::parse_error, "sharp angle outside [0, 180]");
      options.sharp_angle_degrees = angle < 0 ? -1.0 : angle;
    } else if (t == kSectors) {
      once(have_sectors, "SECT");
      sector_data = payload, sector_size = size_t(length), sector_offset = payload_offset;
    } else if (t == kVertices) {
      once(have_vertices, "VERT");
      vertex_data = payload, vertex_size = size_t(length), vertex_offset = payload_offset;
    }  // other tags: a later version's sections, skipped
  }
  if (!have_cage || !have_options || !have_vertices)
    fail(Status::parse_error, source_name + ": missing " +
                                  std::string(!have_cage ? "CAGE" : !have_options ? "OPTS" : "VERT") + " section");
  if (saved.cage.mesh.num_vertices() != b.num_control_vertices)
    fail(Status::parse_error, source_name + ": the cage has " + std::to_string(saved.cage.mesh.num_vertices()) +
                                  " vertices, the binding " + std::to_string(b.num_control_vertices));
  b.mode = options.mode;

  // Per-vertex arrays (decoded once the options say which are present).
  Reader p(vertex_data, vertex_size, source_name, vertex_offset);
  const uint64_t n64 = p.u64("vertex count");
  const uint64_t per_vertex = 12 + 6 * 8 + (1 + 6) * 8 + (local ? 16 : 0) + (exact ? 16 : 0);
  if (n64 == 0) p.error(Status::parse_error, "no vertices");
  if (n64 > kMaxVertices) p.error(Status::limit_exceeded, std::to_string(n64) + " vertices (limit 2^28)");
  if (n64 * per_vertex > p.remaining())
    p.error(Status::parse_error, std::to_string(n64) + " vertices do not fit the section");
  const size_t n = size_t(n64);
  check_memory_estimate(estimate_product(n, exact ? 2200 : 1200), "reading the binding");
  b.foot_points.resize(n);
  for (FootPoint& f : b.foot_points) f.ptex_face = p.u32("ptex face");
  for (FootPoint& f : b.foot_points) f.steps = p.u32("steps");
  for (FootPoint& f : b.foot_points) {
    const uint32_t c = p.u32("converged flag");
    if (c > 1) p.error(Status::parse_error, "converged flag not 0 or 1");
    f.converged = c == 1;
  }
  for (FootPoint& f : b.foot_points) {
    f.u = p.f64("u"), f.v = p.f64("v"), f.distance = p.f64("distance");
    if (f.u < 0 || f.u > 1 || f.v < 0 || f.v > 1 || f.distance < 0)
      p.error(Status::parse_error, "foot point (u, v) outside [0,1]^2 or negative distance");
  }
  for (FootPoint& f : b.foot_points) f.position.x = p.f64("x"), f.position.y = p.f64("y"), f.position.z = p.f64("z");
  b.displacement.resize(n);
  for (double& d : b.displacement) d = p.f64("displacement");
  b.normal_coefficients.resize(6 * n);
  for (double& d : b.normal_coefficients) d = p.f64("normal coefficient");
  if (local) {
    b.tangent_offset.resize(2 * n);
    for (double& d : b.tangent_offset) d = p.f64("tangent offset");
  }
  if (exact) {
    b.displacement_gradient.resize(2 * n);
    for (double& d : b.displacement_gradient) d = p.f64("displacement gradient");
  }

  // The sector split: present exactly when the options say so; copies refer to earlier vertices.
  if (have_sectors != (options.sharp_angle_degrees >= 0))
    fail(Status::parse_error, source_name + (have_sectors ? ": SECT section without a sharp angle"
                                                          : ": sharp angle set but no SECT section"));
  if (have_sectors) {
    Reader q(sector_data, sector_size, source_name, sector_offset);
    const uint64_t scan_vertices = q.u64("scan vertex count");
    if (scan_vertices == 0 || scan_vertices > n) q.error(Status::parse_error, "scan vertex count out of range");
    b.scan_vertex_count = size_t(scan_vertices);
    q.need(4 * uint64_t(n), "source vertices");
    b.source_vertex.resize(n);
    for (size_t i = 0; i < n; ++i) {
      const uint32_t v = q.u32("source vertex");
      if (i < b.scan_vertex_count ? v != i : v >= b.scan_vertex_count)
        q.error(Status::parse_error, "source vertex " + std::to_string(i) + " out of order or range");
      b.source_vertex[i] = v;
    }
    const uint64_t faces = q.u64("face count");
    if (faces == 0 || faces > kMaxVertices * 4 || (faces + 1) * 4 > q.remaining())
      q.error(Status::parse_error, "face count out of range");
    b.face_offsets.resize(size_t(faces) + 1);
    for (uint32_t& o : b.face_offsets) o = q.u32("face offset");
    if (b.face_offsets[0] != 0) q.error(Status::parse_error, "first face offset not 0");
    for (size_t f = 0; f < faces; ++f)
      if (b.face_offsets[f + 1] < b.face_offsets[f] + 3 || b.face_offsets[f + 1] > (1u << 30))
        q.error(Status::parse_error, "face " + std::to_string(f) + " has fewer than 3 vertices or bad offsets");
    if (uint64_t(b.face_offsets.back()) * 4 > q.remaining()) q.error(Status::parse_error, "truncated face vertices");
    b.face_vertices.resize(b.face_offsets.back());
    for (uint32_t& v : b.face_vertices) {
      v = q.u32("face vertex");
      if (v >= n) q.error(Status::parse_error, "face vertex out of range");
    }
  }

  // Rebuild: the limit surface, then the basis rows at the stored foot points and the table.
  std::unique_ptr<SubdivisionSurface> surface;
  try {
    SurfaceOptions surface_options = options.surface;
    surface_options.threads = resolve_threads(threads);
    surface = std::make_unique<SubdivisionSurface>(saved.cage, surface_options);
  } catch (const Error& e) {
    fail(e.status() == Status::out_of_memory || e.status() == Status::cancelled ? e.status() : Status::invalid_mesh,
         source_name + ": the saved cage has no usable limit surface: " + e.what());
  }
  if (surface->num_control_vertices() != b.num_control_vertices)
    fail(Status::parse_error, source_name + ": control vertex count does not match the cage");
  for (size_t i = 0; i < n; ++i) {
    const uint32_t f = b.foot_points[i].ptex_face;
    if (f >= surface->num_ptex_faces() || !surface->has_limit_surface(f))
      fail(Status::parse_error, source_name + ": vertex " + std::to_string(i) + ": ptex face " + std::to_string(f) +
                                    " is not on the cage's limit surface");
  }
  const int workers = resolve_threads(threads);
  options.threads = 0;
  store_basis_rows(b, evaluate_basis_rows(*surface, b.foot_points, workers, monitor, 0.0, 0.8), exact);
  if (options.compact_table)
    b.compact = build_patch_deformer_table(b, *surface, options.patch_table, workers, monitor);
  monitor.report("bind", 1.0);
  return saved;
}

CAGEKIT_NAMESPACE_END
