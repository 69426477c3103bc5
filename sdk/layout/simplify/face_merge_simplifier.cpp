// SPDX-License-Identifier: GPL-3.0-or-later
// Face-merge simplification (thesis §3.3, reconstructed main loop of spec §3.7). See README.md
// for the decisions the thesis leaves open (normalisation, epsilon, initial planes, outer loop).
#include "core/angles.h"
#include "core/edge_key.h"
#include "core/memory_budget.h"
#include "layout/simplify/face_merge_simplifier.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <new>
#include <string>
#include <unordered_set>

#include "core/mesh_validation.h"
#include "core/status.h"
#include "layout/simplify/merge_priority.h"
#include "layout/simplify/operation_record.h"
#include "layout/simplify/polygonal_face_set.h"

CAGEKIT_NAMESPACE_BEGIN
using namespace detail;

namespace {

struct Candidate {
  double key;
  uint32_t a, b;    // merge: face ids a < b; removal: vertex a of face b
  uint32_t va, vb;  // versions of the faces (removal: vb = version of face b)
  uint8_t kind;     // 0 merge, 1 boundary vertex removal
};
// Min-heap order: priority, then merges before removals, then ids (deterministic ties).
inline bool after(const Candidate& x, const Candidate& y) {
  if (x.key != y.key) return x.key > y.key;
  if (x.kind != y.kind) return x.kind > y.kind;
  if (x.a != y.a) return x.a > y.a;
  return x.b > y.b;
}

// Growable array of trivially copyable T on 64-byte aligned storage (cache-line placement of
// heap nodes and entries is part of the layout, see CandidateHeap).
template <class T>
class AlignedArray {
 public:
  AlignedArray() = default;
  AlignedArray(const AlignedArray&) = delete;
  AlignedArray& operator=(const AlignedArray&) = delete;
  ~AlignedArray() { release(); }
  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  T& operator[](size_t i) { return data_[i]; }
  const T& operator[](size_t i) const { return data_[i]; }
  T& back() { return data_[size_ - 1]; }
  void clear() { size_ = 0; }
  void pop_back() { --size_; }
  void push_back(const T& x) {
    if (size_ == cap_) grow();
    data_[size_++] = x;
  }
  const T* data() const { return data_; }

 private:
  void grow() {
    const size_t cap = cap_ ? 2 * cap_ : 1024;
    T* d = static_cast<T*>(::operator new(cap * sizeof(T), std::align_val_t(64)));
    advise_huge_pages(d, cap * sizeof(T));
    if (size_) std::memcpy(static_cast<void*>(d), data_, size_ * sizeof(T));
    release();
    data_ = d;
    cap_ = cap;
  }
  void release() {
    if (data_) ::operator delete(static_cast<void*>(data_), std::align_val_t(64));
    data_ = nullptr;
  }
  T* data_ = nullptr;
  size_t size_ = 0, cap_ = 0;
};

// Indexed 4-ary min-heap with at most one entry per operation: per face pair (merges) and per
// vertex (boundary removals). A push for an operation that already has an entry replaces it in
// place (decrease/increase-key), so the heap never holds more than the number of operations.
// This pops the same sequence of non-stale candidates as a lazy heap with one entry per push:
// a push replaces an entry only after one of its faces changed (the old entry is stale), except
// for the duplicate a step produces when both faces of a pair changed, where the lazy heap
// would pop the smaller of the two keys first, and the second would repeat its result.
//
// Layout: 16-byte nodes (key, entry id) on 64-byte aligned storage with the root at index 3, so
// the four children of a node (4i+1..4i+4, stored at 4i+4..4i+7) are exactly one cache line;
// one 32-byte entry per id (candidate, step of its last push, kind) so that a push touches one
// line per entry instead of one per side array; the heap positions stay a dense side array
// (every sift move writes one).
class CandidateHeap {
 public:
  void init(size_t num_vertices) {
    vertex_handle_.assign(num_vertices, kNone);
    assign_huge(pairs_, 1024, Slot{kEmptyKey, 0});
    pair_count_ = 0;
    heap_.clear();
    for (size_t k = 0; k < kBase; ++k) heap_.push_back(Node{0, 0, 0});
  }
  bool empty() const { return heap_.size() == kBase; }
  size_t size() const { return heap_.size() - kBase; }
  Candidate top() const { return candidate(ent_[heap_[kBase].id]); }
  // Hint: a push for the face pair (a, b) follows soon.
  void prefetch_pair(uint32_t a, uint32_t b) const {
    __builtin_prefetch(&pairs_[hash(directed_edge_key(a, b)) & (pairs_.size() - 1)]);
  }
  // Hint, after prefetch_pair: prefetches the pair's entry if it has one.
  void prefetch_entry(uint32_t a, uint32_t b) const {
    const uint64_t k = directed_edge_key(a, b);
    const size_t mask = pairs_.size() - 1;
    for (size_t i = hash(k) & mask; pairs_[i].key != kEmptyKey; i = (i + 1) & mask)
      if (pairs_[i].key == k) {
        __builtin_prefetch(&ent_[pairs_[i].handle]);
        __builtin_prefetch(&pos_[pairs_[i].handle]);
        return;
      }
  }
  // Same step (a pair pushed from both of its changed faces): keep the smaller key.
  void push(const Candidate& c, uint32_t step) {
    uint32_t* handle;
    if (c.kind == 0) {
      handle = &pair_handle(directed_edge_key(c.a, c.b));
    } else {
      handle = &vertex_handle_[c.a];
    }
    if (*handle == kNone) {
      const uint32_t id = new_id();
      *handle = id;
      Entry& e = ent_[id];
      set(e, c, step);
      pos_[id] = static_cast<uint32_t>(heap_.size());
      heap_.push_back({c.key, id});
      sift_up(heap_.size() - 1);
      return;
    }
    const uint32_t id = *handle;
    Entry& e = ent_[id];
    const uint32_t i = pos_[id];
    if (e.step == step && c.kind == 0 && e.va == c.va && e.vb == c.vb && !(c.key < e.key)) return;
    const bool up = after(candidate(e), c);
    set(e, c, step);
    heap_[i].key = c.key;
    if (up)
      sift_up(i);
    else
      sift_down(i);
  }
  void pop() {
    const uint32_t id = heap_[kBase].id;
    release(id);
    const Node last = heap_.back();
    heap_.pop_back();
    if (heap_.size() > kBase) {
      heap_[kBase] = last;
      pos_[last.id] = kBase;
      sift_down(kBase);
    }
  }
  // Removes the entry of the face pair (a, b), a < b, if there is one. Only for entries that
  // are stale (one of the faces is gone): they would be popped and skipped, so removing them
  // early leaves the sequence of valid pops unchanged, and costs a sift near the leaves
  // instead of a full-depth sift_down from the root.
  void erase_pair_entry(uint32_t a, uint32_t b) {
    const uint64_t k = directed_edge_key(a, b);
    const size_t mask = pairs_.size() - 1;
    size_t s = hash(k) & mask;
    while (pairs_[s].key != k) {
      if (pairs_[s].key == kEmptyKey) return;
      s = (s + 1) & mask;
    }
    const uint32_t id = pairs_[s].handle;
    const size_t i = pos_[id];
    release(id);
    const Node last = heap_.back();
    heap_.pop_back();
    if (i < heap_.size()) {
      heap_[i] = last;
      pos_[last.id] = static_cast<uint32_t>(i);
      sift_up(i);
      sift_down(pos_[last.id]);
    }
  }

 private:
  static constexpr uint32_t kNone = 0xffffffffu;
  static constexpr uint64_t kEmptyKey = ~uint64_t(0);
  static constexpr size_t kBase = 3;  // heap index i is stored at i + kBase
  struct Node {  // 16 bytes: the four children of a node share one cache line
    double key;
    uint32_t id, pad = 0;
  };
  struct Entry {  // 32 bytes
    double key;
    uint32_t a, b, va, vb;
    uint32_t step;  // step of the last push
    uint32_t kind;
  };
  static Candidate candidate(const Entry& e) {
    return Candidate{e.key, e.a, e.b, e.va, e.vb, static_cast<uint8_t>(e.kind)};
  }
  static void set(Entry& e, const Candidate& c, uint32_t step) { e = Entry{c.key, c.a, c.b, c.va, c.vb, step, c.kind}; }
  static bool entry_after(const Entry& x, const Entry& y) {
    if (x.key != y.key) return x.key > y.key;
    if (x.kind != y.kind) return x.kind > y.kind;
    if (x.a != y.a) return x.a > y.a;
    return x.b > y.b;
  }
  bool node_after(const Node& x, const Node& y) const {
    if (x.key != y.key) return x.key > y.key;
    return entry_after(ent_[x.id], ent_[y.id]);
  }
  struct Slot {
    uint64_t key;
    uint32_t handle;
  };
  static size_t hash(uint64_t k) { return static_cast<size_t>((k * 0x9E3779B97F4A7C15ull) >> 20); }

  uint32_t new_id() {
    if (!free_.empty()) {
      const uint32_t id = free_.back();
      free_.pop_back();
      return id;
    }
    ent_.push_back(Entry());
    pos_.push_back(0);
    return static_cast<uint32_t>(ent_.size() - 1);
  }
  void release(uint32_t id) {
    const Entry& e = ent_[id];
    if (e.kind != 0)
      vertex_handle_[e.a] = kNone;
    else
      erase_pair(directed_edge_key(e.a, e.b));
    free_.push_back(id);
  }
  // Open addressing, linear probing, backward-shift deletion.
  uint32_t& pair_handle(uint64_t k) {
    if (2 * (pair_count_ + 1) > pairs_.size()) grow();
    const size_t mask = pairs_.size() - 1;
    size_t i = hash(k) & mask;
    while (pairs_[i].key != kEmptyKey) {
      if (pairs_[i].key == k) return pairs_[i].handle;
      i = (i + 1) & mask;
    }
    pairs_[i] = {k, kNone};
    ++pair_count_;
    return pairs_[i].handle;
  }
  void erase_pair(uint64_t k) {
    const size_t mask = pairs_.size() - 1;
    size_t i = hash(k) & mask;
    while (pairs_[i].key != k) i = (i + 1) & mask;
    size_t j = i;
    for (;;) {
      j = (j + 1) & mask;
      if (pairs_[j].key == kEmptyKey) break;
      const size_t home = hash(pairs_[j].key) & mask;
      // Move j to i if its home is not cyclically in (i, j].
      if ((j > i && (home <= i || home > j)) || (j < i && (home <= i && home > j))) {
        pairs_[i] = pairs_[j];
        i = j;
      }
    }
    pairs_[i].key = kEmptyKey;
    --pair_count_;
  }
  void grow() {
    std::vector<Slot> old;
    old.swap(pairs_);
    assign_huge(pairs_, old.size() * 2, Slot{kEmptyKey, 0});
    const size_t mask = pairs_.size() - 1;
    for (const Slot& s : old) {
      if (s.key == kEmptyKey) continue;
      size_t i = hash(s.key) & mask;
      while (pairs_[i].key != kEmptyKey) i = (i + 1) & mask;
      pairs_[i] = s;
    }
  }
  void sift_up(size_t i) {
    const Node n = heap_[i];
    while (i > kBase) {
      const size_t p = (i - kBase - 1) / 4 + kBase;
      if (!node_after(heap_[p], n)) break;
      heap_[i] = heap_[p];
      pos_[heap_[i].id] = static_cast<uint32_t>(i);
      i = p;
    }
    heap_[i] = n;
    pos_[n.id] = static_cast<uint32_t>(i);
  }
  void sift_down(size_t i) {
    const Node n = heap_[i];
    const size_t size = heap_.size();
    for (;;) {
      const size_t first = 4 * (i - kBase) + 1 + kBase;
      if (first >= size) break;
      size_t best = first;
      const size_t end = std::min(first + 4, size);
      for (size_t k = first + 1; k < end; ++k)
        if (node_after(heap_[best], heap_[k])) best = k;
      if (!node_after(n, heap_[best])) break;
      heap_[i] = heap_[best];
      pos_[heap_[i].id] = static_cast<uint32_t>(i);
      i = best;
    }
    heap_[i] = n;
    pos_[n.id] = static_cast<uint32_t>(i);
  }

  AlignedArray<Node> heap_;
  AlignedArray<Entry> ent_;  // id -> entry
  AlignedArray<uint32_t> pos_;  // id -> storage index in heap_ (dense: written on every sift move)
  std::vector<uint32_t> free_;
  std::vector<uint32_t> vertex_handle_;
  std::vector<Slot> pairs_;
  size_t pair_count_ = 0;
};

struct LevelStats {
  uint64_t faces, vertices;
  double error;
};

}  // namespace

namespace detail {
struct HierarchyData {
  PolygonMesh input;
  Vec3 center;
  double unit = 1, inv_unit = 1;  // unit length of the error terms (input resolution)
  HierarchyRecords hier;
  std::vector<LevelStats> stats;
  std::vector<double> error_prefix_max;
  std::vector<uint32_t> input_alive;  // input faces (all faces of the validated input)
  SimplifyStats work;

  Vec3 normalised(const Vec3& p) const { return (p - center) * inv_unit; }
};
}  // namespace detail

struct SimplificationHierarchy::Impl : detail::HierarchyData {};

namespace {

class Builder {
 public:
  Builder(HierarchyData& impl, const SimplifyOptions& options, const TaskMonitor& monitor)
      : impl_(impl), mesh_(impl.input), options_(options), monitor_(monitor) {}

  void run();

 private:
  HierarchyData& impl_;
  const PolygonMesh& mesh_;
  SimplifyOptions options_;
  const TaskMonitor& monitor_;
  // A cancel point every 2^14 faces of a set-up pass over all faces (each pass takes about a
  // second on a million faces).
  void poll(size_t i) const {
    if ((i & 0x3fff) == 0) monitor_.report("simplify", 0.0);
  }
  PolygonalFaceSet fs_;
  std::vector<Vec3> pos_;  // normalised positions
  CandidateHeap heap_;
  uint32_t step_ = 0;  // finish_step calls so far (duplicate pushes of one step keep the minimum)
  // Scratch.
  std::vector<uint8_t> dirty_flag_;
  std::vector<uint32_t> dirty_;
  std::vector<uint32_t> slot_stamp_, slot_index_;
  uint32_t slot_clock_ = 0;
  PolygonLoops scratch_poly_;
  struct Neighbour {
    uint32_t g;
    uint64_t shared;
    double angle_sum;
    Vec3 n;
    bool ok;
    double key;
  };
  std::vector<Neighbour> nbs_;
  std::vector<uint32_t> twin_, twin_slot_;
  std::vector<uint32_t> scratch_flat_;
  std::vector<std::array<uint32_t, 3>> scratch_tris_;
  bool loops_validated_ = false;  // all faces changed from here on have validated loops
  std::vector<std::vector<uint32_t>> scratch_loops_;
  std::vector<std::vector<uint32_t>> merge_loops_;
  std::vector<uint32_t> scratch_verts_;
  // face -> version while alive, kDeadVersion once merged away (compact copy of WorkFace's
  // version/alive for the staleness test of every popped candidate).
  static constexpr uint32_t kDeadVersion = 0xffffffffu;
  std::vector<uint32_t> ver_;
  // Borders no merge crosses: options_.locked_edges, then the chords that replace two of them.
  std::unordered_set<uint64_t> locked_;

  bool locked(uint32_t a, uint32_t b) const { return !locked_.empty() && locked_.count(edge_key(a, b)) != 0; }
  bool shares_locked_edge(uint32_t f, uint32_t g) const;
  PlaneFrame frame_of(const Vec3& centroid_input, const Vec3& normal) const {
    return PlaneFrame::from_normal(impl_.normalised(centroid_input), normal);
  }
  void project(const std::vector<std::vector<uint32_t>>& loops, const PlaneFrame& frame, PolygonLoops& out) const;
  static void classify_outer(PolygonLoops& poly, std::vector<std::vector<uint32_t>>& loops);
  void rebuild_cdt(uint32_t f);
  void update_cdt_for_removal(uint32_t f, uint32_t v);
  void push(const Candidate& c) { heap_.push(c, step_); }
  void push_candidates(uint32_t f);
  void push_boundary_candidates(uint32_t f);
  bool evaluate_merge(uint32_t f, uint32_t g, double& e) const;
  double merge_key(const WorkFace& F, const WorkFace& G, double sf, double sg, const Vec3& n, uint64_t shared,
                   double angle_sum) const;
  bool removal_valid(uint32_t f, uint32_t v);
  bool try_remove_interior(uint32_t v);
  void mark_dirty(uint32_t f) {
    if (!dirty_flag_[f]) {
      dirty_flag_[f] = 1;
      dirty_.push_back(f);
    }
  }
  // with_cancel_points: poll() every 2^14 faces (the set-up pass over all faces; a merge's few
  // dirty faces need none).
  void decimate_dirty(bool with_cancel_points = false);
  void finish_step(double error, uint32_t merged_from, uint32_t merged_into);
  bool closes_pillow(const std::vector<std::vector<uint32_t>>& loops) const;
  bool try_merge(uint32_t f, uint32_t g, double e);
  bool try_boundary_removal(uint32_t v, uint32_t f);
  bool stale(const Candidate& c) const;
  bool apply(const Candidate& c);
  bool merged_loops_valid(uint32_t f, uint32_t g, std::vector<std::vector<uint32_t>>& loops) const;
  void verify_candidate(const Candidate& c);
  void verify_greedy(const Candidate& committed);
  // The phases of run().
  void choose_normalisation(std::vector<uint32_t>& corners);
  void normalise_positions();
  void allocate_work_state(const std::vector<uint32_t>& corners);
  void lock_edges();
  void init_work_faces();
  void record_input_level();
  void remove_interior_valence2_vertices();
  void seed_candidates();
  void merge_greedily();
};

void Builder::project(const std::vector<std::vector<uint32_t>>& loops, const PlaneFrame& frame,
                      PolygonLoops& out) const {
  out.points.clear();
  out.loops.resize(loops.size());
  for (size_t l = 0; l < loops.size(); ++l) {
    out.loops[l].clear();
    for (const uint32_t v : loops[l]) {
      out.loops[l].push_back(static_cast<uint32_t>(out.points.size()));
      out.points.push_back(frame.project(pos_[v]));
    }
  }
}

// The loop with the largest signed area (counter-clockwise about the proxy normal) becomes the
// outer loop, all others holes; check_polygon_loops then verifies orientation and containment.
void Builder::classify_outer(PolygonLoops& poly, std::vector<std::vector<uint32_t>>& loops) {
  size_t best = 0;
  double best_area = -INFINITY;
  for (size_t l = 0; l < poly.loops.size(); ++l) {
    double a = 0;
    const auto& loop = poly.loops[l];
    for (size_t i = 0; i < loop.size(); ++i) {
      const Vec2 &p = poly.points[loop[i]], &q = poly.points[loop[(i + 1) % loop.size()]];
      a += p.x * q.y - p.y * q.x;
    }
    if (a > best_area) {
      best_area = a;
      best = l;
    }
  }
  if (best != 0) {
    std::swap(poly.loops[0], poly.loops[best]);
    std::swap(loops[0], loops[best]);
  }
}

void Builder::rebuild_cdt(uint32_t f) {
  WorkFace& face = fs_.faces[f];
  face.cdt = AreaMoments();
  if (face.loops.size() == 1 && face.loops[0].size() == 3) {
    const auto& l = face.loops[0];
    face.cdt.add_triangle(pos_[l[0]], pos_[l[1]], pos_[l[2]]);
    return;
  }
  project(face.loops, frame_of(face.centroid, face.normal), scratch_poly_);
  ++impl_.work.triangulations;
  impl_.work.triangulated_vertices += scratch_poly_.points.size();
  std::vector<uint32_t>& flat = scratch_flat_;
  flat.clear();
  for (const auto& l : face.loops) flat.insert(flat.end(), l.begin(), l.end());
  try {
    // After the initial input faces, every face's loops were validated in this same frame
    // (try_merge, removal_valid), so the validity check is skipped.
    if (loops_validated_)
      triangulate_valid_polygon(scratch_poly_, scratch_tris_);
    else
      scratch_tris_ = triangulate_polygon(scratch_poly_);
    // Canonical order (each triangle rotated to start at its smallest vertex id, triangles
    // sorted), so that the rounding of the moments does not depend on the triangulator's
    // output order (the fast path and CGAL list the same triangles in different orders).
    for (auto& t : scratch_tris_) {
      t = {flat[t[0]], flat[t[1]], flat[t[2]]};
      if (t[1] < t[0] && t[1] < t[2])
        t = {t[1], t[2], t[0]};
      else if (t[2] < t[0] && t[2] < t[1])
        t = {t[2], t[0], t[1]};
    }
    std::sort(scratch_tris_.begin(), scratch_tris_.end());
    for (const auto& t : scratch_tris_) face.cdt.add_triangle(pos_[t[0]], pos_[t[1]], pos_[t[2]]);
  } catch (const Error&) {
    // Only input polygons that are not valid in their own plane get here: use a fan.
    for (const auto& l : face.loops)
      for (size_t i = 1; i + 1 < l.size(); ++i) face.cdt.add_triangle(pos_[l[0]], pos_[l[i]], pos_[l[i + 1]]);
  }
}

// Faces with at most this many loop vertices (holes included) get their CDT rebuilt after every
// change, exactly as the thesis does; larger ones keep the moments of a triangulation that is
// updated in place (finish_step), so that the work per operation stays bounded however large a
// (typically planar) face grows. 64 is the fast path's limit (triangulate_valid_polygon).
constexpr uint64_t kRetriangulationLimit = 64;

// Before v leaves the loops of face f (contour decimation): the moments of f's triangulation
// follow the change of its region, the triangle (u, v, w) of v and its loop neighbours, cut off
// where v is convex in f's plane (the region lies left of u -> v -> w) and added where it is
// reflex. Adding is exact (the region gains exactly that triangle, which no other part of the
// face overlaps, since the face stays valid); cutting off is exact when (u, v, w) is a triangle
// of the triangulation or the face is planar, and otherwise the moments of the signed sum, which
// differs from a re-triangulation of v's star only by how far the face bends there. Only used by
// faces above kRetriangulationLimit (finish_step rebuilds the others).
void Builder::update_cdt_for_removal(uint32_t f, uint32_t v) {
  WorkFace& face = fs_.faces[f];
  const StarEntry* e = fs_.star_entry(v, f);
  if (e == nullptr) return;
  const PlaneFrame frame = frame_of(face.centroid, face.normal);
  const Vec3 &u = pos_[e->prev], &p = pos_[v], &w = pos_[e->next];
  const int turn = orient2d(frame.project(u), frame.project(p), frame.project(w));
  if (turn > 0)
    face.cdt.subtract_triangle(u, p, w);
  else if (turn < 0)
    face.cdt.add_triangle(u, w, p);
}

bool Builder::evaluate_merge(uint32_t f, uint32_t g, double& e) const {
  // Recomputed from scratch (used by the greedy-order verifier); push_candidates does the same
  // for all neighbours of f in one pass.
  const WorkFace &F = fs_.faces[f], &G = fs_.faces[g];
  uint64_t shared = 0;
  double angle_sum = 0;
  const double inv_d2 = impl_.inv_unit * impl_.inv_unit;
  const double sf = F.area * inv_d2, sg = G.area * inv_d2;
  const Vec3 nsum = F.normal * sf + G.normal * sg;
  if (!(norm(nsum) > 0)) return false;
  const Vec3 n = normalized(nsum);
  for (const auto& loop : F.loops) {
    const size_t m = loop.size();
    for (size_t i = 0; i < m; ++i) {
      const uint32_t p = loop[(i + m - 1) % m], a = loop[i], b = loop[(i + 1) % m], c = loop[(i + 2) % m];
      if (fs_.face_of_halfedge(b, a) != g) continue;
      if (locked(a, b)) return false;
      ++shared;
      if (fs_.face_of_halfedge(a, p) != g) {
        const StarEntry* h = fs_.star_entry(a, g);
        const double d = inner_angle(pos_[p], pos_[a], pos_[h->next], n) - kPi / 2;
        angle_sum += d * d;
      }
      if (fs_.face_of_halfedge(c, b) != g) {
        const StarEntry* h = fs_.star_entry(b, g);
        const double d = inner_angle(pos_[h->prev], pos_[b], pos_[c], n) - kPi / 2;
        angle_sum += d * d;
      }
    }
  }
  if (shared == 0) return false;
  e = merge_key(F, G, sf, sg, n, shared, angle_sum);
  return true;
}

double Builder::merge_key(const WorkFace& F, const WorkFace& G, double sf, double sg, const Vec3& n, uint64_t shared,
                          double angle_sum) const {
  const Vec3 b = (impl_.normalised(F.centroid) * sf + impl_.normalised(G.centroid) * sg) * (1.0 / (sf + sg));
  AreaMoments mo = F.cdt;
  mo += G.cdt;
  const double l2 = mo.squared_distance_integral(b, n);
  const double l21 = l21_term(sf, F.normal, sg, G.normal, n);
  const uint64_t m = F.num_loop_vertices() + G.num_loop_vertices() - 2 * shared;
  return quantize_priority(merge_priority(l2, l21, m, angle_sum, options_.tie_break_epsilon));
}

void Builder::push_candidates(uint32_t f) {
  // evaluate_merge(f, g) for all neighbours g of f in two passes over f's loops (same
  // arithmetic in the same order, so the same keys).
  if (++slot_clock_ == 0) {
    std::fill(slot_stamp_.begin(), slot_stamp_.end(), 0);
    slot_clock_ = 1;
  }
  const WorkFace& F = fs_.faces[f];
  fs_.prefetch_stars(F.loops);
  twin_.clear();
  twin_slot_.clear();
  nbs_.clear();
  // Neighbours in order of first occurrence; found by a linear search while there are few
  // (no face-indexed scratch access), through the face-indexed stamps beyond that.
  constexpr size_t kLinear = 24;
  bool stamps = false;
  for (const auto& loop : F.loops) {
    const size_t m = loop.size();
    for (size_t i = 0; i < m; ++i) {
      const uint32_t g = fs_.face_of_halfedge(loop[(i + 1) % m], loop[i]);
      twin_.push_back(g);
      if (g == kNoFace) {
        twin_slot_.push_back(kNoFace);
        continue;
      }
      uint32_t slot = kNoFace;
      if (!stamps) {
        for (size_t k = 0; k < nbs_.size(); ++k)
          if (nbs_[k].g == g) {
            slot = static_cast<uint32_t>(k);
            break;
          }
      } else if (slot_stamp_[g] == slot_clock_) {
        slot = slot_index_[g];
      }
      if (slot == kNoFace) {
        slot = static_cast<uint32_t>(nbs_.size());
        heap_.prefetch_pair(std::min(f, g), std::max(f, g));
        __builtin_prefetch(&fs_.faces[g].normal);
        __builtin_prefetch(&fs_.faces[g].cdt.second[2]);
        nbs_.push_back({g, 0, 0.0, Vec3(), false, 0.0});
        if (stamps) {
          slot_stamp_[g] = slot_clock_;
          slot_index_[g] = slot;
        } else if (nbs_.size() > kLinear) {
          stamps = true;
          for (size_t k = 0; k < nbs_.size(); ++k) {
            slot_stamp_[nbs_[k].g] = slot_clock_;
            slot_index_[nbs_[k].g] = static_cast<uint32_t>(k);
          }
        }
      }
      twin_slot_.push_back(slot);
    }
  }
  const double inv_d2 = impl_.inv_unit * impl_.inv_unit;
  const double sf = F.area * inv_d2;
  for (Neighbour& x : nbs_) {
    const WorkFace& G = fs_.faces[x.g];
    __builtin_prefetch(G.loops.data());  // loop sizes, read by merge_key
    const Vec3 nsum = F.normal * sf + G.normal * (G.area * inv_d2);
    x.ok = norm(nsum) > 0;
    if (x.ok) x.n = normalized(nsum);
  }
  size_t base = 0;
  for (const auto& loop : F.loops) {
    const size_t m = loop.size();
    for (size_t i = 0; i < m; ++i) {
      const uint32_t g = twin_[base + i];
      if (g == kNoFace) continue;
      Neighbour& x = nbs_[twin_slot_[base + i]];
      if (!x.ok) continue;
      const uint32_t a = loop[i], b = loop[(i + 1) % m];
      if (locked(a, b)) {
        x.ok = false;  // no candidate: the border between f and g is locked
        continue;
      }
      ++x.shared;
      if (twin_[base + (i + m - 1) % m] != g) {
        const StarEntry* h = fs_.star_entry(a, g);
        const double d = inner_angle(pos_[loop[(i + m - 1) % m]], pos_[a], pos_[h->next], x.n) - kPi / 2;
        x.angle_sum += d * d;
      }
      if (twin_[base + (i + 1) % m] != g) {
        const StarEntry* h = fs_.star_entry(b, g);
        const double d = inner_angle(pos_[h->prev], pos_[b], pos_[loop[(i + 2) % m]], x.n) - kPi / 2;
        x.angle_sum += d * d;
      }
    }
    base += m;
  }
  // Keys first, then the pushes, so that the prefetched heap entries have arrived.
  for (const Neighbour& x : nbs_)
    if (x.ok && x.shared != 0) heap_.prefetch_entry(std::min(f, x.g), std::max(f, x.g));
  for (Neighbour& x : nbs_) {
    if (!x.ok || x.shared == 0) continue;
    const WorkFace& G = fs_.faces[x.g];
    x.key = merge_key(F, G, sf, G.area * inv_d2, x.n, x.shared, x.angle_sum);
  }
  for (const Neighbour& x : nbs_) {
    if (!x.ok || x.shared == 0) continue;
    const uint32_t a = std::min(f, x.g), b = std::max(f, x.g);
    push({x.key, a, b, fs_.faces[a].version, fs_.faces[b].version, 0});
  }
}

void Builder::push_boundary_candidates(uint32_t f) {
  for (const auto& loop : fs_.faces[f].loops) {
    const size_t m = loop.size();
    for (size_t i = 0; i < m; ++i) {
      const uint32_t v = loop[i];
      if (fs_.star_size(v) != 1) continue;
      const double l2 = boundary_vertex_l2(pos_[loop[(i + m - 1) % m]], pos_[v], pos_[loop[(i + 1) % m]]);
      push({quantize_priority(1.0 + l2), v, f, 0, fs_.faces[f].version, 1});
      }
  }
}

// Preconditions of a valence-2 removal for face f: its loops without v stay valid in its plane.
bool Builder::removal_valid(uint32_t f, uint32_t v) {
  const WorkFace& face = fs_.faces[f];
  scratch_loops_ = face.loops;
  for (auto& l : scratch_loops_) {
    auto it = std::find(l.begin(), l.end(), v);
    if (it != l.end()) {
      l.erase(it);
      if (l.size() < 3) return false;
    }
  }
  project(scratch_loops_, frame_of(face.centroid, face.normal), scratch_poly_);
  return check_polygon_loops(scratch_poly_).ok();
}

bool Builder::try_remove_interior(uint32_t v) {
  if (fs_.star_size(v) != 2) return false;
  const StarEntry e0 = fs_.star_begin(v)[0], e1 = fs_.star_begin(v)[1];
  if (e1.prev != e0.next || e1.next != e0.prev) return false;  // not an interior valence-2 vertex
  const uint32_t u = e0.prev, w = e0.next;
  if (fs_.edge_exists(u, w)) return false;
  // Where a locked line meets an unlocked border the vertex stays (the line's end); inside a
  // locked line the chord that replaces two of its edges is locked in turn.
  const bool locked_line = locked(u, v);
  if (locked_line != locked(v, w)) return false;
  if (!removal_valid(e0.face, v) || !removal_valid(e1.face, v)) return false;
  if (locked_line) locked_.insert(edge_key(u, w));
  update_cdt_for_removal(e0.face, v);
  update_cdt_for_removal(e1.face, v);
  fs_.remove_loop_vertex(e0.face, v);
  fs_.remove_loop_vertex(e1.face, v);
  mark_dirty(e0.face);
  mark_dirty(e1.face);
  return true;
}

// Removes interior valence-2 vertices of the dirty faces as long as any can be removed
// (blocked ones are retried whenever one of their faces changes).
void Builder::decimate_dirty(bool with_cancel_points) {
  for (size_t k = 0; k < dirty_.size(); ++k) {
    if (with_cancel_points) poll(k);
    const uint32_t f = dirty_[k];
    bool again = true;
    for (int pass = 0; again && pass < 8 && fs_.faces[f].alive; ++pass) {
      again = false;
      bool blocked = false, removed = false;
      std::vector<uint32_t>& verts = scratch_verts_;
      verts.clear();
      for (const auto& l : fs_.faces[f].loops) verts.insert(verts.end(), l.begin(), l.end());
      for (const uint32_t v : verts) {
        if (fs_.star_size(v) != 2) continue;
        const StarEntry e0 = fs_.star_begin(v)[0], e1 = fs_.star_begin(v)[1];
        if (e1.prev != e0.next || e1.next != e0.prev) continue;
        if (try_remove_interior(v))
          removed = true;
        else
          blocked = true;
      }
      again = removed && blocked;
    }
  }
}

void Builder::finish_step(double error, uint32_t merged_from, uint32_t merged_into) {
  LevelStep step;
  step.record_begin = static_cast<uint32_t>(impl_.hier.records.size());
  for (const uint32_t f : dirty_) {
    WorkFace& face = fs_.faces[f];
    ++face.version;
    ver_[f] = face.alive ? face.version : kDeadVersion;
    if (face.alive) {
      if (face.num_loop_vertices() <= kRetriangulationLimit)
        rebuild_cdt(f);
      else
        ++impl_.work.incremental_updates;  // moments already updated by try_merge / removals
    }
    impl_.hier.add_record(f, face.alive, face.loops, face.normal, face.centroid, face.area);
  }
  step.record_end = static_cast<uint32_t>(impl_.hier.records.size());
  step.merged_from = merged_from;
  step.merged_into = merged_into;
  if (merged_from != kNoRecord) impl_.hier.parent[merged_from] = merged_into;
  impl_.hier.steps.push_back(step);
  const LevelStats& last = impl_.stats.back();
  const uint64_t faces = last.faces - (merged_from != kNoRecord ? 1 : 0);
  impl_.stats.push_back({faces, fs_.used_vertices(), error});
  ++step_;
  for (const uint32_t f : dirty_) {
    dirty_flag_[f] = 0;
    if (!fs_.faces[f].alive) continue;
    push_candidates(f);
    push_boundary_candidates(f);
  }
  dirty_.clear();
}

bool Builder::stale(const Candidate& c) const {
  if (c.kind == 0) {
    return ver_[c.a] != c.va || ver_[c.b] != c.vb;
  }
  return ver_[c.b] != c.vb || fs_.star_size(c.a) != 1 || fs_.star_begin(c.a)[0].face != c.b;
}

// True when the merged face's loops border one and the same face X all round, and X has no
// other edges: the merge would leave a closed "pillow" of two faces over the same vertex cycles,
// whose cage cells duplicate each other. Such a component stops at three faces.
bool Builder::closes_pillow(const std::vector<std::vector<uint32_t>>& loops) const {
  uint32_t other = kNoFace;
  uint64_t count = 0;
  for (const auto& loop : loops) {
    const size_t m = loop.size();
    for (size_t i = 0; i < m; ++i) {
      const uint32_t x = fs_.face_of_halfedge(loop[i + 1 < m ? i + 1 : 0], loop[i]);
      if (x == kNoFace || (other != kNoFace && x != other)) return false;
      other = x;
      ++count;
    }
  }
  return other != kNoFace && fs_.faces[other].num_loop_vertices() == count;
}

bool Builder::shares_locked_edge(uint32_t f, uint32_t g) const {
  for (const auto& loop : fs_.faces[f].loops) {
    const size_t m = loop.size();
    for (size_t i = 0; i < m; ++i)
      if (fs_.face_of_halfedge(loop[(i + 1) % m], loop[i]) == g && locked(loop[i], loop[(i + 1) % m])) return true;
  }
  return false;
}

bool Builder::try_merge(uint32_t f, uint32_t g, double e) {
  if (!locked_.empty() && shares_locked_edge(f, g)) return false;
  std::vector<std::vector<uint32_t>>& loops = merge_loops_;  // reused buffers
  uint64_t shared = 0;
  if (!fs_.splice(f, g, loops, shared)) return false;
  if (closes_pillow(loops)) return false;
  const WorkFace &F = fs_.faces[f], &G = fs_.faces[g];
  const double area = F.area + G.area;
  const Vec3 nsum = F.normal * F.area + G.normal * G.area;
  if (!(norm(nsum) > 0) || !(area > 0)) return false;
  const Vec3 normal = normalized(nsum);
  const Vec3 centroid = (F.centroid * F.area + G.centroid * G.area) * (1.0 / area);
  project(loops, frame_of(centroid, normal), scratch_poly_);
  classify_outer(scratch_poly_, loops);
  if (!check_polygon_loops(scratch_poly_).ok()) return false;
  // The union of both faces' triangulations triangulates the merged face (the merge only
  // removes shared edges): its moments are the sum, the same sum merge_key evaluated (3.3).
  AreaMoments moments = F.cdt;
  moments += G.cdt;
  // Commit: the face with the larger cluster keeps its id (union by size).
  const bool keep_f = F.cluster_size > G.cluster_size || (F.cluster_size == G.cluster_size && f < g);
  const uint32_t keep = keep_f ? f : g, gone = keep_f ? g : f;
  // The candidates of the absorbed face with its other neighbours are stale from here on.
  for (const auto& loop : fs_.faces[gone].loops) {
    const size_t m = loop.size();
    for (size_t i = 0; i < m; ++i) {
      const uint32_t x = fs_.face_of_halfedge(loop[i + 1 < m ? i + 1 : 0], loop[i]);
      if (x != kNoFace && x != keep) heap_.erase_pair_entry(std::min(gone, x), std::max(gone, x));
    }
  }
  fs_.remove_star(f);
  fs_.remove_star(g);
  WorkFace& K = fs_.faces[keep];
  WorkFace& D = fs_.faces[gone];
  K.loops.swap(loops);
  K.normal = normal;
  K.centroid = centroid;
  K.area = area;
  K.cdt = moments;
  K.cluster_size += D.cluster_size;
  D.alive = false;
  // Freed now, outer buffer included (clear() kept it): a dead face is never filled again, and a
  // cancel's unwinding then frees only what the live faces hold (glibc's free of a million small
  // blocks, not the merging, was most of the 0.3 s from a cancel to the return).
  std::vector<std::vector<uint32_t>>().swap(D.loops);
  fs_.add_star(keep);
  mark_dirty(keep);
  mark_dirty(gone);
  decimate_dirty();
  finish_step(e, gone, keep);
  return true;
}

bool Builder::try_boundary_removal(uint32_t v, uint32_t f) {
  const StarEntry e = fs_.star_begin(v)[0];
  if (fs_.edge_exists(e.prev, e.next)) return false;
  if (!removal_valid(f, v)) return false;
  update_cdt_for_removal(f, v);
  fs_.remove_loop_vertex(f, v);
  mark_dirty(f);
  decimate_dirty();
  return true;
}

// Debug: whether the loops `loops` of faces f and g merged form a valid polygon in the plane of
// the merged proxy (the test of try_merge, without its degenerate-proxy checks).
bool Builder::merged_loops_valid(uint32_t f, uint32_t g, std::vector<std::vector<uint32_t>>& loops) const {
  const WorkFace &F = fs_.faces[f], &G = fs_.faces[g];
  const Vec3 n = normalized(F.normal * F.area + G.normal * G.area);
  const Vec3 c = (F.centroid * F.area + G.centroid * G.area) * (1.0 / (F.area + G.area));
  PolygonLoops poly;
  project(loops, frame_of(c, n), poly);
  classify_outer(poly, loops);
  return check_polygon_loops(poly).ok();
}

// Debug (SimplifyOptions::verify_greedy_order): a popped candidate that is valid must be the
// minimum of all valid operations (verify_greedy).
void Builder::verify_candidate(const Candidate& c) {
  if (c.kind == 0) {
    std::vector<std::vector<uint32_t>> loops;
    uint64_t shared;
    if (fs_.splice(c.a, c.b, loops, shared) && merged_loops_valid(c.a, c.b, loops)) verify_greedy(c);
  } else {
    const StarEntry e = fs_.star_begin(c.a)[0];
    if (!fs_.edge_exists(e.prev, e.next) && removal_valid(c.b, c.a)) verify_greedy(c);
  }
}

// Debug (SimplifyOptions::verify_greedy_order): every valid operation is re-evaluated from
// scratch; the committed one must have the minimum priority.
void Builder::verify_greedy(const Candidate& committed) {
  double best = INFINITY;
  std::vector<std::vector<uint32_t>> loops;
  for (uint32_t f = 0; f < fs_.faces.size(); ++f) {
    if (!fs_.faces[f].alive) continue;
    for (const auto& loop : fs_.faces[f].loops)
      for (size_t i = 0; i < loop.size(); ++i) {
        const uint32_t g = fs_.face_of_halfedge(loop[(i + 1) % loop.size()], loop[i]);
        if (g == kNoFace || g < f) continue;
        double e;
        if (!evaluate_merge(f, g, e) || e >= best) continue;
        uint64_t shared;
        if (!fs_.splice(f, g, loops, shared) || closes_pillow(loops)) continue;
        if (merged_loops_valid(f, g, loops)) best = e;
      }
    for (const auto& loop : fs_.faces[f].loops)
      for (size_t i = 0; i < loop.size(); ++i) {
        const uint32_t v = loop[i], m = static_cast<uint32_t>(loop.size());
        if (fs_.star_size(v) != 1) continue;
        const uint32_t u = loop[(i + m - 1) % m], w = loop[(i + 1) % m];
        const double e = quantize_priority(1.0 + boundary_vertex_l2(pos_[u], pos_[v], pos_[w]));
        if (e < best && !fs_.edge_exists(u, w) && removal_valid(f, v)) best = e;
      }
  }
  if (committed.key > best)
    fail(Status::internal_error, "greedy order violated: committed priority " + std::to_string(committed.key) +
                                     " > minimum valid " + std::to_string(best));
}

// Normalisation: centre of the referenced vertices' bounding box, unit = input resolution
// sqrt(mean input face area) (see README: with the bbox diagonal as unit every error term is
// << 1 and the tie-break dominates the priority). The same pass counts the face corners at each
// vertex (`corners`, the capacity of its star).
void Builder::choose_normalisation(std::vector<uint32_t>& corners) {
  const size_t nf = mesh_.num_faces(), nv = mesh_.num_vertices();
  BoundingBox box;
  corners.assign(nv, 0);
  for (const uint32_t v : mesh_.face_vertices) {
    box.extend(mesh_.positions[v]);
    ++corners[v];
  }
  double total_area = 0;
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t* fv = mesh_.face_begin(f);
    for (uint32_t k = 1; k + 1 < mesh_.face_size(f); ++k)
      total_area += 0.5 * norm(cross(mesh_.positions[fv[k]] - mesh_.positions[fv[0]], mesh_.positions[fv[k + 1]] - mesh_.positions[fv[0]]));
  }
  const double unit = std::sqrt(total_area / double(nf > 0 ? nf : 1));
  impl_.unit = !(unit > 0) ? 1.0 : unit;
  impl_.inv_unit = 1.0 / impl_.unit;
  impl_.center = box.empty ? Vec3() : (box.min + box.max) * 0.5;
}

void Builder::normalise_positions() {
  const size_t nv = mesh_.num_vertices();
  pos_.reserve(nv);
  advise_huge_pages(pos_.data(), nv * sizeof(Vec3));
  pos_.resize(nv);
  for (size_t v = 0; v < nv; ++v) pos_[v] = impl_.normalised(mesh_.positions[v]);
}

void Builder::allocate_work_state(const std::vector<uint32_t>& corners) {
  const size_t nf = mesh_.num_faces(), nv = mesh_.num_vertices();
  fs_.faces.reserve(nf);
  advise_huge_pages(fs_.faces.data(), nf * sizeof(WorkFace));
  fs_.faces.resize(nf);
  monitor_.report("simplify", 0.0);  // each of these allocations takes a fraction of a second on a million faces
  fs_.init_stars(corners);
  monitor_.report("simplify", 0.0);
  heap_.init(nv);
  dirty_flag_.assign(nf, 0);
  assign_huge(ver_, nf, 0u);
  monitor_.report("simplify", 0.0);
  slot_stamp_.assign(nf, 0);
  slot_index_.assign(nf, 0);
  monitor_.report("simplify", 0.0);
  impl_.hier.parent.assign(nf, kNoRecord);
  impl_.hier.current.assign(nf, kNoRecord);
}

// One work face per input face, with its loop, its proxy and its star entries.
void Builder::init_work_faces() {
  const size_t nf = mesh_.num_faces();
  for (uint32_t f = 0; f < nf; ++f) {
    poll(f);
    WorkFace& face = fs_.faces[f];
    const uint32_t* v = mesh_.face_begin(f);
    const uint32_t n = mesh_.face_size(f);
    face.loops.assign(1, std::vector<uint32_t>(v, v + n));
    // Proxy (3.1) of an input face: area-weighted normal and centroid of its vertex fan
    // (for triangles: the triangle's own normal, centroid and area).
    Vec3 nsum, csum;
    double area = 0;
    for (uint32_t i = 1; i + 1 < n; ++i) {
      const Vec3 &a = mesh_.positions[v[0]], &b = mesh_.positions[v[i]], &c = mesh_.positions[v[i + 1]];
      const Vec3 cr = cross(b - a, c - a);
      const double t = 0.5 * norm(cr);
      nsum += cr;
      csum += (a + b + c) * (t / 3.0);
      area += t;
    }
    face.normal = normalized(nsum);
    face.area = area;
    face.centroid = area > 0 ? csum * (1.0 / area) : mesh_.positions[v[0]];
    fs_.add_star(f);
  }
}

// Level 0 of the hierarchy: a record (and a triangulation) per input face.
void Builder::record_input_level() {
  const size_t nf = mesh_.num_faces();
  for (uint32_t f = 0; f < nf; ++f) {
    poll(f);
    rebuild_cdt(f);
    impl_.hier.add_record(f, true, fs_.faces[f].loops, fs_.faces[f].normal, fs_.faces[f].centroid, fs_.faces[f].area);
  }
  impl_.stats.push_back({nf, fs_.used_vertices(), 0.0});
}

// Interior valence-2 vertices of a polygonal input are removed right away (one step).
void Builder::lock_edges() {
  if (options_.locked_edges.empty()) return;
  std::unordered_set<uint64_t> input_edges;
  for (size_t f = 0; f < mesh_.num_faces(); ++f) {
    const uint32_t n = mesh_.face_size(f);
    for (uint32_t k = 0; k < n; ++k) input_edges.insert(edge_key(mesh_.face_vertex(f, k), mesh_.face_vertex(f, (k + 1) % n)));
  }
  for (const uint64_t key : options_.locked_edges) {
    if (!input_edges.count(key))
      fail(Status::invalid_argument, "simplify: locked edge (" + std::to_string(edge_key_first(key)) + ", " +
                                         std::to_string(edge_key_second(key)) + ") is not an edge of the mesh");
    locked_.insert(key);
  }
}

void Builder::remove_interior_valence2_vertices() {
  const size_t nf = mesh_.num_faces();
  for (uint32_t f = 0; f < nf; ++f) mark_dirty(f);
  decimate_dirty(true);
  bool changed = false;
  for (const uint32_t f : dirty_)
    if (fs_.faces[f].num_loop_vertices() != mesh_.face_size(f)) changed = true;
  if (changed) {
    std::vector<uint32_t> all;
    all.swap(dirty_);
    for (const uint32_t f : all) {
      dirty_flag_[f] = 0;
      if (fs_.faces[f].num_loop_vertices() != mesh_.face_size(f)) mark_dirty(f);
    }
    finish_step(1.0, kNoRecord, kNoRecord);
  } else {
    for (const uint32_t f : dirty_) dirty_flag_[f] = 0;
    dirty_.clear();
  }
}

void Builder::seed_candidates() {
  const size_t nf = mesh_.num_faces();
  for (uint32_t f = 0; f < nf; ++f) {
    poll(f);
    push_candidates(f);
    push_boundary_candidates(f);
  }
  loops_validated_ = true;
}

// The greedy loop: the candidate of least priority first, skipped when stale (a face it
// involves changed since it was pushed).
void Builder::merge_greedily() {
  const size_t nf = mesh_.num_faces();
  uint64_t ops = 0, merges = 0;
  const double denom = nf > 1 ? static_cast<double>(nf - 1) : 1.0;
  while (!heap_.empty()) {
    const Candidate c = heap_.top();  // copy: pop() may reuse its slot
    heap_.pop();
    if (stale(c)) continue;
    if (options_.verify_greedy_order) verify_candidate(c);
    if (!apply(c)) continue;
    if (c.kind == 0) ++merges;
    if (++ops % 1024 == 0) monitor_.report("simplify", std::min(1.0, static_cast<double>(merges) / denom));
  }
  monitor_.report("simplify", 1.0);
}

// A merge (kind 0) or a boundary-vertex removal; false when it turns out invalid.
bool Builder::apply(const Candidate& c) {
  if (c.kind == 0) return try_merge(c.a, c.b, c.key);
  if (!try_boundary_removal(c.a, c.b)) return false;
  finish_step(c.key, kNoRecord, kNoRecord);
  return true;
}

void Builder::run() {
  // A report between the set-up phases (seconds each on a million faces), so a cancel takes effect there.
  auto checkpoint = [&] { monitor_.report("simplify", 0.0); };
  std::vector<uint32_t> corners;
  choose_normalisation(corners);
  checkpoint();
  normalise_positions();
  if (mesh_.num_faces() >= 0x7fffffffu || mesh_.num_vertices() >= 0x7fffffffu)
    fail(Status::invalid_argument, "simplify: mesh too large");
  checkpoint();
  allocate_work_state(corners);
  lock_edges();
  checkpoint();
  init_work_faces();
  record_input_level();
  checkpoint();
  remove_interior_valence2_vertices();
  seed_candidates();
  checkpoint();
  merge_greedily();
  impl_.hier.level = impl_.hier.steps.size();
}

}  // namespace

SimplificationHierarchy::SimplificationHierarchy(const PolygonMesh& input, const SimplifyOptions& options,
                                                 const TaskMonitor& monitor)
    : impl_(std::make_unique<Impl>()) {
  monitor.report("simplify", 0.0);
  const ValidationReport report = validate_mesh(input, 16, monitor, "simplify", 0.0);
  if (!report.ok()) fail(Status::invalid_mesh, "simplify: invalid input mesh: " + report.summary());
  monitor.report("simplify", 0.0);  // the validation and the copy below each take a fraction of a second per million faces
  if (!(options.tie_break_epsilon >= 0) || !std::isfinite(options.tie_break_epsilon))
    fail(Status::invalid_argument, "simplify: tie_break_epsilon must be finite and >= 0");
  // Measured: ~1 KB per input face at the peak (bunny, 69K faces: 67 MB).
  check_memory_estimate(estimate_product(input.num_faces(), 1024), "the simplification hierarchy");
  impl_->input = input;
  monitor.report("simplify", 0.0);
  Builder(*impl_, options, monitor).run();
  impl_->error_prefix_max.resize(impl_->stats.size());
  double m = 0;
  for (size_t i = 0; i < impl_->stats.size(); ++i) impl_->error_prefix_max[i] = m = std::max(m, impl_->stats[i].error);
}

SimplificationHierarchy::~SimplificationHierarchy() = default;
SimplificationHierarchy::SimplificationHierarchy(SimplificationHierarchy&&) noexcept = default;
SimplificationHierarchy& SimplificationHierarchy::operator=(SimplificationHierarchy&&) noexcept = default;

size_t SimplificationHierarchy::num_levels() const { return impl_->stats.size(); }
size_t SimplificationHierarchy::current_level() const { return impl_->hier.level; }

void SimplificationHierarchy::go_to_level(size_t level) {
  if (level >= num_levels()) fail(Status::invalid_argument, "simplify: level out of range");
  HierarchyRecords& h = impl_->hier;
  while (h.level < level) h.apply(h.level++);
  while (h.level > level) h.undo(--h.level);
}

uint64_t SimplificationHierarchy::face_count(size_t level) const {
  if (level >= num_levels()) fail(Status::invalid_argument, "simplify: level out of range");
  return impl_->stats[level].faces;
}
uint64_t SimplificationHierarchy::vertex_count(size_t level) const {
  if (level >= num_levels()) fail(Status::invalid_argument, "simplify: level out of range");
  return impl_->stats[level].vertices;
}
double SimplificationHierarchy::error(size_t level) const {
  if (level >= num_levels()) fail(Status::invalid_argument, "simplify: level out of range");
  return impl_->stats[level].error;
}

namespace {

// The first level whose count (face or vertex: non-increasing over the levels) is <= `at_most`,
// or the last level when none is.
template <class Count>
size_t first_level_with_at_most(const std::vector<LevelStats>& s, uint64_t at_most, Count count) {
  size_t lo = 0, hi = s.size() - 1;
  if (count(s[hi]) > at_most) return hi;
  while (lo < hi) {
    const size_t mid = (lo + hi) / 2;
    if (count(s[mid]) <= at_most) hi = mid; else lo = mid + 1;
  }
  return lo;
}

}  // namespace

size_t SimplificationHierarchy::level_for_face_count(uint64_t faces) const {
  return first_level_with_at_most(impl_->stats, faces, [](const LevelStats& l) { return l.faces; });
}
size_t SimplificationHierarchy::level_for_vertex_count(uint64_t vertices) const {
  return first_level_with_at_most(impl_->stats, vertices, [](const LevelStats& l) { return l.vertices; });
}
size_t SimplificationHierarchy::level_for_error(double max_error) const {
  // The coarsest level reached before any operation with priority above max_error.
  const auto& m = impl_->error_prefix_max;  // non-decreasing, m[0] = 0
  const size_t first_above = static_cast<size_t>(std::upper_bound(m.begin(), m.end(), max_error) - m.begin());
  return first_above == 0 ? 0 : first_above - 1;
}

PolygonalLevel SimplificationHierarchy::extract() const {
  const Impl& im = *impl_;
  const HierarchyRecords& h = im.hier;
  PolygonalLevel out;
  out.coordinates.origin = im.center;  // HierarchyData::normalised, the frame of every validity check
  out.coordinates.scale = im.inv_unit;
  const size_t nf = im.input.num_faces();
  std::vector<uint32_t> index(nf, kNoRecord);
  std::vector<uint8_t> used(im.input.num_vertices(), 0);
  for (uint32_t f = 0; f < nf; ++f) {
    const FaceRecord& r = h.records[h.current[f]];
    if (!r.alive) continue;
    index[f] = static_cast<uint32_t>(out.faces.size());
    PolygonalFace face;
    h.loops_of(r, face.loops);
    face.normal = r.normal;
    face.centroid = r.centroid;
    face.area = r.area;
    for (const auto& l : face.loops)
      for (const uint32_t v : l)
        if (!used[v]) {
          used[v] = 1;
          ++out.num_vertices;
        }
    out.faces.push_back(std::move(face));
  }
  out.cluster_of_input_face.resize(nf);
  const double inv_d2 = im.inv_unit * im.inv_unit;
  for (uint32_t t = 0; t < nf; ++t) {
    uint32_t x = t;
    while (h.parent[x] != kNoRecord) x = h.parent[x];
    const uint32_t c = index[x];
    out.cluster_of_input_face[t] = c;
    // Exact L2 / L2,1 of the input face against its cluster's proxy (normalised units).
    const PolygonalFace& face = out.faces[c];
    const Vec3 o = im.normalised(face.centroid);
    const uint32_t* v = im.input.face_begin(t);
    for (uint32_t i = 1; i + 1 < im.input.face_size(t); ++i) {
      const Vec3 &a = im.input.positions[v[0]], &b = im.input.positions[v[i]], &cc = im.input.positions[v[i + 1]];
      out.l2_error += triangle_l2(im.normalised(a), im.normalised(b), im.normalised(cc), o, face.normal);
      const Vec3 cr = cross(b - a, cc - a);
      const double area = 0.5 * norm(cr) * inv_d2;
      const Vec3 d = normalized(cr) - face.normal;
      out.l21_error += area * dot(d, d);
    }
  }
  return out;
}

const PolygonMesh& SimplificationHierarchy::input() const { return impl_->input; }
const SimplifyStats& SimplificationHierarchy::stats() const { return impl_->work; }

CAGEKIT_NAMESPACE_END
