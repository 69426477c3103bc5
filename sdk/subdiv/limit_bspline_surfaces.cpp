// SPDX-License-Identifier: GPL-3.0-or-later
#include "subdiv/limit_bspline_surfaces.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <unordered_map>

#include "core/memory_budget.h"
#include "core/parallel_for.h"
#include "subdiv/subdivision_surface.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

constexpr int kDegree = 3;
constexpr double kPi = 3.14159265358979323846;
// Second-row control points next to an extraordinary end of a smooth border that are left to the
// least-squares fit instead of the shared cross derivative.
constexpr int kIrregularSkip = 2;
// A surface whose normal is more than this far from the limit surface's normal somewhere on its
// check grid is folded: it is refined like a surface over the tolerance.
constexpr double kFoldDegrees = 90.0;
// Sine of the angle between the two first derivatives below which a surface point counts as
// degenerate (no normal).
constexpr double kDegenerateSine = 1e-2;
// A normal jump across a smooth border above this is checked against the limit surface's own
// normals there (a cage whose limit folds has such borders).
constexpr double kLimitFoldRadians = 30.0 * kPi / 180.0;
constexpr int kMaxLevelDifference = 1;

// ---- B-spline basics (clamped knot vectors, degree 3) -------------------------------------

std::vector<double> clamped_uniform_knots(int spans) {
  std::vector<double> k;
  k.reserve(size_t(spans) + 7);
  for (int i = 0; i < kDegree; ++i) k.push_back(0.0);
  for (int i = 0; i <= spans; ++i) k.push_back(i == spans ? 1.0 : double(i) / spans);
  for (int i = 0; i < kDegree; ++i) k.push_back(1.0);
  return k;
}

// The knot span index s with knots[s] <= t < knots[s + 1] (the last non-empty span for t = end).
int find_span(const std::vector<double>& knots, int num_points, double t) {
  if (t >= knots[size_t(num_points)]) return num_points - 1;
  if (t <= knots[kDegree]) return kDegree;
  int lo = kDegree, hi = num_points;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (t < knots[size_t(mid)]) hi = mid; else lo = mid;
  }
  return lo;
}

// Values (d[0]) and first derivatives (d[1]) of the 4 non-zero basis functions on span `span`
// (The NURBS Book, A2.3, n = 1).
void basis_derivatives(const std::vector<double>& knots, int span, double t, double d[2][4]) {
  double ndu[4][4], left[4], right[4];
  ndu[0][0] = 1.0;
  for (int j = 1; j <= kDegree; ++j) {
    left[j] = t - knots[size_t(span + 1 - j)];
    right[j] = knots[size_t(span + j)] - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      ndu[j][r] = right[r + 1] + left[j - r];
      const double tmp = ndu[r][j - 1] / ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * tmp;
      saved = left[j - r] * tmp;
    }
    ndu[j][j] = saved;
  }
  for (int j = 0; j <= kDegree; ++j) d[0][j] = ndu[j][kDegree];
  // First derivative: p * (N_{r-1,p-1} / (u_{r+p} - u_r) - N_{r,p-1} / (u_{r+p+1} - u_{r+1})).
  for (int r = 0; r <= kDegree; ++r) {
    double v = 0.0;
    if (r >= 1) v += ndu[r - 1][kDegree - 1] / ndu[kDegree][r - 1];
    if (r <= kDegree - 1) v -= ndu[r][kDegree - 1] / ndu[kDegree][r];
    d[1][r] = kDegree * v;
  }
}

// Dense row-major matrix of the basis values at `params`: rows = params, cols = control points.
std::vector<double> basis_matrix(const std::vector<double>& knots, int num_points, const std::vector<double>& params) {
  std::vector<double> b(params.size() * size_t(num_points), 0.0);
  for (size_t r = 0; r < params.size(); ++r) {
    const int span = find_span(knots, num_points, params[r]);
    double d[2][4];
    basis_derivatives(knots, span, params[r], d);
    for (int k = 0; k <= kDegree; ++k) b[r * size_t(num_points) + size_t(span - kDegree + k)] = d[0][k];
  }
  return b;
}

// Solves the symmetric positive definite system a x = b (n x n, columns of b: nrhs) in place
// by Gaussian elimination with partial pivoting; b becomes x.
void solve_in_place(std::vector<double>& a, int n, std::vector<double>& b, int nrhs) {
  for (int c = 0; c < n; ++c) {
    int p = c;
    for (int r = c + 1; r < n; ++r)
      if (std::fabs(a[size_t(r * n + c)]) > std::fabs(a[size_t(p * n + c)])) p = r;
    if (p != c) {
      for (int k = 0; k < n; ++k) std::swap(a[size_t(c * n + k)], a[size_t(p * n + k)]);
      for (int k = 0; k < nrhs; ++k) std::swap(b[size_t(c * nrhs + k)], b[size_t(p * nrhs + k)]);
    }
    const double d = a[size_t(c * n + c)];
    if (d == 0.0) fail(Status::internal_error, "limit B-spline surfaces: singular least-squares system");
    for (int r = c + 1; r < n; ++r) {
      const double f = a[size_t(r * n + c)] / d;
      if (f == 0.0) continue;
      for (int k = c; k < n; ++k) a[size_t(r * n + k)] -= f * a[size_t(c * n + k)];
      for (int k = 0; k < nrhs; ++k) b[size_t(r * nrhs + k)] -= f * b[size_t(c * nrhs + k)];
    }
  }
  for (int c = n - 1; c >= 0; --c) {
    for (int k = 0; k < nrhs; ++k) {
      double s = b[size_t(c * nrhs + k)];
      for (int j = c + 1; j < n; ++j) s -= a[size_t(c * n + j)] * b[size_t(j * nrhs + k)];
      b[size_t(c * nrhs + k)] = s / a[size_t(c * n + c)];
    }
  }
}

// The least-squares operator L (free.size() x rows) with L y = argmin |B[:, free] x - y|:
// (B_f^T B_f)^-1 B_f^T.
std::vector<double> least_squares_operator(const std::vector<double>& b, size_t rows, int cols,
                                           const std::vector<int>& free) {
  const int nf = int(free.size());
  std::vector<double> ata(size_t(nf * nf), 0.0), at(size_t(nf) * rows, 0.0);
  for (int p = 0; p < nf; ++p)
    for (size_t r = 0; r < rows; ++r) at[size_t(p) * rows + r] = b[r * size_t(cols) + size_t(free[size_t(p)])];
  for (int p = 0; p < nf; ++p)
    for (int q = 0; q < nf; ++q) {
      double s = 0;
      for (size_t r = 0; r < rows; ++r) s += at[size_t(p) * rows + r] * at[size_t(q) * rows + r];
      ata[size_t(p * nf + q)] = s;
    }
  solve_in_place(ata, nf, at, int(rows));
  return at;
}

std::vector<double> uniform_params(int count) {
  std::vector<double> t(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) t[size_t(i)] = i == count - 1 ? 1.0 : double(i) / (count - 1);
  return t;
}

// Least-squares cubic B-spline curve (uniform clamped knots, `spans` spans) through samples y at
// uniform parameters; with fixed ends when `p0`/`p1` are given.
std::vector<Vec3> fit_curve(int spans, const std::vector<Vec3>& y, const Vec3* p0, const Vec3* p1) {
  const int n = spans + kDegree;
  const std::vector<double> knots = clamped_uniform_knots(spans);
  const std::vector<double> params = uniform_params(int(y.size()));
  const std::vector<double> b = basis_matrix(knots, n, params);
  std::vector<int> free;
  for (int i = 0; i < n; ++i)
    if (!((i == 0 && p0) || (i == n - 1 && p1))) free.push_back(i);
  std::vector<Vec3> points(static_cast<size_t>(n));
  if (p0) points[0] = *p0;
  if (p1) points[size_t(n - 1)] = *p1;
  std::vector<Vec3> rhs(y);
  for (size_t r = 0; r < y.size(); ++r) {
    if (p0) rhs[r] -= *p0 * b[r * size_t(n)];
    if (p1) rhs[r] -= *p1 * b[r * size_t(n) + size_t(n - 1)];
  }
  const std::vector<double> l = least_squares_operator(b, y.size(), n, free);
  for (size_t p = 0; p < free.size(); ++p) {
    Vec3 s;
    for (size_t r = 0; r < y.size(); ++r) s += rhs[r] * l[p * y.size() + r];
    points[size_t(free[p])] = s;
  }
  return points;
}

// The least-squares fit of fit_curve with both ends fixed and, at the ends given a unit tangent,
// the end leg along it: P1 = P0 + a0 T0, P(n-2) = P(n-1) + a1 T1, with the lengths a0, a1
// fitted too (never below `min_leg`). Used where the free fit hooks backwards at an
// extraordinary end (its first leg points away from the limit's tangent), which folds the
// surfaces at that corner.
std::vector<Vec3> fit_curve_with_end_tangents(int spans, const std::vector<Vec3>& y, const Vec3& p0, const Vec3& p1,
                                              const Vec3* t0, const Vec3* t1, double min_leg) {
  const int n = spans + kDegree;
  if (n < 4 || (!t0 && !t1)) return fit_curve(spans, y, &p0, &p1);
  const std::vector<double> b = basis_matrix(clamped_uniform_knots(spans), n, uniform_params(int(y.size())));
  std::vector<int> free;
  for (int i = 1; i <= n - 2; ++i)
    if (!((i == 1 && t0) || (i == n - 2 && t1))) free.push_back(i);
  double leg[2] = {-1.0, -1.0};  // < 0: fitted; else fixed at that length
  std::vector<Vec3> points(static_cast<size_t>(n));
  for (int attempt = 0; attempt < 2; ++attempt) {
    std::vector<int> fitted_legs;
    for (int e = 0; e < 2; ++e)
      if ((e == 0 ? t0 : t1) && leg[e] < 0.0) fitted_legs.push_back(e);
    const int unknowns = 3 * int(free.size()) + int(fitted_legs.size());
    std::vector<double> ata(size_t(unknowns) * size_t(unknowns), 0.0), atb(static_cast<size_t>(unknowns), 0.0);
    std::vector<double> coefficients(static_cast<size_t>(unknowns), 0.0);
    for (size_t r = 0; r < y.size(); ++r) {
      const double* w = &b[r * size_t(n)];
      Vec3 target = y[r] - p0 * w[0] - p1 * w[n - 1];
      if (t0) target -= (p0 + *t0 * std::max(leg[0], 0.0)) * w[1];
      if (t1) target -= (p1 + *t1 * std::max(leg[1], 0.0)) * w[n - 2];
      for (int c = 0; c < 3; ++c) {
        std::fill(coefficients.begin(), coefficients.end(), 0.0);
        for (size_t k = 0; k < free.size(); ++k) coefficients[3 * k + size_t(c)] = w[free[k]];
        for (size_t k = 0; k < fitted_legs.size(); ++k) {
          const Vec3& t = fitted_legs[k] == 0 ? *t0 : *t1;
          coefficients[3 * free.size() + k] = (fitted_legs[k] == 0 ? w[1] : w[n - 2]) * (c == 0 ? t.x : c == 1 ? t.y : t.z);
        }
        const double rhs = c == 0 ? target.x : c == 1 ? target.y : target.z;
        for (int i = 0; i < unknowns; ++i) {
          const double ci = coefficients[size_t(i)];
          if (ci == 0.0) continue;
          atb[size_t(i)] += ci * rhs;
          for (int j = 0; j < unknowns; ++j) ata[size_t(i) * size_t(unknowns) + size_t(j)] += ci * coefficients[size_t(j)];
        }
      }
    }
    solve_in_place(ata, unknowns, atb, 1);
    for (size_t k = 0; k < free.size(); ++k) points[size_t(free[k])] = Vec3{atb[3 * k], atb[3 * k + 1], atb[3 * k + 2]};
    bool again = false;
    for (size_t k = 0; k < fitted_legs.size(); ++k) {
      const double a = atb[3 * free.size() + k];
      if (a < min_leg) {
        leg[fitted_legs[k]] = min_leg;
        again = true;
      } else {
        leg[fitted_legs[k]] = a;
      }
    }
    if (!again) break;
  }
  points[0] = p0;
  points[size_t(n - 1)] = p1;
  if (t0) points[1] = p0 + *t0 * leg[0];
  if (t1) points[size_t(n - 2)] = p1 + *t1 * leg[1];
  return points;
}

// Splits a clamped uniform cubic curve of `spans` (even) spans at its middle knot into two
// clamped uniform curves of spans / 2 spans each (Boehm knot insertion of 1/2 twice more).
void split_curve(int spans, const std::vector<Vec3>& points, std::vector<Vec3>& left, std::vector<Vec3>& right) {
  std::vector<double> knots = clamped_uniform_knots(spans);
  std::vector<Vec3> p = points;
  for (int insertion = 0; insertion < 2; ++insertion) {
    const int n = int(p.size());
    const int k = find_span(knots, n, 0.5);  // knots[k] <= 0.5 < knots[k + 1]
    const int s = insertion + 1;              // current multiplicity of 0.5
    std::vector<Vec3> q(size_t(n + 1));
    for (int i = 0; i <= k - kDegree; ++i) q[size_t(i)] = p[size_t(i)];
    for (int i = k - s; i < n; ++i) q[size_t(i + 1)] = p[size_t(i)];
    for (int i = k - kDegree + 1; i <= k - s; ++i) {
      const double a = (0.5 - knots[size_t(i)]) / (knots[size_t(i + kDegree)] - knots[size_t(i)]);
      q[size_t(i)] = p[size_t(i - 1)] * (1.0 - a) + p[size_t(i)] * a;
    }
    knots.insert(knots.begin() + k + 1, 0.5);
    p.swap(q);
  }
  const size_t half = size_t(spans / 2 + kDegree);
  left.assign(p.begin(), p.begin() + long(half));
  right.assign(p.end() - long(half), p.end());
}

// Inserts knot t once (Boehm) into a clamped cubic curve (knots, points).
void insert_knot(std::vector<double>& knots, std::vector<Vec3>& p, double t) {
  const int n = int(p.size());
  const int k = find_span(knots, n, t);  // knots[k] <= t < knots[k + 1]
  std::vector<Vec3> q(size_t(n + 1));
  for (int i = 0; i <= k - kDegree; ++i) q[size_t(i)] = p[size_t(i)];
  for (int i = k; i < n; ++i) q[size_t(i + 1)] = p[size_t(i)];
  for (int i = k - kDegree + 1; i <= k; ++i) {
    const double a = (t - knots[size_t(i)]) / (knots[size_t(i + kDegree)] - knots[size_t(i)]);
    q[size_t(i)] = p[size_t(i - 1)] * (1.0 - a) + p[size_t(i)] * a;
  }
  knots.insert(knots.begin() + k + 1, t);
  p.swap(q);
}

// The same curve with `to` uniform spans (a power-of-two multiple of `from`): every new knot
// inserted once, so the refined curve is the given one (to rounding).
std::vector<Vec3> refine_curve(const std::vector<Vec3>& points, int from, int to) {
  std::vector<Vec3> p = points;
  if (p.empty() || to == from) return p;
  std::vector<double> knots = clamped_uniform_knots(from);
  for (int i = 1; i < to; ++i)
    if ((i * from) % to != 0) insert_knot(knots, p, double(i) / to);
  return p;
}

// ---- topology of the ptex sides --------------------------------------------------------------

// A key of a ptex corner: a cage vertex, an edge midpoint or a face centre.
uint64_t vertex_key(uint32_t v) { return uint64_t(v); }
uint64_t midpoint_key(uint32_t a, uint32_t b) {
  return (uint64_t(1) << 62) | (uint64_t(std::min(a, b)) << 31) | uint64_t(std::max(a, b));
}
uint64_t centre_key(uint32_t f) { return (uint64_t(2) << 62) | uint64_t(f); }

struct Attachment {
  uint32_t ptex = 0;
  int side = 0;
  double s0 = 0, s1 = 1;  // the side's t = 0 / t = 1 on the segment
  double scale = 1;       // ptex units per natural unit: 1 for quads, 1/2 for n-gon sub-faces
  int group = 0;          // 0 or 1: which side of the segment (the cross derivative's sign)
  double lo() const { return std::min(s0, s1); }
  double hi() const { return std::max(s0, s1); }
};

struct Segment {
  int level = 1;  // knot level (quad units): 2^level spans for a cage edge, 2^(level-1) for an inner segment
  int spans = 1;
  uint64_t key0 = 0, key1 = 0;  // corner keys at s = 0 and s = 1
  BorderKind kind = BorderKind::boundary;
  std::vector<Attachment> attachments;
  bool irregular_end[2] = {false, false};  // key0 / key1 is an extraordinary point (no G1 constraint next to it)
  bool keep_tangent[2] = {false, false};   // fit the leg at that end along the limit's direction (see check_corners)
  std::vector<Vec3> curve, cross;  // control points: border curve, natural cross derivative (group 0 inward)
  std::vector<Vec3> curve_half[2], cross_half[2];
};

struct SideRef {
  int segment = -1;
  int attachment = -1;
};

void side_location_impl(int side, double t, double& u, double& v) {
  switch (side) {
    case 0: u = t; v = 0; break;
    case 1: u = 1; v = t; break;
    case 2: u = t; v = 1; break;
    default: u = 0; v = t; break;
  }
}

class Builder {
 public:
  Builder(const Cage& cage, const SubdivisionSurface& surface, const std::vector<Vec3>& points,
          const TaskMonitor& monitor)
      : cage_(cage), surface_(surface), points_(points), monitor_(monitor) {
    build_topology();
  }

  // Knot levels are chosen per surface and direction: every segment (shared border) and every
  // surface starts at min_level; a surface over the tolerance (or folded) goes one level up in
  // both directions together with its four borders, and every surface keeps at least its
  // borders' levels in the matching direction (a border curve is refined into the surface's knots
  // by knot insertion, so it stays the same curve). Repeated until no surface below max_level is
  // over.
  LimitBSplineSurfaces run(const LimitBSplineOptions& options, double diagonal) {
    threads_ = options.threads;
    const uint32_t num_ptex = surface_.num_ptex_faces();
    const double tolerance = options.tolerance * diagonal;
    const double max_jump_deg = options.max_normal_jump_deg;
    level_.assign(num_ptex, {options.min_level, options.min_level});
    for (Segment& seg : segments_) seg.level = options.min_level;
    LimitBSplineSurfaces result;
    for (;;) {
      result = build_all(tolerance, diagonal);
      bool raised = false;
      for (const LimitBSplineSurface& surf : result.surfaces) {
        double jump = 0.0;
        for (const SurfaceSide& side : surf.sides)
          if (side.kind == BorderKind::smooth) jump = std::max(jump, side.max_normal_jump_deg);
        if (surf.exact ||
            (surf.error <= tolerance && surf.max_normal_deviation_deg <= kFoldDegrees && jump <= max_jump_deg))
          continue;
        std::array<int, 2>& level = level_[surf.ptex_face];
        const int next = std::max(level[0], level[1]) + 1;
        if (next > options.max_level) continue;
        level = {next, next};
        for (int side = 0; side < 4; ++side) {
          Segment& seg = segments_[size_t(sides_[surf.ptex_face][size_t(side)].segment)];
          seg.level = std::max(seg.level, next);
        }
        raised = true;
      }
      if (!raised) break;
      for (uint32_t p = 0; p < num_ptex; ++p)
        for (int side = 0; side < 4; ++side) {
          if (sides_[p][size_t(side)].segment < 0) continue;
          const int l = segments_[size_t(sides_[p][size_t(side)].segment)].level;
          int& mine = level_[p][side == 0 || side == 2 ? 0 : 1];
          mine = std::max(mine, l);
        }
      // Levels of one surface differ by at most kMaxLevelDifference (long thin knot cells next to
      // fixed border rows fold).
      for (uint32_t p = 0; p < num_ptex; ++p) {
        const int top = std::max(level_[p][0], level_[p][1]);
        for (int& l : level_[p]) l = std::max(l, top - kMaxLevelDifference);
      }
    }
    return result;
  }

 private:
  // ---- topology ----
  void build_topology() {
    const PolygonMesh& mesh = cage_.mesh;
    const uint32_t num_ptex = surface_.num_ptex_faces();
    sides_.assign(num_ptex, {});
    scale_.assign(num_ptex, 1.0);
    std::vector<char> hole(mesh.num_faces(), 0);
    for (uint32_t h : cage_.holes)
      if (h < hole.size()) hole[h] = 1;
    std::map<std::pair<uint32_t, uint32_t>, float> sharp;
    for (const EdgeCrease& c : cage_.creases)
      sharp[{std::min(c.v0, c.v1), std::max(c.v0, c.v1)}] = c.sharpness;
    std::map<std::pair<uint32_t, uint32_t>, int> edge_segment;
    auto cage_edge = [&](uint32_t a, uint32_t b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = edge_segment.find(key);
      if (it != edge_segment.end()) return it->second;
      Segment s;
      s.key0 = vertex_key(key.first);
      s.key1 = vertex_key(key.second);
      segments_.push_back(s);
      cage_edge_of_.push_back(key);
      edge_segment[key] = int(segments_.size()) - 1;
      return int(segments_.size()) - 1;
    };
    // Attaches side `side` of `ptex` running from cage vertex `from` towards `to` over the
    // whole edge (quads) or its first half (sub-faces).
    auto attach_edge = [&](uint32_t ptex, int side, uint32_t from, uint32_t to, bool half, uint32_t face) {
      const int seg = cage_edge(from, to);
      Attachment a;
      a.ptex = ptex;
      a.side = side;
      const bool forward = from < to;
      a.s0 = forward ? 0.0 : 1.0;
      a.s1 = half ? 0.5 : (forward ? 1.0 : 0.0);
      a.scale = half ? 0.5 : 1.0;
      a.group = int(face);  // replaced by 0/1 below
      segments_[size_t(seg)].attachments.push_back(a);
      sides_[ptex][size_t(side)] = {seg, int(segments_[size_t(seg)].attachments.size()) - 1};
    };
    for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
      if (hole[f]) continue;
      const uint32_t n = mesh.face_size(f);
      auto c = [&](uint32_t k) { return mesh.face_vertex(f, k % n); };
      if (n == 4) {
        const uint32_t p = surface_.ptex_face(f, 0);
        attach_edge(p, 0, c(0), c(1), false, f);
        attach_edge(p, 1, c(1), c(2), false, f);
        attach_edge(p, 2, c(3), c(2), false, f);
        attach_edge(p, 3, c(0), c(3), false, f);
        continue;
      }
      const int first_inner = int(segments_.size());
      for (uint32_t k = 0; k < n; ++k) {  // inner segment k: midpoint of edge k -> centre
        Segment s;
        s.key0 = midpoint_key(c(k), c(k + 1));
        s.key1 = centre_key(f);
        s.kind = BorderKind::smooth;
        segments_.push_back(s);
        cage_edge_of_.push_back({0, 0});
      }
      for (uint32_t k = 0; k < n; ++k) {
        const uint32_t p = surface_.ptex_face(f, k);
        scale_[p] = 0.5;
        attach_edge(p, 0, c(k), c(k + 1), true, f);
        attach_edge(p, 3, c(k), c(k + n - 1), true, f);
        Attachment a;
        a.ptex = p;
        a.scale = 0.5;
        a.side = 1;  // u = 1: midpoint of edge k -> centre
        a.group = 0;
        Segment& in = segments_[size_t(first_inner + int(k))];
        in.attachments.push_back(a);
        sides_[p][1] = {first_inner + int(k), int(in.attachments.size()) - 1};
        a.side = 2;  // v = 1: midpoint of edge k - 1 -> centre
        a.group = 1;
        Segment& prev = segments_[size_t(first_inner + int((k + n - 1) % n))];
        prev.attachments.push_back(a);
        sides_[p][2] = {first_inner + int((k + n - 1) % n), int(prev.attachments.size()) - 1};
      }
    }
    // Kinds and groups of the cage-edge segments.
    std::unordered_map<uint64_t, int> corner_count, sharp_count;
    for (size_t i = 0; i < segments_.size(); ++i) {
      Segment& s = segments_[i];
      if (s.key0 >> 62) continue;  // inner n-gon segment
      std::vector<int> faces;
      for (const Attachment& a : s.attachments)
        if (std::find(faces.begin(), faces.end(), a.group) == faces.end()) faces.push_back(a.group);
      for (Attachment& a : s.attachments) a.group = a.group == faces[0] ? 0 : 1;
      if (faces.size() == 1) {
        s.kind = BorderKind::boundary;
      } else if (faces.size() > 2) {
        s.kind = BorderKind::non_manifold;
      } else {
        auto it = sharp.find(cage_edge_of_[i]);
        s.kind = it != sharp.end() && it->second >= kSharpnessInfinite ? BorderKind::crease : BorderKind::smooth;
      }
    }
    // Extraordinary ends: n-gon centres; cage vertices with other than 4 ptex corners around them
    // (2 on a boundary) or with other than 0 or 2 sharp borders (darts, corners).
    for (const Segment& s : segments_) {
      if (s.key0 >> 62) continue;
      for (uint64_t key : {s.key0, s.key1}) {
        corner_count[key] += 0;
        if (s.kind != BorderKind::smooth) ++sharp_count[key];
        if (s.kind == BorderKind::boundary || s.kind == BorderKind::non_manifold) sharp_count[key] += 100;
      }
    }
    for (uint32_t p = 0; p < num_ptex; ++p)
      for (int side : {0, 2}) {  // a quad's corners: both ends of sides 0 and 2; a sub-face's: (0,0)
        const SideRef& r = sides_[p][size_t(side)];
        if (r.segment < 0 || (side == 2 && scale_[p] < 1.0)) continue;
        const Segment& s = segments_[size_t(r.segment)];
        const Attachment& a = s.attachments[size_t(r.attachment)];
        ++corner_count[a.s0 == 0.0 ? s.key0 : s.key1];
        if (scale_[p] == 1.0) ++corner_count[a.s1 == 0.0 ? s.key0 : s.key1];
      }
    for (Segment& s : segments_) {
      const uint64_t keys[2] = {s.key0, s.key1};
      for (int e = 0; e < 2; ++e) {
        const uint64_t kind = keys[e] >> 62;
        if (kind == 2) {
          s.irregular_end[e] = true;  // an n-gon's centre
        } else if (kind == 0) {
          const int sharp_edges = sharp_count[keys[e]], corners = corner_count[keys[e]];
          if (sharp_edges >= 100) s.irregular_end[e] = corners != 2;
          else s.irregular_end[e] = corners != 4 || (sharp_edges != 0 && sharp_edges != 2);
        }
      }
    }
  }

  // ---- per level ----
  bool exact_structure(uint32_t ptex, double u0, double v0, double size, double span) const {
    const PatchDomain d = surface_.patch_domain(ptex, u0 + 0.5 * size, v0 + 0.5 * size);
    if (d.size >= size * (1.0 - 1e-12)) return d.polynomial;
    if (size <= span * (1.0 + 1e-12)) return false;
    const double h = 0.5 * size;
    return exact_structure(ptex, u0, v0, h, span) && exact_structure(ptex, u0 + h, v0, h, span) &&
           exact_structure(ptex, u0, v0 + h, h, span) && exact_structure(ptex, u0 + h, v0 + h, h, span);
  }

  Vec3 corner(uint64_t key, uint32_t ptex, int side, double t) {
    auto it = corners_.find(key);
    if (it != corners_.end()) return it->second;
    double u, v;
    side_location_impl(side, t, u, v);
    const Vec3 p = surface_.evaluate_position(ptex, u, v, points_);
    corners_[key] = p;
    return p;
  }

  // The attachment of segment `s` that covers segment parameter x, an exact one if possible.
  const Attachment& cover(const Segment& s, double x, int group = -1) const {
    const Attachment* best = nullptr;
    for (const Attachment& a : s.attachments) {
      if (x < a.lo() - 1e-15 || x > a.hi() + 1e-15) continue;
      if (group >= 0 && a.group != group) continue;
      if (!best || (exact_[a.ptex] && !exact_[best->ptex])) best = &a;
    }
    return best ? *best : s.attachments[0];
  }

  static double side_t(const Attachment& a, double x) { return std::clamp((x - a.s0) / (a.s1 - a.s0), 0.0, 1.0); }

  Vec3 limit_on_side(const Attachment& a, double t) const {
    double u, v;
    side_location_impl(a.side, t, u, v);
    return surface_.evaluate_position(a.ptex, u, v, points_);
  }

  // Inward cross derivative of the attachment's face, in natural units (ptex / scale).
  Vec3 inward_on_side(const Attachment& a, double t) const {
    double u, v;
    side_location_impl(a.side, t, u, v);
    const SurfacePoint p = surface_.evaluate_patch_points(a.ptex, u, v, points_);
    Vec3 d;
    switch (a.side) {
      case 0: d = p.dv; break;
      case 1: d = -p.du; break;
      case 2: d = -p.dv; break;
      default: d = p.du; break;
    }
    return d * (1.0 / a.scale);
  }

  void fit_segment(Segment& s) {
    const bool inner = (s.key0 >> 62) != 0;
    s.spans = inner ? (1 << s.level) / 2 : (1 << s.level);
    const int samples = 4 * s.spans + 1;
    std::vector<Vec3> y(static_cast<size_t>(samples));
    for (int k = 0; k < samples; ++k) {
      const double x = k == samples - 1 ? 1.0 : double(k) / (samples - 1);
      const Attachment& a = cover(s, x);
      y[size_t(k)] = limit_on_side(a, side_t(a, x));
    }
    const Attachment& a0 = cover(s, 0.0);
    const Attachment& a1 = cover(s, 1.0);
    const Vec3 p0 = corner(s.key0, a0.ptex, a0.side, side_t(a0, 0.0));
    const Vec3 p1 = corner(s.key1, a1.ptex, a1.side, side_t(a1, 1.0));
    s.curve = fit_curve(s.spans, y, &p0, &p1);
    // A hook at an extraordinary end (the first leg more than 60 deg away from the limit's
    // direction there): refit with that leg along the limit's direction.
    Vec3 tangent[2];
    bool hooked[2] = {false, false};
    for (int e = 0; e < 2; ++e) {
      if (!s.irregular_end[e]) continue;
      const double x0 = e == 0 ? 0.0 : 1.0, x1 = e == 0 ? 1e-4 : 1.0 - 1e-4;
      const Attachment& a = cover(s, x0);
      const Vec3 d = limit_on_side(a, side_t(a, x1)) - limit_on_side(a, side_t(a, x0));
      const Vec3 leg = e == 0 ? s.curve[1] - s.curve[0] : s.curve[s.curve.size() - 2] - s.curve.back();
      if (norm(d) > 0.0 && norm(leg) > 0.0) {
        tangent[e] = d * (1.0 / norm(d));
        hooked[e] = s.keep_tangent[e] || dot(leg, tangent[e]) < 0.5 * norm(leg);
      }
    }
    if (hooked[0] || hooked[1])
      s.curve = fit_curve_with_end_tangents(s.spans, y, p0, p1, hooked[0] ? &tangent[0] : nullptr,
                                            hooked[1] ? &tangent[1] : nullptr, 0.02 * distance(p0, p1) / s.spans);
    s.cross.clear();
    if (s.kind == BorderKind::smooth) {
      for (int k = 0; k < samples; ++k) {
        // Next to an extraordinary end the cross derivative is singular (0 or unbounded at the
        // point): the first span's samples repeat the one at its far end (the control points
        // there are not constrained by it, see fit_surface).
        int kk = k;
        if (s.irregular_end[0]) kk = std::max(kk, 4);
        if (s.irregular_end[1]) kk = std::min(kk, samples - 5);
        const double x = kk == samples - 1 ? 1.0 : double(kk) / (samples - 1);
        const Attachment& g0 = cover(s, x, 0);
        const Attachment& g1 = cover(s, x, 1);
        const Vec3 d0 = inward_on_side(g0, side_t(g0, x)), d1 = -inward_on_side(g1, side_t(g1, x));
        if (exact_[g0.ptex] && !exact_[g1.ptex]) y[size_t(k)] = d0;
        else if (exact_[g1.ptex] && !exact_[g0.ptex]) y[size_t(k)] = d1;
        else y[size_t(k)] = (d0 + d1) * 0.5;
      }
      s.cross = fit_curve(s.spans, y, nullptr, nullptr);
    }
    if (!inner && s.spans >= 2) {
      split_curve(s.spans, s.curve, s.curve_half[0], s.curve_half[1]);
      if (!s.cross.empty()) split_curve(s.spans, s.cross, s.cross_half[0], s.cross_half[1]);
      corners_[midpoint_key(cage_edge_of_[size_t(&s - segments_.data())].first,
                            cage_edge_of_[size_t(&s - segments_.data())].second)] = s.curve_half[1][0];
    }
  }

  // Control points of an attachment's side in its own parameter t (border curve, inward
  // cross derivative in the face's ptex units; empty when the border is not smooth).
  // `spans`: the surface's knot spans along the side (a power-of-two multiple of the segment's).
  void side_points(const Segment& s, const Attachment& a, int spans, std::vector<Vec3>& curve,
                   std::vector<Vec3>& cross) const {
    const bool half = a.hi() - a.lo() < 0.75;
    const int which = half && a.lo() >= 0.5 ? 1 : 0;
    const int own = half ? s.spans / 2 : s.spans;
    curve = refine_curve(half ? s.curve_half[which] : s.curve, own, spans);
    cross = s.cross.empty() ? std::vector<Vec3>() : refine_curve(half ? s.cross_half[which] : s.cross, own, spans);
    if (a.s1 < a.s0) {
      std::reverse(curve.begin(), curve.end());
      std::reverse(cross.begin(), cross.end());
    }
    const double sign = a.group == 0 ? 1.0 : -1.0;
    for (Vec3& d : cross) d = d * (sign * a.scale);
  }

  void fit_surface(LimitBSplineSurface& out, uint32_t ptex, int spans_u, int spans_v) {
    const int nu = spans_u + kDegree, nv = spans_v + kDegree;
    const double hu = 1.0 / spans_u, hv = 1.0 / spans_v;
    out.ptex_face = ptex;
    out.cage_face = surface_.base_face_of_ptex(ptex);
    out.knots_u = clamped_uniform_knots(spans_u);
    out.knots_v = clamped_uniform_knots(spans_v);
    out.num_u = uint32_t(nu);
    out.num_v = uint32_t(nv);
    const size_t total = size_t(nu) * size_t(nv);
    out.points.assign(total, Vec3());
    auto at = [&](int i, int j) -> Vec3& { return out.points[size_t(j * nu + i)]; };
    std::vector<char> fixed(total, 0);
    std::vector<Vec3> sum(total);
    std::vector<int> count(total, 0), guess_count(total, 0);
    std::vector<Vec3> guess(total);
    bool fixed_row[2] = {false, false}, fixed_col[2] = {false, false};  // second rows/cols
    for (int side = 0; side < 4; ++side) {
      const SideRef& ref = sides_[ptex][size_t(side)];
      const Segment& s = segments_[size_t(ref.segment)];
      const bool along_u = side == 0 || side == 2;
      const int n = along_u ? nu : nv;
      const double h = along_u ? hv : hu;  // first knot span across the side
      std::vector<Vec3> curve, cross;
      side_points(s, s.attachments[size_t(ref.attachment)], along_u ? spans_u : spans_v, curve, cross);
      for (int k = 0; k < n; ++k) {
        const int i = along_u ? k : (side == 1 ? nu - 1 : 0);
        const int j = along_u ? (side == 2 ? nv - 1 : 0) : k;
        at(i, j) = curve[size_t(k)];
        fixed[size_t(j * nu + i)] = 2;
      }
      if (cross.empty()) continue;
      if (along_u) fixed_row[side / 2] = true; else fixed_col[side == 3 ? 0 : 1] = true;
      const Attachment& me = s.attachments[size_t(ref.attachment)];
      auto irregular = [&](double x) {
        return (x == 0.0 && s.irregular_end[0]) || (x == 1.0 && s.irregular_end[1]);
      };
      const int k_lo = irregular(me.s0) ? kIrregularSkip + 1 : 1;
      const int k_hi = irregular(me.s1) ? n - 2 - kIrregularSkip : n - 2;
      for (int k = 1; k <= n - 2; ++k) {
        const int i = along_u ? k : (side == 1 ? nu - 2 : 1);
        const int j = along_u ? (side == 2 ? nv - 2 : 1) : k;
        const Vec3 value = curve[size_t(k)] + cross[size_t(k)] * (h / 3.0);
        if (k >= k_lo && k <= k_hi) {
          sum[size_t(j * nu + i)] += value;
          ++count[size_t(j * nu + i)];
        } else {
          guess[size_t(j * nu + i)] += value;
          ++guess_count[size_t(j * nu + i)];
        }
      }
    }
    // Second-row points next to extraordinary ends (no constraint): fitted below, starting from
    // the cross-derivative guess.
    std::vector<int> loose;
    for (size_t idx = 0; idx < total; ++idx) {
      if (fixed[idx] == 2) continue;
      if (count[idx] > 0) {
        out.points[idx] = sum[idx] * (1.0 / count[idx]);
        fixed[idx] = 1;
      } else if (guess_count[idx] > 0) {
        out.points[idx] = guess[idx] * (1.0 / guess_count[idx]);
        loose.push_back(int(idx));
      }
    }
    // Free rows / columns.
    std::vector<int> free_i, free_j;
    for (int k = 1; k < nu - 1; ++k)
      if (!((k == 1 && fixed_col[0]) || (k == nu - 2 && fixed_col[1]))) free_i.push_back(k);
    for (int k = 1; k < nv - 1; ++k)
      if (!((k == 1 && fixed_row[0]) || (k == nv - 2 && fixed_row[1]))) free_j.push_back(k);
    if (loose.size() > 64) loose.resize(64);  // at most 4 sides x 2 ends x kIrregularSkip by construction
    const int nsu = 3 * spans_u + 1, nsv = 3 * spans_v + 1;
    const std::vector<double> params_u = uniform_params(nsu), params_v = uniform_params(nsv);
    const std::vector<double> bu = basis_matrix(out.knots_u, nu, params_u);
    const std::vector<double> bv = basis_matrix(out.knots_v, nv, params_v);
    std::vector<Vec3> samples(size_t(nsu) * size_t(nsv));  // [c][a]: u = params_u[a], v = params_v[c]
    for (int c = 0; c < nsv; ++c)
      for (int a = 0; a < nsu; ++a)
        samples[size_t(c * nsu + a)] =
            surface_.evaluate_position(ptex, params_u[size_t(a)], params_v[size_t(c)], points_);
    // Residual of the samples against the surface without the points in `skip`.
    auto residual = [&](const std::vector<char>& skip) {
      std::vector<Vec3> t(size_t(nv) * size_t(nsu));  // t[j][a] = sum_i P[j][i] Bu[a][i]
      for (int j = 0; j < nv; ++j)
        for (int a = 0; a < nsu; ++a) {
          Vec3 acc;
          for (int i = 0; i < nu; ++i) {
            const double w = bu[size_t(a * nu + i)];
            if (w != 0.0 && !skip[size_t(j * nu + i)]) acc += out.points[size_t(j * nu + i)] * w;
          }
          t[size_t(j * nsu + a)] = acc;
        }
      std::vector<Vec3> r(size_t(nsu) * size_t(nsv));
      for (int c = 0; c < nsv; ++c)
        for (int a = 0; a < nsu; ++a) {
          Vec3 acc;
          for (int j = 0; j < nv; ++j) {
            const double w = bv[size_t(c * nv + j)];
            if (w != 0.0) acc += t[size_t(j * nsu + a)] * w;
          }
          r[size_t(c * nsu + a)] = samples[size_t(c * nsu + a)] - acc;
        }
      return r;
    };
    const bool separable = !free_i.empty() && !free_j.empty();
    std::vector<double> lu, lv;
    std::vector<char> skip_free(total, 0), skip_loose(total, 0);
    if (separable) {
      lu = least_squares_operator(bu, size_t(nsu), nu, free_i);
      lv = least_squares_operator(bv, size_t(nsv), nv, free_j);
      for (int i : free_i)
        for (int j : free_j) skip_free[size_t(j * nu + i)] = 1;
    }
    for (int idx : loose) skip_loose[size_t(idx)] = 1;
    // The inner block (separable least squares: P_free = Lu R Lv^T).
    auto solve_inner = [&]() {
      if (!separable) return;
      const std::vector<Vec3> r = residual(skip_free);
      std::vector<Vec3> q(free_i.size() * size_t(nsv));  // q[p][c] = sum_a Lu[p][a] r[c][a]
      for (size_t p = 0; p < free_i.size(); ++p)
        for (int c = 0; c < nsv; ++c) {
          Vec3 acc;
          for (int a = 0; a < nsu; ++a) acc += r[size_t(c * nsu + a)] * lu[p * size_t(nsu) + size_t(a)];
          q[p * size_t(nsv) + size_t(c)] = acc;
        }
      for (size_t p = 0; p < free_i.size(); ++p)
        for (size_t w = 0; w < free_j.size(); ++w) {
          Vec3 acc;
          for (int c = 0; c < nsv; ++c) acc += q[p * size_t(nsv) + size_t(c)] * lv[w * size_t(nsv) + size_t(c)];
          at(free_i[p], free_j[w]) = acc;
        }
    };
    // The loose points (dense least squares over all samples, few unknowns).
    auto solve_loose = [&]() {
      if (loose.empty()) return;
      const std::vector<Vec3> r = residual(skip_loose);
      const int nl = int(loose.size());
      std::vector<double> ata(size_t(nl * nl), 0.0), rhs(size_t(nl * 3), 0.0);
      for (int c = 0; c < nsv; ++c)
        for (int a = 0; a < nsu; ++a) {
          double w[64];
          bool any = false;
          for (int k = 0; k < nl && k < 64; ++k) {
            const int i = loose[size_t(k)] % nu, j = loose[size_t(k)] / nu;
            w[k] = bu[size_t(a * nu + i)] * bv[size_t(c * nv + j)];
            any = any || w[k] != 0.0;
          }
          if (!any) continue;
          const Vec3& y = r[size_t(c * nsu + a)];
          for (int p = 0; p < nl; ++p) {
            if (w[p] == 0.0) continue;
            for (int q = 0; q < nl; ++q) ata[size_t(p * nl + q)] += w[p] * w[q];
            rhs[size_t(p * 3)] += w[p] * y.x;
            rhs[size_t(p * 3 + 1)] += w[p] * y.y;
            rhs[size_t(p * 3 + 2)] += w[p] * y.z;
          }
        }
      solve_in_place(ata, nl, rhs, 3);
      for (int k = 0; k < nl; ++k)
        out.points[size_t(loose[size_t(k)])] = Vec3{rhs[size_t(k * 3)], rhs[size_t(k * 3 + 1)], rhs[size_t(k * 3 + 2)]};
    };
    solve_inner();
    for (int pass = 0; pass < 2 && !loose.empty(); ++pass) {
      solve_loose();
      solve_inner();
    }
  }

  // Gauss-Newton projection of x onto a parametric surface over [0,1]^2 (evaluate(u, v) ->
  // position, du, dv), from (u, v) with distance `best` there; returns the smallest distance met
  // (an upper bound of the distance from x to the surface).
  template <class Evaluate>
  static double project(const Evaluate& evaluate, const Vec3& x, double u, double v, double best) {
    for (int it = 0; it < 10 && best > 0.0; ++it) {
      Vec3 position, du, dv;
      evaluate(u, v, position, du, dv);
      const Vec3 r = x - position;
      const double a11 = dot(du, du), a12 = dot(du, dv), a22 = dot(dv, dv);
      const double det = a11 * a22 - a12 * a12;
      if (!(det > 1e-30 * a11 * a22) || !(det > 0.0)) break;
      const double b1 = dot(du, r), b2 = dot(dv, r);
      const double step_u = (a22 * b1 - a12 * b2) / det, step_v = (a11 * b2 - a12 * b1) / det;
      bool improved = false;
      double f = 1.0;
      for (int half = 0; half < 6 && !improved; ++half, f *= 0.5) {
        const double nu = std::clamp(u + f * step_u, 0.0, 1.0), nv = std::clamp(v + f * step_v, 0.0, 1.0);
        Vec3 q, qu, qv;
        evaluate(nu, nv, q, qu, qv);
        const double d = distance(x, q);
        if (d < best) {
          improved = best - d > 1e-3 * best;
          best = d;
          u = nu;
          v = nv;
          if (!improved) return best;
        }
      }
      if (!improved) break;
    }
    return best;
  }

  // Fills the surface's error fields on a max(33, 4 spans + 1)^2 grid: the distance to the limit
  // surface at equal parameters, the normal deviation there, and the two-sided error (equal to
  // the parametric error where that is within `tolerance`; else each sample projected onto the
  // other surface, both ways, within the same ptex face).
  void measure(LimitBSplineSurface& s, int spans_u, int spans_v, double tolerance) const {
    const int ncu = std::max(33, 4 * spans_u + 1), ncv = std::max(33, 4 * spans_v + 1);
    double parametric = 0, deviation = 0, near = 0;
    struct Sample {
      double u, v, d;
      Vec3 mine, limit;
    };
    std::vector<Sample> far;
    for (int b = 0; b < ncv; ++b)
      for (int a = 0; a < ncu; ++a) {
        const double u = a == ncu - 1 ? 1.0 : double(a) / (ncu - 1), v = b == ncv - 1 ? 1.0 : double(b) / (ncv - 1);
        const BSplineSurfacePoint x = evaluate_bspline_surface(s, u, v);
        const SurfacePoint l = surface_.evaluate_patch_points(s.ptex_face, u, v, points_);
        const double d = distance(x.position, l.position);
        parametric = std::max(parametric, d);
        if (d > tolerance) far.push_back({u, v, d, x.position, l.position});
        else near = std::max(near, d);
        const Vec3 na = cross(x.du, x.dv), nl = cross(l.du, l.dv);
        // Where the limit's own derivatives are (nearly) parallel its normal is not a reference.
        if (norm(na) > 1e-12 * norm(x.du) * norm(x.dv) && norm(nl) > kDegenerateSine * norm(l.du) * norm(l.dv))
          deviation = std::max(deviation, std::atan2(norm(cross(na, nl)), dot(na, nl)) * 180.0 / kPi);
      }
    double two_sided = far.empty() ? parametric : near;
    if (!far.empty()) {
      // Samples within the tolerance at equal parameters are within it both ways.
      auto on_limit = [&](double u, double v, Vec3& p, Vec3& du, Vec3& dv) {
        const SurfacePoint q = surface_.evaluate_patch_points(s.ptex_face, u, v, points_);
        p = q.position;
        du = q.du;
        dv = q.dv;
      };
      auto on_spline = [&](double u, double v, Vec3& p, Vec3& du, Vec3& dv) {
        const BSplineSurfacePoint q = evaluate_bspline_surface(s, u, v);
        p = q.position;
        du = q.du;
        dv = q.dv;
      };
      for (const Sample& f : far) {
        two_sided = std::max(two_sided, project(on_limit, f.mine, f.u, f.v, f.d));
        two_sided = std::max(two_sided, project(on_spline, f.limit, f.u, f.v, f.d));
      }
      two_sided = std::min(two_sided, parametric);
    }
    s.parametric_error = parametric;
    s.error = two_sided;
    s.max_normal_deviation_deg = deviation;
  }

  // The leg of segment `s` leaving the end where attachment `a` has side parameter `t` (0 or 1),
  // and which end that is (-1: not an end of the segment, e.g. an edge midpoint).
  static int leg_at(const Segment& s, const Attachment& a, double t, Vec3& leg) {
    const double x = t == 0.0 ? a.s0 : a.s1;
    if (x != 0.0 && x != 1.0) return -1;
    const size_t n = s.curve.size();
    leg = x == 0.0 ? s.curve[1] - s.curve[0] : s.curve[n - 2] - s.curve[n - 1];
    return x == 0.0 ? 0 : 1;
  }

  // Every ptex corner at an extraordinary point whose two border legs give a normal more than
  // 45 deg from the limit's next to that corner (a fold of the surfaces there, typical of thin
  // corners, where a leg a few tens of degrees off the limit's direction crosses the other): both
  // legs are marked to be fitted along the limit's directions. Returns whether any was marked.
  bool check_corners() {
    static const int kSideU[4] = {0, 0, 2, 2}, kSideV[4] = {3, 1, 1, 3};
    static const double kTU[4] = {0, 1, 1, 0}, kTV[4] = {0, 0, 1, 1}, kSignU[4] = {1, -1, -1, 1},
                        kSignV[4] = {1, 1, -1, -1};
    bool marked = false;
    for (uint32_t p = 0; p < sides_.size(); ++p) {
      if (!surface_.has_limit_surface(p)) continue;
      for (int c = 0; c < 4; ++c) {
        const SideRef& ru = sides_[p][size_t(kSideU[c])];
        const SideRef& rv = sides_[p][size_t(kSideV[c])];
        if (ru.segment < 0 || rv.segment < 0) continue;
        Segment& su = segments_[size_t(ru.segment)];
        Segment& sv = segments_[size_t(rv.segment)];
        Vec3 leg_u, leg_v;
        const int eu = leg_at(su, su.attachments[size_t(ru.attachment)], kTU[c], leg_u);
        const int ev = leg_at(sv, sv.attachments[size_t(rv.attachment)], kTV[c], leg_v);
        if (eu < 0 || ev < 0 || !(su.irregular_end[eu] || sv.irregular_end[ev])) continue;
        if (su.keep_tangent[eu] && sv.keep_tangent[ev]) continue;
        const Vec3 bspline = cross(leg_u * kSignU[c], leg_v * kSignV[c]);
        const double u = kTU[c] == 0.0 ? 1e-3 : 1.0 - 1e-3, v = kTV[c] == 0.0 ? 1e-3 : 1.0 - 1e-3;
        const SurfacePoint l = surface_.evaluate_patch_points(p, u, v, points_);
        const Vec3 limit = cross(l.du, l.dv);
        if (!(norm(bspline) > 0.0) || !(norm(limit) > 0.0)) continue;
        if (dot(bspline, limit) < std::cos(kPi / 4) * norm(bspline) * norm(limit)) {
          su.keep_tangent[eu] = sv.keep_tangent[ev] = true;
          marked = true;
        }
      }
    }
    return marked;
  }

  // What a segment's fit depends on besides the limit surface: its level, which legs keep the
  // limit's tangent, which attached surfaces are exact (cover() samples those), and (inner n-gon
  // segments) the edge midpoint it starts from.
  std::vector<double> segment_inputs(const Segment& s) const {
    std::vector<double> in{double(s.level), double(s.keep_tangent[0]), double(s.keep_tangent[1])};
    for (const Attachment& a : s.attachments) in.push_back(double(exact_[a.ptex]));
    if (s.key0 >> 62) {
      const auto it = corners_.find(s.key0);
      if (it != corners_.end()) in.insert(in.end(), {it->second.x, it->second.y, it->second.z});
    }
    return in;
  }

  // Fits the segments whose inputs changed since their last fit (a round raises few levels; the
  // others keep their curves). segment_version_ counts each segment's fits.
  void fit_segments() {
    segment_inputs_.resize(segments_.size());
    segment_version_.resize(segments_.size(), 0);
    // Cage-edge segments first (they define the edge midpoints), then the inner ones.
    for (int pass = 0; pass < 2; ++pass)
      for (size_t i = 0; i < segments_.size(); ++i) {
        Segment& s = segments_[i];
        if (((s.key0 >> 62) != 0) != (pass == 1) || s.attachments.empty()) continue;
        std::vector<double> in = segment_inputs(s);
        if (segment_version_[i] > 0 && in == segment_inputs_[i]) continue;
        fit_segment(s);
        segment_inputs_[i] = std::move(in);
        ++segment_version_[i];
      }
  }

  // What a surface's fit depends on: its levels and its four borders' fits.
  std::array<uint64_t, 6> surface_inputs(uint32_t p) const {
    std::array<uint64_t, 6> in{uint64_t(level_[p][0]), uint64_t(level_[p][1]), 0, 0, 0, 0};
    for (size_t side = 0; side < 4; ++side) {
      const int segment = sides_[p][side].segment;
      in[2 + side] = segment < 0 ? ~uint64_t(0) : segment_version_[size_t(segment)];
    }
    return in;
  }

  int spans_of(uint32_t ptex, int direction) const {
    const int quad_spans = 1 << level_[ptex][size_t(direction)];
    return scale_[ptex] < 1.0 ? quad_spans / 2 : quad_spans;
  }

  LimitBSplineSurfaces build_all(double tolerance, double diagonal) {
    const uint32_t num_ptex = surface_.num_ptex_faces();
    monitor_.report("limit B-spline surfaces", 0.05);
    exact_.assign(num_ptex, 0);
    std::vector<uint32_t> ptex_list;
    uint64_t control_points = 0;
    int max_level = 0;
    for (uint32_t p = 0; p < num_ptex; ++p) {
      if (!surface_.has_limit_surface(p)) continue;
      ptex_list.push_back(p);
      const int spans = std::min(spans_of(p, 0), spans_of(p, 1));
      exact_[p] = exact_structure(p, 0.0, 0.0, 1.0, 1.0 / spans) ? 1 : 0;
      control_points += uint64_t(spans_of(p, 0) + 3) * uint64_t(spans_of(p, 1) + 3);
      max_level = std::max({max_level, level_[p][0], level_[p][1]});
    }
    // The points of this round's surfaces, of the previous round's (alive until this round's
    // result replaces them) and of the last fits kept for the next round (fitted_).
    check_memory_estimate(estimate_product(control_points, 3 * sizeof(Vec3)), "limit B-spline surfaces");
    fit_segments();
    for (int repair = 0; repair < 2 && check_corners(); ++repair) fit_segments();
    fitted_.resize(num_ptex);

    LimitBSplineSurfaces result;
    result.level = max_level;
    result.bbox_diagonal = diagonal;
    result.tolerance = tolerance;
    result.ptex_faces = num_ptex;
    std::vector<int> index_of(num_ptex, -1);
    result.surfaces.resize(ptex_list.size());
    // The fits are independent (they read the fitted segments only): in chunks over the worker
    // threads, progress and cancellation between chunks on this thread.
    const size_t workers = size_t(std::max(1, threads_));
    const size_t chunk = 16 * workers;
    for (size_t begin = 0; begin < ptex_list.size(); begin += chunk) {
      monitor_.report("limit B-spline surfaces", 0.1 + 0.8 * double(begin) / double(ptex_list.size()));
      const size_t end = std::min(ptex_list.size(), begin + chunk);
      run_ranges(end - begin, std::min(workers, end - begin), [&](size_t b, size_t e, size_t) {
        for (size_t k = begin + b; k < begin + e; ++k) {
          const uint32_t p = ptex_list[k];
          // A surface whose inputs did not change since the last round is the same surface.
          const std::array<uint64_t, 6> in = surface_inputs(p);
          if (fitted_[p].valid && fitted_[p].inputs == in) {
            result.surfaces[k] = fitted_[p].surface;
            continue;
          }
          fit_surface(result.surfaces[k], p, spans_of(p, 0), spans_of(p, 1));
          measure(result.surfaces[k], spans_of(p, 0), spans_of(p, 1), tolerance);
          fitted_[p] = {true, in, result.surfaces[k]};
        }
      });
    }
    for (size_t k = 0; k < ptex_list.size(); ++k) {
      const uint32_t p = ptex_list[k];
      index_of[p] = int(k);
      LimitBSplineSurface& s = result.surfaces[k];
      s.exact = exact_[p] && s.parametric_error <= 1e-12 * diagonal;
      if (s.exact) ++result.exact_count; else ++result.approximated_count;
      if (!s.exact && (s.error > tolerance || s.max_normal_deviation_deg > kFoldDegrees)) ++result.over_tolerance_count;
      if (s.max_normal_deviation_deg > kFoldDegrees) ++result.folded_count;
      result.max_parametric_error = std::max(result.max_parametric_error, s.parametric_error);
      result.max_normal_deviation_deg = std::max(result.max_normal_deviation_deg, s.max_normal_deviation_deg);
      result.max_error = std::max(result.max_error, s.error);
    }
    // Neighbours and normal jumps.
    for (size_t k = 0; k < ptex_list.size(); ++k) {
      const uint32_t p = ptex_list[k];
      LimitBSplineSurface& surf = result.surfaces[k];
      for (int side = 0; side < 4; ++side) {
        const SideRef& ref = sides_[p][size_t(side)];
        const Segment& seg = segments_[size_t(ref.segment)];
        const Attachment& me = seg.attachments[size_t(ref.attachment)];
        SurfaceSide& out = surf.sides[size_t(side)];
        out.kind = seg.kind;
        for (const Attachment& other : seg.attachments) {
          if (&other == &me || (seg.kind != BorderKind::non_manifold && other.group == me.group)) continue;
          const double lo = std::max(me.lo(), other.lo()), hi = std::min(me.hi(), other.hi());
          if (!(hi > lo)) continue;
          SideNeighbour nb;
          nb.surface = uint32_t(index_of[other.ptex]);
          nb.side = uint8_t(other.side);
          nb.t0 = side_t(me, lo);
          nb.t1 = side_t(me, hi);
          nb.n0 = side_t(other, lo);
          nb.n1 = side_t(other, hi);
          if (nb.t0 > nb.t1) {
            std::swap(nb.t0, nb.t1);
            std::swap(nb.n0, nb.n1);
          }
          out.neighbours.push_back(nb);
          const LimitBSplineSurface& them = result.surfaces[size_t(index_of[other.ptex])];
          const int samples = 4 * seg.spans + 1;
          // Interior points of the shared range only: at the ends several surfaces meet at one
          // corner, where an extraordinary vertex has no well-defined corner normal per surface.
          for (int q = 1; q < samples - 1; ++q) {
            const double x = lo + (hi - lo) * q / (samples - 1);
            double u0, v0, u1, v1;
            side_location_impl(side, side_t(me, x), u0, v0);
            side_location_impl(other.side, side_t(other, x), u1, v1);
            const BSplineSurfacePoint a = evaluate_bspline_surface(surf, u0, v0);
            const BSplineSurfacePoint b = evaluate_bspline_surface(them, u1, v1);
            const Vec3 na = cross(a.du, a.dv), nb2 = cross(b.du, b.dv);
            // Not where either surface is (nearly) degenerate: its normal is not defined there
            // (the limit surface itself can have such points when the cage folds).
            if (norm(na) <= kDegenerateSine * norm(a.du) * norm(a.dv) ||
                norm(nb2) <= kDegenerateSine * norm(b.du) * norm(b.dv))
              continue;
            const double angle = std::atan2(norm(cross(na, nb2)), dot(na, nb2));
            if (seg.kind == BorderKind::smooth && angle > kLimitFoldRadians) {
              // Is the limit surface itself folded here (its own normals on the two sides
              // opposed, or degenerate)? Then no G1 surface can follow it: counted, not a jump.
              const SurfacePoint la = surface_.evaluate_patch_points(p, u0, v0, points_);
              const SurfacePoint lb = surface_.evaluate_patch_points(other.ptex, u1, v1, points_);
              const Vec3 ma = cross(la.du, la.dv), mb = cross(lb.du, lb.dv);
              if (norm(ma) <= kDegenerateSine * norm(la.du) * norm(la.dv) ||
                  norm(mb) <= kDegenerateSine * norm(lb.du) * norm(lb.dv) ||
                  std::atan2(norm(cross(ma, mb)), dot(ma, mb)) > kLimitFoldRadians) {
                ++result.limit_fold_points;
                continue;
              }
            }
            out.max_normal_jump_deg = std::max(out.max_normal_jump_deg, angle * 180.0 / kPi);
          }
        }
        if (seg.kind == BorderKind::smooth)
          result.max_normal_jump_deg = std::max(result.max_normal_jump_deg, out.max_normal_jump_deg);
        else
          result.max_crease_angle_deg = std::max(result.max_crease_angle_deg, out.max_normal_jump_deg);
      }
    }
    return result;
  }

  const Cage& cage_;
  const SubdivisionSurface& surface_;
  const std::vector<Vec3>& points_;
  const TaskMonitor& monitor_;
  std::vector<Segment> segments_;
  std::vector<std::pair<uint32_t, uint32_t>> cage_edge_of_;  // per segment ({0,0} for inner ones)
  std::vector<std::array<SideRef, 4>> sides_;                 // per ptex face
  std::vector<double> scale_;                                 // per ptex face
  std::vector<char> exact_;                                   // per ptex face, this round
  int threads_ = 1;
  std::vector<std::array<int, 2>> level_;                     // per ptex face: knot level in u, v (quad units)
  // Corner points: cage vertices' limit points (evaluated once) and edge midpoints (set by their
  // cage edge's last fit).
  std::unordered_map<uint64_t, Vec3> corners_;
  std::vector<std::vector<double>> segment_inputs_;  // per segment: segment_inputs at its last fit
  std::vector<uint64_t> segment_version_;             // per segment: number of fits so far
  struct Fitted {
    bool valid = false;
    std::array<uint64_t, 6> inputs{};  // surface_inputs at the fit
    LimitBSplineSurface surface;       // fitted and measured, sides not filled in yet
  };
  std::vector<Fitted> fitted_;  // per ptex face: its last fit (rounds refit only what changed)
};

}  // namespace

void side_location(int side, double t, double& u, double& v) { side_location_impl(side, t, u, v); }

BSplineSurfacePoint evaluate_bspline_surface(const LimitBSplineSurface& s, double u, double v) {
  const int su = find_span(s.knots_u, int(s.num_u), u), sv = find_span(s.knots_v, int(s.num_v), v);
  double bu[2][4], bv[2][4];
  basis_derivatives(s.knots_u, su, u, bu);
  basis_derivatives(s.knots_v, sv, v, bv);
  BSplineSurfacePoint r;
  for (int j = 0; j <= kDegree; ++j)
    for (int i = 0; i <= kDegree; ++i) {
      const Vec3& p = s.points[size_t(sv - kDegree + j) * s.num_u + size_t(su - kDegree + i)];
      r.position += p * (bu[0][i] * bv[0][j]);
      r.du += p * (bu[1][i] * bv[0][j]);
      r.dv += p * (bu[0][i] * bv[1][j]);
    }
  return r;
}

LimitBSplineSurfaces build_limit_bspline_surfaces(const Cage& cage, const LimitBSplineOptions& options,
                                                  const TaskMonitor& monitor) {
  if (!(options.tolerance > 0.0) || !std::isfinite(options.tolerance))
    fail(Status::invalid_argument, "limit B-spline surfaces: tolerance must be a finite number > 0");
  if (!(options.max_normal_jump_deg > 0.0) || !std::isfinite(options.max_normal_jump_deg))
    fail(Status::invalid_argument, "limit B-spline surfaces: max_normal_jump_deg must be a finite number > 0");
  if (options.threads < 1 || options.threads > 1024)
    fail(Status::invalid_argument, "limit B-spline surfaces: threads must be in [1, 1024]");
  if (options.max_level < 1 || options.max_level > kMaxLimitBSplineLevel)
    fail(Status::invalid_argument,
         "limit B-spline surfaces: max_level must be in [1, " + std::to_string(kMaxLimitBSplineLevel) + "]");
  if (options.min_level < 1 || options.min_level > options.max_level)
    fail(Status::invalid_argument, "limit B-spline surfaces: min_level must be in [1, max_level]");
  monitor.report("limit B-spline surfaces", 0.0);
  const SubdivisionSurface surface(cage, SurfaceOptions());
  const std::vector<Vec3> points = surface.patch_points(cage.mesh.positions);
  Vec3 lo = cage.mesh.positions.empty() ? Vec3() : cage.mesh.positions[0], hi = lo;
  for (const Vec3& p : cage.mesh.positions) {
    lo = Vec3{std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = Vec3{std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  Builder builder(cage, surface, points, monitor);
  LimitBSplineSurfaces result = builder.run(options, distance(lo, hi));
  monitor.report("limit B-spline surfaces", 1.0);
  return result;
}

CAGEKIT_NAMESPACE_END
