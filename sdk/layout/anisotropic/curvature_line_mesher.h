// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Stage III of the anisotropic remesher (thesis §5.6, spec thesis-ch4-6.md §1.4): the output
// vertices are the intersections of the sampled lines, the edges the line pieces between
// consecutive intersections, and the faces are traced directly in 3D from a half-edge structure
// built by sorting each vertex's edges counter-clockwise in its tangent plane; concave faces and
// faces above the maximum valence are split (convex_face_partition.h).
//
// - Intersections: per input face, segments of different types (any types in faces with
//   Λ < Λ_min, and any segment against a feature or boundary line); at input vertices, every
//   pair of lines listed there. Intersections closer than merge_distance are merged.
// - Edges: consecutive distinct intersections along each line (closed lines wrap around);
//   duplicate edges are dropped, dangling and isolated vertices removed.
// - Half-edges: next(incoming from the k-th edge) = outgoing along the (k−1)-th edge in
//   counter-clockwise order, so faces run counter-clockwise about the surface normal (face on
//   the left). Boundary-line edges keep only their half-edge with the surface on the left.
// - Faces: the cycles of `next`. A cycle is rejected when it contains a removed half-edge,
//   repeats a vertex or runs clockwise about the normals; if any are rejected, the edges whose
//   two half-edges both lie on rejected cycles are deleted (the thesis's "inconsistently oriented
//   edges") and the structure is traced again (up to 4 rounds). A clockwise cycle left over is
//   the inner boundary of an annular region: it is joined to the face around it by two bridge
//   edges (two faces); one that no face contains is a fold, merged into the face across one of its
//   edges (that edge is deleted). Half-edges still on rejected cycles leave holes (`unclosed_half_edges`).
#include <cstdint>
#include <vector>

#include "core/polygon_mesh.h"
#include "core/task_monitor.h"
#include "layout/anisotropic/convex_face_partition.h"
#include "layout/anisotropic/curvature_line_sampling.h"
#include "layout/anisotropic/curvature_tensor_field.h"

CAGEKIT_NAMESPACE_BEGIN

struct LineMeshOptions {
  int max_face_valence = 5;     // >= 3 (the thesis uses 5 throughout)
  double merge_distance = 0.1;  // intersections closer than this · the sampling's min spacing merge [J]
  double confidence_threshold = 0.86602540378443865;  // Λ_min, as in the sampling
};

struct LineMesh {
  PolygonMesh mesh;
  std::vector<Vec3> vertex_normals;
  std::vector<uint32_t> vertex_face;  // an input triangle each output vertex lies on
  // Edges of the line graph that ended up in the mesh, with the type of the line they follow
  // (diagonals added by the partition are not listed).
  struct Edge {
    uint32_t a, b;
    LineType type;
  };
  std::vector<Edge> edges;
  size_t intersections = 0, merged_vertices = 0, dangling_edges_removed = 0, inconsistent_edges_removed = 0;
  size_t unclosed_half_edges = 0;
  size_t bridged_loops = 0;  // annular regions split by two bridge edges
  size_t fold_edges_removed = 0;  // edges deleted to merge folds (clockwise loops no face contains)
  PartitionStats partition;
  double seconds = 0.0;
};

// Meshes the lines of `sampling` (sample_curvature_lines on the same triangles and field).
// Errors: invalid_argument for bad options or a sampling of another mesh; cancelled.
// An empty result (no intersections) is not an error: the mesh then has no faces.
LineMesh mesh_curvature_lines(const PolygonMesh& triangles, const CurvatureField& field, const LineSampling& sampling,
                              const LineMeshOptions& options, const TaskMonitor& monitor = {});

CAGEKIT_NAMESPACE_END
