// SPDX-License-Identifier: GPL-3.0-or-later
// Catmull-Clark refinement, limit points and limit-surface evaluation.

#include "capi/api_guard.h"
#include "capi/option_conversion.h"
#include "subdiv/subdivision_surface.h"
#include "subdiv/uniform_refinement.h"

using namespace cagekit_capi;

namespace {

void copy_vec3(const cagekit::Vec3& v, double* out) {
  out[0] = v.x;
  out[1] = v.y;
  out[2] = v.z;
}

void check_location(const cagekit::SubdivisionSurface& surface, const cagekit_surface_location& l, uint32_t i) {
  if (l.face >= surface.num_ptex_faces())
    fail(Status::invalid_argument, "location " + std::to_string(i) + ": face " + std::to_string(l.face) +
                                       " is not below the ptex face count " +
                                       std::to_string(surface.num_ptex_faces()));
  if (!(l.u >= 0.0 && l.u <= 1.0 && l.v >= 0.0 && l.v <= 1.0))
    fail(Status::invalid_argument, "location " + std::to_string(i) + ": (u, v) = (" + std::to_string(l.u) + ", " +
                                       std::to_string(l.v) + ") is not inside [0,1]^2");
}

}  // namespace

extern "C" {

CAGEKIT_API cagekit_status cagekit_cage_subdivide(cagekit_cage cage, const cagekit_subdivide_options* options,
                                                  cagekit_cage* out) {
  return create_from(cage, "cage", out, [&](cagekit_cage_t& c) {
    const cagekit::RefineOptions ro = subdivide_options_from_c(options);
    cagekit::Cage refined = cagekit::refine_uniform(c.cage, ro, c.context->monitor());
    return std::make_unique<cagekit_cage_t>(c.context, std::move(refined));
  });
}

CAGEKIT_API cagekit_status cagekit_cage_get_limit_points(cagekit_cage cage, uint32_t vertex_capacity,
                                                         uint32_t* vertex_count_out, double* positions,
                                                         double* normals) {
  return guarded(context_of(cage), [&] {
    const cagekit::Cage& c = checked(cage, "cage").cage;
    if (!two_call_check("vertex", static_cast<uint32_t>(c.mesh.num_vertices()), vertex_capacity, vertex_count_out,
                        {{"positions", positions}, {"normals", normals}}) ||
        (positions == nullptr && normals == nullptr))  // nothing wanted: skip the evaluation
      return;
    std::vector<cagekit::Vec3> p, n;
    cagekit::limit_positions_and_normals(c, &p, &n);
    for (size_t v = 0; v < p.size(); ++v) {
      if (positions) copy_vec3(p[v], positions + 3 * v);
      if (normals) copy_vec3(n[v], normals + 3 * v);
    }
  });
}

CAGEKIT_API cagekit_status cagekit_surface_create(cagekit_cage cage, const cagekit_surface_options* options,
                                                  cagekit_surface* out) {
  return create_from(cage, "cage", out, [&](cagekit_cage_t& c) {
    const cagekit::SurfaceOptions so = surface_options_from_c(options);
    c.context->monitor().report("surface", 0.0);
    cagekit::SubdivisionSurface surface(c.cage, so);
    c.context->monitor().report("surface", 1.0);
    return std::make_unique<cagekit_surface_t>(c.context, std::move(surface));
  });
}

CAGEKIT_API void cagekit_surface_retain(cagekit_surface surface) { retain_handle(surface); }
CAGEKIT_API void cagekit_surface_release(cagekit_surface surface) { release_handle(surface); }

CAGEKIT_API cagekit_status cagekit_surface_get_counts(cagekit_surface surface, uint32_t* ptex_face_count,
                                                      uint32_t* control_vertex_count) {
  return guarded(context_of(surface), [&] {
    const cagekit::SubdivisionSurface& s = checked(surface, "surface").surface;
    if (ptex_face_count) *ptex_face_count = s.num_ptex_faces();
    if (control_vertex_count) *control_vertex_count = s.num_control_vertices();
  });
}

CAGEKIT_API cagekit_status cagekit_surface_get_ptex_face(cagekit_surface surface, uint32_t cage_face,
                                                         uint32_t corner, uint32_t* ptex_face) {
  return guarded(context_of(surface), [&] {
    require_not_null(ptex_face, "ptex_face");
    *ptex_face = checked(surface, "surface").surface.ptex_face(cage_face, corner);
  });
}

CAGEKIT_API cagekit_status cagekit_surface_evaluate(cagekit_surface surface, const double* control_positions,
                                                    uint32_t count, const cagekit_surface_location* locations,
                                                    cagekit_surface_point* points) {
  return guarded(context_of(surface), [&] {
    const cagekit::SubdivisionSurface& s = checked(surface, "surface").surface;
    if (count == 0) return;
    require_not_null(locations, "locations");
    require_not_null(points, "points");
    for (uint32_t i = 0; i < count; ++i) check_location(s, locations[i], i);
    std::vector<cagekit::Vec3> control;
    if (control_positions) {
      control.resize(s.num_control_vertices());
      for (size_t v = 0; v < control.size(); ++v)
        control[v] = {control_positions[3 * v], control_positions[3 * v + 1], control_positions[3 * v + 2]};
    }
    for (uint32_t i = 0; i < count; ++i) {
      const cagekit_surface_location& l = locations[i];
      const cagekit::SurfacePoint p =
          control_positions ? s.evaluate(l.face, l.u, l.v, control) : s.evaluate(l.face, l.u, l.v);
      cagekit_surface_point& o = points[i];
      copy_vec3(p.position, o.position);
      copy_vec3(p.du, o.du);
      copy_vec3(p.dv, o.dv);
      copy_vec3(p.duu, o.duu);
      copy_vec3(p.duv, o.duv);
      copy_vec3(p.dvv, o.dvv);
    }
  });
}

CAGEKIT_API cagekit_status cagekit_surface_evaluate_basis(cagekit_surface surface,
                                                          const cagekit_surface_location* location,
                                                          uint32_t basis_capacity, uint32_t* basis_count_out,
                                                          uint32_t* indices, double* w, double* wu, double* wv,
                                                          double* wuu, double* wuv, double* wvv) {
  return guarded(context_of(surface), [&] {
    const cagekit::SubdivisionSurface& s = checked(surface, "surface").surface;
    require_not_null(location, "location");
    check_location(s, *location, 0);
    const cagekit::BasisWeights b = s.basis(location->face, location->u, location->v);
    if (!two_call_check("basis", static_cast<uint32_t>(b.indices.size()), basis_capacity, basis_count_out,
                        {{"indices", indices}, {"w", w}, {"wu", wu}, {"wv", wv}, {"wuu", wuu}, {"wuv", wuv},
                         {"wvv", wvv}}))
      return;
    auto copy = [](const std::vector<double>& from, double* to) {
      if (to) std::copy(from.begin(), from.end(), to);
    };
    if (indices) std::copy(b.indices.begin(), b.indices.end(), indices);
    copy(b.w, w);
    copy(b.wu, wu);
    copy(b.wv, wv);
    copy(b.wuu, wuu);
    copy(b.wuv, wuv);
    copy(b.wvv, wvv);
  });
}

}  // extern "C"
