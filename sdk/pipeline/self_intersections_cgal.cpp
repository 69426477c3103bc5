// SPDX-License-Identifier: GPL-3.0-or-later
// CGAL translation unit of sdk/pipeline: self-intersection counts on a Surface_mesh.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <exception>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "core/memory_budget.h"
#include "core/status.h"
#include "pipeline/self_intersections.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
using Face = Mesh::Face_index;
}  // namespace

SelfIntersections count_self_intersections(const PolygonMesh& mesh) {
  // Surface_mesh (~200 bytes per triangle with its properties) plus the box-intersection pass.
  check_memory_estimate(estimate_product(mesh.num_face_vertices(), 400), "counting self-intersections");
  SelfIntersections result;
  Mesh sm;
  std::vector<Mesh::Vertex_index> vertex(mesh.num_vertices());
  for (size_t v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3& p = mesh.positions[v];
    vertex[v] = sm.add_vertex(Kernel::Point_3(p.x, p.y, p.z));
  }
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t* c = mesh.face_begin(f);
    for (uint32_t k = 1; k + 1 < mesh.face_size(f); ++k) {
      const Face added = sm.add_face(vertex[c[0]], vertex[c[k]], vertex[c[k + 1]]);
      if (added == Mesh::null_face())
        ++result.skipped_faces;
      else
        ++result.triangles;
    }
  }
  std::vector<std::pair<Face, Face>> pairs;
  try {
    CGAL::Polygon_mesh_processing::self_intersections(sm, std::back_inserter(pairs));
  } catch (const std::exception& e) {
    fail(Status::internal_error, std::string("counting self-intersections: CGAL failed: ") + e.what());
  }
  result.pairs = pairs.size();
  return result;
}

CAGEKIT_NAMESPACE_END
