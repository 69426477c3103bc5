// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Closest point on a Catmull-Clark limit surface (thesis §7.4, t = argmin |p - S(t)|^2 (7.3)).
//
// Seeding (the thesis's "closest point on the piecewise-linear C_k" replaced by a simpler robust
// variant): the limit surface is evaluated on a grid of grid_resolution^2 parameter points per
// ptex face, kept in a kd-tree; a query takes its nearest grid points and uses the best points
// of up to `seeds` different ptex faces as starting parameters (plus an optional warm start,
// e.g. the previous foot point, as in the thesis's later passes).
//
// Refinement from each seed: Newton on f(u,v) = |S(u,v) - p|^2 / 2 with the exact second
// derivatives when the Hessian is positive definite, Gauss-Newton ((7.5)-(7.6), J^T J q =
// J^T (p - S)) otherwise; the step is clipped to the unit square (the thesis's case 2), the
// components pushing out through an active bound are dropped, and the step is halved until f
// decreases (instead of Brent's line search (7.7)). No patch hopping across ptex edges: a seed
// that would need to leave its face stops on the face's border, and a seed of the neighbouring
// face (from the grid) takes over. The best result over all seeds is returned, so the search is
// monotone with respect to the warm start.
#include <cstdint>
#include <vector>

#include "core/vec3.h"
#include "fit/point_kd_tree.h"
#include "subdiv/subdivision_surface.h"

CAGEKIT_NAMESPACE_BEGIN

struct FootPoint {
  uint32_t ptex_face = 0;
  double u = 0, v = 0;
  double distance = 0;  // |p - S(t)|
  Vec3 position;        // S(t)
};

struct ClosestPointOptions {
  int grid_resolution = 6;   // seeds per ptex face side
  int seeds = 2;             // ptex faces tried per query
  int max_newton_steps = 60;
  double step_tolerance = 1e-14;  // stop when the (u,v) step is shorter
};

class LimitSurfaceProjector {
 public:
  // `control`: the control-vertex positions to evaluate with (size num_control_vertices()).
  // The surface and control must outlive the projector.
  LimitSurfaceProjector(const SubdivisionSurface& surface, const std::vector<Vec3>& control,
                        const ClosestPointOptions& options = {});

  FootPoint project(const Vec3& p, const FootPoint* warm_start = nullptr) const;
  // Local descent from one starting parameter (no seeding).
  FootPoint refine(const Vec3& p, uint32_t ptex_face, double u, double v) const;

 private:
  const SubdivisionSurface& surface_;
  const std::vector<Vec3>& control_;
  ClosestPointOptions options_;
  std::vector<uint32_t> grid_face_;
  std::vector<float> grid_u_, grid_v_;
  PointKdTree tree_;
};

CAGEKIT_NAMESPACE_END
