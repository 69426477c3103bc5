// SPDX-License-Identifier: GPL-3.0-or-later
// Planar polygons with holes: the exact validity test (thesis §3.4, acceptance item 12) and the
// constrained Delaunay triangulation. Randomised cases are compared against an independent
// brute-force checker on an integer grid with exact int64 orientation tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <set>

#include "core/status.h"
#include "layout/common/planar_polygon.h"

using namespace cagekit;

namespace {

using IPt = std::array<int64_t, 2>;

PolygonLoops make_polygon(const std::vector<std::vector<IPt>>& loops) {
  PolygonLoops poly;
  for (const auto& loop : loops) {
    std::vector<uint32_t> idx;
    for (const auto& p : loop) {
      idx.push_back(static_cast<uint32_t>(poly.points.size()));
      poly.points.push_back({static_cast<double>(p[0]), static_cast<double>(p[1])});
    }
    poly.loops.push_back(idx);
  }
  return poly;
}

// ----------------------------------------------------------- independent exact brute force
IPt ip(const Vec2& v) { return {static_cast<int64_t>(v.x), static_cast<int64_t>(v.y)}; }
int iorient(IPt a, IPt b, IPt c) {
  const int64_t d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  return (d > 0) - (d < 0);
}
bool on_segment(IPt a, IPt b, IPt p) {  // p on closed segment ab, given collinear
  return std::min(a[0], b[0]) <= p[0] && p[0] <= std::max(a[0], b[0]) && std::min(a[1], b[1]) <= p[1] &&
         p[1] <= std::max(a[1], b[1]);
}
bool iseg(IPt a, IPt b, IPt c, IPt d) {
  const int o1 = iorient(a, b, c), o2 = iorient(a, b, d), o3 = iorient(c, d, a), o4 = iorient(c, d, b);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  if (o1 == 0 && on_segment(a, b, c)) return true;
  if (o2 == 0 && on_segment(a, b, d)) return true;
  if (o3 == 0 && on_segment(c, d, a)) return true;
  if (o4 == 0 && on_segment(c, d, b)) return true;
  return false;
}
int64_t twice_area(const PolygonLoops& poly, const std::vector<uint32_t>& loop) {
  int64_t s = 0;
  for (size_t i = 0; i < loop.size(); ++i) {
    const IPt a = ip(poly.points[loop[i]]), b = ip(poly.points[loop[(i + 1) % loop.size()]]);
    s += a[0] * b[1] - a[1] * b[0];
  }
  return s;
}
// Point strictly inside loop (p not on it): ray casting with exact integer arithmetic.
bool inside(const PolygonLoops& poly, const std::vector<uint32_t>& loop, IPt p) {
  bool in = false;
  for (size_t i = 0; i < loop.size(); ++i) {
    IPt a = ip(poly.points[loop[i]]), b = ip(poly.points[loop[(i + 1) % loop.size()]]);
    if ((a[1] > p[1]) != (b[1] > p[1])) {
      if (a[1] > b[1]) std::swap(a, b);
      if (iorient(a, b, p) > 0) in = !in;  // p left of the upward edge: crossing to the right
    }
  }
  return in;
}

PolygonDefect brute_force(const PolygonLoops& poly) {
  const auto& L = poly.loops;
  for (const auto& l : L)
    if (l.size() < 3) return PolygonDefect::too_few_vertices;
  std::vector<std::pair<uint32_t, IPt>> all;
  for (const auto& l : L)
    for (uint32_t v : l) all.push_back({v, ip(poly.points[v])});
  for (size_t i = 0; i < all.size(); ++i)
    for (size_t j = i + 1; j < all.size(); ++j)
      if (all[i].first == all[j].first || all[i].second == all[j].second) return PolygonDefect::repeated_vertex;
  auto edge = [&](size_t l, size_t i, IPt& a, IPt& b) {
    a = ip(poly.points[L[l][i]]);
    b = ip(poly.points[L[l][(i + 1) % L[l].size()]]);
  };
  for (size_t l = 0; l < L.size(); ++l) {
    const size_t n = L[l].size();
    for (size_t i = 0; i < n; ++i)
      for (size_t j = i + 1; j < n; ++j) {
        IPt a, b, c, d;
        edge(l, i, a, b);
        edge(l, j, c, d);
        if (j == i + 1 || (i == 0 && j == n - 1)) {
          // Adjacent: they share exactly one endpoint; overlap if collinear and pointing back.
          const IPt shared = (j == i + 1) ? b : a;
          const IPt p = (j == i + 1) ? a : b, q = (j == i + 1) ? d : c;
          if (iorient(p, shared, q) == 0 &&
              (p[0] - shared[0]) * (q[0] - shared[0]) + (p[1] - shared[1]) * (q[1] - shared[1]) > 0)
            return PolygonDefect::self_intersection;
        } else if (iseg(a, b, c, d)) {
          return PolygonDefect::self_intersection;
        }
      }
  }
  for (size_t l = 0; l < L.size(); ++l)
    for (size_t k = l + 1; k < L.size(); ++k)
      for (size_t i = 0; i < L[l].size(); ++i)
        for (size_t j = 0; j < L[k].size(); ++j) {
          IPt a, b, c, d;
          edge(l, i, a, b);
          edge(k, j, c, d);
          if (iseg(a, b, c, d)) return PolygonDefect::loops_intersect;
        }
  for (size_t h = 1; h < L.size(); ++h)
    if (!inside(poly, L[0], ip(poly.points[L[h][0]]))) return PolygonDefect::hole_outside;
  for (size_t h = 1; h < L.size(); ++h)
    for (size_t g = 1; g < L.size(); ++g)
      if (g != h && inside(poly, L[g], ip(poly.points[L[h][0]]))) return PolygonDefect::holes_nested;
  for (size_t l = 0; l < L.size(); ++l) {
    const int64_t a = twice_area(poly, L[l]);
    if (l == 0 ? a <= 0 : a >= 0) return PolygonDefect::wrong_orientation;
  }
  return PolygonDefect::none;
}

// Star-shaped loop around (cx, cy) with radii in [r0, r1], on the integer grid.
std::vector<IPt> star(std::mt19937& rng, int n, double cx, double cy, double r0, double r1, bool ccw) {
  std::uniform_real_distribution<double> rad(r0, r1), jitter(-0.3, 0.3);
  std::vector<IPt> pts;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * (i + jitter(rng) + 0.5) / n * (ccw ? 1 : -1);
    const double r = rad(rng);
    pts.push_back({static_cast<int64_t>(std::llround(cx + r * std::cos(a))),
                   static_cast<int64_t>(std::llround(cy + r * std::sin(a)))});
  }
  return pts;
}

PolygonLoops random_polygon(std::mt19937& rng, int n_outer, int holes, int n_hole, double scale) {
  std::vector<std::vector<IPt>> loops;
  loops.push_back(star(rng, n_outer, 0, 0, 0.75 * scale, scale, true));
  for (int h = 0; h < holes; ++h) {
    const double a = 2 * M_PI * h / std::max(holes, 1);
    const double off = holes > 1 ? 0.4 * scale : 0.0;
    loops.push_back(star(rng, n_hole, off * std::cos(a), off * std::sin(a), 0.08 * scale, 0.2 * scale, false));
  }
  return make_polygon(loops);
}

const char* name(PolygonDefect d) {
  switch (d) {
    case PolygonDefect::none: return "none";
    case PolygonDefect::too_few_vertices: return "too_few_vertices";
    case PolygonDefect::repeated_vertex: return "repeated_vertex";
    case PolygonDefect::self_intersection: return "self_intersection";
    case PolygonDefect::loops_intersect: return "loops_intersect";
    case PolygonDefect::hole_outside: return "hole_outside";
    case PolygonDefect::holes_nested: return "holes_nested";
    case PolygonDefect::wrong_orientation: return "wrong_orientation";
  }
  return "?";
}

const std::vector<IPt> kSquare = {{0, 0}, {10, 0}, {10, 10}, {0, 10}};

}  // namespace

// ------------------------------------------------------------------------------ validity
TEST(PlanarPolygonValidity, ValidSquareAndTwoHoles) {
  EXPECT_TRUE(check_polygon_loops(make_polygon({kSquare})).ok());
  const auto poly = make_polygon({kSquare, {{1, 1}, {1, 4}, {4, 4}, {4, 1}}, {{6, 6}, {6, 9}, {9, 9}, {9, 6}}});
  const auto v = check_polygon_loops(poly);
  EXPECT_TRUE(v.ok()) << v.message;
}

TEST(PlanarPolygonValidity, HandMadeDefects) {
  struct Case {
    std::vector<std::vector<IPt>> loops;
    PolygonDefect expected;
  };
  const std::vector<Case> cases = {
      {{{{0, 0}, {10, 0}}}, PolygonDefect::too_few_vertices},
      {{{{0, 0}, {10, 0}, {0, 10}, {10, 10}}}, PolygonDefect::self_intersection},  // figure eight
      {{kSquare, {{0, 5}, {3, 3}, {3, 7}}}, PolygonDefect::loops_intersect},        // hole touches outer
      {{kSquare, {{2, 2}, {2, 6}, {6, 6}, {6, 2}}, {{6, 4}, {8, 3}, {8, 5}}},
       PolygonDefect::loops_intersect},                                           // two holes touch
      {{kSquare, {{20, 20}, {20, 22}, {22, 22}}}, PolygonDefect::hole_outside},   // hole outside
      {{kSquare, {{1, 1}, {1, 9}, {9, 9}, {9, 1}}, {{3, 3}, {3, 5}, {5, 5}}}, PolygonDefect::holes_nested},
      {{{{0, 0}, {0, 10}, {10, 10}, {10, 0}}}, PolygonDefect::wrong_orientation},  // clockwise outer
      {{kSquare, {{2, 2}, {6, 2}, {6, 6}}}, PolygonDefect::wrong_orientation},      // CCW hole
      {{{{0, 0}, {10, 0}, {10, 10}, {0, 10}, {0, 0}}}, PolygonDefect::repeated_vertex},  // same coordinates
      {{{{0, 0}, {10, 0}, {5, 0}, {5, 10}}}, PolygonDefect::self_intersection},  // collinear backtracking
      {{{{0, 0}, {10, 0}, {10, 10}, {5, 10}, {5, 0}, {3, 5}}}, PolygonDefect::self_intersection},  // vertex on edge
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const auto poly = make_polygon(cases[i].loops);
    const auto v = check_polygon_loops(poly);
    EXPECT_EQ(v.defect, cases[i].expected) << "case " << i << ": " << v.message;
    EXPECT_FALSE(v.message.empty()) << "case " << i;
    EXPECT_EQ(brute_force(poly), cases[i].expected) << "case " << i << " (test's brute force)";
  }
  // Repeated point index (same index twice in the loop set).
  PolygonLoops poly = make_polygon({kSquare});
  poly.loops[0] = {0, 1, 2, 0, 3};
  EXPECT_EQ(check_polygon_loops(poly).defect, PolygonDefect::repeated_vertex);
  poly = make_polygon({kSquare, {{1, 1}, {1, 4}, {4, 4}}});
  poly.loops[1][0] = 0;
  EXPECT_EQ(check_polygon_loops(poly).defect, PolygonDefect::repeated_vertex);
  // Malformed input never crashes.
  poly = make_polygon({kSquare});
  poly.loops[0][2] = 99;
  EXPECT_FALSE(check_polygon_loops(poly).ok());
  poly = make_polygon({kSquare});
  poly.points[1].x = std::nan("");
  EXPECT_FALSE(check_polygon_loops(poly).ok());
  EXPECT_EQ(check_polygon_loops(PolygonLoops{}).defect, PolygonDefect::too_few_vertices);
}

// The same containment / orientation defects on loop sets large enough for the sweep path.
TEST(PlanarPolygonValidity, LargeContainmentDefects) {
  auto circle = [](int n, double cx, double cy, double r, bool ccw) {
    std::vector<IPt> pts;
    for (int i = 0; i < n; ++i) {
      const double a = 2 * M_PI * i / n * (ccw ? 1 : -1);
      pts.push_back({std::llround(cx + r * std::cos(a)), std::llround(cy + r * std::sin(a))});
    }
    return pts;
  };
  struct Case {
    std::vector<std::vector<IPt>> loops;
    PolygonDefect expected;
  };
  const std::vector<Case> cases = {
      {{circle(60, 0, 0, 1000, true), circle(20, -300, 0, 200, false), circle(20, 300, 0, 200, false)},
       PolygonDefect::none},
      {{circle(60, 0, 0, 1000, true), circle(20, 3000, 0, 200, false)}, PolygonDefect::hole_outside},
      {{circle(60, 0, 0, 1000, true), circle(40, 0, 0, 500, false), circle(20, 0, 0, 100, false)},
       PolygonDefect::holes_nested},
      {{circle(60, 0, 0, 1000, true), circle(20, 0, 0, 100, false), circle(40, 0, 0, 500, false)},
       PolygonDefect::holes_nested},
      {{circle(60, 0, 0, 1000, true), circle(40, 0, 0, 5000, false)}, PolygonDefect::hole_outside},
      {{circle(60, 0, 0, 1000, false)}, PolygonDefect::wrong_orientation},
      {{circle(60, 0, 0, 1000, true), circle(20, 300, 0, 200, true)}, PolygonDefect::wrong_orientation},
      {{circle(60, 0, 0, 1000, true), circle(20, 900, 3, 200, false)}, PolygonDefect::loops_intersect},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const auto poly = make_polygon(cases[i].loops);
    ASSERT_EQ(brute_force(poly), cases[i].expected) << "case " << i << " (test's brute force)";
    const auto v = check_polygon_loops(poly);
    EXPECT_EQ(v.defect, cases[i].expected) << "case " << i << ": " << v.message;
  }
}

TEST(PlanarPolygonValidity, MessagesNameLoopsAndEdges) {
  const auto v = check_polygon_loops(make_polygon({{{0, 0}, {10, 0}, {0, 10}, {10, 10}}}));
  EXPECT_NE(v.message.find("loop 0"), std::string::npos) << v.message;
  EXPECT_NE(v.message.find("edge"), std::string::npos) << v.message;
}

TEST(PlanarPolygonValidity, RandomStarPolygonsAreValid) {
  std::mt19937 rng(7);
  for (int it = 0; it < 300; ++it) {
    const int n = 3 + static_cast<int>(rng() % 200);
    const int holes = static_cast<int>(rng() % 3);
    const auto poly = random_polygon(rng, holes >= 2 ? std::max(n, 12) : n, holes, 3 + static_cast<int>(rng() % 20), 1e6);
    const auto v = check_polygon_loops(poly);
    EXPECT_TRUE(v.ok()) << "iteration " << it << ": " << v.message;
  }
}

// Random perturbations (vertex moved anywhere, onto another vertex, onto an edge, loops reversed,
// indices swapped) on a coarse grid, so touching and collinear cases are frequent. Both the
// brute-force path (small m) and the sweep (large m) are compared with the test's checker.
TEST(PlanarPolygonValidity, RandomPerturbationsMatchBruteForce) {
  std::mt19937 rng(12345);
  std::map<std::string, int> seen;
  for (int it = 0; it < 6000; ++it) {
    const bool large = it % 3 == 0;
    const int n = large ? 40 + static_cast<int>(rng() % 80) : 3 + static_cast<int>(rng() % 14);
    const int holes = static_cast<int>(rng() % 3);
    const double scale = large ? 60 : 12 + static_cast<double>(rng() % 20);
    PolygonLoops poly = random_polygon(rng, n, holes, 3 + static_cast<int>(rng() % (large ? 10 : 4)), scale);
    const int moves = static_cast<int>(rng() % 3);
    for (int k = 0; k < moves; ++k) {
      const uint32_t v = static_cast<uint32_t>(rng() % poly.points.size());
      switch (rng() % 5) {
        case 0: {  // anywhere
          std::uniform_int_distribution<int> c(static_cast<int>(-scale), static_cast<int>(scale));
          poly.points[v] = {static_cast<double>(c(rng)), static_cast<double>(c(rng))};
          break;
        }
        case 1:  // onto another vertex
          poly.points[v] = poly.points[rng() % poly.points.size()];
          break;
        case 2: {  // onto an edge point (exact midpoint when representable)
          const auto& loop = poly.loops[rng() % poly.loops.size()];
          const size_t e = rng() % loop.size();
          const Vec2 a = poly.points[loop[e]], b = poly.points[loop[(e + 1) % loop.size()]];
          poly.points[v] = {std::floor((a.x + b.x) / 2), std::floor((a.y + b.y) / 2)};
          break;
        }
        case 3: {  // reverse a loop
          auto& loop = poly.loops[rng() % poly.loops.size()];
          std::reverse(loop.begin(), loop.end());
          break;
        }
        default: {  // swap two entries of a loop
          auto& loop = poly.loops[rng() % poly.loops.size()];
          std::swap(loop[rng() % loop.size()], loop[rng() % loop.size()]);
          break;
        }
      }
    }
    const PolygonDefect expected = brute_force(poly);
    const auto got = check_polygon_loops(poly);
    ++seen[std::string(large ? "large " : "small ") + name(expected)];
    ASSERT_EQ(got.defect, expected) << "iteration " << it << " (m=" << poly.points.size() << "): got "
                                    << name(got.defect) << " '" << got.message << "', expected " << name(expected);
  }
  for (const auto& [key, count] : seen) std::printf("  %-28s %d\n", key.c_str(), count);
  EXPECT_GT(seen["large self_intersection"], 0);
  EXPECT_GT(seen["large loops_intersect"], 0);
  EXPECT_GT(seen["large none"], 0);
  EXPECT_GT(seen["small none"], 0);
}

// ------------------------------------------------------------------------------ triangulation
namespace {

double angle_at(const Vec2& o, const Vec2& a, const Vec2& b) {
  return std::fabs(std::atan2((a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x),
                              (a.x - o.x) * (b.x - o.x) + (a.y - o.y) * (b.y - o.y)));
}

void check_triangulation(const PolygonLoops& poly) {
  const auto tris = triangulate_polygon(poly);
  size_t m = 0;
  int64_t area2 = 0;
  for (const auto& l : poly.loops) {
    m += l.size();
    area2 += twice_area(poly, l);
  }
  const size_t h = poly.loops.size() - 1;
  ASSERT_EQ(tris.size(), m + 2 * h - 2);
  int64_t tri_area2 = 0;
  std::map<std::pair<uint32_t, uint32_t>, std::pair<size_t, int>> directed;  // edge -> (triangle, corner)
  for (size_t t = 0; t < tris.size(); ++t) {
    const IPt a = ip(poly.points[tris[t][0]]), b = ip(poly.points[tris[t][1]]), c = ip(poly.points[tris[t][2]]);
    ASSERT_EQ(iorient(a, b, c), 1) << "triangle " << t << " not CCW";
    tri_area2 += (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    for (int k = 0; k < 3; ++k) {
      const auto key = std::make_pair(tris[t][k], tris[t][(k + 1) % 3]);
      ASSERT_EQ(directed.count(key), 0u) << "directed edge used twice";
      directed[key] = {t, (k + 2) % 3};
    }
  }
  EXPECT_EQ(tri_area2, area2);
  std::set<std::pair<uint32_t, uint32_t>> constraints;
  for (const auto& l : poly.loops)
    for (size_t i = 0; i < l.size(); ++i) {
      const auto key = std::make_pair(l[i], l[(i + 1) % l.size()]);
      EXPECT_EQ(directed.count(key), 1u) << "constraint edge " << key.first << "-" << key.second << " missing";
      constraints.insert(key);
      constraints.insert({key.second, key.first});
    }
  for (const auto& [key, tc] : directed) {
    if (constraints.count(key) || key.first > key.second) continue;
    const auto other = directed.find({key.second, key.first});
    ASSERT_NE(other, directed.end()) << "interior edge without a twin";
    const Vec2& a = poly.points[key.first];
    const Vec2& b = poly.points[key.second];
    const Vec2& c = poly.points[tris[tc.first][tc.second]];
    const Vec2& d = poly.points[tris[other->second.first][other->second.second]];
    EXPECT_LE(angle_at(c, a, b) + angle_at(d, a, b), M_PI + 1e-9) << "non-Delaunay edge";
  }
}

}  // namespace

TEST(PlanarPolygonTriangulation, HandMadeAndRandom) {
  check_triangulation(make_polygon({kSquare}));
  check_triangulation(make_polygon({{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}}));
  check_triangulation(make_polygon({kSquare, {{1, 1}, {1, 4}, {4, 4}, {4, 1}}, {{6, 6}, {6, 9}, {9, 9}, {9, 6}}}));
  // Collinear boundary vertices.
  check_triangulation(make_polygon({{{0, 0}, {1, 0}, {2, 0}, {3, 0}, {3, 3}, {0, 3}}}));
  std::mt19937 rng(99);
  for (int it = 0; it < 200; ++it) {
    const int n = 3 + static_cast<int>(rng() % (it % 10 == 0 ? 1000 : 40));
    const auto poly = random_polygon(rng, n, static_cast<int>(rng() % 4), 3 + static_cast<int>(rng() % 12), 1e6);
    if (!check_polygon_loops(poly).ok()) continue;  // rounding can rarely make holes touch
    SCOPED_TRACE("iteration " + std::to_string(it));
    check_triangulation(poly);
  }
}

TEST(PlanarPolygonTriangulation, InvalidPolygonThrows) {
  try {
    triangulate_polygon(make_polygon({{{0, 0}, {10, 0}, {0, 10}, {10, 10}}}));
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), Status::invalid_argument);
  }
  EXPECT_THROW(triangulate_polygon(PolygonLoops{}), Error);
}

// Timings (printed; loose bounds only so the sanitizer build passes too).
TEST(PlanarPolygonPerformance, SmallAndLarge) {
  std::mt19937 rng(5);
  std::vector<PolygonLoops> small;
  for (int i = 0; i < 64; ++i) small.push_back(random_polygon(rng, 8 + i % 9, 0, 3, 1e3));
  const auto large = random_polygon(rng, 1000, 0, 3, 1e6);
  const auto large_holes = random_polygon(rng, 900, 4, 25, 1e6);
  using Clock = std::chrono::steady_clock;
  auto time_it = [](int reps, auto&& fn) {
    const auto t0 = Clock::now();
    for (int r = 0; r < reps; ++r) fn(r);
    return std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / reps;
  };
  size_t sink = 0;
#ifdef NDEBUG
  const int reps = 100000;
#else
  const int reps = 4000;  // unoptimised / sanitizer builds: correctness only
#endif
  const double check_small = time_it(reps, [&](int r) { sink += check_polygon_loops(small[r % 64]).ok(); });
  const double tri_small = time_it(reps / 4, [&](int r) { sink += triangulate_polygon(small[r % 64]).size(); });
  const double check_large = time_it(reps / 500, [&](int) { sink += check_polygon_loops(large).ok(); });
  const double tri_large = time_it(reps / 1000, [&](int) { sink += triangulate_polygon(large).size(); });
  const double check_holes = time_it(reps / 500, [&](int) { sink += check_polygon_loops(large_holes).ok(); });
  std::printf("  check_polygon_loops  8-16 vertices: %.3f us/call; 1000 vertices: %.1f us; 1000 + 4 holes: %.1f us\n",
              check_small, check_large, check_holes);
  std::printf("  triangulate_polygon  8-16 vertices: %.3f us/call; 1000 vertices: %.1f us\n", tri_small, tri_large);
  EXPECT_GT(sink, 0u);
  EXPECT_LT(check_large, 50000.0);
}

namespace {
// Triangles as sets of rotation-normalised index triples (orientation kept).
std::set<std::array<uint32_t, 3>> triangle_set(const std::vector<std::array<uint32_t, 3>>& tris) {
  std::set<std::array<uint32_t, 3>> out;
  for (auto t : tris) {
    while (t[0] > t[1] || t[0] > t[2]) t = {t[1], t[2], t[0]};
    out.insert(t);
  }
  return out;
}
}  // namespace

// The fast path (ear clipping + exact Lawson flips, simple polygons up to 64 vertices) returns
// exactly CGAL's CDT triangle set: on random star polygons with double coordinates (CDT unique)
// and on integer-grid polygons full of cocircular quadruples and collinear vertices (where the
// fast path defers to CGAL).
TEST(PlanarPolygonTriangulation, FastPathMatchesCgal) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  size_t compared = 0;
  for (int iter = 0; iter < 3000; ++iter) {
    const int n = 3 + static_cast<int>(rng() % 62);
    const bool grid = iter % 3 == 2;
    PolygonLoops poly;
    std::vector<double> angles(static_cast<size_t>(n));
    for (auto& a : angles) a = unit(rng) * 2 * M_PI;
    std::sort(angles.begin(), angles.end());
    std::vector<uint32_t> loop;
    for (const double a : angles) {
      const double r = grid ? 4 + static_cast<double>(rng() % 8) : 0.2 + unit(rng);
      Vec2 p{r * std::cos(a), r * std::sin(a)};
      if (grid) p = {std::round(p.x), std::round(p.y)};
      loop.push_back(static_cast<uint32_t>(poly.points.size()));
      poly.points.push_back(p);
    }
    poly.loops.push_back(loop);
    if (!check_polygon_loops(poly).ok()) continue;
    const auto fast = triangulate_polygon(poly);
    const auto ref = detail::triangulate_polygon_cgal(poly);
    ASSERT_EQ(triangle_set(fast), triangle_set(ref)) << "iteration " << iter << ", " << n << " vertices";
    std::vector<std::array<uint32_t, 3>> again;
    triangulate_valid_polygon(poly, again);
    ASSERT_EQ(triangle_set(again), triangle_set(ref));
    ++compared;
  }
  EXPECT_GT(compared, 1500u);
}

// flip_out_edge: the two triangles on an inner edge of a convex quadrilateral become the two
// on the other diagonal; a reflex quadrilateral needs a neighbouring flip first or cannot flip;
// polygon edges stay.
TEST(PlanarPolygonTriangulation, FlipOutEdge) {
  PolygonLoops square;
  square.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  square.loops = {{0, 1, 2, 3}};
  std::vector<std::array<uint32_t, 3>> tris = {{0, 1, 2}, {0, 2, 3}};
  EXPECT_TRUE(flip_out_edge(square, tris, 0, 2));
  auto has_edge = [&](uint32_t a, uint32_t b) {
    for (const auto& t : tris)
      for (int k = 0; k < 3; ++k)
        if ((t[k] == a && t[(k + 1) % 3] == b) || (t[k] == b && t[(k + 1) % 3] == a)) return true;
    return false;
  };
  EXPECT_FALSE(has_edge(0, 2));
  EXPECT_TRUE(has_edge(1, 3));
  for (const auto& t : tris) EXPECT_GT(orient2d(square.points[t[0]], square.points[t[1]], square.points[t[2]]), 0);
  EXPECT_TRUE(flip_out_edge(square, tris, 0, 2));   // no longer an edge
  EXPECT_FALSE(flip_out_edge(square, tris, 0, 1));  // a polygon edge
  // A dart (reflex at vertex 2): the inner edge 0-2 is forced.
  PolygonLoops dart;
  dart.points = {{0, 0}, {2, -1}, {0.5, 0}, {2, 1}};
  dart.loops = {{0, 1, 2, 3}};
  std::vector<std::array<uint32_t, 3>> dart_tris = {{0, 1, 2}, {0, 2, 3}};
  EXPECT_FALSE(flip_out_edge(dart, dart_tris, 0, 2));
  EXPECT_EQ(dart_tris, (std::vector<std::array<uint32_t, 3>>{{0, 1, 2}, {0, 2, 3}}));
}

// Holes inserted after an outer loop whose edges are not Delaunay edges: inserting the outer
// loop's constraints deletes triangles of the point-only triangulation, which once left the
// point-location hint for the first hole vertex on a deleted face (a use of freed memory that
// crashed the simplifier on corpus meshes with holes). The outer loop is a comb with thin deep
// notches (each notch side crosses the Delaunay edges between the top vertices), the holes sit
// in the band below the notches, at random.
TEST(PlanarPolygonTriangulation, HolesAfterNonDelaunayOuterLoop) {
  std::mt19937 rng(18);
  size_t triangulated = 0;
  for (int iter = 0; iter < 300; ++iter) {
    const int notches = 3 + static_cast<int>(rng() % 20), holes = 1 + static_cast<int>(rng() % 8);
    const int64_t pitch = 40, width = pitch * (notches + 1), band = 100, top = band + 400;
    std::vector<IPt> outer = {{0, 0}, {width, 0}, {width, top}};
    for (int i = notches; i >= 1; --i) {  // right to left along the top: one V notch per pitch
      const int64_t x = pitch * i + static_cast<int64_t>(rng() % 9) - 4;
      outer.push_back({x + 3, top});
      outer.push_back({x, band + 1 + static_cast<int64_t>(rng() % 50)});
      outer.push_back({x - 3, top});
    }
    outer.push_back({0, top});
    // Any start vertex: the hint was the face of the outer loop's last inserted vertex.
    std::rotate(outer.begin(), outer.begin() + static_cast<std::ptrdiff_t>(rng() % outer.size()), outer.end());
    std::vector<std::vector<IPt>> loops = {outer};
    const int64_t cell = width / holes;
    for (int h = 0; h < holes; ++h) {  // clockwise triangles or quads in the band
      const int64_t x0 = cell * h + 2 + static_cast<int64_t>(rng() % 5), x1 = x0 + cell / 2 + 1;
      const int64_t y0 = 10 + static_cast<int64_t>(rng() % 20), y1 = band - 10 - static_cast<int64_t>(rng() % 20);
      if (rng() % 2)
        loops.push_back({{x0, y0}, {(x0 + x1) / 2, y1}, {x1, y0 + static_cast<int64_t>(rng() % 7)}});
      else
        loops.push_back({{x0, y0}, {x0, y1}, {x1, y1}, {x1, y0}});
    }
    const PolygonLoops poly = make_polygon(loops);
    ASSERT_EQ(brute_force(poly), PolygonDefect::none) << "iteration " << iter;
    SCOPED_TRACE("iteration " + std::to_string(iter));
    check_triangulation(poly);
    ++triangulated;
  }
  EXPECT_EQ(triangulated, 300u);
}

// The classes of input that violate the CDT's preconditions (CGAL's constrained triangulation
// without constraint intersections): two loop vertices on the same point, a vertex on another
// loop's edge (loops that touch, typically nearly collinear edges after projection), a hole
// sharing a piece of the outer loop's edge. Each is reported by the exact check, and both
// triangulate_polygon and the CGAL reference refuse it with Error(invalid_argument) instead of
// reaching CGAL with it.
TEST(PlanarPolygonTriangulation, PreconditionViolationsAreRefused) {
  struct Case {
    const char* what;
    std::vector<std::vector<IPt>> loops;
    PolygonDefect defect;
  };
  const std::vector<Case> cases = {
      {"hole vertex on an outer vertex", {kSquare, {{0, 0}, {2, 5}, {5, 2}}}, PolygonDefect::repeated_vertex},
      {"two outer vertices on one point", {{{0, 0}, {10, 0}, {5, 5}, {10, 10}, {5, 5}, {0, 10}}},
       PolygonDefect::repeated_vertex},
      {"hole vertex on an outer edge", {kSquare, {{5, 0}, {3, 4}, {7, 4}}}, PolygonDefect::loops_intersect},
      {"hole sharing part of an outer edge", {kSquare, {{2, 0}, {2, 3}, {6, 3}, {6, 0}}},
       PolygonDefect::loops_intersect},
      {"vertex on a non-adjacent edge (collinear touch)", {{{0, 0}, {10, 0}, {10, 10}, {5, 0}, {0, 10}}},
       PolygonDefect::self_intersection},
      {"hole vertex on a long, nearly horizontal outer edge",
       {{{0, 0}, {3000000, 3}, {3000000, 10}, {0, 10}}, {{1000000, 1}, {999999, 2}, {1000001, 2}}},
       PolygonDefect::loops_intersect},
      {"two holes touching", {kSquare, {{1, 1}, {1, 4}, {4, 1}}, {{4, 1}, {4, 4}, {7, 4}}},
       PolygonDefect::repeated_vertex},
  };
  for (const Case& c : cases) {
    const PolygonLoops poly = make_polygon(c.loops);
    EXPECT_EQ(brute_force(poly), c.defect) << c.what;
    EXPECT_EQ(check_polygon_loops(poly).defect, c.defect) << c.what << ": " << check_polygon_loops(poly).message;
    for (int path = 0; path < 2; ++path) {
      try {
        if (path == 0)
          triangulate_polygon(poly);
        else
          detail::triangulate_polygon_cgal(poly);
        ADD_FAILURE() << c.what << ": no exception";
      } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::invalid_argument) << c.what;
      }
    }
  }
  // Coincident projected points from distinct 3D points: a vertical wall seen from above.
  const PlaneFrame frame = PlaneFrame::from_normal(Vec3{0, 0, 0}, Vec3{0, 0, 1});
  PolygonLoops wall;
  for (const Vec3& p : {Vec3{0, 0, 0}, Vec3{4, 0, 0}, Vec3{4, 0, 1}, Vec3{4, 4, 1}, Vec3{0, 4, 1}})
    wall.points.push_back(frame.project(p));
  wall.loops = {{0, 1, 2, 3, 4}};
  EXPECT_EQ(check_polygon_loops(wall).defect, PolygonDefect::repeated_vertex) << check_polygon_loops(wall).message;
  EXPECT_THROW(triangulate_polygon(wall), Error);
}
