// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/common/feature_edges.h"

#include <cmath>
#include <string>

#include "core/angles.h"
#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

std::vector<uint8_t> dihedral_feature_edges(const detail::EdgeMap& map, const std::vector<Vec3>& face_normals,
                                            double angle_degrees) {
  const double cos_limit = std::cos(radians_from_degrees(angle_degrees));
  std::vector<uint8_t> flags(map.num_edges(), 0);
  for (size_t e = 0; e < map.num_edges(); ++e) {
    if (map.valence(e) != 2) continue;
    const uint32_t* h = map.corners_begin(e);
    const Vec3& n0 = face_normals[map.corner_face[h[0]]];
    const Vec3& n1 = face_normals[map.corner_face[h[1]]];
    if (dot(n0, n0) == 0.0 || dot(n1, n1) == 0.0) continue;
    // Angle between the normals > angle_degrees  <=>  cos(angle) < cos(limit).
    if (dot(n0, n1) < cos_limit) flags[e] = 1;
  }
  return flags;
}

void check_feature_input(const PolygonMesh& mesh, const char* who) {
  detail::check_mesh_arrays(mesh);
  const std::string w(who);
  const size_t nv = mesh.num_vertices();
  for (const Vec3& p : mesh.positions)
    if (!is_finite(p)) fail(Status::invalid_mesh, w + ": a vertex position is not finite");
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t n = mesh.face_size(f);
    if (n < 3) fail(Status::invalid_mesh, w + ": face " + std::to_string(f) + " has fewer than 3 vertices");
    for (uint32_t i = 0; i < n; ++i)
      if (mesh.face_vertex(f, i) >= nv)
        fail(Status::invalid_mesh, w + ": face " + std::to_string(f) + " has an out-of-range vertex index");
    if (detail::find_repeated_vertex(mesh.face_begin(f), n) != detail::kNone)
      fail(Status::invalid_mesh, w + ": face " + std::to_string(f) + " repeats a vertex");
  }
}

std::vector<uint8_t> detect_feature_edges(const PolygonMesh& mesh, double angle_degrees) {
  if (!(angle_degrees >= 0.0 && angle_degrees <= 180.0))
    fail(Status::invalid_argument, "feature angle must be in [0, 180] degrees");
  check_feature_input(mesh, "feature edges");
  detail::EdgeMap map;
  build_edge_map(map, mesh, std::vector<uint8_t>(mesh.num_faces(), 1));
  std::vector<Vec3> normals(mesh.num_faces());
  for (size_t f = 0; f < mesh.num_faces(); ++f) normals[f] = normalized(mesh.face_vector_area(f));
  const std::vector<uint8_t> edge_flags = dihedral_feature_edges(map, normals, angle_degrees);
  std::vector<uint8_t> corner_flags(mesh.num_face_vertices(), 0);
  for (size_t c = 0; c < corner_flags.size(); ++c) corner_flags[c] = edge_flags[map.corner_edge[c]];
  return corner_flags;
}

CAGEKIT_NAMESPACE_END
