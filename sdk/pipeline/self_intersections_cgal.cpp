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
  auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
    if (sm.add_face(vertex[a], vertex[b], vertex[c]) == Mesh::null_face())
      ++result.skipped_faces;
    else
      ++result.triangles;
  };
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t* c = mesh.face_begin(f);
    if (mesh.face_size(f) == 4) {
      // A quad is split along the diagonal whose two triangles fold least (the larger cosine
      // between their normals): a sampled limit quad next to a boundary corner or an
      // extraordinary vertex can be non-convex, and its other diagonal would fold it over
      // itself where the surface does not.
      const Vec3 &p0 = mesh.positions[c[0]], &p1 = mesh.positions[c[1]], &p2 = mesh.positions[c[2]],
                 &p3 = mesh.positions[c[3]];
      auto cosine = [](const Vec3& n, const Vec3& m) {
        const double l = norm(n) * norm(m);
        return l > 0 ? dot(n, m) / l : -1.0;
      };
      const double along02 = cosine(cross(p1 - p0, p2 - p0), cross(p2 - p0, p3 - p0));
      const double along13 = cosine(cross(p2 - p1, p3 - p1), cross(p3 - p1, p0 - p1));
      if (along13 > along02) {
        add(c[1], c[2], c[3]);
        add(c[1], c[3], c[0]);
      } else {
        add(c[0], c[1], c[2]);
        add(c[0], c[2], c[3]);
      }
      continue;
    }
    mesh.for_each_fan_triangle(f, add);
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
