// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/quad/disk_regions.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <string>
#include <unordered_map>
#include <utility>

#include "core/edge_key.h"
#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

constexpr double kUnreached = std::numeric_limits<double>::infinity();

// Edge-adjacency of the region's faces (indices into `faces`).
std::vector<std::vector<uint32_t>> region_adjacency(const PolygonMesh& triangles, const std::vector<uint32_t>& faces) {
  std::unordered_map<uint64_t, uint32_t> first;  // undirected edge -> first face (local index)
  std::vector<std::vector<uint32_t>> adjacent(faces.size());
  first.reserve(faces.size() * 2);
  for (uint32_t i = 0; i < faces.size(); ++i) {
    const uint32_t f = faces[i], n = triangles.face_size(f);
    for (uint32_t k = 0; k < n; ++k) {
      const uint32_t a = triangles.face_vertex(f, k), b = triangles.face_vertex(f, (k + 1) % n);
      const uint64_t key = edge_key(a, b);
      const auto [it, inserted] = first.emplace(key, i);
      if (!inserted) {
        adjacent[i].push_back(it->second);
        adjacent[it->second].push_back(i);
      }
    }
  }
  return adjacent;
}

Vec3 centroid(const PolygonMesh& mesh, uint32_t f) {
  Vec3 c;
  const uint32_t n = mesh.face_size(f);
  for (uint32_t k = 0; k < n; ++k) c += mesh.positions[mesh.face_vertex(f, k)];
  return c * (1.0 / double(n));
}

// Multi-source Dijkstra over face centroids: distance and nearest source per face.
void geodesic_cells(const std::vector<Vec3>& centre, const std::vector<std::vector<uint32_t>>& adjacent,
                    const std::vector<uint32_t>& sources, std::vector<double>& distance, std::vector<uint32_t>& cell) {
  distance.assign(centre.size(), kUnreached);
  cell.assign(centre.size(), 0xffffffffu);
  using Item = std::pair<double, uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (uint32_t s = 0; s < sources.size(); ++s) {
    distance[sources[s]] = 0.0;
    cell[sources[s]] = s;
    queue.push({0.0, sources[s]});
  }
  while (!queue.empty()) {
    const auto [d, i] = queue.top();
    queue.pop();
    if (d > distance[i]) continue;
    for (const uint32_t j : adjacent[i]) {
      const double e = d + norm(centre[j] - centre[i]);
      if (e < distance[j]) {
        distance[j] = e;
        cell[j] = cell[i];
        queue.push({e, j});
      }
    }
  }
}

uint32_t farthest(const std::vector<double>& distance) {
  uint32_t best = 0;
  for (uint32_t i = 0; i < distance.size(); ++i)
    if (std::isfinite(distance[i]) && distance[i] > distance[best]) best = i;
  return best;
}

}  // namespace

std::vector<uint32_t> split_region_in_two(const PolygonMesh& triangles, const std::vector<uint32_t>& faces) {
  if (faces.size() < 2) return {};
  const std::vector<std::vector<uint32_t>> adjacent = region_adjacency(triangles, faces);
  std::vector<Vec3> centre(faces.size());
  for (size_t i = 0; i < faces.size(); ++i) centre[i] = centroid(triangles, faces[i]);
  std::vector<double> distance;
  std::vector<uint32_t> cell;
  geodesic_cells(centre, adjacent, {0}, distance, cell);
  std::vector<uint32_t> second;
  // A disconnected region: its faces not reached from the first face are the second part.
  for (uint32_t i = 0; i < faces.size(); ++i)
    if (!std::isfinite(distance[i])) second.push_back(faces[i]);
  if (!second.empty()) return second;
  const uint32_t a = farthest(distance);
  geodesic_cells(centre, adjacent, {a}, distance, cell);
  const uint32_t b = farthest(distance);
  if (a == b) return {};
  geodesic_cells(centre, adjacent, {a, b}, distance, cell);
  for (uint32_t i = 0; i < faces.size(); ++i)
    if (cell[i] == 1) second.push_back(faces[i]);
  return second;
}

namespace {

std::vector<uint32_t> faces_of(const std::vector<uint32_t>& face_region, uint32_t region) {
  std::vector<uint32_t> faces;
  for (uint32_t f = 0; f < face_region.size(); ++f)
    if (face_region[f] == region) faces.push_back(f);
  return faces;
}

// The geodesic Voronoi cells of two seed groups (local face indices); returns the faces of the
// second group's cell, or empty when a group is empty.
std::vector<uint32_t> split_between_groups(const PolygonMesh& triangles, const std::vector<uint32_t>& faces,
                                           const std::vector<uint32_t>& first, const std::vector<uint32_t>& second) {
  if (first.empty() || second.empty()) return {};
  const std::vector<std::vector<uint32_t>> adjacent = region_adjacency(triangles, faces);
  std::vector<Vec3> centre(faces.size());
  for (size_t i = 0; i < faces.size(); ++i) centre[i] = centroid(triangles, faces[i]);
  std::vector<uint32_t> sources = first;
  sources.insert(sources.end(), second.begin(), second.end());
  std::vector<double> distance;
  std::vector<uint32_t> cell;
  geodesic_cells(centre, adjacent, sources, distance, cell);
  std::vector<uint32_t> out;
  for (uint32_t i = 0; i < faces.size(); ++i)
    if (cell[i] != 0xffffffffu && cell[i] >= first.size()) out.push_back(faces[i]);
  return out;
}

uint32_t find_root(std::vector<uint32_t>& parent, uint32_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

}  // namespace

std::vector<uint32_t> split_region_between(const PolygonMesh& triangles, const std::vector<uint32_t>& face_region,
                                           uint32_t region, const Vec3& p, const Vec3& q) {
  const std::vector<uint32_t> faces = faces_of(face_region, region);
  if (faces.size() < 2) return {};
  uint32_t near_p = 0, near_q = 0;
  double best_p = kUnreached, best_q = kUnreached;
  for (uint32_t i = 0; i < faces.size(); ++i) {
    const Vec3 c = centroid(triangles, faces[i]);
    const double dp = norm(c - p), dq = norm(c - q);
    if (dp < best_p) best_p = dp, near_p = i;
    if (dq < best_q) best_q = dq, near_q = i;
  }
  std::vector<uint32_t> out;
  if (near_p != near_q) out = split_between_groups(triangles, faces, {near_p}, {near_q});
  return out.empty() || out.size() == faces.size() ? split_region_in_two(triangles, faces) : out;
}

namespace {

// split_region_at_pinch on a face list; empty when the faces touch themselves at no vertex.
std::vector<uint32_t> split_faces_at_pinch(const PolygonMesh& triangles, const std::vector<uint32_t>& faces) {
  // Per vertex: the region's faces around it (local indices).
  std::unordered_map<uint32_t, std::vector<uint32_t>> around;
  for (uint32_t i = 0; i < faces.size(); ++i)
    for (uint32_t k = 0; k < triangles.face_size(faces[i]); ++k) around[triangles.face_vertex(faces[i], k)].push_back(i);
  std::vector<uint32_t> order;  // the vertices in id order: the same pinch is found every time
  for (const auto& [v, list] : around) order.push_back(v);
  std::sort(order.begin(), order.end());
  for (const uint32_t v : order) {
    const std::vector<uint32_t>& list = around[v];
    if (list.size() < 2) continue;
    // Fans: the faces around v joined where two of them share an edge at v.
    std::vector<uint32_t> parent(list.size());
    for (uint32_t j = 0; j < list.size(); ++j) parent[j] = j;
    std::unordered_map<uint32_t, uint32_t> by_other;  // the edge's other vertex -> a face around v
    for (uint32_t j = 0; j < list.size(); ++j) {
      const uint32_t f = faces[list[j]], n = triangles.face_size(f);
      for (uint32_t k = 0; k < n; ++k) {
        if (triangles.face_vertex(f, k) != v) continue;
        for (const uint32_t w : {triangles.face_vertex(f, (k + 1) % n), triangles.face_vertex(f, (k + n - 1) % n)}) {
          const auto [it, inserted] = by_other.emplace(w, j);
          if (!inserted) parent[find_root(parent, j)] = find_root(parent, it->second);
        }
      }
    }
    const uint32_t fan0 = find_root(parent, 0);
    std::vector<uint32_t> first, second;
    for (uint32_t j = 0; j < list.size(); ++j) (find_root(parent, j) == fan0 ? first : second).push_back(list[j]);
    if (second.empty()) continue;
    std::vector<uint32_t> out = split_between_groups(triangles, faces, first, second);
    if (!out.empty() && out.size() < faces.size()) return out;
  }
  return {};
}

// The region's faces as a surface: its edges (vertex pairs, the faces on each side, local face
// indices; kNoFace on the border) and its border loops (border edges joined at their vertices).
constexpr uint32_t kNoFace = 0xffffffffu;

struct RegionEdge {
  uint32_t a, b;
  uint32_t face[2];
};

}  // namespace

std::vector<uint32_t> split_region_at_pinch(const PolygonMesh& triangles, const std::vector<uint32_t>& face_region,
                                            uint32_t region) {
  const std::vector<uint32_t> faces = faces_of(face_region, region);
  std::vector<uint32_t> out = split_faces_at_pinch(triangles, faces);
  return out.empty() ? split_region_in_two(triangles, faces) : out;
}

std::vector<uint32_t> cut_region_handle(const PolygonMesh& triangles, const std::vector<uint32_t>& faces) {
  const uint32_t n = uint32_t(faces.size());
  if (n < 2) return {};
  std::vector<RegionEdge> edges;
  std::unordered_map<uint64_t, uint32_t> edge_index;
  edge_index.reserve(size_t(n) * 2);
  std::unordered_map<uint32_t, uint32_t> vertex_index;  // mesh vertex -> local
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t f = faces[i], m = triangles.face_size(f);
    for (uint32_t k = 0; k < m; ++k) {
      const uint32_t a = triangles.face_vertex(f, k), b = triangles.face_vertex(f, (k + 1) % m);
      vertex_index.emplace(a, uint32_t(vertex_index.size()));
      const uint64_t key = edge_key(a, b);
      const auto [it, inserted] = edge_index.emplace(key, uint32_t(edges.size()));
      if (inserted) {
        edges.push_back({a, b, {i, kNoFace}});
      } else {
        RegionEdge& e = edges[it->second];
        if (e.face[1] != kNoFace) return {};  // an edge of three faces: not a surface
        e.face[1] = i;
      }
    }
  }
  // Border loops, each capped by one extra dual node (n + loop): on the capped, closed surface
  // the edges in neither the dual tree nor the primal spanning tree number twice the genus, and
  // each closes a non-separating dual cycle. A vertex with more than two border edges (a pinch)
  // makes the loops ambiguous: those regions are split at the pinch instead.
  std::vector<uint32_t> parent(vertex_index.size());
  std::vector<uint32_t> border_degree(vertex_index.size(), 0);
  for (uint32_t v = 0; v < parent.size(); ++v) parent[v] = v;
  for (const RegionEdge& e : edges)
    if (e.face[1] == kNoFace) {
      const uint32_t a = vertex_index[e.a], b = vertex_index[e.b];
      if (++border_degree[a] > 2 || ++border_degree[b] > 2) return {};
      parent[find_root(parent, a)] = find_root(parent, b);
    }
  std::unordered_map<uint32_t, uint32_t> cap;  // border loop root -> dual node
  for (RegionEdge& e : edges)
    if (e.face[1] == kNoFace) {
      const uint32_t root = find_root(parent, vertex_index[e.a]);
      e.face[1] = cap.emplace(root, n + uint32_t(cap.size())).first->second;
    }
  const uint32_t nodes = n + uint32_t(cap.size());
  std::vector<std::vector<std::pair<uint32_t, uint32_t>>> dual(nodes);  // node -> (node, edge)
  for (uint32_t e = 0; e < edges.size(); ++e) {
    dual[edges[e].face[0]].push_back({edges[e].face[1], e});
    dual[edges[e].face[1]].push_back({edges[e].face[0], e});
  }
  // Dual tree: breadth first from face 0, so the cycles through it stay short.
  std::vector<uint32_t> tree_parent(nodes, kNoFace), depth(nodes, 0);
  std::vector<uint8_t> in_dual_tree(edges.size(), 0), reached(nodes, 0);
  std::queue<uint32_t> queue;
  queue.push(0);
  reached[0] = 1;
  while (!queue.empty()) {
    const uint32_t x = queue.front();
    queue.pop();
    for (const auto& [y, e] : dual[x])
      if (!reached[y]) {
        reached[y] = 1;
        tree_parent[y] = x;
        depth[y] = depth[x] + 1;
        in_dual_tree[e] = 1;
        queue.push(y);
      }
  }
  for (uint32_t x = 0; x < nodes; ++x)
    if (!reached[x]) return {};  // not edge-connected: split_region_in_two separates the parts
  // Primal spanning forest over the edges the dual tree does not cross; the first edge left out
  // closes a non-separating cycle (the shortest of them by tree depth is taken).
  for (uint32_t v = 0; v < parent.size(); ++v) parent[v] = v;
  uint32_t best = kNoFace, best_length = kNoFace;
  for (uint32_t e = 0; e < edges.size(); ++e) {
    if (in_dual_tree[e]) continue;
    const uint32_t a = find_root(parent, vertex_index[edges[e].a]), b = find_root(parent, vertex_index[edges[e].b]);
    if (a != b) {
      parent[a] = b;
      continue;
    }
    const uint32_t length = depth[edges[e].face[0]] + depth[edges[e].face[1]];
    if (length < best_length) best_length = length, best = e;
  }
  if (best == kNoFace) return {};  // genus 0
  // The dual cycle: both ends' tree paths up to their common ancestor, and the edge itself; its
  // real faces are the new region (a band across the handle, or a strip from border to border).
  std::vector<uint8_t> on_cycle(nodes, 0);
  uint32_t x = edges[best].face[0], y = edges[best].face[1];
  while (x != y) {
    if (depth[x] >= depth[y]) on_cycle[x] = 1, x = tree_parent[x];
    else on_cycle[y] = 1, y = tree_parent[y];
  }
  on_cycle[x] = 1;
  std::vector<uint32_t> band;
  for (uint32_t i = 0; i < n; ++i)
    if (on_cycle[i]) band.push_back(faces[i]);
  if (band.size() == faces.size()) return {};
  return band;
}


std::vector<RegionParameterization> make_disk_regions(const PolygonMesh& triangles, std::vector<uint32_t>& face_region,
                                                      size_t& num_regions, size_t pinned,
                                                      const DiskRegionOptions& options, DiskRegionReport* report,
                                                      const TaskMonitor& monitor) {
  if (face_region.size() != triangles.num_faces())
    fail(Status::invalid_argument, "disk regions: face_region has " + std::to_string(face_region.size()) +
                                       " entries for " + std::to_string(triangles.num_faces()) + " faces");
  DiskRegionReport local;
  DiskRegionReport& rep = report ? *report : local;
  rep = {};
  std::vector<std::vector<uint32_t>> faces(num_regions);
  for (uint32_t f = 0; f < face_region.size(); ++f) {
    if (face_region[f] >= num_regions) fail(Status::invalid_argument, "disk regions: a region id is out of range");
    faces[face_region[f]].push_back(f);
  }
  std::vector<RegionParameterization> domains(num_regions);
  std::vector<uint32_t> check(num_regions);
  for (uint32_t r = 0; r < num_regions; ++r) check[r] = r;
  for (int round = 0; !check.empty(); ++round) {
    std::vector<uint32_t> failing;
    std::vector<bool> by_topology;
    for (size_t k = 0; k < check.size(); ++k) {
      const uint32_t r = check[k];
      monitor.report("disk regions", std::min(0.99, (round + double(k) / double(check.size())) / (options.max_rounds + 1)));
      bool topology = false, folded = false;
      try {
        domains[r] = parameterize_region_lscm(triangles, faces[r], monitor);
        folded = options.split_folded && domains[r].flipped_triangles > 0;
      } catch (const Error& e) {
        if (e.status() != Status::invalid_mesh) throw;
        topology = true;
        domains[r] = {};
      }
      if (!topology && !folded) continue;
      if (topology) domains[r] = {};
      failing.push_back(r);
      by_topology.push_back(topology);
    }
    check.clear();
    // After `max_rounds` a folded map is kept as it is (the layout copes with folds or reports
    // them), but a region that is not a disk has no map at all: it is cut for up to
    // `max_topology_rounds` rounds in all (each cut lowers its genus or halves it, cheese.off: a
    // genus-2 part left after 8 rounds of fold splits).
    if (round >= options.max_rounds) {
      size_t kept = 0;
      for (size_t k = 0; k < failing.size(); ++k) {
        if (!by_topology[k]) {
          ++rep.failing_regions;
          continue;
        }
        failing[kept] = failing[k], by_topology[kept] = true, ++kept;
      }
      failing.resize(kept), by_topology.resize(kept);
      if (!failing.empty() && round >= std::max(options.max_rounds, options.max_topology_rounds)) {
        rep.failing_regions += failing.size();
        break;
      }
    }
    if (failing.empty()) break;
    for (size_t k = 0; k < failing.size(); ++k) {
      const uint32_t r = failing[k];
      if (r < pinned) {
        ++rep.failing_regions;  // the host's region stays as it is
        continue;
      }
      // A closed region or one with a handle is cut across the handle (halving keeps a handle
      // smaller than the parts: polygon_mesh.off's tiny tunnels), one that touches itself at a
      // vertex is split there; anything else is halved.
      std::vector<uint32_t> second;
      bool handle = false;
      if (by_topology[k]) {
        second = split_faces_at_pinch(triangles, faces[r]);
        if (second.empty()) {
          second = cut_region_handle(triangles, faces[r]);
          handle = !second.empty();
        }
      }
      if (second.empty()) second = split_region_in_two(triangles, faces[r]);
      if (second.empty() || second.size() == faces[r].size()) {
        ++rep.failing_regions;
        continue;
      }
      const uint32_t added = uint32_t(num_regions++);
      for (const uint32_t f : second) face_region[f] = added;
      std::vector<uint32_t> kept;
      kept.reserve(faces[r].size() - second.size());
      for (const uint32_t f : faces[r])
        if (face_region[f] == r) kept.push_back(f);
      faces[r] = std::move(kept);
      faces.push_back(std::move(second));
      domains.emplace_back();
      ++rep.split_regions;
      ++(by_topology[k] ? rep.topology_splits : rep.fold_splits);
      rep.handle_cuts += handle;
      check.push_back(r);
      check.push_back(added);
    }
  }
  return domains;
}

CAGEKIT_NAMESPACE_END
