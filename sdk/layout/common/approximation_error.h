// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Distances between an input mesh and its approximation (a simplified level or a cage's
// control mesh), relative to the input's bounding-box diagonal — the definitions used by
// ../shared/spec/peer-measurements.md so CageKit's numbers compare with the peers'.
#include <cstdint>
#include <memory>
#include <vector>

#include "core/polygon_mesh.h"
#include "core/task_monitor.h"

CAGEKIT_NAMESPACE_BEGIN

struct ApproximationError {
  // Largest distance from an input vertex that belongs to a face to the approximation's
  // triangles (polygons fan-split from their first corner), / input bbox diagonal.
  double hausdorff_rel = 0;
  // max(hausdorff_rel, largest distance from sample points of the approximation — its vertices,
  // edge midpoints and a barycentric grid on each triangle — to the input surface) / diagonal.
  double hausdorff_sym_rel = 0;
  // Mean input-vertex distance / diagonal.
  double mean_rel = 0;
  // The approximation -> input direction alone: largest distance from the approximation's
  // samples to the input surface / diagonal (hausdorff_sym_rel = max of this and hausdorff_rel).
  double reverse_rel = 0;
};

// Both meshes need valid indices; faces with fewer than 3 vertices are ignored. `threads`: worker
// threads of the approximation -> input samples (0: std::thread::hardware_concurrency()); the
// result does not depend on it.
ApproximationError measure_approximation_error(const PolygonMesh& input, const PolygonMesh& approximation,
                                               int samples_per_edge = 4, const TaskMonitor& monitor = {},
                                               int threads = 0);

// Distances from points to a mesh's surface (polygons fan-split from their first corner,
// degenerate triangles and faces with bad indices skipped): one CGAL AABB tree, built once.
// Thread-safety: distance() may be called from any number of threads at once.
class SurfaceDistance {
 public:
  // Builds the tree on the calling thread, reporting (`stage`, `fraction`) to `monitor` about every
  // 2^20 triangles sorted and before the search structure: its cancel points on a large mesh
  // (Error(cancelled) leaves nothing behind).
  explicit SurfaceDistance(const PolygonMesh& mesh, const TaskMonitor& monitor = {}, const char* stage = "distance",
                           double fraction = 0.0);
  ~SurfaceDistance();
  SurfaceDistance(const SurfaceDistance&) = delete;
  SurfaceDistance& operator=(const SurfaceDistance&) = delete;
  // True when the mesh has no non-degenerate triangle (distance() is then +infinity).
  bool empty() const;
  double distance(const Vec3& p) const;
  // The point of the mesh closest to p (p itself when the mesh is empty).
  Vec3 closest_point(const Vec3& p) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

// For each point, the face of `mesh` (polygons fan-split from their first corner) nearest to it,
// or UINT32_MAX when the mesh has no non-degenerate triangle. One CGAL AABB tree over the mesh.
std::vector<uint32_t> nearest_faces(const PolygonMesh& mesh, const std::vector<Vec3>& points);

CAGEKIT_NAMESPACE_END
