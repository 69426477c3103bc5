// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Working face structure of the face-merge simplifier (thesis §3.3.1): faces with holes as
// loops of input vertex indices plus a per-vertex "star" (for every face whose loops pass
// through the vertex: that face, the loop predecessor and the loop successor). Since a valid
// face passes through a vertex at most once, a contour half-edge a->b is identified by the
// star entry of a with next == b; its twin b->a by the star entry of b with next == a.
// A vertex's star never grows beyond the number of input faces around it, so the stars live
// in one flat array with fixed per-vertex capacity. Private to sdk/layout.
#include <cstddef>
#include <cstdint>
#include <vector>

#ifdef __linux__
#include <sys/mman.h>
#endif

#include "core/polygon_mesh.h"
#include "layout/simplify/merge_priority.h"

CAGEKIT_NAMESPACE_BEGIN
namespace detail {

// Asks for transparent huge pages on the 2 MiB-aligned interior of [p, p + bytes) (Linux, THP
// in "madvise" mode): the simplifier's big arrays are accessed at random, so 4 KiB pages cost a
// TLB miss on nearly every access. Must precede the first touch of the memory. A hint only.
inline void advise_huge_pages(const void* p, size_t bytes) {
#ifdef __linux__
  constexpr uintptr_t kHuge = uintptr_t(1) << 21;
  if (bytes < 2 * kHuge) return;
  const uintptr_t begin = (reinterpret_cast<uintptr_t>(p) + kHuge - 1) & ~(kHuge - 1);
  const uintptr_t end = (reinterpret_cast<uintptr_t>(p) + bytes) & ~(kHuge - 1);
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}
// v.assign(n, x) on storage advised for huge pages.
template <class T>
void assign_huge(std::vector<T>& v, size_t n, const T& x) {
  if (v.capacity() < n) {
    std::vector<T>().swap(v);
    v.reserve(n);
    advise_huge_pages(v.data(), n * sizeof(T));
  }
  v.assign(n, x);
}

constexpr uint32_t kNoFace = 0xffffffffu;

struct WorkFace {
  std::vector<std::vector<uint32_t>> loops;  // loops[0] outer (CCW about normal), others holes
  Vec3 normal, centroid;                     // proxy (3.1), input units
  double area = 0;                           // sigma, input units
  AreaMoments cdt;                           // moments of the lifted CDT, normalised units
  uint32_t version = 0;                      // bumped whenever loops or proxy change
  uint32_t cluster_size = 1;                 // number of input faces in the cluster
  bool alive = true;
  uint64_t num_loop_vertices() const {
    uint64_t n = 0;
    for (const auto& l : loops) n += l.size();
    return n;
  }
};

struct StarEntry {
  uint32_t face, prev, next;
};

class PolygonalFaceSet {
 public:
  std::vector<WorkFace> faces;

  // capacity[v] = number of input faces around v.
  void init_stars(const std::vector<uint32_t>& capacity);
  void add_star(uint32_t f);     // registers the loops of face f in the stars
  void remove_star(uint32_t f);  // unregisters them

  uint32_t star_size(uint32_t v) const { return head_[v].count; }
  const StarEntry* star_begin(uint32_t v) const { return star_.data() + head_[v].offset; }
  const StarEntry* star_entry(uint32_t v, uint32_t face) const {
    const StarEntry* s = star_begin(v);
    for (uint32_t i = 0, n = head_[v].count; i < n; ++i)
      if (s[i].face == face) return s + i;
    return nullptr;
  }
  // Face owning the contour half-edge a->b, or kNoFace.
  uint32_t face_of_halfedge(uint32_t a, uint32_t b) const {
    const StarEntry* s = star_begin(a);
    for (uint32_t i = 0, n = head_[a].count; i < n; ++i)
      if (s[i].next == b) return s[i].face;
    return kNoFace;
  }
  // Hint: the stars of all vertices of these loops are read soon (two passes, so that the
  // cache misses of the heads and then of the entries overlap).
  void prefetch_stars(const std::vector<std::vector<uint32_t>>& loops) const {
    for (const auto& l : loops)
      for (const uint32_t v : l) __builtin_prefetch(&head_[v]);
    for (const auto& l : loops)
      for (const uint32_t v : l) __builtin_prefetch(star_.data() + head_[v].offset);
  }
  bool edge_exists(uint32_t a, uint32_t b) const {
    return face_of_halfedge(a, b) != kNoFace || face_of_halfedge(b, a) != kNoFace;
  }
  uint64_t used_vertices() const { return used_vertices_; }
  // Removes v from the loops of face f (contour decimation), relinking its loop neighbours.
  void remove_loop_vertex(uint32_t f, uint32_t v);

  // The loops of f and g merged along their common contour (shared half-edge pairs removed,
  // the rest linked into cycles). False when the result would repeat a vertex (shared
  // segments touching) or no loop is left (f and g close a surface): both fail criterion (a).
  // `shared_edges` receives the number of removed half-edge pairs. Loops are unclassified.
  // The inner vectors of `loops` are reused; on failure its contents are unspecified.
  bool splice(uint32_t f, uint32_t g, std::vector<std::vector<uint32_t>>& loops, uint64_t& shared_edges);

 private:
  void remove_star_entry(uint32_t v, uint32_t f);  // f's entry in v's star, if any

  struct StarHead {  // offset and size of a vertex's star: one cache line access per vertex
    uint64_t offset = 0;
    uint32_t count = 0, pad = 0;
  };
  std::vector<StarHead> head_;
  std::vector<StarEntry> star_;
  uint64_t used_vertices_ = 0;
  // Scratch for splice, indexed by vertex, valid where the stamps match: the loop successor of
  // the vertex in face f (k = 0) and g (k = 1), and its outgoing half-edge in the spliced loops.
  struct SpliceScratch {
    uint32_t stamp[2] = {0, 0}, next[2] = {0, 0};
    uint32_t out_stamp = 0, out_next = 0, visited = 0, pad = 0;
  };
  std::vector<SpliceScratch> scratch_;
  uint32_t current_stamp_ = 0;
  std::vector<uint32_t> starts_;
};

}  // namespace detail
CAGEKIT_NAMESPACE_END
