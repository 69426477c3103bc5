// SPDX-License-Identifier: GPL-3.0-or-later
// Remeshing: cagekit_mesh_remesh_anisotropic and cagekit_mesh_remesh_quad, the C shims over
// layout/anisotropic/anisotropic_remesher.h (thesis ch. 5) and layout/quad/quad_remesher.h (ch. 6).
#include <memory>
#include <string>

#include "capi/api_guard.h"
#include "capi/option_conversion.h"
#include "capi/report_conversion.h"
#include "core/mesh_validation.h"
#include "layout/anisotropic/anisotropic_remesher.h"
#include "layout/quad/quad_remesher.h"

using namespace cagekit_capi;

namespace {

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
  return create_from(mesh, "mesh", out, [&](cagekit_mesh_t& m) {
    const cagekit::AnisotropicRemeshOptions ao = anisotropic_options_from_c(options);
    cagekit::AnisotropicRemeshResult r = cagekit::remesh_anisotropic(m.mesh, ao, m.context->monitor());
    if (r.cage.mesh.num_faces() == 0)
      fail(Status::invalid_mesh, "remeshing produced no faces (no two lines intersect: lower the tolerance)");
    const cagekit_anisotropic_report rep = anisotropic_report_to_c(r);
    std::unique_ptr<cagekit_cage_t> cage = new_cage_handle(m, std::move(r.cage));
    write_versioned(report, rep, "cagekit_anisotropic_report");
    return cage;
  });
}

CAGEKIT_API cagekit_status cagekit_mesh_remesh_quad(cagekit_mesh mesh, const cagekit_quad_remesh_options* options,
                                                    cagekit_cage* out, cagekit_quad_remesh_report* report) {
  return create_from(mesh, "mesh", out, [&](cagekit_mesh_t& m) {
    const cagekit::QuadRemeshOptions qo = quad_options_from_c(options, m.mesh.num_faces());
    cagekit::QuadRemeshResult r = cagekit::remesh_quad_dominant(m.mesh, qo, m.context->monitor());
    const cagekit_quad_remesh_report rep = quad_report_to_c(r);
    std::unique_ptr<cagekit_cage_t> cage = new_cage_handle(m, std::move(r.cage));
    write_versioned(report, rep, "cagekit_quad_remesh_report");
    return cage;
  });
}

}  // extern "C"
