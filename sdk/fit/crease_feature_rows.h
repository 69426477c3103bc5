// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Crease-feature rows (not in the thesis): least-squares rows that hold the limit surface's
// crease curves on the scan's sharp feature lines during the fit.
//
// Why: the fit's rows (7.3) pull the surface towards the scan, not the crease curves towards the
// scan's sharp edges. A coarse cage's crease curves (B-splines of its crease polygons) cut the
// polygons' corners, and where a part has small steps (a flange's ledges, a chamfer) the fit
// leaves them beside the edges, or slides them there, at almost no cost in distance: on
// turbine.off at 240 faces, 54 % of the unfitted limit's crease length lies within 1 % of the
// diagonal of a sharp edge, 57-64 % after the fit (tests/bench/RESULTS.md). With these rows every step
// also pulls the points of the limit's crease curves (the piecewise-linear limit mesh's grid
// points on ptex sides along infinitely sharp, two-face cage edges) that lie within `reach` of a
// feature line towards their closest point on it.
//
// Thread-safety: const after construction.
#include <cstdint>
#include <vector>

#include "core/cage.h"
#include "core/polygon_mesh.h"
#include "core/vec3.h"
#include "fit/piecewise_linear_limit_mesh.h"
#include "fit/ptex_adjacency.h"
#include "subdiv/subdivision_surface.h"

CAGEKIT_NAMESPACE_BEGIN

// One straight piece of a sharp feature line (e.g. a sharp edge of the scan).
struct FeatureSegment {
  Vec3 a, b;
};

// The edges `edge_keys` (edge_key()s, e.g. SharpFeatures::edges) of `mesh` as segments; keys
// outside the vertex range are skipped.
std::vector<FeatureSegment> feature_segments(const PolygonMesh& mesh, const std::vector<uint64_t>& edge_keys);

// Closest points on a set of segments within a fixed reach: a uniform grid of cells of side
// `reach`, each segment listed in the cells its pieces (no longer than `reach`) overlap, so
// that a query looks at the 27 cells around its point.
class FeatureLineDistance {
 public:
  // Throws Error(invalid_argument) for reach <= 0 or not finite; non-finite segments are skipped.
  FeatureLineDistance(const std::vector<FeatureSegment>& segments, double reach);
  bool empty() const { return segments_.empty(); }
  // The closest point of the segments to p when one lies within the reach (true), else false.
  bool closest_point(const Vec3& p, Vec3* closest, double* distance) const;

 private:
  uint64_t cell_key(int64_t i, int64_t j, int64_t k) const;
  std::vector<FeatureSegment> segments_;
  double reach_ = 0;
  Vec3 origin_;
  std::vector<uint64_t> cell_keys_;   // sorted, one per (cell, segment) entry
  std::vector<uint32_t> cell_segments_;
};

// The grid points of `linear` (indices into grid_points()) on the limit's crease curves: points
// of ptex sides along the cage's infinitely sharp creases with two faces (boundary creases are
// sharp by the boundary rule and have no feature across them). Each crease curve point is listed
// once: an edge's points are taken from one of its faces only.
std::vector<size_t> crease_curve_grid_points(const Cage& cage, const SubdivisionSurface& surface,
                                             const PtexAdjacency& adjacency, const PiecewiseLinearLimitMesh& linear,
                                             int resolution);

CAGEKIT_NAMESPACE_END
