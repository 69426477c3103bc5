// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Points and vectors of a plane: a face projected into its proxy plane (layout/simplify), the
// local unfolding Ω (layout/anisotropic), the LSCM domains and curve networks (layout/quad).
#include <cmath>

#include "core/namespace.h"

CAGEKIT_NAMESPACE_BEGIN

struct Vec2 {
  double x = 0, y = 0;

  constexpr Vec2() = default;
  constexpr Vec2(double x_, double y_) : x(x_), y(y_) {}

  Vec2& operator+=(const Vec2& o) { x += o.x; y += o.y; return *this; }
  Vec2& operator-=(const Vec2& o) { x -= o.x; y -= o.y; return *this; }
  Vec2& operator*=(double s) { x *= s; y *= s; return *this; }
  friend Vec2 operator+(Vec2 a, const Vec2& b) { return a += b; }
  friend Vec2 operator-(Vec2 a, const Vec2& b) { return a -= b; }
  friend Vec2 operator*(Vec2 a, double s) { return a *= s; }
  friend Vec2 operator*(double s, Vec2 a) { return a *= s; }
  friend bool operator==(const Vec2& a, const Vec2& b) { return a.x == b.x && a.y == b.y; }
  friend bool operator!=(const Vec2& a, const Vec2& b) { return !(a == b); }
};

inline double dot(const Vec2& a, const Vec2& b) { return a.x * b.x + a.y * b.y; }
// The z component of (a, 0) x (b, 0): positive when b lies counter-clockwise of a.
inline double cross(const Vec2& a, const Vec2& b) { return a.x * b.y - a.y * b.x; }
inline double norm(const Vec2& a) { return std::sqrt(dot(a, a)); }
// |a| by std::hypot (no overflow or underflow in the squares; not always the bits of norm(a)):
// the length the quad layout measures directions and chords with.
inline double hypot_length(const Vec2& a) { return std::hypot(a.x, a.y); }
// a divided by hypot_length(a) (a division per component, not a multiplication by the reciprocal
// as normalized(Vec3)); the zero vector for a zero length.
inline Vec2 hypot_normalized(const Vec2& a) {
  const double l = hypot_length(a);
  return l > 0.0 ? Vec2{a.x / l, a.y / l} : Vec2{0.0, 0.0};
}

CAGEKIT_NAMESPACE_END
