// SPDX-License-Identifier: GPL-3.0-or-later
#include "fit/point_kd_tree.h"

#include <algorithm>
#include <numeric>

CAGEKIT_NAMESPACE_BEGIN

namespace {
constexpr uint32_t kLeafSize = 8;
}

PointKdTree::PointKdTree(std::vector<Vec3> points) : points_(std::move(points)) {
  order_.resize(points_.size());
  std::iota(order_.begin(), order_.end(), 0u);
  if (!points_.empty()) build(0, static_cast<uint32_t>(points_.size()));
}

uint32_t PointKdTree::build(uint32_t begin, uint32_t end) {
  const uint32_t id = static_cast<uint32_t>(nodes_.size());
  nodes_.push_back({begin, end, -1, 0.0, 0, 0});
  if (end - begin <= kLeafSize) return id;
  Vec3 lo = points_[order_[begin]], hi = lo;
  for (uint32_t i = begin; i < end; ++i)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], points_[order_[i]][a]);
      hi[a] = std::max(hi[a], points_[order_[i]][a]);
    }
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
  const uint32_t mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](uint32_t a, uint32_t b) { return points_[a][axis] < points_[b][axis]; });
  const double split = points_[order_[mid]][axis];
  const uint32_t left = build(begin, mid);
  const uint32_t right = build(mid, end);
  nodes_[id].axis = axis;
  nodes_[id].split = split;
  nodes_[id].left = left;
  nodes_[id].right = right;
  return id;
}

std::vector<std::pair<double, uint32_t>> PointKdTree::nearest(const Vec3& query, size_t k) const {
  std::vector<std::pair<double, uint32_t>> best;  // max-heap on distance
  if (nodes_.empty() || k == 0) return best;
  struct Item {
    uint32_t node;
    double bound;  // lower bound of the squared distance to the node's region
  };
  std::vector<Item> stack{{0, 0.0}};
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    if (best.size() == k && item.bound >= best.front().first) continue;
    const Node& node = nodes_[item.node];
    if (node.axis < 0) {
      for (uint32_t i = node.begin; i < node.end; ++i) {
        const Vec3 d = points_[order_[i]] - query;
        const double d2 = dot(d, d);
        if (best.size() < k) {
          best.emplace_back(d2, order_[i]);
          std::push_heap(best.begin(), best.end());
        } else if (d2 < best.front().first) {
          std::pop_heap(best.begin(), best.end());
          best.back() = {d2, order_[i]};
          std::push_heap(best.begin(), best.end());
        }
      }
      continue;
    }
    const double diff = query[node.axis] - node.split;
    const uint32_t near_child = diff < 0 ? node.left : node.right;
    const uint32_t far_child = diff < 0 ? node.right : node.left;
    stack.push_back({far_child, std::max(item.bound, diff * diff)});
    stack.push_back({near_child, item.bound});
  }
  std::sort_heap(best.begin(), best.end());
  return best;
}

CAGEKIT_NAMESPACE_END
