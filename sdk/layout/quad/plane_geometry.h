// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Geometry of a region's parameter plane (its LSCM domain) used by the curve network, its
// selection and element energy, and the bending fits.
//
// Thread-safety: pure functions. Errors: none (no checks; callers pass finite points).
#include <vector>

#include "core/vec2.h"

CAGEKIT_NAMESPACE_BEGIN

namespace plane2 {
// Counter-clockwise angle in [0, 2π) that turns direction `from` onto direction `to`.
double ccw_angle(const Vec2& from, const Vec2& to);
// Closed segments [a, b] and [c, d] share a point (collinear overlaps included). When they cross
// at a single point, *s and *t (optional) receive its parameters on the two segments.
bool segments_intersect(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d, double* s = nullptr,
                        double* t = nullptr);
double signed_area(const std::vector<Vec2>& polygon);
}  // namespace plane2

CAGEKIT_NAMESPACE_END
