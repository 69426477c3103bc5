// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Vertex renumbering, in the two directions callers have their maps in:
// - remap_vertices scatters: vertex v of the mesh becomes vertex new_index[v] (several vertices
//   may become one: repair's weld); keep_vertices compacts (repair's cleanup steps);
// - renumber_vertices gathers: vertex k of the result is vertex order[k] of the input (a
//   permutation: the CPU deformer's write order, multires/deformer_vertex_order.h).
// Faces are remapped; face order and corner order are kept.
#include <cstdint>
#include <vector>

#include "core/polygon_mesh.h"

CAGEKIT_NAMESPACE_BEGIN

// Vertex v becomes new_index[v] (0xffffffff: removed, and no face may use it); when several
// vertices get the same new index the position of the first one is kept. Out-of-range face
// indices stay out of range (shifted with the vertex count). No checks: new_index has one entry
// per vertex, each < new_count or 0xffffffff.
void remap_vertices(PolygonMesh& mesh, const std::vector<uint32_t>& new_index, size_t new_count);

// Keeps the vertices v with keep[v] != 0, in their order, and removes the others (no face may
// use a removed vertex; out-of-range face indices stay out of range, shifted). Returns how many
// were removed. `keep` has one entry per vertex.
size_t keep_vertices(PolygonMesh& mesh, const std::vector<uint8_t>& keep);

// Throws Error(invalid_argument) when `order` is not a permutation of the mesh's vertices (wrong
// length, an index out of range or twice), and Error(invalid_mesh) when a face refers to a vertex
// out of range.
PolygonMesh renumber_vertices(const PolygonMesh& mesh, const std::vector<uint32_t>& order);

CAGEKIT_NAMESPACE_END
