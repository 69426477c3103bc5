// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Convex partitioning of the faces traced from the curvature-line graph (thesis §5.6.2.1): a
// corner is concave when its sector normal (next edge x opposite of the incoming edge) points
// against the surface normal there; a concave face is split at the diagonal from its most
// concave corner whose two new faces score best, recursively, and faces above the maximum
// valence are split at the best-scoring diagonal the same way.
//
// Score [J] (the thesis only says it favours angles near π/2): minus the sum over the four new
// corners of (angle − π/2)², plus 0.5 for each new face that is a quad. A diagonal is valid when
// it lies inside the corner angle at both of its ends (measured in each end's tangent plane);
// crossings of the diagonal with other edges of a very non-planar face are not checked.
#include <cstdint>
#include <unordered_set>
#include <vector>

#include "core/edge_key.h"
#include "core/vec3.h"
#include "layout/common/polygon_corners.h"

CAGEKIT_NAMESPACE_BEGIN

struct PartitionStats {
  size_t concave_splits = 0, valence_splits = 0;
  size_t unresolved = 0;  // faces left concave or above the valence because no diagonal was valid
};

// Appends to `out` the convex faces (at most max_valence corners each, when possible) that
// partition the loop. positions/normals are indexed by the loop's vertex ids; max_valence >= 3.
// edges: optional set of the mesh's existing edges (key edge_key(a, b)); diagonals joining two
// vertices that are already joined are not used (they would duplicate an edge), and the
// diagonals used are added to it.
void partition_face(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                    const std::vector<uint32_t>& loop, int max_valence, std::vector<std::vector<uint32_t>>& out,
                    PartitionStats& stats, std::unordered_set<uint64_t>* edges = nullptr);

CAGEKIT_NAMESPACE_END
