// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Smooth sectors of a mesh's vertices (thesis §8.5.2: "a vertex on a sharp feature has its
// position and normal duplicated once per adjacent smooth sector"): the faces around a vertex
// fall into sectors separated by sharp edges — edges whose two faces' normals differ by more than
// an angle, boundary edges and non-manifold edges — and every sector after the first gets a copy
// of the vertex, so each copy's averaged normal sees only the faces of its own sector.
//
// Vertex numbering is stable: a vertex keeps its index for the sector of its first corner (in
// face order); the copies are appended after the original vertices, in order of first use.
#include <cstdint>
#include <vector>

#include "core/polygon_mesh.h"

CAGEKIT_NAMESPACE_BEGIN

struct SectorSplit {
  PolygonMesh mesh;                    // same faces (same order and sizes), vertices duplicated
  std::vector<uint32_t> source_vertex; // per vertex of `mesh`: the input vertex it copies
  size_t num_input_vertices = 0;       // copies are the vertices from this index on
};

// `sharp_angle_degrees` in [0, 180]: an interior manifold edge is sharp when the angle between
// its two faces' normals is above it (faces without a normal, e.g. zero area, count as smooth).
// Faces with out-of-range or repeated indices or fewer than 3 vertices are kept as they are and
// separate nothing. Throws Error(invalid_argument) for an angle outside [0, 180] or NaN.
SectorSplit split_vertices_by_sector(const PolygonMesh& mesh, double sharp_angle_degrees);

CAGEKIT_NAMESPACE_END
