// SPDX-License-Identifier: GPL-3.0-or-later
#include <cmath>

#include "layout/common/planar_polygon.h"

CAGEKIT_NAMESPACE_BEGIN

PlaneFrame PlaneFrame::from_normal(const Vec3& origin, const Vec3& unit_normal) {
  PlaneFrame frame;
  frame.origin = origin;
  frame.normal = unit_normal;
  // The axis least aligned with the normal gives a well-conditioned first tangent.
  const Vec3 helper = std::fabs(unit_normal.x) <= std::fabs(unit_normal.y) &&
                              std::fabs(unit_normal.x) <= std::fabs(unit_normal.z)
                          ? Vec3(1, 0, 0)
                          : (std::fabs(unit_normal.y) <= std::fabs(unit_normal.z) ? Vec3(0, 1, 0) : Vec3(0, 0, 1));
  frame.u = normalized(cross(helper, unit_normal));
  frame.v = cross(unit_normal, frame.u);  // u x v = normal
  return frame;
}

CAGEKIT_NAMESPACE_END
