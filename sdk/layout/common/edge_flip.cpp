// SPDX-License-Identifier: GPL-3.0-or-later
// flip_out_edge (planar_polygon.h): one exact Lawson-style flip that removes a chosen edge from a
// triangulation without Steiner points.
#include <algorithm>

#include "layout/common/planar_polygon.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

// Flips the interior edge (a, b) when its quadrilateral is strictly convex; true when flipped.
bool flip_once(const PolygonLoops& polygon, std::vector<std::array<uint32_t, 3>>& triangles, uint32_t a, uint32_t b,
               int* present) {
  // The triangles with the directed edge a->b and b->a, and their third vertices.
  int t1 = -1, t2 = -1;
  uint32_t c = 0, d = 0;
  for (size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t x = triangles[t][k], y = triangles[t][(k + 1) % 3], z = triangles[t][(k + 2) % 3];
      if (x == a && y == b) t1 = int(t), c = z;
      if (x == b && y == a) t2 = int(t), d = z;
    }
  *present = t1 < 0 && t2 < 0 ? 0 : (t1 < 0 || t2 < 0 ? 1 : 2);  // 1: a polygon edge
  if (*present != 2) return false;
  const auto& P = polygon.points;
  if (std::max({a, b, c, d}) >= P.size()) return false;
  // (a, d, c) and (d, b, c) must both be strictly counter-clockwise.
  if (orient2d(P[a], P[d], P[c]) <= 0 || orient2d(P[d], P[b], P[c]) <= 0) return false;
  triangles[size_t(t1)] = {a, d, c};
  triangles[size_t(t2)] = {d, b, c};
  return true;
}

// The third vertices of the triangles on (a, b) (kNone when absent).
void opposite_vertices(const std::vector<std::array<uint32_t, 3>>& triangles, uint32_t a, uint32_t b, uint32_t* c,
                       uint32_t* d) {
  *c = *d = 0xffffffffu;
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) {
      if (t[k] == a && t[(k + 1) % 3] == b) *c = t[(k + 2) % 3];
      if (t[k] == b && t[(k + 1) % 3] == a) *d = t[(k + 2) % 3];
    }
}

}  // namespace

bool flip_out_edge(const PolygonLoops& polygon, std::vector<std::array<uint32_t, 3>>& triangles, uint32_t a,
                   uint32_t b) {
  int present = 0;
  if (flip_once(polygon, triangles, a, b, &present)) return true;
  if (present == 0) return true;   // not an edge
  if (present == 1) return false;  // a polygon edge: stays
  // Not convex: flip one of the four surrounding edges first (which changes the quadrilateral on
  // (a, b)), then try again; undone when that does not help.
  uint32_t c, d;
  opposite_vertices(triangles, a, b, &c, &d);
  const std::pair<uint32_t, uint32_t> around[4] = {{b, c}, {c, a}, {a, d}, {d, b}};
  for (const auto& [x, y] : around) {
    auto trial = triangles;
    int p = 0;
    if (!flip_once(polygon, trial, x, y, &p)) continue;
    if (flip_once(polygon, trial, a, b, &p)) {
      triangles = std::move(trial);
      return true;
    }
  }
  return false;
}

CAGEKIT_NAMESPACE_END
