// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Exact evaluation of a Catmull-Clark patch around one smooth interior extraordinary vertex
// (EV) of valence N (Stam 1998, "Exact evaluation of Catmull-Clark subdivision surfaces at
// arbitrary parameter values"; thesis §2.5-2.7), by repeated application of the local
// subdivision matrices instead of their eigen-decomposition.
//
// Layout of the 2N+8 control points of a quad face F0 with the EV at its corner, in the frame
// (s, t) of F0 with the EV at (0,0), the face's next vertex at (1,0) and its previous vertex at
// (0,1); grid point (i, j) of that frame, faces F0..F(N-1) counter-clockwise around the EV:
//   0                 the EV
//   1 + k             spoke of F_k: point (1,0) of F_k's own frame (F0's (1,0); F1's is (0,1))
//   N + 1 + k         face-diagonal point (1,1) of F_k
//   2N+1 .. 2N+7      (2,-1) (2,0) (2,1) (2,2) (1,2) (0,2) (-1,2) of F0's frame
// Points with j < 0 lie in F_(N-1), with i < 0 in F_1. The extended layout (2N+17 points, one
// level finer) appends (3,-1) (3,0) (3,1) (3,2) (3,3) (2,3) (1,3) (0,3) (-1,3).
#include <opensubdiv/far/topologyLevel.h>

#include <vector>

#include "core/cage.h"

CAGEKIT_NAMESPACE_BEGIN
namespace subdiv_detail {

// Subdivision matrices of valence N: `extended` is (2N+17) x (2N+8), row-major: the child
// points (extended layout) as combinations of the parent points; its first 2N+8 rows are the
// square subdivision matrix A. Derived by refining a small local mesh with OpenSubdiv once, so
// the rules are exactly OpenSubdiv's smooth Catmull-Clark rules.
struct StamMatrices {
  int valence = 0;
  std::vector<double> extended;
  // Extended-layout indices of the 16 B-spline points (row by row) of the child's three regular
  // sub-patches: [1,2]x[0,1], [1,2]x[1,2], [0,1]x[1,2] of the child's grid.
  int sub_points[3][16] = {};
  std::vector<double> limit;  // limit position mask over the 2N+1 ring points
  // extended * A^l for l = 0..kStoredLevels, each (2N+17) x (2N+8) row-major, one after the
  // other: an evaluation l levels below the patch costs one 16-row product instead of l
  // matrix-vector products (deeper levels continue from the last stored one).
  static constexpr int kStoredLevels = 16;
  std::vector<double> powers;
  int size() const { return 2 * valence + 8; }
};

StamMatrices build_stam_matrices(int valence);

// Gathers the 2N+8 points (level-local vertex indices) of face `face` of `level` with the EV at
// corner `corner`, or the 2N+17 extended points. Returns false, leaving `points` unspecified,
// unless the configuration is one Stam's matrices describe exactly: the EV interior, manifold,
// of valence N >= 3, without sharpness on it or its edges; F0's three other corners interior
// smooth vertices of valence 4 without sharp edges (they and the EV are the only vertices whose
// vertex rule enters the matrices); every face walked through a quad; all points distinct.
bool gather_stam_points(const OpenSubdiv::Far::TopologyLevel& level, int face, int corner, bool extended,
                        std::vector<int>* points);

// Basis weights of the 2N+8 points at (s, t) in [0,1]^2 (EV at (0,0)): w[k * (2N+8) + i] for
// k = value, d/ds, d/dt, d2/ds2, d2/dsdt, d2/dt2. At the EV itself (and within 2^-60 of it)
// the limit position mask, the limit tangent masks along s and t (scaled as the B-spline
// derivatives of a regular vertex), and zero second derivatives.
// `kinds`: how many of the six rows (value, d/ds, d/dt, d2/ds2, d2/dsdt, d2/dt2) to compute;
// the others are left 0 (1 = values only, the fast path of position-only queries).
void stam_basis(const StamMatrices& m, double s, double t, double* w, int kinds = 6);

}  // namespace subdiv_detail
CAGEKIT_NAMESPACE_END
