// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/common/triangle_mesh_input.h"

#include <algorithm>
#include <string>

#include "core/edge_key.h"

#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

PolygonMesh fan_triangulated(const PolygonMesh& input, const char* who) {
  detail::check_mesh_arrays(input);
  PolygonMesh tri;
  tri.positions = input.positions;
  for (size_t f = 0; f < input.num_faces(); ++f) {
    const uint32_t n = input.face_size(f);
    if (n < 3) fail(Status::invalid_mesh, std::string(who) + ": face " + std::to_string(f) + " has fewer than 3 vertices");
    input.for_each_fan_triangle(f, [&](uint32_t a, uint32_t b, uint32_t c) { tri.add_face({a, b, c}); });
  }
  return tri;
}

void require_triangle_mesh(const PolygonMesh& mesh, const char* who) {
  detail::check_mesh_arrays(mesh);
  if (mesh.num_faces() == 0) fail(Status::invalid_mesh, std::string(who) + ": the mesh has no faces");
  const size_t nv = mesh.num_vertices();
  for (size_t v = 0; v < nv; ++v)
    if (!is_finite(mesh.positions[v]))
      fail(Status::invalid_mesh, std::string(who) + ": vertex " + std::to_string(v) + " has a non-finite position");
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const std::string face = std::string(who) + ": face " + std::to_string(f);
    if (mesh.face_size(f) != 3) fail(Status::invalid_mesh, face + " is not a triangle");
    for (uint32_t i = 0; i < 3; ++i)
      if (mesh.face_vertex(f, i) >= nv) fail(Status::invalid_mesh, face + " has an out-of-range vertex index");
    if (detail::find_repeated_vertex(mesh.face_begin(f), 3) != detail::kNone)
      fail(Status::invalid_mesh, face + " repeats a vertex");
  }
}

void build_face_adjacency(FaceAdjacency& adjacency, const PolygonMesh& mesh, const std::vector<uint64_t>& barriers) {
  build_edge_map(adjacency.edges, mesh, std::vector<uint8_t>(mesh.num_faces(), 1));
  const detail::EdgeMap& map = adjacency.edges;
  const size_t nf = mesh.num_faces();
  auto barrier = [&](size_t e) {
    return !barriers.empty() &&
           std::binary_search(barriers.begin(), barriers.end(), edge_key(map.edge_lo[e], map.edge_hi[e]));
  };
  std::vector<uint32_t> count(nf + 1, 0);
  for (size_t e = 0; e < map.num_edges(); ++e) {
    if (barrier(e)) continue;
    const uint32_t k = map.valence(e);
    for (const uint32_t* c = map.corners_begin(e); c != map.corners_end(e); ++c) count[map.corner_face[*c] + 1] += k - 1;
  }
  adjacency.offsets.assign(nf + 1, 0);
  for (size_t f = 0; f < nf; ++f) adjacency.offsets[f + 1] = adjacency.offsets[f] + count[f + 1];
  adjacency.neighbours.assign(adjacency.offsets[nf], 0);
  std::vector<uint32_t> fill(adjacency.offsets.begin(), adjacency.offsets.end() - 1);
  for (size_t e = 0; e < map.num_edges(); ++e) {
    if (barrier(e)) continue;
    for (const uint32_t* a = map.corners_begin(e); a != map.corners_end(e); ++a)
      for (const uint32_t* b = map.corners_begin(e); b != map.corners_end(e); ++b)
        if (a != b) adjacency.neighbours[fill[map.corner_face[*a]]++] = map.corner_face[*b];
  }
}

void require_oriented_manifold_edges(const detail::EdgeMap& edges, const char* who) {
  for (size_t e = 0; e < edges.num_edges(); ++e) {
    const std::string edge = std::string(who) + ": edge " + std::to_string(edges.edge_lo[e]) + "-" +
                             std::to_string(edges.edge_hi[e]);
    if (edges.valence(e) > 2) fail(Status::invalid_mesh, edge + " has more than two faces (non-manifold)");
    if (edges.valence(e) == 2) {
      const uint32_t* h = edges.corners_begin(e);
      if (edges.forward(h[0]) == edges.forward(h[1]))
        fail(Status::invalid_mesh, edge + ": its two faces run it in the same direction (inconsistent orientation)");
    }
  }
}

void triangle_normals_and_areas(const PolygonMesh& mesh, std::vector<Vec3>& normals, std::vector<double>& areas) {
  const size_t nf = mesh.num_faces();
  normals.assign(nf, Vec3{});
  areas.assign(nf, 0.0);
  for (size_t f = 0; f < nf; ++f) {
    const Vec3& a = mesh.positions[mesh.face_vertex(f, 0)];
    const Vec3 n = cross(mesh.positions[mesh.face_vertex(f, 1)] - a, mesh.positions[mesh.face_vertex(f, 2)] - a);
    const double len = norm(n);
    areas[f] = 0.5 * len;
    // Zero-area (or numerically flat) triangles get no direction: they carry no L2,1 weight.
    if (len > 0.0 && std::isfinite(len)) normals[f] = n * (1.0 / len);
  }
}

CAGEKIT_NAMESPACE_END
