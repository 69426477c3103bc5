// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Quality figures of a remeshed polygon mesh, shared by the remeshers (anisotropic_remesher.h,
// quad_remesher.h) and reported by the C API and `cagekit remesh`.
#include <cstdint>
#include <vector>

#include "core/polygon_mesh.h"

CAGEKIT_NAMESPACE_BEGIN

struct RemeshQuality {
  uint64_t faces = 0, vertices = 0, quads = 0;
  uint64_t interior_vertices = 0, valence4_vertices = 0;  // interior: not on a boundary edge
  uint32_t max_face_valence = 0, max_vertex_valence = 0;  // vertex valence: incident edges
  // min sin(corner angle) over corners (T-joints, within 10° of π, excluded); < 0: a concave corner.
  double min_scaled_jacobian = 0.0;
};

// `vertex_normals` (per vertex of `mesh`) orient the corner angles (corner_angle in
// convex_face_partition.h). Indices must be in range.
RemeshQuality measure_remesh_quality(const PolygonMesh& mesh, const std::vector<Vec3>& vertex_normals);

CAGEKIT_NAMESPACE_END
