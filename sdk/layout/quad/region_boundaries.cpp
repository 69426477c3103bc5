// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/quad/region_boundaries.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/status.h"
#include "layout/common/triangle_mesh_input.h"

CAGEKIT_NAMESPACE_BEGIN
namespace {

using detail::EdgeMap;
using detail::kNone;

struct Tracer {
  const PolygonMesh& mesh;
  const std::vector<uint32_t>& face_region;
  EdgeMap edges;
  std::vector<uint8_t> boundary_edge;           // per edge
  std::vector<uint32_t> vertex_edge_offsets;    // boundary edges at each vertex
  std::vector<uint32_t> vertex_edges;
  std::vector<uint8_t> anchor;                  // per vertex: 0, 1 structural, 2 inserted
  std::vector<uint8_t> edge_done;

  uint32_t other_end(uint32_t e, uint32_t v) const { return edges.edge_lo[e] == v ? edges.edge_hi[e] : edges.edge_lo[e]; }
  double length(uint32_t a, uint32_t b) const { return distance(mesh.positions[a], mesh.positions[b]); }

  // Walks boundary edges from vertex `start` along edge `first` until an anchor (or `start`).
  std::vector<uint32_t> walk(uint32_t start, uint32_t first) {
    std::vector<uint32_t> chain{start};
    uint32_t v = start, e = first;
    for (;;) {
      edge_done[e] = 1;
      v = other_end(e, v);
      chain.push_back(v);
      if (anchor[v] || v == start) return chain;
      uint32_t next = kNone;
      for (uint32_t k = vertex_edge_offsets[v]; k < vertex_edge_offsets[v + 1]; ++k)
        if (!edge_done[vertex_edges[k]]) next = vertex_edges[k];
      if (next == kNone) fail(Status::internal_error, "region boundaries: an arc ends at a non-anchor vertex");
      e = next;
    }
  }
};

// Splits a closed chain (first == last) at one and two thirds of its length.
void split_closed_chain(const Tracer& tracer, const std::vector<uint32_t>& chain, std::vector<uint8_t>& anchor,
                        std::vector<std::vector<uint32_t>>& out) {
  const size_t m = chain.size() - 1;  // edges; >= 3 for a closed chain of a triangle mesh
  std::vector<double> s(chain.size(), 0.0);
  for (size_t i = 0; i < m; ++i) s[i + 1] = s[i] + tracer.length(chain[i], chain[i + 1]);
  auto nearest = [&](double target, size_t lo, size_t hi) {
    size_t best = lo;
    for (size_t i = lo; i <= hi; ++i)
      if (std::abs(s[i] - target) < std::abs(s[best] - target)) best = i;
    return best;
  };
  size_t cut[2];
  cut[0] = nearest(s[m] / 3.0, 1, m - 2);
  cut[1] = nearest(2.0 * s[m] / 3.0, cut[0] + 1, m - 1);
  for (int k = 0; k < 2; ++k)
    if (!anchor[chain[cut[k]]]) anchor[chain[cut[k]]] = 2;
  const size_t bounds[4] = {0, cut[0], cut[1], m};
  for (int k = 0; k < 3; ++k) out.emplace_back(chain.begin() + bounds[k], chain.begin() + bounds[k + 1] + 1);
}

}  // namespace

bool RegionBoundaries::is_anchor(uint32_t vertex) const {
  return std::binary_search(anchors.begin(), anchors.end(), vertex);
}

std::vector<uint32_t> RegionBoundaries::loop_vertices(const RegionLoop& loop) const {
  std::vector<uint32_t> out;
  for (size_t k = 0; k < loop.arcs.size(); ++k) {
    const std::vector<uint32_t>& v = arcs[loop.arcs[k]].vertices;
    if (loop.reversed[k])
      out.insert(out.end(), v.rbegin(), v.rend() - 1);
    else
      out.insert(out.end(), v.begin(), v.end() - 1);
  }
  return out;
}

void split_arc(RegionBoundaries& boundaries, uint32_t arc, size_t index) {
  if (arc >= boundaries.arcs.size()) fail(Status::invalid_argument, "split arc: arc id out of range");
  RegionArc& old = boundaries.arcs[arc];
  if (index == 0 || index + 1 >= old.vertices.size())
    fail(Status::invalid_argument, "split arc: the split vertex must be interior to the arc");
  RegionArc tail{std::vector<uint32_t>(old.vertices.begin() + long(index), old.vertices.end()), old.left_region,
                 old.right_region};
  old.vertices.resize(index + 1);
  const uint32_t vertex = tail.vertices.front();
  const uint32_t added = uint32_t(boundaries.arcs.size());
  boundaries.arcs.push_back(std::move(tail));
  const auto at = std::lower_bound(boundaries.anchors.begin(), boundaries.anchors.end(), vertex);
  boundaries.anchor_inserted.insert(boundaries.anchor_inserted.begin() + (at - boundaries.anchors.begin()), 1);
  boundaries.anchors.insert(at, vertex);
  for (std::vector<RegionLoop>& loops : boundaries.region_loops)
    for (RegionLoop& loop : loops)
      for (size_t k = 0; k < loop.arcs.size(); ++k) {
        if (loop.arcs[k] != arc) continue;
        // Forward: (arc, added); reversed: the tail comes first.
        const bool reversed = loop.reversed[k] != 0;
        loop.arcs.insert(loop.arcs.begin() + long(k) + (reversed ? 0 : 1), added);
        loop.reversed.insert(loop.reversed.begin() + long(k), loop.reversed[k]);
        ++k;
      }
}

RegionBoundaries compute_region_boundaries(const PolygonMesh& triangles, const std::vector<uint32_t>& face_region,
                                           size_t num_regions) {
  require_triangle_mesh(triangles, "region boundaries");
  if (face_region.size() != triangles.num_faces())
    fail(Status::invalid_argument, "region boundaries: face_region has " + std::to_string(face_region.size()) +
                                       " entries for " + std::to_string(triangles.num_faces()) + " faces");
  for (size_t f = 0; f < face_region.size(); ++f)
    if (face_region[f] >= num_regions)
      fail(Status::invalid_argument, "region boundaries: face " + std::to_string(f) + " has region " +
                                         std::to_string(face_region[f]) + " >= " + std::to_string(num_regions));
  Tracer t{triangles, face_region, {}, {}, {}, {}, {}, {}};
  build_edge_map(t.edges, triangles, std::vector<uint8_t>(triangles.num_faces(), 1));
  require_oriented_manifold_edges(t.edges, "region boundaries");
  const EdgeMap& edges = t.edges;
  const size_t ne = edges.num_edges(), nv = triangles.num_vertices();
  auto region_of = [&](uint32_t corner) { return face_region[edges.corner_face[corner]]; };

  t.boundary_edge.assign(ne, 0);
  std::vector<uint32_t> count(nv + 1, 0);
  for (uint32_t e = 0; e < ne; ++e) {
    const uint32_t* h = edges.corners_begin(e);
    t.boundary_edge[e] = edges.valence(e) == 1 || region_of(h[0]) != region_of(h[1]);
    if (t.boundary_edge[e]) ++count[edges.edge_lo[e] + 1], ++count[edges.edge_hi[e] + 1];
  }
  t.vertex_edge_offsets.assign(nv + 1, 0);
  for (size_t v = 0; v < nv; ++v) t.vertex_edge_offsets[v + 1] = t.vertex_edge_offsets[v] + count[v + 1];
  t.vertex_edges.assign(t.vertex_edge_offsets[nv], 0);
  std::vector<uint32_t> fill(t.vertex_edge_offsets.begin(), t.vertex_edge_offsets.end() - 1);
  for (uint32_t e = 0; e < ne; ++e)
    if (t.boundary_edge[e]) t.vertex_edges[fill[edges.edge_lo[e]]++] = e, t.vertex_edges[fill[edges.edge_hi[e]]++] = e;
  t.anchor.assign(nv, 0);
  for (size_t v = 0; v < nv; ++v)
    if (count[v + 1] >= 3) t.anchor[v] = 1;

  // Chains from anchors, then the anchor-free cycles (started at their smallest vertex).
  t.edge_done.assign(ne, 0);
  std::vector<std::vector<uint32_t>> chains;
  for (uint32_t v = 0; v < nv; ++v) {
    if (!t.anchor[v]) continue;
    for (uint32_t k = t.vertex_edge_offsets[v]; k < t.vertex_edge_offsets[v + 1]; ++k)
      if (!t.edge_done[t.vertex_edges[k]]) chains.push_back(t.walk(v, t.vertex_edges[k]));
  }
  for (uint32_t e = 0; e < ne; ++e) {
    if (!t.boundary_edge[e] || t.edge_done[e]) continue;
    // Find the smallest vertex of this cycle first, for a deterministic start.
    uint32_t v = edges.edge_lo[e], cur_e = e, smallest = v, smallest_edge = e;
    do {
      v = t.other_end(cur_e, v);
      uint32_t next = kNone;
      for (uint32_t k = t.vertex_edge_offsets[v]; k < t.vertex_edge_offsets[v + 1]; ++k)
        if (t.vertex_edges[k] != cur_e) next = t.vertex_edges[k];
      if (next == kNone) fail(Status::internal_error, "region boundaries: a boundary chain ends at a vertex");
      cur_e = next;
      if (v < smallest) smallest = v, smallest_edge = cur_e;
    } while (cur_e != e);
    t.anchor[smallest] = 2;
    chains.push_back(t.walk(smallest, smallest_edge));
  }

  RegionBoundaries out;
  std::vector<std::vector<uint32_t>> pieces;
  for (std::vector<uint32_t>& chain : chains) {
    if (chain.front() == chain.back())
      split_closed_chain(t, chain, t.anchor, pieces);
    else
      pieces.push_back(std::move(chain));
  }
  for (uint32_t v = 0; v < nv; ++v)
    if (t.anchor[v]) out.anchors.push_back(v), out.anchor_inserted.push_back(t.anchor[v] == 2);

  // Orient every arc (region on the left) and index its edges.
  std::vector<uint32_t> edge_arc(ne, kNone);
  for (std::vector<uint32_t>& piece : pieces) {
    const uint32_t e = edges.find_edge(piece[0], piece[1]);
    const uint32_t* h = edges.corners_begin(e);
    uint32_t left = kMeshBorder, right = kMeshBorder;
    for (uint32_t k = 0; k < edges.valence(e); ++k)
      (edges.from(h[k]) == piece[0] ? left : right) = region_of(h[k]);
    if (left == kMeshBorder || (right != kMeshBorder && right < left)) {
      std::reverse(piece.begin(), piece.end());
      std::swap(left, right);
    }
    const uint32_t id = uint32_t(out.arcs.size());
    for (size_t i = 0; i + 1 < piece.size(); ++i) edge_arc[edges.find_edge(piece[i], piece[i + 1])] = id;
    out.arcs.push_back(RegionArc{std::move(piece), left, right});
  }

  // Loops: boundary half-edges of each region, continued around the end vertex inside the region.
  out.region_loops.assign(num_regions, {});
  std::vector<uint8_t> corner_done(triangles.num_face_vertices(), 0);
  auto is_boundary_corner = [&](uint32_t c) { return t.boundary_edge[edges.corner_edge[c]] != 0; };
  auto next_boundary_corner = [&](uint32_t c) {
    uint32_t g = edges.next_corner(c);
    while (!is_boundary_corner(g)) {
      const uint32_t* h = edges.corners_begin(edges.corner_edge[g]);
      g = edges.next_corner(h[0] == g ? h[1] : h[0]);
    }
    return g;
  };
  for (uint32_t c0 = 0; c0 < corner_done.size(); ++c0) {
    if (corner_done[c0] || !is_boundary_corner(c0) || !t.anchor[edges.from(c0)]) continue;
    const uint32_t r = region_of(c0);
    RegionLoop loop;
    uint32_t c = c0;
    do {
      corner_done[c] = 1;
      loop.length += t.length(edges.from(c), edges.to(c));
      if (t.anchor[edges.from(c)]) {
        const uint32_t arc = edge_arc[edges.corner_edge[c]];
        loop.arcs.push_back(arc);
        loop.reversed.push_back(out.arcs[arc].left_region != r);
      }
      c = next_boundary_corner(c);
    } while (c != c0);
    out.region_loops[r].push_back(std::move(loop));
  }
  for (std::vector<RegionLoop>& loops : out.region_loops)
    std::stable_sort(loops.begin(), loops.end(),
                     [](const RegionLoop& a, const RegionLoop& b) { return a.length > b.length; });

  // Euler characteristic per region: F - E + V, edges and vertices counted once per region.
  out.region_euler_characteristic.assign(num_regions, 0);
  for (uint32_t f = 0; f < triangles.num_faces(); ++f) out.region_euler_characteristic[face_region[f]] += 1;
  std::vector<std::vector<uint32_t>> region_vertices(num_regions);
  for (uint32_t f = 0; f < triangles.num_faces(); ++f)
    for (uint32_t i = 0; i < 3; ++i) region_vertices[face_region[f]].push_back(triangles.face_vertex(f, i));
  for (size_t r = 0; r < num_regions; ++r) {
    std::vector<uint32_t>& v = region_vertices[r];
    std::sort(v.begin(), v.end());
    out.region_euler_characteristic[r] += int(std::unique(v.begin(), v.end()) - v.begin());
  }
  for (uint32_t e = 0; e < ne; ++e) {
    const uint32_t* h = edges.corners_begin(e);
    out.region_euler_characteristic[region_of(h[0])] -= 1;
    if (edges.valence(e) == 2 && region_of(h[1]) != region_of(h[0])) out.region_euler_characteristic[region_of(h[1])] -= 1;
  }
  return out;
}

CAGEKIT_NAMESPACE_END
