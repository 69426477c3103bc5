// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A double-precision point in the form Far::PrimvarRefinerReal<double> interpolates
// (Clear / AddWithWeight).
#include <vector>

#include "core/vec3.h"

CAGEKIT_NAMESPACE_BEGIN
namespace subdiv_detail {

struct PrimvarPoint {
  Vec3 p;
  void Clear() { p = Vec3(); }
  void AddWithWeight(const PrimvarPoint& src, double weight) { p += src.p * weight; }
};

inline std::vector<PrimvarPoint> to_primvar(const std::vector<Vec3>& points) {
  std::vector<PrimvarPoint> out(points.size());
  for (size_t i = 0; i < points.size(); ++i) out[i].p = points[i];
  return out;
}

}  // namespace subdiv_detail
CAGEKIT_NAMESPACE_END
