// SPDX-License-Identifier: GPL-3.0-or-later
#include "subdiv/cage_input_check.h"

#include <opensubdiv/far/types.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/mesh_edge_set.h"
#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN
namespace subdiv_detail {
namespace {

void check_sharpness(float sharpness, const std::string& what) {
  if (!std::isfinite(sharpness) || sharpness < 0.0f)
    fail(Status::invalid_mesh, what + " has sharpness " + std::to_string(sharpness) +
                                   "; it must be finite and >= 0");
}

void check_counts(const PolygonMesh& mesh) {
  const auto& offsets = mesh.face_offsets;
  if (offsets.empty() || offsets.front() != 0)
    fail(Status::invalid_mesh, "face_offsets must start with 0");
  if (offsets.back() != mesh.face_vertices.size())
    fail(Status::invalid_mesh, "face_offsets ends at " + std::to_string(offsets.back()) + " but there are " +
                                   std::to_string(mesh.face_vertices.size()) + " face vertices");
  if (mesh.num_vertices() > static_cast<size_t>(INT_MAX) || mesh.num_face_vertices() > static_cast<size_t>(INT_MAX))
    fail(Status::limit_exceeded, "the cage has more vertices or face vertices than OpenSubdiv can index (2^31 - 1)");
  if (mesh.num_faces() == 0) fail(Status::invalid_mesh, "the cage has no faces");
}

void check_faces(const PolygonMesh& mesh) {
  const size_t num_vertices = mesh.num_vertices();
  const auto& offsets = mesh.face_offsets;
  std::vector<uint32_t> valence(num_vertices, 0);
  std::vector<uint32_t> sorted;
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    if (offsets[f + 1] < offsets[f]) fail(Status::invalid_mesh, "face_offsets decrease at face " + std::to_string(f));
    const uint32_t size = offsets[f + 1] - offsets[f];
    if (size < 3)
      fail(Status::invalid_mesh, "face " + std::to_string(f) + " has " + std::to_string(size) +
                                     " vertices; Catmull-Clark needs at least 3");
    if (size > static_cast<uint32_t>(OpenSubdiv::Far::VALENCE_LIMIT))
      fail(Status::limit_exceeded, "face " + std::to_string(f) + " has " + std::to_string(size) +
                                       " vertices, more than OpenSubdiv's limit");
    const uint32_t* begin = mesh.face_begin(f);
    sorted.assign(begin, begin + size);
    for (uint32_t v : sorted) {
      if (v >= num_vertices)
        fail(Status::invalid_mesh, "face " + std::to_string(f) + " refers to vertex " + std::to_string(v) +
                                       " but the cage has " + std::to_string(num_vertices) + " vertices");
      if (++valence[v] > static_cast<uint32_t>(OpenSubdiv::Far::VALENCE_LIMIT))
        fail(Status::limit_exceeded, "vertex " + std::to_string(v) + " has more incident faces than OpenSubdiv's limit");
    }
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
      fail(Status::invalid_mesh, "face " + std::to_string(f) + " uses a vertex more than once (degenerate face)");
  }
  for (size_t v = 0; v < num_vertices; ++v)
    if (!is_finite(mesh.positions[v]))
      fail(Status::invalid_mesh, "vertex " + std::to_string(v) + " has a non-finite coordinate");
}

void check_tags(const Cage& cage) {
  const PolygonMesh& mesh = cage.mesh;
  if (!cage.creases.empty()) {
    const MeshEdgeSet edges(mesh);
    for (size_t i = 0; i < cage.creases.size(); ++i) {
      const EdgeCrease& c = cage.creases[i];
      const std::string name = "crease " + std::to_string(i) + " (" + std::to_string(c.v0) + ", " +
                               std::to_string(c.v1) + ")";
      if (!edges.contains(c.v0, c.v1))
        fail(Status::invalid_mesh, name + " is not an edge of the cage");
      check_sharpness(c.sharpness, name);
    }
  }
  for (size_t i = 0; i < cage.corners.size(); ++i) {
    const VertexCorner& c = cage.corners[i];
    const std::string name = "corner " + std::to_string(i) + " (vertex " + std::to_string(c.vertex) + ")";
    if (c.vertex >= mesh.num_vertices()) fail(Status::invalid_mesh, name + " is out of range");
    check_sharpness(c.sharpness, name);
  }
  for (size_t i = 0; i < cage.holes.size(); ++i)
    if (cage.holes[i] >= mesh.num_faces())
      fail(Status::invalid_mesh, "hole " + std::to_string(i) + " names face " + std::to_string(cage.holes[i]) +
                                     " but the cage has " + std::to_string(mesh.num_faces()) + " faces");
  if (cage.boundary != BoundaryRule::edges_only && cage.boundary != BoundaryRule::edges_and_corners)
    fail(Status::invalid_mesh, "unknown boundary rule " + std::to_string(static_cast<int>(cage.boundary)));
}

}  // namespace

void check_cage_for_subdivision(const Cage& cage) {
  check_counts(cage.mesh);
  check_faces(cage.mesh);
  check_tags(cage);
}

}  // namespace subdiv_detail
CAGEKIT_NAMESPACE_END
