// SPDX-License-Identifier: GPL-3.0-or-later
// CGAL translation unit of sdk/pipeline: self-intersection counts on a Surface_mesh.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <chrono>
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
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, Face, CGAL::Box_intersection_d::ID_FROM_BOX_ADDRESS>;
using VertexPointMap = Mesh::Property_map<Mesh::Vertex_index, Kernel::Point_3>;
using PairInserter = std::back_insert_iterator<std::vector<std::pair<Face, Face>>>;
// CGAL's own pair test of Polygon_mesh_processing::self_intersections (internal in CGAL 5.5, the
// Debian 12 version): true intersections only, not a shared vertex or edge. Calling
// box_self_intersection_d with it here, instead of self_intersections(), lets the callback below
// report progress and throw on a cancel from inside the box pass.
using StrictTest = CGAL::Polygon_mesh_processing::internal::Strict_intersect_faces<Box, Mesh, VertexPointMap, Kernel,
                                                                                  PairInserter>;

// The reporting state of one count, shared by the copies CGAL makes of the callback.
struct ReportState {
  const TaskMonitor* monitor;
  const char* stage;
  double expected_pairs;  // a guess (~a triangle's neighbours per triangle): the pairs are not known ahead
  uint64_t calls = 0;
  std::chrono::steady_clock::time_point last = std::chrono::steady_clock::now();
};

// Wraps the pair test: every 4096 candidate pairs it looks at the clock and, 0.1 s after the last
// report, reports (which throws Error(cancelled) when the caller cancels).
class MonitoredTest {
 public:
  MonitoredTest(const StrictTest& test, ReportState* state) : test_(test), state_(state) {}
  void operator()(const Box* a, const Box* b) const {
    test_(a, b);
    if (state_->monitor == nullptr || (++state_->calls & 4095u) != 0) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - state_->last < std::chrono::milliseconds(100)) return;
    state_->last = now;
    // The fraction is capped below 1 until the pass ends: the expected count is a guess.
    state_->monitor->report(state_->stage,
                            std::min(0.95, 0.1 + 0.85 * double(state_->calls) / state_->expected_pairs));
  }

 private:
  StrictTest test_;
  ReportState* state_;
};
}  // namespace

SelfIntersections count_self_intersections(const PolygonMesh& mesh, const TaskMonitor* monitor, const char* stage) {
  if (monitor) monitor->report(stage, 0.0);
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
  if (monitor) monitor->report(stage, 0.05);

  // As CGAL's self_intersections (5.5): a degenerate (collinear) triangle is a pair with itself and
  // gets no box; the others one box each, tested in box_self_intersection_d with cutoff 2000.
  std::vector<std::pair<Face, Face>> pairs;
  std::vector<Box> boxes;
  boxes.reserve(sm.number_of_faces());
  const VertexPointMap points = sm.points();
  for (const Face f : sm.faces()) {
    const auto h = sm.halfedge(f);
    const Kernel::Point_3 &p = points[sm.target(h)], &q = points[sm.target(sm.next(h))],
                          &r = points[sm.target(sm.prev(h))];
    if (CGAL::collinear(p, q, r))
      pairs.emplace_back(f, f);
    else
      boxes.emplace_back(p.bbox() + q.bbox() + r.bbox(), f);
  }
  std::vector<const Box*> box_pointers;
  box_pointers.reserve(boxes.size());
  for (const Box& b : boxes) box_pointers.push_back(&b);
  if (monitor) monitor->report(stage, 0.1);
  try {
    const StrictTest test(sm, points, Kernel(), std::back_inserter(pairs));
    ReportState state{monitor, stage, std::max(1.0, 16.0 * double(boxes.size()))};
    const MonitoredTest monitored(test, &state);
    CGAL::box_self_intersection_d<CGAL::Sequential_tag>(box_pointers.begin(), box_pointers.end(), monitored,
                                                        std::ptrdiff_t(2000));
  } catch (const Error&) {
    throw;  // cancelled
  } catch (const std::exception& e) {
    fail(Status::internal_error, std::string("counting self-intersections: CGAL failed: ") + e.what());
  }
  if (monitor) monitor->report(stage, 1.0);
  result.pairs = pairs.size();
  return result;
}

CAGEKIT_NAMESPACE_END
