// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/common/remesh_quality.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "core/angles.h"
#include "core/edge_key.h"
#include "layout/common/polygon_corners.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {


}  // namespace

PolygonMeshFigures polygon_mesh_figures(const PolygonMesh& m) {
  PolygonMeshFigures r;
  r.faces = m.num_faces();
  r.vertices = m.num_vertices();
  std::unordered_map<uint64_t, uint32_t> edge_index;
  edge_index.reserve(m.num_face_vertices());
  for (size_t f = 0; f < m.num_faces(); ++f) {
    const uint32_t n = m.face_size(f);
    const uint32_t* v = m.face_begin(f);
    r.quads += n == 4;
    r.max_face_valence = std::max(r.max_face_valence, n);
    for (uint32_t k = 0; k < n; ++k) {
      const uint32_t a = v[k], b = v[(k + 1) % n];
      const auto [it, inserted] = edge_index.emplace(edge_key(a, b), uint32_t(r.edges.size()));
      if (inserted) {
        r.edges.push_back({std::min(a, b), std::max(a, b)});
        r.edge_uses.push_back(0);
      }
      ++r.edge_uses[it->second];
    }
  }
  std::vector<uint32_t> valence(m.num_vertices(), 0);
  std::vector<uint8_t> boundary(m.num_vertices(), 0);
  for (size_t e = 0; e < r.edges.size(); ++e) {
    const auto [a, b] = r.edges[e];
    ++valence[a];
    ++valence[b];
    if (r.edge_uses[e] == 1) boundary[a] = boundary[b] = 1;
  }
  for (size_t v = 0; v < m.num_vertices(); ++v) {
    r.max_vertex_valence = std::max(r.max_vertex_valence, valence[v]);
    if (boundary[v] || valence[v] == 0) continue;
    ++r.interior_vertices;
    r.valence4_vertices += valence[v] == 4;
  }
  return r;
}

RemeshQuality measure_remesh_quality(const PolygonMesh& m, const std::vector<Vec3>& vertex_normals,
                                     const PolygonMeshFigures* given) {
  const PolygonMeshFigures computed = given ? PolygonMeshFigures() : polygon_mesh_figures(m);
  const PolygonMeshFigures& figures = given ? *given : computed;
  RemeshQuality r;
  static_cast<PolygonMeshCounts&>(r) = figures;
  r.min_scaled_jacobian = m.num_faces() ? 1.0 : 0.0;
  std::vector<uint32_t> loop;
  for (size_t f = 0; f < m.num_faces(); ++f) {
    const uint32_t n = m.face_size(f);
    loop.assign(m.face_begin(f), m.face_begin(f) + n);
    const Vec3 fn = loop_normal(m.positions, loop);
    for (uint32_t k = 0; k < n; ++k) {
      // T-joint vertices (angles within 10° of π) are not corners of the element.
      const double angle = corner_angle(m.positions, vertex_normals, loop, k, fn);
      if (std::fabs(angle - kPi) > kPi / 18.0) r.min_scaled_jacobian = std::min(r.min_scaled_jacobian, std::sin(angle));
    }
  }
  return r;
}

FeatureAlignment measure_feature_alignment(const PolygonMesh& input, const std::vector<uint8_t>& sharp_corners,
                                           const PolygonMesh& output) {
  FeatureAlignment r;
  const PolygonMeshFigures out = polygon_mesh_figures(output);
  double length_sum = 0.0;
  for (const auto& [a, b] : out.edges) length_sum += distance(output.positions[a], output.positions[b]);
  r.delta = out.edges.empty() ? 0.0 : length_sum / double(out.edges.size());

  // Midpoints of the distinct sharp input edges.
  std::vector<Vec3> midpoints;
  {
    std::unordered_map<uint64_t, uint8_t> seen;
    for (size_t f = 0, c = 0; f < input.num_faces(); ++f) {
      const uint32_t n = input.face_size(f);
      const uint32_t* v = input.face_begin(f);
      for (uint32_t k = 0; k < n; ++k, ++c) {
        if (c >= sharp_corners.size() || !sharp_corners[c]) continue;
        if (!seen.emplace(edge_key(v[k], v[(k + 1) % n]), 1).second) continue;
        midpoints.push_back(0.5 * (input.positions[v[k]] + input.positions[v[(k + 1) % n]]));
      }
    }
  }
  r.sharp_edges = midpoints.size();
  if (midpoints.empty() || !(r.delta > 0.0)) return r;

  // Uniform grid of cell size delta over the output edges (each edge listed in the cells its box,
  // grown by delta / 4, overlaps); a midpoint looks in its own cell only.
  const double radius = 0.25 * r.delta, cell = r.delta;
  auto cell_of = [&](double x) { return int64_t(std::floor(x / cell)); };
  auto key = [](int64_t i, int64_t j, int64_t k) {
    return (uint64_t(i & 0x1fffff) << 42) | (uint64_t(j & 0x1fffff) << 21) | uint64_t(k & 0x1fffff);
  };
  std::unordered_map<uint64_t, std::vector<uint32_t>> grid;
  for (uint32_t e = 0; e < out.edges.size(); ++e) {
    const Vec3& a = output.positions[out.edges[e][0]];
    const Vec3& b = output.positions[out.edges[e][1]];
    const int64_t i0 = cell_of(std::min(a.x, b.x) - radius), i1 = cell_of(std::max(a.x, b.x) + radius);
    const int64_t j0 = cell_of(std::min(a.y, b.y) - radius), j1 = cell_of(std::max(a.y, b.y) + radius);
    const int64_t k0 = cell_of(std::min(a.z, b.z) - radius), k1 = cell_of(std::max(a.z, b.z) + radius);
    for (int64_t i = i0; i <= i1; ++i)
      for (int64_t j = j0; j <= j1; ++j)
        for (int64_t k = k0; k <= k1; ++k) grid[key(i, j, k)].push_back(e);
  }
  for (const Vec3& p : midpoints) {
    const auto it = grid.find(key(cell_of(p.x), cell_of(p.y), cell_of(p.z)));
    if (it == grid.end()) continue;
    for (uint32_t e : it->second)
      if (point_segment_distance(p, output.positions[out.edges[e][0]], output.positions[out.edges[e][1]]) <= radius) {
        ++r.followed;
        break;
      }
  }
  return r;
}

CAGEKIT_NAMESPACE_END
