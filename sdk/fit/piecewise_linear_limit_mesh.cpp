// SPDX-License-Identifier: GPL-3.0-or-later
#include "fit/piecewise_linear_limit_mesh.h"

#include <algorithm>
#include <cmath>

#include "core/parallel_for.h"
#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

// Closest point of triangle (a, b, c) to p as barycentric weights (Ericson, Real-Time
// Collision Detection, 5.1.5).
void closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double w[3]) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) { w[0] = 1, w[1] = 0, w[2] = 0; return; }
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) { w[0] = 0, w[1] = 1, w[2] = 0; return; }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double t = d1 / (d1 - d3);
    w[0] = 1 - t, w[1] = t, w[2] = 0;
    return;
  }
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) { w[0] = 0, w[1] = 0, w[2] = 1; return; }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double t = d2 / (d2 - d6);
    w[0] = 1 - t, w[1] = 0, w[2] = t;
    return;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    w[0] = 0, w[1] = 1 - t, w[2] = t;
    return;
  }
  const double sum = va + vb + vc;
  if (!(sum > 0)) {  // degenerate triangle: nearest vertex
    const double da = dot(ap, ap), db = dot(bp, bp), dc = dot(cp, cp);
    w[0] = da <= db && da <= dc, w[1] = db < da && db <= dc, w[2] = dc < da && dc < db;
    return;
  }
  w[1] = vb / sum, w[2] = vc / sum, w[0] = 1 - w[1] - w[2];
}

constexpr uint32_t kLeafSize = 4;  // triangles per BVH leaf

inline double axis_gap(double p, double lo, double hi) { return std::max(0.0, std::max(lo - p, p - hi)); }

inline double box_distance2(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  const double x = axis_gap(p.x, lo.x, hi.x), y = axis_gap(p.y, lo.y, hi.y), z = axis_gap(p.z, lo.z, hi.z);
  return x * x + y * y + z * z;
}

}  // namespace

PiecewiseLinearLimitMesh::PiecewiseLinearLimitMesh(const SubdivisionSurface& surface,
                                                   const std::vector<Vec3>& patch_points, int resolution, int threads)
    : resolution_(resolution) {
  if (resolution < 1 || resolution > 64) fail(Status::invalid_argument, "piecewise-linear mesh: resolution must be in [1, 64]");
  const int r = resolution, g = r + 1;
  for (uint32_t f = 0; f < surface.num_ptex_faces(); ++f)
    if (surface.has_limit_surface(f)) grid_face_.push_back(f);
  if (grid_face_.empty()) fail(Status::invalid_mesh, "piecewise-linear mesh: the cage has no limit surface");
  // Stencils of the grid points over the patch points, on `threads` threads (each fills its own
  // blocks), then joined in block order.
  const size_t blocks = grid_face_.size(), per_block = size_t(g) * size_t(g);
  const size_t workers = std::max<size_t>(1, std::min<size_t>(size_t(std::max(threads, 1)), blocks / 64));
  struct Part {
    std::vector<uint32_t> counts, points;
    std::vector<double> weights;
  };
  std::vector<Part> parts(workers);
  std::vector<size_t> part_begin(workers + 1, 0);
  run_ranges(blocks, workers, [&](size_t begin, size_t end, size_t w) {
    Part& part = parts[w];
    std::vector<uint32_t> points;
    std::vector<double> weights;
    for (size_t b = begin; b < end; ++b)
      for (int i = 0; i < g; ++i)
        for (int j = 0; j < g; ++j) {
          surface.patch_point_weights(grid_face_[b], double(i) / r, double(j) / r, points, weights);
          part.counts.push_back(uint32_t(points.size()));
          part.points.insert(part.points.end(), points.begin(), points.end());
          part.weights.insert(part.weights.end(), weights.begin(), weights.end());
        }
  });
  stencil_offsets_.reserve(blocks * per_block + 1);
  stencil_offsets_.push_back(0);
  for (Part& part : parts) {
    for (uint32_t c : part.counts) stencil_offsets_.push_back(stencil_offsets_.back() + c);
    stencil_points_.insert(stencil_points_.end(), part.points.begin(), part.points.end());
    stencil_weights_.insert(stencil_weights_.end(), part.weights.begin(), part.weights.end());
    part = Part();
  }
  if (stencil_offsets_.size() != blocks * per_block + 1)
    fail(Status::internal_error, "piecewise-linear mesh: grid stencils incomplete");
  evaluate_grid(patch_points, threads);
  for (uint32_t block = 0; block < blocks; ++block) {
    for (int i = 0; i < r; ++i)
      for (int j = 0; j < r; ++j)
        for (int half = 0; half < 2; ++half) {
          tri_face_.push_back(block);
          tri_cell_.push_back(uint16_t(2 * (i * r + j) + half));
        }
  }
  // Corners of every triangle once (triangle order), then the BVH over them, then the corners
  // in BVH order for the queries.
  const size_t T = tri_face_.size();
  std::vector<Vec3> corners(3 * T), centroids(T);
  for (uint32_t t = 0; t < T; ++t) {
    double uv[3][2];
    triangle(t, &corners[3 * size_t(t)], uv);
    centroids[t] = (corners[3 * size_t(t)] + corners[3 * size_t(t) + 1] + corners[3 * size_t(t) + 2]) * (1.0 / 3.0);
  }
  order_.resize(T);
  for (uint32_t t = 0; t < T; ++t) order_[t] = t;
  // Ptex-face centroids: the hierarchy keeps each ptex face's triangles in one subtree (see build).
  std::vector<Vec3> face_centroids(blocks);
  for (size_t b = 0; b < blocks; ++b) {
    Vec3 sum;
    for (size_t k = 0; k < per_block; ++k) sum += grid_[b * per_block + k];
    face_centroids[b] = sum * (1.0 / double(per_block));
  }
  nodes_.reserve(2 * T / kLeafSize + 2);
  build(0, uint32_t(T), corners, centroids, face_centroids);
  corners_.resize(3 * T);
  sorted_ptex_.resize(T);
  for (size_t k = 0; k < T; ++k) {
    std::copy_n(&corners[3 * size_t(order_[k])], 3, &corners_[3 * k]);
    sorted_ptex_[k] = grid_face_[tri_face_[order_[k]]];
  }
  // Which subtrees lie in one ptex face (children follow their parent in the node array).
  for (size_t n = nodes_.size(); n-- > 0;) {
    Node& node = nodes_[n];
    if (node.count > 0) {
      node.ptex_face = sorted_ptex_[node.first];
      for (uint32_t k = node.first + 1; k < node.first + node.count; ++k)
        if (sorted_ptex_[k] != node.ptex_face) node.ptex_face = kNoFace;
    } else {
      const uint32_t a = nodes_[n + 1].ptex_face, b = nodes_[node.first].ptex_face;
      node.ptex_face = a == b ? a : kNoFace;
    }
  }
}

void PiecewiseLinearLimitMesh::evaluate_grid(const std::vector<Vec3>& patch_points, int threads) {
  const size_t count = stencil_offsets_.size() - 1;
  grid_.resize(count);
  for (uint32_t p : stencil_points_)
    if (p >= patch_points.size()) fail(Status::invalid_argument, "piecewise-linear mesh: patch point array too small");
  const size_t workers = std::max<size_t>(1, std::min<size_t>(size_t(std::max(threads, 1)), count / 4096));
  run_ranges(count, workers, [&](size_t begin, size_t end, size_t) {
    for (size_t k = begin; k < end; ++k) {
      Vec3 q;
      for (uint32_t e = stencil_offsets_[k]; e < stencil_offsets_[k + 1]; ++e)
        q += patch_points[stencil_points_[e]] * stencil_weights_[e];
      grid_[k] = q;
    }
  });
}

void PiecewiseLinearLimitMesh::update(const std::vector<Vec3>& patch_points, int threads) {
  evaluate_grid(patch_points, threads);
  const size_t T = order_.size();
  for (size_t k = 0; k < T; ++k) {
    double uv[3][2];
    triangle(order_[k], &corners_[3 * k], uv);
  }
  refit();
}

void PiecewiseLinearLimitMesh::refit() {
  for (size_t n = nodes_.size(); n-- > 0;) {
    Node& node = nodes_[n];
    Vec3 lo(HUGE_VAL, HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL, -HUGE_VAL);
    if (node.count > 0) {
      for (size_t k = 3 * size_t(node.first); k < 3 * size_t(node.first + node.count); ++k)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], corners_[k][a]), hi[a] = std::max(hi[a], corners_[k][a]);
    } else {
      const Node &l = nodes_[n + 1], &r = nodes_[node.first];
      for (int a = 0; a < 3; ++a) lo[a] = std::min(l.lo[a], r.lo[a]), hi[a] = std::max(l.hi[a], r.hi[a]);
    }
    node.lo = lo;
    node.hi = hi;
  }
}

void PiecewiseLinearLimitMesh::triangle(uint32_t t, Vec3 corners[3], double uv[3][2]) const {
  const int r = resolution_, g = r + 1;
  const uint32_t block = tri_face_[t];
  const int cell = tri_cell_[t] / 2, half = tri_cell_[t] % 2;
  const int i = cell / r, j = cell % r;
  // Cell corners (i, j), (i+1, j), (i+1, j+1), (i, j+1); halves split along (i, j)-(i+1, j+1).
  const int ci[3] = {i, i + 1, half == 0 ? i + 1 : i};
  const int cj[3] = {j, half == 0 ? j : j + 1, j + 1};
  for (int k = 0; k < 3; ++k) {
    corners[k] = grid_[size_t(block) * g * g + size_t(ci[k]) * g + size_t(cj[k])];
    uv[k][0] = double(ci[k]) / r;
    uv[k][1] = double(cj[k]) / r;
  }
}

uint32_t PiecewiseLinearLimitMesh::build(uint32_t begin, uint32_t end, const std::vector<Vec3>& corners,
                                         const std::vector<Vec3>& centroids, const std::vector<Vec3>& face_centroids) {
  const uint32_t index = uint32_t(nodes_.size());
  nodes_.push_back({});
  Vec3 lo(HUGE_VAL, HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL, -HUGE_VAL), clo = lo, chi = hi;
  bool one_face = true;
  for (uint32_t k = begin; k < end; ++k) {
    const Vec3* c = &corners[3 * size_t(order_[k])];
    for (int i = 0; i < 3; ++i) {
      const Vec3& p = c[i];
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
    }
    one_face = one_face && tri_face_[order_[k]] == tri_face_[order_[begin]];
  }
  // Split key: the triangle's centroid inside one ptex face; above that the ptex face's
  // centroid, so that every ptex face ends up in one subtree (a query that ignores a face skips
  // it at the subtree's root).
  auto key = [&](uint32_t t) -> const Vec3& { return one_face ? centroids[t] : face_centroids[tri_face_[t]]; };
  for (uint32_t k = begin; k < end; ++k) {
    const Vec3& m = key(order_[k]);
    for (int a = 0; a < 3; ++a) clo[a] = std::min(clo[a], m[a]), chi[a] = std::max(chi[a], m[a]);
  }
  nodes_[index].lo = lo;
  nodes_[index].hi = hi;
  if (end - begin <= kLeafSize) {
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    return index;
  }
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (chi[a] - clo[a] > chi[axis] - clo[axis]) axis = a;
  uint32_t mid = begin + (end - begin) / 2;
  if (one_face) {
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](uint32_t a, uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
  } else {
    // Order by (face centroid, face); then move the split to the nearer end of the middle
    // face's run of triangles, which the two partitions make contiguous.
    auto less = [&](uint32_t a, uint32_t b) {
      const double ka = face_centroids[tri_face_[a]][axis], kb = face_centroids[tri_face_[b]][axis];
      return ka < kb || (ka == kb && tri_face_[a] < tri_face_[b]);
    };
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end, less);
    const uint32_t face = tri_face_[order_[mid]];
    const auto run_begin = std::partition(order_.begin() + begin, order_.begin() + mid,
                                          [&](uint32_t t) { return tri_face_[t] != face; });
    const auto run_end = std::partition(order_.begin() + mid, order_.begin() + end,
                                        [&](uint32_t t) { return tri_face_[t] == face; });
    const uint32_t first = uint32_t(run_begin - order_.begin()), last = uint32_t(run_end - order_.begin());
    mid = (mid - first <= last - mid && first > begin) || last == end ? first : last;
  }
  build(begin, mid, corners, centroids, face_centroids);
  const uint32_t right = build(mid, end, corners, centroids, face_centroids);
  nodes_[index].first = right;
  nodes_[index].count = 0;
  return index;
}

PiecewiseLinearLimitMesh::Hit PiecewiseLinearLimitMesh::closest_point(const Vec3& p, double max_distance,
                                                                       uint32_t exclude_ptex_face) const {
  Hit best;
  double best_d2 = max_distance < HUGE_VAL ? max_distance * max_distance : HUGE_VAL;
  uint32_t best_k = ~0u;
  double best_w[3] = {0, 0, 0};
  // Depth-first, nearer child first; each node's box distance is computed once, by its parent,
  // and kept on the stack (the bound may have shrunk by the time it is popped).
  struct Entry {
    uint32_t node;
    double d2;
  };
  Entry stack[128];
  int top = 0;
  stack[top++] = {0, box_distance2(p, nodes_[0].lo, nodes_[0].hi)};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.d2 >= best_d2) continue;
    const Node& node = nodes_[e.node];
    if (node.count > 0) {
      for (uint32_t k = node.first; k < node.first + node.count; ++k) {
        if (sorted_ptex_[k] == exclude_ptex_face) continue;
        const Vec3* c = &corners_[3 * size_t(k)];
        double w[3];
        closest_on_triangle(p, c[0], c[1], c[2], w);
        const Vec3 q = c[0] * w[0] + c[1] * w[1] + c[2] * w[2];
        const double d2 = dot(q - p, q - p);
        if (d2 < best_d2) {
          best_d2 = d2;
          best_k = k;
          std::copy_n(w, 3, best_w);
          best.position = q;
        }
      }
      continue;
    }
    // Children: left = n + 1, right = node.first.
    const uint32_t a = e.node + 1, b = node.first;
    const bool use_a = exclude_ptex_face == kNoFace || nodes_[a].ptex_face != exclude_ptex_face;
    const bool use_b = exclude_ptex_face == kNoFace || nodes_[b].ptex_face != exclude_ptex_face;
    const double da = use_a ? box_distance2(p, nodes_[a].lo, nodes_[a].hi) : HUGE_VAL;
    const double db = use_b ? box_distance2(p, nodes_[b].lo, nodes_[b].hi) : HUGE_VAL;
    if (top + 2 > 128) fail(Status::internal_error, "piecewise-linear mesh: BVH too deep");
    const Entry near = da < db ? Entry{a, da} : Entry{b, db}, far = da < db ? Entry{b, db} : Entry{a, da};
    if (far.d2 < best_d2) stack[top++] = far;
    if (near.d2 < best_d2) stack[top++] = near;
  }
  if (best_k == ~0u) {
    best.distance = HUGE_VAL;
    return best;
  }
  Vec3 c[3];
  double uv[3][2];
  triangle(order_[best_k], c, uv);
  best.ptex_face = grid_face_[tri_face_[order_[best_k]]];
  best.u = std::clamp(best_w[0] * uv[0][0] + best_w[1] * uv[1][0] + best_w[2] * uv[2][0], 0.0, 1.0);
  best.v = std::clamp(best_w[0] * uv[0][1] + best_w[1] * uv[1][1] + best_w[2] * uv[2][1], 0.0, 1.0);
  best.distance = std::sqrt(best_d2);
  return best;
}

CAGEKIT_NAMESPACE_END
