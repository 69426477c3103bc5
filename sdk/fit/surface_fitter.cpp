// SPDX-License-Identifier: GPL-3.0-or-later
#include "fit/surface_fitter.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <thread>

#include "core/status.h"
#include "fit/least_squares_system.h"
#include "subdiv/subdivision_surface.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Projects all samples (in parallel, in chunks; progress/cancel between chunks on this thread).
void project_all(const LimitSurfaceProjector& projector, const std::vector<Vec3>& samples,
                 std::vector<FootPoint>& feet, bool warm, int threads, const TaskMonitor& monitor,
                 double fraction_begin, double fraction_end) {
  const size_t n = samples.size();
  const size_t chunk = 4096;
  for (size_t begin = 0; begin < n; begin += chunk) {
    monitor.report("fit", fraction_begin + (fraction_end - fraction_begin) * double(begin) / double(n));
    const size_t end = std::min(n, begin + chunk);
    const size_t workers = std::max<size_t>(1, std::min<size_t>(size_t(threads), end - begin));
    std::vector<std::exception_ptr> errors(workers);
    auto work = [&](size_t w) {
      try {
        for (size_t i = begin + w; i < end; i += workers)
          feet[i] = projector.project(samples[i], warm ? &feet[i] : nullptr);
      } catch (...) {
        errors[w] = std::current_exception();
      }
    };
    std::vector<std::thread> pool;
    for (size_t w = 1; w < workers; ++w) pool.emplace_back(work, w);
    work(0);
    for (auto& t : pool) t.join();
    for (auto& e : errors)
      if (e) std::rethrow_exception(e);
  }
}

void record(const std::vector<FootPoint>& feet, double diagonal, FitReport& report) {
  double sum = 0, max = 0;
  for (const FootPoint& f : feet) {
    sum += f.distance * f.distance;
    max = std::max(max, f.distance);
  }
  const double d = diagonal > 0 ? diagonal : 1.0;
  report.l2.push_back(std::sqrt(sum));
  report.rms_relative.push_back(std::sqrt(sum / double(feet.size())) / d);
  report.max_relative.push_back(max / d);
}
}  // namespace

Cage fit_cage_to_points(const Cage& initial, const std::vector<Vec3>& samples, const FitOptions& options,
                        FitReport* report_out, const TaskMonitor& monitor) {
  const auto start = Clock::now();
  if (samples.empty()) fail(Status::invalid_argument, "fit: no samples");
  if (options.iterations < 0) fail(Status::invalid_argument, "fit: iterations must be >= 0");
  if (!(options.smoothness >= 0)) fail(Status::invalid_argument, "fit: smoothness must be >= 0");
  if (!(options.tangential_weight >= 0 && options.tangential_weight <= 1))
    fail(Status::invalid_argument, "fit: tangential_weight must be in [0, 1]");
  BoundingBox box;
  for (const Vec3& p : samples) {
    if (!is_finite(p)) fail(Status::invalid_argument, "fit: non-finite sample");
    box.extend(p);
  }
  const int threads = options.threads > 0 ? options.threads
                                          : int(std::max(1u, std::thread::hardware_concurrency()));

  const SubdivisionSurface surface(initial);
  const size_t n = initial.mesh.num_vertices();
  std::vector<bool> fixed(n, false);
  if (options.keep_crease_vertices_on_samples) {
    for (const EdgeCrease& e : initial.creases)
      if (e.sharpness >= kSharpnessInfinite && e.v0 < n && e.v1 < n) fixed[e.v0] = fixed[e.v1] = true;
    for (const VertexCorner& c : initial.corners)
      if (c.sharpness >= kSharpnessInfinite && c.vertex < n) fixed[c.vertex] = true;
  }

  FitReport report;
  report.bbox_diagonal = box.diagonal();
  std::vector<Vec3> control = initial.mesh.positions;
  std::vector<FootPoint> feet(samples.size());
  const double passes = double(options.iterations + 1);
  {
    const auto t0 = Clock::now();
    const LimitSurfaceProjector projector(surface, control, options.closest_point);
    project_all(projector, samples, feet, false, threads, monitor, 0.0, 1.0 / passes);
    record(feet, report.bbox_diagonal, report);
    report.iteration_seconds.push_back(seconds_since(t0));
  }
  for (int it = 1; it <= options.iterations; ++it) {
    const auto t0 = Clock::now();
    control = solve_control_points(surface, initial, control, samples, feet, options.smoothness, fixed,
                                   options.tangential_weight);
    const LimitSurfaceProjector projector(surface, control, options.closest_point);
    project_all(projector, samples, feet, true, threads, monitor, it / passes, (it + 1) / passes);
    record(feet, report.bbox_diagonal, report);
    report.iteration_seconds.push_back(seconds_since(t0));
    monitor.log(LogLevel::info, "fit iteration " + std::to_string(it) + ": rms " +
                                    std::to_string(report.rms_relative.back()) + ", max " +
                                    std::to_string(report.max_relative.back()) + " of the bbox diagonal");
  }
  monitor.report("fit", 1.0);

  Cage fitted = initial;
  fitted.mesh.positions = control;
  report.seconds = seconds_since(start);
  report.foot_points = std::move(feet);
  if (report_out) *report_out = std::move(report);
  return fitted;
}

CAGEKIT_NAMESPACE_END
