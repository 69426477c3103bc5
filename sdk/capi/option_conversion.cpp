// SPDX-License-Identifier: GPL-3.0-or-later
// The C option structs -> the C++ options, each checked once, shared by every entry point that
// takes them (cagekit_cage_fit, cagekit_hierarchy_build_cage, cagekit_mesh_remesh,
// cagekit_scan_to_cage).
#include "capi/option_conversion.h"

#include <cmath>
#include <cstddef>
#include <string>

#include "capi/api_guard.h"

namespace cagekit_capi {

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

}  // namespace

cagekit_fit_pass fit_pass_to_c(const cagekit::FitPassStatistics& s) {
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

cagekit_fit_two_sided fit_two_sided_to_c(const cagekit::FitPassStatistics& s) {
  cagekit_fit_two_sided t{};
  t.surface_to_scan_max_rel = s.reverse_max_relative;
  t.surface_to_scan_rms_rel = s.reverse_rms_relative;
  t.two_sided_rms_rel = s.two_sided_rms_relative;
  return t;
}

cagekit::FitOptions fit_options_from_c(const cagekit_fit_options* options) {
  const cagekit_fit_options defaults = CAGEKIT_FIT_OPTIONS_INIT;
  const cagekit_fit_options o = read_versioned(options, defaults, "cagekit_fit_options");
  const double inf = HUGE_VAL;
  check_range(o.max_passes, 0, 100000, "max_passes");
  check_real(o.tolerance, 0.0, inf, false, "tolerance");
  check_real(o.fairing, 0.0, inf, false, "fairing");
  check_real(o.tangential_weight, 0.0, 1.0, false, "tangential_weight");
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
  check_real(o.weak_support_fraction, 0.0, inf, false, "weak_support_fraction");
  check_real(o.weak_fairing, 0.0, inf, false, "weak_fairing");
  f.max_passes = static_cast<int>(o.max_passes);
  f.tolerance = o.tolerance;
  f.fairing = o.fairing;
  f.tangential_weight = o.tangential_weight;
  f.keep_crease_vertices_on_samples = bool_from_c(o.keep_crease_vertices, "cagekit_fit_options.keep_crease_vertices");
  f.threads = static_cast<int>(o.threads);
  f.closest_point.max_steps = static_cast<int>(o.max_projection_steps);
  f.closest_point.epsilon = o.projection_epsilon;
  f.closest_point.seed_resolution = static_cast<int>(o.projection_seed_resolution);
  f.weak_support_fraction = o.weak_support_fraction;
  f.weak_fairing = o.weak_fairing;
  f.select_best_two_sided = bool_from_c(o.select_best_two_sided, "cagekit_fit_options.select_best_two_sided");
  check_real(o.reverse_sample_factor, 0.0, 100.0, false, "reverse_sample_factor");
  f.reverse_sample_factor = o.reverse_sample_factor;
  check_real(o.crease_feature_reach, 0.0, 1.0, false, "crease_feature_reach");
  f.crease_feature_reach = o.crease_feature_reach;
  return f;
}

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


void write_fit_report(cagekit_fit_report* report, const PassArray& passes, const cagekit::FitReport& fr) {
  if (!report) return;
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
  r.best_pass = static_cast<uint32_t>(fr.best_pass);
  r.weakly_supported_control_vertices = fr.weakly_supported_control_vertices;
  if (!fr.passes.empty()) {
    r.initial = fit_pass_to_c(fr.passes.front());
    r.final = fit_pass_to_c(fr.passes[fr.best_pass]);
    r.initial_two_sided = fit_two_sided_to_c(fr.passes.front());
    r.final_two_sided = fit_two_sided_to_c(fr.passes[fr.best_pass]);
  }
  const size_t n = std::min<size_t>(passes.capacity, fr.passes.size());
  for (size_t i = 0; i < n; ++i) passes.entries[i] = fit_pass_to_c(fr.passes[i]);
  write_versioned(report, r, "cagekit_fit_report");
}

cagekit::CageBuildOptions cage_options_from_c(const cagekit_cage_options* options) {
  const cagekit_cage_options defaults = CAGEKIT_CAGE_OPTIONS_INIT;
  const cagekit_cage_options o = read_versioned(options, defaults, "cagekit_cage_options");
  if (!std::isfinite(o.crease_angle_degrees)) fail(Status::invalid_argument, "crease_angle_degrees must be finite");
  if (!std::isfinite(o.input_crease_angle_degrees))
    fail(Status::invalid_argument, "cagekit_cage_options.input_crease_angle_degrees must be finite");
  if (o.exact_partition_limit < 3 || o.exact_partition_limit > 64)
    fail(Status::invalid_argument, "exact_partition_limit must be in 3..64");
  if (!(o.feature_angle_degrees >= 0.0 && o.feature_angle_degrees <= 180.0))
    fail(Status::invalid_argument, "cagekit_cage_options.feature_angle_degrees must be in [0, 180]");
  cagekit::CageBuildOptions bo;
  const int32_t rule = raw_enum(o.crease_rule);
  if (rule == CAGEKIT_CREASES_SHARP_INPUT)
    bo.crease_rule = cagekit::CreaseRule::sharp_input;
  else if (rule == CAGEKIT_CREASES_CLUSTER_ANGLE)
    bo.crease_rule = cagekit::CreaseRule::cluster_angle;
  else
    fail(Status::invalid_argument,
         "cagekit_cage_options.crease_rule (" + std::to_string(rule) + ") is not a cagekit_crease_rule");
  bo.features.angle_degrees = o.feature_angle_degrees;
  bo.crease_angle_degrees = o.crease_angle_degrees;
  bo.input_crease_angle_degrees = o.input_crease_angle_degrees;
  bo.tag_boundary_edges = bool_from_c(o.tag_boundary_edges, "cagekit_cage_options.tag_boundary_edges");
  bo.partition.exact_vertex_limit = static_cast<int>(o.exact_partition_limit);
  return bo;
}

void check_remesh_options(const cagekit_remesh_options& o) {
  if (std::isnan(o.feature_angle_degrees) || o.feature_angle_degrees > 180.0)
    fail(Status::invalid_argument, "feature_angle_degrees must be <= 180 (< 0: no feature lines)");
  if (o.max_face_valence < 3 || o.max_face_valence > 1000000)
    fail(Status::invalid_argument, "max_face_valence must be >= 3");
  if (o.threads > 1024) fail(Status::invalid_argument, "threads must be <= 1024");
}

cagekit::QuadRemeshOptions quad_options_from_c(const cagekit_remesh_options& o, uint64_t input_faces) {
  check_remesh_options(o);
  if (!(o.edge_length > 0.0) || !(o.edge_length <= 1.0))
    fail(Status::invalid_argument, "edge_length must be in (0, 1] (relative to the bounding-box diagonal)");
  if (o.regions > 1000000) fail(Status::invalid_argument, "regions must be <= 1000000 (0: by region_tolerance)");
  if (o.regions == 0 && (!(o.region_tolerance >= 0.0) || !std::isfinite(o.region_tolerance)))
    fail(Status::invalid_argument, "region_tolerance must be finite and >= 0");
  if (!(o.triangle_weight > 0.0) || !(o.pentagon_weight > 0.0) || !(o.t_joint_weight > 0.0) ||
      !std::isfinite(o.triangle_weight) || !std::isfinite(o.pentagon_weight) || !std::isfinite(o.t_joint_weight))
    fail(Status::invalid_argument, "triangle_weight, pentagon_weight and t_joint_weight must be positive and finite");
  if (o.refinement_passes > 16) fail(Status::invalid_argument, "refinement_passes must be <= 16");
  cagekit::QuadRemeshOptions qo;
  qo.regions = int(o.regions);
  qo.region_tolerance = o.region_tolerance;
  qo.edge_length = o.edge_length;
  qo.triangle_weight = o.triangle_weight;
  qo.pentagon_weight = o.pentagon_weight;
  qo.t_joint_weight = o.t_joint_weight;
  qo.sample_refinement_passes = int(o.refinement_passes);
  qo.crease_angle_degrees = o.feature_angle_degrees;
  qo.threads = int(o.threads);
  if (o.seed_face_count > 0) {
    if (!o.seed_faces) fail(Status::invalid_argument, "seed_faces is NULL with seed_face_count > 0");
    if (o.seed_face_count > input_faces)
      fail(Status::invalid_argument, "seed_face_count exceeds the mesh's face count");
    qo.seed_faces.assign(o.seed_faces, o.seed_faces + o.seed_face_count);
  }
  if (o.pinned_region_count > 0) {
    if (!o.pinned_region_offsets || !o.pinned_faces)
      fail(Status::invalid_argument, "pinned_region_offsets and pinned_faces must not be NULL with "
                                     "pinned_region_count > 0");
    if (o.pinned_region_count > input_faces)
      fail(Status::invalid_argument, "pinned_region_count exceeds the mesh's face count");
    if (o.pinned_region_offsets[0] != 0) fail(Status::invalid_argument, "pinned_region_offsets[0] must be 0");
    for (uint32_t k = 0; k < o.pinned_region_count; ++k) {
      const uint32_t begin = o.pinned_region_offsets[k], end = o.pinned_region_offsets[k + 1];
      if (end < begin || end > input_faces)
        fail(Status::invalid_argument, "pinned_region_offsets must be non-decreasing and cover at most the "
                                       "mesh's face count (region " + std::to_string(k) + ")");
      qo.pinned_regions.emplace_back(o.pinned_faces + begin, o.pinned_faces + end);
    }
  }
  return qo;
}

cagekit::AnisotropicRemeshOptions anisotropic_options_from_c(const cagekit_remesh_options& o) {
  check_remesh_options(o);
  if (!(o.tolerance > 0.0) || !(o.tolerance <= 1.0))
    fail(Status::invalid_argument, "tolerance must be in (0, 1] (relative to the bounding-box diagonal)");
  if (!(o.curvature_radius >= 0.0) || !(o.curvature_radius <= 1.0))
    fail(Status::invalid_argument, "curvature_radius must be in [0, 1]");
  cagekit::AnisotropicRemeshOptions ao;
  ao.tolerance = o.tolerance;
  ao.feature_angle_degrees = o.feature_angle_degrees;
  ao.max_face_valence = int(o.max_face_valence);
  ao.disk_radius_bbox = o.curvature_radius;
  ao.threads = int(o.threads);
  return ao;
}

}  // namespace cagekit_capi
