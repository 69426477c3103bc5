// SPDX-License-Identifier: GPL-3.0-or-later
// Fitting a cage's limit surface to a scan (thesis ch. 7): cagekit_cage_fit.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "capi/api_guard.h"
#include "fit/surface_fitter.h"

using namespace cagekit_capi;

namespace {

void check_range(uint32_t value, uint32_t min, uint32_t max, const char* name) {
  if (value < min || value > max)
    fail(Status::invalid_argument, std::string("cagekit_fit_options.") + name + " must be in " + std::to_string(min) +
                                       ".." + std::to_string(max) + ", not " + std::to_string(value));
}

void check_real(double value, double min, double max, bool min_exclusive, const char* name) {
  const bool ok = std::isfinite(value) && (min_exclusive ? value > min : value >= min) && value <= max;
  if (!ok) {
    std::string range = std::isinf(max) ? std::string(min_exclusive ? "> " : ">= ") + std::to_string(min)
                                        : "in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
    fail(Status::invalid_argument,
         std::string("cagekit_fit_options.") + name + " must be finite and " + range + ", not " + std::to_string(value));
  }
}

cagekit::FitOptions convert_options(const cagekit_fit_options& o) {
  const double inf = HUGE_VAL;
  check_range(o.max_passes, 0, 100000, "max_passes");
  check_real(o.tolerance, 0.0, inf, false, "tolerance");
  check_real(o.fairing, 0.0, inf, false, "fairing");
  check_real(o.tangential_weight, 0.0, 1.0, false, "tangential_weight");
  if (o.keep_crease_vertices != 0 && o.keep_crease_vertices != 1)
    fail(Status::invalid_argument,
         "cagekit_fit_options.keep_crease_vertices must be 0 or 1, not " + std::to_string(o.keep_crease_vertices));
  cagekit::FitOptions f;
  const int32_t projection = raw_enum(o.projection), solver = raw_enum(o.solver);
  if (projection == CAGEKIT_PROJECTION_EXACT)
    f.projection = cagekit::ProjectionMode::exact;
  else if (projection == CAGEKIT_PROJECTION_PIECEWISE_LINEAR)
    f.projection = cagekit::ProjectionMode::piecewise_linear;
  else
    fail(Status::invalid_argument, "cagekit_fit_options.projection (" + std::to_string(projection) +
                                       ") is not a cagekit_projection_mode");
  if (solver == CAGEKIT_LSQ_DIRECT)
    f.solver = cagekit::LeastSquaresSolver::direct;
  else if (solver == CAGEKIT_LSQ_CGLS)
    f.solver = cagekit::LeastSquaresSolver::cgls;
  else
    fail(Status::invalid_argument,
         "cagekit_fit_options.solver (" + std::to_string(solver) + ") is not a cagekit_lsq_solver");
  check_range(o.threads, 0, 1024, "threads");
  check_range(o.max_projection_steps, 0, 100000, "max_projection_steps");
  check_real(o.projection_epsilon, 0.0, inf, true, "projection_epsilon");
  check_range(o.projection_seed_resolution, 1, 64, "projection_seed_resolution");
  f.max_passes = static_cast<int>(o.max_passes);
  f.tolerance = o.tolerance;
  f.fairing = o.fairing;
  f.tangential_weight = o.tangential_weight;
  f.keep_crease_vertices_on_samples = o.keep_crease_vertices != 0;
  f.threads = static_cast<int>(o.threads);
  f.closest_point.max_steps = static_cast<int>(o.max_projection_steps);
  f.closest_point.epsilon = o.projection_epsilon;
  f.closest_point.seed_resolution = static_cast<int>(o.projection_seed_resolution);
  return f;
}

cagekit_fit_pass convert_pass(const cagekit::FitPassStatistics& s) {
  cagekit_fit_pass p{};
  p.l2 = s.l2;
  p.rms_rel = s.rms_relative;
  p.max_rel = s.max_relative;
  p.mean_rel = s.mean_relative;
  p.max_rel_interior = s.max_relative_interior;
  p.seconds = s.seconds;
  p.unconverged_projections = s.unconverged_projections;
  p.mean_projection_steps = s.mean_projection_steps;
  return p;
}

// The caller's pass array (an input inside the output struct), read before the fit so that a
// bad struct_size fails before any work.
struct PassArray {
  uint32_t capacity = 0;
  cagekit_fit_pass* entries = nullptr;
};

PassArray read_pass_array(const cagekit_fit_report* report) {
  PassArray a;
  if (report == nullptr) return a;
  const size_t size = report->struct_size;
  if (size < sizeof(size_t) || size > (1u << 16))
    fail(Status::invalid_argument, "cagekit_fit_report.struct_size is " + std::to_string(size) +
                                       "; set it to sizeof(cagekit_fit_report)");
  if (size >= offsetof(cagekit_fit_report, passes) + sizeof(report->passes)) {
    a.capacity = report->pass_capacity;
    a.entries = report->passes;
    if (a.capacity > 0 && a.entries == nullptr)
      fail(Status::invalid_argument, "cagekit_fit_report.passes is NULL but pass_capacity is " +
                                         std::to_string(a.capacity));
  }
  return a;
}

}  // namespace

extern "C" {

CAGEKIT_API cagekit_status cagekit_cage_fit(cagekit_cage cage, cagekit_mesh scan, const cagekit_fit_options* options,
                                            cagekit_cage* out, cagekit_fit_report* report) {
  return guarded(context_of(cage), [&] {
    require_not_null(out, "out");
    *out = nullptr;
    cagekit_cage_t& c = checked(cage, "cage");
    const cagekit_mesh_t& s = checked(scan, "scan");
    const cagekit_fit_options defaults = CAGEKIT_FIT_OPTIONS_INIT;
    const cagekit::FitOptions fit_options = convert_options(read_versioned(options, defaults, "cagekit_fit_options"));
    const PassArray passes = read_pass_array(report);
    if (s.mesh.num_vertices() == 0) fail(Status::invalid_argument, "scan has no vertices");

    cagekit::FitReport fr;
    cagekit::Cage fitted = cagekit::fit_cage_to_mesh(c.cage, s.mesh, fit_options, &fr, c.context->monitor());
    auto handle = std::make_unique<cagekit_cage_t>(c.context, std::move(fitted));
    if (report) {
      cagekit_fit_report r{};
      r.struct_size = sizeof(r);
      r.pass_count = static_cast<uint32_t>(fr.passes.size());
      r.pass_capacity = passes.capacity;
      r.passes = passes.entries;
      r.stopped_by_tolerance = fr.stopped_by_tolerance ? 1 : 0;
      r.rejected_last_step = fr.rejected_last_step ? 1 : 0;
      r.fairing_used = fr.fairing_used ? 1 : 0;
      r.unsupported_control_vertices = fr.unsupported_control_vertices;
      r.bbox_diagonal = fr.bbox_diagonal;
      r.seconds = fr.seconds;
      if (!fr.passes.empty()) {
        r.initial = convert_pass(fr.passes.front());
        r.final = convert_pass(fr.passes.back());
      }
      const size_t n = std::min<size_t>(passes.capacity, fr.passes.size());
      for (size_t i = 0; i < n; ++i) passes.entries[i] = convert_pass(fr.passes[i]);
      write_versioned(report, r, "cagekit_fit_report");
    }
    *out = handle.release();
  });
}

}  // extern "C"
