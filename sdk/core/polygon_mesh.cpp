// SPDX-License-Identifier: GPL-3.0-or-later
#include "core/memory_budget.h"
#include "core/polygon_mesh.h"

#include <algorithm>

CAGEKIT_NAMESPACE_BEGIN

void BoundingBox::extend(const Vec3& p) {
  if (empty) {
    min = max = p;
    empty = false;
    return;
  }
  min = {std::min(min.x, p.x), std::min(min.y, p.y), std::min(min.z, p.z)};
  max = {std::max(max.x, p.x), std::max(max.y, p.y), std::max(max.z, p.z)};
}

uint32_t PolygonMesh::add_vertex(const Vec3& p) {
  positions.push_back(p);
  return static_cast<uint32_t>(positions.size() - 1);
}

uint32_t PolygonMesh::add_face(const uint32_t* vertices, size_t count) {
  face_vertices.insert(face_vertices.end(), vertices, vertices + count);
  face_offsets.push_back(static_cast<uint32_t>(face_vertices.size()));
  return static_cast<uint32_t>(num_faces() - 1);
}

uint32_t PolygonMesh::add_face(std::initializer_list<uint32_t> vertices) {
  return add_face(vertices.begin(), vertices.size());
}

void PolygonMesh::clear() {
  positions.clear();
  face_offsets.assign(1, 0);
  face_vertices.clear();
}

void PolygonMesh::reserve(size_t vertices, size_t faces, size_t face_vertex_count) {
  check_memory_estimate(estimate_sum(estimate_sum(estimate_product(vertices, sizeof(Vec3)), estimate_product(faces, 4)),
                                     estimate_product(face_vertex_count, 4)),
                        "a mesh of this size");
  positions.reserve(vertices);
  face_offsets.reserve(faces + 1);
  face_vertices.reserve(face_vertex_count);
}

Vec3 PolygonMesh::face_vector_area(size_t f) const {
  const uint32_t k = face_size(f);
  const uint32_t* v = face_begin(f);
  Vec3 area;
  for (uint32_t c = 0; c < k; ++c) area += cross(positions[v[c]], positions[v[(c + 1) % k]]);
  return area * 0.5;
}

BoundingBox PolygonMesh::bounding_box() const {
  BoundingBox box;
  for (const Vec3& p : positions) box.extend(p);
  return box;
}

bool PolygonMesh::all_faces_have_size(uint32_t n) const {
  for (size_t f = 0; f < num_faces(); ++f)
    if (face_size(f) != n) return false;
  return true;
}

double PolygonMesh::mean_edge_length() const {
  double sum = 0;
  for (size_t f = 0; f < num_faces(); ++f) {
    const uint32_t n = face_size(f);
    for (uint32_t k = 0; k < n; ++k) sum += distance(positions[face_vertex(f, k)], positions[face_vertex(f, (k + 1) % n)]);
  }
  return face_vertices.empty() ? 0.0 : sum / double(face_vertices.size());
}

CAGEKIT_NAMESPACE_END
