// SPDX-License-Identifier: GPL-3.0-or-later
// The corpus harness's crease figures (crease_metrics.h, issue 20) on meshes whose answer is known:
// a unit cube scan has exactly its 12 edges sharp (not the flat diagonals), also as a triangle soup
// and with shuffled orientations; creases on every cube edge give precision and recall 100 %;
// half the edges give recall 50 %; creases farther than the tolerance do not count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "crease_metrics.h"

namespace {

using cagekit_corpus::Segment;
using cagekit_corpus::Vec3;

struct Mesh {
  std::vector<double> xyz;
  std::vector<uint32_t> sizes, indices;
};

const double kCorners[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
// Outward-oriented triangles (the check_harness_rules.sh cube).
const uint32_t kTriangles[12][3] = {{0, 2, 1}, {0, 3, 2}, {0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5},
                                    {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}, {4, 5, 6}, {4, 6, 7}};
const uint32_t kEdges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

Mesh cube(bool soup, bool shuffle_orientation) {
  Mesh m;
  if (!soup)
    for (const auto& c : kCorners) m.xyz.insert(m.xyz.end(), c, c + 3);
  for (int t = 0; t < 12; ++t) {
    uint32_t f[3] = {kTriangles[t][0], kTriangles[t][1], kTriangles[t][2]};
    if (shuffle_orientation && t % 3 == 0) std::swap(f[1], f[2]);
    m.sizes.push_back(3);
    for (const uint32_t v : f) {
      if (soup) {  // every triangle its own corners, as in STL
        m.indices.push_back(uint32_t(m.xyz.size() / 3));
        m.xyz.insert(m.xyz.end(), kCorners[v], kCorners[v] + 3);
      } else {
        m.indices.push_back(v);
      }
    }
  }
  return m;
}

std::vector<Segment> cube_edges(int count, Vec3 offset = {0, 0, 0}) {
  std::vector<Segment> out;
  for (int e = 0; e < count; ++e) {
    Segment s;
    for (int k = 0; k < 3; ++k) {
      s.a[k] = kCorners[kEdges[e][0]][k] + offset[k];
      s.b[k] = kCorners[kEdges[e][1]][k] + offset[k];
    }
    out.push_back(s);
  }
  return out;
}

double total_length(const std::vector<Segment>& segments) {
  double sum = 0.0;
  for (const Segment& s : segments) sum += cagekit_corpus::length(cagekit_corpus::sub(s.b, s.a));
  return sum;
}

const double kTau = 0.01 * std::sqrt(3.0);  // 1 % of the unit cube's diagonal

TEST(CreaseMetrics, CubeHasTwelveSharpEdges) {
  for (const bool soup : {false, true})
    for (const bool shuffled : {false, true}) {
      const Mesh m = cube(soup, shuffled);
      const std::vector<Segment> sharp = cagekit_corpus::sharp_input_edges(m.xyz, m.sizes, m.indices, 40.0);
      EXPECT_EQ(sharp.size(), 12u) << "soup " << soup << " shuffled " << shuffled;
      EXPECT_NEAR(total_length(sharp), 12.0, 1e-12);
    }
}

TEST(CreaseMetrics, QuadCubeAndThreshold) {
  // The cube as six quads: 12 edges bending 90 degrees; none above a 95-degree threshold.
  Mesh m;
  for (const auto& c : kCorners) m.xyz.insert(m.xyz.end(), c, c + 3);
  const uint32_t quads[6][4] = {{0, 3, 2, 1}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}, {4, 5, 6, 7}};
  for (const auto& q : quads) {
    m.sizes.push_back(4);
    m.indices.insert(m.indices.end(), q, q + 4);
  }
  EXPECT_EQ(cagekit_corpus::sharp_input_edges(m.xyz, m.sizes, m.indices, 40.0).size(), 12u);
  EXPECT_EQ(cagekit_corpus::sharp_input_edges(m.xyz, m.sizes, m.indices, 95.0).size(), 0u);
}

TEST(CreaseMetrics, OpenSurfaceHasNoSharpBoundary) {
  // One folded pair of triangles: the fold (45 degrees) is sharp, the boundary edges are not.
  const std::vector<double> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -1, 1};
  const std::vector<uint32_t> sizes = {3, 3};
  const std::vector<uint32_t> fold = {0, 1, 2, 4, 3, 5};  // share the edge 0-1; 3 and 4 duplicate 0 and 1
  EXPECT_EQ(cagekit_corpus::sharp_input_edges(xyz, sizes, fold, 40.0).size(), 1u);
  EXPECT_EQ(cagekit_corpus::sharp_input_edges(xyz, sizes, fold, 50.0).size(), 0u);
}

TEST(CreaseMetrics, EveryCubeEdgeACrease) {
  const Mesh m = cube(false, false);
  const std::vector<Segment> sharp = cagekit_corpus::sharp_input_edges(m.xyz, m.sizes, m.indices, 40.0);
  const cagekit_corpus::CreaseMatch r = cagekit_corpus::match_creases(cube_edges(12), sharp, kTau);
  EXPECT_NEAR(r.creases.total, 12.0, 1e-12);
  EXPECT_NEAR(r.creases.matched, 12.0, 1e-12);  // precision 100 %
  EXPECT_NEAR(r.sharp.total, 12.0, 1e-12);
  EXPECT_NEAR(r.sharp.matched, 12.0, 1e-12);  // recall 100 %
}

TEST(CreaseMetrics, HalfTheEdgesAndAFlatCrease) {
  const Mesh m = cube(true, false);
  const std::vector<Segment> sharp = cagekit_corpus::sharp_input_edges(m.xyz, m.sizes, m.indices, 40.0);
  // Six of the twelve edges (0-1, 1-2, 2-3, 3-0, 4-5, 5-6: the bottom loop and two top edges).
  // Their ends touch other edges, but only within tau of a corner: recall 50 % up to that.
  std::vector<Segment> creases = cube_edges(6);
  cagekit_corpus::CreaseMatch r = cagekit_corpus::match_creases(creases, sharp, kTau);
  EXPECT_DOUBLE_EQ(r.creases.matched / r.creases.total, 1.0);
  EXPECT_NEAR(r.sharp.matched / r.sharp.total, 0.5, 2 * kTau * 8 / 12.0);
  // Plus a crease across the middle of the bottom face (a flat diagonal, length sqrt 2): not
  // within tau of a sharp edge except near its ends.
  creases.push_back({{0.0, 0.0, 0.0}, {1.0, 1.0, 0.0}});
  r = cagekit_corpus::match_creases(creases, sharp, kTau);
  const double precision = r.creases.matched / r.creases.total;
  EXPECT_NEAR(precision, 6.0 / (6.0 + std::sqrt(2.0)), 4 * kTau / (6.0 + std::sqrt(2.0)));
}

TEST(CreaseMetrics, ToleranceIsRespected) {
  const Mesh m = cube(false, false);
  const std::vector<Segment> sharp = cagekit_corpus::sharp_input_edges(m.xyz, m.sizes, m.indices, 40.0);
  // Creases moved off the cube: by 0.9 tau everything matches, by 1.5 tau (perpendicular to
  // the edge 0-1) nothing of it does.
  const double d = kTau / std::sqrt(3.0);
  cagekit_corpus::CreaseMatch r =
      cagekit_corpus::match_creases(cube_edges(12, {0.9 * d, 0.9 * d, 0.9 * d}), sharp, kTau);
  EXPECT_NEAR(r.creases.matched, 12.0, 1e-9);
  EXPECT_NEAR(r.sharp.matched, 12.0, 1e-9);
  const std::vector<Segment> far = {{{0.0, -1.5 * kTau, 0.0}, {1.0, -1.5 * kTau, 0.0}}};
  r = cagekit_corpus::match_creases(far, sharp, kTau);
  EXPECT_EQ(r.creases.matched, 0.0);
  EXPECT_EQ(r.sharp.matched, 0.0);
}

TEST(CreaseMetrics, UndefinedWithoutSegments) {
  const Mesh m = cube(false, false);
  const std::vector<Segment> sharp = cagekit_corpus::sharp_input_edges(m.xyz, m.sizes, m.indices, 40.0);
  const cagekit_corpus::CreaseMatch r = cagekit_corpus::match_creases({}, sharp, kTau);
  EXPECT_EQ(r.creases.total, 0.0);  // no creases: precision undefined
  EXPECT_EQ(r.sharp.matched, 0.0);  // recall 0
  EXPECT_NEAR(r.sharp.total, 12.0, 1e-12);
}

}  // namespace
