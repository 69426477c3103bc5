// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Minimum-bending-energy cubic Bézier between two constrained points of a region's parameter
// plane (thesis §6.5, (6.2)-(6.3); spec thesis-ch4-6.md §2.6): the candidate curves of the quad
// remesher's curve network (quad_curve_network.h).
//
// (6.2): b(t) = c_i B0 + (c_i + λ q_i) B1 + (c_j + μ q_j) B2 + c_j B3 with unit tangents q_i, q_j
// and the chord in front of both. (6.3): E(λ, μ) = ∫₀¹ κ²(t) dt (over the curve parameter, as
// printed; the arc-length version ∫κ² ds has no minimiser for a U-turn: it decreases as the
// curve grows) is minimised for λ, μ ≥ λ_min = 1e-3·|c_j − c_i| (at λ = 0 the curvature is
// singular at t = 0) by an 8×8 log-spaced grid over [0.03, 1.8]·|c_j − c_i| and a compass search
// from its 3 best local minima and from (a·|X − c_i|, b·|X − c_j|), (a, b) = (0.95, 0.1),
// (0.1, 0.95), (0.67, 0.67), where the tangent lines meet at X in front of both points; a trial
// point whose control legs [c_i, c_i + λ q_i] and [c_j, c_j + μ q_j] touch is ignored (so the legs
// of the result never cross). Facing collinear tangents (E ≡ 0) get λ = μ = |c_j − c_i|/3.
//
// Known limit (measured 2026-12-07, README "Tried and not kept"): this search misses the lowest
// basin for about one pair in nine on real networks (a search seeded from the minima of nearby
// tangent angles found a lower E by more than 1e-3 relative on 11 % of blobby.off's 10,000 pairs).
//
// Thread-safety: pure functions. Errors: none; coincident points, or no trial point with
// uncrossed legs, give valid = false.
#include <array>

#include "core/vec2.h"

CAGEKIT_NAMESPACE_BEGIN

struct CubicBezier2 {
  std::array<Vec2, 4> control;
  Vec2 eval(double t) const;
  Vec2 derivative(double t) const;
  Vec2 second_derivative(double t) const;
};

// (6.2): b(t) = c_i B0 + (c_i + λ q_i) B1 + (c_j + μ q_j) B2 + c_j B3.
CubicBezier2 connecting_bezier(const Vec2& ci, const Vec2& qi, const Vec2& cj, const Vec2& qj, double lambda,
                               double mu);
// (6.3) by composite 4-point Gauss-Legendre over `intervals` equal pieces of [0, 1]; +inf where
// b' vanishes at a node.
double bending_energy(const CubicBezier2& curve, int intervals = 8);

struct BendingFit {
  double lambda = 0.0, mu = 0.0, energy = 0.0;
  int evaluations = 0;
  bool valid = false;  // false: every trial point had crossing legs
};
// Minimum of (6.3) over λ, μ (see the file comment). q_i and q_j must be unit vectors.
BendingFit minimize_bending_energy(const Vec2& ci, const Vec2& qi, const Vec2& cj, const Vec2& qj);

CAGEKIT_NAMESPACE_END
