// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Counting the self-intersections of a polygon mesh (a limit surface sampled as a mesh): pairs of
// triangles (quads split along the diagonal that folds least, other polygons fan-split from
// their first corner) that intersect other than in the
// vertices and edges they share, found with CGAL's Polygon_mesh_processing::self_intersections.
#include <cstdint>

#include "core/polygon_mesh.h"

CAGEKIT_NAMESPACE_BEGIN

struct SelfIntersections {
  uint64_t pairs = 0;           // intersecting triangle pairs
  uint64_t triangles = 0;       // triangles tested
  uint64_t skipped_faces = 0;   // faces the half-edge structure could not take (non-manifold)
};

// The mesh needs valid indices. Throws Error(internal_error) when CGAL reports a failure.
SelfIntersections count_self_intersections(const PolygonMesh& mesh);

CAGEKIT_NAMESPACE_END
