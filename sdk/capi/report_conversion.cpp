// SPDX-License-Identifier: GPL-3.0-or-later
// The C++ results -> the C report structs: one table per struct, X(A, C field, expression of the
// C++ result `r`), expanded by CAGEKIT_REPORT_TO_C (versioned structs: struct_size set) or
// CAGEKIT_RECORD_TO_C (the fixed records inside them) into the conversion function.
#include "capi/report_conversion.h"

#include <cstring>

namespace cagekit_capi {

namespace {

#define CAGEKIT_COPY_ROW(A, field, expression) c.field = expression;
#define CAGEKIT_RECORD_TO_C(function, c_struct, cpp_type, table) \
  c_struct function(const cpp_type& r) {                         \
    c_struct c{};                                                \
    table(CAGEKIT_COPY_ROW, _)                                   \
    return c;                                                    \
  }
#define CAGEKIT_REPORT_TO_C(function, c_struct, cpp_type, table) \
  c_struct function(const cpp_type& r) {                         \
    c_struct c{};                                                \
    c.struct_size = sizeof(c);                                   \
    table(CAGEKIT_COPY_ROW, _)                                   \
    return c;                                                    \
  }

uint32_t u32(size_t value) { return static_cast<uint32_t>(value); }
cagekit_bool32 bool32(bool value) { return value ? CAGEKIT_TRUE : CAGEKIT_FALSE; }

uint64_t faces_of_size(const cagekit::PolygonMesh& m, uint32_t size) {
  uint64_t n = 0;
  for (size_t f = 0; f < m.num_faces(); ++f) n += m.face_size(f) == size;
  return n;
}

cagekit_scan_method method_to_c(cagekit::ScanMethod m) {
  switch (m) {
    case cagekit::ScanMethod::simplify: return CAGEKIT_SCAN_SIMPLIFY;
    case cagekit::ScanMethod::quad: return CAGEKIT_SCAN_QUAD;
    case cagekit::ScanMethod::anisotropic: return CAGEKIT_SCAN_ANISOTROPIC;
  }
  return CAGEKIT_SCAN_SIMPLIFY;
}

// The state a fit returned (its best pass) and its first, as records; zero when nothing was measured.
cagekit_fit_pass first_pass(const cagekit::FitReport& r) { return r.passes.empty() ? cagekit_fit_pass{} : fit_pass_to_c(r.passes.front()); }
cagekit_fit_pass best_pass(const cagekit::FitReport& r) { return r.passes.empty() ? cagekit_fit_pass{} : fit_pass_to_c(r.passes[r.best_pass]); }
cagekit_fit_two_sided first_two_sided(const cagekit::FitReport& r) {
  return r.passes.empty() ? cagekit_fit_two_sided{} : fit_two_sided_to_c(r.passes.front());
}
cagekit_fit_two_sided best_two_sided(const cagekit::FitReport& r) {
  return r.passes.empty() ? cagekit_fit_two_sided{} : fit_two_sided_to_c(r.passes[r.best_pass]);
}

}  // namespace

#define CAGEKIT_FIT_PASS_TABLE(X, A)                                                                  \
  X(A, l2, r.l2)                                                                                      \
  X(A, rms_rel, r.rms_relative)                                                                       \
  X(A, max_rel, r.max_relative)                                                                       \
  X(A, mean_rel, r.mean_relative)                                                                     \
  X(A, max_rel_interior, r.max_relative_interior)                                                     \
  X(A, seconds, r.seconds)                                                                            \
  X(A, unconverged_projections, r.unconverged_projections)                                            \
  X(A, mean_projection_steps, r.mean_projection_steps)
CAGEKIT_RECORD_TO_C(fit_pass_to_c, cagekit_fit_pass, cagekit::FitPassStatistics, CAGEKIT_FIT_PASS_TABLE)

#define CAGEKIT_FIT_TWO_SIDED_TABLE(X, A)                                                             \
  X(A, surface_to_scan_max_rel, r.reverse_max_relative)                                               \
  X(A, surface_to_scan_rms_rel, r.reverse_rms_relative)                                               \
  X(A, two_sided_rms_rel, r.two_sided_rms_relative)
CAGEKIT_RECORD_TO_C(fit_two_sided_to_c, cagekit_fit_two_sided, cagekit::FitPassStatistics, CAGEKIT_FIT_TWO_SIDED_TABLE)

// The patch's fields but its control points, which limit_patch_to_c copies as 48 doubles.
#define CAGEKIT_LIMIT_PATCH_TABLE(X, A)                                                               \
  X(A, ptex_face, r.ptex_face)                                                                        \
  X(A, cage_face, r.cage_face)                                                                        \
  X(A, u0, r.u0)                                                                                      \
  X(A, v0, r.v0)                                                                                      \
  X(A, u1, r.u1)                                                                                      \
  X(A, v1, r.v1)                                                                                      \
  X(A, exact, bool32(r.exact))                                                                        \
  X(A, error, r.error)
namespace {
CAGEKIT_RECORD_TO_C(limit_patch_fields, cagekit_limit_patch, cagekit::LimitPatch, CAGEKIT_LIMIT_PATCH_TABLE)
}  // namespace

cagekit_limit_patch limit_patch_to_c(const cagekit::LimitPatch& r) {
  cagekit_limit_patch c = limit_patch_fields(r);
  for (int i = 0; i < 16; ++i) {
    c.control_points[3 * i] = r.points[i].x;
    c.control_points[3 * i + 1] = r.points[i].y;
    c.control_points[3 * i + 2] = r.points[i].z;
  }
  return c;
}

#define CAGEKIT_FIT_REPORT_TABLE(X, A)                                                                \
  X(A, pass_count, u32(r.passes.size()))                                                              \
  X(A, stopped_by_tolerance, bool32(r.stopped_by_tolerance))                                          \
  X(A, rejected_last_step, bool32(r.rejected_last_step))                                              \
  X(A, fairing_used, bool32(r.fairing_used))                                                          \
  X(A, unsupported_control_vertices, r.unsupported_control_vertices)                                  \
  X(A, bbox_diagonal, r.bbox_diagonal)                                                                \
  X(A, seconds, r.seconds)                                                                            \
  X(A, best_pass, u32(r.best_pass))                                                                   \
  X(A, weakly_supported_control_vertices, r.weakly_supported_control_vertices)                        \
  X(A, initial, first_pass(r))                                                                        \
  X(A, final, best_pass(r))                                                                           \
  X(A, initial_two_sided, first_two_sided(r))                                                         \
  X(A, final_two_sided, best_two_sided(r))
CAGEKIT_REPORT_TO_C(fit_report_to_c, cagekit_fit_report, cagekit::FitReport, CAGEKIT_FIT_REPORT_TABLE)

#define CAGEKIT_REPAIR_REPORT_TABLE(X, A)                                                             \
  X(A, welded_vertices, r.welded_vertices)                                                            \
  X(A, dropped_invalid_faces, r.dropped_invalid_faces)                                                \
  X(A, dropped_degenerate_faces, r.dropped_degenerate_faces)                                          \
  X(A, dropped_duplicate_faces, r.dropped_duplicate_faces)                                            \
  X(A, split_vertices, r.split_vertices)                                                              \
  X(A, flipped_faces, r.flipped_faces)                                                                \
  X(A, removed_unreferenced_vertices, r.removed_unreferenced_vertices)                                \
  X(A, removed_non_finite_vertices, r.removed_non_finite_vertices)                                    \
  X(A, non_orientable_components, r.non_orientable_components)
CAGEKIT_REPORT_TO_C(repair_report_to_c, cagekit_repair_report, cagekit::RepairReport, CAGEKIT_REPAIR_REPORT_TABLE)

#define CAGEKIT_MESH_INFO_TABLE(X, A)                                                                 \
  X(A, vertices, r.vertices)                                                                          \
  X(A, faces, r.faces)                                                                                \
  X(A, edges, r.edges)                                                                                \
  X(A, triangles, r.triangles)                                                                        \
  X(A, quads, r.quads)                                                                                \
  X(A, other_polygons, r.other_polygons)                                                              \
  X(A, boundary_edges, r.boundary_edges)                                                              \
  X(A, boundary_loops, r.boundary_loops)                                                              \
  X(A, components, r.components)                                                                      \
  X(A, unreferenced_vertices, r.unreferenced_vertices)                                                \
  X(A, genus, r.genus)                                                                                \
  X(A, manifold, bool32(r.manifold))                                                                  \
  X(A, bbox_min[0], r.bbox.empty ? 0.0 : r.bbox.min[0])                                               \
  X(A, bbox_min[1], r.bbox.empty ? 0.0 : r.bbox.min[1])                                               \
  X(A, bbox_min[2], r.bbox.empty ? 0.0 : r.bbox.min[2])                                               \
  X(A, bbox_max[0], r.bbox.empty ? 0.0 : r.bbox.max[0])                                               \
  X(A, bbox_max[1], r.bbox.empty ? 0.0 : r.bbox.max[1])                                               \
  X(A, bbox_max[2], r.bbox.empty ? 0.0 : r.bbox.max[2])                                               \
  X(A, bbox_diagonal, r.bbox_diagonal)                                                                \
  X(A, creases, r.creases)                                                                            \
  X(A, corners, r.corners)                                                                            \
  X(A, holes, r.holes)                                                                                \
  X(A, invalid_faces, r.invalid_faces)
CAGEKIT_REPORT_TO_C(mesh_info_to_c, cagekit_mesh_info, cagekit::MeshStatistics, CAGEKIT_MESH_INFO_TABLE)

#define CAGEKIT_CAGE_REPORT_TABLE(X, A)                                                               \
  X(A, quads, r.quads)                                                                                \
  X(A, triangles, r.triangles)                                                                        \
  X(A, pentagons, r.pentagons)                                                                        \
  X(A, other_polygons, r.other)                                                                       \
  X(A, creases, r.creases)                                                                            \
  X(A, non_optimal_faces, r.non_optimal_faces)                                                        \
  X(A, non_manifold_edges, r.non_manifold_edges)                                                      \
  X(A, diagonals_flipped, r.diagonals_flipped)                                                        \
  X(A, cells_merged, r.cells_merged)
CAGEKIT_REPORT_TO_C(cage_report_to_c, cagekit_cage_report, cagekit::CageBuildReport, CAGEKIT_CAGE_REPORT_TABLE)

#define CAGEKIT_REMESH_QUALITY_TABLE(X, A)                                                            \
  X(A, faces, r.faces)                                                                                \
  X(A, vertices, r.vertices)                                                                          \
  X(A, quads, r.quads)                                                                                \
  X(A, interior_vertices, r.interior_vertices)                                                        \
  X(A, valence4_vertices, r.valence4_vertices)                                                        \
  X(A, max_face_valence, r.max_face_valence)                                                          \
  X(A, max_vertex_valence, r.max_vertex_valence)                                                      \
  X(A, min_scaled_jacobian, r.min_scaled_jacobian)
namespace {
CAGEKIT_RECORD_TO_C(remesh_quality_figures, cagekit_remesh_quality, cagekit::RemeshQuality, CAGEKIT_REMESH_QUALITY_TABLE)

// The quality figures of a remesher's result, with its own crease count and time.
template <class Result>
cagekit_remesh_quality remesh_quality_of(const Result& r) {
  cagekit_remesh_quality c = remesh_quality_figures(r);
  c.creases = r.creases;
  c.seconds = r.seconds;
  return c;
}
}  // namespace

#define CAGEKIT_ANISOTROPIC_REPORT_TABLE(X, A)                                                        \
  X(A, quality, remesh_quality_of(r))                                                                 \
  X(A, regions, r.regions)                                                                            \
  X(A, lines, r.lines)                                                                                \
  X(A, holes, r.holes)                                                                                \
  X(A, mean_alignment_deg, r.mean_alignment_deg)
CAGEKIT_REPORT_TO_C(anisotropic_report_to_c, cagekit_anisotropic_report, cagekit::AnisotropicRemeshResult,
                    CAGEKIT_ANISOTROPIC_REPORT_TABLE)

#define CAGEKIT_QUAD_REPORT_TABLE(X, A)                                                               \
  X(A, quality, remesh_quality_of(r))                                                                 \
  X(A, regions, r.regions)                                                                            \
  X(A, arcs, r.arcs)                                                                                  \
  X(A, requested_regions, r.requested_regions)                                                        \
  X(A, split_regions, r.split_regions)                                                                \
  X(A, merged_regions, r.merged_regions)                                                              \
  X(A, layout_retries, r.layout_retries)                                                              \
  X(A, mended_faces, r.mended_faces)                                                                  \
  X(A, partitioned_regions, r.partitioned_regions)                                                    \
  X(A, reseeded_regions, r.reseeded_regions)
CAGEKIT_REPORT_TO_C(quad_report_to_c, cagekit_quad_remesh_report, cagekit::QuadRemeshResult, CAGEKIT_QUAD_REPORT_TABLE)

// The scan-to-cage report; `L` is limit_levels (the options', not the result's).
#define CAGEKIT_SCAN_TO_CAGE_REPORT_TABLE(X, A)                                                       \
  X(A, input_vertices, r.conditioning.input_vertices)                                                 \
  X(A, input_faces, r.conditioning.input_faces)                                                       \
  X(A, conditioned_vertices, r.conditioning.vertices)                                                 \
  X(A, conditioned_faces, r.conditioning.faces)                                                       \
  X(A, welded_vertices, r.conditioning.repair.welded_vertices)                                        \
  X(A, dropped_degenerate_faces, r.conditioning.repair.dropped_degenerate_faces)                      \
  X(A, dropped_duplicate_faces, r.conditioning.repair.dropped_duplicate_faces)                        \
  X(A, split_vertices, r.conditioning.repair.split_vertices)                                          \
  X(A, flipped_faces, r.conditioning.repair.flipped_faces)                                            \
  X(A, non_orientable_components, r.conditioning.repair.non_orientable_components)                    \
  X(A, removed_unreferenced_vertices, r.conditioning.repair.removed_unreferenced_vertices)            \
  X(A, components, r.conditioning.components)                                                         \
  X(A, dropped_components, r.conditioning.dropped_components)                                         \
  X(A, dropped_component_faces, r.conditioning.dropped_component_faces)                               \
  X(A, requested_method, method_to_c(r.requested))                                                    \
  X(A, used_method, method_to_c(r.used))                                                              \
  X(A, fallback, bool32(r.fallback))                                                                  \
  X(A, input_is_cage, bool32(r.input_is_cage))                                                        \
  X(A, level, u32(r.level))                                                                           \
  X(A, level_count, u32(r.level_count))                                                               \
  X(A, level_faces, r.level_faces)                                                                    \
  X(A, level_faces_with_holes, r.level_faces_with_holes)                                              \
  X(A, cage_vertices, r.cage.mesh.num_vertices())                                                     \
  X(A, cage_faces, r.cage.mesh.num_faces())                                                           \
  X(A, cage_quads, faces_of_size(r.cage.mesh, 4))                                                     \
  X(A, cage_triangles, faces_of_size(r.cage.mesh, 3))                                                 \
  X(A, creases, r.cage.creases.size())                                                                \
  X(A, remesh_regions, r.remesh_regions)                                                              \
  X(A, remesh_lines, r.remesh_lines)                                                                  \
  X(A, remesh_holes, r.remesh_holes)                                                                  \
  X(A, interior_vertices, r.remesh.interior_vertices)                                                 \
  X(A, valence4_vertices, r.remesh.valence4_vertices)                                                 \
  X(A, max_face_valence, r.remesh.max_face_valence)                                                   \
  X(A, max_vertex_valence, r.remesh.max_vertex_valence)                                               \
  X(A, mean_alignment_deg, r.mean_alignment_deg)                                                      \
  X(A, method_scan_to_cage_max_rel, r.method_error.hausdorff_rel)                                     \
  X(A, method_cage_to_scan_max_rel, r.method_error.reverse_rel)                                       \
  X(A, method_mean_rel, r.method_error.mean_rel)                                                      \
  X(A, input_boundary_loops, r.input_boundary_loops)                                                  \
  X(A, cage_boundary_loops, r.cage_boundary_loops)                                                    \
  X(A, holes_added, r.holes_added)                                                                    \
  X(A, fit_pass_count, u32(r.fit.passes.size()))                                                      \
  X(A, fit_best_pass, u32(r.fit.best_pass))                                                           \
  X(A, fit_initial, first_pass(r.fit))                                                                \
  X(A, fit_final, best_pass(r.fit))                                                                   \
  X(A, fit_initial_two_sided, first_two_sided(r.fit))                                                 \
  X(A, fit_final_two_sided, best_two_sided(r.fit))                                                    \
  X(A, unsupported_control_vertices, r.fit.unsupported_control_vertices)                              \
  X(A, weakly_supported_control_vertices, r.fit.weakly_supported_control_vertices)                    \
  X(A, limit_levels, L)                                                                               \
  X(A, limit_faces, r.limit.mesh.num_faces())                                                         \
  X(A, scan_to_limit_max_rel, r.limit_error.hausdorff_rel)                                            \
  X(A, limit_to_scan_max_rel, r.limit_error.reverse_rel)                                              \
  X(A, limit_mean_rel, r.limit_error.mean_rel)                                                        \
  X(A, self_intersections, r.self_intersections.pairs)                                                \
  X(A, self_intersection_triangles, r.self_intersections.triangles)                                   \
  X(A, method_seconds, r.method_seconds)                                                              \
  X(A, fit_seconds, r.fit_seconds)                                                                    \
  X(A, seconds, r.seconds)                                                                            \
  X(A, simplify_target_used, double(r.target_used))                                                   \
  X(A, scan_self_intersections, r.scan_self_intersections.pairs)                                      \
  X(A, unfitted_self_intersections, r.unfitted_self_intersections.pairs)                              \
  X(A, scan_self_intersections_counted, bool32(r.scan_self_intersections_counted))                    \
  X(A, own_cage_crease_angle_deg, r.input_is_cage ? r.own_cage_crease_angle_used : 0.0)               \
  X(A, fit_fairing_used, r.fit_fairing_used)                                                          \
  X(A, two_sided_refit, bool32(r.two_sided_refit))                                                    \
  X(A, one_sided_fit_max_rel, r.one_sided_fit_max_rel)                                                \
  X(A, sharp_edges, r.host_sharp_edges.found)                                                         \
  X(A, sharp_edges_dropped, r.host_sharp_edges.dropped)                                              \
  X(A, remesh_reseeded_regions, r.remesh_reseeded_regions)

cagekit_scan_to_cage_report scan_to_cage_report_to_c(const cagekit::ScanToCageResult& r, uint32_t L) {
  cagekit_scan_to_cage_report c{};
  c.struct_size = sizeof(c);
  CAGEKIT_SCAN_TO_CAGE_REPORT_TABLE(CAGEKIT_COPY_ROW, _)
  std::strncpy(c.fallback_reason, r.fallback_reason.c_str(), sizeof(c.fallback_reason) - 1);
  return c;
}

}  // namespace cagekit_capi
