// SPDX-License-Identifier: GPL-3.0-or-later
// Remeshing (thesis ch. 5): cagekit_mesh_remesh, the C shim over layout/anisotropic_remesher.h.
#include <cmath>

#include "capi/api_guard.h"
#include "core/mesh_validation.h"
#include "layout/anisotropic_remesher.h"

using namespace cagekit_capi;

extern "C" {

CAGEKIT_API cagekit_status cagekit_mesh_remesh(cagekit_mesh mesh, const cagekit_remesh_options* options,
                                               cagekit_cage* out, cagekit_remesh_report* report) {
  return guarded(context_of(mesh), [&] {
    require_not_null(out, "out");
    *out = nullptr;
    cagekit_mesh_t& m = checked(mesh, "mesh");
    const cagekit_remesh_options defaults = CAGEKIT_REMESH_OPTIONS_INIT;
    const cagekit_remesh_options o = read_versioned(options, defaults, "cagekit_remesh_options");
    if (raw_enum(o.method) != CAGEKIT_REMESH_ANISOTROPIC)
      fail(Status::invalid_argument, "method is not a cagekit_remesh_method this library implements");
    if (!(o.tolerance > 0.0) || !(o.tolerance <= 1.0))
      fail(Status::invalid_argument, "tolerance must be in (0, 1] (relative to the bounding-box diagonal)");
    if (std::isnan(o.feature_angle_degrees) || o.feature_angle_degrees > 180.0)
      fail(Status::invalid_argument, "feature_angle_degrees must be <= 180 (< 0: no feature lines)");
    if (o.max_face_valence < 3 || o.max_face_valence > 1000000)
      fail(Status::invalid_argument, "max_face_valence must be >= 3");
    if (!(o.curvature_radius >= 0.0) || !(o.curvature_radius <= 1.0))
      fail(Status::invalid_argument, "curvature_radius must be in [0, 1]");
    if (o.threads > 1024) fail(Status::invalid_argument, "threads must be <= 1024");
    cagekit::AnisotropicRemeshOptions ao;
    ao.tolerance = o.tolerance;
    ao.feature_angle_degrees = o.feature_angle_degrees;
    ao.max_face_valence = int(o.max_face_valence);
    ao.disk_radius_bbox = o.curvature_radius;
    ao.threads = int(o.threads);
    cagekit::AnisotropicRemeshResult r = cagekit::remesh_anisotropic(m.mesh, ao, m.context->monitor());
    if (r.cage.mesh.num_faces() == 0)
      fail(Status::invalid_mesh, "remeshing produced no faces (no two lines intersect: lower the tolerance)");
    const cagekit::ValidationReport check = cagekit::validate_mesh(r.cage.mesh, 1);
    if (!check.ok()) fail(Status::internal_error, "remeshing produced an invalid mesh: " + check.summary());
    cagekit_remesh_report rep{};
    rep.struct_size = sizeof(rep);
    rep.faces = r.faces;
    rep.vertices = r.vertices;
    rep.quads = r.quads;
    rep.interior_vertices = r.interior_vertices;
    rep.valence4_vertices = r.valence4_vertices;
    rep.max_face_valence = r.max_face_valence;
    rep.max_vertex_valence = r.max_vertex_valence;
    rep.creases = r.creases;
    rep.regions = r.regions;
    rep.lines = r.lines;
    rep.holes = r.holes;
    rep.mean_alignment_deg = r.mean_alignment_deg;
    rep.min_scaled_jacobian = r.min_scaled_jacobian;
    rep.seconds = r.seconds;
    write_versioned(report, rep, "cagekit_remesh_report");
    *out = std::make_unique<cagekit_cage_t>(m.context, std::move(r.cage)).release();
  });
}

}  // extern "C"
