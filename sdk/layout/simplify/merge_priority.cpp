// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/simplify/merge_priority.h"

#include <algorithm>
#include <cmath>
#include <cstring>

CAGEKIT_NAMESPACE_BEGIN
namespace detail {

void AreaMoments::add_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double t = 0.5 * norm(cross(b - a, c - a));
  if (!(t > 0)) return;
  area += t;
  const Vec3 s = a + b + c;
  first += s * (t / 3.0);
  // Integral of x_i x_j over a triangle: |t|/12 (sum_v v_i v_j + s_i s_j).
  const double w = t / 12.0;
  const Vec3* v[3] = {&a, &b, &c};
  double m[6] = {s.x * s.x, s.y * s.y, s.z * s.z, s.x * s.y, s.x * s.z, s.y * s.z};
  for (const Vec3* p : v) {
    m[0] += p->x * p->x;
    m[1] += p->y * p->y;
    m[2] += p->z * p->z;
    m[3] += p->x * p->y;
    m[4] += p->x * p->z;
    m[5] += p->y * p->z;
  }
  for (int i = 0; i < 6; ++i) second[i] += w * m[i];
}

void AreaMoments::subtract_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  AreaMoments t;
  t.add_triangle(a, b, c);
  area -= t.area;
  first = first - t.first;
  for (int i = 0; i < 6; ++i) second[i] -= t.second[i];
}

AreaMoments& AreaMoments::operator+=(const AreaMoments& o) {
  area += o.area;
  first += o.first;
  for (int i = 0; i < 6; ++i) second[i] += o.second[i];
  return *this;
}

double AreaMoments::squared_distance_integral(const Vec3& origin, const Vec3& n) const {
  // int (n.x - c)^2 = n^T S2 n - 2 c n.S1 + c^2 A, c = n.origin.
  const double q = n.x * n.x * second[0] + n.y * n.y * second[1] + n.z * n.z * second[2] +
                   2.0 * (n.x * n.y * second[3] + n.x * n.z * second[4] + n.y * n.z * second[5]);
  const double c = dot(n, origin);
  const double r = q - 2.0 * c * dot(n, first) + c * c * area;
  return r > 0 ? r : 0.0;
}

double triangle_l2(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& origin, const Vec3& n) {
  const double d0 = dot(a - origin, n), d1 = dot(b - origin, n), d2 = dot(c - origin, n);
  const double area = 0.5 * norm(cross(b - a, c - a));
  return (d0 * d0 + d1 * d1 + d2 * d2 + d0 * d1 + d0 * d2 + d1 * d2) * area / 6.0;
}

double l21_term(double sigma_j, const Vec3& n_j, double sigma_k, const Vec3& n_k, const Vec3& n_merged) {
  const Vec3 a = n_j - n_merged, b = n_k - n_merged;
  return sigma_j * dot(a, a) + sigma_k * dot(b, b);
}

double boundary_vertex_l2(const Vec3& vj, const Vec3& vk, const Vec3& vl) {
  const Vec3 s = vl - vj;
  const double len2 = dot(s, s);
  double t = len2 > 0 ? dot(vk - vj, s) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  const Vec3 d = vk - (vj + s * t);
  return std::sqrt(len2) * dot(d, d) / 3.0;
}

double merge_priority(double l2, double l21, uint64_t valence, double angle_sum, double epsilon) {
  const double dm = static_cast<double>(valence) - 4.0;
  return (1.0 + l2) * (1.0 + l21) * (1.0 + epsilon * dm * dm) * (1.0 + epsilon * angle_sum);
}

double quantize_priority(double e) {
  uint64_t u;
  std::memcpy(&u, &e, sizeof u);
  const uint64_t biased_exponent = (u >> 52) & 0x7ff;
  if (biased_exponent != 0 && biased_exponent != 0x7ff) {
    // Normal numbers: keep the top 40 of the 53 significand bits, rounding the magnitude half
    // away from zero; a carry out of the significand bumps the exponent. Bit-identical to the
    // frexp/round/ldexp form below (which is kept for zeros, subnormals, inf and NaN).
    u = (u + (uint64_t(1) << 12)) & ~((uint64_t(1) << 13) - 1);
    std::memcpy(&e, &u, sizeof e);
    return e;
  }
  if (!std::isfinite(e) || e == 0) return e;
  int exp = 0;
  const double m = std::frexp(e, &exp);  // m in [0.5, 1)
  return std::ldexp(std::round(std::ldexp(m, 40)), exp - 40);
}

}  // namespace detail
CAGEKIT_NAMESPACE_END
