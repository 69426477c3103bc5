// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The control-vertex step of the fit (thesis §7.5, A CV0 = V (7.8)) with fixed foot points:
//   minimise  sum_i |sum_j phi_j(t_i) c_j - p_i|^2  +  lambda |L c|^2
//             +  sum_{j weak} lambda_w |(L c)_j - t0_j|^2  +  mu |c - c_current|^2
// (t0_j = 0, or (L c0)_j with c0 the initial cage `cage` for weak vertices with no anchor: below)
// A = [phi_j(t_i)] from the exact basis functions (SubdivisionSurface::basis), L = the umbrella
// Laplacian of the cage (c_j - mean of its edge neighbours), lambda = fairing * trace(A^T A)
// / (number of control vertices) so that `fairing` is independent of sample count and scale,
// mu = 1e-12 * trace(A^T A) / (number of control vertices) only so that vertices without samples
// in their support keep their position (A rank-deficient; counted in the report). Sparse normal
// equations solved with Eigen's SimplicialLDLT (x, y, z share the factorisation) or, with the
// cgls solver, by conjugate gradients on the normal equations without forming them (Eigen's
// LeastSquaresConjugateGradient, the thesis's CGLS), warm-started from current_control, three
// right-hand sides. `fixed` vertices keep their position (their columns move to the
// right-hand side).
//
// tangential_weight w in [0, 1]: w = 1 is the thesis's point distance (7.8). w < 1 weights the
// residual A_i c - p_i by W_i = n_i n_i^T + w (I - n_i n_i^T), n_i the unit normal of the current
// surface (current_control) at t_i: the tangential part of the residual, which the following
// re-projection removes anyway, counts less (a tangent/squared-distance-minimisation variant,
// [J], not in the thesis). The coordinates then couple (3n unknowns, one factorisation; the
// direct solver is used whatever `solver` says).
#include <cstdint>
#include <vector>

#include "core/task_monitor.h"
#include "core/cage.h"
#include "fit/closest_point_on_limit_surface.h"
#include "subdiv/subdivision_surface.h"

CAGEKIT_NAMESPACE_BEGIN

enum class LeastSquaresSolver {
  direct,  // sparse Cholesky (LDL^T) of the normal equations; x, y, z share the factorisation
  cgls,    // conjugate gradients on the normal equations (the thesis's CGLS), warm-started
           // from the current control points
};

struct LeastSquaresOptions {
  double fairing = 0.0;            // lambda / (mean diagonal of A^T A); 0 = no fairing term
  // Weakly supported control vertices: free vertices whose support holds little data (the
  // diagonal of A^T A, the sum of their squared basis values over the samples, is below
  // weak_support_fraction x its mean over the free vertices; 0 with no sample at all) get their
  // own umbrella-Laplacian row with weight weak_fairing x (mean diagonal of A^T A), on top of
  // `fairing`: they are held near the average of their neighbours instead of being left free to
  // fly off after a few distant samples. A cluster of weak vertices (connected by cage edges)
  // that touches no supported or fixed vertex, such as a speck of a component, would collapse to
  // one point that way: its rows keep the initial cage's Laplacian coordinates instead, so it
  // keeps its shape and moves as a whole (not in the thesis, whose dense samples support every
  // vertex). weak_support_fraction 0 turns this off.
  double weak_support_fraction = 0.0;
  double weak_fairing = 1.0;
  double tangential_weight = 1.0;  // w in [0, 1]
  LeastSquaresSolver solver{};     // direct (default) or cgls
  int threads = 1;                 // assembly threads
};

struct LeastSquaresReport {
  size_t unsupported_control_vertices = 0;  // free control vertices with no sample in their support
  size_t weakly_supported_control_vertices = 0;  // free vertices held by the weak-support rows
                                                 // (includes the unsupported ones)
  int cgls_iterations = 0;                  // largest over x, y, z (cgls only)
};

// Returns the new control positions. `fixed` vertices keep their current position. Throws
// invalid_argument for inconsistent sizes or options, internal_error when the solve fails.
// `monitor` (optional): reports (`stage`, `fraction`) between the steps and every 4096 samples of
// the assembly (the steps take seconds with a million samples), so a cancel there throws
// Error(cancelled) within a fraction of a second.
std::vector<Vec3> solve_control_points(const SubdivisionSurface& surface, const Cage& cage,
                                       const std::vector<Vec3>& current_control,
                                       const std::vector<Vec3>& samples,
                                       const std::vector<FootPoint>& foot_points, const std::vector<bool>& fixed,
                                       const LeastSquaresOptions& options, LeastSquaresReport* report = nullptr,
                                       const TaskMonitor* monitor = nullptr, const char* stage = "fit",
                                       double fraction = 0.0);

CAGEKIT_NAMESPACE_END
