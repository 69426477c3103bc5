// SPDX-License-Identifier: GPL-3.0-or-later
// The scan-to-cage journey: cagekit_scan_to_cage, the C shim over pipeline/scan_to_cage.h.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "capi/api_guard.h"
#include "capi/option_conversion.h"
#include "pipeline/scan_to_cage.h"

using namespace cagekit_capi;

namespace {

cagekit_scan_method method_to_c(cagekit::ScanMethod m) {
  switch (m) {
    case cagekit::ScanMethod::simplify: return CAGEKIT_SCAN_SIMPLIFY;
    case cagekit::ScanMethod::quad: return CAGEKIT_SCAN_QUAD;
    case cagekit::ScanMethod::anisotropic: return CAGEKIT_SCAN_ANISOTROPIC;
  }
  return CAGEKIT_SCAN_SIMPLIFY;
}

cagekit_scan_to_cage_report report_to_c(const cagekit::ScanToCageResult& r, uint32_t limit_levels) {
  cagekit_scan_to_cage_report c{};
  c.struct_size = sizeof(c);
  const cagekit::ConditioningReport& k = r.conditioning;
  c.input_vertices = k.input_vertices;
  c.input_faces = k.input_faces;
  c.conditioned_vertices = k.vertices;
  c.conditioned_faces = k.faces;
  c.welded_vertices = k.repair.welded_vertices;
  c.dropped_degenerate_faces = k.repair.dropped_degenerate_faces;
  c.dropped_duplicate_faces = k.repair.dropped_duplicate_faces;
  c.split_vertices = k.repair.split_vertices;
  c.flipped_faces = k.repair.flipped_faces;
  c.non_orientable_components = k.repair.non_orientable_components;
  c.removed_unreferenced_vertices = k.repair.removed_unreferenced_vertices;
  c.components = k.components;
  c.dropped_components = k.dropped_components;
  c.dropped_component_faces = k.dropped_component_faces;
  c.requested_method = method_to_c(r.requested);
  c.used_method = method_to_c(r.used);
  c.fallback = r.fallback ? 1 : 0;
  c.input_is_cage = r.input_is_cage ? 1 : 0;
  std::strncpy(c.fallback_reason, r.fallback_reason.c_str(), sizeof(c.fallback_reason) - 1);
  c.level = static_cast<uint32_t>(r.level);
  c.level_count = static_cast<uint32_t>(r.level_count);
  c.level_faces = r.level_faces;
  c.level_faces_with_holes = r.level_faces_with_holes;
  const cagekit::PolygonMesh& m = r.cage.mesh;
  c.cage_vertices = m.num_vertices();
  c.cage_faces = m.num_faces();
  for (size_t f = 0; f < m.num_faces(); ++f) {
    c.cage_quads += m.face_size(f) == 4;
    c.cage_triangles += m.face_size(f) == 3;
  }
  c.creases = r.cage.creases.size();
  c.remesh_regions = r.remesh_regions;
  c.remesh_lines = r.remesh_lines;
  c.remesh_holes = r.remesh_holes;
  c.interior_vertices = r.remesh.interior_vertices;
  c.valence4_vertices = r.remesh.valence4_vertices;
  c.max_face_valence = r.remesh.max_face_valence;
  c.max_vertex_valence = r.remesh.max_vertex_valence;
  c.mean_alignment_deg = r.mean_alignment_deg;
  c.method_scan_to_cage_max_rel = r.method_error.hausdorff_rel;
  c.method_cage_to_scan_max_rel = r.method_error.reverse_rel;
  c.method_mean_rel = r.method_error.mean_rel;
  c.input_boundary_loops = r.input_boundary_loops;
  c.cage_boundary_loops = r.cage_boundary_loops;
  c.holes_added = r.holes_added;
  const cagekit::FitReport& fit = r.fit;
  c.fit_pass_count = static_cast<uint32_t>(fit.passes.size());
  c.fit_best_pass = static_cast<uint32_t>(fit.best_pass);
  if (!fit.passes.empty()) {
    c.fit_initial = fit_pass_to_c(fit.passes.front());
    c.fit_final = fit_pass_to_c(fit.passes[fit.best_pass]);
    c.fit_initial_two_sided = fit_two_sided_to_c(fit.passes.front());
    c.fit_final_two_sided = fit_two_sided_to_c(fit.passes[fit.best_pass]);
  }
  c.unsupported_control_vertices = fit.unsupported_control_vertices;
  c.weakly_supported_control_vertices = fit.weakly_supported_control_vertices;
  c.limit_levels = limit_levels;
  c.limit_faces = r.limit.mesh.num_faces();
  c.scan_to_limit_max_rel = r.limit_error.hausdorff_rel;
  c.limit_to_scan_max_rel = r.limit_error.reverse_rel;
  c.limit_mean_rel = r.limit_error.mean_rel;
  c.self_intersections = r.self_intersections.pairs;
  c.self_intersection_triangles = r.self_intersections.triangles;
  c.method_seconds = r.method_seconds;
  c.fit_seconds = r.fit_seconds;
  c.seconds = r.seconds;
  c.simplify_target_used = double(r.target_used);
  c.scan_self_intersections = r.scan_self_intersections.pairs;
  c.unfitted_self_intersections = r.unfitted_self_intersections.pairs;
  c.scan_self_intersections_counted = r.scan_self_intersections_counted ? 1 : 0;
  c.own_cage_crease_angle_deg = r.input_is_cage ? r.own_cage_crease_angle_used : 0.0;
  c.fit_fairing_used = r.fit_fairing_used;
  c.two_sided_refit = r.two_sided_refit ? 1 : 0;
  c.one_sided_fit_max_rel = r.one_sided_fit_max_rel;
  c.sharp_edges = r.host_sharp_edges.found;
  c.sharp_edges_dropped = r.host_sharp_edges.dropped;
  return c;
}

}  // namespace

extern "C" {

CAGEKIT_API cagekit_status cagekit_scan_to_cage(cagekit_mesh scan, const cagekit_scan_to_cage_options* options,
                                                cagekit_cage* cage_out, cagekit_cage* limit_out,
                                                cagekit_scan_to_cage_report* report, cagekit_fit_report* fit_report,
                                                uint32_t fit_pass_capacity, uint32_t* fit_pass_count_out,
                                                cagekit_fit_pass* fit_passes) {
  return guarded(context_of(scan), [&] {
    require_not_null(cage_out, "cage_out");
    *cage_out = nullptr;
    if (limit_out) *limit_out = nullptr;
    cagekit_mesh_t& m = checked(scan, "scan");
    const cagekit::ScanToCageOptions o = scan_to_cage_options_from_c(options, m.mesh.num_faces());
    check_fit_report(fit_report);
    // Every fit of the journey (remedies and refit included) has o.fit.max_passes.
    check_pass_array(o.fit.max_passes, fit_pass_capacity, fit_pass_count_out, fit_passes, "fit_pass", "fit_passes");
    if (report) {  // a bad struct_size fails before any work
      cagekit_scan_to_cage_report probe{};
      probe.struct_size = sizeof(probe);
      write_versioned(report, probe, "cagekit_scan_to_cage_report");
    }
    cagekit::ScanToCageResult r = cagekit::scan_to_cage(m.mesh, o, m.context->monitor());
    auto cage = std::make_unique<cagekit_cage_t>(m.context, std::move(r.cage));
    std::unique_ptr<cagekit_cage_t> limit;
    if (limit_out) limit = std::make_unique<cagekit_cage_t>(m.context, r.limit);
    r.cage = cage->cage;  // for the report's cage figures
    write_versioned(report, report_to_c(r, uint32_t(o.limit_levels)), "cagekit_scan_to_cage_report");
    write_fit_report(fit_report, r.fit);
    write_pass_array(r.fit, fit_pass_capacity, fit_pass_count_out, fit_passes, "fit_pass", "fit_passes");
    *cage_out = cage.release();
    if (limit_out) *limit_out = limit.release();
  });
}

}  // extern "C"
