// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Morton (Z-curve) order of points: indices sorted by the interleaved 21-bit cell coordinates of
// each point in a bounding box (ties by index), so that consecutive indices are near in space.
// Used to lay out traversals for cache locality; an order, never a result.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/polygon_mesh.h"

CAGEKIT_NAMESPACE_BEGIN
namespace detail {

// Indices of `points` in Morton order within `box` (non-finite points sort first).
inline std::vector<uint32_t> morton_order(const std::vector<Vec3>& points, const BoundingBox& box) {
  const Vec3 extent = box.max - box.min;
  const double scale = std::max({extent.x, extent.y, extent.z, 1e-300});
  auto spread = [](uint64_t x) {  // 21 bits -> every third bit
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffull;
    x = (x | x << 16) & 0x1f0000ff0000ffull;
    x = (x | x << 8) & 0x100f00f00f00f00full;
    x = (x | x << 4) & 0x10c30c30c30c30c3ull;
    x = (x | x << 2) & 0x1249249249249249ull;
    return x;
  };
  auto cell = [](double t) { return uint64_t(std::clamp(t, 0.0, 1.0) * 2097151.0); };
  std::vector<uint64_t> code(points.size());
  std::vector<uint32_t> order(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const Vec3 q = (1.0 / scale) * (points[i] - box.min);
    code[i] = is_finite(q) ? spread(cell(q.x)) | spread(cell(q.y)) << 1 | spread(cell(q.z)) << 2 : 0;
    order[i] = uint32_t(i);
  }
  std::sort(order.begin(), order.end(),
            [&](uint32_t a, uint32_t b) { return code[a] < code[b] || (code[a] == code[b] && a < b); });
  return order;
}

}  // namespace detail
CAGEKIT_NAMESPACE_END
