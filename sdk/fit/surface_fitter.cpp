// SPDX-License-Identifier: GPL-3.0-or-later
#include "core/memory_budget.h"
#include "fit/surface_fitter.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <memory>
#include <string>
#include <thread>

#include "core/parallel_for.h"
#include "core/status.h"
#include "fit/least_squares_system.h"
#include "fit/piecewise_linear_limit_mesh.h"
#include "fit/ptex_adjacency.h"
#include "layout/common/approximation_error.h"
#include "subdiv/subdivision_surface.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

FitPassStatistics statistics(const std::vector<FootPoint>& feet, const std::vector<bool>* near_boundary,
                             double diagonal) {
  FitPassStatistics s;
  double sum2 = 0, sum = 0;
  size_t steps = 0;
  for (size_t i = 0; i < feet.size(); ++i) {
    const FootPoint& f = feet[i];
    sum2 += f.distance * f.distance;
    sum += f.distance;
    s.max_relative = std::max(s.max_relative, f.distance);
    if (!near_boundary || !(*near_boundary)[i]) s.max_relative_interior = std::max(s.max_relative_interior, f.distance);
    steps += f.steps;
    if (!f.converged) ++s.unconverged_projections;
  }
  const double d = diagonal > 0 ? diagonal : 1.0, n = double(feet.size());
  s.l2 = std::sqrt(sum2);
  s.rms_relative = std::sqrt(sum2 / n) / d;
  s.mean_relative = sum / n / d;
  s.max_relative /= d;
  s.max_relative_interior /= d;
  s.mean_projection_steps = double(steps) / n;
  return s;
}

}  // namespace

Cage fit_cage_to_points(const Cage& initial, const std::vector<Vec3>& samples, const FitOptions& options,
                        FitReport* report_out, const TaskMonitor& monitor, const std::vector<bool>* near_boundary,
                        const PolygonMesh* scan_surface, const std::vector<FeatureSegment>* sharp_features) {
  const auto start = Clock::now();
  if (samples.empty()) fail(Status::invalid_argument, "fit: no samples");
  if (options.max_passes < 0 || options.max_passes > 100000)
    fail(Status::invalid_argument, "fit: max_passes must be in [0, 100000]");
  if (!(options.tolerance >= 0) || !std::isfinite(options.tolerance))
    fail(Status::invalid_argument, "fit: tolerance must be finite and >= 0");
  if (!(options.fairing >= 0) || !std::isfinite(options.fairing))
    fail(Status::invalid_argument, "fit: fairing must be finite and >= 0");
  if (!(options.tangential_weight >= 0 && options.tangential_weight <= 1))
    fail(Status::invalid_argument, "fit: tangential_weight must be in [0, 1]");
  if (!(options.weak_support_fraction >= 0) || !std::isfinite(options.weak_support_fraction))
    fail(Status::invalid_argument, "fit: weak_support_fraction must be finite and >= 0");
  if (!(options.weak_fairing >= 0) || !std::isfinite(options.weak_fairing))
    fail(Status::invalid_argument, "fit: weak_fairing must be finite and >= 0");
  if (options.projection != ProjectionMode::exact && options.projection != ProjectionMode::piecewise_linear)
    fail(Status::invalid_argument, "fit: unknown projection mode");
  if (options.solver != LeastSquaresSolver::direct && options.solver != LeastSquaresSolver::cgls)
    fail(Status::invalid_argument, "fit: unknown least-squares solver");
  if (!(options.crease_feature_reach >= 0) || !std::isfinite(options.crease_feature_reach))
    fail(Status::invalid_argument, "fit: crease_feature_reach must be finite and >= 0");
  if (options.threads < 0) fail(Status::invalid_argument, "fit: threads must be >= 0");
  if (near_boundary && near_boundary->size() != samples.size())
    fail(Status::invalid_argument, "fit: near_boundary must have one flag per sample");
  BoundingBox box;
  for (const Vec3& p : samples) {
    if (!is_finite(p)) fail(Status::invalid_argument, "fit: non-finite sample");
    box.extend(p);
  }
  const int threads = options.threads > 0 ? options.threads
                                          : int(std::max(1u, std::thread::hardware_concurrency()));
  const bool exact = options.projection == ProjectionMode::exact;

  // Measured: ~3.2 KB per sample (foot points, basis rows, least-squares triplets, projection).
  check_memory_estimate(estimate_product(samples.size(), 3300), "fitting");
  SurfaceOptions surface_options = options.surface;
  surface_options.threads = threads;
  const SubdivisionSurface surface(initial, surface_options);
  const PtexAdjacency adjacency(initial.mesh, surface);
  monitor.log(LogLevel::debug, "fit: limit surface built in " + std::to_string(seconds_since(start)) + " s");
  monitor.report("fit", 0.0);
  const size_t n = initial.mesh.num_vertices();
  std::vector<bool> fixed(n, false);
  if (options.keep_crease_vertices_on_samples) {
    for (const EdgeCrease& e : initial.creases)
      if (e.sharpness >= kSharpnessInfinite && e.v0 < n && e.v1 < n) fixed[e.v0] = fixed[e.v1] = true;
    for (const VertexCorner& c : initial.corners)
      if (c.sharpness >= kSharpnessInfinite && c.vertex < n) fixed[c.vertex] = true;
  }
  // In LeastSquaresOptions' member order (each argument bears its member's name).
  const LeastSquaresOptions lsq{options.fairing,           options.weak_support_fraction, options.weak_fairing,
                                options.tangential_weight, options.solver,                threads};

  FitReport report;
  report.bbox_diagonal = box.diagonal();
  report.fairing_used = options.fairing > 0;
  const double passes = double(options.max_passes + 1);
  double excluded_seconds = 0;  // piecewise-linear mode: exact statistics, not part of the method

  // Foot points used by the method (exact or piecewise linear) and, in piecewise-linear mode,
  // the exact ones for the statistics.
  std::vector<Vec3> control = initial.mesh.positions;
  std::vector<FootPoint> feet(samples.size()), exact_feet;
  // The L2 the method minimises: the exact one, or in piecewise-linear mode the distance to the
  // piecewise-linear mesh (the statistics report the exact one in both modes).
  double objective = 0;
  // One piecewise-linear limit mesh for all passes: built for the first projection, updated
  // (stored grid stencils, refitted hierarchy) when a pass needs it again.
  std::unique_ptr<PiecewiseLinearLimitMesh> linear;
  // Surface -> scan: the scan's triangles in one tree, queried at the linear mesh's grid points.
  std::unique_ptr<SurfaceDistance> scan_distance;
  if (scan_surface != nullptr && scan_surface->num_faces() > 0) {
    scan_distance = std::make_unique<SurfaceDistance>(*scan_surface, monitor, "fit", 0.0);
    if (scan_distance->empty()) scan_distance.reset();
    monitor.report("fit", 0.0);
  }
  // Crease-feature rows: the feature lines within reach, and the limit's crease-curve grid points
  // (found once the linear mesh exists).
  std::unique_ptr<FeatureLineDistance> feature_lines;
  if (sharp_features && !sharp_features->empty() && options.crease_feature_reach > 0 && !initial.creases.empty() &&
      box.diagonal() > 0) {
    feature_lines = std::make_unique<FeatureLineDistance>(*sharp_features, options.crease_feature_reach * box.diagonal());
    if (feature_lines->empty()) feature_lines.reset();
  }
  std::vector<size_t> crease_points;
  bool crease_points_found = false;
  // The grid points' distances to the scan in the last projected state.
  std::vector<double> reverse_distance;
  auto measure_reverse = [&](FitPassStatistics& s, double fraction) {
    if (!scan_distance || !linear) return;
    const std::vector<Vec3>& grid = linear->grid_points();
    std::vector<double>& d = reverse_distance;
    d.assign(grid.size(), 0.0);
    parallel_for(grid.size(), threads, monitor, "fit", fraction, fraction,
                 [&](size_t i) { d[i] = scan_distance->distance(grid[i]); });
    double largest = 0, sum2 = 0;
    for (const double x : d) largest = std::max(largest, x), sum2 += x * x;
    const double diag = report.bbox_diagonal > 0 ? report.bbox_diagonal : 1.0;
    s.reverse_max_relative = largest / diag;
    s.reverse_rms_relative = grid.empty() ? 0.0 : std::sqrt(sum2 / double(grid.size())) / diag;
    s.two_sided_rms_relative =
        std::sqrt(0.5 * (s.rms_relative * s.rms_relative + s.reverse_rms_relative * s.reverse_rms_relative));
  };
  auto project = [&](const std::vector<Vec3>& ctrl, bool warm, double f0, double f1) {
    const auto build_start = Clock::now();
    const bool linear_mesh =
        !(exact && warm) || options.closest_point.reseed_from_linear_mesh || scan_distance || feature_lines;
    std::vector<Vec3> points = surface.patch_points(ctrl);
    if (linear_mesh) {
      if (!linear)
        linear = std::make_unique<PiecewiseLinearLimitMesh>(surface, points, options.closest_point.seed_resolution,
                                                            threads);
      else
        linear->update(points, threads);
      monitor.log(LogLevel::debug, "fit: piecewise-linear limit mesh ready in " +
                                       std::to_string(seconds_since(build_start)) + " s");
    }
    const LimitSurfaceProjector projector(surface, &adjacency, std::move(points), linear_mesh ? linear.get() : nullptr,
                                          options.closest_point);
    if (exact) {
      parallel_for(samples.size(), threads, monitor, "fit", f0, f1, [&](size_t i) {
        feet[i] = projector.project(samples[i], warm ? &feet[i] : nullptr);
      });
      FitPassStatistics st = statistics(feet, near_boundary, report.bbox_diagonal);
      measure_reverse(st, f1);
      objective = st.l2;
      return st;
    }
    parallel_for(samples.size(), threads, monitor, "fit", f0, 0.5 * (f0 + f1),
                 [&](size_t i) { feet[i] = projector.project_piecewise_linear(samples[i]); });
    const auto t0 = Clock::now();
    exact_feet.resize(samples.size());
    parallel_for(samples.size(), threads, monitor, "fit", 0.5 * (f0 + f1), f1, [&](size_t i) {
      exact_feet[i] = projector.project(samples[i], warm ? &exact_feet[i] : nullptr);
    });
    FitPassStatistics s = statistics(exact_feet, near_boundary, report.bbox_diagonal);
    const FitPassStatistics own = statistics(feet, nullptr, report.bbox_diagonal);
    s.unconverged_projections = own.unconverged_projections;
    s.mean_projection_steps = own.mean_projection_steps;
    measure_reverse(s, f1);
    objective = own.l2;
    excluded_seconds += seconds_since(t0);
    return s;
  };

  // The state returned: the best by the two-sided RMS when it is measured, else the last one
  // kept (L2 never increases from one kept state to the next).
  const bool two_sided = options.select_best_two_sided && scan_distance != nullptr;
  // Two-sided least squares: the objective of acceptance and stopping is the two-sided RMS.
  const bool reverse_rows = options.reverse_sample_factor > 0 && scan_distance != nullptr;
  auto project_state = [&](const std::vector<Vec3>& ctrl, bool warm, double f0, double f1) {
    FitPassStatistics st = project(ctrl, warm, f0, f1);
    if (reverse_rows && std::isfinite(st.two_sided_rms_relative)) objective = st.two_sided_rms_relative;
    return st;
  };
  // The rows of one step: the samples and, with reverse rows, the grid points of the current
  // state that lie far from the scan, each aimed at its closest scan point.
  std::vector<Vec3> step_samples;
  std::vector<FootPoint> step_feet;
  // Grid points as rows: each aimed at `targets[i]` from its own (ptex face, u, v).
  auto add_grid_rows = [&](const std::vector<size_t>& points, const std::vector<Vec3>& targets) {
    if (step_samples.empty()) step_samples = samples, step_feet = feet;
    const std::vector<Vec3>& grid = linear->grid_points();
    for (size_t i = 0; i < points.size(); ++i) {
      FootPoint f;
      linear->grid_point_parameters(points[i], f.ptex_face, f.u, f.v);
      f.position = grid[points[i]];
      f.distance = distance(grid[points[i]], targets[i]);
      step_samples.push_back(targets[i]);
      step_feet.push_back(f);
    }
  };
  // Crease-feature rows of the current state: its crease-curve points within reach of a feature.
  auto crease_feature_rows = [&](double fraction) -> size_t {
    if (!feature_lines || !linear) return 0;
    if (!crease_points_found) {
      crease_points = crease_curve_grid_points(initial, surface, adjacency, *linear,
                                               options.closest_point.seed_resolution);
      crease_points_found = true;
    }
    if (crease_points.empty()) return 0;
    const std::vector<Vec3>& grid = linear->grid_points();
    std::vector<Vec3> target(crease_points.size());
    std::vector<uint8_t> within(crease_points.size(), 0);
    parallel_for(crease_points.size(), threads, monitor, "fit", fraction, fraction, [&](size_t i) {
      within[i] = feature_lines->closest_point(grid[crease_points[i]], &target[i], nullptr) ? 1 : 0;
    });
    std::vector<size_t> points;
    std::vector<Vec3> targets;
    for (size_t i = 0; i < crease_points.size(); ++i)
      if (within[i]) points.push_back(crease_points[i]), targets.push_back(target[i]);
    if (!points.empty()) add_grid_rows(points, targets);
    return points.size();
  };
  auto far_grid_points = [&](double current_rms_relative, double fraction) -> size_t {
    if (!reverse_rows || !linear || reverse_distance.size() != linear->grid_points().size()) return 0;
    const double threshold = options.reverse_sample_factor * current_rms_relative * report.bbox_diagonal;
    std::vector<size_t> far;
    for (size_t k = 0; k < reverse_distance.size(); ++k)
      if (reverse_distance[k] > threshold) far.push_back(k);
    if (far.empty()) return 0;
    if (step_samples.empty()) step_samples = samples, step_feet = feet;
    const size_t first = step_samples.size();
    step_samples.resize(first + far.size());
    step_feet.resize(first + far.size());
    const std::vector<Vec3>& grid = linear->grid_points();
    parallel_for(far.size(), threads, monitor, "fit", fraction, fraction, [&](size_t i) {
      const size_t k = far[i];
      FootPoint& f = step_feet[first + i];
      linear->grid_point_parameters(k, f.ptex_face, f.u, f.v);
      f.position = grid[k];
      f.distance = reverse_distance[k];
      step_samples[first + i] = scan_distance->closest_point(grid[k]);
    });
    return far.size();
  };
  std::vector<Vec3> best_control;
  std::vector<FootPoint> best_feet;
  auto keep_if_best = [&](const FitPassStatistics& s) {
    const size_t k = report.passes.size() - 1;
    if (k > 0 && two_sided && !(s.two_sided_rms_relative < report.passes[report.best_pass].two_sided_rms_relative))
      return;
    report.best_pass = k;
    best_control = control;
    best_feet = exact ? feet : exact_feet;
  };
  {
    const auto t0 = Clock::now();
    const double excluded_before = excluded_seconds;
    FitPassStatistics s = project_state(control, false, 0.0, 1.0 / passes);
    s.seconds = seconds_since(t0) - (excluded_seconds - excluded_before);
    report.passes.push_back(s);
    keep_if_best(s);
  }
  for (int pass = 1; pass <= options.max_passes; ++pass) {
    const auto t0 = Clock::now();
    const double excluded_before = excluded_seconds;
    const double objective_before = objective;
    LeastSquaresReport lsq_report;
    step_samples.clear();
    step_feet.clear();
    const size_t reverse_samples = far_grid_points(report.passes.back().rms_relative, pass / passes);
    const size_t crease_samples = crease_feature_rows(pass / passes);
    std::vector<Vec3> next =
        reverse_samples + crease_samples > 0
            ? solve_control_points(surface, initial, control, step_samples, step_feet, fixed, lsq, &lsq_report,
                                   &monitor, "fit", pass / passes)
            : solve_control_points(surface, initial, control, samples, feet, fixed, lsq, &lsq_report, &monitor,
                                   "fit", pass / passes);
    const double lsq_seconds = seconds_since(t0);
    report.unsupported_control_vertices = lsq_report.unsupported_control_vertices;
    report.weakly_supported_control_vertices = lsq_report.weakly_supported_control_vertices;
    const std::vector<FootPoint> previous_feet = feet, previous_exact = exact_feet;
    FitPassStatistics s = project_state(next, true, pass / passes, (pass + 1) / passes);
    s.reverse_samples = reverse_samples;
    s.crease_feature_samples = crease_samples;
    s.seconds = seconds_since(t0) - (excluded_seconds - excluded_before);
    const double before = objective_before;
    if (objective > before) {  // never let the error grow: undo the step and stop
      feet = previous_feet;
      exact_feet = previous_exact;
      report.rejected_last_step = true;
      monitor.log(LogLevel::info, "fit pass " + std::to_string(pass) + " would increase " +
                                      (reverse_rows ? "the two-sided RMS (" : "L2 (") + std::to_string(before) + " -> " + std::to_string(objective) + "); stopped");
      objective = before;
      break;
    }
    control = std::move(next);
    report.passes.push_back(s);
    keep_if_best(s);
    monitor.log(LogLevel::info, "fit pass " + std::to_string(pass) + ": rms " + std::to_string(s.rms_relative) +
                                    ", max " + std::to_string(s.max_relative) + " of the bbox diagonal" +
                                    (std::isnan(s.reverse_max_relative)
                                         ? std::string()
                                         : "; surface -> scan rms " + std::to_string(s.reverse_rms_relative) +
                                               ", max " + std::to_string(s.reverse_max_relative)) +
                                    "; " + std::to_string(lsq_seconds) + " s least squares, " +
                                    std::to_string(s.seconds - lsq_seconds) + " s projection");
    if (before - objective < options.tolerance * before) {
      report.stopped_by_tolerance = pass < options.max_passes;
      break;
    }
  }
  monitor.report("fit", 1.0);
  if (report.best_pass + 1 != report.passes.size())
    monitor.log(LogLevel::info, "fit: returning state " + std::to_string(report.best_pass) + " of " +
                                    std::to_string(report.passes.size() - 1) +
                                    " (the lowest two-sided distance; later steps lowered L2 but moved the surface "
                                    "away from the scan)");

  Cage fitted = initial;
  fitted.mesh.positions = std::move(best_control);
  report.seconds = seconds_since(start) - excluded_seconds;
  report.foot_points = std::move(best_feet);
  if (report_out) *report_out = std::move(report);
  return fitted;
}

Cage fit_cage_to_mesh(const Cage& initial, const PolygonMesh& scan, const FitOptions& options, FitReport* report,
                      const TaskMonitor& monitor, const std::vector<FeatureSegment>* sharp_features) {
  const size_t n = scan.num_vertices();
  for (uint32_t v : scan.face_vertices)
    if (v >= n) fail(Status::invalid_argument, "fit: the scan has a face vertex index out of range");
  // Boundary edges: undirected edges used by exactly one face (a second on a million-face scan:
  // cancel points before and after the sort).
  monitor.report("fit", 0.0);
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  edges.reserve(scan.face_vertices.size());
  for (size_t f = 0; f < scan.num_faces(); ++f) {
    const uint32_t k = scan.face_size(f);
    for (uint32_t c = 0; c < k; ++c) {
      const uint32_t a = scan.face_vertex(f, c), b = scan.face_vertex(f, (c + 1) % k);
      edges.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  std::sort(edges.begin(), edges.end());
  monitor.report("fit", 0.0);
  std::vector<bool> on_boundary(n, false), near;
  for (size_t i = 0; i < edges.size();) {
    size_t j = i + 1;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) on_boundary[edges[i].first] = on_boundary[edges[i].second] = true;
    i = j;
  }
  near = on_boundary;
  for (size_t f = 0; f < scan.num_faces(); ++f) {
    const uint32_t k = scan.face_size(f);
    for (uint32_t c = 0; c < k; ++c) {
      const uint32_t a = scan.face_vertex(f, c), b = scan.face_vertex(f, (c + 1) % k);
      if (on_boundary[a]) near[b] = true;
      if (on_boundary[b]) near[a] = true;
    }
  }
  return fit_cage_to_points(initial, scan.positions, options, report, monitor, &near, &scan, sharp_features);
}

CAGEKIT_NAMESPACE_END
