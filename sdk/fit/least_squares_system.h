// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The control-vertex step of the fit (thesis §7.5, A CV0 = V (7.8)) with fixed foot points:
//   minimise  sum_i |sum_j phi_j(t_i) c_j - p_i|^2  +  lambda |L c|^2  +  mu |c - c_current|^2
// A = [phi_j(t_i)] from the exact basis functions (SubdivisionSurface::basis), L = the umbrella
// Laplacian of the cage (c_j - mean of its edge neighbours), lambda = smoothness * trace(A^T A)
// / (number of control vertices) so that `smoothness` is independent of sample count and scale,
// mu = 1e-12 * trace(A^T A) / (number of control vertices) only so that vertices without samples
// in their support keep their position (A rank-deficient). Sparse normal equations solved with
// Eigen's SimplicialLDLT; x, y, z share the factorisation. `fixed` vertices keep their position
// (their columns move to the right-hand side).
//
// tangential_weight w in [0, 1]: w = 1 is the thesis's point distance (7.8). w < 1 weights the
// residual A_i c - p_i by W_i = n_i n_i^T + w (I - n_i n_i^T), n_i the unit normal of the current
// surface (current_control) at t_i: the tangential part of the residual, which the following
// re-projection removes anyway, counts less (a tangent/squared-distance-minimisation variant,
// [J], not in the thesis). The coordinates then couple (3n unknowns, one factorisation).
#include <cstdint>
#include <vector>

#include "core/cage.h"
#include "fit/closest_point_on_limit_surface.h"
#include "subdiv/subdivision_surface.h"

CAGEKIT_NAMESPACE_BEGIN

std::vector<Vec3> solve_control_points(const SubdivisionSurface& surface, const Cage& cage,
                                       const std::vector<Vec3>& current_control,
                                       const std::vector<Vec3>& samples,
                                       const std::vector<FootPoint>& foot_points, double smoothness,
                                       const std::vector<bool>& fixed, double tangential_weight = 1.0);

CAGEKIT_NAMESPACE_END
