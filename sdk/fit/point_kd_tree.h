// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// PointKdTree: a static 3-d tree over a point set for k-nearest-neighbour queries. Used by the
// fitting layer to seed the closest-point search from a grid of limit-surface points.
// Thread-safety: const queries may run concurrently.
#include <cstdint>
#include <utility>
#include <vector>

#include "core/vec3.h"

CAGEKIT_NAMESPACE_BEGIN

class PointKdTree {
 public:
  PointKdTree() = default;
  explicit PointKdTree(std::vector<Vec3> points);

  size_t size() const { return points_.size(); }
  // Up to k nearest points as (squared distance, point index), nearest first.
  std::vector<std::pair<double, uint32_t>> nearest(const Vec3& query, size_t k) const;

 private:
  struct Node {
    uint32_t begin, end;   // range in order_
    int axis;              // -1: leaf
    double split;
    uint32_t left, right;  // children (nodes_ indices)
  };
  uint32_t build(uint32_t begin, uint32_t end);
  std::vector<Vec3> points_;
  std::vector<uint32_t> order_;
  std::vector<Node> nodes_;
};

CAGEKIT_NAMESPACE_END
