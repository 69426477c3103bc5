// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// fit_cage_to_points: fit a cage's Catmull-Clark limit surface to dense samples (thesis ch. 7).
// Alternates (§7.2, [Die95]) the parameterisation step (foot points = closest points on the
// current limit surface, §7.4, closest_point_on_limit_surface.h) and the control-vertex step
// (linear least squares with the exact basis functions, §7.5, least_squares_system.h). The cage's
// connectivity and tags are kept; only control-vertex positions change.
#include <vector>

#include "core/cage.h"
#include "core/task_monitor.h"
#include "fit/closest_point_on_limit_surface.h"

CAGEKIT_NAMESPACE_BEGIN

struct FitOptions {
  // Control-vertex steps; each is followed by a parameter correction (re-projection).
  int iterations = 5;
  // Weight of the umbrella-Laplacian regulariser |L c|^2 relative to the mean diagonal of
  // A^T A (see least_squares_system.h). The thesis has none (§7.5); a small default keeps
  // control vertices with few samples in their support from drifting. 0 = the thesis's fit.
  double smoothness = 1e-4;
  // Keep the vertices on infinitely sharp crease edges and the corner-tagged vertices at their
  // input positions (for cages built on the scan, where those vertices are scan samples).
  bool keep_crease_vertices_on_samples = false;
  // 1 = the thesis's point-distance least squares. < 1 down-weights the tangential part of each
  // residual in the control-vertex step (see least_squares_system.h): far faster convergence of
  // the control points (tangent-distance-like), not in the thesis. Range [0, 1].
  double tangential_weight = 1.0;
  ClosestPointOptions closest_point;
  // Worker threads of the projection step; 0 = std::thread::hardware_concurrency().
  int threads = 0;
};

struct FitReport {
  // Entry 0: the initial cage; entry k: after k control-vertex steps and the re-projection.
  // Distances are |p_i - S(t_i)| at the foot points, relative to the samples' bbox diagonal.
  std::vector<double> rms_relative, max_relative;
  std::vector<double> l2;  // the thesis's L2 (7.1): sqrt(sum |p_i - S(t_i)|^2), absolute
  std::vector<double> iteration_seconds;
  double bbox_diagonal = 0;
  double seconds = 0;
  std::vector<FootPoint> foot_points;  // final foot points of the samples
};

// Throws Error(invalid_argument) for no samples, non-finite samples or options out of range,
// Error(invalid_mesh) for a cage that cannot be subdivided, Error(cancelled) via the monitor
// (stage "fit", fraction over projection passes).
Cage fit_cage_to_points(const Cage& initial, const std::vector<Vec3>& samples, const FitOptions& options = {},
                        FitReport* report = nullptr, const TaskMonitor& monitor = {});

CAGEKIT_NAMESPACE_END
