// SPDX-License-Identifier: GPL-3.0-or-later
#include "fit/closest_point_on_limit_surface.h"

#include <algorithm>
#include <cmath>

#include "core/status.h"
#include "fit/piecewise_linear_limit_mesh.h"
#include "fit/ptex_adjacency.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

constexpr double kSnap = 1e-12;  // parameters this close to 0 or 1 are on the border

// Brent's minimisation of phi on [0, b] without derivatives (Brent 1973, ch. 5; the classic
// golden-section + parabolic interpolation scheme). Returns the best abscissa found.
template <typename Phi>
double brent_minimize(Phi&& phi, double b, double f0, double* f_best) {
  constexpr double kGolden = 0.3819660112501051;
  double a = 0, x = kGolden * b, w = x, v = x;
  double fx = phi(x), fw = fx, fv = fx;
  double d = 0, e = 0;
  double best_x = 0, best_f = f0;
  if (fx < best_f) best_x = x, best_f = fx;
  for (int iter = 0; iter < 60; ++iter) {
    const double m = 0.5 * (a + b);
    const double tol = 1e-10 * std::abs(x) + 1e-14, tol2 = 2 * tol;
    if (std::abs(x - m) <= tol2 - 0.5 * (b - a)) break;
    bool golden = true;
    if (std::abs(e) > tol) {
      double r = (x - w) * (fx - fv), q = (x - v) * (fx - fw), p = (x - v) * q - (x - w) * r;
      q = 2 * (q - r);
      if (q > 0) p = -p;
      q = std::abs(q);
      const double e_old = e;
      e = d;
      if (std::abs(p) < std::abs(0.5 * q * e_old) && p > q * (a - x) && p < q * (b - x)) {
        d = p / q;
        const double u = x + d;
        if (u - a < tol2 || b - u < tol2) d = x < m ? tol : -tol;
        golden = false;
      }
    }
    if (golden) {
      e = (x < m ? b : a) - x;
      d = kGolden * e;
    }
    const double u = std::abs(d) >= tol ? x + d : x + (d > 0 ? tol : -tol);
    const double fu = phi(u);
    if (fu < best_f) best_x = u, best_f = fu;
    if (fu <= fx) {
      (u < x ? b : a) = x;
      v = w, fv = fw, w = x, fw = fx, x = u, fx = fu;
    } else {
      (u < x ? a : b) = u;
      if (fu <= fw || w == x) {
        v = w, fv = fw, w = u, fw = fu;
      } else if (fu <= fv || v == x || v == w) {
        v = u, fv = fu;
      }
    }
  }
  *f_best = best_f;
  return best_x;
}

}  // namespace

LimitSurfaceProjector::LimitSurfaceProjector(const SubdivisionSurface& surface, const PtexAdjacency* adjacency,
                                             const std::vector<Vec3>& control, const ClosestPointOptions& options,
                                             bool linear_mesh, int threads)
    : surface_(surface), options_(options), points_(surface.patch_points(control)), adjacency_(adjacency) {
  check_options();
  if (linear_mesh) {
    own_linear_ = std::make_unique<PiecewiseLinearLimitMesh>(surface, points_, options.seed_resolution, threads);
    linear_ = own_linear_.get();
  }
}

LimitSurfaceProjector::LimitSurfaceProjector(const SubdivisionSurface& surface, const PtexAdjacency* adjacency,
                                             std::vector<Vec3> patch_points,
                                             const PiecewiseLinearLimitMesh* linear_mesh,
                                             const ClosestPointOptions& options)
    : surface_(surface), options_(options), points_(std::move(patch_points)), adjacency_(adjacency),
      linear_(linear_mesh) {
  check_options();  // a patch point array of the wrong size throws at the first evaluation
}

void LimitSurfaceProjector::check_options() const {
  if (options_.max_steps < 0 || options_.max_steps > 100000)
    fail(Status::invalid_argument, "closest point: max_steps must be in [0, 100000]");
  if (!(options_.epsilon > 0) || !std::isfinite(options_.epsilon))
    fail(Status::invalid_argument, "closest point: epsilon must be finite and > 0");
  if (options_.seed_resolution < 1 || options_.seed_resolution > 64)
    fail(Status::invalid_argument, "closest point: seed_resolution must be in [1, 64]");
}

LimitSurfaceProjector::~LimitSurfaceProjector() = default;

double LimitSurfaceProjector::distance2(uint32_t face, double u, double v, const Vec3& p) const {
  const Vec3 d = surface_.evaluate_position(face, u, v, points_) - p;
  return dot(d, d);
}

namespace {

// A hit on the piecewise-linear limit mesh as a foot point (no search steps taken).
FootPoint foot_point_of(const PiecewiseLinearLimitMesh::Hit& hit) {
  return FootPoint{hit.ptex_face, hit.u, hit.v, hit.distance, hit.position};
}

}  // namespace

FootPoint LimitSurfaceProjector::project_piecewise_linear(const Vec3& p) const {
  if (!linear_) fail(Status::invalid_argument, "closest point: built without the piecewise-linear mesh");
  return foot_point_of(linear_->closest_point(p));
}

FootPoint LimitSurfaceProjector::project(const Vec3& p, const FootPoint* warm_start) const {
  if (!warm_start) return refine(p, project_piecewise_linear(p));
  FootPoint best = refine(p, *warm_start);
  if (!linear_ || !options_.reseed_from_linear_mesh) return best;
  // Safeguard against a warm start caught in a local minimum after the surface moved: when the
  // piecewise-linear mesh has a closer point in another ptex face, search from there too.
  const PiecewiseLinearLimitMesh::Hit hit = linear_->closest_point(p, best.distance, best.ptex_face);
  if (!(hit.distance < best.distance) || hit.ptex_face == best.ptex_face) return best;
  FootPoint other = refine(p, foot_point_of(hit));
  other.steps += best.steps;
  if (other.distance < best.distance) return other;
  best.steps = other.steps;
  return best;
}

FootPoint LimitSurfaceProjector::refine(const Vec3& p, const FootPoint& start) const {
  uint32_t face = start.ptex_face;
  double u = std::clamp(start.u, 0.0, 1.0), v = std::clamp(start.v, 0.0, 1.0);
  SurfacePoint s = surface_.evaluate_patch_points(face, u, v, points_);
  Vec3 r = s.position - p;
  double f = dot(r, r);
  FootPoint best;
  best.ptex_face = face, best.u = u, best.v = v, best.position = s.position;
  double best_f = f;
  int entered_side = -1;  // side of `face` the search came in through by the last transfer
  bool converged = false;
  int step = 0;
  for (; step < options_.max_steps; ++step) {
    const double g0 = dot(r, s.du), g1 = dot(r, s.dv);
    const double a = dot(s.du, s.du), b = dot(s.du, s.dv), c = dot(s.dv, s.dv);
    double h00 = a + dot(r, s.duu), h01 = b + dot(r, s.duv), h11 = c + dot(r, s.dvv);
    double det = h00 * h11 - h01 * h01;
    if (!(h00 > 0 && det > 1e-12 * (a * c + 1e-300))) {  // not positive definite: Gauss-Newton
      h00 = a * (1 + 1e-12) + 1e-300;
      h01 = b;
      h11 = c * (1 + 1e-12) + 1e-300;
      det = h00 * h11 - h01 * h01;
      if (!(det > 0)) break;  // degenerate Jacobian
    }
    double qu = -(h11 * g0 - h01 * g1) / det, qv = -(-h01 * g0 + h00 * g1) / det;
    if (!std::isfinite(qu) || !std::isfinite(qv)) break;
    const bool last = std::hypot(qu, qv) < options_.epsilon;  // converged: one final step
    // On the border with q pointing out: transfer (case 3) or drop the outward component.
    const double out[4] = {v <= 0 ? -qv : 0, u >= 1 ? qu : 0, v >= 1 ? qv : 0, u <= 0 ? -qu : 0};
    int side = -1;
    for (int k = 0; k < 4; ++k)
      if (out[k] > 0 && (side < 0 || out[k] > out[side])) side = k;
    if (side >= 0) {
      if (adjacency_ && side != entered_side && !last) {
        uint32_t nf = face;
        double nu = u, nv = v;
        const int arrived = adjacency_->transfer(nf, nu, nv, side);
        if (arrived >= 0) {
          face = nf, u = nu, v = nv;
          s = surface_.evaluate_patch_points(face, u, v, points_);
          r = s.position - p;
          f = dot(r, r);
          entered_side = arrived;
          continue;
        }
      }
      for (int k = 0; k < 4; ++k)
        if (out[k] > 0) (k == 0 || k == 2 ? qv : qu) = 0;
      if (std::hypot(qu, qv) < options_.epsilon) {
        converged = true;  // a constrained stationary point on the border
        break;
      }
    }
    // Case 2: scale the step so that it stays in the square.
    double alpha = 1.0;
    if (u + qu < 0) alpha = std::min(alpha, -u / qu);
    if (u + qu > 1) alpha = std::min(alpha, (1 - u) / qu);
    if (v + qv < 0) alpha = std::min(alpha, -v / qv);
    if (v + qv > 1) alpha = std::min(alpha, (1 - v) / qv);
    auto at = [&](double lambda, double& nu, double& nv) {
      // Clamped, and snapped onto the border within rounding so that the border tests hold.
      nu = std::clamp(u + lambda * qu, 0.0, 1.0);
      nv = std::clamp(v + lambda * qv, 0.0, 1.0);
      if (nu < kSnap) nu = 0;
      if (nu > 1 - kSnap) nu = 1;
      if (nv < kSnap) nv = 0;
      if (nv > 1 - kSnap) nv = 1;
    };
    double nu, nv;
    at(alpha, nu, nv);
    // The final step only needs the position (the search ends after it): no derivatives.
    SurfacePoint ns;
    if (last)
      ns.position = surface_.evaluate_position(face, nu, nv, points_);
    else
      ns = surface_.evaluate_patch_points(face, nu, nv, points_);
    Vec3 nr = ns.position - p;
    double nf = dot(nr, nr);
    if (!(nf < f) && last) {
      converged = true;  // |q| < epsilon and the last small step gains nothing
      break;
    }
    if (!(nf < f)) {
      // (7.7): Brent along q on (0, alpha].
      double lambda_f;
      const double lambda = brent_minimize(
          [&](double t) {
            double lu, lv;
            at(t, lu, lv);
            return distance2(face, lu, lv, p);
          },
          alpha, f, &lambda_f);
      if (!(lambda > 0 && lambda_f < f)) {
        converged = true;  // no decrease along a descent direction: stationary to working precision
        break;
      }
      at(lambda, nu, nv);
      ns = surface_.evaluate_patch_points(face, nu, nv, points_);
      nr = ns.position - p;
      nf = dot(nr, nr);
    }
    if (nu != u || nv != v) entered_side = -1;
    u = nu, v = nv, s = ns, r = nr, f = nf;
    if (f < best_f) {
      best_f = f;
      best.ptex_face = face, best.u = u, best.v = v, best.position = s.position;
    }
    if (last) {
      converged = true;
      ++step;
      break;
    }
  }
  best.distance = std::sqrt(best_f);
  best.steps = uint32_t(step);
  best.converged = converged;
  return best;
}

CAGEKIT_NAMESPACE_END
