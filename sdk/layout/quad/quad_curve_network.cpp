// SPDX-License-Identifier: GPL-3.0-or-later
// Candidate curve network (thesis §6.5); see quad_curve_network.h.
#include "layout/quad/quad_curve_network.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <thread>

#include "core/angles.h"
#include "core/parallel_for.h"
#include "core/simd_dispatch.h"
#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

namespace plane2 {

double ccw_angle(const Vec2& from, const Vec2& to) {
  double a = std::atan2(cross(from, to), dot(from, to));
  if (a < 0.0) a += 2.0 * kPi;
  return a;
}

namespace {
double orient(const Vec2& a, const Vec2& b, const Vec2& c) { return cross(b - a, c - a); }
bool on_segment(const Vec2& a, const Vec2& b, const Vec2& p) {
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
         p.y <= std::max(a.y, b.y);
}
}  // namespace

bool segments_intersect(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d, double* s, double* t) {
  if (std::max(a.x, b.x) < std::min(c.x, d.x) || std::max(c.x, d.x) < std::min(a.x, b.x) ||
      std::max(a.y, b.y) < std::min(c.y, d.y) || std::max(c.y, d.y) < std::min(a.y, b.y))
    return false;
  const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) {
    if (s) *s = o3 / (o3 - o4);
    if (t) *t = o1 / (o1 - o2);
    return true;
  }
  // Touching or collinear cases: report the touching point's parameters where they are defined.
  auto report = [&](double ps, double pt) {
    if (s) *s = ps;
    if (t) *t = pt;
    return true;
  };
  auto param = [](const Vec2& p, const Vec2& q, const Vec2& x) {
    const Vec2 e = q - p;
    const double l2 = dot(e, e);
    return l2 > 0.0 ? std::clamp(dot(x - p, e) / l2, 0.0, 1.0) : 0.0;
  };
  if (o1 == 0 && on_segment(a, b, c)) return report(param(a, b, c), 0.0);
  if (o2 == 0 && on_segment(a, b, d)) return report(param(a, b, d), 1.0);
  if (o3 == 0 && on_segment(c, d, a)) return report(0.0, param(c, d, a));
  if (o4 == 0 && on_segment(c, d, b)) return report(1.0, param(c, d, b));
  return false;
}

double signed_area(const std::vector<Vec2>& polygon) {
  double a = 0.0;
  for (size_t i = 0, n = polygon.size(); i < n; ++i) a += cross(polygon[i], polygon[(i + 1) % n]);
  return 0.5 * a;
}

}  // namespace plane2

using namespace plane2;

Vec2 CubicBezier2::eval(double t) const {
  const double s = 1.0 - t;
  const double b0 = s * s * s, b1 = 3 * s * s * t, b2 = 3 * s * t * t, b3 = t * t * t;
  return {b0 * control[0].x + b1 * control[1].x + b2 * control[2].x + b3 * control[3].x,
          b0 * control[0].y + b1 * control[1].y + b2 * control[2].y + b3 * control[3].y};
}

Vec2 CubicBezier2::derivative(double t) const {
  const double s = 1.0 - t;
  const Vec2 d0 = control[1] - control[0], d1 = control[2] - control[1], d2 = control[3] - control[2];
  return (d0 * (s * s) + d1 * (2 * s * t) + d2 * (t * t)) * 3.0;
}

Vec2 CubicBezier2::second_derivative(double t) const {
  const Vec2 e0 = control[2] - control[1] * 2.0 + control[0];
  const Vec2 e1 = control[3] - control[2] * 2.0 + control[1];
  return (e0 * (1.0 - t) + e1 * t) * 6.0;
}

CubicBezier2 connecting_bezier(const Vec2& ci, const Vec2& qi, const Vec2& cj, const Vec2& qj, double lambda,
                               double mu) {
  return {{ci, ci + qi * lambda, cj + qj * mu, cj}};
}

namespace {
// Gauss-Legendre nodes of (6.3) over `intervals` equal pieces, with the Bernstein factors of b'
// and the quadrature weight ½·h·w per node, computed with the same expressions (and so to the
// same bits) as evaluating them node by node.
struct QuadratureNodes {
  std::vector<double> s, t, a, b, c, q;
  explicit QuadratureNodes(int intervals) {
    static const double kNode[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
    static const double kWeight[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
    const double h = 1.0 / intervals;
    for (int k = 0; k < intervals; ++k)
      for (int g = 0; g < 4; ++g) {
        const double tt = h * (k + 0.5 * (kNode[g] + 1.0)), ss = 1.0 - tt;
        t.push_back(tt), s.push_back(ss);
        a.push_back(3 * ss * ss), b.push_back(6 * ss * tt), c.push_back(3 * tt * tt);
        q.push_back(0.5 * h * kWeight[g]);
      }
  }
};
}  // namespace

namespace {
// (6.3) over `nodes`, summed in node order; once the partial sum reaches `bound` the rest is
// skipped and the partial sum returned (the terms are >= 0 and rounding is monotone, so the
// full sum would be >= bound too: a caller comparing "< bound" gets the same answer).
CAGEKIT_VECTOR_CLONES double bending_energy_below(const CubicBezier2& curve, const QuadratureNodes& nodes,
                                                   double bound) {
  // b' and b'' as combinations of the control-polygon differences (the hot loop of the network).
  const Vec2 d0 = curve.control[1] - curve.control[0], d1 = curve.control[2] - curve.control[1],
             d2 = curve.control[3] - curve.control[2];
  const Vec2 e0 = d1 - d0, e1 = d2 - d1;
  const size_t n = nodes.t.size();
  const double* S = nodes.s.data();
  const double* T = nodes.t.data();
  const double* A = nodes.a.data();
  const double* B = nodes.b.data();
  const double* C = nodes.c.data();
  const double* Q = nodes.q.data();
  // Chunks of kChunk terms (independent: vectorisable), each summed in order. A degenerate node
  // (b' = 0) makes the energy +inf wherever it is; a chunk past the bound is not looked at.
  constexpr size_t kChunk = 8;
  double energy = 0.0;
  for (size_t first = 0; first < n; first += kChunk) {
    const size_t m = std::min(kChunk, n - first);
    double term[kChunk];
    int degenerate = 0;
    for (size_t j = 0; j < m; ++j) {
      const size_t i = first + j;
      const double x1 = A[i] * d0.x + B[i] * d1.x + C[i] * d2.x, y1 = A[i] * d0.y + B[i] * d1.y + C[i] * d2.y;
      const double x2 = 6 * (S[i] * e0.x + T[i] * e1.x), y2 = 6 * (S[i] * e0.y + T[i] * e1.y);
      const double speed2 = x1 * x1 + y1 * y1;
      degenerate |= !(speed2 > 0.0);
      const double cr = x1 * y2 - y1 * x2;
      term[j] = Q[i] * cr * cr / (speed2 * speed2 * speed2);
    }
    if (degenerate) return std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < m; ++j) energy += term[j];
    if (energy >= bound) return energy;
  }
  return energy;
}

const QuadratureNodes& default_nodes() {
  static const QuadratureNodes kEight(8);  // the default, used by the minimisation
  return kEight;
}
}  // namespace

double bending_energy(const CubicBezier2& curve, int intervals) {
  std::unique_ptr<QuadratureNodes> other;
  if (intervals != 8) other = std::make_unique<QuadratureNodes>(intervals);
  return bending_energy_below(curve, other ? *other : default_nodes(), std::numeric_limits<double>::infinity());
}

BendingFit minimize_bending_energy(const Vec2& ci, const Vec2& qi, const Vec2& cj, const Vec2& qj) {
  BendingFit fit;
  const double d = hypot_length(cj - ci);
  if (!(d > 0.0)) return fit;
  const Vec2 chord = (cj - ci) * (1.0 / d);
  // Facing collinear tangents: a straight segment, E ≡ 0 for every (λ, μ).
  if (std::fabs(cross(qi, chord)) < 1e-12 && std::fabs(cross(qj, chord)) < 1e-12 && dot(qi, chord) > 0.0 &&
      dot(qj, chord) < 0.0) {
    fit.lambda = fit.mu = d / 3.0;
    fit.valid = true;
    return fit;
  }
  const double lower = 1e-3 * d;
  const QuadratureNodes& nodes = default_nodes();
  // E at (λ, μ), or any value >= bound once it is known to be at least that.
  auto energy_at = [&](double lambda, double mu, double bound = std::numeric_limits<double>::infinity()) {
    ++fit.evaluations;
    if (segments_intersect(ci, ci + qi * lambda, cj, cj + qj * mu))
      return std::numeric_limits<double>::infinity();
    return bending_energy_below(connecting_bezier(ci, qi, cj, qj, lambda, mu), nodes, bound);
  };
  // (6.3) has several basins (e.g. a quarter turn: the symmetric stationary point is beaten by
  // two asymmetric ones), so every local minimum of the grid starts a compass search.
  static const double kGrid[8] = {0.03, 0.07, 0.15, 0.3, 0.5, 0.8, 1.2, 1.8};
  double grid[8][8];
  for (int a = 0; a < 8; ++a)
    for (int b = 0; b < 8; ++b) grid[a][b] = energy_at(kGrid[a] * d, kGrid[b] * d);
  std::vector<std::pair<double, std::pair<int, int>>> starts;
  for (int a = 0; a < 8; ++a)
    for (int b = 0; b < 8; ++b) {
      const double e = grid[a][b];
      if (!std::isfinite(e)) continue;
      bool local = true;
      for (int da = -1; da <= 1; ++da)
        for (int db = -1; db <= 1; ++db) {
          const int x = a + da, y = b + db;
          if ((da || db) && x >= 0 && x < 8 && y >= 0 && y < 8 && grid[x][y] < e) local = false;
        }
      if (local) starts.push_back({e, {a, b}});
    }
  std::sort(starts.begin(), starts.end());
  if (starts.size() > 3) starts.resize(3);
  std::vector<std::array<double, 3>> seeds;  // (E, λ, μ)
  for (const auto& start : starts)
    seeds.push_back({start.first, kGrid[start.second.first] * d, kGrid[start.second.second] * d});
  // Narrow valleys run through the control polygon whose legs end at the crossing X of the two
  // tangent lines (e.g. the quarter turn's optimum, λ = |X − c_i|, μ small): seeds there too.
  const double denominator = cross(qi, qj);
  if (std::fabs(denominator) > 1e-12) {
    const double lx = cross(cj - ci, qj) / denominator, mx = cross(cj - ci, qi) / denominator;
    if (lx > 0.0 && mx > 0.0) {
      for (const auto& ab : {std::array<double, 2>{0.95, 0.1}, {0.1, 0.95}, {0.67, 0.67}}) {
        const double l = std::max(lower, ab[0] * lx), u = std::max(lower, ab[1] * mx);
        const double e = energy_at(l, u);
        if (std::isfinite(e)) seeds.push_back({e, l, u});
      }
    }
  }
  if (seeds.empty()) return fit;
  double best = std::numeric_limits<double>::infinity(), lambda = 0.0, mu = 0.0;
  for (const auto& seed : seeds) {
    double e = seed[0], l = seed[1], u = seed[2];
    // Compass search: shrink the step when no axis move improves; bounded iterations.
    double step = 0.1 * d;
    // The point the last move came from: its energy is above e, so a move back is skipped
    // (it would be evaluated and rejected).
    double from_l = std::numeric_limits<double>::quiet_NaN(), from_u = from_l;
    for (int iteration = 0; iteration < 400 && step > 1e-4 * d; ++iteration) {
      bool improved = false;
      const double moves[4][2] = {{step, 0}, {-step, 0}, {0, step}, {0, -step}};
      for (const auto& m : moves) {
        const double tl = std::max(lower, l + m[0]), tu = std::max(lower, u + m[1]);
        if (tl == l && tu == u) continue;
        if (tl == from_l && tu == from_u) continue;
        const double te = energy_at(tl, tu, e);  // only "te < e" matters
        if (te < e) {
          from_l = l, from_u = u;
          e = te, l = tl, u = tu, improved = true;
          break;
        }
      }
      if (!improved) step *= 0.5;
    }
    if (e < best) best = e, lambda = l, mu = u;
  }
  fit.lambda = lambda, fit.mu = mu, fit.energy = best, fit.valid = true;
  return fit;
}

size_t BendingFitCache::KeyHash::operator()(const Key& k) const {
  uint64_t h = 0x9e3779b97f4a7c15ull;
  for (uint64_t v : k) {
    h ^= v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    h *= 0xff51afd7ed558ccdull;
  }
  return size_t(h ^ (h >> 33));
}

BendingFitCache::Key BendingFitCache::key(const Vec2& ci, const Vec2& qi, const Vec2& cj, const Vec2& qj) {
  const double values[8] = {ci.x, ci.y, qi.x, qi.y, cj.x, cj.y, qj.x, qj.y};
  Key k;
  std::memcpy(k.data(), values, sizeof values);
  return k;
}

void BendingFitCache::use_segments(int segments) {
  if (segments != segments_) entries_.clear(), segments_ = segments;
}

const BendingFitCache::Entry* BendingFitCache::find(const Key& k) const {
  const auto it = entries_.find(k);
  return it == entries_.end() ? nullptr : &it->second;
}

namespace {

void validate(const std::vector<std::vector<Vec2>>& loops, const CurveNetworkOptions& options) {
  if (loops.empty()) fail(Status::invalid_argument, "curve network: the region has no loop");
  if (!(options.min_angle >= 0.0 && options.min_angle < options.concave_angle && options.concave_angle < 6.2832) ||
      options.polyline_segments < 2 || options.polyline_segments > 4096 || options.threads < 0)
    fail(Status::invalid_argument, "curve network: options out of range (need 0 <= min_angle < concave_angle < 2π, "
                                   "2 <= polyline_segments <= 4096, threads >= 0)");
  for (size_t l = 0; l < loops.size(); ++l) {
    if (loops[l].size() < 3)
      fail(Status::invalid_argument, "curve network: loop " + std::to_string(l) + " has fewer than 3 points");
    for (size_t i = 0; i < loops[l].size(); ++i) {
      const Vec2& p = loops[l][i];
      if (!std::isfinite(p.x) || !std::isfinite(p.y))
        fail(Status::invalid_argument, "curve network: non-finite point in loop " + std::to_string(l));
      if (p == loops[l][(i + 1) % loops[l].size()])
        fail(Status::invalid_argument,
             "curve network: loop " + std::to_string(l) + " repeats point " + std::to_string(i) + " consecutively");
    }
  }
  if (!(signed_area(loops[0]) > 0.0))
    fail(Status::invalid_argument, "curve network: the outer loop (first) is not counter-clockwise");
}

bool polyline_crosses_itself(const std::vector<Vec2>& line) {
  const size_t n = line.size() - 1;
  for (size_t a = 0; a < n; ++a)
    for (size_t b = a + 2; b < n; ++b)
      if (segments_intersect(line[a], line[a + 1], line[b], line[b + 1])) return true;
  return false;
}

// The curve meets a boundary edge anywhere but at its own end points (where it starts on the two
// boundary edges incident to each end point). The polyline's pieces are grouped in runs of
// kRun with a box each, so that an edge is tested only against the pieces of runs whose box it
// meets (a filter: the same answer as testing every piece).
bool polyline_crosses_boundary(const CurveNetwork& net, const std::vector<Vec2>& line, uint32_t p0, uint32_t p1) {
  constexpr size_t kRun = 4;
  const size_t n = line.size() - 1;
  const size_t runs = (n + kRun - 1) / kRun;
  struct Box {
    double lo[2], hi[2];
  };
  Box boxes[4096 / kRun + 1];
  Box all{{line[0].x, line[0].y}, {line[0].x, line[0].y}};
  for (size_t r = 0; r < runs; ++r) {
    Box& b = boxes[r];
    const Vec2& first = line[r * kRun];
    b = {{first.x, first.y}, {first.x, first.y}};
    for (size_t i = r * kRun + 1; i <= std::min(n, (r + 1) * kRun); ++i) {
      b.lo[0] = std::min(b.lo[0], line[i].x), b.hi[0] = std::max(b.hi[0], line[i].x);
      b.lo[1] = std::min(b.lo[1], line[i].y), b.hi[1] = std::max(b.hi[1], line[i].y);
    }
    for (int k = 0; k < 2; ++k) all.lo[k] = std::min(all.lo[k], b.lo[k]), all.hi[k] = std::max(all.hi[k], b.hi[k]);
  }
  auto disjoint = [](const Box& box, const Vec2& a, const Vec2& b) {
    return std::max(a.x, b.x) < box.lo[0] || std::min(a.x, b.x) > box.hi[0] || std::max(a.y, b.y) < box.lo[1] ||
           std::min(a.y, b.y) > box.hi[1];
  };
  for (uint32_t e = 0; e < net.points.size(); ++e) {
    const uint32_t f = net.points[e].next;
    const Vec2 &a = net.points[e].uv, &b = net.points[f].uv;
    if (disjoint(all, a, b)) continue;
    const bool at0 = e == p0 || f == p0, at1 = e == p1 || f == p1;
    for (size_t r = 0; r < runs; ++r) {
      if (disjoint(boxes[r], a, b)) continue;
      for (size_t s = r * kRun; s < std::min(n, (r + 1) * kRun); ++s) {
        if (s == 0 && at0) {
          // The first piece starts on this edge; only a touch away from c_i counts.
          double u = 0, v = 0;
          if (segments_intersect(line[0], line[1], a, b, &u, &v) && u > 1e-9) return true;
          continue;
        }
        if (s + 1 == n && at1) {
          double u = 0, v = 0;
          if (segments_intersect(line[s], line[s + 1], a, b, &u, &v) && u < 1.0 - 1e-9) return true;
          continue;
        }
        if (segments_intersect(line[s], line[s + 1], a, b)) return true;
      }
    }
  }
  return false;
}

}  // namespace

CurveNetwork build_curve_network(const std::vector<std::vector<Vec2>>& loops, const CurveNetworkOptions& options,
                                 const TaskMonitor& monitor, BendingFitCache* cache) {
  validate(loops, options);
  CurveNetwork net;
  net.loop_begin.push_back(0);
  for (size_t l = 0; l < loops.size(); ++l) {
    const uint32_t begin = net.loop_begin.back(), n = static_cast<uint32_t>(loops[l].size());
    for (uint32_t i = 0; i < n; ++i) {
      NetworkPoint p;
      p.uv = loops[l][i];
      p.loop = static_cast<uint32_t>(l);
      p.prev = begin + (i + n - 1) % n;
      p.next = begin + (i + 1) % n;
      net.points.push_back(p);
    }
    net.loop_begin.push_back(begin + n);
  }
  // Internal angles and ports.
  for (uint32_t i = 0; i < net.points.size(); ++i) {
    NetworkPoint& p = net.points[i];
    const Vec2 to_next = hypot_normalized(net.points[p.next].uv - p.uv);
    const Vec2 to_prev = hypot_normalized(net.points[p.prev].uv - p.uv);
    p.angle = ccw_angle(to_next, to_prev);
    p.first_port = static_cast<uint32_t>(net.ports.size());
    if (!(p.angle > options.min_angle)) continue;
    auto rotated = [&](double a) {  // to_next turned counter-clockwise by a: into the region
      return Vec2{std::cos(a) * to_next.x - std::sin(a) * to_next.y,
                  std::sin(a) * to_next.x + std::cos(a) * to_next.y};
    };
    if (p.angle > options.concave_angle) {
      net.ports.push_back({i, rotated(p.angle / 3.0)});
      net.ports.push_back({i, rotated(2.0 * p.angle / 3.0)});
      p.port_count = 2;
    } else {
      net.ports.push_back({i, rotated(p.angle / 2.0)});
      p.port_count = 1;
    }
  }
  const uint32_t num_ports = static_cast<uint32_t>(net.ports.size());
  const int segments = options.polyline_segments;
  if (cache) cache->use_segments(segments);
  // Per first port a, its curves and counters; ports are handed out dynamically (the work per
  // port falls with a) and the results concatenated in port order, so the network does not
  // depend on the thread count.
  struct PortResult {
    std::vector<NetworkCurve> curves;
    size_t considered = 0, crossing = 0, self = 0, invalid = 0, hits = 0;
    std::vector<std::pair<BendingFitCache::Key, BendingFitCache::Entry>> new_fits;  // misses, for the cache
  };
  std::vector<PortResult> results(num_ports);
  std::atomic<uint32_t> next_port{0};
  const size_t workers = std::max<size_t>(
      1, std::min<size_t>(options.threads > 0 ? size_t(options.threads) : std::thread::hardware_concurrency(),
                          num_ports / 8 + 1));
  run_ranges(workers, workers, [&](size_t, size_t, size_t worker) {
    for (uint32_t a = next_port++; a < num_ports; a = next_port++) {
      if (worker == 0) monitor.report("quad curve network", double(a) / std::max(1u, num_ports));
      PortResult& out = results[a];
      const NetworkPort& pa = net.ports[a];
      const NetworkPoint& ca = net.points[pa.point];
      for (uint32_t b = a + 1; b < num_ports; ++b) {
        const NetworkPort& pb = net.ports[b];
        if (pb.point == pa.point || pb.point == ca.next || pb.point == ca.prev) continue;
        const NetworkPoint& cb = net.points[pb.point];
        const Vec2 chord = cb.uv - ca.uv;
        // A chord behind either tangent needs a turn of more than π/2 at that end.
        if (!(dot(chord, pa.tangent) > 0.0) || !(dot(chord, pb.tangent) < 0.0)) continue;
        ++out.considered;
        // The pair's fit, polyline and self-crossing test (from the cache when it has them).
        BendingFitCache::Entry computed;
        const BendingFitCache::Entry* entry = nullptr;
        BendingFitCache::Key key{};
        if (cache) {
          key = BendingFitCache::key(ca.uv, pa.tangent, cb.uv, pb.tangent);
          entry = cache->find(key);
          out.hits += entry != nullptr;
        }
        if (!entry) {
          computed.fit = minimize_bending_energy(ca.uv, pa.tangent, cb.uv, pb.tangent);
          if (computed.fit.valid) {
            const CubicBezier2 bezier =
                connecting_bezier(ca.uv, pa.tangent, cb.uv, pb.tangent, computed.fit.lambda, computed.fit.mu);
            computed.polyline.resize(segments + 1);
            for (int k = 0; k <= segments; ++k) computed.polyline[k] = bezier.eval(double(k) / segments);
            computed.polyline.front() = ca.uv, computed.polyline.back() = cb.uv;
            computed.self_intersecting = polyline_crosses_itself(computed.polyline);
          }
          entry = &computed;
        }
        const BendingFit& fit = entry->fit;
        if (!fit.valid) {
          ++out.invalid;
        } else if (entry->self_intersecting) {
          ++out.self;
        } else if (polyline_crosses_boundary(net, entry->polyline, pa.point, pb.point)) {
          ++out.crossing;
        } else {
          NetworkCurve curve;
          curve.ports = {a, b};
          curve.lambda = fit.lambda, curve.mu = fit.mu, curve.energy = fit.energy;
          curve.bezier = connecting_bezier(ca.uv, pa.tangent, cb.uv, pb.tangent, fit.lambda, fit.mu);
          if (entry == &computed && !cache)
            curve.polyline = std::move(computed.polyline);
          else
            curve.polyline = entry->polyline;
          out.curves.push_back(std::move(curve));
        }
        if (cache && entry == &computed) out.new_fits.emplace_back(key, std::move(computed));
      }
    }
  });
  for (PortResult& r : results) {
    net.pairs_considered += r.considered;
    net.discarded_crossing += r.crossing;
    net.discarded_self_intersection += r.self;
    net.discarded_invalid += r.invalid;
    for (NetworkCurve& c : r.curves) net.curves.push_back(std::move(c));
    if (cache) {
      cache->hits += r.hits;
      cache->misses += r.new_fits.size();
      for (auto& [key, entry] : r.new_fits) cache->insert(key, std::move(entry));
    }
  }
  monitor.report("quad curve network", 1.0);
  return net;
}

CAGEKIT_NAMESPACE_END
