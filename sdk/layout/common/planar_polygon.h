// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Planar polygons with holes (thesis §3.3.1): a face of the simplified mesh projected into its
// proxy plane. Exact-predicate validity test (§3.3, the injectivity criterion) and constrained
// Delaunay triangulation without Steiner points. Implemented with CGAL (Epick: exact
// predicates, inexact constructions) in ONE translation unit (planar_polygon_cgal.cpp).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/vec2.h"
#include "core/vec3.h"

CAGEKIT_NAMESPACE_BEGIN

// An orthonormal frame (origin + axes u, v with u x v = normal) of a proxy plane.
struct PlaneFrame {
  Vec3 origin, u, v, normal;
  static PlaneFrame from_normal(const Vec3& origin, const Vec3& unit_normal);
  Vec2 project(const Vec3& p) const { return {dot(p - origin, u), dot(p - origin, v)}; }
};

// loops[0] is the outer loop, the others are holes. Each loop lists indices into `points`;
// consecutive entries (cyclically) are the loop's edges.
struct PolygonLoops {
  std::vector<Vec2> points;
  std::vector<std::vector<uint32_t>> loops;
};

enum class PolygonDefect : int {
  none = 0,
  too_few_vertices,      // a loop with fewer than 3 vertices
  repeated_vertex,       // the same point index (or identical coordinates) twice in the loop set
  self_intersection,     // a loop is not a simple polygon
  loops_intersect,       // two loops touch or cross
  hole_outside,          // a hole is not inside the outer loop
  holes_nested,          // a hole lies inside another hole
  wrong_orientation,     // outer loop not counter-clockwise or a hole not clockwise (fold-over guard)
};

struct PolygonValidity {
  PolygonDefect defect = PolygonDefect::none;
  std::string message;  // which loop(s)/edges, for diagnostics and tests
  bool ok() const { return defect == PolygonDefect::none; }
};

// The injectivity criterion (a)-(d) plus the orientation guard, with exact predicates.
// O(m log m) in the total number of loop vertices m (brute-force exact pair tests below ~40
// vertices, where they are faster and allocation-free; a Shamos-Hoey sweep above).
// Malformed input (empty loop set, point index out of range, non-finite coordinate) is
// reported as too_few_vertices (no outer loop) or self_intersection (the loop is no polygon).
// Defects are reported in this order: too_few_vertices, repeated_vertex, self_intersection /
// loops_intersect, hole_outside, holes_nested, wrong_orientation.
PolygonValidity check_polygon_loops(const PolygonLoops& polygon);

// Exact orientation predicate (CGAL Epick, filtered): +1 if a, b, c turn counter-clockwise,
// -1 if clockwise, 0 if collinear. Coordinates must be finite.
int orient2d(const Vec2& a, const Vec2& b, const Vec2& c);

// Constrained Delaunay triangulation of a valid polygon with holes, no Steiner points: the
// triangles cover exactly the polygon's interior, each counter-clockwise, as index triples into
// polygon.points. Throws Error(invalid_argument) if the polygon is not valid.
std::vector<std::array<uint32_t, 3>> triangulate_polygon(const PolygonLoops& polygon);

// As triangulate_polygon, for a polygon already known to be valid (check_polygon_loops ok):
// skips the validity check and reuses `triangles`' storage. Simple polygons of up to 64
// vertices take a fast path (ear clipping + exact Lawson flips, falling back to CGAL when four
// vertices are cocircular), so the result is always the same triangle set as CGAL's CDT.
void triangulate_valid_polygon(const PolygonLoops& polygon, std::vector<std::array<uint32_t, 3>>& triangles);

// Removes the edge (a, b) (polygon point indices) from a triangulation of a polygon by flipping
// it: the two triangles on it, (a, b, c) and (b, a, d), become (a, d, c) and (d, b, c) when they
// form a strictly convex quadrilateral (exact orient2d); when they do not, one of the four edges
// around them is flipped first if that makes the flip possible. Used to keep one face's diagonal
// off a vertex pair that another face already joins. Returns true when (a, b) is no longer an
// edge of the triangulation (flipped, or never an interior edge), false when it stays (no such
// flips, or a polygon edge). The result is a triangulation without Steiner points, no longer
// Delaunay.
bool flip_out_edge(const PolygonLoops& polygon, std::vector<std::array<uint32_t, 3>>& triangles, uint32_t a,
                   uint32_t b);

namespace detail {
// The CGAL constrained Delaunay triangulation behind triangulate_polygon (reference for tests).
std::vector<std::array<uint32_t, 3>> triangulate_polygon_cgal(const PolygonLoops& polygon);
}  // namespace detail

CAGEKIT_NAMESPACE_END
