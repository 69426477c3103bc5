// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// PolygonMesh: an indexed polygon mesh (vertex positions + variable-size faces).
// It is a plain container: it does not require manifoldness, orientation or valid indices;
// see mesh_validation.h for checks and mesh_repair.h for repairs.
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <vector>

#include "core/vec3.h"

CAGEKIT_NAMESPACE_BEGIN

struct BoundingBox {
  Vec3 min, max;
  bool empty = true;
  void extend(const Vec3& p);
  double diagonal() const { return empty ? 0.0 : distance(min, max); }
};

class PolygonMesh {
 public:
  std::vector<Vec3> positions;
  // Face f has vertices face_vertices[face_offsets[f] .. face_offsets[f+1]).
  // Invariant: face_offsets.size() == num_faces() + 1 and face_offsets[0] == 0.
  std::vector<uint32_t> face_offsets{0};
  std::vector<uint32_t> face_vertices;

  size_t num_vertices() const { return positions.size(); }
  size_t num_faces() const { return face_offsets.size() - 1; }
  size_t num_face_vertices() const { return face_vertices.size(); }
  uint32_t face_size(size_t f) const { return face_offsets[f + 1] - face_offsets[f]; }
  const uint32_t* face_begin(size_t f) const { return face_vertices.data() + face_offsets[f]; }
  uint32_t* face_begin(size_t f) { return face_vertices.data() + face_offsets[f]; }
  uint32_t face_vertex(size_t f, size_t corner) const { return face_vertices[face_offsets[f] + corner]; }

  uint32_t add_vertex(const Vec3& p);
  // Appends a face; indices are not checked here.
  uint32_t add_face(const uint32_t* vertices, size_t count);
  uint32_t add_face(std::initializer_list<uint32_t> vertices);
  void clear();
  void reserve(size_t vertices, size_t faces, size_t face_vertex_count);

  BoundingBox bounding_box() const;
  // Vector area of face f (1/2 sum of p_i x p_{i+1}, Newell): its direction is the face normal,
  // its length the area for planar faces. Indices must be in range.
  Vec3 face_vector_area(size_t f) const;
  bool all_faces_have_size(uint32_t n) const;
  // Mean length of the faces' edges, each half-edge counted once (shared edges twice); 0 without
  // faces. Indices must be in range.
  double mean_edge_length() const;
  // The fan triangulation of face f from its first corner, the one fan rule of the SDK:
  // visit(v0, v1, v2), visit(v0, v2, v3), … (none for faces of fewer than three vertices).
  template <class Visit>
  void for_each_fan_triangle(size_t f, Visit&& visit) const {
    const uint32_t* v = face_begin(f);
    for (uint32_t k = 1; k + 1 < face_size(f); ++k) visit(v[0], v[k], v[k + 1]);
  }
};

CAGEKIT_NAMESPACE_END
