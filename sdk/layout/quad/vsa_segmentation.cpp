// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/quad/vsa_segmentation.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <utility>

#include "core/edge_key.h"
#include "core/status.h"
#include "layout/common/triangle_mesh_input.h"

CAGEKIT_NAMESPACE_BEGIN
namespace {

using detail::kNone;

// The flooding queue: per unassigned face at most one entry, its least (cost, region) offer so
// far, in a 4-ary min-heap ordered by (cost, face, region) with a position index per face
// (decrease-key). The faces come out in the same order and to the same regions as from a plain
// priority queue of every (cost, face, region) offer (whose later offers for an assigned face are
// skipped), with about half the heap operations on a smaller heap: flooding is most of the
// segmentation's time on large meshes.
class FloodQueue {
 public:
  void reset(size_t faces) {
    heap_.clear();
    position_.assign(faces, kAbsent);
  }
  bool empty() const { return heap_.empty(); }
  // Face `face` offered to `region` at `cost`: kept if it beats the face's current offer.
  void offer(double cost, uint32_t face, uint32_t region) {
    const Entry e{cost, face, region};
    uint32_t i = position_[face];
    if (i == kAbsent) {
      i = uint32_t(heap_.size());
      heap_.push_back(e);
    } else if (!less(e, heap_[i])) {
      return;
    }
    sift_up(i, e);
  }
  // Removes the least entry; returns its face and region.
  std::pair<uint32_t, uint32_t> pop() {
    const Entry top = heap_.front();
    position_[top.face] = kAbsent;
    const Entry last = heap_.back();
    heap_.pop_back();
    if (!heap_.empty()) sift_down(0, last);
    return {top.face, top.region};
  }

 private:
  struct Entry {
    double cost;
    uint32_t face, region;
  };
  static constexpr uint32_t kAbsent = 0xffffffffu;
  static bool less(const Entry& a, const Entry& b) {
    return a.cost < b.cost || (a.cost == b.cost && (a.face < b.face || (a.face == b.face && a.region < b.region)));
  }
  void place(uint32_t i, const Entry& e) {
    heap_[i] = e;
    position_[e.face] = i;
  }
  void sift_up(uint32_t i, const Entry& e) {
    while (i > 0) {
      const uint32_t parent = (i - 1) / 4;
      if (!less(e, heap_[parent])) break;
      place(i, heap_[parent]);
      i = parent;
    }
    place(i, e);
  }
  void sift_down(uint32_t i, const Entry& e) {
    const size_t n = heap_.size();
    for (;;) {
      const size_t first = 4 * size_t(i) + 1;
      if (first >= n) break;
      size_t best = first;
      const size_t end = std::min(first + 4, n);
      for (size_t c = first + 1; c < end; ++c)
        if (less(heap_[c], heap_[best])) best = c;
      if (!less(heap_[best], e)) break;
      place(i, heap_[best]);
      i = uint32_t(best);
    }
    place(i, e);
  }
  std::vector<Entry> heap_;
  std::vector<uint32_t> position_;  // per face: its heap index, or kAbsent
};

// The partition state that a teleport saves and a roll-back restores.
struct PartitionState {
  std::vector<uint32_t> face_region;
  std::vector<Vec3> proxy;
  std::vector<uint32_t> seed;
  double error = 0.0;
};

class VsaSolver {
 public:
  VsaSolver(const PolygonMesh& mesh, const VsaOptions& options, const TaskMonitor& monitor, VsaSegmentation& out)
      : mesh_(mesh), options_(options), monitor_(monitor), out_(out) {
    build_face_adjacency(adjacency_, mesh, options.barrier_edges);
    triangle_normals_and_areas(mesh, normal_, area_);
    centroid_.resize(mesh.num_faces());
    for (size_t f = 0; f < mesh.num_faces(); ++f)
      centroid_[f] = (mesh.positions[mesh.face_vertex(f, 0)] + mesh.positions[mesh.face_vertex(f, 1)] +
                      mesh.positions[mesh.face_vertex(f, 2)]) * (1.0 / 3.0);
    for (double a : area_) out_.total_area += a;
    if (!(out_.total_area > 0.0)) fail(Status::invalid_mesh, "vsa segmentation: every face has zero area");
  }

  void run() {
    initial_regions();
    const size_t target = size_t(options_.region_count);
    const bool tolerance_mode = options_.tolerance >= 0.0;
    const size_t insertion_iterations =
        size_t(std::min(options_.insertion_lloyd_iterations, options_.max_lloyd_iterations));
    relax(insertion_iterations, true);
    out_.count_history.emplace_back(uint32_t(state_.proxy.size()), state_.error);
    while (state_.proxy.size() < target) {
      if (tolerance_mode && state_.error <= options_.tolerance * out_.total_area) break;
      // Count mode inserts batches (a fraction of the current count); tolerance mode one region
      // at a time, so that it stops at the first count meeting the tolerance.
      const size_t current = state_.proxy.size();
      const size_t batch =
          tolerance_mode ? 1
                         : std::max<size_t>(1, std::min(target - current,
                                                        size_t(double(current) * options_.insertion_batch_fraction)));
      if (!insert_regions_at_worst(batch)) break;
      relax(insertion_iterations, true);
      out_.count_history.emplace_back(uint32_t(state_.proxy.size()), state_.error);
      monitor_.report("vsa segmentation", 0.8 * double(state_.proxy.size()) / double(target));
    }
    if (tolerance_mode && state_.error > options_.tolerance * out_.total_area)
      monitor_.log(LogLevel::warning, "vsa segmentation: tolerance not met with the largest region count");
    relax(size_t(options_.max_lloyd_iterations), false);
    teleport();
    finish();
  }

 private:
  double cost(uint32_t f, uint32_t r) const {
    const Vec3 d = normal_[f] - state_.proxy[r];
    return area_[f] * dot(d, d);
  }
  bool pinned(uint32_t r) const { return r < num_pinned_; }
  bool across_barrier(size_t e) const {
    const std::vector<uint64_t>& b = options_.barrier_edges;
    const detail::EdgeMap& edges = adjacency_.edges;
    return !b.empty() && std::binary_search(b.begin(), b.end(), edge_key(edges.edge_lo[e], edges.edge_hi[e]));
  }

  void initial_regions();
  void choose_seeds();
  void flood();
  void fit_proxies();
  double total_error() const;
  void relax(size_t max_iterations, bool first_iteration_free);
  uint32_t worst_face(uint32_t region) const;
  bool insert_regions_at_worst(size_t count);
  void teleport();
  void finish();
  // Region sums: area and Σ|f| n_f (L2,1 region error = 2(A − ‖S‖) after the proxy fit).
  void region_sums(std::vector<double>& area, std::vector<Vec3>& sum) const;

  const PolygonMesh& mesh_;
  const VsaOptions& options_;
  const TaskMonitor& monitor_;
  VsaSegmentation& out_;
  FaceAdjacency adjacency_;
  std::vector<Vec3> normal_;
  std::vector<double> area_;
  std::vector<Vec3> centroid_;
  std::vector<uint32_t> pushed_by_;  // flooding scratch: the last region that queued each face
  FloodQueue queue_;                 // flooding scratch (empty between floods)
  size_t num_pinned_ = 0;
  PartitionState state_;
};

void VsaSolver::initial_regions() {
  const size_t nf = mesh_.num_faces();
  state_.face_region.assign(nf, kNone);
  // Pinned regions: ids 0 .. P-1, each a non-empty, edge-connected set of distinct faces.
  for (const std::vector<uint32_t>& set : options_.pinned_regions) {
    const uint32_t r = uint32_t(state_.proxy.size());
    const std::string name = "vsa segmentation: pinned region " + std::to_string(r);
    if (set.empty()) fail(Status::invalid_argument, name + " is empty");
    for (uint32_t f : set) {
      if (f >= nf) fail(Status::invalid_argument, name + " has an out-of-range face " + std::to_string(f));
      if (state_.face_region[f] != kNone)
        fail(Status::invalid_argument, name + ": face " + std::to_string(f) + " is pinned twice");
      state_.face_region[f] = r;
    }
    std::vector<uint32_t> stack{set[0]};
    std::vector<uint8_t> seen(nf, 0);
    seen[set[0]] = 1;
    size_t reached = 1;
    while (!stack.empty()) {
      const uint32_t f = stack.back();
      stack.pop_back();
      for (uint32_t k = adjacency_.offsets[f]; k < adjacency_.offsets[f + 1]; ++k) {
        const uint32_t g = adjacency_.neighbours[k];
        if (!seen[g] && state_.face_region[g] == r) seen[g] = 1, ++reached, stack.push_back(g);
      }
    }
    if (reached != set.size()) fail(Status::invalid_argument, name + " is not edge-connected");
    state_.proxy.push_back(Vec3{});
    state_.seed.push_back(set[0]);
  }
  num_pinned_ = state_.proxy.size();
  // Connected components of the unpinned faces: each needs at least one region.
  std::vector<uint32_t> component(nf, kNone);
  std::vector<uint32_t> component_best;  // largest-area face of each component
  size_t free_faces = 0;
  for (uint32_t s = 0; s < nf; ++s) {
    if (state_.face_region[s] != kNone || component[s] != kNone) continue;
    const uint32_t c = uint32_t(component_best.size());
    component_best.push_back(s);
    std::vector<uint32_t> stack{s};
    component[s] = c;
    while (!stack.empty()) {
      const uint32_t f = stack.back();
      stack.pop_back();
      ++free_faces;
      if (area_[f] > area_[component_best[c]]) component_best[c] = f;
      for (uint32_t k = adjacency_.offsets[f]; k < adjacency_.offsets[f + 1]; ++k) {
        const uint32_t g = adjacency_.neighbours[k];
        if (component[g] == kNone && state_.face_region[g] == kNone) component[g] = c, stack.push_back(g);
      }
    }
  }
  std::vector<uint8_t> covered(component_best.size(), 0);
  for (uint32_t f : options_.seed_faces) {
    if (f >= nf) fail(Status::invalid_argument, "vsa segmentation: seed face " + std::to_string(f) + " is out of range");
    if (state_.face_region[f] != kNone)
      fail(Status::invalid_argument, "vsa segmentation: seed face " + std::to_string(f) + " is pinned or repeated");
    state_.face_region[f] = uint32_t(state_.proxy.size());
    state_.proxy.push_back(normal_[f]);
    state_.seed.push_back(f);
    covered[component[f]] = 1;
  }
  for (size_t c = 0; c < component_best.size(); ++c) {
    if (covered[c]) continue;
    const uint32_t f = component_best[c];
    state_.face_region[f] = uint32_t(state_.proxy.size());
    state_.proxy.push_back(normal_[f]);
    state_.seed.push_back(f);
  }
  const size_t requested = size_t(options_.region_count);
  if (state_.proxy.size() > requested)
    fail(Status::invalid_argument,
         "vsa segmentation: " + std::to_string(requested) + " regions requested but at least " +
             std::to_string(state_.proxy.size()) + " are needed (" + std::to_string(num_pinned_) + " pinned, " +
             std::to_string(options_.seed_faces.size()) + " seeds, " + std::to_string(component_best.size()) +
             " connected components of unpinned faces)");
  if (requested - num_pinned_ > free_faces)
    fail(Status::invalid_argument, "vsa segmentation: " + std::to_string(requested - num_pinned_) +
                                       " free regions requested but only " + std::to_string(free_faces) +
                                       " unpinned faces");
  // Pinned proxies are fitted once; they never change afterwards.
  fit_proxies();
}

void VsaSolver::region_sums(std::vector<double>& area, std::vector<Vec3>& sum) const {
  area.assign(state_.proxy.size(), 0.0);
  sum.assign(state_.proxy.size(), Vec3{});
  for (size_t f = 0; f < state_.face_region.size(); ++f) {
    const uint32_t r = state_.face_region[f];
    if (r == kNone) continue;
    area[r] += area_[f];
    sum[r] += normal_[f] * area_[f];
  }
}

void VsaSolver::fit_proxies() {
  std::vector<double> area;
  std::vector<Vec3> sum;
  region_sums(area, sum);
  for (size_t r = 0; r < sum.size(); ++r) {
    // A region of zero-area faces only keeps its previous proxy.
    if (norm(sum[r]) > 0.0) state_.proxy[r] = normalized(sum[r]);
  }
}

double VsaSolver::total_error() const {
  double e = 0.0;
  for (uint32_t f = 0; f < state_.face_region.size(); ++f) {
    // Before the first flooding only the seeds are assigned: no partition yet.
    if (state_.face_region[f] == kNone) return HUGE_VAL;
    e += cost(f, state_.face_region[f]);
  }
  return e;
}

void VsaSolver::choose_seeds() {
  std::vector<double> best(state_.proxy.size(), HUGE_VAL);
  for (uint32_t f = 0; f < state_.face_region.size(); ++f) {
    const uint32_t r = state_.face_region[f];
    if (r == kNone || pinned(r)) continue;
    const double c = cost(f, r);
    if (c < best[r]) best[r] = c, state_.seed[r] = f;
  }
}

void VsaSolver::flood() {
  const size_t nf = state_.face_region.size();
  for (size_t f = 0; f < nf; ++f)
    if (!pinned(state_.face_region[f])) state_.face_region[f] = kNone;
  // (cost, face, region), smallest first; ties broken by face then region: deterministic.
  FloodQueue& queue = queue_;
  queue.reset(nf);
  // A face's cost to a region does not depend on which face of the region reaches it: a second
  // offer by the same region would change nothing.
  pushed_by_.assign(nf, kNone);
  auto push_neighbours = [&](uint32_t f, uint32_t r) {
    for (uint32_t k = adjacency_.offsets[f]; k < adjacency_.offsets[f + 1]; ++k) {
      const uint32_t g = adjacency_.neighbours[k];
      if (state_.face_region[g] == kNone && pushed_by_[g] != r) {
        pushed_by_[g] = r;
        queue.offer(cost(g, r), g, r);
      }
    }
  };
  for (uint32_t r = uint32_t(num_pinned_); r < state_.proxy.size(); ++r) state_.face_region[state_.seed[r]] = r;
  for (uint32_t r = uint32_t(num_pinned_); r < state_.proxy.size(); ++r) push_neighbours(state_.seed[r], r);
  while (!queue.empty()) {
    const auto [f, r] = queue.pop();
    state_.face_region[f] = r;
    push_neighbours(f, r);
  }
  for (size_t f = 0; f < nf; ++f)
    if (state_.face_region[f] == kNone)
      fail(Status::internal_error, "vsa segmentation: face " + std::to_string(f) + " was reached by no region");
}

void VsaSolver::relax(size_t max_iterations, bool first_iteration_free) {
  out_.relaxation_starts.push_back(out_.error_history.size());
  PartitionState previous;
  if (!first_iteration_free) previous = state_;
  for (size_t it = 0; it < max_iterations; ++it) {
    const bool judged = it > 0 || !first_iteration_free;
    choose_seeds();
    flood();
    fit_proxies();
    state_.error = total_error();
    monitor_.report("vsa segmentation", 0.8 * double(state_.proxy.size()) / double(std::max(1, options_.region_count)));
    // The first iteration after a new seed is always taken: the state before it is no flooding
    // result. Other iterations must not raise the error: the flooding is greedy, so an iteration
    // can, and then the lower state is kept (a local minimum).
    if (judged && state_.error > previous.error) {
      state_ = std::move(previous);
      ++out_.rejected_lloyd_iterations;
      return;
    }
    out_.error_history.push_back(state_.error);
    if (judged && previous.error - state_.error <= options_.relative_convergence * out_.total_area) return;
    previous = state_;
  }
}

uint32_t VsaSolver::worst_face(uint32_t region) const {
  // The face of largest cost other than the seed. Ties (symmetric configurations, e.g. a proxy
  // halfway between two planar sides: every face costs the same) go to the face farthest from
  // the seed, so that the new seed and the old one end up apart rather than side by side.
  const uint32_t seed = state_.seed[region];
  uint32_t face = kNone;
  double face_cost = -1.0, face_distance = -1.0;
  for (uint32_t f = 0; f < state_.face_region.size(); ++f) {
    if (state_.face_region[f] != region || f == seed) continue;
    const double c = cost(f, region);
    const double d = distance(centroid_[f], centroid_[seed]);
    const double tie = 1e-9 * std::max(c, face_cost);
    if (c > face_cost + tie || (c >= face_cost - tie && d > face_distance)) face = f, face_cost = c, face_distance = d;
  }
  return face;
}

bool VsaSolver::insert_regions_at_worst(size_t count) {
  std::vector<double> region_error(state_.proxy.size(), 0.0);
  std::vector<uint32_t> region_size(state_.proxy.size(), 0);
  for (uint32_t f = 0; f < state_.face_region.size(); ++f) {
    region_error[state_.face_region[f]] += cost(f, state_.face_region[f]);
    ++region_size[state_.face_region[f]];
  }
  // The `count` worst regions (largest error; ties to the lower id) with at least two faces.
  std::vector<uint32_t> candidates;
  for (uint32_t r = uint32_t(num_pinned_); r < state_.proxy.size(); ++r)
    if (region_size[r] >= 2) candidates.push_back(r);
  if (candidates.empty()) return false;
  std::stable_sort(candidates.begin(), candidates.end(),
                   [&](uint32_t a, uint32_t b) { return region_error[a] > region_error[b]; });
  if (candidates.size() > count) candidates.resize(count);
  for (uint32_t worst : candidates) {
    const uint32_t face = worst_face(worst);
    const uint32_t r = uint32_t(state_.proxy.size());
    state_.face_region[face] = r;
    state_.proxy.push_back(norm(normal_[face]) > 0.0 ? normal_[face] : state_.proxy[worst]);
    state_.seed.push_back(face);
  }
  state_.error = total_error();
  return true;
}

void VsaSolver::teleport() {
  std::set<std::pair<uint32_t, uint32_t>> rejected;  // (removed, target) tried in the current state
  for (int attempt = 0; attempt < options_.teleport_attempts; ++attempt) {
    if (!(state_.error > 0.0)) return;  // nothing to improve
    std::vector<double> area;
    std::vector<Vec3> sum;
    region_sums(area, sum);
    const size_t nr = state_.proxy.size();
    std::vector<double> error(nr);
    for (size_t r = 0; r < nr; ++r) error[r] = 2.0 * (area[r] - norm(sum[r]));
    // Cheapest merge of each unpinned region with an unpinned neighbour (its faces would go
    // to that neighbour: the error increase of removing it, to first order).
    std::vector<double> merge_cost(nr, HUGE_VAL);
    std::vector<uint32_t> size(nr, 0);
    for (uint32_t f = 0; f < state_.face_region.size(); ++f) ++size[state_.face_region[f]];
    const detail::EdgeMap& edges = adjacency_.edges;
    for (size_t e = 0; e < edges.num_edges(); ++e) {
      if (across_barrier(e)) continue;  // the regions either side are no neighbours
      const uint32_t* h = edges.corners_begin(e);
      for (uint32_t a = 0; a + 1 < edges.valence(e); ++a) {
        const uint32_t i = state_.face_region[edges.corner_face[h[a]]];
        const uint32_t j = state_.face_region[edges.corner_face[h[a + 1]]];
        if (i == j || pinned(i) || pinned(j)) continue;
        const double merged = 2.0 * (area[i] + area[j] - norm(sum[i] + sum[j])) - error[i] - error[j];
        merge_cost[i] = std::min(merge_cost[i], merged);
        merge_cost[j] = std::min(merge_cost[j], merged);
      }
    }
    // Candidates: (merge cost, removed region); the target is the worst other region.
    std::vector<std::pair<double, uint32_t>> order;
    for (uint32_t r = uint32_t(num_pinned_); r < nr; ++r)
      if (merge_cost[r] < HUGE_VAL) order.emplace_back(merge_cost[r], r);
    std::sort(order.begin(), order.end());
    uint32_t removed = kNone, target = kNone;
    for (const auto& candidate : order) {
      uint32_t worst = kNone;
      for (uint32_t r = uint32_t(num_pinned_); r < nr; ++r)
        if (r != candidate.second && size[r] >= 2 && (worst == kNone || error[r] > error[worst])) worst = r;
      if (worst == kNone || rejected.count({candidate.second, worst})) continue;
      removed = candidate.second, target = worst;
      break;
    }
    if (removed == kNone) return;
    const uint32_t seed_face = worst_face(target);
    PartitionState saved = state_;
    saved.error = total_error();
    const size_t history_size = out_.error_history.size(), starts_size = out_.relaxation_starts.size();
    // Remove `removed`: its faces are re-flooded by its neighbours; its id seeds the target.
    for (uint32_t f = 0; f < state_.face_region.size(); ++f)
      if (state_.face_region[f] == removed) state_.face_region[f] = kNone;
    state_.face_region[seed_face] = removed;
    state_.seed[removed] = seed_face;
    state_.proxy[removed] = norm(normal_[seed_face]) > 0.0 ? normal_[seed_face] : state_.proxy[target];
    // Seeds of the other regions stay; flood directly (a region's seed is its own face).
    flood();
    fit_proxies();
    state_.error = total_error();
    relax(size_t(std::max(1, options_.teleport_relaxation_steps)), false);
    VsaTeleport record{removed, target, seed_face, saved.error, state_.error, state_.error < saved.error};
    out_.teleports.push_back(record);
    if (record.accepted) {
      rejected.clear();
      relax(size_t(options_.max_lloyd_iterations), false);
    } else {
      state_ = std::move(saved);
      out_.error_history.resize(history_size);
      out_.relaxation_starts.resize(starts_size);
      rejected.insert({removed, target});
    }
    monitor_.report("vsa segmentation", 0.8 + 0.2 * double(attempt + 1) / double(options_.teleport_attempts));
  }
}

void VsaSolver::finish() {
  out_.face_region = state_.face_region;
  out_.proxy_normal = state_.proxy;
  out_.region_seed = state_.seed;
  out_.region_pinned.assign(state_.proxy.size(), 0);
  for (size_t r = 0; r < num_pinned_; ++r) out_.region_pinned[r] = 1;
  out_.region_area.assign(state_.proxy.size(), 0.0);
  out_.region_error.assign(state_.proxy.size(), 0.0);
  for (uint32_t f = 0; f < state_.face_region.size(); ++f) {
    const uint32_t r = state_.face_region[f];
    out_.region_area[r] += area_[f];
    out_.region_error[r] += cost(f, r);
  }
  out_.total_error = 0.0;
  for (double e : out_.region_error) out_.total_error += e;
}

}  // namespace

std::vector<uint32_t> VsaSegmentation::region_faces(uint32_t r) const {
  std::vector<uint32_t> faces;
  for (uint32_t f = 0; f < face_region.size(); ++f)
    if (face_region[f] == r) faces.push_back(f);
  return faces;
}

VsaSegmentation segment_vsa(const PolygonMesh& triangles, const VsaOptions& options, const TaskMonitor& monitor) {
  if (options.region_count < 1) fail(Status::invalid_argument, "vsa segmentation: region_count must be >= 1");
  if (!(options.tolerance < 0.0 || std::isfinite(options.tolerance)))
    fail(Status::invalid_argument, "vsa segmentation: tolerance must be finite");
  if (options.max_lloyd_iterations < 1 || options.insertion_lloyd_iterations < 1 || options.teleport_attempts < 0 || options.teleport_relaxation_steps < 1 ||
      !(options.relative_convergence >= 0.0) || !(options.insertion_batch_fraction >= 0.0) ||
      !std::isfinite(options.insertion_batch_fraction))
    fail(Status::invalid_argument, "vsa segmentation: iteration counts must be >= 1 (teleport_attempts >= 0), the "
                                   "convergence threshold and insertion batch fraction finite and >= 0");
  require_triangle_mesh(triangles, "vsa segmentation");
  if (size_t(options.region_count) > triangles.num_faces())
    fail(Status::invalid_argument, "vsa segmentation: " + std::to_string(options.region_count) +
                                       " regions requested but the mesh has only " +
                                       std::to_string(triangles.num_faces()) + " faces");
  VsaSegmentation out;
  VsaSolver solver(triangles, options, monitor, out);
  solver.run();
  return out;
}

CAGEKIT_NAMESPACE_END
