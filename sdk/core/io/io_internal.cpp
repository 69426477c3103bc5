// SPDX-License-Identifier: GPL-3.0-or-later
#include "core/io/io_internal.h"
#include "core/io/text_writer.h"

#include <algorithm>
#include <cmath>

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

void ReadContext::fail_at_line(size_t line, const std::string& message, Status status) const {
  fail(status, source + ":" + std::to_string(line) + ": " + message);
}

void ReadContext::fail_at_byte(size_t offset, const std::string& message, Status status) const {
  fail(status, source + ": byte " + std::to_string(offset) + ": " + message);
}

void ReadContext::fail_here(const std::string& message, Status status) const {
  fail(status, source + ": " + message);
}

void ReadContext::check_limit(uint64_t count, uint64_t limit, const char* what, size_t line_or_byte,
                              bool is_line) const {
  if (count <= limit) return;
  const std::string message = std::to_string(count) + " " + what + " exceed the limit of " +
                              std::to_string(limit) + " (ReadOptions)";
  if (is_line) fail_at_line(line_or_byte, message, Status::limit_exceeded);
  fail_at_byte(line_or_byte, message, Status::limit_exceeded);
}

void check_not_empty(const Cage& cage, const ReadContext& context) {
  if (cage.mesh.num_vertices() == 0) context.fail_here("no vertices");
  if (cage.mesh.num_faces() == 0) context.fail_here("no faces (a point cloud is not a mesh)");
}

namespace {

void check_faces_for_writing(const PolygonMesh& mesh) {
  const auto& offsets = mesh.face_offsets;
  if (offsets.empty() || offsets.front() != 0 || offsets.back() != mesh.face_vertices.size())
    fail(Status::invalid_mesh, "face_offsets does not match face_vertices");
  const size_t nv = mesh.num_vertices();
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    if (offsets[f + 1] < offsets[f]) fail(Status::invalid_mesh, "face_offsets is not increasing");
    if (mesh.face_size(f) < 3)
      fail(Status::invalid_mesh, "face " + std::to_string(f) + " has " +
                                     std::to_string(mesh.face_size(f)) + " vertices (at least 3 needed)");
  }
  for (uint32_t v : mesh.face_vertices)
    if (v >= nv)
      fail(Status::invalid_mesh, "a face refers to vertex " + std::to_string(v) + " but the mesh has " +
                                     std::to_string(nv) + " vertices");
}

void check_sharpness(float s, const char* what) {
  if (!std::isfinite(s) || s < 0)
    fail(Status::invalid_mesh, std::string(what) + " sharpness must be finite and >= 0");
}

void check_tags_for_writing(const Cage& cage) {
  const size_t nv = cage.mesh.num_vertices(), nf = cage.mesh.num_faces();
  for (const EdgeCrease& c : cage.creases) {
    if (c.v0 >= nv || c.v1 >= nv)
      fail(Status::invalid_mesh, "crease (" + std::to_string(c.v0) + ", " + std::to_string(c.v1) +
                                     ") refers to a vertex that does not exist");
    check_sharpness(c.sharpness, "crease");
  }
  for (const VertexCorner& c : cage.corners) {
    if (c.vertex >= nv)
      fail(Status::invalid_mesh, "corner tag refers to vertex " + std::to_string(c.vertex) +
                                     " that does not exist");
    check_sharpness(c.sharpness, "corner");
  }
  for (uint32_t h : cage.holes)
    if (h >= nf) fail(Status::invalid_mesh, "hole tag refers to face " + std::to_string(h) + " that does not exist");
  if (cage.boundary != BoundaryRule::edges_only && cage.boundary != BoundaryRule::edges_and_corners)
    fail(Status::invalid_mesh, "unknown boundary rule");
}

void check_options(const WriteOptions& options) {
  if (options.draco_position_bits < 1 || options.draco_position_bits > 30)
    fail(Status::invalid_argument, "draco_position_bits must be in 1..30");
  if (options.draco_speed < 0 || options.draco_speed > 10)
    fail(Status::invalid_argument, "draco_speed must be in 0..10");
  if (options.obj_precision < 1 || options.obj_precision > 17)
    fail(Status::invalid_argument, "obj_precision must be in 1..17");
}

}  // namespace

void validate_for_writing(const Cage& cage, const WriteOptions& options) {
  check_options(options);
  const PolygonMesh& mesh = cage.mesh;
  if (mesh.num_vertices() == 0) fail(Status::invalid_mesh, "the mesh has no vertices; nothing to write");
  if (mesh.num_vertices() > UINT32_MAX) fail(Status::invalid_mesh, "too many vertices for 32-bit indices");
  for (size_t v = 0; v < mesh.num_vertices(); ++v)
    if (!is_finite(mesh.positions[v]))
      fail(Status::invalid_mesh, "vertex " + std::to_string(v) + " has a non-finite coordinate");
  if (mesh.num_faces() == 0 || mesh.face_offsets.size() < 2)
    fail(Status::invalid_mesh, "the mesh has no faces; nothing to write");
  check_faces_for_writing(mesh);
  check_tags_for_writing(cage);
}

double max_position_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double worst = 0;
  const size_t n = std::min(a.size(), b.size());
  for (size_t i = 0; i < n; ++i) worst = std::max(worst, distance(a[i], b[i]));
  return worst;
}

double write_ascii_vertices_and_faces(const PolygonMesh& mesh, ProgressTicker& progress, TextWriter& w) {
  const double total = double(mesh.num_vertices() + mesh.num_faces());
  double error = 0;
  for (size_t v = 0; v < mesh.num_vertices(); ++v) {
    error = std::max(error, w.point(mesh.positions[v]));
    w.ch('\n');
    progress.tick(double(v) / total);
  }
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    w.uint(mesh.face_size(f));
    const uint32_t* corner = mesh.face_begin(f);
    for (uint32_t k = 0; k < mesh.face_size(f); ++k) {
      w.ch(' ');
      w.uint(corner[k]);
    }
    w.ch('\n');
    progress.tick(double(mesh.num_vertices() + f) / total);
  }
  return error;
}

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
