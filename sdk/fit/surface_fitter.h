// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// fit_cage_to_points / fit_cage_to_mesh: fit a cage's Catmull-Clark limit surface to dense
// samples (thesis ch. 7). Alternates (§7.2, [Die95]) the parameterisation step (foot points =
// closest points on the current limit surface, §7.4, closest_point_on_limit_surface.h) and the
// control-vertex step (linear least squares with the exact basis functions, §7.5,
// least_squares_system.h), until the drop of the thesis's L2 (7.1) falls under `tolerance`
// (relative, (7.2)) or `max_passes` control-vertex steps are done. The L2 the method minimises
// (exact; in piecewise-linear mode the distance to the piecewise-linear mesh) never increases from
// pass to pass: a step that would increase it is rejected and the fit stops. The cage's
// connectivity and tags (creases, corners, holes, boundary rule) are kept, so tagged edges stay
// sharp in the fitted surface; only control-vertex positions change.
#include <cmath>
#include <cstddef>
#include <vector>

#include "core/cage.h"
#include "core/polygon_mesh.h"
#include "core/task_monitor.h"
#include "fit/closest_point_on_limit_surface.h"
#include "fit/crease_feature_rows.h"
#include "fit/least_squares_system.h"
#include "subdiv/subdivision_surface.h"

CAGEKIT_NAMESPACE_BEGIN

// The limit surface the fit works on: smooth extraordinary vertices are exact at any isolation
// level (Stam), so level 3 only shrinks their Stam corner squares (cheaper evaluations); the
// end caps around sharp extraordinary vertices at level 4 (bunny figures equal to 4 digits with
// levels 2-3 / 4-6, the build twice as fast as at 6).
inline SurfaceOptions fit_surface_options() {
  SurfaceOptions options;
  options.isolation_level = 3;
  options.sharp_extraordinary_isolation_level = 4;
  return options;
}

enum class ProjectionMode {
  exact,             // closest points on the exact limit surface (§7.4), the default
  piecewise_linear,  // closest points on the piecewise-linear level-2 limit mesh ([HDD+94]);
                     // a reference for the benchmark (thesis Fig. 7.5), not the default
};

struct FitOptions {
  // Control-vertex steps at most; each is followed by a parameter correction (re-projection).
  int max_passes = 5;
  // Stop when L2_k - L2_{k+1} < tolerance * L2_k ((7.2), made relative so that it does not
  // depend on the model's units or sample count). 0 = run max_passes steps.
  double tolerance = 1e-4;
  // Weight of the umbrella-Laplacian fairing term |L c|^2 relative to the mean diagonal of
  // A^T A (see least_squares_system.h). Off by default (the thesis has none, §7.5); control
  // vertices with no samples in their support then keep their position and are counted in
  // FitReport::unsupported_control_vertices.
  double fairing = 0.0;
  // Control vertices whose support holds little data (least_squares_system.h) get their own
  // fairing rows, so they stay near the average of their neighbours instead of flying off after a
  // few distant samples (a cluster of them with no supported neighbour keeps the initial cage's
  // shape instead of collapsing); 0 = off (the thesis's free vertices). Not in the thesis.
  double weak_support_fraction = 0.05;
  double weak_fairing = 1.0;
  // Judge every state by its two-sided distance (scan -> surface and surface -> scan RMS,
  // two_sided_rms_relative) and return the best state, not the last: a step can lower the
  // thesis's one-sided L2 while parts of the surface move away from the scan. Needs the scan's
  // faces (fit_cage_to_mesh, or `scan_surface`); without them states are judged by L2.
  bool select_best_two_sided = true;
  // Two-sided least squares (not in the thesis, which fits scan -> surface only): when > 0 and
  // the scan's faces are known, each step also pulls the limit surface's grid points that lie
  // farther than reverse_sample_factor x the forward RMS from the scan towards their closest scan
  // point (extra rows of (7.3) whose foot is the grid point's (ptex face, u, v)). Parts of the
  // limit that bulge away from a coarse or thin scan, where no scan sample has its foot, are then
  // drawn back. Steps are accepted and stopped by the two-sided RMS instead of L2. 0 = off.
  double reverse_sample_factor = 0.0;
  // Crease-feature rows (crease_feature_rows.h, not in the thesis): when the scan's sharp feature
  // lines are given, each step also pulls the points of the limit's crease curves that lie within
  // crease_feature_reach x the bbox diagonal of a feature line onto their closest point of it, so
  // that crease curves stay on the sharp edges they were put on instead of sliding along the
  // surface. 0 = off.
  double crease_feature_reach = 0.02;
  // Keep the vertices on infinitely sharp crease edges and the corner-tagged vertices at their
  // input positions (for cages built on the scan, where those vertices are scan samples).
  bool keep_crease_vertices_on_samples = false;
  // 1 = the thesis's point-distance least squares. < 1 down-weights the tangential part of each
  // residual in the control-vertex step (see least_squares_system.h), not in the thesis.
  double tangential_weight = 1.0;
  ProjectionMode projection = ProjectionMode::exact;
  LeastSquaresSolver solver = LeastSquaresSolver::direct;
  ClosestPointOptions closest_point;
  // The limit surface's evaluation (subdivision_surface.h). Fitting uses a lower isolation
  // level around boundary/crease/corner extraordinary vertices than the surface's default (10):
  // the Gregory end caps there cover parameter squares of 2^-6 instead of 2^-10 around each such
  // vertex, which does not change the fit's error (bunny: identical to 4 digits) and builds the
  // surface several times faster on cages with many tagged vertices.
  SurfaceOptions surface = fit_surface_options();
  // Worker threads of the projection and assembly steps; 0 = std::thread::hardware_concurrency().
  int threads = 0;
};

// Statistics of one state of the fit. Distances are |p_i - S(t_i)| at the foot points of the
// exact projection, relative to the samples' bbox diagonal (in piecewise-linear mode too: the
// samples are then projected exactly for the statistics only, outside `seconds`).
struct FitPassStatistics {
  double l2 = 0;                // the thesis's L2 (7.1): sqrt(sum |p_i - S(t_i)|^2), model units
  double rms_relative = 0;      // L2 / sqrt(N) / diagonal
  double max_relative = 0;      // max_i |p_i - S(t_i)| / diagonal
  double mean_relative = 0;     // mean_i |p_i - S(t_i)| / diagonal
  double max_relative_interior = 0;  // max over samples not on or next to a scan boundary
  double seconds = 0;           // time of this pass (least squares + projection)
  size_t unconverged_projections = 0;  // searches that hit max_steps before |q| < epsilon
  double mean_projection_steps = 0;    // update steps per search (hops and line searches count)
  // Surface -> scan: distances from the limit surface's grid points (the vertices of the
  // piecewise-linear limit mesh, (seed_resolution + 1)^2 per ptex face) to the scan's triangles,
  // relative to the diagonal; NaN when the scan's faces are not known.
  double reverse_max_relative = NAN;
  double reverse_rms_relative = NAN;
  // sqrt((rms_relative^2 + reverse_rms_relative^2) / 2): what select_best_two_sided minimises.
  double two_sided_rms_relative = NAN;
  // Grid points added as surface -> scan rows to the step that led to this state
  // (FitOptions::reverse_sample_factor; 0 for the initial state and with it off).
  size_t reverse_samples = 0;
  // Crease-curve points added as crease-feature rows to the step that led to this state
  // (FitOptions::crease_feature_reach; 0 for the initial state, with it off or no feature lines).
  size_t crease_feature_samples = 0;
};

struct FitReport {
  // Entry 0: the initial cage; entry k: after k control-vertex steps and the re-projection.
  std::vector<FitPassStatistics> passes;
  bool stopped_by_tolerance = false;  // (7.2) ended the fit before max_passes
  bool rejected_last_step = false;    // the last step would have increased L2 and was undone
  size_t unsupported_control_vertices = 0;  // no sample in their support in the last step
  size_t weakly_supported_control_vertices = 0;  // held by weak-support fairing in the last step
  bool fairing_used = false;
  // The state returned (index into passes): the best by two_sided_rms_relative with
  // select_best_two_sided and known faces, else the last kept.
  size_t best_pass = 0;
  double bbox_diagonal = 0;
  double seconds = 0;  // whole fit (setup, all passes; without piecewise-linear mode's statistics)
  std::vector<FootPoint> foot_points;  // final foot points of the samples
};

// Throws Error(invalid_argument) for no samples, non-finite samples or options out of range,
// Error(invalid_mesh) for a cage that cannot be subdivided or has no limit surface,
// Error(cancelled) via the monitor (stage "fit", fraction over passes; reported at least once per
// pass). `near_boundary` (optional, one flag per sample) marks the samples excluded from
// max_relative_interior. `scan_surface` (optional): the triangles the samples lie on, for the
// surface -> scan figures and the two-sided choice of the returned state. `sharp_features`
// (optional): the scan's sharp feature lines, for the crease-feature rows.
Cage fit_cage_to_points(const Cage& initial, const std::vector<Vec3>& samples, const FitOptions& options = {},
                        FitReport* report = nullptr, const TaskMonitor& monitor = {},
                        const std::vector<bool>* near_boundary = nullptr,
                        const PolygonMesh* scan_surface = nullptr,
                        const std::vector<FeatureSegment>* sharp_features = nullptr);

// The samples are all of the scan's vertices (foot_points[i] belongs to vertex i); a vertex is
// "near the boundary" when it is on a boundary edge of the scan or shares an edge with such a
// vertex. `sharp_features` as above (e.g. the scan's sharp edges, detect_sharp_features).
Cage fit_cage_to_mesh(const Cage& initial, const PolygonMesh& scan, const FitOptions& options = {},
                      FitReport* report = nullptr, const TaskMonitor& monitor = {},
                      const std::vector<FeatureSegment>* sharp_features = nullptr);

CAGEKIT_NAMESPACE_END
