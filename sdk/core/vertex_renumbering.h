// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// renumber_vertices: the same mesh with its vertices in another order (vertex k of the result is
// vertex order[k] of the input; faces remapped, face order and corner order kept). Used to apply
// the CPU deformer's write order (multires/deformer_vertex_order.h) to a scan.
#include <cstdint>
#include <vector>

#include "core/polygon_mesh.h"

CAGEKIT_NAMESPACE_BEGIN

// Throws Error(invalid_argument) when `order` is not a permutation of the mesh's vertices (wrong
// length, an index out of range or twice), and Error(invalid_mesh) when a face refers to a vertex
// out of range.
PolygonMesh renumber_vertices(const PolygonMesh& mesh, const std::vector<uint32_t>& order);

CAGEKIT_NAMESPACE_END
