// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/remesh_quality.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "layout/convex_face_partition.h"

CAGEKIT_NAMESPACE_BEGIN

RemeshQuality measure_remesh_quality(const PolygonMesh& m, const std::vector<Vec3>& vertex_normals) {
  constexpr double kPi = 3.14159265358979323846;
  RemeshQuality r;
  r.faces = m.num_faces();
  r.vertices = m.num_vertices();
  std::unordered_map<uint64_t, int> edge_use;
  r.min_scaled_jacobian = m.num_faces() ? 1.0 : 0.0;
  std::vector<uint32_t> loop;
  for (size_t f = 0; f < m.num_faces(); ++f) {
    const uint32_t n = m.face_size(f);
    r.quads += n == 4;
    r.max_face_valence = std::max(r.max_face_valence, n);
    loop.assign(m.face_begin(f), m.face_begin(f) + n);
    const Vec3 fn = loop_normal(m.positions, loop);
    for (uint32_t k = 0; k < n; ++k) {
      ++edge_use[edge_key(loop[k], loop[(k + 1) % n])];
      // T-joint vertices (angles within 10° of π) are not corners of the element.
      const double angle = corner_angle(m.positions, vertex_normals, loop, k, fn);
      if (std::fabs(angle - kPi) > kPi / 18.0) r.min_scaled_jacobian = std::min(r.min_scaled_jacobian, std::sin(angle));
    }
  }
  std::vector<uint32_t> valence(m.num_vertices(), 0);
  std::vector<uint8_t> boundary(m.num_vertices(), 0);
  for (const auto& [key, uses] : edge_use) {
    const uint32_t a = uint32_t(key >> 32), b = uint32_t(key & 0xffffffffu);
    ++valence[a];
    ++valence[b];
    if (uses == 1) boundary[a] = boundary[b] = 1;
  }
  for (size_t v = 0; v < m.num_vertices(); ++v) {
    r.max_vertex_valence = std::max(r.max_vertex_valence, valence[v]);
    if (boundary[v]) continue;
    ++r.interior_vertices;
    r.valence4_vertices += valence[v] == 4;
  }
  return r;
}

CAGEKIT_NAMESPACE_END
