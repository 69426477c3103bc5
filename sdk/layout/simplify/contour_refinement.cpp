// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/simplify/contour_refinement.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "core/edge_key.h"
#include "core/status.h"
#include "layout/common/planar_polygon.h"
#include "layout/simplify/cage_builder.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {


// The border half-edges of every cluster: (cluster, from) -> the half-edges' ends.
class ClusterBorders {
 public:
  ClusterBorders(const PolygonMesh& input, const std::vector<uint32_t>& cluster_of_face) {
    // Every half-edge as (from, to) key with its face, sorted: the opposite of (u, v) is found by
    // binary search (a hash map over millions of half-edges is several times slower).
    std::vector<std::pair<uint64_t, uint32_t>> half_edges;
    half_edges.reserve(input.num_face_vertices());
    for (uint32_t f = 0; f < input.num_faces(); ++f) {
      const uint32_t n = input.face_size(f);
      for (uint32_t k = 0; k < n; ++k)
        half_edges.emplace_back(directed_edge_key(input.face_vertex(f, k), input.face_vertex(f, (k + 1) % n)), f);
    }
    std::sort(half_edges.begin(), half_edges.end());
    auto cluster_of = [&](uint32_t f) { return f < cluster_of_face.size() ? cluster_of_face[f] : UINT32_MAX; };
    for (const auto& [key, f] : half_edges) {
      const uint32_t c = cluster_of(f);
      if (c == UINT32_MAX) continue;
      const uint32_t u = edge_key_first(key), v = edge_key_second(key);
      const auto opposite = std::lower_bound(half_edges.begin(), half_edges.end(), std::make_pair(directed_edge_key(v, u), 0u));
      bool inside = false;
      for (auto it = opposite; it != half_edges.end() && it->first == directed_edge_key(v, u); ++it)
        inside = inside || cluster_of(it->second) == c;
      if (inside) continue;
      next_.emplace(directed_edge_key(c, u), v);
      ++count_[c];
    }
  }

  // The chain of input vertices from a to b along cluster c's border, or empty if not found.
  std::vector<uint32_t> chain(uint32_t c, uint32_t a, uint32_t b) const {
    const auto limit_it = count_.find(c);
    const size_t limit = limit_it == count_.end() ? 0 : limit_it->second;
    const auto first = next_.equal_range(directed_edge_key(c, a));
    for (auto it = first.first; it != first.second; ++it) {
      std::vector<uint32_t> path{a, it->second};
      bool ok = true;
      while (path.back() != b && ok) {
        if (path.size() > limit + 1) {
          ok = false;
          break;
        }
        const auto range = next_.equal_range(directed_edge_key(c, path.back()));
        if (range.first == range.second || std::next(range.first) != range.second) {
          ok = false;  // dead end or a pinch inside the chain: not a level edge's chain
          break;
        }
        path.push_back(range.first->second);
      }
      if (ok) return path;
    }
    return {};
  }

 private:
  std::unordered_multimap<uint64_t, uint32_t> next_;
  std::unordered_map<uint32_t, size_t> count_;
};

// Douglas-Peucker over chain[0..m]: flags of the vertices to keep (ends always kept).
void douglas_peucker(const PolygonMesh& input, const std::vector<uint32_t>& chain, double tolerance,
                     std::vector<char>& keep) {
  keep.assign(chain.size(), 0);
  keep.front() = keep.back() = 1;
  std::vector<std::pair<size_t, size_t>> stack{{0, chain.size() - 1}};
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    if (j <= i + 1) continue;
    const Vec3& a = input.positions[chain[i]];
    const Vec3& b = input.positions[chain[j]];
    double worst = -1;
    size_t at = i;
    for (size_t k = i + 1; k < j; ++k) {
      const double d = point_segment_distance(input.positions[chain[k]], a, b);
      if (d > worst) {
        worst = d;
        at = k;
      }
    }
    if (worst <= tolerance) continue;
    keep[at] = 1;
    stack.push_back({i, at});
    stack.push_back({at, j});
  }
}

}  // namespace

PolygonalLevel refine_level_contours(const PolygonMesh& input, const PolygonalLevel& level, double chord_tolerance,
                                     ContourRefinementReport* report) {
  if (!(chord_tolerance > 0) || !std::isfinite(chord_tolerance))
    fail(Status::invalid_argument, "contour refinement: chord tolerance must be finite and > 0");
  ContourRefinementReport local;
  ContourRefinementReport& r = report ? *report : local;
  r = ContourRefinementReport{};
  const ClusterBorders borders(input, level.cluster_of_input_face);
  // Per level edge (undirected) whose refinement made a face invalid: its tolerance is doubled
  // (kFrozen doublings: not refined at all).
  constexpr int kFrozen = 24;
  std::unordered_map<uint64_t, int> coarser;
  PolygonalLevel out = level;
  std::vector<char> keep;
  for (;;) {
    ContourRefinementReport pass;
    std::vector<uint32_t> invalid;
    for (size_t f = 0; f < level.faces.size(); ++f) {
      PolygonalFace& face = out.faces[f];
      face.loops.clear();
      for (const auto& loop : level.faces[f].loops) {
        std::vector<uint32_t> refined;
        for (size_t k = 0; k < loop.size(); ++k) {
          const uint32_t a = loop[k], b = loop[(k + 1) % loop.size()];
          refined.push_back(a);
          const auto c = coarser.find(edge_key(a, b));
          const int doublings = c == coarser.end() ? 0 : c->second;
          if (doublings >= kFrozen) {
            ++pass.edges_frozen;
            continue;
          }
          std::vector<uint32_t> chain = borders.chain(uint32_t(f), a, b);
          if (chain.empty()) {
            ++pass.edges_no_chain;
            continue;
          }
          if (chain.size() <= 2) continue;
          // Canonical direction, so that both faces along the edge keep the same vertices.
          const bool reversed = a > b;
          if (reversed) std::reverse(chain.begin(), chain.end());
          if (doublings > 0) ++pass.edges_coarsened;
          douglas_peucker(input, chain, std::ldexp(chord_tolerance, doublings), keep);
          if (reversed) {
            std::reverse(chain.begin(), chain.end());
            std::reverse(keep.begin(), keep.end());
          }
          size_t added = 0;
          for (size_t i = 1; i + 1 < chain.size(); ++i)
            if (keep[i]) {
              refined.push_back(chain[i]);
              ++added;
            }
          if (added > 0) {
            ++pass.edges_refined;
            pass.vertices_added += added;
          }
        }
        face.loops.push_back(std::move(refined));
      }
      std::vector<uint32_t> unused;
      if (!check_polygon_loops(project_face(input, face, level.coordinates, &unused)).ok()) invalid.push_back(uint32_t(f));
    }
    r = pass;
    if (invalid.empty()) break;
    bool changed = false;
    for (uint32_t f : invalid)
      for (const auto& loop : level.faces[f].loops)
        for (size_t k = 0; k < loop.size(); ++k) {
          int& d = coarser[edge_key(loop[k], loop[(k + 1) % loop.size()])];
          if (d < kFrozen) {
            ++d;
            changed = true;
          }
        }
    if (!changed) {
      // Every edge of the invalid faces is frozen: they are the level's own faces again, so
      // they were invalid in the level itself. Keep the level's loops for them.
      for (uint32_t f : invalid) out.faces[f].loops = level.faces[f].loops;
      break;
    }
  }
  std::unordered_set<uint32_t> used;
  for (const PolygonalFace& face : out.faces)
    for (const auto& loop : face.loops) used.insert(loop.begin(), loop.end());
  out.num_vertices = used.size();
  return out;
}

CAGEKIT_NAMESPACE_END
