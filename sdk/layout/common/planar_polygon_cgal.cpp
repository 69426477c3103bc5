// SPDX-License-Identifier: GPL-3.0-or-later
// Planar polygons with holes: exact validity test and constrained Delaunay triangulation.
// This is the only translation unit of the layout layer that includes CGAL's triangulation and
// kernel headers (each CGAL TU costs ~25 s and 1.4 GB to compile); other files reach the exact
// predicate through orient2d().
//
// Validity (thesis §3.4): all predicates are exact (Epick orientation with static filters and
// exact fallback; coordinate comparisons of doubles are exact). Small loop sets (the simplifier's
// hot path: one call per candidate merge) use allocation-free brute-force pair tests with
// bounding-box rejection; larger ones use a Shamos-Hoey sweep generalised from CGAL's
// is_simple_2 (Polygon_2_simplicity.h) to several loops, which also yields the loops' nesting
// tree in the same O(m log m) pass.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_face_base_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "core/status.h"
#include "layout/common/cgal_guard.h"
#include "layout/common/planar_polygon.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_2;

inline int orient(const Vec2& a, const Vec2& b, const Vec2& c) {
  return static_cast<int>(CGAL::orientation(Point(a.x, a.y), Point(b.x, b.y), Point(c.x, c.y)));
}
inline bool less_xy(const Vec2& a, const Vec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); }
// -1, 0, +1 lexicographic comparison.
inline int compare_xy(const Vec2& a, const Vec2& b) {
  if (a.x != b.x) return a.x < b.x ? -1 : 1;
  if (a.y != b.y) return a.y < b.y ? -1 : 1;
  return 0;
}
// c lies on the closed segment [a, b], given that a, b, c are collinear.
inline bool collinear_between(const Vec2& a, const Vec2& b, const Vec2& c) {
  return compare_xy(a, c) * compare_xy(c, b) >= 0;
}

// Closed segments [p1,p2] and [q1,q2] share a point (exact).
bool segments_intersect(const Vec2& p1, const Vec2& p2, const Vec2& q1, const Vec2& q2) {
  if (std::max(p1.x, p2.x) < std::min(q1.x, q2.x) || std::max(q1.x, q2.x) < std::min(p1.x, p2.x) ||
      std::max(p1.y, p2.y) < std::min(q1.y, q2.y) || std::max(q1.y, q2.y) < std::min(p1.y, p2.y))
    return false;
  const int o1 = orient(p1, p2, q1), o2 = orient(p1, p2, q2);
  if (o1 * o2 > 0) return false;
  const int o3 = orient(q1, q2, p1), o4 = orient(q1, q2, p2);
  if (o3 * o4 > 0) return false;
  if (o1 != 0 || o2 != 0 || o3 != 0 || o4 != 0) return true;  // proper or touching, non-collinear
  // All four collinear: the projections overlap (bounding boxes overlap on the common line).
  return collinear_between(p1, p2, q1) || collinear_between(p1, p2, q2) || collinear_between(q1, q2, p1) ||
         collinear_between(q1, q2, p2);
}

// Adjacent edges a-b and b-c overlap beyond their shared vertex b (collinear backtracking).
inline bool adjacent_overlap(const Vec2& a, const Vec2& b, const Vec2& c) {
  return orient(a, b, c) == 0 && compare_xy(a, b) == compare_xy(c, b);
}

// Winding number of a closed loop around p (p not on the loop), exact.
int winding(const PolygonLoops& poly, const std::vector<uint32_t>& loop, const Vec2& p) {
  int w = 0;
  const size_t n = loop.size();
  for (size_t i = 0; i < n; ++i) {
    const Vec2& a = poly.points[loop[i]];
    const Vec2& b = poly.points[loop[(i + 1) % n]];
    if (a.y <= p.y) {
      if (b.y > p.y && orient(a, b, p) > 0) ++w;
    } else if (b.y <= p.y && orient(a, b, p) < 0) {
      --w;
    }
  }
  return w;
}

// +1 CCW / -1 CW loop, exact: the turn at the lexicographically smallest vertex (0 if degenerate).
int loop_orientation(const PolygonLoops& poly, const std::vector<uint32_t>& loop) {
  const size_t n = loop.size();
  size_t k = 0;
  for (size_t i = 1; i < n; ++i)
    if (less_xy(poly.points[loop[i]], poly.points[loop[k]])) k = i;
  return orient(poly.points[loop[(k + n - 1) % n]], poly.points[loop[k]], poly.points[loop[(k + 1) % n]]);
}

PolygonValidity make(PolygonDefect defect, const std::string& message) {
  PolygonValidity v;
  v.defect = defect;
  v.message = message;
  return v;
}

std::string edge_name(size_t loop, size_t edge) {
  return "loop " + std::to_string(loop) + " edge " + std::to_string(edge);
}

// ---------------------------------------------------------------- Shamos-Hoey sweep (large m)
// Loop vertices are flattened to positions 0..m-1; edge e runs from position e to nxt[e].
struct Sweep;
struct SweepLess {
  Sweep* s;
  bool operator()(uint32_t i, uint32_t j) const;
};
struct Sweep {
  using Less = SweepLess;
  using Tree = std::set<uint32_t, Less>;
  struct EdgeData {
    Tree::iterator it;
    bool in_tree = false;
    bool left_to_right = false;
  };

  std::vector<Vec2> pt;
  std::vector<uint32_t> nxt, prv, loop_of, local;
  std::vector<uint32_t> order_of;  // rank of each position in xy order
  std::vector<EdgeData> edges;
  std::vector<int> parent, ccw;    // per loop: enclosing loop (-1: none), orientation
  std::vector<char> seen;
  bool ok = true;
  int64_t fail_a = -1, fail_b = -1;  // a vertex / edge pair where the sweep failed

  void fail(uint32_t a, uint32_t b) {
    if (ok) {
      fail_a = a;
      fail_b = b;
    }
    ok = false;
  }
  uint32_t left_index(uint32_t e) const { return edges[e].left_to_right ? e : nxt[e]; }
  bool less_than_in_tree(uint32_t new_edge, uint32_t tree_edge) {
    uint32_t left, right;
    if (edges[tree_edge].left_to_right) {
      left = tree_edge;
      right = nxt[tree_edge];
    } else {
      right = tree_edge;
      left = nxt[tree_edge];
    }
    const uint32_t mid = left_index(new_edge);
    if (mid == left) return true;
    const int o = orient(pt[left], pt[mid], pt[right]);
    if (o > 0) return true;
    if (o < 0) return false;
    fail(mid, tree_edge);
    return true;
  }
  bool on_right_side(uint32_t vt, uint32_t e, bool above) {
    const int turn = orient(pt[e], pt[vt], pt[nxt[e]]);
    const bool left_turn = edges[e].left_to_right ? above : !above;
    const bool good = left_turn ? turn < 0 : turn > 0;
    if (!good) fail(vt, e);
    return good;
  }
  bool insertion(Tree& tree, uint32_t pv, uint32_t mv, uint32_t nv) {
    const int o = orient(pt[pv], pt[mv], pt[nv]);
    if (o == 0) {
      fail(mv, pv);
      return false;
    }
    const bool left_turn = o > 0;
    EdgeData &tp = edges[pv], &tm = edges[mv];
    tp.in_tree = false;
    tp.left_to_right = false;
    tm.in_tree = false;
    tm.left_to_right = true;
    if (left_turn) {
      tp.it = tree.insert(pv).first;
      tp.in_tree = true;
      tm.it = tree.insert(mv).first;
      tm.in_tree = true;
    } else {
      tm.it = tree.insert(mv).first;
      tm.in_tree = true;
      tp.it = tree.insert(pv).first;
      tp.in_tree = true;
    }
    const uint32_t loop = loop_of[mv];
    if (!seen[loop]) {  // the loop's lexicographically smallest vertex: orientation + nesting
      seen[loop] = 1;
      ccw[loop] = left_turn ? 1 : 0;
      const uint32_t lower = left_turn ? mv : pv;
      Tree::iterator it = edges[lower].it;
      if (it != tree.begin()) {
        const uint32_t below = *std::prev(it);
        const uint32_t k = loop_of[below];
        const bool inside = (edges[below].left_to_right ? 1 : 0) == ccw[k];
        parent[loop] = inside ? static_cast<int>(k) : parent[k];
      }
    }
    return ok;
  }
  bool replacement(Tree& tree, uint32_t cur_edge, uint32_t next_edge) {
    EdgeData& td = edges[cur_edge];
    Tree::iterator cur = td.it;
    const uint32_t vt = td.left_to_right ? next_edge : cur_edge;
    if (cur != tree.begin() && !on_right_side(vt, *std::prev(cur), true)) return false;
    Tree::iterator above = std::next(cur);
    if (above != tree.end() && !on_right_side(vt, *above, false)) return false;
    EdgeData& nd = edges[next_edge];
    nd.left_to_right = td.left_to_right;
    nd.in_tree = false;
    tree.erase(cur);
    td.in_tree = false;
    nd.it = tree.insert(above, next_edge);
    nd.in_tree = true;
    return ok;
  }
  bool deletion(Tree& tree, uint32_t pv, uint32_t mv) {
    EdgeData &tp = edges[pv], &tm = edges[mv];
    Tree::iterator ps = tp.it, ms = tm.it;
    const uint32_t vt = tp.left_to_right ? mv : pv;
    Tree::iterator above = std::next(ps);
    if (above == ms) {
      ++above;
    } else if (std::next(ms) != ps) {
      fail(vt, std::next(ms) == tree.end() ? pv : *std::next(ms));
      return false;
    }
    tree.erase(ps);
    tp.in_tree = false;
    tree.erase(ms);
    tm.in_tree = false;
    if (above != tree.end() && !on_right_side(vt, *above, false)) return false;
    if (above != tree.begin() && !on_right_side(vt, *std::prev(above), true)) return false;
    return true;
  }
  // Runs the sweep over all positions; returns false at the first detected intersection.
  bool run(size_t nloops) {
    const size_t m = pt.size();
    std::vector<uint32_t> rank(m);
    for (size_t i = 0; i < m; ++i) rank[i] = static_cast<uint32_t>(i);
    std::sort(rank.begin(), rank.end(), [&](uint32_t a, uint32_t b) { return less_xy(pt[a], pt[b]); });
    order_of.assign(m, 0);
    for (size_t i = 0; i < m; ++i) order_of[rank[i]] = static_cast<uint32_t>(i);
    parent.assign(nloops, -1);
    ccw.assign(nloops, 0);
    seen.assign(nloops, 0);
    Tree tree(Less{this});
    edges.assign(m, EdgeData{tree.end(), false, false});
    for (size_t i = 0; i < m && ok; ++i) {
      const uint32_t cur = rank[i], pv = prv[cur], nv = nxt[cur];
      const bool next_right = order_of[cur] < order_of[nv], prev_right = order_of[cur] < order_of[pv];
      if (next_right) {
        if (prev_right)
          insertion(tree, pv, cur, nv);
        else
          replacement(tree, pv, cur);
      } else {
        if (prev_right)
          replacement(tree, cur, pv);
        else
          deletion(tree, pv, cur);
      }
    }
    return ok;
  }
};

bool SweepLess::operator()(uint32_t i, uint32_t j) const {
  if (i == j) return false;
  if (s->edges[j].in_tree) return s->less_than_in_tree(i, j);
  return !s->less_than_in_tree(j, i);
}

void flatten(const PolygonLoops& poly, const std::vector<size_t>& which, Sweep& s) {
  size_t m = 0;
  for (size_t l : which) m += poly.loops[l].size();
  s.pt.resize(m);
  s.nxt.resize(m);
  s.prv.resize(m);
  s.loop_of.resize(m);
  s.local.resize(m);
  size_t base = 0;
  for (size_t w = 0; w < which.size(); ++w) {
    const auto& loop = poly.loops[which[w]];
    const size_t n = loop.size();
    for (size_t k = 0; k < n; ++k) {
      s.pt[base + k] = poly.points[loop[k]];
      s.nxt[base + k] = static_cast<uint32_t>(base + (k + 1) % n);
      s.prv[base + k] = static_cast<uint32_t>(base + (k + n - 1) % n);
      s.loop_of[base + k] = static_cast<uint32_t>(w);
      s.local[base + k] = static_cast<uint32_t>(k);
    }
    base += n;
  }
}

constexpr size_t kBruteForceLimit = 40;

PolygonValidity check_small(const PolygonLoops& poly) {
  const auto& P = poly.points;
  const size_t nl = poly.loops.size();
  // Repeated indices or coordinates.
  for (size_t li = 0; li < nl; ++li) {
    const auto& A = poly.loops[li];
    for (size_t i = 0; i < A.size(); ++i)
      for (size_t lj = li; lj < nl; ++lj) {
        const auto& B = poly.loops[lj];
        for (size_t j = (lj == li ? i + 1 : 0); j < B.size(); ++j)
          if (A[i] == B[j] || P[A[i]] == P[B[j]])
            return make(PolygonDefect::repeated_vertex,
                        "loop " + std::to_string(li) + " vertex " + std::to_string(i) + " and loop " +
                            std::to_string(lj) + " vertex " + std::to_string(j) +
                            (A[i] == B[j] ? " repeat point index " + std::to_string(A[i])
                                          : " have identical coordinates"));
      }
  }
  // Edge pairs: first within each loop (self_intersection), then across loops.
  for (int pass = 0; pass < 2; ++pass)
  for (size_t li = 0; li < nl; ++li) {
    const auto& A = poly.loops[li];
    const size_t na = A.size();
    for (size_t i = 0; i < na; ++i) {
      const Vec2 &a0 = P[A[i]], &a1 = P[A[(i + 1) % na]];
      // Adjacent edge i, i+1 (within the loop).
      if (pass == 0 && adjacent_overlap(a0, a1, P[A[(i + 2) % na]]))
        return make(PolygonDefect::self_intersection, edge_name(li, i) + " and edge " +
                                                          std::to_string((i + 1) % na) +
                                                          " overlap (collinear, backtracking)");
      for (size_t lj = (pass == 0 ? li : li + 1); lj < (pass == 0 ? li + 1 : nl); ++lj) {
        const auto& B = poly.loops[lj];
        const size_t nb = B.size();
        size_t j = 0;
        if (lj == li) j = i + 2;
        for (; j < nb; ++j) {
          if (lj == li && i == 0 && j == na - 1) continue;  // adjacent through the wrap
          if (segments_intersect(a0, a1, P[B[j]], P[B[(j + 1) % nb]])) {
            if (lj == li)
              return make(PolygonDefect::self_intersection,
                          edge_name(li, i) + " and edge " + std::to_string(j) + " intersect");
            return make(PolygonDefect::loops_intersect,
                        edge_name(li, i) + " and " + edge_name(lj, j) + " intersect");
          }
        }
      }
    }
  }
  // Containment: loops are now disjoint, so one vertex decides.
  for (size_t h = 1; h < nl; ++h)
    if (winding(poly, poly.loops[0], P[poly.loops[h][0]]) == 0)
      return make(PolygonDefect::hole_outside, "hole loop " + std::to_string(h) + " is not inside the outer loop");
  for (size_t h = 1; h < nl; ++h)
    for (size_t g = 1; g < nl; ++g)
      if (g != h && winding(poly, poly.loops[g], P[poly.loops[h][0]]) != 0)
        return make(PolygonDefect::holes_nested,
                    "hole loop " + std::to_string(h) + " lies inside hole loop " + std::to_string(g));
  for (size_t l = 0; l < nl; ++l) {
    const int o = loop_orientation(poly, poly.loops[l]);
    if (l == 0 ? o <= 0 : o >= 0)
      return make(PolygonDefect::wrong_orientation,
                  l == 0 ? std::string("outer loop 0 is not counter-clockwise")
                         : "hole loop " + std::to_string(l) + " is not clockwise");
  }
  return {};
}

PolygonValidity check_large(const PolygonLoops& poly, size_t m) {
  const auto& P = poly.points;
  const size_t nl = poly.loops.size();
  {  // repeated indices / coordinates: sort positions by (x, y, index)
    struct Item {
      Vec2 p;
      uint32_t index, loop, k;
    };
    std::vector<Item> items;
    items.reserve(m);
    for (size_t l = 0; l < nl; ++l)
      for (size_t k = 0; k < poly.loops[l].size(); ++k)
        items.push_back({P[poly.loops[l][k]], poly.loops[l][k], static_cast<uint32_t>(l), static_cast<uint32_t>(k)});
    std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
      const int c = compare_xy(a.p, b.p);
      return c != 0 ? c < 0 : a.index < b.index;
    });
    for (size_t i = 1; i < items.size(); ++i)
      if (items[i - 1].p == items[i].p) {
        const Item &a = items[i - 1], &b = items[i];
        return make(PolygonDefect::repeated_vertex,
                    "loop " + std::to_string(a.loop) + " vertex " + std::to_string(a.k) + " and loop " +
                        std::to_string(b.loop) + " vertex " + std::to_string(b.k) +
                        (a.index == b.index ? " repeat point index " + std::to_string(a.index)
                                            : " have identical coordinates"));
      }
  }
  std::vector<size_t> all(nl);
  for (size_t l = 0; l < nl; ++l) all[l] = l;
  Sweep s;
  flatten(poly, all, s);
  if (!s.run(nl)) {
    // Classify: is one loop on its own non-simple?
    for (size_t l = 0; l < nl; ++l) {
      Sweep one;
      flatten(poly, std::vector<size_t>{l}, one);
      if (!one.run(1)) {
        std::ostringstream msg;
        msg << "loop " << l << " is not simple";
        if (one.fail_a >= 0)
          msg << " (at vertex " << one.local[one.fail_a] << ", against edge " << one.local[one.fail_b] << ")";
        return make(PolygonDefect::self_intersection, msg.str());
      }
    }
    std::ostringstream msg;
    msg << "loops intersect";
    if (s.fail_a >= 0)
      msg << " (loop " << s.loop_of[s.fail_a] << " vertex " << s.local[s.fail_a] << " against " << "loop "
          << s.loop_of[s.fail_b] << " edge " << s.local[s.fail_b] << ")";
    return make(PolygonDefect::loops_intersect, msg.str());
  }
  if (s.parent[0] != -1)
    return make(PolygonDefect::hole_outside,
                "hole loop " + std::to_string(s.parent[0]) + " encloses the outer loop");
  for (size_t h = 1; h < nl; ++h)
    if (s.parent[h] == -1)
      return make(PolygonDefect::hole_outside, "hole loop " + std::to_string(h) + " is not inside the outer loop");
  for (size_t h = 1; h < nl; ++h)
    if (s.parent[h] != 0)
      return make(PolygonDefect::holes_nested,
                  "hole loop " + std::to_string(h) + " lies inside hole loop " + std::to_string(s.parent[h]));
  for (size_t l = 0; l < nl; ++l)
    if ((l == 0) != (s.ccw[l] == 1))
      return make(PolygonDefect::wrong_orientation,
                  l == 0 ? std::string("outer loop 0 is not counter-clockwise")
                         : "hole loop " + std::to_string(l) + " is not clockwise");
  return {};
}

// ---------------------------------------------------------------- fast CDT of small simple polygons
// Ear clipping with exact orientation tests followed by Lawson flips with the exact in-circle
// predicate: the result is the constrained Delaunay triangulation, which is unique unless four
// vertices of a flippable quadrilateral are cocircular. In that case (and if no ear is found,
// which cannot happen for a valid polygon) the caller falls back to CGAL, so the triangle set
// is always the one CGAL's CDT produces. ~10x faster than building a CGAL CDT for the 8-16
// vertex polygons of the simplifier.
constexpr size_t kFastTriangulationLimit = 64;

inline int in_circle(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  return static_cast<int>(
      CGAL::side_of_oriented_circle(Point(a.x, a.y), Point(b.x, b.y), Point(c.x, c.y), Point(d.x, d.y)));
}

bool triangulate_small_simple(const PolygonLoops& polygon, std::vector<std::array<uint32_t, 3>>& out) {
  const auto& loop = polygon.loops[0];
  const int n = static_cast<int>(loop.size());
  if (n < 3 || static_cast<size_t>(n) > kFastTriangulationLimit) return false;
  Vec2 p[kFastTriangulationLimit];
  int prv[kFastTriangulationLimit], nxt[kFastTriangulationLimit];
  bool convex[kFastTriangulationLimit];
  // Triangle across the edge i -> nxt[i] of the remaining polygon (a clipped ear), or -1.
  int edge_tri[kFastTriangulationLimit], edge_k[kFastTriangulationLimit];
  struct Tri {
    int v[3], nb[3];  // nb[k]: triangle across the edge opposite v[k], -1 on the polygon boundary
  };
  Tri tri[kFastTriangulationLimit];
  for (int i = 0; i < n; ++i) {
    p[i] = polygon.points[loop[i]];
    prv[i] = i == 0 ? n - 1 : i - 1;
    nxt[i] = i + 1 == n ? 0 : i + 1;
    edge_tri[i] = -1;
  }
  for (int i = 0; i < n; ++i) convex[i] = orient(p[prv[i]], p[i], p[nxt[i]]) > 0;
  int nt = 0, remaining = n, cur = 0;
  auto link = [&](int t, int k, int i) {  // triangle t's edge opposite k is the polygon edge i -> nxt[i]
    tri[t].nb[k] = edge_tri[i];
    if (edge_tri[i] >= 0) tri[edge_tri[i]].nb[edge_k[i]] = t;
  };
  while (true) {
    const int a = prv[cur], c = nxt[cur];
    if (remaining == 3) {
      Tri& t = tri[nt];
      t.v[0] = a;
      t.v[1] = cur;
      t.v[2] = c;
      link(nt, 2, a);
      link(nt, 0, cur);
      link(nt, 1, c);
      ++nt;
      break;
    }
    // Find an ear: a strictly convex vertex whose closed triangle holds no other vertex. Only
    // non-convex vertices need testing (the vertex of a blocking chain farthest from the
    // diagonal is one).
    int tries = 0;
    for (;; cur = nxt[cur]) {
      if (++tries > remaining) return false;
      if (!convex[cur]) continue;
      const int ea = prv[cur], ec = nxt[cur];
      const Vec2 &A = p[ea], &B = p[cur], &C = p[ec];
      const double xmin = std::min(A.x, std::min(B.x, C.x)), xmax = std::max(A.x, std::max(B.x, C.x));
      const double ymin = std::min(A.y, std::min(B.y, C.y)), ymax = std::max(A.y, std::max(B.y, C.y));
      bool ear = true;
      for (int q = nxt[ec]; q != ea; q = nxt[q]) {
        if (convex[q]) continue;
        const Vec2& Q = p[q];
        if (Q.x < xmin || Q.x > xmax || Q.y < ymin || Q.y > ymax) continue;
        if (orient(A, B, Q) >= 0 && orient(B, C, Q) >= 0 && orient(C, A, Q) >= 0) {
          ear = false;
          break;
        }
      }
      if (ear) break;
    }
    const int ea = prv[cur], ec = nxt[cur];
    Tri& t = tri[nt];
    t.v[0] = ea;
    t.v[1] = cur;
    t.v[2] = ec;
    link(nt, 2, ea);   // ea -> cur
    link(nt, 0, cur);  // cur -> ec
    t.nb[1] = -1;      // ec -> ea: the new diagonal, linked when its other side is clipped
    nxt[ea] = ec;
    prv[ec] = ea;
    edge_tri[ea] = nt;
    edge_k[ea] = 1;
    ++nt;
    --remaining;
    convex[ea] = orient(p[prv[ea]], p[ea], p[ec]) > 0;
    convex[ec] = orient(p[ea], p[ec], p[nxt[ec]]) > 0;
    cur = ec;
  }
  // Lawson flips to the constrained Delaunay triangulation.
  int stack_t[4 * kFastTriangulationLimit + 8], stack_k[4 * kFastTriangulationLimit + 8];
  int top = 0;
  bool overflow = false;
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k)
      if (tri[t].nb[k] > t) {
        stack_t[top] = t;
        stack_k[top++] = k;
      }
  auto back_index = [&](int u, int t) {
    return tri[u].nb[0] == t ? 0 : (tri[u].nb[1] == t ? 1 : 2);
  };
  auto push = [&](int t, int k) {
    if (tri[t].nb[k] < 0) return;
    if (top == static_cast<int>(sizeof(stack_t) / sizeof(stack_t[0]))) {
      overflow = true;  // fall back to CGAL below
      return;
    }
    stack_t[top] = t;
    stack_k[top++] = k;
  };
  int flips = 0;
  while (top > 0) {
    --top;
    const int t = stack_t[top], k = stack_k[top];
    const int u = tri[t].nb[k];
    if (u < 0) continue;
    const int ku = back_index(u, t);
    const int a = tri[t].v[k], b = tri[t].v[(k + 1) % 3], c = tri[t].v[(k + 2) % 3];
    const int d = tri[u].v[ku];
    if (in_circle(p[a], p[b], p[c], p[d]) <= 0) continue;
    if (++flips > 64 * n) return false;  // cannot happen (Lawson flips terminate)
    const int ta = tri[t].nb[(k + 1) % 3], tb = tri[t].nb[(k + 2) % 3];    // across c-a, a-b
    const int ub = tri[u].nb[(ku + 1) % 3], uc = tri[u].nb[(ku + 2) % 3];  // across b-d, d-c
    tri[t] = Tri{{a, b, d}, {ub, u, tb}};
    tri[u] = Tri{{a, d, c}, {uc, ta, t}};
    if (ub >= 0) tri[ub].nb[back_index(ub, u)] = t;
    if (ta >= 0) tri[ta].nb[back_index(ta, t)] = u;
    push(t, 0);
    push(t, 2);
    push(u, 0);
    push(u, 1);
  }
  if (overflow) return false;
  // Cocircular quadrilaterals: the CDT is not unique; leave the choice to CGAL.
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      const int u = tri[t].nb[k];
      if (u <= t) continue;
      const int d = tri[u].v[back_index(u, t)];
      if (in_circle(p[tri[t].v[0]], p[tri[t].v[1]], p[tri[t].v[2]], p[d]) >= 0) return false;
    }
  out.resize(static_cast<size_t>(nt));
  for (int t = 0; t < nt; ++t)
    out[static_cast<size_t>(t)] = {loop[tri[t].v[0]], loop[tri[t].v[1]], loop[tri[t].v[2]]};
  return true;
}

// ---------------------------------------------------------------- triangulation
struct FaceInfo {
  int depth = -1;
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<uint32_t, Kernel>;
using Fbb = CGAL::Triangulation_face_base_with_info_2<FaceInfo, Kernel>;
using Fb = CGAL::Constrained_triangulation_face_base_2<Kernel, Fbb>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::No_constraint_intersection_tag>;

PolygonValidity check_loops(const PolygonLoops& polygon) {
  const size_t nl = polygon.loops.size();
  if (nl == 0) return make(PolygonDefect::too_few_vertices, "no outer loop");
  size_t m = 0;
  for (size_t l = 0; l < nl; ++l) {
    const auto& loop = polygon.loops[l];
    if (loop.size() < 3)
      return make(PolygonDefect::too_few_vertices,
                  "loop " + std::to_string(l) + " has " + std::to_string(loop.size()) + " vertices");
    for (size_t k = 0; k < loop.size(); ++k) {
      if (loop[k] >= polygon.points.size())
        return make(PolygonDefect::self_intersection, "loop " + std::to_string(l) + " vertex " + std::to_string(k) +
                                                          ": point index " + std::to_string(loop[k]) +
                                                          " out of range");
      const Vec2& p = polygon.points[loop[k]];
      if (!std::isfinite(p.x) || !std::isfinite(p.y))
        return make(PolygonDefect::self_intersection,
                    "loop " + std::to_string(l) + " vertex " + std::to_string(k) + ": non-finite coordinate");
    }
    m += loop.size();
  }
  return m <= kBruteForceLimit ? check_small(polygon) : check_large(polygon, m);
}

// The CDT of a polygon that check_polygon_loops accepted (CGAL's checks still run: see cgal_guard.h).
std::vector<std::array<uint32_t, 3>> constrained_delaunay(const PolygonLoops& polygon) {
  CDT cdt;
  // All vertices first, then all constraints. The point-location hint must be a face that
  // exists: inserting a constraint deletes the triangles it crosses, so a hint taken before
  // a loop's constraints went in (as the first vertex of the next loop once used) can be a
  // freed face, and the walk from it read freed memory (SIGSEGV on polygons with holes whose
  // outer loop edges are not Delaunay edges). Point insertion only splits and flips faces,
  // so each new vertex's face is live when the next point is inserted.
  std::vector<CDT::Vertex_handle> handles;
  size_t m = 0;
  for (const auto& loop : polygon.loops) m += loop.size();
  handles.reserve(m);
  CDT::Face_handle hint;
  for (const auto& loop : polygon.loops)
    for (const uint32_t index : loop) {
      const Vec2& p = polygon.points[index];
      CDT::Vertex_handle v = cdt.insert(Point(p.x, p.y), hint);
      v->info() = index;
      hint = v->face();
      handles.push_back(v);
    }
  size_t base = 0;
  for (const auto& loop : polygon.loops) {
    const size_t n = loop.size();
    for (size_t k = 0; k < n; ++k) cdt.insert_constraint(handles[base + k], handles[base + (k + 1) % n]);
    base += n;
  }
  // Nesting depth by flood fill from the infinite face, crossing constraints increments it.
  std::vector<CDT::Face_handle> stack;
  std::vector<CDT::Edge> border;
  auto fill = [&](CDT::Face_handle start, int depth) {
    if (start->info().depth != -1) return;
    stack.clear();
    stack.push_back(start);
    start->info().depth = depth;
    while (!stack.empty()) {
      CDT::Face_handle f = stack.back();
      stack.pop_back();
      for (int i = 0; i < 3; ++i) {
        CDT::Face_handle n = f->neighbor(i);
        if (n->info().depth != -1) continue;
        if (cdt.is_constrained(CDT::Edge(f, i))) {
          border.push_back(CDT::Edge(f, i));
        } else {
          n->info().depth = depth;
          stack.push_back(n);
        }
      }
    }
  };
  fill(cdt.infinite_face(), 0);
  for (size_t b = 0; b < border.size(); ++b) {
    const CDT::Edge e = border[b];
    CDT::Face_handle n = e.first->neighbor(e.second);
    if (n->info().depth == -1) fill(n, e.first->info().depth + 1);
  }
  std::vector<std::array<uint32_t, 3>> triangles;
  triangles.reserve(cdt.number_of_faces());
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    if (f->info().depth % 2 == 1)
      triangles.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  return triangles;
}

}  // namespace

int orient2d(const Vec2& a, const Vec2& b, const Vec2& c) {
  return detail::cgal_guarded("orient2d", [&] { return orient(a, b, c); });
}

PolygonValidity check_polygon_loops(const PolygonLoops& polygon) {
  return detail::cgal_guarded("check_polygon_loops", [&] { return check_loops(polygon); });
}

std::vector<std::array<uint32_t, 3>> triangulate_polygon(const PolygonLoops& polygon) {
  const PolygonValidity validity = check_polygon_loops(polygon);
  if (!validity.ok()) fail(Status::invalid_argument, "triangulate_polygon: invalid polygon: " + validity.message);
  std::vector<std::array<uint32_t, 3>> triangles;
  triangulate_valid_polygon(polygon, triangles);
  return triangles;
}

void triangulate_valid_polygon(const PolygonLoops& polygon, std::vector<std::array<uint32_t, 3>>& triangles) {
  const bool fast = detail::cgal_guarded("triangulate_valid_polygon", [&] {
    return polygon.loops.size() == 1 && triangulate_small_simple(polygon, triangles);
  });
  if (!fast) triangles = detail::triangulate_polygon_cgal(polygon);
}

namespace detail {
std::vector<std::array<uint32_t, 3>> triangulate_polygon_cgal(const PolygonLoops& polygon) {
  const PolygonValidity validity = check_polygon_loops(polygon);
  if (!validity.ok()) fail(Status::invalid_argument, "triangulate_polygon: invalid polygon: " + validity.message);
  return detail::cgal_guarded("triangulate_polygon", [&] { return constrained_delaunay(polygon); });
}
}  // namespace detail

CAGEKIT_NAMESPACE_END
