// SPDX-License-Identifier: GPL-3.0-or-later
#include "pipeline/scan_to_cage.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <set>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "core/edge_key.h"
#include "core/mesh_statistics.h"
#include "core/mesh_validation.h"
#include "core/status.h"
#include "layout/common/feature_edges.h"
#include "layout/common/sharp_input_features.h"
#include "subdiv/uniform_refinement.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

double surface_area(const PolygonMesh& mesh) {
  double area = 0;
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    Vec3 n;
    mesh.for_each_fan_triangle(f, [&](uint32_t a, uint32_t b, uint32_t c) {
      n += cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
    });
    area += 0.5 * norm(n);
  }
  return area;
}

// The faces the method would make, or 0 when it cannot be told before running it.
uint64_t expected_faces(const ScanToCageOptions& o, const PolygonMesh& mesh) {
  switch (o.method) {
    case ScanMethod::simplify: return o.target_is_vertices ? 0 : o.target;
    case ScanMethod::quad: {
      const double spacing = o.quad.edge_length * mesh.bounding_box().diagonal();
      const double by_area = spacing > 0 ? surface_area(mesh) / (spacing * spacing) : 0.0;
      return std::max<uint64_t>(uint64_t(std::max(o.quad.regions, 0)), uint64_t(std::min(by_area, 1e18)));
    }
    case ScanMethod::anisotropic: return 0;
  }
  return 0;
}

// Phase 2 for a tiny input: the conditioned mesh is its own cage, its feature edges (dihedral
// angle above `angle`, layout/feature_edges.h) tagged infinitely sharp.
// Angle 0 creases every edge: the limit surface then is the mesh itself (planar polygons).
Cage own_cage(const PolygonMesh& mesh, double angle_degrees) {
  Cage cage;
  cage.mesh = mesh;
  if (angle_degrees < 0) return cage;
  const std::vector<uint8_t> feature =
      angle_degrees > 0 ? detect_feature_edges(mesh, std::min(angle_degrees, 180.0)) : std::vector<uint8_t>();
  std::set<std::pair<uint32_t, uint32_t>> edges;
  for (size_t f = 0, corner = 0; f < mesh.num_faces(); ++f)
    for (uint32_t k = 0; k < mesh.face_size(f); ++k, ++corner)
      if (angle_degrees == 0 || feature[corner]) {
        const uint32_t a = mesh.face_vertex(f, k), b = mesh.face_vertex(f, (k + 1) % mesh.face_size(f));
        edges.insert({std::min(a, b), std::max(a, b)});
      }
  for (const auto& [a, b] : edges) cage.creases.push_back({a, b, kSharpnessInfinite});
  return cage;
}

// Phase 1b: the conditioned scan's sharp edges as the fit's feature lines (none when the fit's
// crease-feature rows are off or the scan has faces detect_sharp_features refuses).
std::shared_ptr<const std::vector<FeatureSegment>> sharp_feature_segments(const PolygonMesh& mesh,
                                                                          const ScanToCageOptions& o,
                                                                          const TaskMonitor& monitor) {
  auto segments = std::make_shared<std::vector<FeatureSegment>>();
  if (!(o.fit.crease_feature_reach > 0)) return segments;
  SharpFeatures features;
  try {
    features = detect_sharp_features(mesh, o.cage.features, monitor);
  } catch (const Error& e) {
    if (e.status() != Status::invalid_mesh) throw;
    monitor.log(LogLevel::info, std::string("scan_to_cage: no feature lines for the fit: ") + e.what());
    return segments;
  }
  monitor.report("sharp features", 0.9);
  *segments = feature_segments(mesh, features.edges);
  monitor.report("sharp features", 1.0);
  return segments;
}

// Phase 2: the initial cage by the method (fills the method's figures of `r`).
// The simplification hierarchy is built once per run and reused by every simplify attempt.
Cage initial_cage(const PolygonMesh& mesh, ScanMethod method, const ScanToCageOptions& o, ScanToCageResult& r,
                  std::unique_ptr<SimplificationHierarchy>& cached, const TaskMonitor& monitor) {
  switch (method) {
    case ScanMethod::simplify: {
      if (!cached) cached = std::make_unique<SimplificationHierarchy>(mesh, o.simplify, monitor);
      SimplificationHierarchy& hierarchy = *cached;
      r.level_count = hierarchy.num_levels();
      r.level = o.target_is_vertices ? hierarchy.level_for_vertex_count(o.target)
                                     : hierarchy.level_for_face_count(o.target);
      hierarchy.go_to_level(r.level);
      // Going to the level, extracting it and building the cage take seconds on a million-face
      // scan together: cancel points between them, and inside the cage build.
      monitor.report("level", 0.0);
      const PolygonalLevel level = hierarchy.extract();
      monitor.report("level", 1.0);
      r.level_faces = level.faces.size();
      r.level_faces_with_holes = 0;
      for (const auto& f : level.faces) r.level_faces_with_holes += f.loops.size() > 1;
      r.cage_report = {};
      Cage cage = build_quad_dominant_cage(hierarchy.input(), level, o.cage, &r.cage_report, monitor);
      monitor.report("cage", 1.0);
      r.creases = r.cage_report.creases;
      return cage;
    }
    case ScanMethod::quad: {
      QuadRemeshResult q = remesh_quad_dominant(mesh, o.quad, monitor);
      r.remesh = q;
      r.remesh_regions = q.regions;
      r.remesh_reseeded_regions = q.reseeded_regions;
      r.remesh_lines = q.arcs;
      r.creases = q.creases;
      return std::move(q.cage);
    }
    case ScanMethod::anisotropic: {
      AnisotropicRemeshResult a = remesh_anisotropic(mesh, o.anisotropic, monitor);
      if (a.cage.mesh.num_faces() == 0)
        fail(Status::invalid_mesh, "anisotropic remeshing produced no faces (no two lines intersect)");
      r.remesh = a;
      r.remesh_regions = a.regions;
      r.remesh_lines = a.lines;
      r.remesh_holes = a.holes;
      r.mean_alignment_deg = a.mean_alignment_deg;
      r.creases = a.creases;
      return std::move(a.cage);
    }
  }
  fail(Status::invalid_argument, "unknown method");
}

// Phase 3: "" when the cage is a valid manifold cage without holes the input did not have.
std::string check_cage(const Cage& cage, ScanToCageResult& r) {
  const ValidationReport v = validate_cage(cage, 1);
  if (!v.ok()) return "the cage is not valid: " + v.summary();
  const MeshStatistics s = compute_mesh_statistics(cage.mesh);
  if (!s.manifold) return "the cage is not manifold";
  r.cage_boundary_loops = s.boundary_loops;
  r.holes_added = s.boundary_loops > r.input_boundary_loops ? s.boundary_loops - r.input_boundary_loops : 0;
  if (r.holes_added > 0)
    return "the cage has " + std::to_string(r.holes_added) + " hole(s) the input does not have (" +
           std::to_string(s.boundary_loops) + " boundary loops, input " + std::to_string(r.input_boundary_loops) + ")";
  return "";
}

std::string percent(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.3g %%", 100 * x);
  return buffer;
}

// `must_beat`: a remedy's candidate is given up (before the costly distance measurement) unless
// its limit has fewer self-intersecting pairs than this.
constexpr uint64_t kNoBound = UINT64_MAX;
std::string evaluate(const ScanToCageOptions& o, ScanToCageResult& r, const TaskMonitor& monitor,
                     uint64_t must_beat = kNoBound);
std::string fit_and_judge(const ScanToCageOptions& o, ScanToCageResult& r, const TaskMonitor& monitor,
                          uint64_t must_beat = kNoBound);

// True when remedies apply: the limit has more self-intersecting pairs than the conditioned
// scan (counted once per run, on the first need; a scan too large for the memory budget counts
// as clean). A faithful surface inherits the scan's own.
bool self_intersects_beyond_scan(const ScanToCageOptions& o, ScanToCageResult& r, const TaskMonitor& monitor) {
  if (!o.remedy_self_intersections || r.self_intersections.pairs == 0) return false;
  if (!r.scan_self_intersections_counted) {
    try {
      r.scan_self_intersections = count_self_intersections(r.conditioned, &monitor, "scan self-intersections");
    } catch (const Error& e) {
      if (e.status() != Status::out_of_memory) throw;
      monitor.log(LogLevel::info, std::string("scan_to_cage: the scan's self-intersections not counted: ") + e.what());
      r.scan_self_intersections = {};
    }
    r.scan_self_intersections_counted = true;
  }
  return r.self_intersections.pairs > r.scan_self_intersections.pairs;
}

// The remedies stop once the limit has no more self-intersections than the scan.
bool inherited_only(const ScanToCageResult& r) {
  return r.self_intersections.pairs <= r.scan_self_intersections.pairs;
}

// Moves `from` into `to` keeping `to`'s conditioned scan (results are copied without the scan).
void take_result(ScanToCageResult& to, ScanToCageResult&& from) {
  PolygonMesh scan = std::move(to.conditioned);
  to = std::move(from);
  to.conditioned = std::move(scan);
}

// A copy of r without its conditioned scan.
ScanToCageResult copy_without_scan(ScanToCageResult& r) {
  PolygonMesh scan = std::move(r.conditioned);
  ScanToCageResult copy = r;
  r.conditioned = std::move(scan);
  return copy;
}

// The fairing weights a self-intersecting fit is tried again with (FitOptions::fairing): the
// fit's pull towards detail the cage is too coarse to follow folds the limit surface; fairing
// holds the control vertices near their neighbours' average.
constexpr double kRemedyFairing[] = {0.01, 0.1};

// r's initial cage fitted again with `fairing` and judged, into `candidate` (a copy of r without
// the scan; r keeps its conditioned scan). Returns fit_and_judge's problem ("" when good).
std::string refit_with_fairing(const ScanToCageOptions& o, ScanToCageResult& r, double fairing,
                               ScanToCageResult& candidate, const TaskMonitor& monitor, uint64_t must_beat = kNoBound) {
  ScanToCageOptions refit = o;
  refit.fit.fairing = fairing;
  candidate = copy_without_scan(r);
  candidate.conditioned = std::move(r.conditioned);
  const std::string problem = fit_and_judge(refit, candidate, monitor, must_beat);
  r.conditioned = std::move(candidate.conditioned);
  return problem;
}

// The last phase: r's initial cage fitted by two-sided least squares, kept when its limit is
// closer to the scan both ways, has no more self-intersecting pairs, and is good. Tried with r's
// fairing, then (while it self-intersects more) with the remedies' larger ones. "Closer" means the
// larger of the two one-sided maxima drops by at least 5 %: every control vertex moves, and a
// smaller gain is within what any refit changes (on pinion.off a 1.2 % gain slid the limit's
// crease curves along the surface, off the gear's sharp edges: crease precision 99.7 -> 67.6 %).
// A refit that fails (other than by cancellation) leaves r as it is: r is already good.
constexpr double kTwoSidedRefitGain = 0.95;

void refit_two_sided(const ScanToCageOptions& o, ScanToCageResult& r, const TaskMonitor& monitor) {
  if (!(o.two_sided_refit_factor > 0) || r.input_is_cage) return;
  const double before = std::max(r.limit_error.hausdorff_rel, r.limit_error.reverse_rel);
  if (!std::isfinite(before) || before <= 0) return;
  ScanToCageOptions two_sided = o;
  two_sided.fit.reverse_sample_factor = o.two_sided_refit_factor;
  std::vector<double> fairings = {r.fit_fairing_used};
  for (const double f : kRemedyFairing)
    if (f > r.fit_fairing_used) fairings.push_back(f);
  for (const double fairing : fairings) {
    ScanToCageResult candidate;
    std::string problem;
    try {
      problem = refit_with_fairing(two_sided, r, fairing, candidate, monitor, r.self_intersections.pairs + 1);
    } catch (const Error& e) {
      if (e.status() == Status::cancelled) throw;
      if (r.conditioned.num_faces() == 0) r.conditioned = std::move(candidate.conditioned);
      monitor.log(LogLevel::info, std::string("scan_to_cage: the two-sided refit failed (") + e.what() +
                                      "): the one-sided fit is kept");
      return;
    }
    const double after = std::max(candidate.limit_error.hausdorff_rel, candidate.limit_error.reverse_rel);
    if (problem.empty() && after < kTwoSidedRefitGain * before) {
      monitor.log(LogLevel::info, "scan_to_cage: two-sided refit (fairing " + std::to_string(fairing) +
                                      ") kept: limit <-> scan " + percent(after) + " instead of " +
                                      percent(before));
      const double one_sided_seconds = r.fit_seconds;
      take_result(r, std::move(candidate));
      r.fit_seconds += one_sided_seconds;
      r.fit_fairing_used = fairing;
      r.two_sided_refit = true;
      r.one_sided_fit_max_rel = before;
      return;
    }
    monitor.log(LogLevel::info, "scan_to_cage: the two-sided refit (fairing " + std::to_string(fairing) +
                                    ") is not kept (" +
                                    (problem.empty() ? "limit <-> scan " + percent(after) + ", before " + percent(before)
                                                     : problem) +
                                    ")");
    if (problem != "no fewer self-intersections") return;
  }
}

// A fitted limit that self-intersects more than the scan is fitted again with more fairing;
// the first good result with no more than the scan's, else the good one with the fewest, is kept.
void remedy_fit(const ScanToCageOptions& o, ScanToCageResult& r, const TaskMonitor& monitor) {
  for (const double fairing : kRemedyFairing) {
    if (fairing <= r.fit_fairing_used) continue;
    ScanToCageResult candidate;
    const std::string problem = refit_with_fairing(o, r, fairing, candidate, monitor, r.self_intersections.pairs);
    if (!problem.empty() || candidate.self_intersections.pairs >= r.self_intersections.pairs) continue;
    monitor.log(LogLevel::info, "scan_to_cage: fitted again with fairing " + std::to_string(fairing) + ": " +
                                    std::to_string(candidate.self_intersections.pairs) +
                                    " self-intersecting pairs instead of " +
                                    std::to_string(r.self_intersections.pairs));
    take_result(r, std::move(candidate));
    r.fit_fairing_used = fairing;
    if (inherited_only(r)) return;
  }
}

// A fitted limit that strays from the scan (a spike: control vertices the fit pulled far out,
// where few samples constrain them) is fitted again with more fairing; the first good result is
// kept. Returns "" when one was found, else the original problem.
std::string remedy_stray(const ScanToCageOptions& o, ScanToCageResult& r, const std::string& problem,
                         const TaskMonitor& monitor) {
  for (const double fairing : kRemedyFairing) {
    if (fairing <= r.fit_fairing_used) continue;
    ScanToCageResult candidate;
    const std::string why = refit_with_fairing(o, r, fairing, candidate, monitor);
    if (!why.empty()) continue;
    monitor.log(LogLevel::info, "scan_to_cage: fitted again with fairing " + std::to_string(fairing) + ": " + problem +
                                    " before, good now");
    take_result(r, std::move(candidate));
    r.fit_fairing_used = fairing;
    return "";
  }
  return problem;
}

// A tiny input as its own cage whose limit self-intersects more than the scan: creased at 20
// degrees, then on every edge (the limit is then the input's own planar polygons); the good
// result with the fewest self-intersections is kept.
void remedy_own_cage(const ScanToCageOptions& o, ScanToCageResult& r, const TaskMonitor& monitor) {
  for (const double angle : {20.0, 0.0}) {
    if (o.own_cage_crease_angle_degrees >= 0 && angle >= o.own_cage_crease_angle_degrees) continue;
    ScanToCageResult candidate = copy_without_scan(r);
    candidate.conditioned = std::move(r.conditioned);
    candidate.initial_cage = own_cage(candidate.conditioned, angle);
    candidate.creases = candidate.initial_cage.creases.size();
    candidate.own_cage_crease_angle_used = angle;
    const std::string problem = evaluate(o, candidate, monitor, r.self_intersections.pairs);
    r.conditioned = std::move(candidate.conditioned);
    if (!problem.empty() || candidate.self_intersections.pairs >= r.self_intersections.pairs) continue;
    monitor.log(LogLevel::info, "scan_to_cage: own cage creased " +
                                    (angle > 0 ? "at " + std::to_string(int(angle)) + " degrees" : "on every edge") +
                                    ": " + std::to_string(candidate.self_intersections.pairs) +
                                    " self-intersecting pairs instead of " +
                                    std::to_string(r.self_intersections.pairs));
    take_result(r, std::move(candidate));
    if (inherited_only(r)) return;
  }
}

// Phases 2-6 for one method. Returns "" when the result is good, else why not (the result's
// figures are filled as far as they got).
std::string attempt(ScanMethod method, const ScanToCageOptions& o, ScanToCageResult& r,
                    std::unique_ptr<SimplificationHierarchy>& hierarchy, const TaskMonitor& monitor) {
  const PolygonMesh& mesh = r.conditioned;
  r.used = method;
  const auto t0 = Clock::now();
  ScanToCageOptions effective = o;
  effective.method = method;
  const uint64_t expected = expected_faces(effective, mesh);
  r.input_is_cage = expected > 0 && mesh.num_faces() <= expected;
  if (r.input_is_cage) {
    monitor.log(LogLevel::info, "scan_to_cage: the input has " + std::to_string(mesh.num_faces()) +
                                    " faces, no more than " + scan_method_name(method) + " would make (" +
                                    std::to_string(expected) + "): it is its own cage");
    r.initial_cage = own_cage(mesh, o.own_cage_crease_angle_degrees);
    r.creases = r.initial_cage.creases.size();
    r.own_cage_crease_angle_used = o.own_cage_crease_angle_degrees;
    r.level_faces = mesh.num_faces();  // the input is the "level"
  } else {
    r.initial_cage = initial_cage(mesh, method, o, r, hierarchy, monitor);
    if (method == ScanMethod::anisotropic && r.initial_cage.mesh.num_faces() >= mesh.num_faces() &&
        mesh.num_faces() < o.small_input_faces) {
      monitor.log(LogLevel::info, "scan_to_cage: anisotropic remeshing made more faces than the input has: the input "
                                  "is its own cage");
      r.initial_cage = own_cage(mesh, o.own_cage_crease_angle_degrees);
      r.creases = r.initial_cage.creases.size();
      r.own_cage_crease_angle_used = o.own_cage_crease_angle_degrees;
      r.input_is_cage = true;
    }
  }
  r.method_seconds = seconds_since(t0);
  r.fit_fairing_used = o.fit.fairing;
  std::string problem = evaluate(o, r, monitor);
  if (!r.input_is_cage && problem.find("strays") != std::string::npos) problem = remedy_stray(o, r, problem, monitor);
  if (problem.empty() && self_intersects_beyond_scan(o, r, monitor)) remedy_fit(o, r, monitor);
  if (problem.empty() && r.input_is_cage && self_intersects_beyond_scan(o, r, monitor))
    remedy_own_cage(o, r, monitor);
  return problem;
}

// Phases 3-6 on r.initial_cage. Returns "" when the result is good, else why not (the result's
// figures are filled as far as they got).
std::string evaluate(const ScanToCageOptions& o, ScanToCageResult& r, const TaskMonitor& monitor,
                     uint64_t must_beat) {
  const PolygonMesh& mesh = r.conditioned;
  const std::string cage_problem = check_cage(r.initial_cage, r);
  if (!cage_problem.empty()) return cage_problem;
  r.method_error = measure_approximation_error(mesh, r.initial_cage.mesh, 4, monitor, o.fit.threads);
  return fit_and_judge(o, r, monitor, must_beat);
}

// Phases 4-6 on r.initial_cage (checked by phase 3).
std::string fit_and_judge(const ScanToCageOptions& o, ScanToCageResult& r, const TaskMonitor& monitor,
                          uint64_t must_beat) {
  const PolygonMesh& mesh = r.conditioned;
  const auto t1 = Clock::now();
  r.fit = {};
  r.cage = fit_cage_to_mesh(r.initial_cage, mesh, o.fit, &r.fit, monitor, r.sharp_features.get());
  r.fit_seconds = seconds_since(t1);
  // The fit moves every control vertex: faces can collapse or fold onto each other. Then its
  // initial state (pass 0, the method's cage) is the result, judged like any other.
  const ValidationReport fitted = validate_cage(r.cage, 1);
  if (!fitted.ok()) {
    monitor.log(LogLevel::warning, "scan_to_cage: the fitted cage is not valid (" + fitted.summary() +
                                       "): the unfitted cage is kept");
    r.cage = r.initial_cage;
    r.fit.best_pass = 0;
  }

  RefineOptions refine;
  refine.levels = o.limit_levels;
  refine.limit_positions = true;
  r.limit = refine_uniform(r.cage, refine, monitor);
  r.self_intersections = r.unfitted_self_intersections = {};
  if (o.self_intersection_level > 0) {
    refine.levels = o.self_intersection_level;
    const Cage level = o.self_intersection_level == o.limit_levels ? r.limit : refine_uniform(r.cage, refine, monitor);
    r.self_intersections = count_self_intersections(level.mesh, &monitor, "limit self-intersections");
    if (r.self_intersections.pairs >= must_beat) return "no fewer self-intersections";
    if (r.self_intersections.pairs > 0)
      r.unfitted_self_intersections = count_self_intersections(refine_uniform(r.initial_cage, refine, monitor).mesh,
                                                               &monitor, "limit self-intersections");
  }
  r.limit_error = measure_approximation_error(mesh, r.limit.mesh, 4, monitor, o.fit.threads);

  // Phase 6: the good-result rule.
  const double scan_to_limit = r.limit_error.hausdorff_rel, limit_to_scan = r.limit_error.reverse_rel;
  if (!std::isfinite(scan_to_limit) || !std::isfinite(limit_to_scan))
    return "the limit surface's distance to the scan is not finite";
  const double bound = std::max(o.max_limit_to_scan, o.limit_to_scan_factor * scan_to_limit);
  if (mesh.num_faces() >= o.small_input_faces && limit_to_scan > bound)
    return "the limit surface strays " + percent(limit_to_scan) + " of the diagonal from the scan (bound " +
           percent(bound) + "; scan -> limit " + percent(scan_to_limit) + ")";
  return "";
}

// Simplify at the target, and while the limit surface strays from the scan, at 2x and 4x the
// target (a coarse cage of a detailed part cannot follow it; a finer level of the same hierarchy
// can): the first good one is returned and r.target_used says which.
std::string attempt_simplify(const ScanToCageOptions& o, ScanToCageResult& r,
                             std::unique_ptr<SimplificationHierarchy>& hierarchy, const TaskMonitor& monitor) {
  ScanToCageOptions s = o;
  s.method = ScanMethod::simplify;
  std::string problem;
  // The good result with the fewest self-intersections so far (when the first good one has some).
  std::unique_ptr<ScanToCageResult> best;
  for (int k = 0; k <= o.finer_simplify_attempts; ++k) {
    r.target_used = s.target;
    problem = attempt(ScanMethod::simplify, s, r, hierarchy, monitor);
    if (problem.empty()) {
      if (r.input_is_cage || !self_intersects_beyond_scan(o, r, monitor)) {
        best.reset();
        break;
      }
      if (!best || r.self_intersections.pairs < best->self_intersections.pairs)
        best = std::make_unique<ScanToCageResult>(copy_without_scan(r));
      problem = "the limit surface has " + std::to_string(r.self_intersections.pairs) +
                " self-intersecting triangle pairs (the scan " +
                std::to_string(r.scan_self_intersections.pairs) + ")";
    } else if (r.input_is_cage || problem.find("strays") == std::string::npos) {
      break;
    }
    const uint64_t size = s.target_is_vertices ? r.conditioned.num_vertices() : r.conditioned.num_faces();
    if (k == o.finer_simplify_attempts || 2 * s.target >= size) break;
    monitor.log(LogLevel::info, "scan_to_cage: simplify at " + std::to_string(s.target) + ": " + problem +
                                    "; trying " + std::to_string(2 * s.target));
    s.target *= 2;
  }
  if (best) {
    // No finer attempt was free of self-intersections: the good one with the fewest.
    const bool carried = r.scan_self_intersections_counted;
    const SelfIntersections scan = r.scan_self_intersections;
    take_result(r, std::move(*best));
    r.scan_self_intersections_counted = carried;
    r.scan_self_intersections = scan;
    monitor.log(LogLevel::warning, "scan_to_cage: the limit surface keeps " +
                                       std::to_string(r.self_intersections.pairs) +
                                       " self-intersecting triangle pairs (simplify at " +
                                       std::to_string(r.target_used) + ", the fewest of the finer attempts)");
    return "";
  }
  return problem;
}

}  // namespace

const char* scan_method_name(ScanMethod method) {
  switch (method) {
    case ScanMethod::simplify: return "simplify";
    case ScanMethod::quad: return "quad";
    case ScanMethod::anisotropic: return "anisotropic";
  }
  return "unknown";
}

namespace {

// Phase 1c: the host's sharp edges (input vertex pairs) on the conditioned scan, found by their
// ends' positions, given to every method.
ScanToCageOptions with_sharp_edges(const ScanToCageOptions& options, const PolygonMesh& scan, ScanToCageResult& r) {
  ScanToCageOptions o = options;
  if (options.sharp_edges.empty()) return o;
  const PolygonMesh& mesh = r.conditioned;
  struct PositionHash {
    size_t operator()(const Vec3& p) const {
      return std::hash<double>()(p.x) ^ (std::hash<double>()(p.y) * 31) ^ (std::hash<double>()(p.z) * 1031);
    }
  };
  struct PositionEqual {
    bool operator()(const Vec3& a, const Vec3& b) const { return a.x == b.x && a.y == b.y && a.z == b.z; }
  };
  std::unordered_map<Vec3, uint32_t, PositionHash, PositionEqual> vertex_at;
  for (uint32_t v = 0; v < mesh.num_vertices(); ++v) vertex_at.emplace(mesh.positions[v], v);
  std::unordered_set<uint64_t> edges;
  for (size_t f = 0; f < mesh.num_faces(); ++f)
    for (uint32_t k = 0; k < mesh.face_size(f); ++k)
      edges.insert(edge_key(mesh.face_vertex(f, k), mesh.face_vertex(f, (k + 1) % mesh.face_size(f))));
  std::vector<uint64_t> mapped;
  for (const uint64_t key : options.sharp_edges) {
    const uint32_t a = edge_key_first(key), b = edge_key_second(key);
    if (a >= scan.num_vertices() || b >= scan.num_vertices())
      fail(Status::invalid_argument, "scan_to_cage: sharp edge (" + std::to_string(a) + ", " + std::to_string(b) +
                                         ") names a vertex the scan does not have");
    const auto ia = vertex_at.find(scan.positions[a]), ib = vertex_at.find(scan.positions[b]);
    if (ia == vertex_at.end() || ib == vertex_at.end() || ia->second == ib->second ||
        !edges.count(edge_key(ia->second, ib->second))) {
      ++r.host_sharp_edges.dropped;
      continue;
    }
    mapped.push_back(edge_key(ia->second, ib->second));
  }
  std::sort(mapped.begin(), mapped.end());
  mapped.erase(std::unique(mapped.begin(), mapped.end()), mapped.end());
  r.host_sharp_edges.found = mapped.size();
  o.simplify.locked_edges = mapped;
  o.cage.features.host_edges = mapped;
  o.quad.sharp_edges = mapped;
  o.anisotropic.sharp_edges = mapped;
  return o;
}

}  // namespace

ScanToCageResult scan_to_cage(const PolygonMesh& scan, const ScanToCageOptions& given, const TaskMonitor& monitor) {
  const auto start = Clock::now();
  if (given.limit_levels < 1 || given.limit_levels > kMaxUniformLevels)
    fail(Status::invalid_argument, "scan_to_cage: limit_levels must be in 1.." + std::to_string(kMaxUniformLevels));
  if (given.self_intersection_level < 0 || given.self_intersection_level > kMaxUniformLevels)
    fail(Status::invalid_argument,
         "scan_to_cage: self_intersection_level must be in 0.." + std::to_string(kMaxUniformLevels));
  if (!(given.max_limit_to_scan > 0) || !std::isfinite(given.max_limit_to_scan) ||
      !(given.limit_to_scan_factor > 0) || !std::isfinite(given.limit_to_scan_factor))
    fail(Status::invalid_argument, "scan_to_cage: max_limit_to_scan and limit_to_scan_factor must be finite and > 0");
  if (given.method == ScanMethod::simplify && given.target == 0)
    fail(Status::invalid_argument, "scan_to_cage: the simplification target must be at least 1");

  ScanToCageResult r;
  r.requested = given.method;
  // Phase 1.
  r.conditioned = condition_input(scan, given.conditioning, &r.conditioning, monitor);
  // Each step between the phases reports, so a cancel on a large scan takes effect between them.
  monitor.report("statistics", 0.0);
  r.input_boundary_loops = compute_mesh_statistics(r.conditioned, monitor).boundary_loops;
  monitor.report("sharp features", 0.0);
  const ScanToCageOptions with_host_edges = with_sharp_edges(given, scan, r);
  const ScanToCageOptions& options = with_host_edges;
  r.sharp_features = sharp_feature_segments(r.conditioned, options, monitor);

  std::string problem;
  std::unique_ptr<SimplificationHierarchy> hierarchy;
  try {
    problem = options.method == ScanMethod::simplify ? attempt_simplify(options, r, hierarchy, monitor)
                                                     : attempt(options.method, options, r, hierarchy, monitor);
  } catch (const Error& e) {
    // Cancellation and memory limits are never replaced by another method (the options were
    // checked before: an invalid_argument from inside a remesher is one of its failures).
    if (e.status() == Status::cancelled || e.status() == Status::out_of_memory ||
        e.status() == Status::limit_exceeded || options.method == ScanMethod::simplify ||
        !options.fallback_to_simplify)
      throw;
    problem = std::string("failed: ") + e.what();
  }
  if (!problem.empty() && options.method != ScanMethod::simplify && options.fallback_to_simplify) {
    r.fallback = true;
    r.fallback_reason = std::string(scan_method_name(options.method)) + ": " + problem;
    monitor.log(LogLevel::warning, "scan_to_cage: " + r.fallback_reason + "; falling back to simplify (" +
                                       std::to_string(options.target) + " faces)");
    ScanToCageResult fresh;
    fresh.conditioned = std::move(r.conditioned);
    fresh.conditioning = r.conditioning;
    fresh.requested = r.requested;
    fresh.fallback = true;
    fresh.fallback_reason = r.fallback_reason;
    fresh.input_boundary_loops = r.input_boundary_loops;
    fresh.host_sharp_edges = r.host_sharp_edges;
    fresh.sharp_features = r.sharp_features;
    r = std::move(fresh);
    ScanToCageOptions simplify = options;
    simplify.method = ScanMethod::simplify;
    simplify.target_is_vertices = false;
    problem = attempt_simplify(simplify, r, hierarchy, monitor);
    if (!problem.empty()) problem = "simplify (fallback after " + r.fallback_reason + "): " + problem;
  } else if (!problem.empty()) {
    problem = std::string(scan_method_name(options.method)) + ": " + problem;
  }
  if (!problem.empty()) fail(Status::quality, "no good cage: " + problem);
  refit_two_sided(options, r, monitor);
  r.seconds = seconds_since(start);
  return r;
}

CAGEKIT_NAMESPACE_END
