// SPDX-License-Identifier: GPL-3.0-or-later
// Cage handles: creation from a mesh, crease/corner/hole tags, boundary rule.
#include <algorithm>
#include <cmath>

#include "capi/api_guard.h"
#include "capi/mesh_conversion.h"
#include "core/mesh_edge_set.h"
#include "core/mesh_validation.h"

using namespace cagekit_capi;

namespace {

float checked_sharpness(const float* sharpness, uint32_t i, const char* what) {
  const float s = sharpness ? sharpness[i] : CAGEKIT_SHARP;
  if (!std::isfinite(s) || s < 0)
    fail(Status::invalid_argument, std::string(what) + " " + std::to_string(i) + " has sharpness " +
                                       std::to_string(s) + "; it must be finite and >= 0");
  return std::min(s, CAGEKIT_SHARP);
}

}  // namespace

extern "C" {

CAGEKIT_API cagekit_status cagekit_cage_create(cagekit_mesh mesh, cagekit_cage* out) {
  return create_from(mesh, "mesh", out, [&](cagekit_mesh_t& m) {
    const cagekit::ValidationReport report = cagekit::validate_mesh(m.mesh, 1);
    if (!report.ok()) fail(Status::invalid_mesh, "cannot make a cage of an invalid mesh: " + report.summary());
    cagekit::Cage cage;
    cage.mesh = m.mesh;
    return std::make_unique<cagekit_cage_t>(m.context, std::move(cage));
  });
}

CAGEKIT_API void cagekit_cage_retain(cagekit_cage cage) { retain_handle(cage); }
CAGEKIT_API void cagekit_cage_release(cagekit_cage cage) { release_handle(cage); }

CAGEKIT_API cagekit_status cagekit_cage_get_mesh(cagekit_cage cage, cagekit_mesh* out) {
  return create_from(cage, "cage", out, [&](cagekit_cage_t& c) {
    return make_mesh_handle(c.context, c.cage.mesh);
  });
}

CAGEKIT_API cagekit_status cagekit_cage_set_creases(cagekit_cage cage, uint32_t count, const uint32_t* vertex_pairs,
                                                    const float* sharpness) {
  return guarded(context_of(cage), [&] {
    cagekit_cage_t& c = checked(cage, "cage");
    if (count > 0) require_not_null(vertex_pairs, "vertex_pairs");
    const cagekit::MeshEdgeSet edges(c.cage.mesh);
    std::vector<cagekit::EdgeCrease> creases;
    creases.reserve(count);
    for (uint32_t i = 0; i < count; ++i) {
      const uint32_t a = vertex_pairs[2 * i], b = vertex_pairs[2 * i + 1];
      if (!edges.contains(a, b))
        fail(Status::invalid_argument, "crease " + std::to_string(i) + " (" + std::to_string(a) + ", " +
                                           std::to_string(b) + ") is not an edge of the cage");
      const float s = checked_sharpness(sharpness, i, "crease");
      if (s > 0) creases.push_back({a, b, s});
    }
    c.cage.creases = std::move(creases);
  });
}

CAGEKIT_API cagekit_status cagekit_cage_get_creases(cagekit_cage cage, uint32_t crease_capacity,
                                                    uint32_t* crease_count_out, uint32_t* vertex_pairs,
                                                    float* sharpness) {
  return guarded(context_of(cage), [&] {
    const auto& creases = checked(cage, "cage").cage.creases;
    if (!two_call_check("crease", static_cast<uint32_t>(creases.size()), crease_capacity, crease_count_out,
                        {{"vertex_pairs", vertex_pairs}, {"sharpness", sharpness}}))
      return;
    for (size_t i = 0; i < creases.size(); ++i) {
      if (vertex_pairs) {
        vertex_pairs[2 * i] = creases[i].v0;
        vertex_pairs[2 * i + 1] = creases[i].v1;
      }
      if (sharpness) sharpness[i] = creases[i].sharpness;
    }
  });
}

CAGEKIT_API cagekit_status cagekit_cage_set_corners(cagekit_cage cage, uint32_t count, const uint32_t* vertices,
                                                    const float* sharpness) {
  return guarded(context_of(cage), [&] {
    cagekit_cage_t& c = checked(cage, "cage");
    if (count > 0) require_not_null(vertices, "vertices");
    std::vector<cagekit::VertexCorner> corners;
    corners.reserve(count);
    for (uint32_t i = 0; i < count; ++i) {
      if (vertices[i] >= c.cage.mesh.num_vertices())
        fail(Status::invalid_argument, "corner " + std::to_string(i) + " names vertex " + std::to_string(vertices[i]) +
                                           " but the cage has " + std::to_string(c.cage.mesh.num_vertices()));
      const float s = checked_sharpness(sharpness, i, "corner");
      if (s > 0) corners.push_back({vertices[i], s});
    }
    c.cage.corners = std::move(corners);
  });
}

CAGEKIT_API cagekit_status cagekit_cage_get_corners(cagekit_cage cage, uint32_t corner_capacity,
                                                    uint32_t* corner_count_out, uint32_t* vertices, float* sharpness) {
  return guarded(context_of(cage), [&] {
    const auto& corners = checked(cage, "cage").cage.corners;
    if (!two_call_check("corner", static_cast<uint32_t>(corners.size()), corner_capacity, corner_count_out,
                        {{"vertices", vertices}, {"sharpness", sharpness}}))
      return;
    for (size_t i = 0; i < corners.size(); ++i) {
      if (vertices) vertices[i] = corners[i].vertex;
      if (sharpness) sharpness[i] = corners[i].sharpness;
    }
  });
}

CAGEKIT_API cagekit_status cagekit_cage_set_holes(cagekit_cage cage, uint32_t count, const uint32_t* faces) {
  return guarded(context_of(cage), [&] {
    cagekit_cage_t& c = checked(cage, "cage");
    if (count > 0) require_not_null(faces, "faces");
    for (uint32_t i = 0; i < count; ++i)
      if (faces[i] >= c.cage.mesh.num_faces())
        fail(Status::invalid_argument, "hole " + std::to_string(i) + " names face " + std::to_string(faces[i]) +
                                           " but the cage has " + std::to_string(c.cage.mesh.num_faces()));
    std::vector<uint32_t> holes(faces, faces + count);
    std::sort(holes.begin(), holes.end());
    holes.erase(std::unique(holes.begin(), holes.end()), holes.end());
    c.cage.holes = std::move(holes);
  });
}

CAGEKIT_API cagekit_status cagekit_cage_get_holes(cagekit_cage cage, uint32_t hole_capacity, uint32_t* hole_count_out,
                                                  uint32_t* faces) {
  return guarded(context_of(cage), [&] {
    const auto& holes = checked(cage, "cage").cage.holes;
    if (two_call_check("hole", static_cast<uint32_t>(holes.size()), hole_capacity, hole_count_out, {{"faces", faces}}))
      std::copy(holes.begin(), holes.end(), faces);
  });
}

CAGEKIT_API cagekit_status cagekit_cage_set_boundary_rule(cagekit_cage cage, cagekit_boundary_rule rule) {
  return guarded(context_of(cage), [&] {
    cagekit_cage_t& c = checked(cage, "cage");
    const int32_t raw = raw_enum(rule);
    if (raw != CAGEKIT_BOUNDARY_EDGES_ONLY && raw != CAGEKIT_BOUNDARY_EDGES_AND_CORNERS)
      fail(Status::invalid_argument, "rule is not a cagekit_boundary_rule");
    c.cage.boundary = static_cast<cagekit::BoundaryRule>(raw);
  });
}

CAGEKIT_API cagekit_status cagekit_cage_get_boundary_rule(cagekit_cage cage, cagekit_boundary_rule* rule) {
  return guarded(context_of(cage), [&] {
    require_not_null(rule, "rule");
    *rule = static_cast<cagekit_boundary_rule>(checked(cage, "cage").cage.boundary);
  });
}

CAGEKIT_API cagekit_status cagekit_cage_get_info(cagekit_cage cage, cagekit_mesh_info* info) {
  return guarded(context_of(cage), [&] { const cagekit::Cage& c = checked(cage, "cage").cage;
    fill_info(c.mesh, &c, info); });
}

}  // extern "C"
