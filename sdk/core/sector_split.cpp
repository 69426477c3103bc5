// SPDX-License-Identifier: GPL-3.0-or-later
#include "core/sector_split.h"

#include <cmath>

#include "core/angles.h"
#include "core/edge_map.h"
#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

SectorSplit split_vertices_by_sector(const PolygonMesh& mesh, double sharp_angle_degrees) {
  if (!(sharp_angle_degrees >= 0 && sharp_angle_degrees <= 180))
    fail(Status::invalid_argument, "sector split: the sharp angle must be in [0, 180] degrees");
  detail::check_mesh_arrays(mesh);
  const size_t n = mesh.num_vertices(), nf = mesh.num_faces();
  // Faces the edge map can take; their unit normals (zero when they have none).
  std::vector<uint8_t> include(nf, 0);
  std::vector<Vec3> normal(nf);
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t k = mesh.face_size(f);
    const uint32_t* v = &mesh.face_vertices[mesh.face_offsets[f]];
    bool ok = k >= 3;
    for (uint32_t c = 0; ok && c < k; ++c) ok = v[c] < n;
    if (!ok || detail::find_repeated_vertex(v, k) != detail::kNone) continue;
    include[f] = 1;
    const Vec3 a = mesh.face_vector_area(f);
    const double l = norm(a);
    if (l > 0 && std::isfinite(l)) normal[f] = a * (1.0 / l);
  }
  detail::EdgeMap map;
  detail::build_edge_map(map, mesh, include);
  const double cos_limit = std::cos(radians_from_degrees(sharp_angle_degrees));
  detail::UnionFind corners(mesh.face_vertices.size());
  detail::glue_fans(map, corners, [&](size_t e) {
    if (map.valence(e) != 2) return false;  // boundary or non-manifold: sharp
    const uint32_t* h = map.corners_begin(e);
    const Vec3 &a = normal[map.corner_face[h[0]]], &b = normal[map.corner_face[h[1]]];
    if (norm(a) == 0 || norm(b) == 0) return true;
    return dot(a, b) >= cos_limit;
  });
  SectorSplit out;
  out.num_input_vertices = n;
  out.mesh.face_offsets = mesh.face_offsets;
  out.mesh.face_vertices = mesh.face_vertices;
  out.mesh.positions = mesh.positions;
  out.source_vertex.resize(n);
  for (size_t v = 0; v < n; ++v) out.source_vertex[v] = uint32_t(v);
  // Each class of corners at a vertex: the first one met keeps the vertex, later ones get copies.
  std::vector<uint32_t> class_vertex(mesh.face_vertices.size(), detail::kNone);
  std::vector<uint8_t> vertex_taken(n, 0);
  for (size_t f = 0; f < nf; ++f) {
    if (!include[f]) continue;
    for (uint32_t c = mesh.face_offsets[f]; c < mesh.face_offsets[f + 1]; ++c) {
      const uint32_t v = mesh.face_vertices[c], root = corners.find(c);
      if (class_vertex[root] == detail::kNone) {
        if (!vertex_taken[v]) {
          vertex_taken[v] = 1;
          class_vertex[root] = v;
        } else {
          if (out.mesh.positions.size() >= UINT32_MAX)
            fail(Status::limit_exceeded, "sector split: more than 2^32 vertices");
          class_vertex[root] = uint32_t(out.mesh.positions.size());
          out.mesh.positions.push_back(mesh.positions[v]);
          out.source_vertex.push_back(v);
        }
      }
      out.mesh.face_vertices[c] = class_vertex[root];
    }
  }
  return out;
}

CAGEKIT_NAMESPACE_END
