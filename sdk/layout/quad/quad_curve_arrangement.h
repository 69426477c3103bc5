// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The arrangement of a configuration of the curve selection (thesis §6.6.1, spec thesis-ch4-6.md
// §2.7), private to layout/quad (its user is the optimiser, quad_curve_selection.cpp): the
// selected curves of a CurveNetwork, their crossings and the faces of the planar map they make
// with the boundary loops, traced in the region's parameter plane and rated by the element
// energy (quad_element_energy.h). The meshing rules are those of quad_curve_selection.h.
//
// Incremental evaluation (the bottleneck the thesis names in §6.10): a move (remove R, add A)
// rebuilds the crossing chains only of the curves in R ∪ A and of the selected curves they cross;
// the dirty vertices are the chain vertices of R ∪ A and, on a crossed curve, the crossings that
// appear or disappear and their chain neighbours; only the faces through a dirty vertex are
// removed and traced again. Curve-curve crossings are computed once per pair, face energies are
// cached by their vertex cycle, and a trial's ΔE is reused while the faces it removes are alive.
//
// Thread-safety: one Arrangement per thread. Errors: internal_error if a face cycle does not
// close (an inconsistent planar map).
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include "core/vec2.h"
#include "layout/quad/quad_curve_network.h"
#include "layout/quad/quad_element_energy.h"

CAGEKIT_NAMESPACE_BEGIN

struct QuadSelection;

namespace quad_detail {

struct Crossing {
  double ta = 0.0, tb = 0.0;  // parameters on curves a < b
  Vec2 position{};
  Vec2 dir_a{}, dir_b{};  // forward polyline directions at the crossing
};

struct ChainVertex {
  double t = 0.0;
  uint64_t id = 0;
  Vec2 position{};
  Vec2 dir{};  // forward direction of the curve's polyline at this vertex
};
using Chain = std::vector<ChainVertex>;

// carrier >= 0: curve; carrier < 0: boundary edge from point -1-carrier to its next point.
struct HalfEdge {
  uint64_t from = 0;
  int64_t carrier = 0;
  int dir = 1;
  bool operator==(const HalfEdge& o) const { return from == o.from && carrier == o.carrier && dir == o.dir; }
};
struct HalfEdgeHash {
  size_t operator()(const HalfEdge& h) const {
    uint64_t x = h.from * 0x9E3779B97F4A7C15ull ^ (uint64_t(h.carrier) + 0x632BE59BD9B4E019ull) * 0xC2B2AE3D27D4EB4Full;
    x ^= uint64_t(h.dir + 1) << 1;
    return size_t(x ^ (x >> 29));
  }
};
struct CycleHash {
  size_t operator()(const std::vector<uint64_t>& v) const {
    uint64_t x = 0xcbf29ce484222325ull;
    for (uint64_t id : v) x = (x ^ id) * 0x100000001b3ull;
    return size_t(x);
  }
};

struct Face {
  std::vector<HalfEdge> cycle;
  double energy = 0.0;
  bool alive = false;
};

class Arrangement {
 public:
  Arrangement(const CurveNetwork& net, const ElementWeights& weights) : net_(net), weights_(weights) {
    chains_.resize(net.curves.size());
    selected_.assign(net.curves.size(), 0);
    port_curve_.assign(net.ports.size(), -1);
  }

  // Full rebuild for `curves` (a matching).
  void reset(const std::vector<uint32_t>& curves);

  double energy() const { return energy_; }
  const std::vector<uint32_t>& selected() const { return list_; }
  bool is_selected(uint32_t c) const { return selected_[c] != 0; }
  int64_t port_curve(uint32_t port) const { return port_curve_[port]; }

  // Energy change of removing `removed` and adding `added` (ports must be free after removal);
  // applied when commit is true.
  // `bound` (a trial only; face energies must be >= 0): once the change is known to be at least
  // `bound` the remaining new faces are not traced and a value >= bound is returned (a caller
  // that compares "< bound" gets the same answer).
  double evaluate(const std::vector<uint32_t>& removed, const std::vector<uint32_t>& added, bool commit,
                  double bound = std::numeric_limits<double>::infinity());

  // Smallest crossing angle (in [0, π/2]) of curve c with the other selected curves.
  double smallest_crossing_angle(uint32_t c);

  void export_mesh(QuadSelection& out);

 private:
  struct View;  // the arrangement with a trial move's overrides (quad_curve_arrangement.cpp)

  const std::vector<Crossing>& crossings(uint32_t a, uint32_t b);
  // Whether curves a and b cross: !crossings(min, max).empty(), remembered per pair in a dense table
  // when the network has at most kDenseCrossCurves curves (the question evaluate() asks of every
  // selected curve for every trial move).
  bool crosses(uint32_t a, uint32_t b);
  template <typename Selection>
  Chain build_chain(uint32_t c, const Selection& selection);
  // Calls f(o) for every curve o selected in `selected` / the view (the curves a chain may cross).
  template <typename F>
  void for_each_chain_candidate(const std::vector<char>& selected, F&& f) const;
  template <typename F>
  void for_each_chain_candidate(const View& view, F&& f) const;
  template <typename Visited>
  // `start_index`: where start.from lies in the chain of start's curve (kUnknownIndex: looked up;
  // ignored for a boundary edge).
  // `keep_cycle` false: the face's cycle is not stored (a trial move needs only the energy).
  Face trace(const View& view, const HalfEdge& start, size_t start_index, bool keep_cycle, Visited& visited);
  static constexpr size_t kUnknownIndex = ~size_t(0);
  double rate(const std::vector<uint64_t>& ids, const std::vector<Vec2>& polygon);
  void add_face(Face f);
  void compact_faces();

  const CurveNetwork& net_;
  ElementWeights weights_;
  std::vector<Chain> chains_;
  std::vector<char> selected_;
  std::vector<uint32_t> list_;
  std::vector<int64_t> port_curve_;
  std::vector<Face> faces_;
  std::unordered_map<HalfEdge, uint32_t, HalfEdgeHash> face_of_;
  std::unordered_map<uint64_t, std::vector<Crossing>> crossing_cache_;
  static constexpr size_t kDenseCrossCurves = 2048;
  std::vector<uint8_t> crosses_;  // curves x curves: 0 not known yet, 1 no crossing, 2 crossing
  // Bounding boxes of every curve's polyline and of its runs of kRun pieces (built on first use).
  static constexpr size_t kRun = 4;
  struct Box {
    double lo[2], hi[2];
    bool meets(const Box& o) const {
      return lo[0] <= o.hi[0] && o.lo[0] <= hi[0] && lo[1] <= o.hi[1] && o.lo[1] <= hi[1];
    }
    void add(const Vec2& p) {
      lo[0] = std::min(lo[0], p.x), hi[0] = std::max(hi[0], p.x);
      lo[1] = std::min(lo[1], p.y), hi[1] = std::max(hi[1], p.y);
    }
  };
  struct CurveBoxes {
    Box all;
    std::vector<Box> runs;
  };
  std::vector<CurveBoxes> boxes_;
  const CurveBoxes& boxes(uint32_t c);
  std::unordered_map<std::vector<uint64_t>, double, CycleHash> energy_cache_;
  // evaluate()'s lists, kept between calls (no allocation per trial move once they have grown).
  struct Scratch {
    std::vector<uint32_t> touched, changed;
    std::vector<uint64_t> dirty_old, dirty, old_ids, new_ids;
    std::vector<HalfEdge> visited;
  } scratch_;
  // trace()'s buffers, kept between calls (an Arrangement is used by one thread at a time).
  std::vector<uint64_t> trace_ids_, cycle_key_;
  std::vector<Vec2> trace_polygon_;
  // (removed, added) curve ids, each pair sorted and padded with kNoCurve.
  using MoveKey = std::array<uint32_t, 4>;
  struct MoveKeyHash {
    size_t operator()(const MoveKey& k) const {
      uint64_t x = 0x84222325cbf29ce4ull;
      for (uint32_t v : k) x = (x ^ v) * 0x100000001b3ull;
      return size_t(x ^ (x >> 32));
    }
  };
  static MoveKey move_key(const std::vector<uint32_t>& removed, const std::vector<uint32_t>& added);
  struct CachedDelta {
    double delta = 0.0;
    std::vector<uint32_t> old_faces;
  };
  std::unordered_map<MoveKey, CachedDelta, MoveKeyHash> delta_cache_;
  double energy_ = 0.0;
};

}  // namespace quad_detail

CAGEKIT_NAMESPACE_END
