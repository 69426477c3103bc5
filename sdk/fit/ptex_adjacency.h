// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// PtexAdjacency: which ptex face lies across each side of each ptex face of a cage, and the
// parameter transfer across that side (the "hopping" of the closest-point search, thesis §7.4
// case 3).
//
// OpenSubdiv's ptex convention: a quad face is one ptex face with (0,0) at its first vertex,
// u towards the second and v towards the last; an n-gon (n != 4) has n ptex faces, the one of
// corner k with (0,0) at vertex k, (1,0) at the midpoint of edge (k, k+1), (1,1) at the face
// centre and (0,1) at the midpoint of edge (k-1, k). Sides: 0: v = 0, 1: u = 1, 2: v = 1,
// 3: u = 0; along a side, the varying coordinate is its parameter. The limit surface's
// parameterisation along a shared cage edge is the same (uniform) from both faces, so the
// transfer is affine: a quad's side covers a whole cage edge, an n-gon ptex face's outer side
// half of one.
//
// Thread-safety: const after construction.
#include <cstdint>
#include <vector>

#include "core/polygon_mesh.h"
#include "subdiv/subdivision_surface.h"

CAGEKIT_NAMESPACE_BEGIN

class PtexAdjacency {
 public:
  // `surface` must be the surface of a cage with this mesh; it tells the ptex numbering and
  // which ptex faces are holes (never entered).
  PtexAdjacency(const PolygonMesh& cage, const SubdivisionSurface& surface);

  // (face, u, v) lies on `side` of `face` (u or v on the side's value). Moves it to the same
  // point of the ptex face across that side and returns the side of the new face it arrived on;
  // returns -1 and leaves the arguments unchanged on an open boundary (no neighbour, a hole
  // face, or a non-manifold edge with no unique neighbour).
  int transfer(uint32_t& face, double& u, double& v, int side) const;

  // The cage edge (its edge_key()) that `side` of ptex `face` runs along, or kNoEdge for the
  // spokes of an n-gon's ptex face (its sides 1 and 2) and for arguments out of range.
  static constexpr uint64_t kNoEdge = ~uint64_t(0);
  uint64_t cage_edge(uint32_t face, int side) const;

 private:
  struct Side {
    uint64_t line = 0;  // cage edge (edge_key()) or face spoke (1 << 63 | corner)
    double offset = 0, scale = 0;  // line parameter = offset + scale * side parameter
  };
  std::vector<Side> sides_;  // 4 per ptex face
  // Sides sorted by line, for the lookup of the other sides on a line.
  std::vector<uint64_t> sorted_lines_;
  std::vector<uint32_t> sorted_sides_;  // 4 * face + side
  std::vector<bool> hole_;
  std::vector<uint32_t> base_face_;  // per ptex face
};

CAGEKIT_NAMESPACE_END
