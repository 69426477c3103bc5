// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/quad/arc_fit.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN
namespace {

// 4-point Gauss-Legendre on [0, 1]: exact to degree 7. The (6.1) normal-equation integrands
// B_k (L − P0 B0 − P3 B3) are degree 6 per edge, the residual ‖L − C‖² too.
const double kGaussX[4] = {0.0694318442029737, 0.3300094782075719, 0.6699905217924281, 0.9305681557970263};
const double kGaussW[4] = {0.1739274225687269, 0.3260725774312731, 0.3260725774312731, 0.1739274225687269};

void bernstein(double u, double b[4]) {
  const double w = 1.0 - u;
  b[0] = w * w * w, b[1] = 3.0 * u * w * w, b[2] = 3.0 * u * u * w, b[3] = u * u * u;
}

void check_points(const std::vector<Vec3>& points, const std::vector<double>& s) {
  if (points.size() < 2) fail(Status::invalid_argument, "arc fit: an arc needs at least 2 points");
  if (s.size() != points.size()) fail(Status::invalid_argument, "arc fit: one parameter per point is needed");
  for (size_t i = 0; i < points.size(); ++i) {
    if (!is_finite(points[i]) || !std::isfinite(s[i]))
      fail(Status::invalid_argument, "arc fit: point " + std::to_string(i) + " is not finite");
    if (i > 0 && s[i] < s[i - 1]) fail(Status::invalid_argument, "arc fit: parameters must be non-decreasing");
  }
  if (s[0] != 0.0) fail(Status::invalid_argument, "arc fit: the first parameter must be 0");
}

}  // namespace

Vec3 ArcCubic::evaluate(double t) const {
  double b[4];
  bernstein(parameter_length > 0.0 ? t / parameter_length : 0.0, b);
  return control[0] * b[0] + control[1] * b[1] + control[2] * b[2] + control[3] * b[3];
}

Vec3 ArcCubic::derivative(double t) const {
  if (!(parameter_length > 0.0)) return Vec3{};
  const double u = t / parameter_length, w = 1.0 - u;
  const Vec3 d = (control[1] - control[0]) * (w * w) + (control[2] - control[1]) * (2.0 * u * w) +
                 (control[3] - control[2]) * (u * u);
  return d * (3.0 / parameter_length);
}

std::vector<double> arc_length_parameters(const std::vector<Vec3>& points) {
  std::vector<double> s(points.size(), 0.0);
  for (size_t i = 1; i < points.size(); ++i) s[i] = s[i - 1] + distance(points[i - 1], points[i]);
  return s;
}

ArcCubic fit_arc_cubic(const std::vector<Vec3>& points, const std::vector<double>& s) {
  check_points(points, s);
  ArcCubic cubic;
  const Vec3 p0 = points.front(), p3 = points.back();
  cubic.parameter_length = s.back();
  cubic.control = {p0, p0 + (p3 - p0) * (1.0 / 3.0), p0 + (p3 - p0) * (2.0 / 3.0), p3};
  if (!(cubic.parameter_length > 0.0)) return cubic;
  const double S = cubic.parameter_length;
  // Normal equations in P1, P2: (∫B_k B_l dt) P_l = ∫ B_k (L − P0 B0 − P3 B3) dt, k, l in {1, 2};
  // ∫_0^S B_k B_l dt = S C(3,k) C(3,l) / (7 C(6,k+l)).
  const double m11 = S * 9.0 / 105.0, m12 = S * 9.0 / 140.0, m22 = S * 9.0 / 105.0;
  Vec3 r1, r2;
  for (size_t i = 0; i + 1 < points.size(); ++i) {
    const double h = s[i + 1] - s[i];
    if (h <= 0.0) continue;
    for (int q = 0; q < 4; ++q) {
      const double t = s[i] + h * kGaussX[q];
      double b[4];
      bernstein(t / S, b);
      const Vec3 rest = points[i] * (1.0 - kGaussX[q]) + points[i + 1] * kGaussX[q] - p0 * b[0] - p3 * b[3];
      r1 += rest * (b[1] * h * kGaussW[q]);
      r2 += rest * (b[2] * h * kGaussW[q]);
    }
  }
  const double det = m11 * m22 - m12 * m12;  // = S² 81 (1/105² − 1/140²) > 0
  cubic.control[1] = (r1 * m22 - r2 * m12) * (1.0 / det);
  cubic.control[2] = (r2 * m11 - r1 * m12) * (1.0 / det);
  return cubic;
}

double arc_fit_rms(const ArcCubic& cubic, const std::vector<Vec3>& points, const std::vector<double>& s) {
  check_points(points, s);
  if (!(s.back() > 0.0)) return 0.0;
  const double* x = kGaussX;
  const double* w = kGaussW;
  double sum = 0.0;
  for (size_t i = 0; i + 1 < points.size(); ++i) {
    const double h = s[i + 1] - s[i];
    for (int q = 0; q < 4; ++q) {
      const Vec3 d = points[i] * (1.0 - x[q]) + points[i + 1] * x[q] - cubic.evaluate(s[i] + h * x[q]);
      sum += dot(d, d) * h * w[q];
    }
  }
  return std::sqrt(sum / s.back());
}

namespace {

// ∫_a^b ‖C'(t)‖ dt by 5-point Gauss-Legendre.
double length_gauss(const ArcCubic& c, double a, double b) {
  const double x[5] = {0.0, -0.5384693101056831, 0.5384693101056831, -0.9061798459386640, 0.9061798459386640};
  const double w[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665, 0.2369268850561891,
                       0.2369268850561891};
  double sum = 0.0;
  for (int q = 0; q < 5; ++q) sum += w[q] * norm(c.derivative(0.5 * (a + b) + 0.5 * (b - a) * x[q]));
  return 0.5 * (b - a) * sum;
}

// Cumulative length table on 64 equal parameter intervals (each exact to ~1e-12 for a cubic
// whose speed is smooth; cusps of a degenerate cubic lose accuracy but stay monotone).
constexpr int kIntervals = 64;

}  // namespace

double arc_cubic_length(const ArcCubic& cubic) {
  double len = 0.0;
  const double S = cubic.parameter_length;
  for (int k = 0; k < kIntervals; ++k) len += length_gauss(cubic, S * k / kIntervals, S * (k + 1) / kIntervals);
  return len;
}

ArcSamples sample_arc_cubic(const ArcCubic& cubic, double spacing) {
  if (!(spacing > 0.0) || !std::isfinite(spacing))
    fail(Status::invalid_argument, "arc samples: the spacing must be positive and finite");
  const double len = arc_cubic_length(cubic);
  return sample_arc_cubic_count(cubic, std::max(0L, long(std::ceil(len / spacing - 1e-9)) - 1));
}

ArcSamples sample_arc_cubic_count(const ArcCubic& cubic, long r) {
  if (r < 0) fail(Status::invalid_argument, "arc samples: the sample count must not be negative");
  const double S = cubic.parameter_length;
  std::vector<double> table(kIntervals + 1, 0.0);
  for (int k = 0; k < kIntervals; ++k)
    table[k + 1] = table[k] + length_gauss(cubic, S * k / kIntervals, S * (k + 1) / kIntervals);
  const double len = table[kIntervals];
  ArcSamples out;
  out.t.push_back(0.0);
  for (long k = 1; k <= r; ++k) {
    const double target = len * double(k) / double(r + 1);
    const int i = int(std::upper_bound(table.begin(), table.end(), target) - table.begin()) - 1;
    const int cell = std::min(std::max(i, 0), kIntervals - 1);
    // Newton on the length inside the cell, safeguarded by bisection.
    double lo = S * cell / kIntervals, hi = S * (cell + 1) / kIntervals, t = 0.5 * (lo + hi);
    for (int it = 0; it < 50; ++it) {
      const double f = table[cell] + length_gauss(cubic, S * cell / kIntervals, t) - target;
      if (std::abs(f) <= 1e-13 * len) break;
      (f > 0 ? hi : lo) = t;
      const double speed = norm(cubic.derivative(t));
      const double newton = speed > 0.0 ? t - f / speed : 0.5 * (lo + hi);
      t = (newton > lo && newton < hi) ? newton : 0.5 * (lo + hi);
    }
    out.t.push_back(t);
  }
  out.t.push_back(S);
  out.position = evaluate_at(cubic, out.t);
  out.position.front() = cubic.control[0];
  out.position.back() = cubic.control[3];
  return out;
}

std::vector<Vec3> evaluate_at(const ArcCubic& cubic, const std::vector<double>& t) {
  std::vector<Vec3> out;
  out.reserve(t.size());
  for (double x : t) out.push_back(cubic.evaluate(x));
  return out;
}

CAGEKIT_NAMESPACE_END
