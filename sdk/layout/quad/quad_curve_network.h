// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The candidate curve network of one region of the two-step quad-dominant remeshing (thesis
// §6.5, spec thesis-ch4-6.md §2.6): minimum-bending-energy cubic Béziers (6.2)-(6.3) between
// pairs of eligible constrained points in the region's LSCM domain Ω_i.
//
// Input: the region's loops of constrained points in Ω_i (RemeshConstraints::loop_samples_uv),
// outer loop first and counter-clockwise, holes clockwise (the region on the left of every
// loop). A point c_i with internal angle α_i > ψ is eligible; its tangent q_i is the bisector of
// α_i pointing into the region (the normal of the boundary curve C̄ in the limit of dense
// samples; at an anchor C̄ has no normal). A point with α_i > `concave_angle` gets two tangents
// that trisect α_i ("ports"; the selection counts them as two points).
//
// Per pair of ports (p, q) on different, non-neighbouring points whose chord lies in front of both
// tangents, the minimum-bending-energy cubic (6.2)-(6.3) (bending_fit.h). Afterwards a curve whose
// polyline (`polyline_segments` pieces, equal parameter steps) crosses or touches a boundary loop
// away from its own end points, or crosses itself, is discarded.
//
// Thread-safety: pure functions (build_curve_network runs `threads` workers inside). Errors: invalid_argument for no loop, a loop of fewer than three
// points, a non-finite coordinate, two consecutive equal points, an outer loop that is not
// counter-clockwise or bad options; cancelled from the monitor.
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/task_monitor.h"
#include "core/vec2.h"
#include "layout/quad/bending_fit.h"
#include "layout/quad/plane_geometry.h"

CAGEKIT_NAMESPACE_BEGIN

struct CurveNetworkOptions {
  double min_angle = 2.0943951023931957;      // ψ = 2π/3: eligibility needs α_i > ψ
  double concave_angle = 3.6651914291880923;  // 7π/6: above it, two tangents trisect α_i
  int polyline_segments = 32;                 // polyline of every curve (crossing tests, meshing)
  int threads = 1;  // workers for the pairs (0 = hardware concurrency); the result does not depend on it
};

struct NetworkPoint {
  Vec2 uv{};
  uint32_t loop = 0;
  uint32_t prev = 0, next = 0;  // neighbours on the loop (region on the left going to `next`)
  double angle = 0.0;           // internal angle α_i on the region's side, in (0, 2π)
  uint32_t first_port = 0, port_count = 0;  // ports[first_port, first_port + port_count)
};

struct NetworkPort {
  uint32_t point = 0;
  Vec2 tangent{};  // unit, into the region
};

struct NetworkCurve {
  std::array<uint32_t, 2> ports{};  // ports[0] < ports[1]
  double lambda = 0.0, mu = 0.0, energy = 0.0;
  CubicBezier2 bezier;
  std::vector<Vec2> polyline;  // polyline_segments + 1 points, from ports[0] to ports[1]
};

struct CurveNetwork {
  std::vector<NetworkPoint> points;  // the loops concatenated, in input order
  std::vector<uint32_t> loop_begin;  // loop l: points [loop_begin[l], loop_begin[l + 1])
  std::vector<NetworkPort> ports;
  std::vector<NetworkCurve> curves;
  size_t pairs_considered = 0;       // port pairs for which (6.3) was minimised
  size_t discarded_crossing = 0;     // dropped: crossing a boundary loop (curve leaves the region)
  size_t discarded_self_intersection = 0;
  size_t discarded_invalid = 0;      // no trial point with uncrossed legs
  size_t num_loops() const { return loop_begin.size() - 1; }
};

// Memo of the per-pair work of build_curve_network, keyed by the exact bits of (c_i, q_i, c_j,
// q_j): the minimisation of (6.3), the curve's polyline and whether it crosses itself (pure
// functions of the key for a given polyline_segments), so a hit gives what a new computation
// would. The sample-count refinement of the quad remesher rebuilds a region's network after
// moving the samples of one arc; every pair of ports whose points and tangents did not move is
// then a hit (the minimisation is ~90% of a network build); only the test against the region's
// boundary (which moved) is repeated. Not thread-safe: one cache per region / concurrent caller.
class BendingFitCache {
 public:
  using Key = std::array<uint64_t, 8>;
  struct KeyHash {
    size_t operator()(const Key& k) const;
  };
  struct Entry {
    BendingFit fit;
    bool self_intersecting = false;
    std::vector<Vec2> polyline;  // empty when !fit.valid
  };
  static Key key(const Vec2& ci, const Vec2& qi, const Vec2& cj, const Vec2& qj);
  // The entries are for one polyline_segments value; another value empties the cache first.
  void use_segments(int segments);
  const Entry* find(const Key& k) const;
  void insert(const Key& k, Entry entry) { entries_.emplace(k, std::move(entry)); }
  size_t size() const { return entries_.size(); }
  size_t hits = 0, misses = 0;

 private:
  int segments_ = 0;
  std::unordered_map<Key, Entry, KeyHash> entries_;
};

// `cache` (optional) is read by the workers and extended after them, so the result is the same
// with or without it and for any thread count.
CurveNetwork build_curve_network(const std::vector<std::vector<Vec2>>& loops, const CurveNetworkOptions& options = {},
                                 const TaskMonitor& monitor = {}, BendingFitCache* cache = nullptr);

CAGEKIT_NAMESPACE_END
