// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/common/polygon_corners.h"

#include <cmath>

#include "core/angles.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

double angle_between(const Vec3& e_next, const Vec3& e_back, const Vec3& n) {
  // Counter-clockwise (about n) angle from the outgoing edge to the reversed incoming edge.
  const Vec3 a = e_next - dot(e_next, n) * n, b = e_back - dot(e_back, n) * n;
  double t = std::atan2(dot(cross(a, b), n), dot(a, b));
  if (t < 0.0) t += 2.0 * kPi;
  return t;
}

}  // namespace

double corner_angle(const std::vector<Vec3>& p, const std::vector<Vec3>& n, const std::vector<uint32_t>& loop,
                    size_t i, const Vec3& face_normal) {
  const size_t m = loop.size();
  const uint32_t v = loop[i], next = loop[(i + 1) % m], prev = loop[(i + m - 1) % m];
  Vec3 nv = normalized(n[v]);
  if (dot(face_normal, face_normal) > 0.0 && dot(nv, face_normal) < 0.5) nv = face_normal;
  return angle_between(p[next] - p[v], p[prev] - p[v], nv);
}

Vec3 loop_normal(const std::vector<Vec3>& p, const std::vector<uint32_t>& loop) {
  Vec3 a{};
  for (size_t k = 0; k < loop.size(); ++k) a = a + cross(p[loop[k]], p[loop[(k + 1) % loop.size()]]);
  return normalized(a);
}

CAGEKIT_NAMESPACE_END
