// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Curvature tensor field of a triangle mesh (thesis ch. 5, Stage I; spec thesis-ch4-6.md §1.2):
// edge tensors (5.1), vertex tensors averaged over geodesic disks trimmed by feature curves
// (5.2), barycentric interpolation (5.3), eigen-decomposition with the swapped pairing
// (5.4)-(5.6), flattening into a face's unfolding (5.7), direction-coherence confidence (5.8),
// confidence-weighted smoothing (5.9) and the frame re-alignment of §5.4.1.1.
//
// Conventions (thesis (5.6)): |k_min| <= |k_max|; t_min is the eigenvector of T paired with
// k_max and is the direction of minimum curvature (the axis of a cylinder); t_max = n x t_min.
#include <array>
#include <cstdint>
#include <vector>

#include "core/polygon_mesh.h"
#include "core/task_monitor.h"

CAGEKIT_NAMESPACE_BEGIN

struct CurvatureOptions {
  // Radius r of the geodesic disk of (5.2), in mean edge lengths of the input [J]. The CSM03
  // estimate needs a disk spanning several edges: below ~2 edge lengths it is dominated by
  // which edges happen to cross the disk. Used when disk_radius_bbox <= 0.
  double disk_radius = 3.0;
  // When > 0: r = disk_radius_bbox * bounding-box diagonal instead (the thesis's setting:
  // 0.01 for Buddha and Rocker Arm, 0.005 for David).
  double disk_radius_bbox = 0.0;
  // Edges whose faces' normals differ by more than this are feature edges (trim the disks, zero
  // tensor); < 0: no detection (host-given features only). Must be <= 180.
  double feature_angle_degrees = -1.0;
  // Iterations of the confidence-weighted Laplacian (5.9); 0 = no smoothing.
  int smoothing_iterations = 5;
  // Worker threads for the vertex tensors (0 = hardware concurrency). Results do not depend on it.
  int threads = 1;
};

struct CurvatureField {
  // Symmetric 3x3 tensor stored as xx, yy, zz, xy, xz, yz.
  using Tensor = std::array<double, 6>;

  // Per vertex, after smoothing and re-alignment (§5.4.1.1): the filtered tensor T(v) (the one
  // (5.3) interpolates), unit normal n (area-weighted mean of the adjacent face normals), unit
  // tangent principal directions t_min, t_max = n x t_min, the curvatures (|k_min| <= |k_max|,
  // signed: > 0 where the surface bends away from n, i.e. convex for outward normals), and the
  // confidence Λ(v) of (5.8) (mean of the adjacent faces' Λ(f); 0 for isolated vertices).
  std::vector<Tensor> vertex_tensor;
  std::vector<Vec3> vertex_normal, vertex_t_min, vertex_t_max;
  std::vector<double> vertex_k_min, vertex_k_max, vertex_confidence;

  // Per face: the tensor (5.3) at the centroid (u = v = w = 1/3), decomposed against the face
  // normal like a vertex tensor, and Λ(f) of (5.8) from the final vertex directions.
  std::vector<Tensor> face_tensor;
  std::vector<Vec3> face_t_min, face_t_max;
  std::vector<double> face_k_min, face_k_max, face_confidence;

  // The unsmoothed estimate (5.2) per vertex (before (5.9)), its t_min and the per-face
  // confidence of that estimate: kept for inspection and tests.
  std::vector<Tensor> raw_vertex_tensor;
  std::vector<Vec3> raw_vertex_t_min;
  std::vector<double> raw_face_confidence;

  // Per corner (size num_face_vertices): 1 where the corner's edge was treated as a feature
  // (detected, host-given, boundary, non-manifold or inconsistently oriented).
  std::vector<uint8_t> barrier_edges;
  double disk_radius = 0.0;  // r actually used, in model units
};

// Estimates the field on a triangle mesh. host_feature_edges: optional per-corner flags
// (size num_face_vertices; flags[c] != 0 tags the edge of corner c's half-edge), combined
// with the detected ones. Errors (Error, never abort): invalid_mesh for non-triangle faces,
// out-of-range indices, repeated vertices in a face, non-finite positions, an empty mesh;
// invalid_argument for bad options or a flag array of the wrong size; cancelled from the monitor.
// Edges of valence != 2 and edges whose two faces traverse them in the same direction are
// barriers with zero tensor; zero-area faces contribute no bending and no area.
CurvatureField estimate_curvature_field(const PolygonMesh& triangles, const CurvatureOptions& options,
                                        const std::vector<uint8_t>* host_feature_edges = nullptr,
                                        const TaskMonitor& monitor = {});

// T(p) of (5.3) at barycentric (u, v, w) of face f (weights of its corners 0, 1, 2).
CurvatureField::Tensor interpolate_tensor(const PolygonMesh& triangles, const CurvatureField& field, uint32_t face,
                                          double u, double v, double w);

// Flattening (5.7) into the isometric unfolding of one face: corner 0 at (0, 0), corner 1 on the
// +u axis, corner 2 at v > 0 (the unfolding keeps the face's orientation). For each corner:
// t̄_min (unit, 2D) and T̄ = Q̄ diag(k_min, k_max) Q̄ᵀ with Q̄ = [t̄_max | t̄_min], t̄_max = rot(t̄_min, π/2).
struct FlattenedFace {
  std::array<std::array<double, 2>, 3> corner;     // unfolded positions
  std::array<std::array<double, 2>, 3> t_min;      // flattened min directions
  std::array<std::array<double, 3>, 3> tensor;     // T̄ per corner as (uu, vv, uv)
};
FlattenedFace flatten_face(const PolygonMesh& triangles, const CurvatureField& field, uint32_t face);

CAGEKIT_NAMESPACE_END
