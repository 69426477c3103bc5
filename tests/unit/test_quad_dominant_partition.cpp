// SPDX-License-Identifier: GPL-3.0-or-later
// Quad-dominant partitioning (thesis §3.9, acceptance item 20): cells convex with valence 3-5,
// only CDT diagonals, tiling the polygon, and score equal to the exhaustive optimum (all subsets
// of CDT diagonals, enumerated here with exact integer arithmetic).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>
#include <random>
#include <set>

#include "core/status.h"
#include "layout/common/quad_dominant_partition.h"

using namespace cagekit;

namespace {

using IPt = std::array<int64_t, 2>;
using Tris = std::vector<std::array<uint32_t, 3>>;

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

IPt ip(const Vec2& v) { return {static_cast<int64_t>(v.x), static_cast<int64_t>(v.y)}; }
int iorient(IPt a, IPt b, IPt c) {
  const int64_t d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  return (d > 0) - (d < 0);
}
int64_t twice_area(const PolygonLoops& poly, const std::vector<uint32_t>& loop) {
  int64_t s = 0;
  for (size_t i = 0; i < loop.size(); ++i) {
    const IPt a = ip(poly.points[loop[i]]), b = ip(poly.points[loop[(i + 1) % loop.size()]]);
    s += a[0] * b[1] - a[1] * b[0];
  }
  return s;
}
int omega(int n) { return n == 4 ? 0 : n == 5 ? 1 : 2; }

// Score of a cell polygon under the documented rule, or -1 if it is not convex.
int cell_score(const PolygonLoops& poly, const std::vector<uint32_t>& cell) {
  const size_t n = cell.size();
  int effective = 0;
  for (size_t i = 0; i < n; ++i) {
    const int o = iorient(ip(poly.points[cell[(i + n - 1) % n]]), ip(poly.points[cell[i]]),
                          ip(poly.points[cell[(i + 1) % n]]));
    if (o < 0) return -1;
    effective += o > 0;
  }
  if (effective < 3 || n < 3 || n > 5) return -1;
  return std::max(omega(static_cast<int>(n)), omega(effective));
}

// Exhaustive optimum over all subsets of the triangulation's interior diagonals.
int brute_force_optimum(const PolygonLoops& poly, const Tris& tris) {
  std::map<std::pair<uint32_t, uint32_t>, std::vector<int>> edge_tris;
  for (int t = 0; t < static_cast<int>(tris.size()); ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = tris[t][k], b = tris[t][(k + 1) % 3];
      edge_tris[{std::min(a, b), std::max(a, b)}].push_back(t);
    }
  std::vector<std::pair<int, int>> diagonals;
  for (const auto& [e, ts] : edge_tris)
    if (ts.size() == 2) diagonals.push_back({ts[0], ts[1]});
  const int T = static_cast<int>(tris.size()), D = static_cast<int>(diagonals.size());
  EXPECT_LE(D, 24) << "brute force too large";
  int best = -1;
  std::vector<int> uf(T), size(T);
  std::vector<std::vector<int>> members(T);
  for (uint64_t mask = 0; mask < (uint64_t{1} << D); ++mask) {
    std::iota(uf.begin(), uf.end(), 0);
    std::fill(size.begin(), size.end(), 1);
    auto find = [&](int x) {
      while (uf[x] != x) x = uf[x];
      return x;
    };
    bool ok = true;
    for (int d = 0; d < D && ok; ++d)
      if (mask >> d & 1) {
        const int a = find(diagonals[d].first), b = find(diagonals[d].second);
        if (a == b) continue;
        uf[a] = b;
        size[b] += size[a];
        if (size[b] > 3) ok = false;
      }
    if (!ok) continue;
    for (auto& m : members) m.clear();
    for (int t = 0; t < T; ++t) members[find(t)].push_back(t);
    int total = 0;
    for (int r = 0; r < T && ok; ++r) {
      if (members[r].empty()) continue;
      // Boundary cycle of the component.
      std::map<uint32_t, uint32_t> next;
      std::set<std::pair<uint32_t, uint32_t>> directed;
      for (int t : members[r])
        for (int k = 0; k < 3; ++k) directed.insert({tris[t][k], tris[t][(k + 1) % 3]});
      for (const auto& [a, b] : directed)
        if (!directed.count({b, a})) {
          if (next.count(a)) ok = false;
          next[a] = b;
        }
      if (!ok || next.size() != members[r].size() + 2) {
        ok = false;
        break;
      }
      std::vector<uint32_t> cell;
      uint32_t cur = next.begin()->first;
      for (size_t i = 0; i < next.size(); ++i) {
        cell.push_back(cur);
        cur = next[cur];
      }
      if (cur != cell[0]) {
        ok = false;
        break;
      }
      const int s = cell_score(poly, cell);
      if (s < 0) ok = false;
      total += s;
    }
    if (ok && (best < 0 || total < best)) best = total;
  }
  return best;
}

// Checks that the partition is a valid tiling by convex CDT cells and that its score is right.
void check_partition(const PolygonLoops& poly, const Tris& tris, const QuadDominantPartition& part) {
  std::set<std::pair<uint32_t, uint32_t>> tri_edges;
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) tri_edges.insert({t[k], t[(k + 1) % 3]});
  std::set<std::pair<uint32_t, uint32_t>> boundary;
  int64_t area = 0;
  for (const auto& l : poly.loops) {
    area += twice_area(poly, l);
    for (size_t i = 0; i < l.size(); ++i) boundary.insert({l[i], l[(i + 1) % l.size()]});
  }
  int64_t cell_area = 0;
  int score = 0;
  std::set<std::pair<uint32_t, uint32_t>> cell_edges;
  for (size_t c = 0; c < part.cells.size(); ++c) {
    const auto& cell = part.cells[c];
    ASSERT_GE(cell.size(), 3u);
    ASSERT_LE(cell.size(), 5u);
    for (uint32_t v : cell) ASSERT_LT(v, poly.points.size());
    const int s = cell_score(poly, cell);
    ASSERT_GE(s, 0) << "cell " << c << " not convex";
    score += s;
    cell_area += twice_area(poly, cell);
    for (size_t i = 0; i < cell.size(); ++i) {
      const auto e = std::make_pair(cell[i], cell[(i + 1) % cell.size()]);
      ASSERT_TRUE(tri_edges.count(e)) << "cell edge is not a CDT edge";
      ASSERT_TRUE(cell_edges.insert(e).second) << "directed cell edge used twice";
    }
  }
  for (const auto& e : cell_edges)
    if (!boundary.count(e)) {
      ASSERT_TRUE(cell_edges.count({e.second, e.first})) << "dangling cell edge";
    }
  for (const auto& e : boundary) ASSERT_TRUE(cell_edges.count(e)) << "boundary edge not covered";
  EXPECT_EQ(cell_area, area);
  EXPECT_EQ(score, part.score);
}

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

PolygonLoops random_polygon(std::mt19937& rng, int n_outer, int holes, int n_hole, double scale, double r0 = 0.4) {
  std::vector<std::vector<IPt>> loops;
  loops.push_back(star(rng, n_outer, 0, 0, r0 * scale, scale, true));
  for (int h = 0; h < holes; ++h) {
    const double a = 2 * M_PI * h / std::max(holes, 1);
    const double off = holes > 1 ? 0.3 * scale : 0.0;
    loops.push_back(star(rng, n_hole, off * std::cos(a), off * std::sin(a), 0.05 * scale, 0.12 * scale, false));
  }
  return make_polygon(loops);
}

void compare_with_brute_force(const PolygonLoops& poly, const char* what) {
  const Tris tris = triangulate_polygon(poly);
  const auto part = partition_quad_dominant(poly, tris);
  check_partition(poly, tris, part);
  EXPECT_TRUE(part.optimal) << what;
  EXPECT_EQ(part.score, brute_force_optimum(poly, tris)) << what;
}

}  // namespace

TEST(QuadDominantPartition, LShapeIsTwoQuads) {
  const auto poly = make_polygon({{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}});
  const Tris tris = triangulate_polygon(poly);
  const auto part = partition_quad_dominant(poly, tris);
  check_partition(poly, tris, part);
  EXPECT_EQ(part.score, 0);
  EXPECT_EQ(part.cells.size(), 2u);
  EXPECT_TRUE(part.optimal);
}

TEST(QuadDominantPartition, HexagonAndSquare) {
  // Convex hexagon: its 4 CDT triangles; the optimum depends on which diagonals the CDT has.
  const auto hex = make_polygon({{{2, 0}, {1, 2}, {-1, 2}, {-2, 0}, {-1, -2}, {1, -2}}});
  const Tris tris = triangulate_polygon(hex);
  const auto part = partition_quad_dominant(hex, tris);
  check_partition(hex, tris, part);
  const int best = brute_force_optimum(hex, tris);
  EXPECT_EQ(part.score, best);
  std::printf("  hexagon: %zu cells, score %d (brute force %d)\n", part.cells.size(), part.score, best);
  EXPECT_LE(part.score, 1);  // at worst a quad + ... : a pentagon + triangle is 3, quad+quad 0
  const auto square = make_polygon({{{0, 0}, {1, 0}, {1, 1}, {0, 1}}});
  const auto sq = partition_quad_dominant(square, triangulate_polygon(square));
  EXPECT_EQ(sq.score, 0);
  ASSERT_EQ(sq.cells.size(), 1u);
  EXPECT_EQ(sq.cells[0].size(), 4u);
  const auto tri = make_polygon({{{0, 0}, {1, 0}, {0, 1}}});
  EXPECT_EQ(partition_quad_dominant(tri, triangulate_polygon(tri)).score, 2);
}

TEST(QuadDominantPartition, CollinearCornerIsNotRewarded) {
  // A triangle with an extra vertex on one side: the only cell is a "quad" with a straight
  // corner, scored as a triangle.
  const auto poly = make_polygon({{{0, 0}, {1, 0}, {2, 0}, {0, 2}}});
  const Tris tris = triangulate_polygon(poly);
  const auto part = partition_quad_dominant(poly, tris);
  check_partition(poly, tris, part);
  EXPECT_EQ(part.score, brute_force_optimum(poly, tris));
}

TEST(QuadDominantPartition, RandomSimpleMatchesBruteForce) {
  std::mt19937 rng(2024);
  int done = 0;
  for (int it = 0; it < 400; ++it) {
    const int n = 4 + static_cast<int>(rng() % 9);  // 4..12
    const auto poly = random_polygon(rng, n, 0, 3, it % 2 ? 8.0 : 1000.0);
    if (!check_polygon_loops(poly).ok()) continue;
    SCOPED_TRACE("iteration " + std::to_string(it));
    compare_with_brute_force(poly, "simple");
    ++done;
  }
  EXPECT_GT(done, 200);
}

TEST(QuadDominantPartition, RandomWithHoleMatchesBruteForce) {
  std::mt19937 rng(77);
  int done = 0;
  for (int it = 0; it < 200; ++it) {
    const int n = 6 + static_cast<int>(rng() % 4);  // outer 6..9 + hole 3..4: <= 13 vertices
    const auto poly = random_polygon(rng, n, 1, 3 + static_cast<int>(rng() % 2), it % 2 ? 30.0 : 1000.0, 0.6);
    if (!check_polygon_loops(poly).ok()) continue;
    SCOPED_TRACE("iteration " + std::to_string(it));
    compare_with_brute_force(poly, "one hole");
    ++done;
  }
  EXPECT_GT(done, 100);
}

TEST(QuadDominantPartition, TwentyVerticesMatchBruteForce) {
  std::mt19937 rng(31337);
  int done = 0;
  for (int it = 0; it < 12 && done < 6; ++it) {
    PolygonLoops poly;
    if (it % 3 == 0)
      poly = random_polygon(rng, 20, 0, 3, 1000.0);
    else if (it % 3 == 1)
      poly = random_polygon(rng, 17, 1, 3, 1000.0, 0.6);
    else
      poly = random_polygon(rng, 10, 2, 3, 1000.0, 0.7);  // 16 vertices, 2 holes
    if (!check_polygon_loops(poly).ok()) continue;
    SCOPED_TRACE("iteration " + std::to_string(it));
    compare_with_brute_force(poly, "<= 20 vertices");
    ++done;
  }
  EXPECT_GE(done, 3);
}

TEST(QuadDominantPartition, LargeFacesAreFast) {
  std::mt19937 rng(8);
  using Clock = std::chrono::steady_clock;
  for (int holes : {0, 3, 12}) {
    auto poly = random_polygon(rng, 300, holes == 12 ? 0 : holes, 6, 1e6, 0.8);
    if (holes == 12) {  // a 4 x 3 grid of holes
      std::vector<std::vector<IPt>> loops;
      for (const auto& l : poly.loops) {
        loops.emplace_back();
        for (uint32_t v : l) loops.back().push_back(ip(poly.points[v]));
      }
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 3; ++j)
          loops.push_back(star(rng, 6, (-0.45 + 0.3 * i) * 1e6, (-0.3 + 0.3 * j) * 1e6, 0.05e6, 0.12e6, false));
      poly = make_polygon(loops);
    }
    ASSERT_TRUE(check_polygon_loops(poly).ok());
    const Tris tris = triangulate_polygon(poly);
    const auto t0 = Clock::now();
    const int reps = 20;
    QuadDominantPartition part;
    for (int r = 0; r < reps; ++r) part = partition_quad_dominant(poly, tris);
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count() / reps;
    check_partition(poly, tris, part);
    std::printf("  %zu vertices, %d holes: %.3f ms, score %d, %zu cells, optimal %d\n", poly.points.size(), holes,
                ms, part.score, part.cells.size(), part.optimal ? 1 : 0);
    if (holes == 0) {
      EXPECT_TRUE(part.optimal);  // the tree DP is exact at any size
    }
    EXPECT_LT(ms, 200.0);
  }
  // Small faces: the simplifier's hot path.
  std::vector<PolygonLoops> small;
  std::vector<Tris> small_tris;
  while (small.size() < 64) {
    auto poly = random_polygon(rng, 8 + static_cast<int>(small.size() % 9), 0, 3, 1000.0);
    if (!check_polygon_loops(poly).ok()) continue;
    small_tris.push_back(triangulate_polygon(poly));
    small.push_back(std::move(poly));
  }
#ifdef NDEBUG
  const int reps = 50000;
#else
  const int reps = 2000;  // unoptimised / sanitizer builds: correctness only
#endif
  size_t sink = 0;
  const auto t0 = Clock::now();
  for (int r = 0; r < reps; ++r) sink += partition_quad_dominant(small[r % 64], small_tris[r % 64]).cells.size();
  const double us = std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / reps;
  std::printf("  8-16 vertices: %.2f us per partition\n", us);
  EXPECT_GT(sink, 0u);
}

TEST(QuadDominantPartition, FixedDiagonalsAboveTheLimitStayValid) {
  std::mt19937 rng(4);
  const auto poly = random_polygon(rng, 40, 6, 4, 1e6, 0.8);
  ASSERT_TRUE(check_polygon_loops(poly).ok());
  const Tris tris = triangulate_polygon(poly);
  PartitionOptions opt;
  opt.exact_vertex_limit = 4;
  const auto exact = partition_quad_dominant(poly, tris);
  const auto part = partition_quad_dominant(poly, tris, opt);
  check_partition(poly, tris, part);
  check_partition(poly, tris, exact);
  EXPECT_GE(part.score, exact.score);
}

TEST(QuadDominantPartition, BadInputThrows) {
  const auto poly = make_polygon({{{0, 0}, {1, 0}, {1, 1}, {0, 1}}});
  auto expect_invalid = [&](const Tris& tris) {
    try {
      partition_quad_dominant(poly, tris);
      ADD_FAILURE() << "no exception";
    } catch (const Error& e) {
      EXPECT_EQ(e.status(), Status::invalid_argument);
    }
  };
  expect_invalid({{0, 1, 7}});                  // index out of range
  expect_invalid({{0, 2, 1}});                  // clockwise
  expect_invalid({{0, 1, 2}, {0, 1, 2}});       // duplicate triangle
  expect_invalid({{0, 1, 2}, {0, 1, 3}});       // overlapping
  EXPECT_EQ(partition_quad_dominant(poly, {}).cells.size(), 0u);
}
