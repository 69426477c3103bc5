// SPDX-License-Identifier: GPL-3.0-or-later
// Point-to-triangle-soup distances with CGAL's AABB tree (the peers were measured with it).
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <thread>
#include <utility>
#include <vector>

#include "layout/common/approximation_error.h"

#include "core/memory_budget.h"
#include "core/parallel_for.h"
#include "layout/common/cgal_guard.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using TriangleList = std::vector<Triangle>;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, TriangleList::const_iterator>;
using AabbTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Point to_point(const Vec3& v) { return Point(v.x, v.y, v.z); }

// Fan triangles of every face (from its first corner), skipping faces with bad indices;
// face_of (optional): the face of each triangle.
TriangleList fan_triangles(const PolygonMesh& mesh, std::vector<uint32_t>* face_of = nullptr) {
  TriangleList triangles;
  triangles.reserve(mesh.num_face_vertices());
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t n = mesh.face_size(f);
    const uint32_t* v = mesh.face_begin(f);
    if (n < 3 || std::any_of(v, v + n, [&](uint32_t i) { return i >= mesh.num_vertices(); })) continue;
    mesh.for_each_fan_triangle(f, [&](uint32_t a, uint32_t b, uint32_t c) {
      Triangle t(to_point(mesh.positions[a]), to_point(mesh.positions[b]), to_point(mesh.positions[c]));
      if (t.is_degenerate()) return;
      triangles.push_back(t);
      if (face_of) face_of->push_back(uint32_t(f));
    });
  }
  return triangles;
}

// Builds `tree` (its hierarchy, not yet its search structure) with CGAL's own bounding-box and
// split functors, so the tree is the one build() makes, and reports (`stage`, `fraction`) after
// about every 2^20 primitives split: a million-triangle tree takes about a second, and the reports
// are its cancel points. A cancel's exception leaves the tree unbuilt; its owner drops it.
void build_reporting(AabbTree& tree, const TaskMonitor& monitor, const char* stage, double fraction) {
  const auto compute_bbox = tree.traits().compute_bbox_object();
  const auto split = tree.traits().split_primitives_object();
  size_t since_report = 0;
  const auto split_reporting = [&](auto first, auto beyond, const auto& bbox) {
    since_report += size_t(beyond - first);
    if (since_report >= (size_t(1) << 20)) {
      since_report = 0;
      monitor.report(stage, fraction);
    }
    split(first, beyond, bbox);
  };
  tree.custom_build(compute_bbox, split_reporting);
}

// Builds `tree`'s search structure (the KD-tree of hint points that distance queries start
// from). CGAL's own takes one point per triangle in one call, about 0.45 s on a million triangles
// without a cancel point; above 2^19 triangles the points of every k-th triangle (k = 1 + n / 2^19,
// at most about 2^19 points) are enough: a hint only bounds where a query starts, the distances and
// closest points are the tree's exact ones either way. Up to 2^19 triangles it is CGAL's own call,
// as before.
void accelerate_reporting(AabbTree& tree, const TriangleList& triangles, const TaskMonitor& monitor,
                          const char* stage, double fraction) {
  const size_t n = triangles.size(), stride = 1 + n / (size_t(1) << 19);
  if (stride == 1) {
    tree.accelerate_distance_queries();
    return;
  }
  std::vector<std::pair<Point, TriangleList::const_iterator>> hints;
  hints.reserve(n / stride + 1);
  for (size_t i = 0; i < n; i += stride) hints.emplace_back(triangles[i].vertex(0), triangles.begin() + std::ptrdiff_t(i));
  monitor.report(stage, fraction);
  tree.accelerate_distance_queries(hints.begin(), hints.end());
}

std::vector<uint32_t> nearest_faces_cgal(const PolygonMesh& mesh, const std::vector<Vec3>& points);
ApproximationError measure_approximation_error_cgal(const PolygonMesh& input, const PolygonMesh& approximation,
                                                    int samples_per_edge, const TaskMonitor& monitor, int threads);

}  // namespace

struct SurfaceDistance::Tree {
  TriangleList triangles;
  std::unique_ptr<AabbTree> tree;
};

SurfaceDistance::SurfaceDistance(const PolygonMesh& mesh, const TaskMonitor& monitor, const char* stage,
                                 double fraction)
    : tree_(std::make_unique<Tree>()) {
  check_memory_estimate(estimate_product(mesh.num_face_vertices(), 250), "building a distance tree");
  tree_->triangles = fan_triangles(mesh);
  if (tree_->triangles.empty()) return;
  monitor.report(stage, fraction);
  auto tree = std::make_unique<AabbTree>(tree_->triangles.begin(), tree_->triangles.end());
  // Built now (the tree and its search structure), so that concurrent const queries only read.
  detail::cgal_guarded("SurfaceDistance", [&] { build_reporting(*tree, monitor, stage, fraction); });
  monitor.report(stage, fraction);  // the search structure next: about as long again
  detail::cgal_guarded("SurfaceDistance", [&] { accelerate_reporting(*tree, tree_->triangles, monitor, stage, fraction); });
  tree_->tree = std::move(tree);
}

SurfaceDistance::~SurfaceDistance() = default;

bool SurfaceDistance::empty() const { return !tree_->tree; }

double SurfaceDistance::distance(const Vec3& p) const {
  if (!tree_->tree) return HUGE_VAL;
  return std::sqrt(tree_->tree->squared_distance(to_point(p)));
}

Vec3 SurfaceDistance::closest_point(const Vec3& p) const {
  if (!tree_->tree) return p;
  const auto q = tree_->tree->closest_point(to_point(p));
  return Vec3{CGAL::to_double(q.x()), CGAL::to_double(q.y()), CGAL::to_double(q.z())};
}

std::vector<uint32_t> nearest_faces(const PolygonMesh& mesh, const std::vector<Vec3>& points) {
  return detail::cgal_guarded("nearest_faces", [&] { return nearest_faces_cgal(mesh, points); });
}

ApproximationError measure_approximation_error(const PolygonMesh& input, const PolygonMesh& approximation,
                                               int samples_per_edge, const TaskMonitor& monitor, int threads) {
  return detail::cgal_guarded("measure_approximation_error", [&] {
    return measure_approximation_error_cgal(input, approximation, samples_per_edge, monitor, threads);
  });
}

namespace {

std::vector<uint32_t> nearest_faces_cgal(const PolygonMesh& mesh, const std::vector<Vec3>& points) {
  check_memory_estimate(estimate_product(mesh.num_face_vertices(), 250), "finding nearest faces");
  std::vector<uint32_t> face_of;
  const TriangleList triangles = fan_triangles(mesh, &face_of);
  std::vector<uint32_t> result(points.size(), UINT32_MAX);
  if (triangles.empty()) return result;
  AabbTree tree(triangles.begin(), triangles.end());
  tree.accelerate_distance_queries();
  for (size_t i = 0; i < points.size(); ++i)
    result[i] = face_of[size_t(tree.closest_point_and_primitive(to_point(points[i])).second - triangles.begin())];
  return result;
}

ApproximationError measure_approximation_error_cgal(const PolygonMesh& input, const PolygonMesh& approximation,
                                                    int samples_per_edge, const TaskMonitor& monitor, int threads) {
  ApproximationError result;
  // Two triangle lists and two CGAL AABB trees (~250 bytes per triangle with the KD-tree for
  // distance queries), plus the samples.
  check_memory_estimate(estimate_product(estimate_sum(input.num_face_vertices(), approximation.num_face_vertices()), 250),
                        "measuring the approximation error");
  const double diagonal = input.bounding_box().diagonal();
  const TriangleList input_triangles = fan_triangles(input);
  const TriangleList approx_triangles = fan_triangles(approximation);
  if (diagonal <= 0 || input_triangles.empty() || approx_triangles.empty()) return result;

  // Input vertices (those on a face) -> approximation.
  monitor.report("error", 0.0);
  AabbTree approx_tree(approx_triangles.begin(), approx_triangles.end());
  approx_tree.accelerate_distance_queries();
  std::vector<uint8_t> on_face(input.num_vertices(), 0);
  for (uint32_t v : input.face_vertices)
    if (v < on_face.size()) on_face[v] = 1;
  double max_distance = 0, sum = 0;
  uint64_t count = 0;
  for (size_t v = 0; v < input.num_vertices(); ++v) {
    if (!on_face[v] || !is_finite(input.positions[v])) continue;
    const double d = std::sqrt(approx_tree.squared_distance(to_point(input.positions[v])));
    max_distance = std::max(max_distance, d);
    sum += d;
    ++count;
    if ((v & 0xffff) == 0) monitor.report("error", 0.5 * double(v) / double(input.num_vertices()));
  }
  result.hausdorff_rel = max_distance / diagonal;
  result.mean_rel = count ? sum / double(count) / diagonal : 0.0;

  // Samples of the approximation -> input surface.
  monitor.report("error", 0.5);  // the input's tree takes a while on a large scan: a cancel point before it
  AabbTree input_tree(input_triangles.begin(), input_triangles.end());
  // Built now (tree and search structure) so that the worker threads' queries only read it.
  build_reporting(input_tree, monitor, "error", 0.5);
  monitor.report("error", 0.5);  // the tree, then its search structure: each ~a second on a million faces
  accelerate_reporting(input_tree, input_triangles, monitor, "error", 0.5);
  const int n = std::max(1, samples_per_edge);
  // The largest distance does not depend on the order: the triangles are split over `threads`
  // workers (progress and cancellation on the calling thread's range only).
  const size_t workers =
      std::max<size_t>(1, std::min<size_t>(size_t(resolve_threads(threads)), approx_triangles.size() / 4096));
  std::vector<double> worker_max(workers, 0.0);
  // Set when the calling thread's report throws (a cancel): the other ranges stop at their next
  // triangle instead of running to their end before run_ranges rethrows.
  std::atomic<bool> stop{false};
  run_ranges(approx_triangles.size(), workers, [&](size_t begin, size_t end, size_t w) {
    double local = 0;
    for (size_t t = begin; t < end; ++t) {
      if (w != 0 && stop.load(std::memory_order_relaxed)) return;
      const Triangle& tri = approx_triangles[t];
      for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j) {
          const double a = double(i) / n, b = double(j) / n, c = 1.0 - a - b;
          const Point p(a * tri[0].x() + b * tri[1].x() + c * tri[2].x(),
                        a * tri[0].y() + b * tri[1].y() + c * tri[2].y(),
                        a * tri[0].z() + b * tri[1].z() + c * tri[2].z());
          local = std::max(local, input_tree.squared_distance(p));
        }
      if (w == 0 && ((t - begin) & 0xfff) == 0) {
        try {
          monitor.report("error", 0.5 + 0.5 * double(t - begin) / double(std::max<size_t>(1, end - begin)));
        } catch (...) {
          stop.store(true);
          throw;
        }
      }
    }
    worker_max[w] = local;
  });
  const double max_back = *std::max_element(worker_max.begin(), worker_max.end());
  result.reverse_rel = std::sqrt(max_back) / diagonal;
  result.hausdorff_sym_rel = std::max(result.hausdorff_rel, result.reverse_rel);
  monitor.report("error", 1.0);
  return result;
}

}  // namespace

CAGEKIT_NAMESPACE_END
