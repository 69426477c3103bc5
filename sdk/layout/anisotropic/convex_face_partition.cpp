// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/anisotropic/convex_face_partition.h"

#include <cmath>

#include "core/angles.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {
constexpr double kConcaveTolerance = 1e-6;  // radians past π before a corner counts as concave

std::vector<uint32_t> sub_loop(const std::vector<uint32_t>& loop, size_t from, size_t to) {
  std::vector<uint32_t> out;
  for (size_t k = from;; k = (k + 1) % loop.size()) {
    out.push_back(loop[k]);
    if (k == to) break;
  }
  return out;
}
}  // namespace

void partition_face(const std::vector<Vec3>& p, const std::vector<Vec3>& n, const std::vector<uint32_t>& loop,
                    int max_valence, std::vector<std::vector<uint32_t>>& out, PartitionStats& stats,
                    std::unordered_set<uint64_t>* edges) {
  std::vector<std::vector<uint32_t>> stack{loop};
  for (size_t guard = 0; !stack.empty() && guard < 100000; ++guard) {
    const std::vector<uint32_t> f = std::move(stack.back());
    stack.pop_back();
    const size_t m = f.size();
    if (m < 3) continue;
    const Vec3 fn = loop_normal(p, f);
    std::vector<double> theta(m);
    size_t worst = m;
    for (size_t i = 0; i < m; ++i) {
      theta[i] = corner_angle(p, n, f, i, fn);
      if (theta[i] > kPi + kConcaveTolerance && (worst == m || theta[i] > theta[worst])) worst = i;
    }
    const bool concave = worst != m;
    if (!concave && m <= size_t(max_valence)) {
      out.push_back(f);
      continue;
    }
    // Candidates, in order of preference: diagonals from the most concave corner, from any
    // concave corner, any diagonal inside both end angles; then (non-planar faces whose projected
    // angles do not add up) any diagonal leaving convex angles at both ends [J].
    size_t bi = m, bj = m;
    for (int level = concave ? 0 : 2; level < 4 && bi == m; ++level) {
      double best_score = -1e300;
      for (size_t i = 0; i < m; ++i) {
        if (level == 0 && i != worst) continue;
        if (level == 1 && !(theta[i] > kPi + kConcaveTolerance)) continue;
        for (size_t j = 0; j < m; ++j) {
          if (j == i || j == (i + 1) % m || (j + 1) % m == i) continue;
          if (level >= 2 && j < i) continue;
          if (edges && edges->count(edge_key(f[i], f[j]))) continue;
          const std::vector<uint32_t> a = sub_loop(f, i, j), b = sub_loop(f, j, i);
          // New corners: in a, i is first and j last; in b, j is first and i last.
          const Vec3 fa = loop_normal(p, a), fb = loop_normal(p, b);
          const double ai = corner_angle(p, n, a, 0, fa), aj = corner_angle(p, n, a, a.size() - 1, fa);
          const double bj2 = corner_angle(p, n, b, 0, fb), bi2 = corner_angle(p, n, b, b.size() - 1, fb);
          const double tol = 1e-6;
          if (level < 3) {
            if (std::fabs(ai + bi2 - theta[i]) > tol || std::fabs(aj + bj2 - theta[j]) > tol) continue;  // outside
            if (ai < tol || bi2 < tol || aj < tol || bj2 < tol) continue;
          } else {
            const double hi = kPi + kConcaveTolerance;
            if (ai < tol || bi2 < tol || aj < tol || bj2 < tol || ai > hi || bi2 > hi || aj > hi || bj2 > hi) continue;
          }
          const double h = 0.5 * kPi;
          double score = -((ai - h) * (ai - h) + (aj - h) * (aj - h) + (bi2 - h) * (bi2 - h) + (bj2 - h) * (bj2 - h));
          score += (a.size() == 4 ? 0.5 : 0.0) + (b.size() == 4 ? 0.5 : 0.0);
          if (score > best_score) {
            best_score = score;
            bi = i;
            bj = j;
          }
        }
      }
    }
    if (bi == m) {
      ++stats.unresolved;
      out.push_back(f);
      continue;
    }
    ++(concave ? stats.concave_splits : stats.valence_splits);
    if (edges) edges->insert(edge_key(f[bi], f[bj]));
    stack.push_back(sub_loop(f, bi, bj));
    stack.push_back(sub_loop(f, bj, bi));
  }
}

CAGEKIT_NAMESPACE_END
