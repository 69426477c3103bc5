// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/simplify/polygonal_face_set.h"

#include <algorithm>
#include <cstddef>

CAGEKIT_NAMESPACE_BEGIN
namespace detail {

void PolygonalFaceSet::init_stars(const std::vector<uint32_t>& capacity) {
  const size_t n = capacity.size();
  assign_huge(head_, n, StarHead{});
  uint64_t total = 0;
  for (size_t v = 0; v < n; ++v) {
    head_[v].offset = total;
    total += capacity[v];
  }
  assign_huge(star_, total, StarEntry{kNoFace, 0, 0});
  assign_huge(scratch_, n, SpliceScratch{});
  used_vertices_ = 0;
}

void PolygonalFaceSet::add_star(uint32_t f) {
  for (const auto& loop : faces[f].loops) {
    const size_t m = loop.size();
    for (size_t i = 0; i < m; ++i) {
      const uint32_t v = loop[i];
      const uint32_t c = head_[v].count++;
      if (c == 0) ++used_vertices_;
      star_[head_[v].offset + c] = {f, loop[(i + m - 1) % m], loop[(i + 1) % m]};
    }
  }
}

void PolygonalFaceSet::remove_star_entry(uint32_t v, uint32_t f) {
  StarEntry* s = star_.data() + head_[v].offset;
  const uint32_t n = head_[v].count;
  for (uint32_t i = 0; i < n; ++i)
    if (s[i].face == f) {
      s[i] = s[n - 1];
      if (--head_[v].count == 0) --used_vertices_;
      break;
    }
}

void PolygonalFaceSet::remove_star(uint32_t f) {
  for (const auto& loop : faces[f].loops)
    for (const uint32_t v : loop) remove_star_entry(v, f);
}

void PolygonalFaceSet::remove_loop_vertex(uint32_t f, uint32_t v) {
  const StarEntry* e = star_entry(v, f);
  if (e == nullptr) return;
  const uint32_t u = e->prev, w = e->next;
  for (auto& loop : faces[f].loops)
    for (size_t i = 0; i < loop.size(); ++i)
      if (loop[i] == v) {
        loop.erase(loop.begin() + static_cast<std::ptrdiff_t>(i));
        break;
      }
  StarEntry* s = star_.data() + head_[u].offset;
  for (uint32_t i = 0; i < head_[u].count; ++i)
    if (s[i].face == f) s[i].next = w;
  s = star_.data() + head_[w].offset;
  for (uint32_t i = 0; i < head_[w].count; ++i)
    if (s[i].face == f) s[i].prev = u;
  remove_star_entry(v, f);
}

bool PolygonalFaceSet::splice(uint32_t f, uint32_t g, std::vector<std::vector<uint32_t>>& loops,
                              uint64_t& shared_edges) {
  // The inner vectors of `loops` are reused (no allocation once their capacity suffices); on
  // failure the contents of `loops` are unspecified.
  shared_edges = 0;
  if (++current_stamp_ == 0) {  // wrapped: clear the stamps
    std::fill(scratch_.begin(), scratch_.end(), SpliceScratch{});
    current_stamp_ = 1;
  }
  const uint32_t stamp = current_stamp_;
  starts_.clear();
  const uint32_t pair[2] = {f, g};
  // Loop successors of both faces in a vertex-indexed scratch (a valid face passes through a
  // vertex at most once): the half-edge a->b of one face is shared iff the other face has
  // b->a, i.e. the same test as face_of_halfedge(b, a) == other (a directed contour half-edge
  // belongs to at most one face) without scanning the stars.
  for (int k = 0; k < 2; ++k)
    for (const auto& loop : faces[pair[k]].loops) {
      const size_t m = loop.size();
      for (size_t i = 0; i < m; ++i) {
        SpliceScratch& x = scratch_[loop[i]];
        x.stamp[k] = stamp;
        x.next[k] = loop[i + 1 < m ? i + 1 : 0];
      }
    }
  for (int k = 0; k < 2; ++k) {
    for (const auto& loop : faces[pair[k]].loops) {
      const size_t m = loop.size();
      for (size_t i = 0; i < m; ++i) {
        const uint32_t a = loop[i], b = loop[(i + 1) % m];
        const SpliceScratch& y = scratch_[b];
        if (y.stamp[1 - k] == stamp && y.next[1 - k] == a) {
          if (k == 0) ++shared_edges;
          continue;
        }
        SpliceScratch& x = scratch_[a];
        if (x.out_stamp == stamp) return false;  // two outgoing half-edges: repeated vertex
        x.out_stamp = stamp;
        x.out_next = b;
        x.visited = 0;
        starts_.push_back(a);
      }
    }
  }
  if (starts_.empty()) return false;
  size_t count = 0;
  for (const uint32_t s : starts_) {
    if (scratch_[s].visited) continue;
    if (count == loops.size()) loops.emplace_back();
    std::vector<uint32_t>& loop = loops[count++];
    loop.clear();
    uint32_t cur = s;
    do {
      SpliceScratch& x = scratch_[cur];
      if (x.out_stamp != stamp || x.visited) return false;  // broken or pinched cycle
      x.visited = 1;
      loop.push_back(cur);
      cur = x.out_next;
    } while (cur != s);
  }
  loops.resize(count);
  return true;
}

}  // namespace detail
CAGEKIT_NAMESPACE_END
