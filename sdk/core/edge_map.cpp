// SPDX-License-Identifier: GPL-3.0-or-later
#include "core/edge_map.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN
namespace detail {

void check_mesh_arrays(const PolygonMesh& mesh) {
  const auto& off = mesh.face_offsets;
  if (off.empty())
    fail(Status::invalid_mesh, "mesh face_offsets is empty (it must hold at least the leading 0)");
  if (off[0] != 0)
    fail(Status::invalid_mesh, "mesh face_offsets[0] is " + std::to_string(off[0]) + ", not 0");
  for (size_t f = 1; f < off.size(); ++f)
    if (off[f] < off[f - 1])
      fail(Status::invalid_mesh, "mesh face_offsets decrease at face " + std::to_string(f - 1) + " (" +
                                     std::to_string(off[f - 1]) + " then " + std::to_string(off[f]) + ")");
  if (off.back() != mesh.face_vertices.size())
    fail(Status::invalid_mesh, "mesh face_offsets ends at " + std::to_string(off.back()) + " but there are " +
                                   std::to_string(mesh.face_vertices.size()) + " face vertices");
}

uint32_t find_repeated_vertex(const uint32_t* v, uint32_t n) {
  if (n <= 12) {
    for (uint32_t i = 1; i < n; ++i)
      for (uint32_t j = 0; j < i; ++j)
        if (v[i] == v[j]) return v[i];
    return kNone;
  }
  std::vector<uint32_t> s(v, v + n);
  std::sort(s.begin(), s.end());
  const auto it = std::adjacent_find(s.begin(), s.end());
  return it == s.end() ? kNone : *it;
}

bool face_has_zero_area(const PolygonMesh& mesh, size_t f) {
  const uint32_t n = mesh.face_size(f);
  const uint32_t* v = mesh.face_begin(f);
  if (n < 3) return true;
  const Vec3 p0 = mesh.positions[v[0]];
  double extent = 0;
  for (uint32_t i = 1; i < n; ++i) {
    const Vec3 d = mesh.positions[v[i]] - p0;
    extent = std::max({extent, std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)});
  }
  if (extent == 0) return true;          // every vertex at the same point
  if (!std::isfinite(extent)) return false;  // overflow: cannot tell, assume a real face
  // Vector area of the polygon scaled to a unit extent (fan from vertex 0).
  Vec3 area;
  Vec3 prev = (mesh.positions[v[1]] - p0) * (1.0 / extent);
  if (!is_finite(prev)) {  // 1/extent overflowed (subnormal extent): divide instead
    prev = mesh.positions[v[1]] - p0;
    prev = {prev.x / extent, prev.y / extent, prev.z / extent};
  }
  for (uint32_t i = 2; i < n; ++i) {
    Vec3 d = mesh.positions[v[i]] - p0;
    d = {d.x / extent, d.y / extent, d.z / extent};
    area += cross(prev, d);
    prev = d;
  }
  return 0.5 * norm(area) <= 1e-12;
}

void canonical_face(const uint32_t* v, uint32_t n, std::vector<uint32_t>& out, bool& reversed) {
  out.resize(n);
  uint32_t m = 0;
  for (uint32_t i = 1; i < n; ++i)
    if (v[i] < v[m]) m = i;
  const uint32_t next = v[(m + 1) % n], prev = v[(m + n - 1) % n];
  reversed = prev < next;
  for (uint32_t i = 0; i < n; ++i) out[i] = reversed ? v[(m + n - i) % n] : v[(m + i) % n];
}

namespace {
uint64_t mix64(uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ull;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebull;
  x ^= x >> 31;
  return x;
}
}  // namespace

void find_duplicate_faces(const PolygonMesh& mesh, const std::vector<uint8_t>& include,
                          std::vector<uint32_t>& duplicate_of, std::vector<uint8_t>& reversed_dup) {
  const size_t nf = mesh.num_faces();
  duplicate_of.assign(nf, kNone);
  reversed_dup.assign(nf, 0);
  // Open-addressing hash table of the first face of each distinct canonical cycle, filled in
  // face order: a later face that finds an equal cycle is its duplicate. Linear time.
  size_t capacity = 16;
  while (capacity < 2 * nf) capacity <<= 1;
  const size_t mask = capacity - 1;
  std::vector<uint32_t> slot_face(capacity, kNone);
  std::vector<uint64_t> slot_hash(capacity, 0);
  std::vector<uint32_t> canon, other;
  for (size_t f = 0; f < nf; ++f) {
    if (!include[f]) continue;
    bool rev = false;
    canonical_face(mesh.face_begin(f), mesh.face_size(f), canon, rev);
    uint64_t h = mix64(canon.size() + 0x9e3779b97f4a7c15ull);
    for (uint32_t x : canon) h = mix64(h ^ x);
    for (size_t slot = h & mask;; slot = (slot + 1) & mask) {
      const uint32_t g = slot_face[slot];
      if (g == kNone) {
        slot_face[slot] = static_cast<uint32_t>(f);
        slot_hash[slot] = h;
        break;
      }
      if (slot_hash[slot] != h || mesh.face_size(g) != canon.size()) continue;
      bool rev_g = false;
      canonical_face(mesh.face_begin(g), mesh.face_size(g), other, rev_g);
      if (other == canon) {
        duplicate_of[f] = g;
        reversed_dup[f] = rev != rev_g;
        break;
      }
    }
  }
}

void UnionFind::reset(size_t n) {
  parent_.resize(n);
  for (size_t i = 0; i < n; ++i) parent_[i] = static_cast<uint32_t>(i);
  rank_.assign(n, 0);
}

bool UnionFind::unite(uint32_t x, uint32_t y) {
  x = find(x);
  y = find(y);
  if (x == y) return false;
  if (rank_[x] < rank_[y]) std::swap(x, y);
  parent_[y] = x;
  if (rank_[x] == rank_[y]) ++rank_[x];
  return true;
}

uint32_t EdgeMap::find_edge(uint32_t a, uint32_t b) const {
  if (a == b) return kNone;
  const uint32_t lo = std::min(a, b), hi = std::max(a, b);
  if (static_cast<size_t>(lo) + 1 >= vertex_first_edge.size()) return kNone;
  const auto first = edge_hi.begin() + vertex_first_edge[lo];
  const auto last = edge_hi.begin() + vertex_first_edge[lo + 1];
  const auto it = std::lower_bound(first, last, hi);
  return it != last && *it == hi ? static_cast<uint32_t>(it - edge_hi.begin()) : kNone;
}

void build_edge_map(EdgeMap& map, const PolygonMesh& mesh, const std::vector<uint8_t>& include) {
  map.mesh = &mesh;
  const size_t nf = mesh.num_faces(), nc = mesh.face_vertices.size(), nv = mesh.num_vertices();
  const auto& off = mesh.face_offsets;
  const auto& fv = mesh.face_vertices;
  map.corner_face.resize(nc);
  for (size_t f = 0; f < nf; ++f)
    std::fill(map.corner_face.begin() + off[f], map.corner_face.begin() + off[f + 1], static_cast<uint32_t>(f));
  map.corner_edge.assign(nc, kNone);

  // Counting sort of the included half-edges by their smaller endpoint.
  std::vector<uint32_t> start(nv + 1, 0);
  size_t included = 0;
  for (size_t f = 0; f < nf; ++f) {
    if (!include[f]) continue;
    const uint32_t b = off[f], e = off[f + 1];
    for (uint32_t c = b; c < e; ++c) {
      const uint32_t u = fv[c], w = fv[c + 1 == e ? b : c + 1];
      ++start[std::min(u, w) + 1];
    }
    included += e - b;
  }
  for (size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<uint64_t> keys(included);  // (other endpoint << 32) | corner
  {
    std::vector<uint32_t> pos(start.begin(), start.end() - 1);
    for (size_t f = 0; f < nf; ++f) {
      if (!include[f]) continue;
      const uint32_t b = off[f], e = off[f + 1];
      for (uint32_t c = b; c < e; ++c) {
        const uint32_t u = fv[c], w = fv[c + 1 == e ? b : c + 1];
        keys[pos[std::min(u, w)]++] = (static_cast<uint64_t>(std::max(u, w)) << 32) | c;
      }
    }
  }

  map.edge_lo.clear();
  map.edge_hi.clear();
  map.edge_offsets.assign(1, 0);
  map.edge_corners.resize(included);
  map.edge_lo.reserve(included / 2 + 1);
  map.edge_hi.reserve(included / 2 + 1);
  map.edge_offsets.reserve(included / 2 + 2);
  map.vertex_first_edge.assign(nv + 1, 0);
  size_t k = 0;
  for (size_t v = 0; v < nv; ++v) {
    map.vertex_first_edge[v] = static_cast<uint32_t>(map.edge_lo.size());
    uint64_t* b = keys.data() + start[v];
    uint64_t* e = keys.data() + start[v + 1];
    if (e - b < 2) {
      // nothing to sort (and b may be null when no face is included: no pointer arithmetic on it)
    } else if (e - b <= 16) {  // insertion sort: buckets are usually a handful of half-edges
      for (uint64_t* i = b + 1; i < e; ++i) {
        const uint64_t x = *i;
        uint64_t* j = i;
        for (; j > b && *(j - 1) > x; --j) *j = *(j - 1);
        *j = x;
      }
    } else {
      std::sort(b, e);
    }
    for (uint64_t* i = b; i < e;) {
      const uint32_t hi = static_cast<uint32_t>(*i >> 32);
      const uint32_t edge = static_cast<uint32_t>(map.edge_lo.size());
      map.edge_lo.push_back(static_cast<uint32_t>(v));
      map.edge_hi.push_back(hi);
      for (; i < e && static_cast<uint32_t>(*i >> 32) == hi; ++i) {
        const uint32_t c = static_cast<uint32_t>(*i);
        map.edge_corners[k++] = c;
        map.corner_edge[c] = edge;
      }
      map.edge_offsets.push_back(static_cast<uint32_t>(k));
    }
  }
  map.vertex_first_edge[nv] = static_cast<uint32_t>(map.edge_lo.size());
}

}  // namespace detail
CAGEKIT_NAMESPACE_END
