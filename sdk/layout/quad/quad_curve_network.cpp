// SPDX-License-Identifier: GPL-3.0-or-later
// Candidate curve network (thesis §6.5); see quad_curve_network.h.
#include "layout/quad/quad_curve_network.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <string>
#include <thread>

#include "core/parallel_for.h"
#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

using namespace plane2;

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
