// SPDX-License-Identifier: GPL-3.0-or-later
// Parameter-plane geometry; see plane_geometry.h.
#include "layout/quad/plane_geometry.h"

#include <algorithm>
#include <cmath>

#include "core/angles.h"

CAGEKIT_NAMESPACE_BEGIN

namespace plane2 {

double ccw_angle(const Vec2& from, const Vec2& to) {
  double a = std::atan2(cross(from, to), dot(from, to));
  if (a < 0.0) a += 2.0 * kPi;
  return a;
}

namespace {
double orient(const Vec2& a, const Vec2& b, const Vec2& c) { return cross(b - a, c - a); }
bool on_segment(const Vec2& a, const Vec2& b, const Vec2& p) {
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
         p.y <= std::max(a.y, b.y);
}
}  // namespace

bool segments_intersect(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d, double* s, double* t) {
  if (std::max(a.x, b.x) < std::min(c.x, d.x) || std::max(c.x, d.x) < std::min(a.x, b.x) ||
      std::max(a.y, b.y) < std::min(c.y, d.y) || std::max(c.y, d.y) < std::min(a.y, b.y))
    return false;
  const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) {
    if (s) *s = o3 / (o3 - o4);
    if (t) *t = o1 / (o1 - o2);
    return true;
  }
  // Touching or collinear cases: report the touching point's parameters where they are defined.
  auto report = [&](double ps, double pt) {
    if (s) *s = ps;
    if (t) *t = pt;
    return true;
  };
  auto param = [](const Vec2& p, const Vec2& q, const Vec2& x) {
    const Vec2 e = q - p;
    const double l2 = dot(e, e);
    return l2 > 0.0 ? std::clamp(dot(x - p, e) / l2, 0.0, 1.0) : 0.0;
  };
  if (o1 == 0 && on_segment(a, b, c)) return report(param(a, b, c), 0.0);
  if (o2 == 0 && on_segment(a, b, d)) return report(param(a, b, d), 1.0);
  if (o3 == 0 && on_segment(c, d, a)) return report(0.0, param(c, d, a));
  if (o4 == 0 && on_segment(c, d, b)) return report(1.0, param(c, d, b));
  return false;
}

double signed_area(const std::vector<Vec2>& polygon) {
  double a = 0.0;
  for (size_t i = 0, n = polygon.size(); i < n; ++i) a += cross(polygon[i], polygon[(i + 1) % n]);
  return 0.5 * a;
}

}  // namespace plane2

CAGEKIT_NAMESPACE_END
