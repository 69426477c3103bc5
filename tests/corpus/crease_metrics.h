// SPDX-License-Identifier: GPL-3.0-or-later
// Crease figures of the corpus harness (issue 20): how well a cage's crease tags match the sharp
// features of the scan it was fitted to. Plain geometry on positions and faces (no SDK, no CGAL),
// so that test_crease_metrics can check it on meshes whose answer is known.
//
//  - sharp_input_edges: the scan's edges with exactly two faces whose unit normals make an angle
//    above a threshold (the harness uses 40 degrees), after welding exact duplicate positions.
//  - SegmentGrid: nearest-segment queries over a uniform grid (cell = the tolerance).
//  - match_length: the length of one set of segments lying within a tolerance of another,
//    sampled at spacing <= tolerance / 4 (each sample weighted by its share of the length).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <unordered_map>
#include <utility>
#include <vector>

namespace cagekit_corpus {

using Vec3 = std::array<double, 3>;

struct Segment {
  Vec3 a, b;
};

inline Vec3 sub(const Vec3& p, const Vec3& q) { return {p[0] - q[0], p[1] - q[1], p[2] - q[2]}; }
inline double dot(const Vec3& p, const Vec3& q) { return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]; }
inline double length(const Vec3& v) { return std::sqrt(dot(v, v)); }
// The point at parameter t of a segment (0: a, 1: b).
inline Vec3 point_at(const Segment& s, double t) {
  return {s.a[0] + t * (s.b[0] - s.a[0]), s.a[1] + t * (s.b[1] - s.a[1]), s.a[2] + t * (s.b[2] - s.a[2])};
}

inline double point_segment_distance(const Vec3& p, const Segment& s) {
  const Vec3 d = sub(s.b, s.a);
  const double dd = dot(d, d);
  double t = dd > 0.0 ? dot(sub(p, s.a), d) / dd : 0.0;
  t = std::min(1.0, std::max(0.0, t));
  return length(sub(p, point_at(s, t)));
}

// Edges of a polygon mesh (xyz: 3 per vertex; sizes: corners per face; indices: the corners)
// whose two faces bend by more than `angle_degrees`. Exact duplicate positions are welded first,
// so an STL or OFF triangle soup connects. Face normals are Newell normals (any polygon). An edge
// counts only with exactly two faces of non-zero area; when both faces run the edge in the same
// direction (inconsistent orientation), one normal is flipped, so the angle is the bend of the
// surface, not an orientation artefact. Faces with bad indices are skipped.
inline std::vector<Segment> sharp_input_edges(const std::vector<double>& xyz, const std::vector<uint32_t>& sizes,
                                              const std::vector<uint32_t>& indices, double angle_degrees) {
  const size_t vertex_count = xyz.size() / 3;
  auto position = [&](uint32_t v) {
    return Vec3{xyz[3 * size_t(v)], xyz[3 * size_t(v) + 1], xyz[3 * size_t(v) + 2]};
  };
  // Weld: every vertex maps to the first vertex with the same position.
  std::vector<uint32_t> weld(vertex_count);
  {
    std::map<Vec3, uint32_t> first;
    for (size_t v = 0; v < vertex_count; ++v) {
      const Vec3 p = position(uint32_t(v));
      const bool finite = std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
      weld[v] = finite ? first.emplace(p, uint32_t(v)).first->second : uint32_t(v);  // NaN: not comparable
    }
  }
  // Per undirected edge: up to two (unit normal, runs from the smaller vertex) incidences; more
  // than two marks it non-manifold.
  struct Incidence {
    Vec3 normal;
    bool forward;
  };
  struct EdgeFaces {
    Incidence side[2];
    int count = 0;
  };
  std::unordered_map<uint64_t, EdgeFaces> edges;
  size_t at = 0;
  for (const uint32_t n : sizes) {
    if (at + n > indices.size()) break;
    const uint32_t* f = indices.data() + at;
    at += n;
    bool ok = n >= 3;
    for (uint32_t i = 0; ok && i < n; ++i) ok = f[i] < vertex_count;
    if (!ok) continue;
    Vec3 normal = {0.0, 0.0, 0.0};  // Newell: twice the area vector
    for (uint32_t i = 0; i < n; ++i) {
      const Vec3 p = position(f[i]), q = position(f[(i + 1) % n]);
      normal[0] += (p[1] - q[1]) * (p[2] + q[2]);
      normal[1] += (p[2] - q[2]) * (p[0] + q[0]);
      normal[2] += (p[0] - q[0]) * (p[1] + q[1]);
    }
    const double area2 = length(normal);
    const bool flat = !(area2 > 0.0) || !std::isfinite(area2);
    if (!flat)
      for (double& c : normal) c /= area2;
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t u = weld[f[i]], w = weld[f[(i + 1) % n]];
      if (u == w) continue;
      EdgeFaces& e = edges[(uint64_t(std::min(u, w)) << 32) | std::max(u, w)];
      if (e.count < 2) e.side[e.count] = {flat ? Vec3{0.0, 0.0, 0.0} : normal, u < w};
      ++e.count;
    }
  }
  const double cos_limit = std::cos(angle_degrees * 3.14159265358979323846 / 180.0);
  std::vector<Segment> sharp;
  for (const auto& [key, e] : edges) {
    if (e.count != 2) continue;
    Vec3 n0 = e.side[0].normal, n1 = e.side[1].normal;
    if (length(n0) == 0.0 || length(n1) == 0.0) continue;  // a face of zero area has no normal
    if (e.side[0].forward == e.side[1].forward) n1 = {-n1[0], -n1[1], -n1[2]};
    if (dot(n0, n1) < cos_limit)
      sharp.push_back({position(uint32_t(key >> 32)), position(uint32_t(key & 0xffffffffu))});
  }
  return sharp;
}

// Segments in a uniform grid for "is any segment within `tolerance` of p?" queries. Each segment
// is registered in the cells of points sampled along it at spacing <= cell / 2, so every point of
// the segment is within cell / 4 of a registered sample; a query then scans the cells within
// tolerance + cell / 4 of p (with cell = tolerance: 5 x 5 x 5 cells) and tests exact distances.
class SegmentGrid {
 public:
  SegmentGrid(std::vector<Segment> segments, double tolerance)
      : segments_(std::move(segments)), tolerance_(tolerance), cell_(tolerance) {
    reach_ = int(std::ceil((tolerance_ + 0.25 * cell_) / cell_));
    for (uint32_t s = 0; s < segments_.size(); ++s) {
      const Segment& seg = segments_[s];
      const int steps = std::max(1, int(std::ceil(length(sub(seg.b, seg.a)) / (0.5 * cell_))));
      uint64_t last = ~uint64_t(0);
      for (int i = 0; i <= steps; ++i) {
        const uint64_t key = key_of(cell_of(point_at(seg, double(i) / steps)));
        if (key == last) continue;
        last = key;
        std::vector<uint32_t>& in = cells_[key];
        if (in.empty() || in.back() != s) in.push_back(s);
      }
    }
  }

  bool empty() const { return segments_.empty(); }

  bool within(const Vec3& p) const {
    const std::array<int64_t, 3> c = cell_of(p);
    for (int dx = -reach_; dx <= reach_; ++dx)
      for (int dy = -reach_; dy <= reach_; ++dy)
        for (int dz = -reach_; dz <= reach_; ++dz) {
          const auto it = cells_.find(key_of({c[0] + dx, c[1] + dy, c[2] + dz}));
          if (it == cells_.end()) continue;
          for (const uint32_t s : it->second)
            if (point_segment_distance(p, segments_[s]) <= tolerance_) return true;
        }
    return false;
  }

 private:
  std::array<int64_t, 3> cell_of(const Vec3& p) const {
    return {int64_t(std::floor(p[0] / cell_)), int64_t(std::floor(p[1] / cell_)), int64_t(std::floor(p[2] / cell_))};
  }
  // 21 bits per axis (wrapping): distinct cells may share a key, which only costs extra distance tests.
  static uint64_t key_of(const std::array<int64_t, 3>& c) {
    const uint64_t mask = (uint64_t(1) << 21) - 1;
    return (uint64_t(c[0]) & mask) | ((uint64_t(c[1]) & mask) << 21) | ((uint64_t(c[2]) & mask) << 42);
  }

  std::vector<Segment> segments_;
  double tolerance_, cell_;
  int reach_ = 1;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

struct MatchedLength {
  double total = 0.0;    // length of the measured segments
  double matched = 0.0;  // of it, the length whose samples lie within the tolerance of the other set
};

// Splits each segment into ceil(length / (tolerance / 4)) equal pieces (at least one) and counts
// the length of each piece whose midpoint is within the grid's tolerance of one of its segments.
inline MatchedLength match_length(const std::vector<Segment>& measured, const SegmentGrid& other, double tolerance) {
  MatchedLength m;
  const double spacing = 0.25 * tolerance;
  for (const Segment& s : measured) {
    const double len = length(sub(s.b, s.a));
    if (!(len > 0.0) || !std::isfinite(len)) continue;
    m.total += len;
    if (other.empty()) continue;
    const int pieces = std::max(1, int(std::ceil(len / spacing)));
    int hits = 0;
    for (int i = 0; i < pieces; ++i) {
      if (other.within(point_at(s, (i + 0.5) / pieces))) ++hits;
    }
    m.matched += len * hits / pieces;
  }
  return m;
}

// Precision and recall of crease segments against sharp input segments, tolerance absolute.
struct CreaseMatch {
  MatchedLength creases;  // crease length near a sharp input edge (precision = matched / total)
  MatchedLength sharp;    // sharp input length near a crease (recall = matched / total)
};

inline CreaseMatch match_creases(const std::vector<Segment>& creases, const std::vector<Segment>& sharp,
                                 double tolerance) {
  CreaseMatch r;
  if (!(tolerance > 0.0) || !std::isfinite(tolerance)) return r;
  r.creases = match_length(creases, SegmentGrid(sharp, tolerance), tolerance);
  r.sharp = match_length(sharp, SegmentGrid(creases, tolerance), tolerance);
  return r;
}

}  // namespace cagekit_corpus
