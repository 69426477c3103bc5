// SPDX-License-Identifier: GPL-3.0-or-later
// Element shape measure (thesis §6.6.2); see quad_element_energy.h.
#include "layout/quad/quad_element_energy.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <numeric>

#include "core/angles.h"

CAGEKIT_NAMESPACE_BEGIN

using namespace plane2;

namespace {
const size_t kMaxSplitValence = 24;  // larger faces are not split (rated as they are)
}  // namespace

namespace {
// interior_angles into `angles` (polygon.size() values).
void interior_angles_into(const std::vector<Vec2>& polygon, double* angles) {
  const size_t n = polygon.size();
  for (size_t i = 0; i < n; ++i) {
    const Vec2& p = polygon[i];
    angles[i] = ccw_angle(polygon[(i + 1) % n] - p, polygon[(i + n - 1) % n] - p);
  }
}

// A polygon's interior angles on the stack when it is small (every face the selection rates,
// nearly), else on the heap.
class Angles {
 public:
  explicit Angles(const std::vector<Vec2>& polygon) : Angles(polygon.size()) { interior_angles_into(polygon, data_); }
  // Uninitialised, for the caller to fill (data()).
  explicit Angles(size_t n) {
    if (n > kStack) heap_.resize(n);
    data_ = n > kStack ? heap_.data() : stack_;
  }
  Angles(const Angles&) = delete;
  Angles& operator=(const Angles&) = delete;
  const double* data() const { return data_; }
  double* data() { return data_; }
  double operator[](size_t i) const { return data_[i]; }

 private:
  static constexpr size_t kStack = 32;
  double stack_[kStack];
  std::vector<double> heap_;
  double* data_;
};
}  // namespace

std::vector<double> interior_angles(const std::vector<Vec2>& polygon) {
  std::vector<double> angles(polygon.size());
  interior_angles_into(polygon, angles.data());
  return angles;
}

namespace {

// (6.4)-(6.8) of the quad q[0..3] with interior angles g[0..3] (interior_angles of q).
QuadEnergyTerms quad_terms(const Vec2* quad, const double* g) {
  double l[4], lmax = 0.0;
  for (int i = 0; i < 4; ++i) l[i] = hypot_length(quad[(i + 1) % 4] - quad[i]), lmax = std::max(lmax, l[i]);
  QuadEnergyTerms e;
  for (int i = 0; i < 4; ++i) {
    e.orthogonality += std::fabs(g[i] - kPi / 2);             // (6.4)
    e.parallelism += std::fabs(g[i] + g[(i + 1) % 4] - kPi);  // (6.5)
    e.rhombus *= 2.0 - (lmax > 0 ? l[i] / lmax : 0.0);        // (6.6)
  }
  auto ratio = [](double a, double b) { return std::max(a, b) > 0 ? std::min(a, b) / std::max(a, b) : 0.0; };
  e.rectangle = (2.0 - ratio(l[0], l[2])) * (2.0 - ratio(l[1], l[3]));  // (6.7)
  e.total = (1.0 + e.orthogonality) * (1.0 + e.parallelism) * e.rhombus * e.rectangle - 1.0;  // (6.8)
  return e;
}

// (6.9) from the polygon's n interior angles.
double angle_deviation(const double* angles, size_t n, double beta) {
  double e = 0.0;
  for (size_t i = 0; i < n; ++i) e += std::fabs(angles[i] - beta);
  return e;
}

}  // namespace

QuadEnergyTerms quad_energy_terms(const std::array<Vec2, 4>& quad) {
  const std::vector<Vec2> polygon(quad.begin(), quad.end());
  const std::vector<double> g = interior_angles(polygon);
  return quad_terms(quad.data(), g.data());
}

double angle_deviation_energy(const std::vector<Vec2>& polygon, double beta) {
  const Angles angles(polygon);
  return angle_deviation(angles.data(), polygon.size(), beta);  // (6.9)
}

namespace {

double rate_convex(const std::vector<Vec2>& polygon, const Angles& angles, const ElementWeights& w,
                   uint32_t& t_joints) {
  size_t n = polygon.size();
  std::vector<Vec2> without_t_joints;
  const std::vector<Vec2>* reduced_polygon = &polygon;  // the polygon, or it without its T-joints
  double extra = 0.0;
  if (n > 4) {
    std::vector<size_t> straight;
    for (size_t i = 0; i < n; ++i)
      if (std::fabs(angles[i] - kPi) <= w.t_joint_tolerance) straight.push_back(i);
    std::sort(straight.begin(), straight.end(),
              [&](size_t a, size_t b) { return std::fabs(angles[a] - kPi) < std::fabs(angles[b] - kPi); });
    const size_t k = std::min(straight.size(), n - 3);
    if (k > 0) {
      std::vector<char> drop(n, 0);
      for (size_t i = 0; i < k; ++i) drop[straight[i]] = 1;
      for (size_t i = 0; i < n; ++i)
        if (!drop[i]) without_t_joints.push_back(polygon[i]);
      reduced_polygon = &without_t_joints;
      extra = double(k) * w.t_joint;
      t_joints += static_cast<uint32_t>(k);
      n = without_t_joints.size();
    }
  }
  const std::vector<Vec2>& reduced = *reduced_polygon;
  // The polygon's own angles when nothing was dropped (the same values interior_angles would
  // give again); a polygon without its T-joints has other angles at their neighbours.
  std::optional<Angles> reduced_angles_storage;
  const double* reduced_angles = angles.data();
  if (reduced_polygon != &polygon) reduced_angles = reduced_angles_storage.emplace(reduced).data();
  if (n == 4) return extra + quad_terms(reduced.data(), reduced_angles).total;
  if (n == 3) return extra + w.triangle * (w.polygon_offset + angle_deviation(reduced_angles, n, kPi / 3));
  const double beta = (double(n) - 2.0) * kPi / double(n);
  double e = extra + w.pentagon * (w.polygon_offset + angle_deviation(reduced_angles, n, beta));
  if (n > 5) e += w.high_valence * (double(n) - 5.0);
  return e;
}

// A diagonal (i, j) of a simple polygon lies inside it: it crosses no edge and both parts are
// counter-clockwise.
bool diagonal_inside(const std::vector<Vec2>& polygon, size_t i, size_t j) {
  const size_t n = polygon.size();
  for (size_t e = 0; e < n; ++e) {
    const size_t f = (e + 1) % n;
    if (e == i || f == i || e == j || f == j) continue;
    if (segments_intersect(polygon[i], polygon[j], polygon[e], polygon[f])) return false;
  }
  return true;
}

// Greedy split: each diagonal from the most concave vertex is scored by rating its two parts
// without further splitting; only the best one is split recursively (O(n²) per level instead of
// the exponential search over all split trees).
// `pieces`: also list the output faces (ElementRating::pieces); the energy is the same either way.
ElementRating rate_recursive(const std::vector<Vec2>& polygon, const ElementWeights& w, int depth, bool split,
                             bool pieces) {
  ElementRating rating;
  const size_t n = polygon.size();
  auto whole_polygon_is_the_piece = [&] {
    if (!pieces) return;
    rating.pieces.emplace_back(n);
    std::iota(rating.pieces.back().begin(), rating.pieces.back().end(), 0u);
  };
  if (n < 3 || !(signed_area(polygon) > 0.0)) {
    rating.energy = w.invalid;
    rating.invalid = true;
    whole_polygon_is_the_piece();
    return rating;
  }
  const Angles angles(polygon);
  size_t concave = n;
  for (size_t i = 0; i < n; ++i)
    if (angles[i] > kPi + w.t_joint_tolerance && (concave == n || angles[i] > angles[concave])) concave = i;
  if (split && concave != n && n > 3 && n <= kMaxSplitValence && depth < 16) {
    // The two parts of the diagonal (concave, j): the vertices from one end to the other.
    auto part_of = [&](size_t from, size_t to, std::vector<uint32_t>& indices, std::vector<Vec2>& sub_polygon) {
      indices.clear(), sub_polygon.clear();
      for (size_t k = from;; k = (k + 1) % n) {
        indices.push_back(static_cast<uint32_t>(k));
        sub_polygon.push_back(polygon[k]);
        if (k == to) break;
      }
    };
    double best_score = std::numeric_limits<double>::infinity();
    size_t best_j = n;
    std::vector<uint32_t> indices;
    std::vector<Vec2> sub_polygon;
    for (size_t step = 2; step + 1 < n; ++step) {
      const size_t j = (concave + step) % n;
      if (!diagonal_inside(polygon, concave, j)) continue;
      double score = 0.0;
      for (const auto& [from, to] : {std::pair<size_t, size_t>{concave, j}, {j, concave}}) {
        part_of(from, to, indices, sub_polygon);
        // rate_recursive(sub_polygon, w, depth + 1, false, false) without recomputing what it
        // would find again: the part's angles are the polygon's except at the diagonal's ends
        // (same neighbours, so the same values), and its area is positive.
        if (!(signed_area(sub_polygon) > 0.0)) {
          score += std::numeric_limits<double>::infinity();
          continue;
        }
        const size_t m = sub_polygon.size();
        Angles sub_angles(m);
        for (size_t i = 0; i < m; ++i)
          sub_angles.data()[i] =
              i == 0 || i + 1 == m
                  ? ccw_angle(sub_polygon[(i + 1) % m] - sub_polygon[i], sub_polygon[(i + m - 1) % m] - sub_polygon[i])
                  : angles[indices[i]];
        uint32_t unused_t_joints = 0;
        score += rate_convex(sub_polygon, sub_angles, w, unused_t_joints);
      }
      if (score < best_score) best_score = score, best_j = j;
    }
    if (std::isfinite(best_score)) {
      ElementRating combined;
      for (const auto& [from, to] : {std::pair<size_t, size_t>{concave, best_j}, {best_j, concave}}) {
        part_of(from, to, indices, sub_polygon);
        const ElementRating r = rate_recursive(sub_polygon, w, depth + 1, true, pieces);
        combined.energy += r.energy;
        combined.t_joints += r.t_joints;
        combined.invalid = combined.invalid || r.invalid;
        for (const auto& piece : r.pieces) {
          std::vector<uint32_t> mapped;
          for (uint32_t k : piece) mapped.push_back(indices[k]);
          combined.pieces.push_back(std::move(mapped));
        }
      }
      return combined;
    }
  }
  rating.energy = rate_convex(polygon, angles, w, rating.t_joints);
  whole_polygon_is_the_piece();
  return rating;
}

}  // namespace

ElementRating rate_element(const std::vector<Vec2>& polygon, const ElementWeights& weights) {
  return rate_recursive(polygon, weights, 0, true, true);
}

double element_energy(const std::vector<Vec2>& polygon, const ElementWeights& weights) {
  return rate_recursive(polygon, weights, 0, true, false).energy;
}

CAGEKIT_NAMESPACE_END
