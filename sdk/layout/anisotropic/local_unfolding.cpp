// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/anisotropic/local_unfolding.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/angles.h"

CAGEKIT_NAMESPACE_BEGIN

FaceFrame face_frame(const PolygonMesh& mesh, uint32_t f) {
  FaceFrame fr;
  const Vec3 a = mesh.positions[mesh.face_vertices[3 * f]], b = mesh.positions[mesh.face_vertices[3 * f + 1]],
             c = mesh.positions[mesh.face_vertices[3 * f + 2]];
  fr.origin = a;
  fr.u = normalized(b - a);
  fr.n = normalized(cross(b - a, c - a));
  fr.v = cross(fr.n, fr.u);
  fr.corner[0] = {0.0, 0.0};
  fr.corner[1] = {dot(b - a, fr.u), 0.0};
  fr.corner[2] = {dot(c - a, fr.u), dot(c - a, fr.v)};
  return fr;
}

LocalUnfolding::LocalUnfolding(const PolygonMesh& mesh, const TriangleAdjacency& adjacency, size_t max_faces)
    : mesh_(mesh), adj_(adjacency), max_faces_(max_faces < 4 ? 4 : max_faces) {}

void LocalUnfolding::reset(uint32_t face) {
  omega_.clear();
  omega_[face] = Placement{};
  needs_reset_ = false;
}

void LocalUnfolding::reroot(const WalkEnd& end, Vec2& point, std::vector<Vec2*> dirs) {
  point = end.placement.invert(point);
  for (Vec2* d : dirs) *d = end.placement.unrotate(*d);
  reset(end.face);
}

const Placement* LocalUnfolding::placement(uint32_t face) const {
  auto it = omega_.find(face);
  return it == omega_.end() ? nullptr : &it->second;
}

std::array<double, 3> LocalUnfolding::barycentric(uint32_t face, const Placement& pl, Vec2 p) const {
  const FaceFrame fr = frame(face);
  const Vec2 a = pl.apply(fr.corner[0]), b = pl.apply(fr.corner[1]), c = pl.apply(fr.corner[2]);
  const double area = cross(b - a, c - a);
  if (!(std::fabs(area) > 0.0)) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, nan, nan};
  }
  const double w0 = cross(b - p, c - p) / area, w1 = cross(c - p, a - p) / area;
  return {w0, w1, 1.0 - w0 - w1};
}

Vec3 LocalUnfolding::position(uint32_t face, const Placement& pl, Vec2 p) const {
  const FaceFrame fr = frame(face);
  const Vec2 q = pl.invert(p);
  return fr.origin + q.x * fr.u + q.y * fr.v;
}

Vec2 LocalUnfolding::to_omega(uint32_t face, const Placement& pl, const Vec3& d) const {
  const FaceFrame fr = frame(face);
  return pl.rotate({dot(d, fr.u), dot(d, fr.v)});
}

Vec3 LocalUnfolding::to_space(uint32_t face, const Placement& pl, Vec2 d) const {
  const FaceFrame fr = frame(face);
  const Vec2 q = pl.unrotate(d);
  return q.x * fr.u + q.y * fr.v;
}

Placement LocalUnfolding::neighbour_placement(uint32_t face, const Placement& pl, uint32_t c, uint32_t tw) const {
  const FaceFrame ff = frame(face), fg = frame(tw / 3);
  const Vec2 A = pl.apply(ff.corner[c % 3]), B = pl.apply(ff.corner[TriangleAdjacency::next(c) % 3]);
  const Vec2 a = fg.corner[tw % 3], b = fg.corner[TriangleAdjacency::next(tw) % 3];  // a <-> B, b <-> A
  const double angle = std::atan2((A - B).y, (A - B).x) - std::atan2((b - a).y, (b - a).x);
  Placement out;
  out.c = std::cos(angle);
  out.s = std::sin(angle);
  out.t = B - out.rotate(a);
  return out;
}

Placement LocalUnfolding::place(uint32_t face, const Placement& pl, uint32_t c, uint32_t tw) {
  const Placement cand = neighbour_placement(face, pl, c, tw);
  const uint32_t g = tw / 3;
  auto it = omega_.find(g);
  if (it != omega_.end()) {
    const FaceFrame fg = frame(g);
    const Vec2 a = fg.corner[tw % 3], b = fg.corner[TriangleAdjacency::next(tw) % 3];
    const double tol = 1e-9 * (norm(b - a) + 1e-300);
    if (norm(it->second.apply(a) - cand.apply(a)) <= tol && norm(it->second.apply(b) - cand.apply(b)) <= tol)
      return it->second;
    needs_reset_ = true;  // reached around a vertex with angle defect: use the path's unfolding
    return cand;
  }
  if (omega_.size() >= max_faces_) {
    needs_reset_ = true;
    return cand;
  }
  omega_.emplace(g, cand);
  return cand;
}

bool LocalUnfolding::leave_vertex(uint32_t face, uint32_t corner, Vec2 dir, uint32_t& out_face, Vec2& out_point,
                                  Vec2& out_dir) {
  const Placement* plp = placement(face);
  if (!plp || corner / 3 != face) return false;
  const Placement pl = *plp;
  // The fan of corners at the vertex, counter-clockwise, starting at a boundary corner if any.
  uint32_t start = corner;
  bool open = false;
  for (int k = 0; k < 4096; ++k) {
    const uint32_t t = adj_.twin[start];
    if (t == detail::kNone) {
      open = true;
      break;
    }
    const uint32_t cw = TriangleAdjacency::next(t);
    if (cw == corner) break;
    start = cw;
  }
  std::vector<uint32_t> fan;
  for (uint32_t c = start; fan.size() < 4096;) {
    fan.push_back(c);
    const uint32_t t = adj_.twin[TriangleAdjacency::prev(c)];
    if (t == detail::kNone || t == start) break;
    c = t;
  }
  std::vector<double> theta(fan.size());
  double total = 0.0;
  size_t self = fan.size();
  for (size_t k = 0; k < fan.size(); ++k) {
    const uint32_t c = fan[k];
    const FaceFrame fr = frame(c / 3);
    const Vec2 e1 = fr.corner[TriangleAdjacency::next(c) % 3] - fr.corner[c % 3];
    const Vec2 e2 = fr.corner[TriangleAdjacency::prev(c) % 3] - fr.corner[c % 3];
    theta[k] = std::atan2(std::fabs(cross(e1, e2)), dot(e1, e2));
    if (!std::isfinite(theta[k])) theta[k] = 0.0;
    total += theta[k];
    if (c == corner) self = k;
  }
  if (!(total > 0.0) || self == fan.size()) return false;
  // Polar map ρ⁻¹: the corner angles rescaled to sum to 2π (π at a boundary vertex).
  const double scale = (open ? kPi : 2.0 * kPi) / total;
  double phi_self = 0.0;
  for (size_t k = 0; k < self; ++k) phi_self += theta[k] * scale;
  const FaceFrame fs = frame(face);
  const Vec2 e = pl.rotate(fs.corner[TriangleAdjacency::next(corner) % 3] - fs.corner[corner % 3]);
  double phi = phi_self + std::atan2(cross(e, dir), dot(e, dir)) * scale;
  const double full = open ? kPi : 2.0 * kPi;
  if (open) {
    if (phi < -1e-12 || phi > full + 1e-12) return false;
    phi = std::clamp(phi, 0.0, full);
  } else {
    phi = std::fmod(phi, full);
    if (phi < 0.0) phi += full;
  }
  double acc = 0.0;
  size_t k = 0;
  for (; k + 1 < fan.size(); ++k) {
    if (phi < acc + theta[k] * scale) break;
    acc += theta[k] * scale;
  }
  const double beta = std::clamp((phi - acc) / scale, 0.0, theta[k]);
  const uint32_t c = fan[k];
  const FaceFrame fr = frame(c / 3);
  Vec2 ek = fr.corner[TriangleAdjacency::next(c) % 3] - fr.corner[c % 3];
  const double len = norm(ek);
  if (!(len > 0.0)) return false;
  ek = (1.0 / len) * ek;
  out_face = c / 3;
  out_point = fr.corner[c % 3];
  out_dir = {std::cos(beta) * ek.x - std::sin(beta) * ek.y, std::sin(beta) * ek.x + std::cos(beta) * ek.y};
  reset(out_face);
  return true;
}

CAGEKIT_NAMESPACE_END
