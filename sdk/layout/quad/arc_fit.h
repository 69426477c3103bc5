// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Least-squares cubic of a region-boundary arc and its equidistant constraint samples (thesis
// §6.4.2-6.4.3, spec thesis-ch4-6.md §2.4-2.5).
//
// (6.1): for an arc v_0..v_m with arc-length parameters s_0 = 0, s_i = Σ_{j<i} ‖v_j − v_{j+1}‖,
// C minimises Σ_i ∫_{s_i}^{s_{i+1}} ‖L_i(t) − C(t)‖² dt (L_i the linear interpolant of the edge)
// subject to C(s_0) = v_0, C(s_m) = v_m. C is a cubic in Bernstein form over u = t / s_m, so only
// the two inner control points are unknown: a 2x2 system per coordinate (the same matrix for all
// coordinates), its right-hand side integrated exactly by 3-point Gauss-Legendre per edge.
// The same functions fit the planar pre-image C̄ in a region's LSCM domain (thesis §6.4.3) from
// the (u, v) of the arc vertices and the *3D* parameters s_i (z = 0).
//
// Samples: r = max(0, ⌈len(C) / δ⌉ − 1) interior points equidistant in arc length of C, so the
// spacing is at most δ (the spec's [J] r ≈ round(len/δ) − 1 gave arcs shorter than 1.5 δ no
// sample at all and the glued meshes a third fewer faces than Table 6.1), plus both ends: t_0 = 0, ..., t_{r+1} = s_m; c_0 = v_0 and c_{r+1} = v_m exactly.
// The samples belong to the arc, not to a region: both neighbouring regions read the same ones.
//
// Thread-safety: pure functions. Errors: invalid_argument for fewer than 2 points, non-finite
// points, a parameter vector of the wrong size or not non-decreasing, δ <= 0 or not finite.
#include <array>
#include <vector>

#include "core/vec3.h"

CAGEKIT_NAMESPACE_BEGIN

struct ArcCubic {
  std::array<Vec3, 4> control;   // Bernstein control points; control[0] = v_0, control[3] = v_m
  double parameter_length = 0.0; // s_m: C is defined on t in [0, s_m]
  Vec3 evaluate(double t) const;
  Vec3 derivative(double t) const;  // dC/dt
};

struct ArcSamples {
  std::vector<double> t;      // r + 2 parameters, t[0] = 0, t.back() = s_m, increasing
  std::vector<Vec3> position; // C(t_k), first and last exactly v_0 and v_m
};

// s_i: cumulative edge lengths of the polyline (s_0 = 0).
std::vector<double> arc_length_parameters(const std::vector<Vec3>& points);

// (6.1) with the end points fixed. A polyline of zero length gives the constant cubic.
ArcCubic fit_arc_cubic(const std::vector<Vec3>& points, const std::vector<double>& s);

// sqrt((6.1) / s_m): the RMS distance between the polyline and the cubic at equal parameters.
double arc_fit_rms(const ArcCubic& cubic, const std::vector<Vec3>& points, const std::vector<double>& s);

// Length of C (adaptive Gauss-Legendre, relative accuracy ~1e-10).
double arc_cubic_length(const ArcCubic& cubic);

// The r + 2 samples at spacing at most δ (see the header comment).
ArcSamples sample_arc_cubic(const ArcCubic& cubic, double spacing);
// The same with a given number r >= 0 of interior samples (equidistant in arc length).
ArcSamples sample_arc_cubic_count(const ArcCubic& cubic, long r);

// C̄(t_k) for a cubic fitted to other points (e.g. the arc's (u, v)) with the same parameters.
std::vector<Vec3> evaluate_at(const ArcCubic& cubic, const std::vector<double>& t);

CAGEKIT_NAMESPACE_END
