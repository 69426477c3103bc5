// SPDX-License-Identifier: GPL-3.0-or-later
#include "fit/crease_feature_rows.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_set>

#include "core/edge_key.h"
#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

constexpr int64_t kCellRange = int64_t(1) << 20;  // 21 bits per axis in a key

}  // namespace

std::vector<FeatureSegment> feature_segments(const PolygonMesh& mesh, const std::vector<uint64_t>& edge_keys) {
  std::vector<FeatureSegment> out;
  out.reserve(edge_keys.size());
  const size_t n = mesh.num_vertices();
  for (const uint64_t key : edge_keys) {
    const uint64_t a = edge_key_first(key), b = edge_key_second(key);
    if (a < n && b < n) out.push_back({mesh.positions[a], mesh.positions[b]});
  }
  return out;
}

uint64_t FeatureLineDistance::cell_key(int64_t i, int64_t j, int64_t k) const {
  auto wrap = [](int64_t x) { return uint64_t(std::clamp<int64_t>(x + kCellRange, 0, 2 * kCellRange - 1)); };
  return (wrap(i) << 42) | (wrap(j) << 21) | wrap(k);
}

FeatureLineDistance::FeatureLineDistance(const std::vector<FeatureSegment>& segments, double reach) : reach_(reach) {
  if (!(reach > 0) || !std::isfinite(reach)) fail(Status::invalid_argument, "feature lines: reach must be finite and > 0");
  for (const FeatureSegment& s : segments)
    if (is_finite(s.a) && is_finite(s.b)) segments_.push_back(s);
  if (segments_.empty()) return;
  origin_ = segments_[0].a;
  for (const FeatureSegment& s : segments_)
    for (const Vec3& p : {s.a, s.b})
      origin_ = {std::min(origin_.x, p.x), std::min(origin_.y, p.y), std::min(origin_.z, p.z)};
  // A grid too fine for the key's range (reach tiny against the extent) gets larger cells: the
  // query then only looks at more segments, never misses one.
  Vec3 extent{0, 0, 0};
  for (const FeatureSegment& s : segments_)
    for (const Vec3& p : {s.a, s.b})
      extent = {std::max(extent.x, p.x - origin_.x), std::max(extent.y, p.y - origin_.y),
                std::max(extent.z, p.z - origin_.z)};
  const double largest = std::max({extent.x, extent.y, extent.z});
  if (largest / reach_ > double(kCellRange / 2)) reach_ = largest / double(kCellRange / 2);
  reach = reach_;
  std::vector<std::pair<uint64_t, uint32_t>> entries;
  for (uint32_t id = 0; id < segments_.size(); ++id) {
    const FeatureSegment& s = segments_[id];
    const int pieces = std::max(1, int(std::ceil(distance(s.a, s.b) / reach)));
    std::vector<uint64_t> keys;
    for (int piece = 0; piece < pieces; ++piece) {
      const Vec3 p = s.a + (double(piece) / pieces) * (s.b - s.a), q = s.a + (double(piece + 1) / pieces) * (s.b - s.a);
      const int64_t i0 = int64_t(std::floor((std::min(p.x, q.x) - origin_.x) / reach)),
                    i1 = int64_t(std::floor((std::max(p.x, q.x) - origin_.x) / reach));
      const int64_t j0 = int64_t(std::floor((std::min(p.y, q.y) - origin_.y) / reach)),
                    j1 = int64_t(std::floor((std::max(p.y, q.y) - origin_.y) / reach));
      const int64_t k0 = int64_t(std::floor((std::min(p.z, q.z) - origin_.z) / reach)),
                    k1 = int64_t(std::floor((std::max(p.z, q.z) - origin_.z) / reach));
      for (int64_t i = i0; i <= i1; ++i)
        for (int64_t j = j0; j <= j1; ++j)
          for (int64_t k = k0; k <= k1; ++k) keys.push_back(cell_key(i, j, k));
    }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    for (const uint64_t key : keys) entries.push_back({key, id});
  }
  std::sort(entries.begin(), entries.end());
  cell_keys_.reserve(entries.size());
  cell_segments_.reserve(entries.size());
  for (const auto& [key, id] : entries) cell_keys_.push_back(key), cell_segments_.push_back(id);
}

bool FeatureLineDistance::closest_point(const Vec3& p, Vec3* closest, double* distance_out) const {
  if (segments_.empty() || !is_finite(p)) return false;
  const double fi = std::floor((p.x - origin_.x) / reach_), fj = std::floor((p.y - origin_.y) / reach_),
               fk = std::floor((p.z - origin_.z) / reach_);
  // A point farther than the key range from the segments has none within reach.
  if (std::abs(fi) > double(kCellRange - 2) || std::abs(fj) > double(kCellRange - 2) ||
      std::abs(fk) > double(kCellRange - 2))
    return false;
  const int64_t ci = int64_t(fi), cj = int64_t(fj), ck = int64_t(fk);
  double best = reach_;
  bool found = false;
  for (int64_t i = ci - 1; i <= ci + 1; ++i)
    for (int64_t j = cj - 1; j <= cj + 1; ++j)
      for (int64_t k = ck - 1; k <= ck + 1; ++k) {
        const uint64_t key = cell_key(i, j, k);
        const auto range = std::equal_range(cell_keys_.begin(), cell_keys_.end(), key);
        for (auto it = range.first; it != range.second; ++it) {
          const FeatureSegment& s = segments_[cell_segments_[size_t(it - cell_keys_.begin())]];
          const Vec3 q = closest_point_on_segment(p, s.a, s.b);
          const double d = distance(p, q);
          if (d <= best) {
            best = d;
            found = true;
            if (closest) *closest = q;
          }
        }
      }
  if (found && distance_out) *distance_out = best;
  return found;
}

std::vector<size_t> crease_curve_grid_points(const Cage& cage, const SubdivisionSurface& surface,
                                             const PtexAdjacency& adjacency, const PiecewiseLinearLimitMesh& linear,
                                             int resolution) {
  std::vector<size_t> out;
  if (resolution < 1) return out;
  // Infinitely sharp crease edges with two faces, each claimed by the first base face seen.
  std::map<uint64_t, int> faces_of_edge;
  for (size_t f = 0; f < cage.mesh.num_faces(); ++f) {
    const uint32_t n = cage.mesh.face_size(f);
    for (uint32_t k = 0; k < n; ++k)
      ++faces_of_edge[edge_key(cage.mesh.face_vertex(f, k), cage.mesh.face_vertex(f, (k + 1) % n))];
  }
  std::map<uint64_t, uint32_t> claimed;  // crease edge -> base face whose ptex sides give its points
  for (const EdgeCrease& e : cage.creases) {
    if (!(e.sharpness >= kSharpnessInfinite)) continue;
    const auto it = faces_of_edge.find(edge_key(e.v0, e.v1));
    if (it != faces_of_edge.end() && it->second == 2) claimed[it->first] = ~0u;
  }
  if (claimed.empty()) return out;
  const std::vector<Vec3>& grid = linear.grid_points();
  std::unordered_set<size_t> taken;
  for (size_t g = 0; g < grid.size(); ++g) {
    uint32_t face = 0;
    double u = 0, v = 0;
    linear.grid_point_parameters(g, face, u, v);
    const long i = std::lround(u * resolution), j = std::lround(v * resolution);
    const int sides[4] = {j == 0 ? 0 : -1, i == resolution ? 1 : -1, j == resolution ? 2 : -1, i == 0 ? 3 : -1};
    for (const int side : sides) {
      if (side < 0) continue;
      const uint64_t edge = adjacency.cage_edge(face, side);
      const auto c = claimed.find(edge);
      if (c == claimed.end()) continue;
      const uint32_t base = surface.base_face_of_ptex(face);
      if (c->second == ~0u) c->second = base;
      if (c->second != base) continue;
      if (taken.insert(g).second) out.push_back(g);
      break;
    }
  }
  return out;
}

CAGEKIT_NAMESPACE_END
