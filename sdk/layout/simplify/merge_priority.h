// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Error terms and priorities of the face-merge simplifier (thesis §3.3.3, (3.2)-(3.8)).
// Private to sdk/layout. All quantities are in NORMALISED units: positions translated to the
// bounding-box centre and divided by the bounding-box diagonal, so every priority is
// independent of the model's units (see README.md).
#include <cmath>
#include <cstdint>

#include "core/angles.h"
#include "core/vec3.h"

CAGEKIT_NAMESPACE_BEGIN
namespace detail {

// Area moments of a set of triangles: area, first moment (integral of x) and the symmetric
// second moment (integral of x x^T: xx, yy, zz, xy, xz, yz). The integral of the squared
// signed distance to any plane is a quadratic form of these, so L2 (3.2)/(3.3) of a merge
// candidate over both faces' lifted CDTs costs O(1) once each face's CDT moments are cached.
struct AreaMoments {
  double area = 0;
  Vec3 first;
  double second[6] = {0, 0, 0, 0, 0, 0};

  void add_triangle(const Vec3& a, const Vec3& b, const Vec3& c);
  // Removes what add_triangle(a, b, c) adds (the moments of a region that loses that triangle).
  void subtract_triangle(const Vec3& a, const Vec3& b, const Vec3& c);
  AreaMoments& operator+=(const AreaMoments& o);
  // Integral over the triangles of (dot(n, x - origin))^2 dA, clamped to >= 0. Equals the sum
  // of (3.2) over the triangles (exact integral of the squared signed distance).
  double squared_distance_integral(const Vec3& origin, const Vec3& unit_normal) const;
};

// (3.2) written out for one triangle: (1/6)(d0^2+d1^2+d2^2+d0d1+d0d2+d1d2)|t|.
double triangle_l2(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& origin, const Vec3& unit_normal);

// (3.4): sigma_j |N_j - N'|^2 + sigma_k |N_k - N'|^2.
double l21_term(double sigma_j, const Vec3& n_j, double sigma_k, const Vec3& n_k, const Vec3& n_merged);

// (3.6): (1/3) |v_j - v_l| d^2, d = distance of v_k to the segment v_j v_l.
double boundary_vertex_l2(const Vec3& vj, const Vec3& vk, const Vec3& vl);

// Inner angle at `v` of a face whose region lies to the left of prev -> v -> next about
// `unit_normal` (vectors projected into the plane), in [0, 2 pi).
// Inline (hot in the simplifier's candidate evaluation); no FMA contraction is enabled, so the
// result is the same bits as an out-of-line call.
inline double inner_angle(const Vec3& prev, const Vec3& v, const Vec3& next, const Vec3& n) {
  Vec3 a = prev - v, b = next - v;
  a -= n * dot(a, n);
  b -= n * dot(b, n);
  double theta = std::atan2(dot(n, cross(b, a)), dot(b, a));
  if (theta < 0) theta += 2.0 * kPi;
  return theta;
}

// (3.5) with the tie-break factors (3.8):
// E = (1 + L2)(1 + L2,1)(1 + eps (m - 4)^2)(1 + eps * angle_sum), angle_sum = sum (alpha_q - pi/2)^2.
double merge_priority(double l2, double l21, uint64_t valence, double angle_sum, double epsilon);

// Rounds a priority to 40 significant bits so that candidates whose priorities differ only by
// floating-point noise (e.g. after scaling the model) compare equal and fall to the
// deterministic tie-break by element ids.
double quantize_priority(double e);

}  // namespace detail
CAGEKIT_NAMESPACE_END
