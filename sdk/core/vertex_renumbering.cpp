// SPDX-License-Identifier: GPL-3.0-or-later
#include "core/vertex_renumbering.h"

#include <string>
#include <utility>

#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {
constexpr uint32_t kRemoved = 0xffffffffu;
}  // namespace

void remap_vertices(PolygonMesh& m, const std::vector<uint32_t>& new_index, size_t new_count) {
  const size_t nv = m.num_vertices();
  std::vector<Vec3> positions(new_count);
  for (size_t v = nv; v-- > 0;)
    if (new_index[v] != kRemoved) positions[new_index[v]] = m.positions[v];
  for (uint32_t& v : m.face_vertices)
    v = v < nv ? new_index[v] : static_cast<uint32_t>(v - nv + new_count);
  m.positions = std::move(positions);
}

size_t keep_vertices(PolygonMesh& m, const std::vector<uint8_t>& keep) {
  const size_t nv = m.num_vertices();
  std::vector<uint32_t> new_index(nv, kRemoved);
  size_t count = 0;
  for (size_t v = 0; v < nv; ++v)
    if (keep[v]) new_index[v] = static_cast<uint32_t>(count++);
  if (count != nv) remap_vertices(m, new_index, count);
  return nv - count;
}

PolygonMesh renumber_vertices(const PolygonMesh& mesh, const std::vector<uint32_t>& order) {
  const size_t n = mesh.num_vertices();
  if (order.size() != n)
    fail(Status::invalid_argument, "renumber_vertices: the order has " + std::to_string(order.size()) +
                                       " entries for " + std::to_string(n) + " vertices");
  std::vector<uint32_t> new_id(n, kRemoved);
  for (uint32_t k = 0; k < n; ++k) {
    const uint32_t v = order[k];
    if (v >= n || new_id[v] != kRemoved)
      fail(Status::invalid_argument, "renumber_vertices: order[" + std::to_string(k) + "] = " + std::to_string(v) +
                                         (v >= n ? " is out of range" : " appears twice"));
    new_id[v] = k;
  }
  for (uint32_t v : mesh.face_vertices)
    if (v >= n) fail(Status::invalid_mesh, "renumber_vertices: a face refers to vertex " + std::to_string(v) + " of " + std::to_string(n));
  PolygonMesh out = mesh;
  remap_vertices(out, new_id, n);
  return out;
}

CAGEKIT_NAMESPACE_END
