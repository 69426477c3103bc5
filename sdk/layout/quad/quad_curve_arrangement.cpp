// SPDX-License-Identifier: GPL-3.0-or-later
// The arrangement of selected curves (thesis §6.6.1) with incremental face updates; see
// quad_curve_arrangement.h.
#include "layout/quad/quad_curve_arrangement.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <new>
#include <type_traits>
#include <unordered_map>
#include <unordered_set>

#include "core/angles.h"
#include "core/edge_key.h"
#include "core/status.h"
#include "layout/quad/quad_curve_selection.h"

CAGEKIT_NAMESPACE_BEGIN

using namespace plane2;

namespace quad_detail {

namespace {

constexpr uint64_t kCrossingFlag = uint64_t(1) << 63;

// Vertex ids: a boundary point p is p; the k-th crossing (by parameter on a) of curves a < b is
// flagged and packs (a, b, k).
uint64_t crossing_id(uint32_t a, uint32_t b, uint32_t k) {
  return kCrossingFlag | (uint64_t(a) << 39) | (uint64_t(b) << 15) | uint64_t(k);
}

// A strictly increasing function of ccw_angle(from, to) in [0, 4) without atan2 (the hot loop of
// face tracing only compares angles).
double pseudo_ccw_angle(const Vec2& from, const Vec2& to) {
  const double c = cross(from, to), d = dot(from, to);
  const double r = std::fabs(c) + std::fabs(d);
  if (!(r > 0.0)) return 0.0;
  const double p = d / r;  // in [-1, 1]: 1 at angle 0, -1 at π
  return c >= 0.0 ? 1.0 - p : 3.0 + p;
}

struct Fan {
  HalfEdge edge;
  Vec2 direction;
  size_t index = 0;  // curve edges: where edge.from lies in the curve's chain
};

// At most four half-edges leave a vertex: two boundary edges and two ports, or two crossing curves.
// Raw storage: a std::array<Fan, 4> would zero its 4 items on every fan() (Fan's members have
// default initialisers), a measurable share of face tracing.
struct FanList {
  alignas(Fan) unsigned char storage[4 * sizeof(Fan)];
  size_t count = 0;
  void push_back(const Fan& f) { new (storage + count++ * sizeof(Fan)) Fan(f); }
  const Fan* begin() const { return std::launder(reinterpret_cast<const Fan*>(storage)); }
  const Fan* end() const { return begin() + count; }
};
static_assert(std::is_trivially_destructible<Fan>::value, "FanList never destroys its items");

// A map of a few keys (a trial move's overrides: a handful of curves and ports), in insertion
// order: a linear scan beats hashing and a node allocation per key.
template <typename Value>
struct FlatMap {
  std::vector<std::pair<uint32_t, Value>> items;
  const Value* find(uint32_t key) const {
    for (const auto& item : items)
      if (item.first == key) return &item.second;
    return nullptr;
  }
  size_t count(uint32_t key) const { return find(key) != nullptr; }
  Value& operator[](uint32_t key) {
    for (auto& item : items)
      if (item.first == key) return item.second;
    items.emplace_back(key, Value{});
    return items.back().second;
  }
  auto begin() { return items.begin(); }
  auto end() { return items.end(); }
  auto begin() const { return items.begin(); }
  auto end() const { return items.end(); }
};

// The half-edges traced by one evaluate (a few dozen): a flat list beats a node-based hash set.
// It lives in the arrangement's buffer (`items`, emptied here), reused from call to call.
struct SmallHalfEdgeSet {
  explicit SmallHalfEdgeSet(std::vector<HalfEdge>& buffer) : items(buffer) { items.clear(); }
  std::vector<HalfEdge>& items;
  size_t count(const HalfEdge& h) const { return std::find(items.begin(), items.end(), h) != items.end(); }
  void insert(const HalfEdge& h) { items.push_back(h); }  // trace inserts each half-edge once
};

}  // namespace

struct Arrangement::View {
  explicit View(Arrangement& a) : arr(a) {}
  Arrangement& arr;
  FlatMap<char> selected_override;
  FlatMap<int64_t> port_override;
  FlatMap<Chain> chain_override;

  bool is_selected(uint32_t c) const {
    const char* s = selected_override.find(c);
    return s ? *s != 0 : arr.selected_[c] != 0;
  }
  int64_t port_curve(uint32_t p) const {
    const int64_t* c = port_override.find(p);
    return c ? *c : arr.port_curve_[p];
  }
  const Chain& chain(uint32_t c) const {
    const Chain* chain = chain_override.find(c);
    return chain ? *chain : arr.chains_[c];
  }
  static size_t locate(const Chain& chain, uint64_t id) {
    for (size_t i = 0; i < chain.size(); ++i)
      if (chain[i].id == id) return i;
    fail(Status::internal_error, "quad selection: vertex missing from a curve's chain");
  }
  Vec2 position(uint64_t id) const {
    if (!(id & kCrossingFlag)) return arr.net_.points[id].uv;
    const uint32_t a = uint32_t((id >> 39) & 0xFFFFFF);
    const Chain& c = chain(a);
    return c[locate(c, id)].position;
  }
  // Outgoing half-edges at vertex v. `known_curve` / `known_index` (optional): where v lies in
  // that curve's chain, when the caller knows it (face tracing arrives along a curve), which
  // spares one linear search of a chain that may run to hundreds of crossings.
  FanList fan(uint64_t v, int64_t known_curve = -1, size_t known_index = 0) const {
    FanList out;
    const CurveNetwork& net = arr.net_;
    if (!(v & kCrossingFlag)) {
      const NetworkPoint& p = net.points[v];
      out.push_back({{v, -1 - int64_t(v), 1}, net.points[p.next].uv - p.uv});
      out.push_back({{v, -1 - int64_t(p.prev), -1}, net.points[p.prev].uv - p.uv});
      for (uint32_t k = 0; k < p.port_count; ++k) {
        const int64_t c = port_curve(p.first_port + k);
        if (c < 0) continue;
        const Chain& chain = this->chain(uint32_t(c));
        if (chain.size() < 2) continue;
        if (net.curves[c].ports[0] == p.first_port + k)
          out.push_back({{v, c, 1}, chain.front().dir, 0});
        else
          out.push_back({{v, c, -1}, chain.back().dir * -1.0, chain.size() - 1});
      }
      return out;
    }
    const uint32_t curves[2] = {uint32_t((v >> 39) & 0xFFFFFF), uint32_t((v >> 15) & 0xFFFFFF)};
    for (uint32_t c : curves) {
      const Chain& chain = this->chain(c);
      const size_t i = int64_t(c) == known_curve ? known_index : locate(chain, v);
      if (i + 1 < chain.size()) out.push_back({{v, c, 1}, chain[i].dir, i});
      if (i > 0) out.push_back({{v, c, -1}, chain[i].dir * -1.0, i});
    }
    return out;
  }
  // Target of h and the direction of its twin there.
  std::pair<uint64_t, Vec2> target(const HalfEdge& h) const {
    const CurveNetwork& net = arr.net_;
    if (h.carrier < 0) {
      const uint32_t e = uint32_t(-1 - h.carrier), f = net.points[e].next;
      if (h.dir > 0) return {f, net.points[e].uv - net.points[f].uv};
      return {e, net.points[f].uv - net.points[e].uv};
    }
    const Chain& chain = this->chain(uint32_t(h.carrier));
    const size_t i = locate(chain, h.from);
    const size_t j = h.dir > 0 ? i + 1 : i - 1;
    return {chain[j].id, chain[j].dir * (h.dir > 0 ? -1.0 : 1.0)};
  }
};

void Arrangement::reset(const std::vector<uint32_t>& curves) {
  for (auto& c : chains_) c.clear();
  std::fill(selected_.begin(), selected_.end(), 0);
  std::fill(port_curve_.begin(), port_curve_.end(), -1);
  faces_.clear();
  face_of_.clear();
  delta_cache_.clear();
  energy_ = 0.0;
  for (uint32_t c : curves) {
    selected_[c] = 1;
    for (uint32_t p : net_.curves[c].ports) port_curve_[p] = c;
  }
  list_.assign(curves.begin(), curves.end());
  std::sort(list_.begin(), list_.end());
  for (uint32_t c : list_) chains_[c] = build_chain(c, selected_);
  View view(*this);
  std::unordered_set<HalfEdge, HalfEdgeHash> visited;
  auto trace_from = [&](const HalfEdge& h, size_t index) {
    if (visited.count(h)) return;
    Face f = trace(view, h, index, true, visited);
    add_face(std::move(f));
  };
  for (uint32_t p = 0; p < net_.points.size(); ++p) trace_from({p, -1 - int64_t(p), 1}, 0);
  for (uint32_t c : list_)
    for (size_t i = 0; i + 1 < chains_[c].size(); ++i) {
      trace_from({chains_[c][i].id, int64_t(c), 1}, i);
      trace_from({chains_[c][i + 1].id, int64_t(c), -1}, i + 1);
    }
}

double Arrangement::evaluate(const std::vector<uint32_t>& removed, const std::vector<uint32_t>& added, bool commit,
                             double bound) {
  // A trial's ΔE depends only on the faces it removes: every face it traces reuses half-edges
  // of those faces or runs through them. So a cached ΔE stays exact while they are all alive.
  const bool cacheable = !commit && removed.size() <= 2 && added.size() <= 2;
  MoveKey key{};
  if (cacheable) {
    key = move_key(removed, added);
    auto it = delta_cache_.find(key);
    if (it != delta_cache_.end() &&
        std::all_of(it->second.old_faces.begin(), it->second.old_faces.end(),
                    [&](uint32_t f) { return faces_[f].alive; }))
      return it->second.delta;
  }
  View view(*this);
  for (uint32_t c : removed) view.selected_override[c] = 0;
  for (uint32_t c : added) view.selected_override[c] = 1;
  for (uint32_t c : removed)
    for (uint32_t p : net_.curves[c].ports) view.port_override[p] = -1;
  for (uint32_t c : added)
    for (uint32_t p : net_.curves[c].ports) view.port_override[p] = c;
  // Curves whose chain changes: R ∪ A and the selected curves crossing them. (The lists below
  // are the arrangement's buffers, reused from one evaluate to the next.)
  std::vector<uint32_t>& touched = scratch_.touched;
  touched.assign(removed.begin(), removed.end());
  touched.insert(touched.end(), added.begin(), added.end());
  std::vector<uint32_t>& changed = scratch_.changed;
  changed.assign(touched.begin(), touched.end());
  for (uint32_t c : list_)
    if (!view.selected_override.count(c))
      for (uint32_t t : touched)
        if (crosses(c, t)) {
          changed.push_back(c);
          break;
        }
  // Dirty vertices. Removed / added curves: all their old / new chain vertices (end points
  // included: their fans change). A selected curve they cross: the crossings that disappear or
  // appear and their chain neighbours (its pieces there merge or split). Every other vertex
  // keeps its fan and its pieces, so a face through none of them is unchanged.
  std::vector<uint64_t>&dirty_old = scratch_.dirty_old, &dirty = scratch_.dirty;
  dirty_old.clear(), dirty.clear();
  auto mark = [](std::vector<uint64_t>& side, uint64_t id) { side.push_back(id); };
  auto contains = [](const Chain& chain, uint64_t id) {
    return std::any_of(chain.begin(), chain.end(), [&](const ChainVertex& v) { return v.id == id; });
  };
  std::vector<uint64_t>&old_ids = scratch_.old_ids, &new_ids = scratch_.new_ids;
  auto sorted_ids = [](const Chain& chain, std::vector<uint64_t>& ids) {
    ids.clear();
    for (const ChainVertex& v : chain) ids.push_back(v.id);
    std::sort(ids.begin(), ids.end());
  };
  for (uint32_t c : changed) {
    const Chain& old_chain = chains_[c];
    if (!view.is_selected(c)) {
      for (const ChainVertex& v : old_chain) mark(dirty_old, v.id);
      view.chain_override[c] = Chain();
      continue;
    }
    view.chain_override[c] = build_chain(c, view);
    const Chain& new_chain = view.chain_override[c];
    if (!selected_[c]) {
      for (const ChainVertex& v : new_chain) mark(dirty, v.id);
      continue;
    }
    // Membership in the other state's chain by binary search (chains run to hundreds of crossings).
    sorted_ids(old_chain, old_ids), sorted_ids(new_chain, new_ids);
    auto in_new = [&](uint64_t id) { return std::binary_search(new_ids.begin(), new_ids.end(), id); };
    auto in_old = [&](uint64_t id) { return std::binary_search(old_ids.begin(), old_ids.end(), id); };
    for (size_t i = 0; i < old_chain.size(); ++i)
      if (!in_new(old_chain[i].id)) {
        mark(dirty_old, old_chain[i].id);
        if (i > 0) mark(dirty, old_chain[i - 1].id);
        if (i + 1 < old_chain.size()) mark(dirty, old_chain[i + 1].id);
      }
    for (size_t i = 0; i < new_chain.size(); ++i)
      if (!in_old(new_chain[i].id)) {
        mark(dirty, new_chain[i].id);
        if (i > 0) mark(dirty_old, new_chain[i - 1].id);
        if (i + 1 < new_chain.size()) mark(dirty_old, new_chain[i + 1].id);
      }
  }
  // One dirty set for both sides (a face through a dirty vertex that exists in both states is
  // removed and traced again, identical or not), each side keeping the vertices it has.
  dirty.insert(dirty.end(), dirty_old.begin(), dirty_old.end());
  dirty_old = dirty;
  auto exists_old = [&](uint64_t id) {
    if (!(id & kCrossingFlag)) return true;
    return contains(chains_[uint32_t((id >> 39) & 0xFFFFFF)], id);
  };
  auto exists_new = [&](uint64_t id) {
    if (!(id & kCrossingFlag)) return true;
    return contains(view.chain(uint32_t((id >> 39) & 0xFFFFFF)), id);
  };
  dirty_old.erase(std::remove_if(dirty_old.begin(), dirty_old.end(), [&](uint64_t id) { return !exists_old(id); }),
                  dirty_old.end());
  dirty.erase(std::remove_if(dirty.begin(), dirty.end(), [&](uint64_t id) { return !exists_new(id); }), dirty.end());
  for (auto* list : {&dirty_old, &dirty}) {
    std::sort(list->begin(), list->end());
    list->erase(std::unique(list->begin(), list->end()), list->end());
  }
  // Old faces through a dirty vertex.
  View old_view(*this);
  std::vector<uint32_t> old_faces;  // kept in the delta cache
  for (uint64_t v : dirty_old)
    for (const Fan& f : old_view.fan(v)) {
      auto it = face_of_.find(f.edge);
      if (it != face_of_.end()) old_faces.push_back(it->second);
    }
  std::sort(old_faces.begin(), old_faces.end());
  old_faces.erase(std::unique(old_faces.begin(), old_faces.end()), old_faces.end());
  double delta = 0.0;
  for (uint32_t f : old_faces) delta -= faces_[f].energy;
  if (!commit && delta >= bound) return delta;  // the new faces can only add (see below)
  SmallHalfEdgeSet visited(scratch_.visited);
  std::vector<Face> new_faces;  // only to commit: a trial needs the energies, not the cycles
  for (uint64_t v : dirty)
    for (const Fan& f : view.fan(v)) {
      if (f.edge.carrier < 0 && f.edge.dir < 0) continue;  // outside the region
      if (visited.count(f.edge)) continue;
      Face face = trace(view, f.edge, f.index, commit, visited);
      delta += face.energy;
      if (commit) new_faces.push_back(std::move(face));
      // The faces still to trace add energies >= 0 (and rounding is monotone): the trial is
      // known to change E by at least `bound`. Not cached (the value is partial).
      else if (delta >= bound) return delta;
    }
  if (cacheable) delta_cache_[key] = {delta, old_faces};
  if (commit) {
    for (uint32_t f : old_faces) {
      for (const HalfEdge& h : faces_[f].cycle) face_of_.erase(h);
      faces_[f].alive = false;
      energy_ -= faces_[f].energy;
    }
    for (auto& [c, s] : view.selected_override) selected_[c] = s;
    for (auto& [p, c] : view.port_override) port_curve_[p] = c;
    for (auto& [c, chain] : view.chain_override) chains_[c] = std::move(chain);
    list_.clear();
    for (uint32_t c = 0; c < selected_.size(); ++c)
      if (selected_[c]) list_.push_back(c);
    for (Face& f : new_faces) add_face(std::move(f));
    compact_faces();
  }
  return delta;
}

double Arrangement::smallest_crossing_angle(uint32_t c) {
  double smallest = kPi / 2;
  for (uint32_t o : list_) {
    if (o == c) continue;
    const uint32_t a = std::min(c, o), b = std::max(c, o);
    for (const Crossing& x : crossings(a, b)) {
      double angle =
          std::acos(std::clamp(std::fabs(dot(hypot_normalized(x.dir_a), hypot_normalized(x.dir_b))), 0.0, 1.0));
      smallest = std::min(smallest, angle);
    }
  }
  return smallest;
}

void Arrangement::export_mesh(QuadSelection& out) {
  std::unordered_map<uint64_t, uint32_t> index;
  View view(*this);
  for (const Face& f : faces_) {
    if (!f.alive) continue;
    std::vector<uint64_t> ids;
    std::vector<Vec2> polygon;
    for (const HalfEdge& h : f.cycle) ids.push_back(h.from), polygon.push_back(view.position(h.from));
    const ElementRating rating = rate_element(polygon, weights_);
    if (rating.invalid) ++out.invalid_faces;
    for (const auto& piece : rating.pieces) {
      std::vector<uint32_t> face;
      for (uint32_t k : piece) {
        auto [it, inserted] = index.emplace(ids[k], uint32_t(out.vertices.size()));
        if (inserted) {
          out.vertices.push_back(polygon[k]);
          out.vertex_point.push_back((ids[k] & kCrossingFlag) ? -1 : int64_t(ids[k]));
        }
        face.push_back(it->second);
      }
      const size_t n = face.size();
      (n == 4 ? out.quads : n == 3 ? out.triangles : n == 5 ? out.pentagons : out.larger) += 1;
      out.faces.push_back(std::move(face));
    }
  }
}

const std::vector<Crossing>& Arrangement::crossings(uint32_t a, uint32_t b) {
  const uint64_t key = directed_edge_key(a, b);
  auto it = crossing_cache_.find(key);
  if (it != crossing_cache_.end()) return it->second;
  std::vector<Crossing> found;
  const NetworkCurve &ca = net_.curves[a], &cb = net_.curves[b];
  const std::vector<Vec2>&pa = ca.polyline, &pb = cb.polyline;
  const size_t na = pa.size() - 1, nb = pb.size() - 1;
  const uint32_t ea[2] = {net_.ports[ca.ports[0]].point, net_.ports[ca.ports[1]].point};
  const uint32_t eb[2] = {net_.ports[cb.ports[0]].point, net_.ports[cb.ports[1]].point};
  // Pieces are tested in runs of kRun whose boxes meet (a filter: the same crossings in the
  // same order as testing every pair of pieces).
  const CurveBoxes &ba = boxes(a), &bb = boxes(b);
  if (ba.all.meets(bb.all)) {
    for (size_t ra = 0; ra < ba.runs.size(); ++ra) {
      if (!ba.runs[ra].meets(bb.all)) continue;
      for (size_t s = ra * kRun; s < std::min(na, (ra + 1) * kRun); ++s)
        for (size_t rb = 0; rb < bb.runs.size(); ++rb) {
          if (!ba.runs[ra].meets(bb.runs[rb])) continue;
          for (size_t u = rb * kRun; u < std::min(nb, (rb + 1) * kRun); ++u) {
            // Pieces at a shared end point touch there by construction.
            const bool shared = (s == 0 || s + 1 == na) && (u == 0 || u + 1 == nb) &&
                                ea[s == 0 ? 0 : 1] == eb[u == 0 ? 0 : 1];
            if (shared) continue;
            double sigma = 0, tau = 0;
            if (!segments_intersect(pa[s], pa[s + 1], pb[u], pb[u + 1], &sigma, &tau)) continue;
            Crossing x;
            x.ta = (double(s) + sigma) / double(na);
            x.tb = (double(u) + tau) / double(nb);
            x.position = pa[s] + (pa[s + 1] - pa[s]) * sigma;
            x.dir_a = pa[s + 1] - pa[s];
            x.dir_b = pb[u + 1] - pb[u];
            if (x.ta <= 0.0 || x.ta >= 1.0 || x.tb <= 0.0 || x.tb >= 1.0) continue;  // at an end point
            found.push_back(x);
          }
        }
    }
  }
  std::sort(found.begin(), found.end(), [](const Crossing& x, const Crossing& y) { return x.ta < y.ta; });
  // A crossing at a polyline vertex is reported by two neighbouring pieces.
  std::vector<Crossing> unique;
  for (const Crossing& x : found)
    if (unique.empty() || std::fabs(x.ta - unique.back().ta) > 1e-9 || std::fabs(x.tb - unique.back().tb) > 1e-9)
      unique.push_back(x);
  return crossing_cache_.emplace(key, std::move(unique)).first->second;
}

bool Arrangement::crosses(uint32_t a, uint32_t b) {
  const uint32_t lo = std::min(a, b), hi = std::max(a, b);
  const size_t n = net_.curves.size();
  if (n > kDenseCrossCurves) return !crossings(lo, hi).empty();
  if (crosses_.empty()) crosses_.assign(n * n, 0);
  uint8_t& known = crosses_[lo * n + hi];
  if (known == 0) known = crossings(lo, hi).empty() ? 1 : 2;
  return known == 2;
}

template <typename Selection>
Chain Arrangement::build_chain(uint32_t c, const Selection& selection) {
  const NetworkCurve& curve = net_.curves[c];
  const std::vector<Vec2>& line = curve.polyline;
  Chain chain;
  chain.push_back({0.0, net_.ports[curve.ports[0]].point, line.front(), line[1] - line[0]});
  for_each_chain_candidate(selection, [&](uint32_t o) {
    // The dense crossing table answers most pairs (no crossing) without a hash lookup.
    if (o == c || !crosses(c, o)) return;
    const uint32_t a = std::min(c, o), b = std::max(c, o);
    const std::vector<Crossing>& xs = crossings(a, b);
    for (uint32_t k = 0; k < xs.size(); ++k) {
      const Crossing& x = xs[k];
      chain.push_back({c == a ? x.ta : x.tb, crossing_id(a, b, k), x.position, c == a ? x.dir_a : x.dir_b});
    }
  });
  const size_t n = line.size() - 1;
  chain.push_back({1.0, net_.ports[curve.ports[1]].point, line.back(), line[n] - line[n - 1]});
  std::sort(chain.begin() + 1, chain.end() - 1,
            [](const ChainVertex& x, const ChainVertex& y) { return x.t < y.t || (x.t == y.t && x.id < y.id); });
  return chain;
}

template <typename F>
void Arrangement::for_each_chain_candidate(const std::vector<char>& selected, F&& f) const {
  for (uint32_t c : list_)
    if (selected[c]) f(c);
}

template <typename F>
void Arrangement::for_each_chain_candidate(const View& view, F&& f) const {
  for (uint32_t c : list_)
    if (view.is_selected(c)) f(c);
  for (auto& [c, s] : view.selected_override)
    if (s && !selected_[c]) f(c);
}

template <typename Visited>
Face Arrangement::trace(const View& view, const HalfEdge& start, size_t start_index, bool keep_cycle,
                        Visited& visited) {
  Face face;
  std::vector<uint64_t>& ids = trace_ids_;
  std::vector<Vec2>& polygon = trace_polygon_;
  ids.clear(), polygon.clear();
  if (keep_cycle) face.cycle.reserve(8);
  // The walk carries where each half-edge's start lies in its curve's chain (the target is the
  // next chain vertex, and the next half-edge starts there), and the start's position, so that
  // chains are searched only for the other curve through a crossing: the same faces, positions
  // and choices as looking every vertex up (View::target, View::position).
  HalfEdge h = start;
  size_t index = start.carrier >= 0 && start_index == kUnknownIndex
                     ? View::locate(view.chain(uint32_t(start.carrier)), start.from)
                     : start_index;
  Vec2 position = view.position(start.from);
  const size_t limit = 4 * (net_.points.size() + 64 * (list_.size() + 8) * (list_.size() + 8));
  for (size_t step = 0;; ++step) {
    if (step > limit) fail(Status::internal_error, "quad selection: a face cycle does not close");
    if (keep_cycle) face.cycle.push_back(h);
    visited.insert(h);
    ids.push_back(h.from);
    polygon.push_back(position);
    uint64_t w = 0;
    Vec2 twin_direction;
    size_t w_index = 0;
    if (h.carrier < 0) {
      const std::pair<uint64_t, Vec2> t = view.target(h);
      w = t.first, twin_direction = t.second;
      position = net_.points[w].uv;
    } else {
      const Chain& chain = view.chain(uint32_t(h.carrier));
      w_index = h.dir > 0 ? index + 1 : index - 1;
      const ChainVertex& x = chain[w_index];
      w = x.id, twin_direction = x.dir * (h.dir > 0 ? -1.0 : 1.0);
      position = (w & kCrossingFlag) ? x.position : net_.points[w].uv;
    }
    const HalfEdge twin{w, h.carrier, -h.dir};
    double best = std::numeric_limits<double>::infinity();
    HalfEdge next = twin;
    size_t next_index = w_index;
    for (const Fan& f : view.fan(w, h.carrier, w_index)) {
      if (f.edge == twin) continue;
      const double angle = pseudo_ccw_angle(f.direction, twin_direction);  // clockwise from the twin
      if (angle < best) best = angle, next = f.edge, next_index = f.index;
    }
    h = next;
    index = next_index;
    if (h == start) break;
  }
  face.energy = rate(ids, polygon);
  face.alive = true;
  return face;
}

double Arrangement::rate(const std::vector<uint64_t>& ids, const std::vector<Vec2>& polygon) {
  // The cycle from its smallest vertex id, so that every start of the same face finds it.
  std::vector<uint64_t>& key = cycle_key_;
  const auto smallest = std::min_element(ids.begin(), ids.end());
  key.assign(smallest, ids.end());
  key.insert(key.end(), ids.begin(), smallest);
  auto it = energy_cache_.find(key);
  if (it != energy_cache_.end()) return it->second;
  const double e = element_energy(polygon, weights_);
  energy_cache_.emplace(key, e);
  return e;
}

void Arrangement::add_face(Face f) {
  const uint32_t id = uint32_t(faces_.size());
  for (const HalfEdge& h : f.cycle) face_of_[h] = id;
  energy_ += f.energy;
  faces_.push_back(std::move(f));
}

void Arrangement::compact_faces() {
  if (faces_.size() < 4096) return;
  delta_cache_.clear();  // face ids change
  std::vector<Face> alive;
  for (Face& f : faces_)
    if (f.alive) alive.push_back(std::move(f));
  faces_.clear();
  face_of_.clear();
  energy_ = 0.0;
  for (Face& f : alive) add_face(std::move(f));
}

const Arrangement::CurveBoxes& Arrangement::boxes(uint32_t c) {
  if (boxes_.empty()) {
    boxes_.resize(net_.curves.size());
    for (size_t k = 0; k < net_.curves.size(); ++k) {
      const std::vector<Vec2>& line = net_.curves[k].polyline;
      const size_t n = line.size() - 1;
      CurveBoxes& b = boxes_[k];
      b.all = {{line[0].x, line[0].y}, {line[0].x, line[0].y}};
      for (size_t r = 0; r * kRun < n; ++r) {
        Box box{{line[r * kRun].x, line[r * kRun].y}, {line[r * kRun].x, line[r * kRun].y}};
        for (size_t i = r * kRun + 1; i <= std::min(n, (r + 1) * kRun); ++i) box.add(line[i]);
        b.runs.push_back(box);
        b.all.add(Vec2{box.lo[0], box.lo[1]});
        b.all.add(Vec2{box.hi[0], box.hi[1]});
      }
    }
  }
  return boxes_[c];
}

Arrangement::MoveKey Arrangement::move_key(const std::vector<uint32_t>& removed, const std::vector<uint32_t>& added) {
  const uint32_t kNoCurve = 0xffffffffu;
  MoveKey k{kNoCurve, kNoCurve, kNoCurve, kNoCurve};
  for (size_t i = 0; i < removed.size(); ++i) k[i] = removed[i];
  for (size_t i = 0; i < added.size(); ++i) k[2 + i] = added[i];
  if (k[0] > k[1]) std::swap(k[0], k[1]);
  if (k[2] > k[3]) std::swap(k[2], k[3]);
  return k;
}

}  // namespace quad_detail

CAGEKIT_NAMESPACE_END
