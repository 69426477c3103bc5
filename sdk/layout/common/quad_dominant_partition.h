// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Quad-dominant partitioning of a planar polygon with holes (thesis §3.4): a partition into
// convex cells whose edges are polygon edges or interior diagonals of the polygon's constrained
// Delaunay triangulation (no Steiner points), minimising the score
//   omega = sum over cells of 0 (quad), 1 (pentagon), 2 (triangle), infinity (otherwise).
// Every convex cell of k vertices is a union of k-2 CDT triangles, so cells have 1-3 triangles.
#include <array>
#include <cstdint>
#include <vector>

#include "layout/common/planar_polygon.h"

CAGEKIT_NAMESPACE_BEGIN

struct PartitionOptions {
  // Faces with at most this many vertices are solved exactly (thesis: 20); larger ones first
  // fix some CDT diagonals to split the face, then solve the pieces exactly.
  int exact_vertex_limit = 20;
};

struct QuadDominantPartition {
  // Each cell lists polygon point indices counter-clockwise.
  std::vector<std::vector<uint32_t>> cells;
  int score = 0;         // omega of the partition
  bool optimal = false;  // proven optimal (always true for faces within exact_vertex_limit)
};

// `triangles` must be triangulate_polygon(polygon) (or any triangulation of it without
// Steiner points; the partition uses only its diagonals).
QuadDominantPartition partition_quad_dominant(const PolygonLoops& polygon,
                                              const std::vector<std::array<uint32_t, 3>>& triangles,
                                              const PartitionOptions& options = {});

CAGEKIT_NAMESPACE_END
