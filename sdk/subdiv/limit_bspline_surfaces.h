// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// LimitBSplineSurfaces: the limit surface of a cage as one bicubic B-spline surface per ptex face
// (a cage quad is one surface, an n-gon n), what a CAD kernel takes directly
// (OpenCASCADE Geom_BSplineSurface, FreeCAD Part.BSplineSurface): clamped ("open") knot
// vectors with simple uniform interior knots, degree 3 x 3, non-rational.
//
// Knots. Every surface of a quad ptex face has 2^level_u uniform spans in u and 2^level_v in v,
// every surface of an n-gon sub-face half as many (a sub-face is half an edge long). Levels are
// chosen per surface and direction: each shared border (a segment) has a level too; a surface
// takes at least the levels of its borders in the matching direction, and the border curve is
// refined into the surface's knots by knot insertion (the same curve). Everything starts at
// min_level; a surface over the tolerance, folded, or with a normal jump above
// max_normal_jump_deg across a smooth border goes one level up in both directions with
// its four borders, until no surface below max_level is over (each round refits only the borders
// and surfaces whose levels or inputs changed). (A quad side next to an n-gon is
// split at its middle knot for the two sub-faces.)
//
// Exact surfaces. A ptex face whose limit surface is covered by regular B-spline patches of the
// adaptive patch table (SubdivisionSurface::patch_domain), each at least one knot span large,
// is piecewise bicubic on the knot grid (and C2 inside the face), so the fit below reproduces
// it exactly; such a surface is marked exact after its error on the check grid is measured to
// be below 1e-12 of the bounding-box diagonal.
//
// Fit. Every shared border (cage edge, or an n-gon's inner edge from an edge midpoint to its
// centre) is fitted once: a cubic B-spline curve through its two end points (least squares on 4
// limit samples per span, from an exact side when there is one), whose control points become
// the border rows of both surfaces (the halves of a cage-edge curve, by knot insertion, for
// n-gon sub-faces), so shared borders are the same curves. Across a smooth (non-crease) border
// the cross-boundary derivative of the limit surface is fitted once too (a cubic B-spline with
// the same knots), and the second control row of both surfaces is the border row plus h/3 times
// it (h: first knot span): both surfaces then have the same (opposite) cross derivative along
// the border, so their normals agree there (G1), except in the first and last span of a border,
// where the corner control points belong to the neighbouring borders and the twist point is the
// average of its two constraints. The remaining inner control points are the least-squares fit
// to a (3 spans + 1)^2 grid of limit samples. Crease edges are C0 borders (no cross-derivative
// constraint), boundary edges are boundaries; ptex faces of hole faces have no surface.
//
// Report. parametric_error: the largest distance to the limit surface at equal parameters over
// a max(33, 4 spans + 1)^2 grid per surface; error: the two-sided distance at those samples
// (equal to the parametric error where that is within the tolerance, else every far sample
// projected onto the other surface by Gauss-Newton within the ptex face, both ways; an upper
// bound at the samples); max_normal_deviation_deg: against the limit's normal at equal
// parameters (above 90 deg: folded); normal jumps: the angle between the two surfaces' normals at 4 spans + 1 points
// along every shared border (smooth borders: should be ~0; crease borders: the crease angle).
//
// Thread-safety: reentrant, the result is a plain value; the surfaces of one round are fitted
// on options.threads threads. Errors: Error(invalid_argument) for
// options out of range, Error(invalid_mesh) for a cage that cannot be subdivided,
// Error(out_of_memory) against the memory budget, Error(cancelled) through the monitor
// (checked once per surface).
#include <array>
#include <cstdint>
#include <vector>

#include "core/cage.h"
#include "core/task_monitor.h"

CAGEKIT_NAMESPACE_BEGIN

constexpr int kMaxLimitBSplineLevel = 7;  // 128 spans per quad side

struct LimitBSplineOptions {
  // Largest distance allowed between an approximated surface and the limit surface, as a
  // fraction of the bounding-box diagonal of the cage's control points. > 0.
  double tolerance = 1e-4;
  // Largest knot level tried, [1, kMaxLimitBSplineLevel]; surfaces still above the tolerance at
  // this level are kept and counted (over_tolerance_count).
  int max_level = 5;
  // Smallest knot level tried, [1, max_level].
  int min_level = 1;
  // A surface whose normal jumps by more than this (degrees) across a smooth border is refined
  // like one over the tolerance (the jump is largest in the knot spans next to extraordinary
  // points, where G1 is not constrained, and shrinks with them). > 0.
  double max_normal_jump_deg = 0.5;
  // Worker threads for the surface fits, >= 1 (the surfaces do not depend on it).
  int threads = 1;
};

enum class BorderKind : uint8_t {
  boundary = 0,     // a boundary edge (or next to a hole): no neighbour
  smooth = 1,       // shared with one neighbour, tangent-continuous there
  crease = 2,       // shared along an infinitely sharp crease (C0)
  non_manifold = 3  // a cage edge in more than two faces (sharp): the border curve is shared by all
};

// One neighbour along a side: the side's parameter range [t0, t1] (a quad side next to an
// n-gon has two neighbours, each on half of it) and where that lies on the neighbour:
// neighbour side parameter = n0 + (t - t0) / (t1 - t0) * (n1 - n0) (n1 < n0: reversed).
struct SideNeighbour {
  uint32_t surface = 0;
  uint8_t side = 0;
  double t0 = 0, t1 = 1, n0 = 0, n1 = 1;
};

// Sides: 0 is v = 0 (parameter u), 1 is u = 1 (parameter v), 2 is v = 1 (parameter u), 3 is
// u = 0 (parameter v).
struct SurfaceSide {
  BorderKind kind = BorderKind::boundary;
  std::vector<SideNeighbour> neighbours;
  double max_normal_jump_deg = 0;  // along this side (0 for boundaries)
};

struct LimitBSplineSurface {
  uint32_t ptex_face = 0;  // SubdivisionSurface's ptex face numbering
  uint32_t cage_face = 0;
  int degree_u = 3, degree_v = 3;
  // Clamped knot vectors with multiplicities (degree + 1 at each end), in the ptex face's [0,1].
  std::vector<double> knots_u, knots_v;
  uint32_t num_u = 0, num_v = 0;  // control points per direction (knots.size() - degree - 1)
  // Row-major: point (i, j) (i along u, j along v) at j * num_u + i.
  std::vector<Vec3> points;
  bool exact = false;  // the surface is the limit surface there (measured below 1e-12 of the diagonal)
  // Measured two-sided distance to the limit surface over the check grid (model units): the
  // largest distance from a sample of either surface to the other (each sample projected onto the
  // other surface within the same ptex face, so an upper bound at the samples).
  double error = 0;
  double parametric_error = 0;          // largest distance at equal parameters (>= error)
  double max_normal_deviation_deg = 0;  // largest angle to the limit's normal at equal parameters
  std::array<SurfaceSide, 4> sides;
};

struct LimitBSplineSurfaces {
  std::vector<LimitBSplineSurface> surfaces;  // by ptex face (holes skipped)
  int level = 0;                              // largest knot level used (2^level spans per quad side)
  uint32_t exact_count = 0, approximated_count = 0;
  uint32_t over_tolerance_count = 0;  // approximated surfaces above the tolerance (or folded) at max_level
  uint32_t folded_count = 0;          // surfaces whose normal deviates by more than 90 deg somewhere
  double max_error = 0;               // over all surfaces (two-sided), model units
  double max_parametric_error = 0;    // over all surfaces, model units
  double max_normal_deviation_deg = 0;
  double max_normal_jump_deg = 0;     // over smooth shared borders
  // Border samples left out of max_normal_jump_deg because the limit surface itself folds or is
  // degenerate there (its own normals on the two sides more than 30 deg apart, or its derivatives
  // nearly parallel): a fault of the cage, not of the fit.
  uint32_t limit_fold_points = 0;
  double max_crease_angle_deg = 0;    // largest normal jump over crease / non-manifold borders
  double bbox_diagonal = 0;           // of the cage's control points
  double tolerance = 0;               // absolute: options.tolerance * bbox_diagonal
  uint32_t ptex_faces = 0;            // of the cage (including holes)
};

LimitBSplineSurfaces build_limit_bspline_surfaces(const Cage& cage, const LimitBSplineOptions& options,
                                                  const TaskMonitor& monitor = TaskMonitor());

struct BSplineSurfacePoint {
  Vec3 position, du, dv;
};

// The surface's point and first derivatives at (u, v) in [0,1]^2 (de Boor / Cox-de Boor).
BSplineSurfacePoint evaluate_bspline_surface(const LimitBSplineSurface& surface, double u, double v);

// The point on side `side` (0..3, see SurfaceSide) at side parameter t, as (u, v).
void side_location(int side, double t, double& u, double& v);

CAGEKIT_NAMESPACE_END
