// SPDX-License-Identifier: GPL-3.0-or-later
// Remeshing: cagekit_mesh_remesh, the C shim over layout/anisotropic_remesher.h (thesis ch. 5) and
// layout/quad_remesher.h (thesis ch. 6).
#include <cmath>
#include <string>

#include "capi/api_guard.h"
#include "core/mesh_validation.h"
#include "layout/anisotropic_remesher.h"
#include "layout/quad_remesher.h"

using namespace cagekit_capi;

namespace {

void write_quality(cagekit_remesh_report& rep, const cagekit::RemeshQuality& q) {
  rep.faces = q.faces;
  rep.vertices = q.vertices;
  rep.quads = q.quads;
  rep.interior_vertices = q.interior_vertices;
  rep.valence4_vertices = q.valence4_vertices;
  rep.max_face_valence = q.max_face_valence;
  rep.max_vertex_valence = q.max_vertex_valence;
  rep.min_scaled_jacobian = q.min_scaled_jacobian;
}

}  // namespace

extern "C" {

CAGEKIT_API cagekit_status cagekit_mesh_remesh(cagekit_mesh mesh, const cagekit_remesh_options* options,
                                               cagekit_cage* out, cagekit_remesh_report* report) {
  return guarded(context_of(mesh), [&] {
    require_not_null(out, "out");
    *out = nullptr;
    cagekit_mesh_t& m = checked(mesh, "mesh");
    const cagekit_remesh_options defaults = CAGEKIT_REMESH_OPTIONS_INIT;
    const cagekit_remesh_options o = read_versioned(options, defaults, "cagekit_remesh_options");
    const auto method = raw_enum(o.method);
    if (method != CAGEKIT_REMESH_ANISOTROPIC && method != CAGEKIT_REMESH_QUAD)
      fail(Status::invalid_argument, "method is not a cagekit_remesh_method this library implements");
    if (std::isnan(o.feature_angle_degrees) || o.feature_angle_degrees > 180.0)
      fail(Status::invalid_argument, "feature_angle_degrees must be <= 180 (< 0: no feature lines)");
    if (o.max_face_valence < 3 || o.max_face_valence > 1000000)
      fail(Status::invalid_argument, "max_face_valence must be >= 3");
    if (o.threads > 1024) fail(Status::invalid_argument, "threads must be <= 1024");
    cagekit_remesh_report rep{};
    rep.struct_size = sizeof(rep);
    cagekit::Cage cage;
    if (method == CAGEKIT_REMESH_QUAD) {
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
      const uint64_t input_faces = m.mesh.num_faces();
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
      cagekit::QuadRemeshResult r = cagekit::remesh_quad_dominant(m.mesh, qo, m.context->monitor());
      write_quality(rep, r);
      rep.creases = r.creases;
      rep.regions = r.regions;
      rep.lines = r.arcs;
      rep.seconds = r.seconds;
      cage = std::move(r.cage);
    } else {
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
      cagekit::AnisotropicRemeshResult r = cagekit::remesh_anisotropic(m.mesh, ao, m.context->monitor());
      if (r.cage.mesh.num_faces() == 0)
        fail(Status::invalid_mesh, "remeshing produced no faces (no two lines intersect: lower the tolerance)");
      write_quality(rep, r);
      rep.creases = r.creases;
      rep.regions = r.regions;
      rep.lines = r.lines;
      rep.holes = r.holes;
      rep.mean_alignment_deg = r.mean_alignment_deg;
      rep.seconds = r.seconds;
      cage = std::move(r.cage);
    }
    const cagekit::ValidationReport check = cagekit::validate_mesh(cage.mesh, 1);
    if (!check.ok()) fail(Status::internal_error, "remeshing produced an invalid mesh: " + check.summary());
    write_versioned(report, rep, "cagekit_remesh_report");
    *out = std::make_unique<cagekit_cage_t>(m.context, std::move(cage)).release();
  });
}

}  // extern "C"
