// SPDX-License-Identifier: GPL-3.0-or-later
#include "core/vertex_renumbering.h"

#include <string>

#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

PolygonMesh renumber_vertices(const PolygonMesh& mesh, const std::vector<uint32_t>& order) {
  const size_t n = mesh.num_vertices();
  if (order.size() != n)
    fail(Status::invalid_argument, "renumber_vertices: the order has " + std::to_string(order.size()) +
                                       " entries for " + std::to_string(n) + " vertices");
  constexpr uint32_t kUnset = 0xffffffffu;
  std::vector<uint32_t> new_id(n, kUnset);
  PolygonMesh out;
  out.positions.reserve(n);
  for (uint32_t k = 0; k < n; ++k) {
    const uint32_t v = order[k];
    if (v >= n || new_id[v] != kUnset)
      fail(Status::invalid_argument, "renumber_vertices: order[" + std::to_string(k) + "] = " + std::to_string(v) +
                                         (v >= n ? " is out of range" : " appears twice"));
    new_id[v] = k;
    out.positions.push_back(mesh.positions[v]);
  }
  out.face_offsets = mesh.face_offsets;
  out.face_vertices.reserve(mesh.face_vertices.size());
  for (uint32_t v : mesh.face_vertices) {
    if (v >= n) fail(Status::invalid_mesh, "renumber_vertices: a face refers to vertex " + std::to_string(v) + " of " + std::to_string(n));
    out.face_vertices.push_back(new_id[v]);
  }
  return out;
}

CAGEKIT_NAMESPACE_END
