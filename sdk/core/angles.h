// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Pi and the degree/radian conversions, spelled once for the whole SDK. The conversions keep
// the order of operations of the expressions they replace (`degrees * kPi / 180.0`,
// `radians * 180.0 / kPi`), so results are the same to the bit.
#include "core/namespace.h"

CAGEKIT_NAMESPACE_BEGIN

constexpr double kPi = 3.14159265358979323846;

constexpr double radians_from_degrees(double degrees) { return degrees * kPi / 180.0; }
constexpr double degrees_from_radians(double radians) { return radians * 180.0 / kPi; }

CAGEKIT_NAMESPACE_END
