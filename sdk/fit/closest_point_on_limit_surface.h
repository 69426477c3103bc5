// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Closest point on a Catmull-Clark limit surface (thesis §7.4, t = argmin |p - S(t)|^2 (7.3)).
//
// Start value: the closest point on the piecewise-linear limit mesh (piecewise_linear_limit_mesh.h,
// a BVH over the limit surface sampled at the level-2 vertices) for a first projection; the
// previous foot point for later passes (warm start), with the piecewise-linear closest point as
// a second start when it is in another ptex face and closer (the surface moved between passes;
// not in the thesis, which warm-starts only: measured on the bunny, max 0.81% -> 0.67%).
//
// Update steps in a ptex face (thesis (7.4)-(7.6)): q solves H q = -J^T (S - p) with the exact
// Newton Hessian H = J^T J + sum_k r_k Hess(S_k) when it is positive definite and the thesis's
// Gauss-Newton matrix J^T J otherwise (S, J and the second derivatives are exact). Then, as in
// the thesis:
//   1. (u,v) + q inside the unit square: the step is taken;
//   2. outside: q is scaled so that the point lands on the square's border, and the search
//      stays in the face (the next step may point back in);
//   3. already on the border with q pointing out through a side: the point is transferred to
//      the ptex face across that side (ptex_adjacency.h; at a corner, the side of the larger
//      outward component; repeated transfers walk around extraordinary vertices). No geometric
//      move in this step. An open boundary (or a move straight back across the side just
//      entered through) drops the outward component instead.
// When a step does not decrease the distance, Brent's one-dimensional minimisation along q
// ((7.7), lambda in (0, 1]) picks the step length; no decrease along q at all ends the search
// (a stationary point to working precision). Termination: |q| < epsilon (1e-6) or max_steps
// (500) update steps; the best point seen (never worse than the start) is returned.
#include <cstdint>
#include <memory>
#include <vector>

#include "core/vec3.h"
#include "subdiv/subdivision_surface.h"

CAGEKIT_NAMESPACE_BEGIN

class PtexAdjacency;
class PiecewiseLinearLimitMesh;

struct FootPoint {
  uint32_t ptex_face = 0;
  double u = 0, v = 0;
  double distance = 0;  // |p - S(t)| (or to the piecewise-linear mesh, for project_piecewise_linear)
  Vec3 position;        // S(t)
  uint32_t steps = 0;   // update steps of the search (transfers and line searches included)
  bool converged = true;  // false: max_steps reached before |q| < epsilon
};

struct ClosestPointOptions {
  int max_steps = 500;     // thesis n
  double epsilon = 1e-6;   // thesis: stop when |q| < epsilon (parameter units of a ptex face)
  int seed_resolution = 4;  // grid quads per ptex face side of the piecewise-linear limit mesh
  // With a warm start, also search from the piecewise-linear closest point when it is in another
  // ptex face and closer (false = the thesis: warm start only).
  bool reseed_from_linear_mesh = true;
};

class LimitSurfaceProjector {
 public:
  // `control`: the control-vertex positions to evaluate with (size num_control_vertices()).
  // `adjacency` (of the same surface's cage; null = no transfers, searches stop on the border
  // of their ptex face) and the surface must outlive the projector. `linear_mesh`: build the
  // piecewise-linear limit mesh (needed by project() and project_piecewise_linear(), not by
  // refine()), evaluated on `threads` threads.
  LimitSurfaceProjector(const SubdivisionSurface& surface, const PtexAdjacency* adjacency,
                        const std::vector<Vec3>& control, const ClosestPointOptions& options = {},
                        bool linear_mesh = true, int threads = 1);
  // With the patch points already applied (surface.patch_points(control)) and a piecewise-linear
  // mesh owned by the caller (null: project() needs a warm start and never reseeds;
  // project_piecewise_linear() throws), which must match the patch points and outlive the
  // projector: repeated projections (the passes of a fit) then update one mesh
  // (PiecewiseLinearLimitMesh::update) instead of building one per pass.
  LimitSurfaceProjector(const SubdivisionSurface& surface, const PtexAdjacency* adjacency,
                        std::vector<Vec3> patch_points, const PiecewiseLinearLimitMesh* linear_mesh,
                        const ClosestPointOptions& options = {});
  ~LimitSurfaceProjector();

  // Exact closest point, started from the piecewise-linear closest point or, with a warm start,
  // from the warm start; then also from the piecewise-linear closest point when that lies in
  // another ptex face and is closer than the warm search's result (the better result wins).
  FootPoint project(const Vec3& p, const FootPoint* warm_start = nullptr) const;
  // Exact closest point, started from `start` (warm start; its ptex face and (u, v) are used).
  FootPoint refine(const Vec3& p, const FootPoint& start) const;
  // Closest point on the piecewise-linear limit mesh only ([HDD+94]); position and distance
  // are those of the piecewise-linear mesh.
  FootPoint project_piecewise_linear(const Vec3& p) const;

  const std::vector<Vec3>& patch_points() const { return points_; }

 private:
  double distance2(uint32_t face, double u, double v, const Vec3& p) const;
  const SubdivisionSurface& surface_;
  ClosestPointOptions options_;
  std::vector<Vec3> points_;  // surface.patch_points(control)
  const PtexAdjacency* adjacency_;
  std::unique_ptr<PiecewiseLinearLimitMesh> own_linear_;
  const PiecewiseLinearLimitMesh* linear_ = nullptr;  // own_linear_ or the caller's
  void check_options() const;
};

CAGEKIT_NAMESPACE_END
