// SPDX-License-Identifier: GPL-3.0-or-later
// Remeshing: cagekit_mesh_remesh, the C shim over layout/anisotropic_remesher.h (thesis ch. 5) and
// layout/quad_remesher.h (thesis ch. 6).
#include <cmath>
#include <string>

#include "capi/api_guard.h"
#include "capi/option_conversion.h"
#include "core/mesh_validation.h"
#include "layout/anisotropic/anisotropic_remesher.h"
#include "layout/quad/quad_remesher.h"

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
    check_remesh_options(o);
    cagekit_remesh_report rep{};
    rep.struct_size = sizeof(rep);
    cagekit::Cage cage;
    if (method == CAGEKIT_REMESH_QUAD) {
      const cagekit::QuadRemeshOptions qo = quad_options_from_c(o, m.mesh.num_faces());
      cagekit::QuadRemeshResult r = cagekit::remesh_quad_dominant(m.mesh, qo, m.context->monitor());
      write_quality(rep, r);
      rep.creases = r.creases;
      rep.regions = r.regions;
      rep.lines = r.arcs;
      rep.seconds = r.seconds;
      rep.requested_regions = r.requested_regions;
      rep.split_regions = r.split_regions;
      rep.merged_regions = r.merged_regions;
      rep.layout_retries = r.layout_retries;
      rep.mended_faces = r.mended_faces;
      rep.partitioned_regions = r.partitioned_regions;
      cage = std::move(r.cage);
    } else {
      const cagekit::AnisotropicRemeshOptions ao = anisotropic_options_from_c(o);
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
