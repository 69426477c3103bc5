// SPDX-License-Identifier: GPL-3.0-or-later
// Minimum-bending-energy cubic Béziers (thesis §6.5); see bending_fit.h.
#include "layout/quad/bending_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

#include "core/simd_dispatch.h"
#include "layout/quad/plane_geometry.h"

CAGEKIT_NAMESPACE_BEGIN

using plane2::segments_intersect;

Vec2 CubicBezier2::eval(double t) const {
  const double s = 1.0 - t;
  const double b0 = s * s * s, b1 = 3 * s * s * t, b2 = 3 * s * t * t, b3 = t * t * t;
  return {b0 * control[0].x + b1 * control[1].x + b2 * control[2].x + b3 * control[3].x,
          b0 * control[0].y + b1 * control[1].y + b2 * control[2].y + b3 * control[3].y};
}

Vec2 CubicBezier2::derivative(double t) const {
  const double s = 1.0 - t;
  const Vec2 d0 = control[1] - control[0], d1 = control[2] - control[1], d2 = control[3] - control[2];
  return (d0 * (s * s) + d1 * (2 * s * t) + d2 * (t * t)) * 3.0;
}

Vec2 CubicBezier2::second_derivative(double t) const {
  const Vec2 e0 = control[2] - control[1] * 2.0 + control[0];
  const Vec2 e1 = control[3] - control[2] * 2.0 + control[1];
  return (e0 * (1.0 - t) + e1 * t) * 6.0;
}

CubicBezier2 connecting_bezier(const Vec2& ci, const Vec2& qi, const Vec2& cj, const Vec2& qj, double lambda,
                               double mu) {
  return {{ci, ci + qi * lambda, cj + qj * mu, cj}};
}

namespace {
// Gauss-Legendre nodes of (6.3) over `intervals` equal pieces, with the Bernstein factors of b'
// and the quadrature weight ½·h·w per node, computed with the same expressions (and so to the
// same bits) as evaluating them node by node.
struct QuadratureNodes {
  std::vector<double> s, t, a, b, c, q;
  explicit QuadratureNodes(int intervals) {
    static const double kNode[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
    static const double kWeight[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
    const double h = 1.0 / intervals;
    for (int k = 0; k < intervals; ++k)
      for (int g = 0; g < 4; ++g) {
        const double tt = h * (k + 0.5 * (kNode[g] + 1.0)), ss = 1.0 - tt;
        t.push_back(tt), s.push_back(ss);
        a.push_back(3 * ss * ss), b.push_back(6 * ss * tt), c.push_back(3 * tt * tt);
        q.push_back(0.5 * h * kWeight[g]);
      }
  }
};
}  // namespace

namespace {
// (6.3) over `nodes`, summed in node order; once the partial sum reaches `bound` the rest is
// skipped and the partial sum returned (the terms are >= 0 and rounding is monotone, so the
// full sum would be >= bound too: a caller comparing "< bound" gets the same answer).
CAGEKIT_VECTOR_CLONES double bending_energy_below(const CubicBezier2& curve, const QuadratureNodes& nodes,
                                                   double bound) {
  // b' and b'' as combinations of the control-polygon differences (the hot loop of the network).
  const Vec2 d0 = curve.control[1] - curve.control[0], d1 = curve.control[2] - curve.control[1],
             d2 = curve.control[3] - curve.control[2];
  const Vec2 e0 = d1 - d0, e1 = d2 - d1;
  const size_t n = nodes.t.size();
  const double* S = nodes.s.data();
  const double* T = nodes.t.data();
  const double* A = nodes.a.data();
  const double* B = nodes.b.data();
  const double* C = nodes.c.data();
  const double* Q = nodes.q.data();
  // Chunks of kChunk terms (independent: vectorisable), each summed in order. A degenerate node
  // (b' = 0) makes the energy +inf wherever it is; a chunk past the bound is not looked at.
  constexpr size_t kChunk = 8;
  double energy = 0.0;
  for (size_t first = 0; first < n; first += kChunk) {
    const size_t m = std::min(kChunk, n - first);
    double term[kChunk];
    int degenerate = 0;
    for (size_t j = 0; j < m; ++j) {
      const size_t i = first + j;
      const double x1 = A[i] * d0.x + B[i] * d1.x + C[i] * d2.x, y1 = A[i] * d0.y + B[i] * d1.y + C[i] * d2.y;
      const double x2 = 6 * (S[i] * e0.x + T[i] * e1.x), y2 = 6 * (S[i] * e0.y + T[i] * e1.y);
      const double speed2 = x1 * x1 + y1 * y1;
      degenerate |= !(speed2 > 0.0);
      const double cr = x1 * y2 - y1 * x2;
      term[j] = Q[i] * cr * cr / (speed2 * speed2 * speed2);
    }
    if (degenerate) return std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < m; ++j) energy += term[j];
    if (energy >= bound) return energy;
  }
  return energy;
}

const QuadratureNodes& default_nodes() {
  static const QuadratureNodes kEight(8);  // the default, used by the minimisation
  return kEight;
}
}  // namespace

double bending_energy(const CubicBezier2& curve, int intervals) {
  std::unique_ptr<QuadratureNodes> other;
  if (intervals != 8) other = std::make_unique<QuadratureNodes>(intervals);
  return bending_energy_below(curve, other ? *other : default_nodes(), std::numeric_limits<double>::infinity());
}

BendingFit minimize_bending_energy(const Vec2& ci, const Vec2& qi, const Vec2& cj, const Vec2& qj) {
  BendingFit fit;
  const double d = hypot_length(cj - ci);
  if (!(d > 0.0)) return fit;
  const Vec2 chord = (cj - ci) * (1.0 / d);
  // Facing collinear tangents: a straight segment, E ≡ 0 for every (λ, μ).
  if (std::fabs(cross(qi, chord)) < 1e-12 && std::fabs(cross(qj, chord)) < 1e-12 && dot(qi, chord) > 0.0 &&
      dot(qj, chord) < 0.0) {
    fit.lambda = fit.mu = d / 3.0;
    fit.valid = true;
    return fit;
  }
  const double lower = 1e-3 * d;
  const QuadratureNodes& nodes = default_nodes();
  // E at (λ, μ), or any value >= bound once it is known to be at least that.
  auto energy_at = [&](double lambda, double mu, double bound = std::numeric_limits<double>::infinity()) {
    ++fit.evaluations;
    if (segments_intersect(ci, ci + qi * lambda, cj, cj + qj * mu))
      return std::numeric_limits<double>::infinity();
    return bending_energy_below(connecting_bezier(ci, qi, cj, qj, lambda, mu), nodes, bound);
  };
  // (6.3) has several basins (e.g. a quarter turn: the symmetric stationary point is beaten by
  // two asymmetric ones), so every local minimum of the grid starts a compass search.
  static const double kGrid[8] = {0.03, 0.07, 0.15, 0.3, 0.5, 0.8, 1.2, 1.8};
  double grid[8][8];
  for (int a = 0; a < 8; ++a)
    for (int b = 0; b < 8; ++b) grid[a][b] = energy_at(kGrid[a] * d, kGrid[b] * d);
  std::vector<std::pair<double, std::pair<int, int>>> starts;
  for (int a = 0; a < 8; ++a)
    for (int b = 0; b < 8; ++b) {
      const double e = grid[a][b];
      if (!std::isfinite(e)) continue;
      bool local = true;
      for (int da = -1; da <= 1; ++da)
        for (int db = -1; db <= 1; ++db) {
          const int x = a + da, y = b + db;
          if ((da || db) && x >= 0 && x < 8 && y >= 0 && y < 8 && grid[x][y] < e) local = false;
        }
      if (local) starts.push_back({e, {a, b}});
    }
  std::sort(starts.begin(), starts.end());
  if (starts.size() > 3) starts.resize(3);
  std::vector<std::array<double, 3>> seeds;  // (E, λ, μ)
  for (const auto& start : starts)
    seeds.push_back({start.first, kGrid[start.second.first] * d, kGrid[start.second.second] * d});
  // Narrow valleys run through the control polygon whose legs end at the crossing X of the two
  // tangent lines (e.g. the quarter turn's optimum, λ = |X − c_i|, μ small): seeds there too.
  const double denominator = cross(qi, qj);
  if (std::fabs(denominator) > 1e-12) {
    const double lx = cross(cj - ci, qj) / denominator, mx = cross(cj - ci, qi) / denominator;
    if (lx > 0.0 && mx > 0.0) {
      for (const auto& ab : {std::array<double, 2>{0.95, 0.1}, {0.1, 0.95}, {0.67, 0.67}}) {
        const double l = std::max(lower, ab[0] * lx), u = std::max(lower, ab[1] * mx);
        const double e = energy_at(l, u);
        if (std::isfinite(e)) seeds.push_back({e, l, u});
      }
    }
  }
  if (seeds.empty()) return fit;
  double best = std::numeric_limits<double>::infinity(), lambda = 0.0, mu = 0.0;
  for (const auto& seed : seeds) {
    double e = seed[0], l = seed[1], u = seed[2];
    // Compass search: shrink the step when no axis move improves; bounded iterations.
    double step = 0.1 * d;
    // The point the last move came from: its energy is above e, so a move back is skipped
    // (it would be evaluated and rejected).
    double from_l = std::numeric_limits<double>::quiet_NaN(), from_u = from_l;
    for (int iteration = 0; iteration < 400 && step > 1e-4 * d; ++iteration) {
      bool improved = false;
      const double moves[4][2] = {{step, 0}, {-step, 0}, {0, step}, {0, -step}};
      for (const auto& m : moves) {
        const double tl = std::max(lower, l + m[0]), tu = std::max(lower, u + m[1]);
        if (tl == l && tu == u) continue;
        if (tl == from_l && tu == from_u) continue;
        const double te = energy_at(tl, tu, e);  // only "te < e" matters
        if (te < e) {
          from_l = l, from_u = u;
          e = te, l = tl, u = tu, improved = true;
          break;
        }
      }
      if (!improved) step *= 0.5;
    }
    if (e < best) best = e, lambda = l, mu = u;
  }
  fit.lambda = lambda, fit.mu = mu, fit.energy = best, fit.valid = true;
  return fit;
}

CAGEKIT_NAMESPACE_END
