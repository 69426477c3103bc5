// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Element shape measure of the quad-dominant remeshing (thesis §6.6.2, spec thesis-ch4-6.md
// §2.7-2.8): (6.4)-(6.8) for quads, (6.9) for triangles and pentagons, T-joints, concave faces.
// Angles and lengths are those of the straight polygon of the face's vertices (what is output).
//
// rate_element(polygon) for a counter-clockwise polygon of n vertices:
// - n < 3, or signed area <= 0 (a flipped face, or the clockwise cycle around a hole that no
//   curve reaches): `invalid` (the thesis rejects such configurations; a finite penalty keeps
//   descent possible from an invalid start).
// - a concave vertex (γ > π + t_joint_tolerance): split by the diagonal from the most concave
//   vertex that lies inside the face and whose two parts, rated unsplit, cost least; the parts
//   are split again the same way (§6.6.1 "after splitting all concave faces"; the thesis gives
//   no split rule).
// - n > 4 with k vertices within t_joint_tolerance of π (k < n − 2, those closest to π first):
//   rated as the (n − k)-gon without them, plus k·w_T.
// - 4: E_q (6.8). 3 / 5: w·(offset + E_a) with (6.9) E_a = Σ|γ_i − β|, β = π/3 / 3π/5; offset 1
//   is the spec's fix (taken literally, offset 0, an equilateral triangle costs nothing whatever
//   the weight). n >= 6 after T-joints: w_PT·(offset + E_a(β = (n−2)π/n)) + high_valence·(n − 5)
//   (the thesis: "penalized by high values", not quantified).
//
// Thread-safety: pure functions. No errors: degenerate polygons get the `invalid` penalty.
#include <array>
#include <cstdint>
#include <vector>

#include "layout/quad/quad_curve_network.h"

CAGEKIT_NAMESPACE_BEGIN

struct QuadEnergyTerms {
  double orthogonality = 0.0;  // (6.4) E⊥
  double parallelism = 0.0;    // (6.5) E∥
  double rhombus = 1.0;        // (6.6) E◇
  double rectangle = 1.0;      // (6.7) E▭
  double total = 0.0;          // (6.8) E_q
};

struct ElementWeights {
  double triangle = 40.0;   // w△
  double pentagon = 40.0;   // w_PT
  double t_joint = 100.0;   // w_T
  double t_joint_tolerance = 0.3490658503988659;  // π/9: |γ − π| below it is a T-joint (and not concave)
  double polygon_offset = 1.0;     // see the file comment
  double high_valence = 1000.0;    // per vertex above 5
  double invalid = 1e6;            // flipped face, hole cycle, fewer than 3 vertices
};

// Internal angles of a counter-clockwise polygon, each in [0, 2π).
std::vector<double> interior_angles(const std::vector<Vec2>& polygon);
QuadEnergyTerms quad_energy_terms(const std::array<Vec2, 4>& quad);
// (6.9) without weight.
double angle_deviation_energy(const std::vector<Vec2>& polygon, double beta);

struct ElementRating {
  double energy = 0.0;
  // The output faces: the polygon itself, or its concave split; indices into the polygon.
  std::vector<std::vector<uint32_t>> pieces;
  uint32_t t_joints = 0;   // over all pieces
  bool invalid = false;
};
ElementRating rate_element(const std::vector<Vec2>& polygon, const ElementWeights& weights);
// rate_element(polygon, weights).energy without listing the pieces (the selection's inner loop).
double element_energy(const std::vector<Vec2>& polygon, const ElementWeights& weights);

CAGEKIT_NAMESPACE_END
