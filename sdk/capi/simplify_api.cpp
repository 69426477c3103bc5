// SPDX-License-Identifier: GPL-3.0-or-later
// Structure-preserving simplification (thesis ch. 3): hierarchy handles, level browsing,
// polygonal faces, cluster maps, quad-dominant cages, approximation error.
#include <cmath>

#include "capi/api_guard.h"
#include "capi/option_conversion.h"
#include "capi/report_conversion.h"
#include "capi/mesh_conversion.h"
#include "layout/common/approximation_error.h"
#include "layout/simplify/cage_builder.h"
#include "layout/simplify/contour_refinement.h"

using namespace cagekit_capi;

namespace {

uint32_t checked_level(const cagekit_hierarchy_t& h, uint32_t level) {
  if (level >= h.hierarchy.num_levels())
    fail(Status::invalid_argument, "level " + std::to_string(level) + " is not below the level count " +
                                       std::to_string(h.hierarchy.num_levels()));
  return level;
}

}  // namespace

extern "C" {

CAGEKIT_API cagekit_status cagekit_hierarchy_create(cagekit_mesh mesh, const cagekit_simplify_options* options,
                                                    cagekit_hierarchy* out) {
  return create_from(mesh, "mesh", out, [&](cagekit_mesh_t& m) {
    const cagekit::SimplifyOptions so = simplify_options_from_c(options);
    cagekit::SimplificationHierarchy hierarchy(m.mesh, so, m.context->monitor());
    return std::make_unique<cagekit_hierarchy_t>(m.context, std::move(hierarchy), so.locked_edges);
  });
}

CAGEKIT_API void cagekit_hierarchy_retain(cagekit_hierarchy hierarchy) { retain_handle(hierarchy); }
CAGEKIT_API void cagekit_hierarchy_release(cagekit_hierarchy hierarchy) { release_handle(hierarchy); }

CAGEKIT_API cagekit_status cagekit_hierarchy_get_level_count(cagekit_hierarchy hierarchy, uint32_t* count) {
  return guarded(context_of(hierarchy), [&] {
    require_not_null(count, "count");
    *count = static_cast<uint32_t>(checked(hierarchy, "hierarchy").hierarchy.num_levels());
  });
}

CAGEKIT_API cagekit_status cagekit_hierarchy_get_level_info(cagekit_hierarchy hierarchy, uint32_t level,
                                                            cagekit_level_info* info) {
  return guarded(context_of(hierarchy), [&] {
    const cagekit_hierarchy_t& h = checked(hierarchy, "hierarchy");
    require_not_null(info, "info");
    checked_level(h, level);
    cagekit_level_info out{};
    out.struct_size = sizeof(out);
    out.faces = h.hierarchy.face_count(level);
    out.vertices = h.hierarchy.vertex_count(level);
    out.error = h.hierarchy.error(level);
    write_versioned(info, out, "cagekit_level_info");
  });
}

CAGEKIT_API cagekit_status cagekit_hierarchy_find_level(cagekit_hierarchy hierarchy, cagekit_level_query query,
                                                        double value, uint32_t* level) {
  return guarded(context_of(hierarchy), [&] {
    const cagekit_hierarchy_t& h = checked(hierarchy, "hierarchy");
    require_not_null(level, "level");
    if (!(value >= 0)) fail(Status::invalid_argument, "value must be >= 0 (and not NaN)");
    const double capped = std::min(value, 1.8e19);
    switch (raw_enum(query)) {
      case CAGEKIT_LEVEL_BY_FACES:
        *level = static_cast<uint32_t>(h.hierarchy.level_for_face_count(static_cast<uint64_t>(capped)));
        break;
      case CAGEKIT_LEVEL_BY_VERTICES:
        *level = static_cast<uint32_t>(h.hierarchy.level_for_vertex_count(static_cast<uint64_t>(capped)));
        break;
      case CAGEKIT_LEVEL_BY_ERROR:
        *level = static_cast<uint32_t>(h.hierarchy.level_for_error(value));
        break;
      default:
        fail(Status::invalid_argument, "query is not a cagekit_level_query");
    }
  });
}

CAGEKIT_API cagekit_status cagekit_hierarchy_set_level(cagekit_hierarchy hierarchy, uint32_t level) {
  return guarded(context_of(hierarchy), [&] {
    cagekit_hierarchy_t& h = checked(hierarchy, "hierarchy");
    checked_level(h, level);
    if (level == h.hierarchy.current_level()) return;
    h.hierarchy.go_to_level(level);
    h.level = h.hierarchy.extract();
  });
}

CAGEKIT_API cagekit_status cagekit_hierarchy_get_current_level(cagekit_hierarchy hierarchy, uint32_t* level) {
  return guarded(context_of(hierarchy), [&] {
    require_not_null(level, "level");
    *level = static_cast<uint32_t>(checked(hierarchy, "hierarchy").hierarchy.current_level());
  });
}

CAGEKIT_API cagekit_status cagekit_hierarchy_get_current_info(cagekit_hierarchy hierarchy,
                                                              cagekit_polygonal_level_info* info) {
  return guarded(context_of(hierarchy), [&] {
    const cagekit_hierarchy_t& h = checked(hierarchy, "hierarchy");
    require_not_null(info, "info");
    cagekit_polygonal_level_info out{};
    out.struct_size = sizeof(out);
    out.level = static_cast<uint32_t>(h.hierarchy.current_level());
    out.faces = h.level.faces.size();
    out.vertices = h.level.num_vertices;
    std::vector<uint32_t> point_to_input;
    for (const auto& f : h.level.faces) {
      out.faces_with_holes += f.loops.size() > 1;
      out.invalid_faces += !cagekit::check_polygon_loops(cagekit::project_face(h.hierarchy.input(), f, h.level.coordinates, &point_to_input)).ok();
    }
    out.l2_error = h.level.l2_error;
    out.l21_error = h.level.l21_error;
    write_versioned(info, out, "cagekit_polygonal_level_info");
  });
}

CAGEKIT_API cagekit_status cagekit_hierarchy_get_faces(cagekit_hierarchy hierarchy, uint32_t face_capacity,
                                                       uint32_t* face_count_out, uint32_t* loops_per_face,
                                                       uint32_t loop_capacity, uint32_t* loop_count_out,
                                                       uint32_t* loop_sizes, uint64_t index_capacity,
                                                       uint64_t* index_count_out, uint32_t* loop_vertices) {
  return guarded(context_of(hierarchy), [&] {
    const auto& faces = checked(hierarchy, "hierarchy").level.faces;
    uint32_t loops = 0;
    uint64_t indices = 0;
    for (const auto& f : faces) {
      loops += static_cast<uint32_t>(f.loops.size());
      for (const auto& l : f.loops) indices += l.size();
    }
    const auto face_count = static_cast<uint32_t>(faces.size());
    // Every count is reported before any capacity check fails.
    write_count("face", face_count, face_count_out);
    write_count("loop", loops, loop_count_out);
    write_count("index", indices, index_count_out);
    const bool fill_faces =
        two_call_check("face", face_count, face_capacity, face_count_out, {{"loops_per_face", loops_per_face}});
    const bool fill_loops = two_call_check("loop", loops, loop_capacity, loop_count_out, {{"loop_sizes", loop_sizes}});
    const bool fill_indices =
        two_call_check("index", indices, index_capacity, index_count_out, {{"loop_vertices", loop_vertices}});
    uint32_t l = 0;
    uint64_t i = 0;
    for (uint32_t f = 0; f < face_count; ++f) {
      if (fill_faces) loops_per_face[f] = static_cast<uint32_t>(faces[f].loops.size());
      for (const auto& loop : faces[f].loops) {
        if (fill_loops) loop_sizes[l] = static_cast<uint32_t>(loop.size());
        ++l;
        if (fill_indices) std::copy(loop.begin(), loop.end(), loop_vertices + i);
        i += loop.size();
      }
    }
  });
}

CAGEKIT_API cagekit_status cagekit_hierarchy_get_clusters(cagekit_hierarchy hierarchy, uint32_t input_face_capacity,
                                                          uint32_t* input_face_count_out,
                                                          uint32_t* cluster_of_input_face) {
  return guarded(context_of(hierarchy), [&] {
    const auto& clusters = checked(hierarchy, "hierarchy").level.cluster_of_input_face;
    if (two_call_check("input_face", static_cast<uint32_t>(clusters.size()), input_face_capacity,
                       input_face_count_out, {{"cluster_of_input_face", cluster_of_input_face}}))
      std::copy(clusters.begin(), clusters.end(), cluster_of_input_face);
  });
}

CAGEKIT_API cagekit_status cagekit_hierarchy_get_polygon_mesh(cagekit_hierarchy hierarchy, cagekit_mesh* out) {
  return create_from(hierarchy, "hierarchy", out, [&](const cagekit_hierarchy_t& h) {
    return make_mesh_handle(h.context, cagekit::polygonal_level_mesh(h.hierarchy.input(), h.level));
  });
}

CAGEKIT_API cagekit_status cagekit_hierarchy_get_refined_polygon_mesh(cagekit_hierarchy hierarchy,
                                                                      double chord_tolerance, cagekit_mesh* out) {
  return create_from(hierarchy, "hierarchy", out, [&](const cagekit_hierarchy_t& h) {
    if (!(chord_tolerance > 0) || !std::isfinite(chord_tolerance))
      fail(Status::invalid_argument, "chord_tolerance must be finite and > 0");
    const cagekit::PolygonMesh& input = h.hierarchy.input();
    const double diagonal = input.bounding_box().diagonal();
    const cagekit::PolygonalLevel refined =
        cagekit::refine_level_contours(input, h.level, chord_tolerance * (diagonal > 0 ? diagonal : 1.0));
    return make_mesh_handle(h.context, cagekit::polygonal_level_mesh(input, refined));
  });
}

CAGEKIT_API cagekit_status cagekit_hierarchy_build_cage(cagekit_hierarchy hierarchy, const cagekit_cage_options* options,
                                                        cagekit_cage* out, cagekit_cage_report* report) {
  return create_from(hierarchy, "hierarchy", out, [&](const cagekit_hierarchy_t& h) {
    cagekit::CageBuildOptions bo = cage_options_from_c(options);
    std::vector<uint64_t>& host = bo.features.host_edges;  // the hierarchy's and the options' own
    host.insert(host.end(), h.sharp_edges.begin(), h.sharp_edges.end());
    cagekit::CageBuildReport br;
    cagekit::Cage cage = cagekit::build_quad_dominant_cage(h.hierarchy.input(), h.level, bo, &br, h.context->monitor());
    if (report) {
      const cagekit_cage_report r = cage_report_to_c(br);
      write_versioned(report, r, "cagekit_cage_report");
    }
    return std::make_unique<cagekit_cage_t>(h.context, std::move(cage));
  });
}

CAGEKIT_API cagekit_status cagekit_mesh_measure_error(cagekit_mesh input, cagekit_mesh approximation,
                                                      cagekit_approximation_error* error) {
  return guarded(context_of(input), [&] {
    cagekit_mesh_t& in = checked(input, "input");
    const cagekit_mesh_t& approx = checked(approximation, "approximation");
    require_not_null(error, "error");
    const cagekit::ApproximationError e =
        cagekit::measure_approximation_error(in.mesh, approx.mesh, 4, in.context->monitor());
    cagekit_approximation_error out{};
    out.struct_size = sizeof(out);
    out.hausdorff_rel = e.hausdorff_rel;
    out.hausdorff_sym_rel = e.hausdorff_sym_rel;
    out.mean_rel = e.mean_rel;
    write_versioned(error, out, "cagekit_approximation_error");
  });
}

}  // extern "C"
