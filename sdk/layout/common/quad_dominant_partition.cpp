// SPDX-License-Identifier: GPL-3.0-or-later
// Quad-dominant partitioning (thesis §3.9 / spec §3.9, acceptance item 20).
//
// Method. A cell is a union of 1-3 triangles of the given triangulation that is connected across
// interior diagonals and convex. Such cells are connected subsets of the triangulation's dual
// graph. For a simple polygon the dual graph is a tree, and the optimum is found EXACTLY at any
// size by a tree DP: root each tree; f(t) = best partition of t's subtree in which t's cell lies
// inside the subtree ("t is the top of its cell"); the cells with top t are {t}, {t,c},
// {t,c1,c2}, {t,c,grandchild} (c children), a constant number per node. O(T).
// A polygon with h holes has a dual graph with h independent cycles. We pick a spanning forest
// (cutting the dual edges that belong to the fewest convex cells) and enumerate, for each cut
// dual edge, which cell (if any) contains both of its triangles; each combination leaves a forest
// solved by the DP. This is exact. The enumeration is bounded: for faces with at most
// exact_vertex_limit vertices it is always complete (optimal = true); above, when the number of
// combinations times T exceeds a budget, the cut edges with most options are "fixed" as cell
// boundaries (the thesis' "fix some CDT diagonals"), and optimal = false.
//
// Degenerate corners. Cells are convex if no corner is reflex (exact orientation); a 180-degree
// corner is allowed (the vertex must stay in the cell's loop, or the neighbouring cell would get
// a T-junction). Such a corner lowers the cell's geometric ("effective") valence below its listed
// (topological) valence; the score is the worse of the two: omega = max(w(listed), w(effective))
// with w(4)=0, w(5)=1, w(3)=2. So a "quad" with a straight corner scores as a triangle and a
// "pentagon" with a straight corner still scores as a pentagon: degeneracy is never rewarded.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "core/edge_key.h"
#include "core/status.h"
#include "layout/common/quad_dominant_partition.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

constexpr int kNone = -1;

int omega(int valence) { return valence == 4 ? 0 : valence == 5 ? 1 : 2; }

struct Cell {
  int tris[3] = {-1, -1, -1};
  int nt = 0;
  uint32_t v[5] = {};
  int nv = 0;
  int score = 0;
};

class Partitioner {
 public:
  Partitioner(const PolygonLoops& polygon, const std::vector<std::array<uint32_t, 3>>& triangles)
      : P_(polygon.points), T_(triangles) {}

  // Builds the cell polygon of the triangles `tris`; false if it is not a convex 3-5-gon.
  bool make_cell(const int* tris, int nt, Cell& cell) const {
    uint32_t from[9], to[9];
    int ne = 0;
    for (int i = 0; i < nt; ++i)
      for (int k = 0; k < 3; ++k) {
        from[ne] = T_[tris[i]][k];
        to[ne] = T_[tris[i]][(k + 1) % 3];
        ++ne;
      }
    bool keep[9];
    for (int i = 0; i < ne; ++i) {
      keep[i] = true;
      for (int j = 0; j < ne; ++j)
        if (from[j] == to[i] && to[j] == from[i]) keep[i] = false;
    }
    uint32_t f2[9], t2[9];
    int nb = 0;
    for (int i = 0; i < ne; ++i)
      if (keep[i]) {
        f2[nb] = from[i];
        t2[nb] = to[i];
        ++nb;
      }
    if (nb != nt + 2) return false;
    cell.nt = nt;
    for (int i = 0; i < nt; ++i) cell.tris[i] = tris[i];
    cell.nv = nb;
    uint32_t cur = f2[0];
    for (int i = 0; i < nb; ++i) {
      cell.v[i] = cur;
      int found = -1;
      for (int j = 0; j < nb; ++j)
        if (f2[j] == cur) {
          if (found >= 0) return false;  // vertex visited twice: not a simple cell
          found = j;
        }
      if (found < 0) return false;
      cur = t2[found];
    }
    if (cur != cell.v[0]) return false;
    int effective = 0;
    for (int i = 0; i < nb; ++i) {
      const int o = orient2d(P_[cell.v[(i + nb - 1) % nb]], P_[cell.v[i]], P_[cell.v[(i + 1) % nb]]);
      if (o < 0) return false;
      if (o > 0) ++effective;
    }
    if (effective < 3) return false;
    cell.score = std::max(omega(nb), omega(effective));
    return true;
  }

  QuadDominantPartition run(const PartitionOptions& options) {
    validate();
    QuadDominantPartition result;
    result.optimal = true;
    const int T = static_cast<int>(T_.size());
    if (T == 0) return result;
    build_adjacency();
    build_forest();
    build_candidates();

    // Vertex count for the exactness guarantee.
    std::vector<char> used(P_.size(), 0);
    int nverts = 0;
    for (const auto& t : T_)
      for (uint32_t v : t)
        if (!used[v]) {
          used[v] = 1;
          ++nverts;
        }

    // Bound the enumeration over cut dual edges.
    none_fixed_.assign(cuts_.size(), 0);
    std::vector<int> active(cuts_.size());
    std::iota(active.begin(), active.end(), 0);
    if (nverts > options.exact_vertex_limit) {
      const double budget = 2e7;
      auto combos = [&]() {
        double c = static_cast<double>(T);
        for (int k : active) c *= 1.0 + static_cast<double>(cuts_[k].options.size());
        return c;
      };
      while (!active.empty() && combos() > budget) {
        auto it = std::max_element(active.begin(), active.end(), [&](int a, int b) {
          return cuts_[a].options.size() < cuts_[b].options.size();
        });
        none_fixed_[*it] = 1;
        result.optimal = false;
        active.erase(it);
      }
    }
    for (size_t k = 0; k < cuts_.size(); ++k)
      if (cuts_[k].options.empty()) none_fixed_[k] = 1;  // nothing to choose: a boundary anyway
    active_.clear();
    for (int k : active)
      if (!cuts_[k].options.empty()) active_.push_back(k);

    assigned_.assign(T, kNone);
    choice_.assign(cuts_.size(), -1);
    best_total_ = -1;
    enumerate(0, 0);

    // Reconstruct with the best combination.
    assigned_.assign(T, kNone);
    for (size_t a = 0; a < active_.size(); ++a) {
      const int k = active_[a], c = best_choice_[a];
      if (c >= 0)
        for (int i = 0; i < cuts_[k].options[c].nt; ++i) assigned_[cuts_[k].options[c].tris[i]] = k;
    }
    dp();
    int total = 0;
    auto emit = [&](const Cell& cell) {
      result.cells.emplace_back(cell.v, cell.v + cell.nv);
      total += cell.score;
    };
    for (size_t a = 0; a < active_.size(); ++a)
      if (best_choice_[a] >= 0) emit(cuts_[active_[a]].options[best_choice_[a]]);
    std::vector<int> stack(roots_.begin(), roots_.end());
    while (!stack.empty()) {
      const int t = stack.back();
      stack.pop_back();
      if (assigned_[t] != kNone) {
        for (int c : children_[t])
          if (c >= 0) stack.push_back(c);
        continue;
      }
      const Candidate& cand = cands_[pick_[t]];
      emit(cand.cell);
      for (int i = 0; i < cand.next; ++i) stack.push_back(cand.ext[i]);
    }
    result.score = total;
    return result;
  }

 private:
  struct CutEdge {
    int t1, t2;
    std::vector<Cell> options;  // convex cells containing both t1 and t2
  };
  struct Candidate {
    Cell cell;
    int ext[8];  // tree children of the members that are not members
    int next = 0;
  };

  void validate() const {
    const size_t n = P_.size();
    for (size_t i = 0; i < T_.size(); ++i) {
      const auto& t = T_[i];
      for (uint32_t v : t) {
        if (v >= n)
          fail(Status::invalid_argument, "partition_quad_dominant: triangle " + std::to_string(i) +
                                             " has point index " + std::to_string(v) + " out of range");
        if (!std::isfinite(P_[v].x) || !std::isfinite(P_[v].y))
          fail(Status::invalid_argument, "partition_quad_dominant: triangle " + std::to_string(i) +
                                             " has a non-finite vertex");
      }
      if (orient2d(P_[t[0]], P_[t[1]], P_[t[2]]) <= 0)
        fail(Status::invalid_argument, "partition_quad_dominant: triangle " + std::to_string(i) +
                                           " is not counter-clockwise (or degenerate)");
    }
  }

  void build_adjacency() {
    const int T = static_cast<int>(T_.size());
    nbr_.assign(T, {-1, -1, -1});
    struct HalfEdge {
      uint64_t key;
      int tri, side;
      bool forward;
    };
    std::vector<HalfEdge> he;
    he.reserve(3 * T_.size());
    for (int t = 0; t < T; ++t)
      for (int k = 0; k < 3; ++k) {
        const uint32_t a = T_[t][k], b = T_[t][(k + 1) % 3];
        const uint32_t lo = std::min(a, b), hi = std::max(a, b);
        he.push_back({directed_edge_key(lo, hi), t, k, a < b});
      }
    std::sort(he.begin(), he.end(), [](const HalfEdge& x, const HalfEdge& y) { return x.key < y.key; });
    for (size_t i = 0; i < he.size();) {
      size_t j = i;
      while (j < he.size() && he[j].key == he[i].key) ++j;
      if (j - i > 2 || (j - i == 2 && he[i].forward == he[i + 1].forward))
        fail(Status::invalid_argument,
             "partition_quad_dominant: triangles overlap (an edge is used by " + std::to_string(j - i) +
                 " triangles or twice in one direction)");
      if (j - i == 2) {
        nbr_[he[i].tri][he[i].side] = he[i + 1].tri;
        nbr_[he[i + 1].tri][he[i + 1].side] = he[i].tri;
      }
      i = j;
    }
  }

  // Spanning forest of the dual graph: cut the dual edges that lie in the fewest convex cells.
  void build_forest() {
    const int T = static_cast<int>(T_.size());
    struct DualEdge {
      int t1, t2;
      std::vector<Cell> options;
    };
    std::vector<DualEdge> dual;
    // Options (convex cells through a dual edge) only steer which edges are cut; a dual graph
    // without cycles (a simple polygon, the hot path) needs none of them.
    int ndual = 0;
    for (int t = 0; t < T; ++t)
      for (int k = 0; k < 3; ++k) ndual += nbr_[t][k] > t;
    const bool has_cycles = ndual > T - 1;
    dual.reserve(ndual);
    auto options_of = [&](int t, int u) {
      std::vector<Cell> options;
      Cell cell;
      int pair[2] = {t, u};
      if (make_cell(pair, 2, cell)) options.push_back(cell);
      for (int s = 0; s < 2; ++s)
        for (int q = 0; q < 3; ++q) {
          const int w = nbr_[pair[s]][q];
          if (w < 0 || w == t || w == u) continue;
          int tri3[3] = {t, u, w};
          if (make_cell(tri3, 3, cell)) options.push_back(cell);
        }
      return options;
    };
    for (int t = 0; t < T; ++t)
      for (int k = 0; k < 3; ++k) {
        const int u = nbr_[t][k];
        if (u > t) dual.push_back({t, u, has_cycles ? options_of(t, u) : std::vector<Cell>{}});
      }
    std::vector<int> order(dual.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return dual[a].options.size() > dual[b].options.size(); });
    std::vector<int> uf(T);
    std::iota(uf.begin(), uf.end(), 0);
    auto find = [&](int x) {
      while (uf[x] != x) x = uf[x] = uf[uf[x]];
      return x;
    };
    std::vector<std::array<int, 3>> tree_adj(T, {-1, -1, -1});
    for (int idx : order) {
      DualEdge& d = dual[idx];
      const int a = find(d.t1), b = find(d.t2);
      if (a != b) {
        uf[a] = b;
        for (int& s : tree_adj[d.t1])
          if (s < 0) {
            s = d.t2;
            break;
          }
        for (int& s : tree_adj[d.t2])
          if (s < 0) {
            s = d.t1;
            break;
          }
      } else {
        // (A dual graph with several components can have cycles although ndual <= T - 1.)
        cuts_.push_back({d.t1, d.t2, has_cycles ? std::move(d.options) : options_of(d.t1, d.t2)});
      }
    }
    parent_.assign(T, -1);
    children_.assign(T, {-1, -1, -1});
    post_.clear();
    roots_.clear();
    std::vector<char> seen(T, 0);
    std::vector<int> bfs;
    for (int r = 0; r < T; ++r) {
      if (seen[r]) continue;
      roots_.push_back(r);
      seen[r] = 1;
      bfs.clear();
      bfs.push_back(r);
      for (size_t i = 0; i < bfs.size(); ++i) {
        const int t = bfs[i];
        int nc = 0;
        for (int u : tree_adj[t])
          if (u >= 0 && !seen[u]) {
            seen[u] = 1;
            parent_[u] = t;
            children_[t][nc++] = u;
            bfs.push_back(u);
          }
      }
      post_.insert(post_.end(), bfs.rbegin(), bfs.rend());
    }
  }

  void add_candidate(int t, const int* members, int nm) {
    Candidate cand;
    if (!make_cell(members, nm, cand.cell)) return;
    for (int i = 0; i < nm; ++i)
      for (int c : children_[members[i]]) {
        if (c < 0) continue;
        bool member = false;
        for (int j = 0; j < nm; ++j) member = member || members[j] == c;
        if (!member) cand.ext[cand.next++] = c;
      }
    (void)t;
    cands_.push_back(cand);
  }

  void build_candidates() {
    const int T = static_cast<int>(T_.size());
    cand_begin_.assign(T + 1, 0);
    cands_.clear();
    for (int t = 0; t < T; ++t) {
      cand_begin_[t] = static_cast<int>(cands_.size());
      int one[1] = {t};
      add_candidate(t, one, 1);
      const auto& ch = children_[t];
      for (int i = 0; i < 3; ++i) {
        if (ch[i] < 0) continue;
        int two[2] = {t, ch[i]};
        add_candidate(t, two, 2);
        for (int j = i + 1; j < 3; ++j)
          if (ch[j] >= 0) {
            int three[3] = {t, ch[i], ch[j]};
            add_candidate(t, three, 3);
          }
        for (int g : children_[ch[i]])
          if (g >= 0) {
            int three[3] = {t, ch[i], g};
            add_candidate(t, three, 3);
          }
      }
    }
    cand_begin_[T] = static_cast<int>(cands_.size());
  }

  // Tree DP over the forest with the triangles in assigned_ removed; returns the forest's cost.
  int dp() {
    const int T = static_cast<int>(T_.size());
    g_.resize(T);
    pick_.resize(T);
    for (int t : post_) {
      if (assigned_[t] != kNone) {
        int s = 0;
        for (int c : children_[t])
          if (c >= 0) s += g_[c];
        g_[t] = s;
        continue;
      }
      int best = -1, best_c = -1;
      for (int ci = cand_begin_[t]; ci < cand_begin_[t + 1]; ++ci) {
        const Candidate& cand = cands_[ci];
        bool free = true;
        for (int i = 1; i < cand.cell.nt; ++i) free = free && assigned_[cand.cell.tris[i]] == kNone;
        if (!free) continue;
        int s = cand.cell.score;
        for (int i = 0; i < cand.next; ++i) s += g_[cand.ext[i]];
        if (best < 0 || s < best) {
          best = s;
          best_c = ci;
        }
      }
      g_[t] = best;  // {t} is always a candidate
      pick_[t] = best_c;
    }
    int total = 0;
    for (int r : roots_) total += g_[r];
    return total;
  }

  static bool contains(const Cell& c, int t) {
    for (int i = 0; i < c.nt; ++i)
      if (c.tris[i] == t) return true;
    return false;
  }

  void enumerate(size_t a, int fixed) {
    if (best_total_ >= 0 && fixed >= best_total_) return;  // scores are non-negative
    if (a == active_.size()) {
      const int total = fixed + dp();
      if (best_total_ < 0 || total < best_total_) {
        best_total_ = total;
        best_choice_.assign(active_.size(), -1);
        for (size_t i = 0; i < active_.size(); ++i) best_choice_[i] = choice_[active_[i]];
      }
      return;
    }
    const int k = active_[a];
    const CutEdge& cut = cuts_[k];
    if (assigned_[cut.t1] != kNone && assigned_[cut.t1] == assigned_[cut.t2]) {
      choice_[k] = -2;  // already inside an earlier chosen cell
      enumerate(a + 1, fixed);
      return;
    }
    // Option "none": t1 and t2 end up in different cells.
    choice_[k] = -1;
    none_fixed_[k] = 1;
    enumerate(a + 1, fixed);
    none_fixed_[k] = 0;
    for (size_t o = 0; o < cut.options.size(); ++o) {
      const Cell& cell = cut.options[o];
      bool ok = true;
      for (int i = 0; i < cell.nt && ok; ++i) ok = assigned_[cell.tris[i]] == kNone;
      for (size_t q = 0; q < cuts_.size() && ok; ++q)
        if (none_fixed_[q] && contains(cell, cuts_[q].t1) && contains(cell, cuts_[q].t2)) ok = false;
      if (!ok) continue;
      for (int i = 0; i < cell.nt; ++i) assigned_[cell.tris[i]] = k;
      choice_[k] = static_cast<int>(o);
      enumerate(a + 1, fixed + cell.score);
      for (int i = 0; i < cell.nt; ++i) assigned_[cell.tris[i]] = kNone;
    }
    choice_[k] = -1;
  }

  const std::vector<Vec2>& P_;
  const std::vector<std::array<uint32_t, 3>>& T_;
  std::vector<std::array<int, 3>> nbr_, children_;
  std::vector<int> parent_, post_, roots_;
  std::vector<CutEdge> cuts_;
  std::vector<Candidate> cands_;
  std::vector<int> cand_begin_;
  std::vector<char> none_fixed_;
  std::vector<int> active_, assigned_, choice_, best_choice_, g_, pick_;
  int best_total_ = -1;
};

}  // namespace

QuadDominantPartition partition_quad_dominant(const PolygonLoops& polygon,
                                              const std::vector<std::array<uint32_t, 3>>& triangles,
                                              const PartitionOptions& options) {
  Partitioner partitioner(polygon, triangles);
  return partitioner.run(options);
}

CAGEKIT_NAMESPACE_END
