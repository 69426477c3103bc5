// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Counting the self-intersections of a polygon mesh (a limit surface sampled as a mesh): pairs of
// triangles (quads split along the diagonal that folds least, other polygons fan-split from
// their first corner) that intersect other than in the
// vertices and edges they share, found with CGAL's Polygon_mesh_processing::self_intersections.
#include <cstdint>

#include "core/polygon_mesh.h"
#include "core/task_monitor.h"

CAGEKIT_NAMESPACE_BEGIN

struct SelfIntersections {
  uint64_t pairs = 0;           // intersecting triangle pairs
  uint64_t triangles = 0;       // triangles tested
  uint64_t skipped_faces = 0;   // faces the half-edge structure could not take (non-manifold)
};

// The mesh needs valid indices. Throws Error(internal_error) when CGAL reports a failure.
// `monitor` (optional) gets `stage` reports at least every ~0.1 s of the count (a 1M-triangle scan
// takes seconds), its fraction the share of the boxes' candidate pairs tested so far as far as it can
// be known (the box pass's pairs are not known ahead: it reaches 1 only at the end); a cancel there
// throws Error(cancelled) from inside the box pass.
SelfIntersections count_self_intersections(const PolygonMesh& mesh, const TaskMonitor* monitor = nullptr,
                                           const char* stage = "self-intersections");

CAGEKIT_NAMESPACE_END
