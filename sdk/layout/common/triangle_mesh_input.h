// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Input checks shared by the chapter-6 steps (segmentation, region boundaries, LSCM): they all
// take a triangle mesh and must answer a broken one with a precise Error, never a crash.
#include <cstdint>
#include <vector>

#include "core/edge_map.h"
#include "core/polygon_mesh.h"

CAGEKIT_NAMESPACE_BEGIN

// Throws Error(invalid_mesh), naming `who` and the offending face/vertex, unless the mesh has at
// least one face, every face is a triangle of three distinct in-range vertices and every
// position is finite. Zero-area triangles are allowed (callers give them zero weight).
void require_triangle_mesh(const PolygonMesh& mesh, const char* who);

// The faces of `input` fan-triangulated (v0, vk, vk+1), positions shared. Error(invalid_mesh),
// naming `who`, for bad face arrays (check_mesh_arrays) or a face with fewer than 3 vertices.
PolygonMesh fan_triangulated(const PolygonMesh& input, const char* who);

// Edge map over all faces plus, per face, its edge-adjacent faces (faces sharing an edge of any
// valence). Used for region flooding and connectivity.
struct FaceAdjacency {
  detail::EdgeMap edges;
  std::vector<uint32_t> offsets{0};  // neighbours of f: neighbours[offsets[f] .. offsets[f+1])
  std::vector<uint32_t> neighbours;
};
// Faces are neighbours across every edge but the `barriers` (sorted edge_key()s; a region border
// the host fixed): faces joined only across barriers are in different components.
void build_face_adjacency(FaceAdjacency& adjacency, const PolygonMesh& mesh,
                          const std::vector<uint64_t>& barriers = {});

// Throws Error(invalid_mesh) naming `who` when an edge has more than two faces or its two faces
// run it in the same direction (the region boundary tracing and LSCM need an oriented
// 2-manifold with boundary).
void require_oriented_manifold_edges(const detail::EdgeMap& edges, const char* who);

// Unit normal (zero for a zero-area face) and area of every triangle.
void triangle_normals_and_areas(const PolygonMesh& mesh, std::vector<Vec3>& normals, std::vector<double>& areas);

CAGEKIT_NAMESPACE_END
