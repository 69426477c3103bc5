// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Quality figures of a remeshed output against its input, shared by the remeshers' reports and
// tests/bench/bench_remesh (one definition for CageKit's and a peer's output):
// - polygon_mesh_figures: faces, quads, vertex valences (valence = number of distinct edges at a
//   vertex; interior = not on an edge used by one face only);
// - measure_feature_alignment: the share of the input's sharp edges that an output edge follows;
// - measure_remesh_quality: the figures the remeshers report (quad_remesher.h,
//   anisotropic_remesher.h; the C API's cagekit_remesh_quality), counts plus the scaled Jacobian.
#include <array>
#include <cstdint>
#include <vector>

#include "core/polygon_mesh.h"

CAGEKIT_NAMESPACE_BEGIN

// The counts every figure set below starts from.
struct PolygonMeshCounts {
  uint64_t faces = 0, vertices = 0, quads = 0;
  uint64_t interior_vertices = 0, valence4_vertices = 0;  // interior: not on a boundary edge
  uint32_t max_face_valence = 0, max_vertex_valence = 0;  // vertex valence: incident edges
  double quads_pct() const { return faces ? 100.0 * double(quads) / double(faces) : 0.0; }
  double valence4_pct() const {
    return interior_vertices ? 100.0 * double(valence4_vertices) / double(interior_vertices) : 0.0;
  }
};

struct PolygonMeshFigures : PolygonMeshCounts {
  // The mesh's distinct undirected edges (a < b) and how many face sides use each.
  std::vector<std::array<uint32_t, 2>> edges;
  std::vector<uint32_t> edge_uses;
};

// Faces need valid indices (< num_vertices). Vertices on no face count neither as interior nor
// as boundary vertices.
PolygonMeshFigures polygon_mesh_figures(const PolygonMesh& mesh);

struct RemeshQuality : PolygonMeshCounts {
  // min sin(corner angle) over corners (T-joints, within 10° of π, excluded); < 0: a concave corner.
  double min_scaled_jacobian = 0.0;
};

// The counts of polygon_mesh_figures plus the scaled Jacobian; `vertex_normals` (per vertex of
// `mesh`) orient the corner angles (corner_angle in polygon_corners.h). Indices must be in
// range. `figures`: polygon_mesh_figures(mesh) when the caller has them already (else computed).
RemeshQuality measure_remesh_quality(const PolygonMesh& mesh, const std::vector<Vec3>& vertex_normals,
                                     const PolygonMeshFigures* figures = nullptr);

struct FeatureAlignment {
  uint64_t sharp_edges = 0;  // distinct input edges flagged sharp
  uint64_t followed = 0;     // ... whose midpoint lies within delta / 4 of an output edge
  double delta = 0.0;        // mean output edge length (model units)
  double share() const { return sharp_edges ? double(followed) / double(sharp_edges) : 1.0; }
};

// input: a mesh whose faces have valid indices; sharp_corners: per-corner flags as
// detect_feature_edges returns them (size input.num_face_vertices()); output: a polygon mesh in
// the same units. An edge counts once however many of its corners are flagged.
FeatureAlignment measure_feature_alignment(const PolygonMesh& input, const std::vector<uint8_t>& sharp_corners,
                                           const PolygonMesh& output);

CAGEKIT_NAMESPACE_END
