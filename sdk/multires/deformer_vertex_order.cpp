// SPDX-License-Identifier: GPL-3.0-or-later
// The CPU deformer's write order as a scan renumbering; see deformer_vertex_order.h.
#include "multires/deformer_vertex_order.h"

CAGEKIT_NAMESPACE_BEGIN

std::vector<uint32_t> deformer_vertex_order(const ScanBinding& b) {
  const size_t bound = b.num_vertices();
  const size_t scan = b.source_vertex.empty() ? bound : b.scan_vertex_count;
  std::vector<uint32_t> order;
  order.reserve(scan);
  std::vector<uint8_t> placed(scan, 0);
  auto visit = [&](uint32_t v) {
    if (v >= bound) return;
    const uint32_t s = b.source_vertex.empty() ? v : b.source_vertex[v];
    if (s < scan && !placed[s]) placed[s] = 1, order.push_back(s);
  };
  const PatchDeformerTable& t = b.compact;
  for (uint32_t v : t.vertex) visit(v);
  for (uint32_t v : t.irregular_vertex) visit(v);
  for (uint32_t s = 0; s < scan; ++s)
    if (!placed[s]) order.push_back(s);
  return order;
}

CAGEKIT_NAMESPACE_END
