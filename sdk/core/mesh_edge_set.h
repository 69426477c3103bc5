// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The undirected edges of a polygon mesh, for the one rule every layer applies to crease tags
// (thesis §2.2.1): a crease names an edge of the cage's mesh. validate_cage, the limit surface's
// input check (subdiv/cage_input_check) and cagekit_cage_set_creases all ask this set; each
// reports a miss in its own terms (a validation record, invalid_mesh, invalid_argument).
// Thread-safety: immutable after construction.
#include <cstdint>
#include <vector>

#include "core/polygon_mesh.h"

CAGEKIT_NAMESPACE_BEGIN

class MeshEdgeSet {
 public:
  // Every pair of cyclically consecutive vertices of every face. O(n log n) in the face vertices.
  explicit MeshEdgeSet(const PolygonMesh& mesh);

  // True when (a, b), in either order, is an edge of the mesh; never for a == b.
  bool contains(uint32_t a, uint32_t b) const;

 private:
  std::vector<uint64_t> keys_;  // sorted, unique edge_key()s
};

CAGEKIT_NAMESPACE_END
