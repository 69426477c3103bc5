// SPDX-License-Identifier: GPL-3.0-or-later
#include "subdiv/limit_patches.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <string>

#include "core/memory_budget.h"
#include "core/parallel_for.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

// Samples per side of the grid the error of an approximated patch is measured on; the fit uses
// every kStride-th one (9 per side). Exact patches are checked on the 9 x 9 fit grid.
constexpr int kGrid = 33;
constexpr int kFit = 9;
constexpr int kStride = (kGrid - 1) / (kFit - 1);  // 4

double bernstein(int i, double s) {
  const double r = 1.0 - s;
  switch (i) {
    case 0: return r * r * r;
    case 1: return 3.0 * s * r * r;
    case 2: return 3.0 * s * s * r;
    default: return s * s * s;
  }
}

// Inverts a small dense matrix in place (Gauss-Jordan with partial pivoting; the matrices here
// are fixed and well conditioned).
template <int N>
void invert(double (&a)[N][N]) {
  double inv[N][N] = {};
  for (int i = 0; i < N; ++i) inv[i][i] = 1.0;
  for (int c = 0; c < N; ++c) {
    int pivot = c;
    for (int r = c + 1; r < N; ++r)
      if (std::fabs(a[r][c]) > std::fabs(a[pivot][c])) pivot = r;
    for (int k = 0; k < N; ++k) {
      std::swap(a[c][k], a[pivot][k]);
      std::swap(inv[c][k], inv[pivot][k]);
    }
    const double d = 1.0 / a[c][c];
    for (int k = 0; k < N; ++k) {
      a[c][k] *= d;
      inv[c][k] *= d;
    }
    for (int r = 0; r < N; ++r) {
      if (r == c) continue;
      const double f = a[r][c];
      for (int k = 0; k < N; ++k) {
        a[r][k] -= f * a[c][k];
        inv[r][k] -= f * inv[c][k];
      }
    }
  }
  for (int i = 0; i < N; ++i)
    for (int k = 0; k < N; ++k) a[i][k] = inv[i][k];
}

// The fixed matrices of the conversions, built once.
struct BezierFitMatrices {
  double interpolate[4][4];  // inverse of B_i(a / 3): exact polynomial from a 4 x 4 grid
  double edge[2][2];         // inverse normal matrix of the inner two points of a border curve
  double inner[4][4];        // inverse normal matrix of the 4 inner points
  double b[kFit][4];         // B_i(a / (kFit - 1))
  double g[kGrid][4];        // B_i(a / (kGrid - 1))

  BezierFitMatrices() {
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 4; ++i) interpolate[a][i] = bernstein(i, a / 3.0);
    invert(interpolate);
    for (int a = 0; a < kFit; ++a)
      for (int i = 0; i < 4; ++i) b[a][i] = bernstein(i, a / double(kFit - 1));
    for (int a = 0; a < kGrid; ++a)
      for (int i = 0; i < 4; ++i) g[a][i] = bernstein(i, a / double(kGrid - 1));
    double e[2][2] = {};
    for (int a = 1; a < kFit - 1; ++a)
      for (int p = 0; p < 2; ++p)
        for (int q = 0; q < 2; ++q) e[p][q] += b[a][1 + p] * b[a][1 + q];
    invert(e);
    for (int p = 0; p < 2; ++p)
      for (int q = 0; q < 2; ++q) edge[p][q] = e[p][q];
    double n[4][4] = {};
    for (int ta = 1; ta < kFit - 1; ++ta)
      for (int sa = 1; sa < kFit - 1; ++sa) {
        double w[4];
        for (int k = 0; k < 4; ++k) w[k] = b[sa][1 + (k & 1)] * b[ta][1 + (k >> 1)];
        for (int p = 0; p < 4; ++p)
          for (int q = 0; q < 4; ++q) n[p][q] += w[p] * w[q];
      }
    invert(n);
    for (int p = 0; p < 4; ++p)
      for (int q = 0; q < 4; ++q) inner[p][q] = n[p][q];
  }
};

const BezierFitMatrices& matrices() {
  static const BezierFitMatrices m;
  return m;
}

// Thrown to unwind a worker after another one failed (caught in the worker; the other's error is
// the one reported).
struct Stopped {};

class PatchBuilder {
 public:
  // Called every so often with the ptex face being worked on (may throw to stop the build).
  using Check = std::function<void(size_t ptex)>;

  PatchBuilder(const SubdivisionSurface& surface, const std::vector<Vec3>& points, const LimitPatchOptions& options,
               double tolerance, int split_depth, std::atomic<size_t>& total, const std::atomic<bool>& stop,
               Check check)
      : surface_(surface),
        points_(points),
        options_(options),
        tolerance_(tolerance),
        split_depth_(split_depth),
        total_(total),
        stop_(stop),
        check_(std::move(check)) {}

  void build_face(uint32_t ptex, std::vector<LimitPatch>& out) {
    out.clear();
    if (!surface_.has_limit_surface(ptex)) return;
    ptex_ = ptex;
    if (check_) check_(ptex);
    cage_face_ = surface_.base_face_of_ptex(ptex);
    square(0.0, 0.0, 1.0, 0, out);
  }

 private:
  Vec3 limit(double u, double v) const {
    return surface_.evaluate_position(ptex_, std::min(u, 1.0), std::min(v, 1.0), points_);
  }

  void square(double u0, double v0, double size, int depth, std::vector<LimitPatch>& out) {
    if (stop_) throw Stopped();
    if (check_ && ++squares_ % 64 == 0) check_(ptex_);
    const PatchDomain d = surface_.patch_domain(ptex_, u0 + 0.5 * size, v0 + 0.5 * size);
    const bool single = d.size >= size * (1.0 - 1e-12);
    LimitPatch patch;
    patch.ptex_face = ptex_;
    patch.cage_face = cage_face_;
    patch.u0 = u0;
    patch.v0 = v0;
    patch.u1 = u0 + size;
    patch.v1 = v0 + size;
    if (single && d.polynomial) {
      exact(patch);
      emit(patch, out);
      return;
    }
    if (!single && depth < split_depth_) {
      split(u0, v0, size, depth, out);
      return;
    }
    approximate(patch);
    if (patch.error > tolerance_ && depth < options_.max_depth) {
      split(u0, v0, size, depth, out);
      return;
    }
    emit(patch, out);
  }

  void split(double u0, double v0, double size, int depth, std::vector<LimitPatch>& out) {
    const double h = 0.5 * size;
    square(u0, v0, h, depth + 1, out);
    square(u0 + h, v0, h, depth + 1, out);
    square(u0, v0 + h, h, depth + 1, out);
    square(u0 + h, v0 + h, h, depth + 1, out);
  }

  void emit(const LimitPatch& patch, std::vector<LimitPatch>& out) {
    if (total_.fetch_add(1) + 1 > options_.max_patches)
      fail(Status::limit_exceeded, "limit patches: more than max_patches = " + std::to_string(options_.max_patches) +
                                       " patches needed at this tolerance and max_depth");
    out.push_back(patch);
  }

  // The limit surface on the square's kGrid x kGrid grid, or only on every stride-th point.
  void sample(const LimitPatch& p, int stride = 1) {
    const double size = p.u1 - p.u0;
    for (int tb = 0; tb < kGrid; tb += stride)
      for (int sa = 0; sa < kGrid; sa += stride)
        grid_[tb][sa] = limit(p.u0 + size * sa / double(kGrid - 1), p.v0 + size * tb / double(kGrid - 1));
  }

  double measure(const LimitPatch& p, int stride = 1) const {
    const BezierFitMatrices& m = matrices();
    double worst = 0;
    for (int tb = 0; tb < kGrid; tb += stride)
      for (int sa = 0; sa < kGrid; sa += stride) {
        Vec3 x;
        for (int j = 0; j < 4; ++j)
          for (int i = 0; i < 4; ++i) x += p.points[4 * j + i] * (m.g[sa][i] * m.g[tb][j]);
        worst = std::max(worst, distance(x, grid_[tb][sa]));
      }
    return worst;
  }

  // The polynomial from its values on the 4 x 4 grid s, t in {0, 1/3, 2/3, 1}: P = M^-1 X M^-T.
  void exact(LimitPatch& p) {
    const BezierFitMatrices& m = matrices();
    const double size = p.u1 - p.u0;
    Vec3 x[4][4], y[4][4];
    for (int b = 0; b < 4; ++b)
      for (int a = 0; a < 4; ++a) x[b][a] = limit(p.u0 + size * a / 3.0, p.v0 + size * b / 3.0);
    for (int b = 0; b < 4; ++b)
      for (int i = 0; i < 4; ++i) {
        Vec3 s;
        for (int a = 0; a < 4; ++a) s += x[b][a] * m.interpolate[i][a];
        y[b][i] = s;
      }
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) {
        Vec3 s;
        for (int b = 0; b < 4; ++b) s += y[b][i] * m.interpolate[j][b];
        p.points[4 * j + i] = s;
      }
    p.exact = true;
    sample(p, kStride);
    p.error = measure(p, kStride);
  }

  // Border curves by least squares with interpolated corners, then the inner points.
  void approximate(LimitPatch& p) {
    const BezierFitMatrices& m = matrices();
    sample(p);
    // Border k: (start index, index step) into the 4 x 4 control net; samples along it.
    auto border = [&](int c0, int dc, auto sample_at) {
      const Vec3 p0 = sample_at(0), p3 = sample_at(kFit - 1);
      Vec3 r1, r2;
      for (int a = 1; a < kFit - 1; ++a) {
        const Vec3 r = sample_at(a) - p0 * m.b[a][0] - p3 * m.b[a][3];
        r1 += r * m.b[a][1];
        r2 += r * m.b[a][2];
      }
      p.points[c0] = p0;
      p.points[c0 + dc] = r1 * m.edge[0][0] + r2 * m.edge[0][1];
      p.points[c0 + 2 * dc] = r1 * m.edge[1][0] + r2 * m.edge[1][1];
      p.points[c0 + 3 * dc] = p3;
    };
    border(0, 1, [&](int a) { return grid_[0][kStride * a]; });           // t = 0
    border(12, 1, [&](int a) { return grid_[kGrid - 1][kStride * a]; });  // t = 1
    border(0, 4, [&](int a) { return grid_[kStride * a][0]; });           // s = 0
    border(3, 4, [&](int a) { return grid_[kStride * a][kGrid - 1]; });   // s = 1
    static constexpr int kInner[4] = {5, 6, 9, 10};  // (1,1) (2,1) (1,2) (2,2)
    Vec3 rhs[4];
    for (int tb = 1; tb < kFit - 1; ++tb)
      for (int sa = 1; sa < kFit - 1; ++sa) {
        Vec3 r = grid_[kStride * tb][kStride * sa];
        for (int j = 0; j < 4; ++j)
          for (int i = 0; i < 4; ++i) {
            const int k = 4 * j + i;
            if (k == 5 || k == 6 || k == 9 || k == 10) continue;
            r -= p.points[k] * (m.b[sa][i] * m.b[tb][j]);
          }
        for (int k = 0; k < 4; ++k) rhs[k] += r * (m.b[sa][1 + (k & 1)] * m.b[tb][1 + (k >> 1)]);
      }
    for (int k = 0; k < 4; ++k) {
      Vec3 s;
      for (int q = 0; q < 4; ++q) s += rhs[q] * m.inner[k][q];
      p.points[kInner[k]] = s;
    }
    p.exact = false;
    p.error = measure(p);
  }

  const SubdivisionSurface& surface_;
  const std::vector<Vec3>& points_;
  const LimitPatchOptions& options_;
  const double tolerance_;
  const int split_depth_;
  std::atomic<size_t>& total_;
  const std::atomic<bool>& stop_;
  Check check_;
  size_t squares_ = 0;
  uint32_t ptex_ = 0, cage_face_ = 0;
  Vec3 grid_[kGrid][kGrid];
};

}  // namespace

SurfaceOptions limit_patch_surface_options() { return SurfaceOptions(); }

Vec3 evaluate_limit_patch(const LimitPatch& patch, double s, double t) {
  Vec3 x;
  for (int j = 0; j < 4; ++j) {
    const double bj = bernstein(j, t);
    for (int i = 0; i < 4; ++i) x += patch.points[4 * j + i] * (bernstein(i, s) * bj);
  }
  return x;
}

LimitPatches build_limit_patches(const Cage& cage, const LimitPatchOptions& options, const TaskMonitor& monitor) {
  if (!(options.tolerance > 0.0) || !std::isfinite(options.tolerance))
    fail(Status::invalid_argument, "limit patches: tolerance must be a finite number > 0");
  if (options.max_depth < 0 || options.max_depth > kMaxLimitPatchDepth)
    fail(Status::invalid_argument, "limit patches: max_depth must be in [0, " +
                                       std::to_string(kMaxLimitPatchDepth) + "]");
  if (options.threads < 1) fail(Status::invalid_argument, "limit patches: threads must be >= 1");
  if (options.max_patches < 1 || options.max_patches > kMaxLimitPatches)
    fail(Status::invalid_argument, "limit patches: max_patches must be in [1, " + std::to_string(kMaxLimitPatches) + "]");
  monitor.report("limit patches", 0.0);
  SurfaceOptions surface_options = limit_patch_surface_options();
  surface_options.threads = options.threads;
  const SubdivisionSurface surface(cage, surface_options);
  const std::vector<Vec3> points = surface.patch_points(cage.mesh.positions);

  LimitPatches result;
  Vec3 lo = cage.mesh.positions.empty() ? Vec3() : cage.mesh.positions[0], hi = lo;
  for (const Vec3& p : cage.mesh.positions) {
    lo = Vec3{std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = Vec3{std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  result.bbox_diagonal = distance(lo, hi);
  result.tolerance = options.tolerance * result.bbox_diagonal;

  const uint32_t num_ptex = surface.num_ptex_faces();
  std::vector<std::vector<LimitPatch>> per_face(num_ptex);
  std::atomic<size_t> total{0};
  std::atomic<bool> stop{false};
  // The calling thread (worker 0) reports progress and checks the memory budget as it goes;
  // when it fails (cancelled, over budget) the others stop at their next square.
  run_ranges(num_ptex, std::min<size_t>(size_t(options.threads), std::max<uint32_t>(num_ptex, 1)),
             [&](size_t begin, size_t end, size_t worker) {
               PatchBuilder::Check check;
               if (worker == 0)
                 check = [&](size_t face) {
                   monitor.report("limit patches", 0.1 + 0.85 * double(face - begin) / double(end - begin));
                   check_memory_estimate(estimate_product(total.load(), sizeof(LimitPatch)), "limit patches");
                 };
               PatchBuilder builder(surface, points, options, result.tolerance, surface_options.isolation_level,
                                    total, stop, check);
               try {
                 for (size_t i = begin; i < end; ++i) builder.build_face(uint32_t(i), per_face[i]);
               } catch (const Stopped&) {
                 return;
               } catch (...) {
                 stop = true;
                 throw;
               }
             });
  check_memory_estimate(estimate_product(total.load(), sizeof(LimitPatch)), "limit patches");
  result.patches.reserve(total.load());
  for (std::vector<LimitPatch>& face : per_face) {
    for (const LimitPatch& p : face) {
      result.patches.push_back(p);
      if (p.exact) {
        ++result.exact_count;
      } else {
        ++result.approximated_count;
        result.max_error = std::max(result.max_error, p.error);
        if (p.error > result.tolerance) ++result.over_tolerance_count;
      }
    }
    std::vector<LimitPatch>().swap(face);
  }
  monitor.report("limit patches", 1.0);
  return result;
}

CAGEKIT_NAMESPACE_END
