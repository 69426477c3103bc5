// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The per-vertex "distance to the scan" of a drawn surface (a cage's tessellated limit surface,
// or a mesh), two-sided:
//   d(v) = max( distance from vertex v to the scan's surface,
//               max over the scan vertices s whose nearest triangle of the drawn surface has v as
//               a corner of the distance from s to the drawn surface ).
// So max_v d(v) is the two-sided (symmetric) vertex-to-surface Hausdorff distance between the
// drawn surface and the scan, and a spike of either surface away from the other shows up at the
// vertices where it is. Exact point-to-triangle distances (CGAL AABB trees of
// layout/common/approximation_error.h; no CGAL in this translation unit).
#include <vector>

#include "core/polygon_mesh.h"
#include "core/task_monitor.h"

CAGEKIT_NAMESPACE_BEGIN

// `surface`: the drawn surface as a triangle mesh. Returns one value per surface vertex.
std::vector<double> two_sided_distance_to_scan(const PolygonMesh& surface, const PolygonMesh& scan,
                                               const TaskMonitor& monitor = {});

CAGEKIT_NAMESPACE_END
