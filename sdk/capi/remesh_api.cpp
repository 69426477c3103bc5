// SPDX-License-Identifier: GPL-3.0-or-later
// Remeshing: cagekit_mesh_remesh_anisotropic and cagekit_mesh_remesh_quad, the C shims over
// layout/anisotropic/anisotropic_remesher.h (thesis ch. 5) and layout/quad/quad_remesher.h (ch. 6).
#include <memory>
#include <string>

#include "capi/api_guard.h"
#include "capi/option_conversion.h"
#include "core/mesh_validation.h"
#include "layout/anisotropic/anisotropic_remesher.h"
#include "layout/quad/quad_remesher.h"

using namespace cagekit_capi;

namespace {

cagekit_remesh_quality quality_to_c(const cagekit::RemeshQuality& q, uint64_t creases, double seconds) {
  cagekit_remesh_quality c{};
  c.faces = q.faces;
  c.vertices = q.vertices;
  c.quads = q.quads;
  c.interior_vertices = q.interior_vertices;
  c.valence4_vertices = q.valence4_vertices;
  c.max_face_valence = q.max_face_valence;
  c.max_vertex_valence = q.max_vertex_valence;
  c.creases = creases;
  c.min_scaled_jacobian = q.min_scaled_jacobian;
  c.seconds = seconds;
  return c;
}

// The remeshers promise a valid oriented 2-manifold; a result that is not one is an internal error.
std::unique_ptr<cagekit_cage_t> new_cage_handle(cagekit_mesh_t& input, cagekit::Cage&& cage) {
  const cagekit::ValidationReport check = cagekit::validate_mesh(cage.mesh, 1);
  if (!check.ok()) fail(Status::internal_error, "remeshing produced an invalid mesh: " + check.summary());
  return std::make_unique<cagekit_cage_t>(input.context, std::move(cage));
}

}  // namespace

extern "C" {

CAGEKIT_API cagekit_status cagekit_mesh_remesh_anisotropic(cagekit_mesh mesh, const cagekit_anisotropic_options* options,
                                                           cagekit_cage* out, cagekit_anisotropic_report* report) {
  return guarded(context_of(mesh), [&] {
    require_not_null(out, "out");
    *out = nullptr;
    cagekit_mesh_t& m = checked(mesh, "mesh");
    const cagekit::AnisotropicRemeshOptions ao = anisotropic_options_from_c(options);
    cagekit::AnisotropicRemeshResult r = cagekit::remesh_anisotropic(m.mesh, ao, m.context->monitor());
    if (r.cage.mesh.num_faces() == 0)
      fail(Status::invalid_mesh, "remeshing produced no faces (no two lines intersect: lower the tolerance)");
    cagekit_anisotropic_report rep{};
    rep.struct_size = sizeof(rep);
    rep.quality = quality_to_c(r, r.creases, r.seconds);
    rep.regions = r.regions;
    rep.lines = r.lines;
    rep.holes = r.holes;
    rep.mean_alignment_deg = r.mean_alignment_deg;
    std::unique_ptr<cagekit_cage_t> cage = new_cage_handle(m, std::move(r.cage));
    write_versioned(report, rep, "cagekit_anisotropic_report");
    *out = cage.release();
  });
}

CAGEKIT_API cagekit_status cagekit_mesh_remesh_quad(cagekit_mesh mesh, const cagekit_quad_remesh_options* options,
                                                    cagekit_cage* out, cagekit_quad_remesh_report* report) {
  return guarded(context_of(mesh), [&] {
    require_not_null(out, "out");
    *out = nullptr;
    cagekit_mesh_t& m = checked(mesh, "mesh");
    const cagekit::QuadRemeshOptions qo = quad_options_from_c(options, m.mesh.num_faces());
    cagekit::QuadRemeshResult r = cagekit::remesh_quad_dominant(m.mesh, qo, m.context->monitor());
    cagekit_quad_remesh_report rep{};
    rep.struct_size = sizeof(rep);
    rep.quality = quality_to_c(r, r.creases, r.seconds);
    rep.regions = r.regions;
    rep.arcs = r.arcs;
    rep.requested_regions = r.requested_regions;
    rep.split_regions = r.split_regions;
    rep.merged_regions = r.merged_regions;
    rep.layout_retries = r.layout_retries;
    rep.mended_faces = r.mended_faces;
    rep.partitioned_regions = r.partitioned_regions;
    std::unique_ptr<cagekit_cage_t> cage = new_cage_handle(m, std::move(r.cage));
    write_versioned(report, rep, "cagekit_quad_remesh_report");
    *out = cage.release();
  });
}

}  // extern "C"
