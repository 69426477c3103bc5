// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// LimitPatches: the limit surface of a cage as bicubic Bezier patches, what a CAD kernel needs to
// rebuild the surface (B-spline/Bezier faces of a STEP file, FreeCAD's Part.BSplineSurface).
//
// Every ptex face of the cage is covered by a quadtree of squares. A square on which the limit
// surface is one bicubic polynomial (a regular B-spline patch of the feature-adaptive patch table,
// including patches bounded by infinitely sharp creases, which are exact cubic B-splines) becomes
// that polynomial in Bezier form, exactly (up to rounding). Squares up to the adaptive isolation
// level are split to reach those patches. The rest (Stam patches at smooth extraordinary vertices,
// Gregory end caps at extraordinary vertices on creases and boundaries) is approximated:
// per square, each border curve is the least-squares cubic through samples of the limit surface
// along that border with the corners interpolated (so two equal squares that share a border
// share its curve, and the corner points are on the surface), the 4 inner control points are the
// least-squares fit to a 9 x 9 grid of limit points; the square is split into 4 while its
// measured error is above the tolerance and the depth allows. The error of a patch is the largest
// distance between patch and limit surface at the same parameters over a 33 x 33 grid (an upper
// bound of the geometric distance at those samples; between samples it is not a bound).
//
// Crease edges, boundaries and the borders of ptex faces are always borders of patches, so sharp
// features lie on patch borders and are kept: an exact patch reproduces its crease curve, an
// approximated one stays within its error of it.
//
// Thread-safety: build_limit_patches is reentrant (no shared state); the result is a plain value.
// Errors: Error(invalid_argument) for options out of range, Error(invalid_mesh) for a cage that
// cannot be subdivided, Error(limit_exceeded) when more than options.max_patches patches would be
// needed (a larger tolerance or a smaller max_depth needs fewer), Error(out_of_memory) against the
// memory budget, Error(cancelled) through the monitor (checked every 64 squares).
#include <array>
#include <cstdint>
#include <vector>

#include "core/cage.h"
#include "core/task_monitor.h"
#include "subdiv/subdivision_surface.h"

CAGEKIT_NAMESPACE_BEGIN

constexpr int kMaxLimitPatchDepth = 12;
constexpr size_t kMaxLimitPatches = size_t(1) << 22;  // ~1.9 GB of patches

struct LimitPatchOptions {
  // Largest distance allowed between an approximated patch and the limit surface, as a fraction
  // of the bounding-box diagonal of the cage's control points. > 0.
  double tolerance = 1e-4;
  // How often a square that is not one polynomial may be split into 4, [0, kMaxLimitPatchDepth].
  // Patches still above the tolerance at this depth are kept and counted (over_tolerance).
  int max_depth = 8;
  // Worker threads (results do not depend on it).
  int threads = 1;
  // More patches than this fail with limit_exceeded, [1, kMaxLimitPatches].
  size_t max_patches = size_t(1) << 20;
};

struct LimitPatch {
  uint32_t ptex_face = 0;  // SubdivisionSurface's ptex face numbering
  uint32_t cage_face = 0;
  // The patch's square in the ptex face: Bezier (s, t) in [0,1]^2 is the ptex location
  // (u0 + s (u1 - u0), v0 + t (v1 - v0)).
  double u0 = 0, v0 = 0, u1 = 1, v1 = 1;
  bool exact = false;  // the polynomial is the limit surface there
  double error = 0;    // measured largest distance to the limit surface (model units; 0 if exact)
  // Bicubic Bezier control points: point (i, j) at 4 * j + i has weight B_i(s) B_j(t).
  std::array<Vec3, 16> points;
};

struct LimitPatches {
  std::vector<LimitPatch> patches;  // by ptex face, then quadtree order
  uint32_t exact_count = 0, approximated_count = 0;
  uint32_t over_tolerance_count = 0;  // approximated patches above the tolerance at max_depth
  double max_error = 0;               // largest error of an approximated patch, model units
  double bbox_diagonal = 0;           // of the cage's control points
  double tolerance = 0;               // absolute: options.tolerance * bbox_diagonal
};

// The surface options the patches are made for (the defaults of SubdivisionSurface): patches
// reproduce SubdivisionSurface(cage, limit_patch_surface_options()).
SurfaceOptions limit_patch_surface_options();

LimitPatches build_limit_patches(const Cage& cage, const LimitPatchOptions& options,
                                 const TaskMonitor& monitor = TaskMonitor());

// The patch's point at (s, t) in [0,1]^2 (de Casteljau-free Bernstein sum).
Vec3 evaluate_limit_patch(const LimitPatch& patch, double s, double t);

CAGEKIT_NAMESPACE_END
