// SPDX-License-Identifier: GPL-3.0-or-later
// The C option structs -> the C++ options, each checked once, shared by every entry point that
// takes them (cagekit_cage_fit, cagekit_hierarchy_build_cage, cagekit_mesh_remesh_anisotropic,
// cagekit_mesh_remesh_quad, cagekit_scan_to_cage). One table per struct drives its checks and
// conversion, and is checked against the header's *_INIT defaults at compile time.
#include "capi/option_conversion.h"

#include <cmath>
#include <cstddef>
#include <string>
#include <thread>

#include "capi/api_guard.h"
#include "capi/option_rules.h"
#include "capi/report_conversion.h"

namespace cagekit_capi {


// cagekit_fit_options: field, default (CAGEKIT_FIT_OPTIONS_INIT), rule, C++ destination in `f`.
#define CAGEKIT_FIT_OPTION_TABLE(X, A)                                                                   \
  X(A, max_passes, 5, (UintIn{0, 100000}), f.max_passes)                                                 \
  X(A, tolerance, 1e-4, at_least(0.0), f.tolerance)                                                      \
  X(A, fairing, 0.0, at_least(0.0), f.fairing)                                                           \
  X(A, tangential_weight, 1.0, closed_range(0.0, 1.0), f.tangential_weight)                              \
  X(A, keep_crease_vertices, 0, Boolean{}, f.keep_crease_vertices_on_samples)                            \
  X(A, projection, CAGEKIT_PROJECTION_EXACT, kProjectionModes, f.projection)                             \
  X(A, solver, CAGEKIT_LSQ_DIRECT, kSolvers, f.solver)                                                   \
  X(A, threads, 0, kThreads, f.threads)                                                         \
  X(A, max_projection_steps, 500, (UintIn{0, 100000}), f.closest_point.max_steps)                        \
  X(A, projection_epsilon, 1e-6, greater_than(0.0), f.closest_point.epsilon)                            \
  X(A, projection_seed_resolution, 4, (UintIn{1, 64}), f.closest_point.seed_resolution)                  \
  X(A, weak_support_fraction, 0.05, at_least(0.0), f.weak_support_fraction)                              \
  X(A, weak_fairing, 1.0, at_least(0.0), f.weak_fairing)                                                 \
  X(A, select_best_two_sided, 1, Boolean{}, f.select_best_two_sided)                                     \
  X(A, reverse_sample_factor, 0.0, closed_range(0.0, 100.0), f.reverse_sample_factor)                    \
  X(A, crease_feature_reach, 0.02, closed_range(0.0, 1.0), f.crease_feature_reach)

constexpr EnumRule<cagekit::ProjectionMode, 2> kProjectionModes{
    "cagekit_projection_mode",
    {{CAGEKIT_PROJECTION_EXACT, "CAGEKIT_PROJECTION_EXACT", cagekit::ProjectionMode::exact},
     {CAGEKIT_PROJECTION_PIECEWISE_LINEAR, "CAGEKIT_PROJECTION_PIECEWISE_LINEAR",
      cagekit::ProjectionMode::piecewise_linear}}};
constexpr EnumRule<cagekit::LeastSquaresSolver, 2> kSolvers{
    "cagekit_lsq_solver",
    {{CAGEKIT_LSQ_DIRECT, "CAGEKIT_LSQ_DIRECT", cagekit::LeastSquaresSolver::direct},
     {CAGEKIT_LSQ_CGLS, "CAGEKIT_LSQ_CGLS", cagekit::LeastSquaresSolver::cgls}}};

CAGEKIT_OPTIONS_FROM_C(fit_options_from_c, cagekit_fit_options, CAGEKIT_FIT_OPTIONS_INIT, CAGEKIT_FIT_OPTION_TABLE, cagekit::FitOptions, f, {})

void check_fit_report(const cagekit_fit_report* report) {
  if (report == nullptr) return;
  const size_t size = report->struct_size;
  if (size < sizeof(size_t) || size > (1u << 16))
    fail(Status::invalid_argument, "cagekit_fit_report.struct_size is " + std::to_string(size) +
                                       "; set it to sizeof(cagekit_fit_report)");
}

void check_pass_array(int max_passes, uint32_t capacity, uint32_t* count_out, const cagekit_fit_pass* passes,
                      const char* x, const char* name) {
  two_call_check(x, static_cast<uint32_t>(max_passes) + 1, capacity, count_out, {{name, passes}});
}

void write_pass_array(const cagekit::FitReport& fr, uint32_t capacity, uint32_t* count_out, cagekit_fit_pass* passes,
                      const char* x, const char* name) {
  if (two_call_check(x, static_cast<uint32_t>(fr.passes.size()), capacity, count_out, {{name, passes}}))
    for (size_t i = 0; i < fr.passes.size(); ++i) passes[i] = fit_pass_to_c(fr.passes[i]);
}

void write_fit_report(cagekit_fit_report* report, const cagekit::FitReport& fr) {
  if (report) write_versioned(report, fit_report_to_c(fr), "cagekit_fit_report");
}

// cagekit_cage_options: field, default (CAGEKIT_CAGE_OPTIONS_INIT), rule, C++ destination in `bo`.
#define CAGEKIT_CAGE_OPTION_TABLE(X, A)                                                               \
  X(A, crease_angle_degrees, 30.0, at_most(180.0), bo.crease_angle_degrees)                           \
  X(A, tag_boundary_edges, 1, Boolean{}, bo.tag_boundary_edges)                                       \
  X(A, exact_partition_limit, 20, (UintIn{3, 64}), bo.partition.exact_vertex_limit)                   \
  X(A, input_crease_angle_degrees, -1.0, at_most(180.0), bo.input_crease_angle_degrees)               \
  X(A, crease_rule, CAGEKIT_CREASES_SHARP_INPUT, kCreaseRules, bo.crease_rule)                        \
  X(A, feature_angle_degrees, 40.0, closed_range(0.0, 180.0), bo.features.angle_degrees)                \
  X(A, sharp_edges, NULL, ByHand{}, bo.features.host_edges)                                           \
  X(A, sharp_edge_count, 0, (SharpEdgePairs{o.sharp_edges}), bo.features.host_edges)

constexpr EnumRule<cagekit::CreaseRule, 2> kCreaseRules{
    "cagekit_crease_rule",
    {{CAGEKIT_CREASES_SHARP_INPUT, "CAGEKIT_CREASES_SHARP_INPUT", cagekit::CreaseRule::sharp_input},
     {CAGEKIT_CREASES_CLUSTER_ANGLE, "CAGEKIT_CREASES_CLUSTER_ANGLE", cagekit::CreaseRule::cluster_angle}}};

CAGEKIT_OPTIONS_FROM_C(cage_options_from_c, cagekit_cage_options, CAGEKIT_CAGE_OPTIONS_INIT, CAGEKIT_CAGE_OPTION_TABLE,
                       cagekit::CageBuildOptions, bo, {})

// cagekit_anisotropic_options: field, default (CAGEKIT_ANISOTROPIC_OPTIONS_INIT), rule, C++
// destination in `ao`.
#define CAGEKIT_ANISOTROPIC_OPTION_TABLE(X, A)                                                        \
  X(A, tolerance, 0.002, half_open_range(0.0, 1.0), ao.tolerance)                                     \
  X(A, feature_angle_degrees, 40.0, at_most(180.0), ao.feature_angle_degrees)                         \
  X(A, max_face_valence, 5, (UintIn{3, 1000000}), ao.max_face_valence)                                \
  X(A, threads, 0, kThreads, ao.threads)                                                     \
  X(A, curvature_radius, 0.01, closed_range(0.0, 1.0), ao.disk_radius_bbox)                          \
  X(A, sharp_edges, NULL, ByHand{}, ao.sharp_edges)                                                   \
  X(A, sharp_edge_count, 0, (SharpEdgePairs{o.sharp_edges}), ao.sharp_edges)

CAGEKIT_OPTIONS_FROM_C(anisotropic_options_from_c, cagekit_anisotropic_options, CAGEKIT_ANISOTROPIC_OPTIONS_INIT,
                       CAGEKIT_ANISOTROPIC_OPTION_TABLE, cagekit::AnisotropicRemeshOptions, ao, {})

// cagekit_quad_remesh_options: field, default (CAGEKIT_QUAD_REMESH_OPTIONS_INIT), rule, C++
// destination in `qo`; the seed and pinned-region arrays are checked after the table.
#define CAGEKIT_QUAD_REMESH_OPTION_TABLE(X, A)                                                        \
  X(A, edge_length, 0.05, half_open_range(0.0, 1.0), qo.edge_length)                                  \
  X(A, regions, 30, (UintIn{0, 1000000}), qo.regions)                                                 \
  X(A, region_tolerance, 0.01, at_least(0.0), qo.region_tolerance)                                    \
  X(A, crease_angle_degrees, 40.0, at_most(180.0), qo.crease_angle_degrees)                           \
  X(A, triangle_weight, 40.0, greater_than(0.0), qo.triangle_weight)                                  \
  X(A, pentagon_weight, 40.0, greater_than(0.0), qo.pentagon_weight)                                  \
  X(A, t_joint_weight, 100.0, greater_than(0.0), qo.t_joint_weight)                                   \
  X(A, refinement_passes, 1, (UintIn{0, 16}), qo.sample_refinement_passes)                            \
  X(A, threads, 0, kThreads, qo.threads)                                                     \
  X(A, seed_faces, NULL, ByHand{}, qo.seed_faces)                                                     \
  X(A, seed_face_count, 0, ByHand{}, qo.seed_faces)                                                   \
  X(A, pinned_region_count, 0, ByHand{}, qo.pinned_regions)                                           \
  X(A, pinned_region_offsets, NULL, ByHand{}, qo.pinned_regions)                                      \
  X(A, pinned_faces, NULL, ByHand{}, qo.pinned_regions)                                              \
  X(A, sharp_edges, NULL, ByHand{}, qo.sharp_edges)                                                   \
  X(A, sharp_edge_count, 0, (SharpEdgePairs{o.sharp_edges}), qo.sharp_edges)

CAGEKIT_OPTIONS_FROM_C(quad_options_by_table, cagekit_quad_remesh_options, CAGEKIT_QUAD_REMESH_OPTIONS_INIT,
                       CAGEKIT_QUAD_REMESH_OPTION_TABLE, cagekit::QuadRemeshOptions, qo, {})

cagekit::QuadRemeshOptions quad_options_from_c(const cagekit_quad_remesh_options* options, uint64_t input_faces) {
  cagekit::QuadRemeshOptions qo = quad_options_by_table(options);
  const cagekit_quad_remesh_options o = read_versioned(options, k_cagekit_quad_remesh_options_defaults,
                                                       "cagekit_quad_remesh_options");
  if (o.seed_face_count > 0) {
    if (!o.seed_faces)
      fail(Status::invalid_argument, "cagekit_quad_remesh_options.seed_faces must not be NULL with seed_face_count " +
                                         std::to_string(o.seed_face_count));
    if (o.seed_face_count > input_faces)
      fail(Status::invalid_argument, "cagekit_quad_remesh_options.seed_face_count must be at most the mesh's " +
                                         std::to_string(input_faces) + " faces, not " +
                                         std::to_string(o.seed_face_count));
    qo.seed_faces.assign(o.seed_faces, o.seed_faces + o.seed_face_count);
  }
  if (o.pinned_region_count > 0) {
    if (!o.pinned_region_offsets || !o.pinned_faces)
      fail(Status::invalid_argument, "cagekit_quad_remesh_options.pinned_region_offsets and pinned_faces must not "
                                     "be NULL with pinned_region_count " + std::to_string(o.pinned_region_count));
    if (o.pinned_region_count > input_faces)
      fail(Status::invalid_argument, "cagekit_quad_remesh_options.pinned_region_count must be at most the mesh's " +
                                         std::to_string(input_faces) + " faces, not " +
                                         std::to_string(o.pinned_region_count));
    if (o.pinned_region_offsets[0] != 0)
      fail(Status::invalid_argument, "cagekit_quad_remesh_options.pinned_region_offsets[0] must be 0, not " +
                                         std::to_string(o.pinned_region_offsets[0]));
    for (uint32_t k = 0; k < o.pinned_region_count; ++k) {
      const uint32_t begin = o.pinned_region_offsets[k], end = o.pinned_region_offsets[k + 1];
      if (end < begin || end > input_faces)
        fail(Status::invalid_argument, "cagekit_quad_remesh_options.pinned_region_offsets must be non-decreasing "
                                       "and at most the mesh's face count (region " + std::to_string(k) + ")");
      qo.pinned_regions.emplace_back(o.pinned_faces + begin, o.pinned_faces + end);
    }
  }
  return qo;
}

// cagekit_write_options: field, default (CAGEKIT_WRITE_OPTIONS_INIT), rule, C++ destination in `w`.
#define CAGEKIT_WRITE_OPTION_TABLE(X, A)                                                              \
  X(A, format, CAGEKIT_FORMAT_AUTO, kFileFormats, w.format)                                           \
  X(A, ply_binary, 1, Boolean{}, w.ply_binary)                                                        \
  X(A, draco_position_bits, 14, (UintIn{1, 30}), w.draco_position_bits)                               \
  X(A, draco_speed, 5, (UintIn{0, 10}), w.draco_speed)

constexpr EnumRule<cagekit::FileFormat, 6> kFileFormats{
    "cagekit_file_format",
    {{CAGEKIT_FORMAT_AUTO, "CAGEKIT_FORMAT_AUTO", cagekit::FileFormat::unknown},
     {CAGEKIT_FORMAT_OBJ, "CAGEKIT_FORMAT_OBJ", cagekit::FileFormat::obj},
     {CAGEKIT_FORMAT_PLY, "CAGEKIT_FORMAT_PLY", cagekit::FileFormat::ply},
     {CAGEKIT_FORMAT_OFF, "CAGEKIT_FORMAT_OFF", cagekit::FileFormat::off},
     {CAGEKIT_FORMAT_DRACO, "CAGEKIT_FORMAT_DRACO", cagekit::FileFormat::draco},
     {CAGEKIT_FORMAT_STL, "CAGEKIT_FORMAT_STL", cagekit::FileFormat::stl}}};

CAGEKIT_OPTIONS_FROM_C(write_options_from_c, cagekit_write_options, CAGEKIT_WRITE_OPTIONS_INIT, CAGEKIT_WRITE_OPTION_TABLE, cagekit::WriteOptions, w, {})

// cagekit_repair_options (CAGEKIT_REPAIR_OPTIONS_INIT) -> `ro`: the steps become its flags (WELD
// off: no welding, tolerance -1).
struct RepairSteps {
  FlagsIn flags;
};
void apply(const RepairSteps& rule, uint32_t steps, const char* name, cagekit::RepairOptions& ro) {
  apply(rule.flags, steps, name, steps);
  ro.drop_invalid_faces = steps & CAGEKIT_REPAIR_DROP_INVALID_FACES;
  ro.drop_degenerate_faces = steps & CAGEKIT_REPAIR_DROP_DEGENERATE_FACES;
  ro.drop_duplicate_faces = steps & CAGEKIT_REPAIR_DROP_DUPLICATE_FACES;
  ro.split_non_manifold = steps & CAGEKIT_REPAIR_SPLIT_NON_MANIFOLD;
  ro.orient_consistently = steps & CAGEKIT_REPAIR_ORIENT;
  ro.remove_unreferenced_vertices = steps & CAGEKIT_REPAIR_REMOVE_UNREFERENCED;
}

#define CAGEKIT_REPAIR_OPTION_TABLE(X, A)                                                             \
  X(A, steps, CAGEKIT_REPAIR_DEFAULT, (RepairSteps{{0x7f, "CAGEKIT_REPAIR_*"}}), ro)                  \
  X(A, weld_tolerance, 0.0, at_least(0.0), ro.weld_tolerance)

CAGEKIT_OPTIONS_FROM_C(repair_options_from_c, cagekit_repair_options, CAGEKIT_REPAIR_OPTIONS_INIT,
                       CAGEKIT_REPAIR_OPTION_TABLE, cagekit::RepairOptions, ro,
                       if (!(o.steps & CAGEKIT_REPAIR_WELD)) ro.weld_tolerance = -1.0;)

// cagekit_subdivide_options (CAGEKIT_SUBDIVIDE_OPTIONS_INIT) -> `ro`.
#define CAGEKIT_SUBDIVIDE_OPTION_TABLE(X, A)                                                          \
  X(A, levels, 1, (UintIn{0, CAGEKIT_MAX_SUBDIVISION_LEVELS}), ro.levels)                             \
  X(A, limit_positions, 0, Boolean{}, ro.limit_positions)

CAGEKIT_OPTIONS_FROM_C(subdivide_options_from_c, cagekit_subdivide_options, CAGEKIT_SUBDIVIDE_OPTIONS_INIT, CAGEKIT_SUBDIVIDE_OPTION_TABLE, cagekit::RefineOptions, ro, {})

// cagekit_surface_options (CAGEKIT_SURFACE_OPTIONS_INIT) -> `so`.
#define CAGEKIT_SURFACE_OPTION_TABLE(X, A)                                                            \
  X(A, isolation_level, 2, (UintIn{1, 10}), so.isolation_level)                                       \
  X(A, sharp_isolation_level, 10, (UintIn{1, 10}), so.sharp_extraordinary_isolation_level)

CAGEKIT_OPTIONS_FROM_C(surface_options_from_c, cagekit_surface_options, CAGEKIT_SURFACE_OPTIONS_INIT, CAGEKIT_SURFACE_OPTION_TABLE, cagekit::SurfaceOptions, so, {})

// cagekit_limit_patch_options (CAGEKIT_LIMIT_PATCH_OPTIONS_INIT) -> `lo`; threads 0 becomes the
// hardware's thread count after the table.
#define CAGEKIT_LIMIT_PATCH_OPTION_TABLE(X, A)                                                        \
  X(A, tolerance, 1e-4, greater_than(0.0), lo.tolerance)                                              \
  X(A, max_depth, 8, (UintIn{0, cagekit::kMaxLimitPatchDepth}), lo.max_depth)                         \
  X(A, threads, 0, kThreads, lo.threads)

CAGEKIT_OPTIONS_FROM_C(limit_patch_options_from_c, cagekit_limit_patch_options, CAGEKIT_LIMIT_PATCH_OPTIONS_INIT,
                       CAGEKIT_LIMIT_PATCH_OPTION_TABLE, cagekit::LimitPatchOptions, lo,
                       if (lo.threads == 0) lo.threads = int(std::max(1u, std::thread::hardware_concurrency()));)

// cagekit_limit_surface_options (CAGEKIT_LIMIT_SURFACE_OPTIONS_INIT) -> `lo`; min_level <= max_level
// after the table.
#define CAGEKIT_LIMIT_SURFACE_OPTION_TABLE(X, A)                                                      \
  X(A, tolerance, 1e-4, greater_than(0.0), lo.tolerance)                                              \
  X(A, max_level, 5, (UintIn{1, cagekit::kMaxLimitBSplineLevel}), lo.max_level)                       \
  X(A, min_level, 1, (UintIn{1, cagekit::kMaxLimitBSplineLevel}), lo.min_level)                       \
  X(A, max_normal_jump_deg, 0.5, greater_than(0.0), lo.max_normal_jump_deg)                         \
  X(A, threads, 0, kThreads, lo.threads)

CAGEKIT_OPTIONS_FROM_C(limit_surface_options_from_c, cagekit_limit_surface_options,
                       CAGEKIT_LIMIT_SURFACE_OPTIONS_INIT, CAGEKIT_LIMIT_SURFACE_OPTION_TABLE,
                       cagekit::LimitBSplineOptions, lo,
                       if (lo.min_level > lo.max_level) fail(Status::invalid_argument,
                           "cagekit_limit_surface_options.min_level must be at most max_level (" +
                           std::to_string(lo.max_level) + "), not " + std::to_string(lo.min_level));
                       if (lo.threads == 0) lo.threads = int(std::max(1u, std::thread::hardware_concurrency()));)

// cagekit_simplify_options (CAGEKIT_SIMPLIFY_OPTIONS_INIT) -> `so`.
#define CAGEKIT_SIMPLIFY_OPTION_TABLE(X, A)                                                           \
  X(A, tie_break_epsilon, 0.01, at_least(0.0), so.tie_break_epsilon)                                  \
  X(A, sharp_edges, NULL, ByHand{}, so.locked_edges)                                                  \
  X(A, sharp_edge_count, 0, (SharpEdgePairs{o.sharp_edges}), so.locked_edges)

CAGEKIT_OPTIONS_FROM_C(simplify_options_from_c, cagekit_simplify_options, CAGEKIT_SIMPLIFY_OPTIONS_INIT,
                       CAGEKIT_SIMPLIFY_OPTION_TABLE, cagekit::SimplifyOptions, so, {})

// cagekit_bind_options (CAGEKIT_BIND_OPTIONS_INIT) -> `bo`; a negative sharp angle is "off" (-1).
#define CAGEKIT_BIND_OPTION_TABLE(X, A)                                                               \
  X(A, mode, CAGEKIT_DISPLACEMENT_NORMAL, kDisplacementModes, bo.mode)                                \
  X(A, exact_normals, 0, Boolean{}, bo.exact_normals)                                                 \
  X(A, threads, 0, kThreads, bo.threads)                                                     \
  X(A, sharp_angle_degrees, -1.0, at_most(180.0), bo.sharp_angle_degrees)

constexpr EnumRule<cagekit::DisplacementMode, 2> kDisplacementModes{
    "cagekit_displacement_mode",
    {{CAGEKIT_DISPLACEMENT_NORMAL, "CAGEKIT_DISPLACEMENT_NORMAL", cagekit::DisplacementMode::normal},
     {CAGEKIT_DISPLACEMENT_LOCAL_FRAME, "CAGEKIT_DISPLACEMENT_LOCAL_FRAME", cagekit::DisplacementMode::local_frame}}};

CAGEKIT_OPTIONS_FROM_C(bind_options_from_c, cagekit_bind_options, CAGEKIT_BIND_OPTIONS_INIT, CAGEKIT_BIND_OPTION_TABLE,
                       cagekit::BindOptions, bo, if (bo.sharp_angle_degrees < 0) bo.sharp_angle_degrees = -1.0;)

// cagekit_gl_deformer_options (CAGEKIT_GL_DEFORMER_OPTIONS_INIT) -> `go`.
#define CAGEKIT_GL_DEFORMER_OPTION_TABLE(X, A) X(A, optimize_vertex_cache, 1, Boolean{}, go.optimize_vertex_cache)

CAGEKIT_OPTIONS_FROM_C(gl_deformer_options_from_c, cagekit_gl_deformer_options, CAGEKIT_GL_DEFORMER_OPTIONS_INIT, CAGEKIT_GL_DEFORMER_OPTION_TABLE, cagekit::GlDeformerOptions, go, {})

// cagekit_scan_to_cage_options: field, default (CAGEKIT_SCAN_TO_CAGE_OPTIONS_INIT), rule, C++
// destination in `s`; the nested option structs are converted after the table.
#define CAGEKIT_SCAN_TO_CAGE_OPTION_TABLE(X, A)                                                            \
  X(A, method, CAGEKIT_SCAN_SIMPLIFY, kScanMethods, s.method)                                              \
  X(A, repair, 1, Boolean{}, s.conditioning.repair)                                                        \
  X(A, components, CAGEKIT_COMPONENTS_ALL, kComponentModes, s.conditioning.components)                     \
  X(A, weld_tolerance_rel, 1e-7, at_least(0.0), s.conditioning.weld_tolerance_relative)                    \
  X(A, target_query, CAGEKIT_LEVEL_BY_FACES, kTargetQueries, s.target_is_vertices)                         \
  X(A, target, 60.0, closed_range(1.0, 1e12), s.target)                                                    \
  X(A, cage, NULL, ByHand{}, s.cage)                                                                       \
  X(A, quad, NULL, ByHand{}, s.quad)                                                                       \
  X(A, anisotropic, NULL, ByHand{}, s.anisotropic)                                                         \
  X(A, fit, NULL, ByHand{}, s.fit)                                                                         \
  X(A, limit_levels, 3, (UintIn{1, CAGEKIT_MAX_SUBDIVISION_LEVELS}), s.limit_levels)                       \
  X(A, self_intersection_level, 2, (UintIn{0, CAGEKIT_MAX_SUBDIVISION_LEVELS}), s.self_intersection_level) \
  X(A, max_limit_to_scan_rel, 0.05, greater_than(0.0), s.max_limit_to_scan)                                \
  X(A, limit_to_scan_factor, 3.0, greater_than(0.0), s.limit_to_scan_factor)                               \
  X(A, small_input_faces, 1000, (UintIn{0, UINT64_MAX}), s.small_input_faces)                              \
  X(A, fallback_to_simplify, 1, Boolean{}, s.fallback_to_simplify)                                         \
  X(A, finer_simplify_attempts, 2, (UintIn{0, 8}), s.finer_simplify_attempts)                              \
  X(A, two_sided_refit_factor, 3.0, closed_range(0.0, 100.0), s.two_sided_refit_factor)                \
  X(A, sharp_edges, NULL, ByHand{}, s.sharp_edges)                                                         \
  X(A, sharp_edge_count, 0, (SharpEdgePairs{o.sharp_edges}), s.sharp_edges)

constexpr EnumRule<cagekit::ScanMethod, 3> kScanMethods{
    "cagekit_scan_method",
    {{CAGEKIT_SCAN_SIMPLIFY, "CAGEKIT_SCAN_SIMPLIFY", cagekit::ScanMethod::simplify},
     {CAGEKIT_SCAN_QUAD, "CAGEKIT_SCAN_QUAD", cagekit::ScanMethod::quad},
     {CAGEKIT_SCAN_ANISOTROPIC, "CAGEKIT_SCAN_ANISOTROPIC", cagekit::ScanMethod::anisotropic}}};
constexpr EnumRule<cagekit::ComponentMode, 2> kComponentModes{
    "cagekit_component_mode",
    {{CAGEKIT_COMPONENTS_ALL, "CAGEKIT_COMPONENTS_ALL", cagekit::ComponentMode::all},
     {CAGEKIT_COMPONENTS_LARGEST, "CAGEKIT_COMPONENTS_LARGEST", cagekit::ComponentMode::largest}}};
// The level query decides whether `target` counts vertices.
constexpr EnumRule<bool, 2> kTargetQueries{"cagekit_level_query",
                                           {{CAGEKIT_LEVEL_BY_FACES, "CAGEKIT_LEVEL_BY_FACES", false},
                                            {CAGEKIT_LEVEL_BY_VERTICES, "CAGEKIT_LEVEL_BY_VERTICES", true}}};

CAGEKIT_OPTIONS_FROM_C(scan_to_cage_options_by_table, cagekit_scan_to_cage_options, CAGEKIT_SCAN_TO_CAGE_OPTIONS_INIT,
                       CAGEKIT_SCAN_TO_CAGE_OPTION_TABLE, cagekit::ScanToCageOptions, s, {})

cagekit::ScanToCageOptions scan_to_cage_options_from_c(const cagekit_scan_to_cage_options* options,
                                                       uint64_t input_faces) {
  cagekit::ScanToCageOptions s = scan_to_cage_options_by_table(options);
  const cagekit_scan_to_cage_options o = read_versioned(options, k_cagekit_scan_to_cage_options_defaults,
                                                        "cagekit_scan_to_cage_options");
  s.cage = cage_options_from_c(o.cage);
  if (s.method == cagekit::ScanMethod::quad) s.quad = quad_options_from_c(o.quad, input_faces);
  if (s.method == cagekit::ScanMethod::anisotropic) s.anisotropic = anisotropic_options_from_c(o.anisotropic);
  s.fit = fit_options_from_c(o.fit);
  if (!s.cage.features.host_edges.empty() || !s.quad.sharp_edges.empty() || !s.anisotropic.sharp_edges.empty())
    fail(Status::invalid_argument, "cagekit_scan_to_cage_options: give the sharp edges in its own sharp_edges (the "
                                   "scan's vertex pairs, found again after the conditioning), not in the nested "
                                   "cage, quad or anisotropic options");
  return s;
}

}  // namespace cagekit_capi
