// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// PiecewiseLinearLimitMesh: the limit surface sampled on a regular (u, v) grid of
// `resolution` x `resolution` quads per ptex face (two triangles each), with a bounding-volume
// hierarchy for closest-point queries. With resolution 4 its vertices are those of the level-2
// mesh C_2 of a quad cage pushed to their limit positions (thesis §7.4: the piecewise-linear
// C_k that seeds the exact search; the piecewise-linear projection of [HDD+94] for the
// reference mode of the fit). A hit returns the ptex face and the (u, v) interpolated linearly
// over the triangle.
//
// Thread-safety: const queries may run concurrently.
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/vec3.h"
#include "subdiv/subdivision_surface.h"

CAGEKIT_NAMESPACE_BEGIN

class PiecewiseLinearLimitMesh {
 public:
  struct Hit {
    uint32_t ptex_face = 0;
    double u = 0, v = 0;
    double distance = 0;  // to the piecewise-linear mesh
    Vec3 position;        // on the piecewise-linear mesh
  };
  static constexpr uint32_t kNoFace = ~0u;

  // `patch_points` from surface.patch_points(control). Hole faces are left out. Throws
  // invalid_argument for resolution < 1 and invalid_mesh when no face has a limit surface.
  // The grid is evaluated on `threads` threads.
  PiecewiseLinearLimitMesh(const SubdivisionSurface& surface, const std::vector<Vec3>& patch_points,
                           int resolution, int threads = 1);

  // The same grid for new control positions (patch points of the same surface): every grid
  // point is one stored weighted sum of patch points (its stencil, computed once), and the
  // hierarchy keeps its tree and refits its boxes. Same result as constructing anew, up to the
  // tree's shape (queries return the same closest points).
  void update(const std::vector<Vec3>& patch_points, int threads = 1);

  // The closest point; with `max_distance`, only points closer than that are looked for (a
  // faster query) and a Hit with distance = +infinity is returned when there is none. With
  // `exclude_ptex_face`, triangles of that ptex face are ignored (the closest point elsewhere).
  Hit closest_point(const Vec3& p, double max_distance = HUGE_VAL, uint32_t exclude_ptex_face = kNoFace) const;
  size_t num_triangles() const { return tri_face_.size(); }
  // The grid points on the limit surface, (resolution + 1)^2 per listed ptex face.
  const std::vector<Vec3>& grid_points() const { return grid_; }
  // Where grid point k lies: its ptex face and (u, v) = (i / resolution, j / resolution).
  void grid_point_parameters(size_t k, uint32_t& ptex_face, double& u, double& v) const {
    const size_t g = size_t(resolution_) + 1, block = k / (g * g), in_block = k % (g * g);
    ptex_face = grid_face_[block];
    u = double(in_block / g) / resolution_;
    v = double(in_block % g) / resolution_;
  }

 private:
  struct Node {
    Vec3 lo, hi;
    uint32_t first, count;  // leaf: triangles [first, first + count); inner: count = 0, first = right child
    uint32_t ptex_face;     // the ptex face of every triangle below, or kNoFace when they differ
  };
  uint32_t build(uint32_t begin, uint32_t end, const std::vector<Vec3>& corners, const std::vector<Vec3>& centroids,
                 const std::vector<Vec3>& face_centroids);
  void evaluate_grid(const std::vector<Vec3>& patch_points, int threads);
  void refit();

  int resolution_;
  std::vector<Vec3> grid_;           // (resolution + 1)^2 points per listed ptex face
  std::vector<uint32_t> grid_face_;  // ptex face of each block of grid points
  // Stencil of every grid point over the patch points: entries [stencil_offsets_[k], [k + 1]).
  std::vector<uint32_t> stencil_offsets_, stencil_points_;
  std::vector<double> stencil_weights_;
  std::vector<uint32_t> tri_face_;   // per triangle: index into grid_face_ (block)
  std::vector<uint16_t> tri_cell_;   // per triangle: 2 * (i * resolution + j) + which half
  std::vector<uint32_t> order_;      // triangles in BVH order
  std::vector<uint32_t> sorted_ptex_;  // ptex face of each triangle, in BVH order
  std::vector<Vec3> corners_;        // 3 per triangle, in BVH order
  std::vector<Node> nodes_;
  void triangle(uint32_t t, Vec3 corners[3], double uv[3][2]) const;
};

CAGEKIT_NAMESPACE_END
