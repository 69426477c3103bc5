// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Segmentation connectivity (thesis §6.4.1, spec thesis-ch4-6.md §2.3): anchors, the arcs
// between them and every region's boundary loops as sequences of arcs.
//
// Anchors: vertices with >= 3 incident region-boundary edges (an edge is a region boundary when
// its two faces are in different regions or it is a mesh-border edge). For a manifold vertex this
// is the thesis's rule (>= 3 adjacent faces in distinct regions, >= 2 on the mesh border) plus
// the vertex where one pair of regions meets twice (A B A B around it), where arcs also change.
// Arcs: maximal chains of region-boundary edges between anchors; along one arc the two sides are
// constant. A chain that closes on itself (a region enclosed by one neighbour, a hole of the mesh
// inside one region, or an arc that starts and ends at the same anchor) is split into three arcs
// at one third and two thirds of its length by inserted anchors (spec [J]: "insert 2-3 artificial
// anchors"), so every arc has two distinct end anchors and a single cubic (6.1) can fit it.
// Loops: per region, the closed sequences of arcs around it with the region on the left (seen
// from the side the face normals point to): the outer boundary and one loop per hole.
//
// Thread-safety: a pure function; concurrent calls are safe.
// Errors: invalid_mesh for an invalid triangle mesh, an edge with more than two faces or two faces
// running an edge in the same direction (the loops need an oriented 2-manifold with boundary);
// invalid_argument when face_region has the wrong size or a region id >= num_regions.
#include <cstdint>
#include <vector>

#include "core/polygon_mesh.h"

CAGEKIT_NAMESPACE_BEGIN

// The "region" across a mesh-border arc.
constexpr uint32_t kMeshBorder = 0xffffffffu;

struct RegionArc {
  // Input vertices from anchor to anchor (>= 2, first != last, both anchors).
  std::vector<uint32_t> vertices;
  // left_region's faces run the arc's edges first-to-last (the region is on the left);
  // right_region is the other side, or kMeshBorder. Interior arcs have left < right.
  uint32_t left_region = 0;
  uint32_t right_region = kMeshBorder;
};

struct RegionLoop {
  std::vector<uint32_t> arcs;      // in traversal order, region on the left
  std::vector<uint8_t> reversed;   // 1 where the arc is walked last-to-first
  double length = 0.0;             // sum of the input edge lengths
};

struct RegionBoundaries {
  std::vector<uint32_t> anchors;          // vertex ids, increasing
  std::vector<uint8_t> anchor_inserted;   // per anchor: 1 when inserted to split a closed chain
  std::vector<RegionArc> arcs;
  // Per region, its boundary loops, longest first (the outer loop of a disk-like region with holes
  // is normally the longest; the LSCM domain's signed areas tell for sure).
  std::vector<std::vector<RegionLoop>> region_loops;
  // Per region: V - E + F of its faces; for an edge-connected region with b loops the genus is
  // (2 - χ - b) / 2 (0: a disk with b - 1 holes).
  std::vector<int> region_euler_characteristic;

  bool is_anchor(uint32_t vertex) const;
  int region_genus(uint32_t region) const {
    return (2 - region_euler_characteristic[region] - int(region_loops[region].size())) / 2;
  }
  // The input vertices of a loop in traversal order (each shared anchor once; closed, the first
  // vertex is not repeated at the end).
  std::vector<uint32_t> loop_vertices(const RegionLoop& loop) const;
};

// Splits arc `arc` at its interior vertex `index` (0 < index < vertices.size() - 1), which
// becomes an inserted anchor: the arc keeps vertices [0, index], a new arc (appended) takes
// [index, end], and every loop that uses the arc uses both pieces in its order. Used when a single
// cubic fits an arc poorly (spec §2.4 [J]). Error(invalid_argument) for a bad arc or index.
void split_arc(RegionBoundaries& boundaries, uint32_t arc, size_t index);

RegionBoundaries compute_region_boundaries(const PolygonMesh& triangles, const std::vector<uint32_t>& face_region,
                                           size_t num_regions);

CAGEKIT_NAMESPACE_END
