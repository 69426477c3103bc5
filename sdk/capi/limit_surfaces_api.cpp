// SPDX-License-Identifier: GPL-3.0-or-later
// The limit surface as one B-spline surface per ptex face (subdiv/limit_bspline_surfaces.h).

#include <string>

#include "capi/api_guard.h"
#include "capi/option_conversion.h"
#include "subdiv/limit_bspline_surfaces.h"

using namespace cagekit_capi;

namespace {

const cagekit::LimitBSplineSurface& surface_at(const cagekit::LimitBSplineSurfaces& s, uint32_t index) {
  if (index >= s.surfaces.size())
    fail(Status::invalid_argument, "surface index " + std::to_string(index) + " is out of range (" +
                                       std::to_string(s.surfaces.size()) + " surfaces)");
  return s.surfaces[index];
}

cagekit_surface_border_kind border_kind_to_c(cagekit::BorderKind kind) {
  switch (kind) {
    case cagekit::BorderKind::boundary: return CAGEKIT_SURFACE_BORDER_BOUNDARY;
    case cagekit::BorderKind::smooth: return CAGEKIT_SURFACE_BORDER_SMOOTH;
    case cagekit::BorderKind::crease: return CAGEKIT_SURFACE_BORDER_CREASE;
    case cagekit::BorderKind::non_manifold: return CAGEKIT_SURFACE_BORDER_NON_MANIFOLD;
  }
  return CAGEKIT_SURFACE_BORDER_BOUNDARY;
}

}  // namespace

extern "C" {

CAGEKIT_API cagekit_status cagekit_limit_surfaces_create(cagekit_cage cage,
                                                         const cagekit_limit_surface_options* options,
                                                         cagekit_limit_surfaces* out) {
  return create_from(cage, "cage", out, [&](cagekit_cage_t& c) {
    const cagekit::LimitBSplineOptions lo = limit_surface_options_from_c(options);
    cagekit::LimitBSplineSurfaces surfaces = cagekit::build_limit_bspline_surfaces(c.cage, lo, c.context->monitor());
    return std::make_unique<cagekit_limit_surfaces_t>(c.context, std::move(surfaces));
  });
}

CAGEKIT_API void cagekit_limit_surfaces_retain(cagekit_limit_surfaces surfaces) { retain_handle(surfaces); }
CAGEKIT_API void cagekit_limit_surfaces_release(cagekit_limit_surfaces surfaces) { release_handle(surfaces); }

CAGEKIT_API cagekit_status cagekit_limit_surfaces_get_info(cagekit_limit_surfaces surfaces,
                                                           cagekit_limit_surface_info* info) {
  return guarded(context_of(surfaces), [&] {
    const cagekit::LimitBSplineSurfaces& s = checked(surfaces, "surfaces").surfaces;
    require_not_null(info, "info");
    cagekit_limit_surface_info i{};
    i.struct_size = sizeof(i);
    i.surface_count = static_cast<uint32_t>(s.surfaces.size());
    i.exact_count = s.exact_count;
    i.approximated_count = s.approximated_count;
    i.over_tolerance_count = s.over_tolerance_count;
    i.max_error = s.max_error;
    i.max_error_rel = s.bbox_diagonal > 0 ? s.max_error / s.bbox_diagonal : 0.0;
    i.max_normal_jump_deg = s.max_normal_jump_deg;
    i.max_crease_angle_deg = s.max_crease_angle_deg;
    i.bbox_diagonal = s.bbox_diagonal;
    i.tolerance = s.tolerance;
    i.level = static_cast<uint32_t>(s.level);
    i.ptex_face_count = s.ptex_faces;
    write_versioned(info, i, "cagekit_limit_surface_info");
  });
}

CAGEKIT_API cagekit_status cagekit_limit_surfaces_get_surface(cagekit_limit_surfaces surfaces, uint32_t index,
                                                              cagekit_limit_surface* surface) {
  return guarded(context_of(surfaces), [&] {
    const cagekit::LimitBSplineSurface& s = surface_at(checked(surfaces, "surfaces").surfaces, index);
    require_not_null(surface, "surface");
    cagekit_limit_surface c{};
    c.ptex_face = s.ptex_face;
    c.cage_face = s.cage_face;
    c.degree_u = static_cast<uint32_t>(s.degree_u);
    c.degree_v = static_cast<uint32_t>(s.degree_v);
    c.knot_count_u = static_cast<uint32_t>(s.knots_u.size());
    c.knot_count_v = static_cast<uint32_t>(s.knots_v.size());
    c.num_u = s.num_u;
    c.num_v = s.num_v;
    c.exact = s.exact ? CAGEKIT_TRUE : CAGEKIT_FALSE;
    c.error = s.error;
    for (int k = 0; k < 4; ++k) {
      c.sides[k].kind = border_kind_to_c(s.sides[size_t(k)].kind);
      c.sides[k].neighbour_count = static_cast<uint32_t>(s.sides[size_t(k)].neighbours.size());
      c.sides[k].max_normal_jump_deg = s.sides[size_t(k)].max_normal_jump_deg;
    }
    *surface = c;
  });
}

CAGEKIT_API cagekit_status cagekit_limit_surfaces_get_knots(cagekit_limit_surfaces surfaces, uint32_t index,
                                                            cagekit_surface_direction direction,
                                                            uint32_t knot_capacity, uint32_t* knot_count_out,
                                                            double* knots) {
  return guarded(context_of(surfaces), [&] {
    const cagekit::LimitBSplineSurface& s = surface_at(checked(surfaces, "surfaces").surfaces, index);
    const int32_t d = raw_enum(direction);
    if (d != CAGEKIT_SURFACE_DIRECTION_U && d != CAGEKIT_SURFACE_DIRECTION_V)
      fail(Status::invalid_argument, "direction must be CAGEKIT_SURFACE_DIRECTION_U or CAGEKIT_SURFACE_DIRECTION_V, not " +
                                         std::to_string(d));
    const std::vector<double>& k = d == CAGEKIT_SURFACE_DIRECTION_U ? s.knots_u : s.knots_v;
    if (two_call_check("knot", static_cast<uint32_t>(k.size()), knot_capacity, knot_count_out, {{"knots", knots}}))
      std::copy(k.begin(), k.end(), knots);
  });
}

CAGEKIT_API cagekit_status cagekit_limit_surfaces_get_control_points(cagekit_limit_surfaces surfaces, uint32_t index,
                                                                     uint32_t point_capacity,
                                                                     uint32_t* point_count_out, double* points) {
  return guarded(context_of(surfaces), [&] {
    const cagekit::LimitBSplineSurface& s = surface_at(checked(surfaces, "surfaces").surfaces, index);
    if (two_call_check("point", static_cast<uint32_t>(s.points.size()), point_capacity, point_count_out,
                       {{"points", points}}))
      for (size_t k = 0; k < s.points.size(); ++k) {
        points[3 * k] = s.points[k].x;
        points[3 * k + 1] = s.points[k].y;
        points[3 * k + 2] = s.points[k].z;
      }
  });
}

CAGEKIT_API cagekit_status cagekit_limit_surfaces_get_neighbours(cagekit_limit_surfaces surfaces, uint32_t index,
                                                                 uint32_t side, uint32_t neighbour_capacity,
                                                                 uint32_t* neighbour_count_out,
                                                                 cagekit_limit_surface_neighbour* neighbours) {
  return guarded(context_of(surfaces), [&] {
    const cagekit::LimitBSplineSurface& s = surface_at(checked(surfaces, "surfaces").surfaces, index);
    if (side > 3) fail(Status::invalid_argument, "side must be 0..3, not " + std::to_string(side));
    const std::vector<cagekit::SideNeighbour>& n = s.sides[side].neighbours;
    if (two_call_check("neighbour", static_cast<uint32_t>(n.size()), neighbour_capacity, neighbour_count_out,
                       {{"neighbours", neighbours}}))
      for (size_t k = 0; k < n.size(); ++k) {
        cagekit_limit_surface_neighbour c{};
        c.surface = n[k].surface;
        c.side = n[k].side;
        c.t0 = n[k].t0;
        c.t1 = n[k].t1;
        c.n0 = n[k].n0;
        c.n1 = n[k].n1;
        neighbours[k] = c;
      }
  });
}

}  // extern "C"
