// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/quad/remesh_constraints.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <unordered_map>

#include "core/angles.h"
#include "core/edge_map.h"
#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {
// A loop of arcs is a polygon of the curve network when it has at least 3 constrained points
// (the sum of its arcs' segment counts) and, with two arcs, a sample inside each.
bool arcs_form_polygon(const RemeshConstraints& constraints, const std::vector<uint32_t>& arcs) {
  uint64_t points = 0;
  for (const uint32_t a : arcs) {
    const uint64_t segments = constraints.arcs[a].samples.t.size() - 1;
    if (arcs.size() == 2 && segments < 2) return false;
    points += segments;
  }
  return points >= 3;
}

// Raises the segment counts of a loop's arcs, in turn, until the loop is such a polygon.
void raise_to_polygon(const std::vector<uint32_t>& arcs, std::vector<uint32_t>& segments) {
  if (arcs.size() == 2)
    for (const uint32_t a : arcs) segments[a] = std::max<uint32_t>(segments[a], 2);
  uint64_t points = 0;
  for (const uint32_t a : arcs) points += segments[a];
  for (size_t k = 0; points < 3 && !arcs.empty(); ++k, ++points) ++segments[arcs[k % arcs.size()]];
}
}  // namespace

double spacing_from_bbox_fraction(const PolygonMesh& mesh, double fraction) {
  if (!(fraction > 0.0) || !std::isfinite(fraction))
    fail(Status::invalid_argument, "remesh constraints: the spacing fraction must be positive and finite");
  return fraction * mesh.bounding_box().diagonal();
}

RemeshConstraints compute_remesh_constraints(const PolygonMesh& triangles, const std::vector<uint32_t>& face_region,
                                             size_t num_regions, const ConstraintOptions& options,
                                             const TaskMonitor& monitor, std::vector<RegionParameterization>* domains) {
  if (domains && domains->size() != num_regions)
    fail(Status::invalid_argument, "remesh constraints: " + std::to_string(domains->size()) + " domains for " +
                                       std::to_string(num_regions) + " regions");
  if (!(options.spacing > 0.0) || !std::isfinite(options.spacing))
    fail(Status::invalid_argument, "remesh constraints: the sample spacing must be positive and finite");
  RemeshConstraints out;
  out.boundaries = compute_region_boundaries(triangles, face_region, num_regions);
  // Arcs are fitted in id order; a split appends its second half, which is fitted in turn.
  for (uint32_t a = 0; a < out.boundaries.arcs.size(); ++a) {
    for (;;) {
      const std::vector<uint32_t>& vertices = out.boundaries.arcs[a].vertices;
      std::vector<Vec3> points;
      for (uint32_t v : vertices) points.push_back(triangles.positions[v]);
      ArcConstraint c;
      c.s = arc_length_parameters(points);
      c.cubic = fit_arc_cubic(points, c.s);
      for (size_t i = 0; i < points.size(); ++i)
        c.fit_max_deviation = std::max(c.fit_max_deviation, distance(points[i], c.cubic.evaluate(c.s[i])));
      c.fit_rms = arc_fit_rms(c.cubic, points, c.s);
      if (options.max_fit_rms > 0.0 && points.size() >= 3 && c.fit_rms > options.max_fit_rms * options.spacing) {
        size_t middle = 1;
        for (size_t i = 1; i + 1 < points.size(); ++i)
          if (std::abs(c.s[i] - 0.5 * c.s.back()) < std::abs(c.s[middle] - 0.5 * c.s.back())) middle = i;
        split_arc(out.boundaries, a, middle);
        continue;
      }
      out.arcs.push_back(std::move(c));
      break;
    }
  }
  monitor.report("remesh constraints", 0.1);
  std::vector<std::vector<uint32_t>> faces(num_regions);
  for (uint32_t f = 0; f < face_region.size(); ++f) faces[face_region[f]].push_back(f);
  out.domains.reserve(num_regions);
  out.region_arcs.resize(num_regions);
  for (uint32_t r = 0; r < num_regions; ++r) {
    if (faces[r].empty()) fail(Status::invalid_argument, "remesh constraints: region " + std::to_string(r) + " is empty");
    if (domains && !(*domains)[r].faces.empty())
      out.domains.push_back(std::move((*domains)[r]));
    else
      out.domains.push_back(parameterize_region_lscm(triangles, faces[r]));
    const RegionParameterization& domain = out.domains.back();
    // The outer loop is the one with the largest signed area in Ω_i (the longest in 3D need
    // not be, e.g. on an annulus around a torus' tube); it goes first.
    std::vector<RegionLoop>& loops = out.boundaries.region_loops[r];
    size_t outer = 0;
    double outer_area = -HUGE_VAL;
    for (size_t l = 0; l < loops.size(); ++l) {
      const double area = signed_domain_area(domain, out.boundaries.loop_vertices(loops[l]));
      if (area > outer_area) outer_area = area, outer = l;
    }
    std::rotate(loops.begin(), loops.begin() + long(outer), loops.begin() + long(outer) + 1);
    for (const RegionLoop& loop : out.boundaries.region_loops[r])
      for (uint32_t arc : loop.arcs) {
        const ArcConstraint& constraint = out.arcs[arc];
        std::vector<Vec3> uv;
        for (uint32_t v : out.boundaries.arcs[arc].vertices) {
          const auto& p = domain.uv_of(v);
          uv.push_back(Vec3{p.x, p.y, 0.0});
        }
        RegionArcDomain entry;
        entry.arc = arc;
        entry.planar = fit_arc_cubic(uv, constraint.s);
        out.region_arcs[r].push_back(std::move(entry));
      }
    monitor.report("remesh constraints", 0.1 + 0.85 * double(r + 1) / double(num_regions));
  }

  // Sample counts: ⌈len/δ⌉ segments per arc, or the joint allocation.
  std::vector<double> ideal(out.arcs.size());
  for (size_t a = 0; a < out.arcs.size(); ++a) ideal[a] = arc_cubic_length(out.arcs[a].cubic) / options.spacing;
  std::vector<uint32_t> segments(out.arcs.size());
  if (options.balance_samples) {
    std::vector<SegmentAllocationRegion> problem(num_regions);
    for (uint32_t r = 0; r < num_regions; ++r) {
      const std::vector<RegionLoop>& loops = out.boundaries.region_loops[r];
      size_t entry = 0;
      for (const RegionLoop& loop : loops) {
        const size_t n = loop.arcs.size();
        // Direction in Ω_i leaving the loop's k-th anchor along arc k (walk direction), and
        // arriving at anchor k + 1 along it: chords to the point δ along the arc's parameter.
        std::vector<Vec2> leave(n), arrive(n);
        for (size_t k = 0; k < n; ++k) {
          const ArcCubic& planar = out.region_arcs[r][entry + k].planar;
          const double S = planar.parameter_length, h = std::min(S, options.spacing);
          const Vec3 p0 = planar.evaluate(0.0), p1 = planar.evaluate(h), q0 = planar.evaluate(S - h),
                     q1 = planar.evaluate(S);
          Vec2 start{p1.x - p0.x, p1.y - p0.y}, end{q1.x - q0.x, q1.y - q0.y};
          if (loop.reversed[k]) {
            leave[k] = {-end.x, -end.y};
            arrive[k] = {-start.x, -start.y};
          } else {
            leave[k] = start;
            arrive[k] = end;
          }
        }
        std::vector<size_t> corners;  // k: the anchor where arc k starts is a corner
        for (size_t k = 0; k < n; ++k) {
          const Vec2& in = arrive[(k + n - 1) % n];
          const Vec2& outd = leave[k];
          const double cross = in.x * outd.y - in.y * outd.x, dot = in.x * outd.x + in.y * outd.y;
          if (cross == 0.0 && dot == 0.0) continue;
          const double internal = kPi - std::atan2(cross, dot);  // region on the left
          if (internal < options.corner_angle) corners.push_back(k);
        }
        const size_t first = corners.empty() ? 0 : corners.front();
        std::vector<std::vector<uint32_t>> sides;
        for (size_t i = 0; i < n; ++i) {
          const size_t k = (first + i) % n;
          if (sides.empty() || std::find(corners.begin(), corners.end(), k) != corners.end()) sides.emplace_back();
          sides.back().push_back(loop.arcs[k]);
        }
        for (auto& side : sides) problem[r].sides.push_back(std::move(side));
        entry += n;
      }
      problem[r].quad_like = loops.size() == 1 && problem[r].sides.size() == 4;
    }
    segments = allocate_arc_segments(ideal, problem);
  } else {
    for (size_t a = 0; a < ideal.size(); ++a) segments[a] = uint32_t(std::max(1L, long(std::ceil(ideal[a] - 1e-9))));
  }
  // A loop is a polygon of the curve network: it needs at least 3 constrained points (the sum of
  // its arcs' segment counts), and a loop of two arcs a sample inside each (else its 3 points are
  // the two anchors and one sample, collinear where the arcs are nearly straight: a sliver
  // region with no area); short loops get their arcs' counts raised in turn.
  for (const std::vector<RegionLoop>& loops : out.boundaries.region_loops)
    for (const RegionLoop& loop : loops) raise_to_polygon(loop.arcs, segments);
  // A hole of the input (a loop of mesh-border arcs, one region on their left) keeps at least 3
  // samples too, and a sample inside each arc where it has two: else the glued faces on either
  // side share the chord between two samples and the hole is closed (lion.off: a 4-edge hole
  // split between two regions' 1-segment arcs).
  out.arc_border_loop.assign(out.arcs.size(), kMeshBorder);
  {
    detail::UnionFind anchors(triangles.num_vertices());  // the border arcs' anchors, chained
    for (const RegionArc& ra : out.boundaries.arcs)
      if (ra.right_region == kMeshBorder) anchors.unite(ra.vertices.front(), ra.vertices.back());
    std::unordered_map<uint32_t, uint32_t> loop_of_root;
    for (uint32_t a = 0; a < out.boundaries.arcs.size(); ++a) {  // in arc order: deterministic
      const RegionArc& ra = out.boundaries.arcs[a];
      if (ra.right_region != kMeshBorder) continue;
      const auto [it, added] = loop_of_root.emplace(anchors.find(ra.vertices.front()), uint32_t(out.border_loops.size()));
      if (added) out.border_loops.emplace_back();
      out.border_loops[it->second].push_back(a);
      out.arc_border_loop[a] = it->second;
    }
    for (const std::vector<uint32_t>& arcs : out.border_loops) raise_to_polygon(arcs, segments);
  }
  for (uint32_t a = 0; a < out.arcs.size(); ++a) {
    out.arcs[a].base_segments = uint32_t(std::max(1L, long(std::ceil(ideal[a] - 1e-9))));
    resample_arc(out, a, segments[a]);
  }
  monitor.report("remesh constraints", 1.0);
  return out;
}

uint64_t fewest_loop_points(const RemeshConstraints& constraints, uint32_t region) {
  uint64_t fewest = UINT64_MAX;
  for (const RegionLoop& loop : constraints.boundaries.region_loops.at(region)) {
    uint64_t points = 0;
    for (uint32_t a : loop.arcs) points += constraints.arcs[a].samples.t.size() - 1;
    fewest = std::min(fewest, points);
  }
  return fewest;
}

bool loops_are_polygons(const RemeshConstraints& constraints, uint32_t region) {
  for (const RegionLoop& loop : constraints.boundaries.region_loops.at(region))
    if (!arcs_form_polygon(constraints, loop.arcs)) return false;
  return true;
}

bool border_loop_is_polygon(const RemeshConstraints& constraints, uint32_t arc) {
  const uint32_t loop = constraints.arc_border_loop.at(arc);
  return loop == kMeshBorder || arcs_form_polygon(constraints, constraints.border_loops[loop]);
}

void resample_arc(RemeshConstraints& constraints, uint32_t arc, uint32_t segments) {
  if (arc >= constraints.arcs.size()) fail(Status::invalid_argument, "resample_arc: arc id out of range");
  if (segments == 0) fail(Status::invalid_argument, "resample_arc: at least one segment");
  ArcConstraint& c = constraints.arcs[arc];
  c.samples = sample_arc_cubic_count(c.cubic, long(segments) - 1);
  const RegionArc& ra = constraints.boundaries.arcs[arc];
  for (uint32_t r : {ra.left_region, ra.right_region}) {
    if (r >= constraints.region_arcs.size()) continue;  // mesh border
    for (RegionArcDomain& entry : constraints.region_arcs[r]) {
      if (entry.arc != arc) continue;
      entry.samples_uv.clear();
      for (const Vec3& p : evaluate_at(entry.planar, c.samples.t)) entry.samples_uv.push_back({p.x, p.y});
      const auto& a = constraints.domains[r].uv_of(ra.vertices.front());
      const auto& b = constraints.domains[r].uv_of(ra.vertices.back());
      entry.samples_uv.front() = a;
      entry.samples_uv.back() = b;
    }
  }
}

namespace {

uint32_t base_segments(double ideal) { return uint32_t(std::max(1L, long(std::ceil(ideal - 1e-9)))); }

struct AllocationState {
  const std::vector<double>& ideal;
  const std::vector<SegmentAllocationRegion>& regions;
  const SegmentAllocationOptions& options;
  std::vector<std::vector<uint32_t>> arc_regions;  // per arc, the regions having it (with repeats)

  double region_cost(uint32_t r, const std::vector<uint32_t>& n) const {
    const SegmentAllocationRegion& region = regions[r];
    long total = 0;
    std::vector<long> side(region.sides.size(), 0);
    for (size_t s = 0; s < region.sides.size(); ++s)
      for (uint32_t a : region.sides[s]) side[s] += long(n[a]);
    for (long x : side) total += x;
    double cost = (total % 2 != 0) ? options.odd_cost : 0.0;
    if (region.quad_like && side.size() == 4)
      cost += options.mismatch_cost * double(std::labs(side[0] - side[2]) + std::labs(side[1] - side[3]));
    return cost;
  }
  double arc_cost(uint32_t a, uint32_t n) const {
    return options.deviation_cost * std::abs(double(n) - double(base_segments(ideal[a])));
  }
  // Cost change when arc a goes from n[a] to value.
  double delta(uint32_t a, uint32_t value, std::vector<uint32_t>& n) const {
    const uint32_t old = n[a];
    double before = arc_cost(a, old), after = arc_cost(a, value);
    std::vector<uint32_t> seen;
    for (uint32_t r : arc_regions[a]) {
      if (std::find(seen.begin(), seen.end(), r) != seen.end()) continue;
      seen.push_back(r);
      before += region_cost(r, n);
    }
    n[a] = value;
    for (uint32_t r : seen) after += region_cost(r, n);
    n[a] = old;
    return after - before;
  }
};

void check_allocation_input(const std::vector<double>& ideal, const std::vector<SegmentAllocationRegion>& regions) {
  for (double x : ideal)
    if (!std::isfinite(x) || x < 0.0) fail(Status::invalid_argument, "segment allocation: ideal counts must be finite and >= 0");
  for (const SegmentAllocationRegion& region : regions)
    for (const auto& side : region.sides)
      for (uint32_t a : side)
        if (a >= ideal.size()) fail(Status::invalid_argument, "segment allocation: arc id out of range");
}

}  // namespace

double segment_allocation_cost(const std::vector<uint32_t>& segments, const std::vector<double>& ideal,
                               const std::vector<SegmentAllocationRegion>& regions,
                               const SegmentAllocationOptions& options) {
  check_allocation_input(ideal, regions);
  if (segments.size() != ideal.size()) fail(Status::invalid_argument, "segment allocation: wrong number of counts");
  AllocationState state{ideal, regions, options, {}};
  double cost = 0.0;
  for (uint32_t a = 0; a < ideal.size(); ++a) cost += state.arc_cost(a, segments[a]);
  for (uint32_t r = 0; r < regions.size(); ++r) cost += state.region_cost(r, segments);
  return cost;
}

std::vector<uint32_t> allocate_arc_segments(const std::vector<double>& ideal,
                                            const std::vector<SegmentAllocationRegion>& regions,
                                            const SegmentAllocationOptions& options) {
  check_allocation_input(ideal, regions);
  if (options.max_change < 0) fail(Status::invalid_argument, "segment allocation: max_change must be >= 0");
  AllocationState state{ideal, regions, options, std::vector<std::vector<uint32_t>>(ideal.size())};
  for (uint32_t r = 0; r < regions.size(); ++r)
    for (const auto& side : regions[r].sides)
      for (uint32_t a : side) state.arc_regions[a].push_back(r);
  const size_t m = ideal.size();
  std::vector<uint32_t> base(m), lo(m), hi(m);
  for (size_t a = 0; a < m; ++a) {
    base[a] = base_segments(ideal[a]);
    lo[a] = uint32_t(std::max(1L, long(base[a]) - long(options.max_change)));
    hi[a] = base[a] + uint32_t(options.max_change);
  }
  std::vector<uint32_t> n = base;
  // Greedy descent: the best single-arc change while one lowers the cost.
  for (;;) {
    double best = -1e-12;
    uint32_t best_arc = 0, best_value = 0;
    for (uint32_t a = 0; a < m; ++a)
      for (uint32_t v = lo[a]; v <= hi[a]; ++v) {
        if (v == n[a]) continue;
        const double d = state.delta(a, v, n);
        if (d < best) best = d, best_arc = a, best_value = v;
      }
    if (best >= -1e-12) break;
    n[best_arc] = best_value;
  }
  // Annealing over single-arc moves (deterministic), keeping the best configuration seen.
  std::vector<uint32_t> best_n = n;
  double cost = segment_allocation_cost(n, ideal, regions, options), best_cost = cost;
  if (m > 0 && options.anneal_steps > 0) {
    std::mt19937 rng(12345u);
    const double t0 = 0.5 * std::max(options.odd_cost, options.mismatch_cost), t1 = 0.01;
    for (int step = 0; step < options.anneal_steps; ++step) {
      const double temperature = t0 * std::pow(t1 / t0, double(step) / double(options.anneal_steps));
      const uint32_t a = uint32_t(rng() % m);
      const uint32_t span = hi[a] - lo[a] + 1;
      uint32_t v = lo[a] + uint32_t(rng() % span);
      if (v == n[a]) continue;
      const double d = state.delta(a, v, n);
      const double u = double(rng() % 1000000u) / 1e6;
      if (d <= 0.0 || u < std::exp(-d / temperature)) {
        n[a] = v;
        cost += d;
        if (cost < best_cost - 1e-12) best_cost = cost, best_n = n;
      }
    }
  }
  return best_n;
}

namespace {

// Appends an arc's entries (first to last, or reversed), leaving out its last point (the next
// arc's first) so that each anchor appears once in a closed loop.
template <class T>
void append_arc(std::vector<T>& out, const std::vector<T>& arc, bool reversed) {
  if (reversed)
    out.insert(out.end(), arc.rbegin(), arc.rend() - 1);
  else
    out.insert(out.end(), arc.begin(), arc.end() - 1);
}

}  // namespace

std::vector<Vec3> RemeshConstraints::loop_samples(uint32_t region, size_t loop) const {
  const RegionLoop& l = boundaries.region_loops.at(region).at(loop);
  std::vector<Vec3> out;
  for (size_t k = 0; k < l.arcs.size(); ++k) append_arc(out, arcs[l.arcs[k]].samples.position, l.reversed[k] != 0);
  return out;
}

std::vector<Vec2> RemeshConstraints::loop_samples_uv(uint32_t region, size_t loop) const {
  const std::vector<RegionLoop>& loops = boundaries.region_loops.at(region);
  size_t first = 0;
  for (size_t i = 0; i < loop; ++i) first += loops[i].arcs.size();
  const RegionLoop& l = loops.at(loop);
  std::vector<Vec2> out;
  for (size_t k = 0; k < l.arcs.size(); ++k) append_arc(out, region_arcs[region][first + k].samples_uv, l.reversed[k] != 0);
  return out;
}

CAGEKIT_NAMESPACE_END
