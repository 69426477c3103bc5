// SPDX-License-Identifier: GPL-3.0-or-later
#include "fit/closest_point_on_limit_surface.h"

#include <algorithm>
#include <cmath>

#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

LimitSurfaceProjector::LimitSurfaceProjector(const SubdivisionSurface& surface,
                                             const std::vector<Vec3>& control,
                                             const ClosestPointOptions& options)
    : surface_(surface), control_(control), options_(options) {
  if (options.grid_resolution < 1 || options.seeds < 1 || options.max_newton_steps < 0)
    fail(Status::invalid_argument, "closest point: grid_resolution and seeds must be >= 1");
  if (control.size() != surface.num_control_vertices())
    fail(Status::invalid_argument, "closest point: control array of the wrong size");
  const int g = options.grid_resolution;
  std::vector<Vec3> points;
  const uint32_t faces = surface.num_ptex_faces();
  points.reserve(size_t(faces) * g * g);
  for (uint32_t f = 0; f < faces; ++f) {
    for (int i = 0; i < g; ++i)
      for (int j = 0; j < g; ++j) {
        const double u = (i + 0.5) / g, v = (j + 0.5) / g;
        SurfacePoint sp;
        try {
          sp = surface.evaluate(f, u, v, control);
        } catch (const Error&) {
          continue;  // ptex face of a hole face: not part of the surface
        }
        points.push_back(sp.position);
        grid_face_.push_back(f);
        grid_u_.push_back(static_cast<float>(u));
        grid_v_.push_back(static_cast<float>(v));
      }
  }
  tree_ = PointKdTree(std::move(points));
}

FootPoint LimitSurfaceProjector::refine(const Vec3& p, uint32_t face, double u, double v) const {
  SurfacePoint s = surface_.evaluate(face, u, v, control_);
  Vec3 r = s.position - p;
  double f = 0.5 * dot(r, r);
  for (int step = 0; step < options_.max_newton_steps; ++step) {
    const double g0 = dot(r, s.du), g1 = dot(r, s.dv);
    const double a = dot(s.du, s.du), b = dot(s.du, s.dv), c = dot(s.dv, s.dv);
    // Newton Hessian; fall back to Gauss-Newton (J^T J) when it is not positive definite.
    double h00 = a + dot(r, s.duu), h01 = b + dot(r, s.duv), h11 = c + dot(r, s.dvv);
    double det = h00 * h11 - h01 * h01;
    if (!(h00 > 0 && det > 1e-12 * (a * c + 1e-300))) {
      h00 = a * (1 + 1e-12) + 1e-300;
      h01 = b;
      h11 = c * (1 + 1e-12) + 1e-300;
      det = h00 * h11 - h01 * h01;
      if (!(det > 0)) break;
    }
    double qu = -(h11 * g0 - h01 * g1) / det, qv = -(-h01 * g0 + h00 * g1) / det;
    // Active bounds: drop the components that push out of the unit square through them.
    if ((u <= 0 && qu < 0) || (u >= 1 && qu > 0)) qu = 0;
    if ((v <= 0 && qv < 0) || (v >= 1 && qv > 0)) qv = 0;
    // Clip to the square (thesis case 2: stop on the border of the face).
    double alpha = 1.0;
    if (u + qu < 0) alpha = std::min(alpha, -u / qu);
    if (u + qu > 1) alpha = std::min(alpha, (1 - u) / qu);
    if (v + qv < 0) alpha = std::min(alpha, -v / qv);
    if (v + qv > 1) alpha = std::min(alpha, (1 - v) / qv);
    bool improved = false;
    double step_length = 0;
    for (int halving = 0; halving < 40; ++halving, alpha *= 0.5) {
      const double nu = std::clamp(u + alpha * qu, 0.0, 1.0), nv = std::clamp(v + alpha * qv, 0.0, 1.0);
      step_length = std::hypot(nu - u, nv - v);
      if (step_length == 0) break;
      const SurfacePoint ns = surface_.evaluate(face, nu, nv, control_);
      const Vec3 nr = ns.position - p;
      const double nf = 0.5 * dot(nr, nr);
      if (nf <= f) {
        improved = nf < f || step_length > 0;
        u = nu;
        v = nv;
        s = ns;
        r = nr;
        f = nf;
        break;
      }
      if (step_length < options_.step_tolerance) break;
    }
    if (!improved || step_length < options_.step_tolerance) break;
  }
  FootPoint out;
  out.ptex_face = face;
  out.u = u;
  out.v = v;
  out.position = s.position;
  out.distance = std::sqrt(2 * f);
  return out;
}

FootPoint LimitSurfaceProjector::project(const Vec3& p, const FootPoint* warm_start) const {
  FootPoint best;
  best.distance = HUGE_VAL;
  if (warm_start) best = refine(p, warm_start->ptex_face, warm_start->u, warm_start->v);
  const size_t k = size_t(options_.seeds) * 4;
  std::vector<uint32_t> tried;
  for (const auto& hit : tree_.nearest(p, k)) {
    const uint32_t index = hit.second;
    const uint32_t face = grid_face_[index];
    if (std::find(tried.begin(), tried.end(), face) != tried.end()) continue;
    if (static_cast<int>(tried.size()) >= options_.seeds) break;
    tried.push_back(face);
    const FootPoint candidate = refine(p, face, grid_u_[index], grid_v_[index]);
    if (candidate.distance < best.distance) best = candidate;
  }
  if (!(best.distance < HUGE_VAL)) fail(Status::invalid_argument, "closest point: the surface is empty");
  return best;
}

CAGEKIT_NAMESPACE_END
