// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The per-face line-sample database of thesis §5.5.4 (spec thesis-ch4-6.md §1.3): every line is
// split at the input mesh edges, so each segment lies in one triangle; each face keeps a list of
// the segments inside it and each vertex the segments that touch it. Insertion is O(1).
// A query (p, r) conquers the "p-cell" around p's face depth-first and tests the cached
// segments of those faces exactly.
//
// Decision [J]: a neighbour face joins the p-cell when the shared edge is within r of p (the
// thesis: "at least one vertex within r"). The edge test also reaches segments in very large
// faces whose vertices are all farther than r, the pitfall the thesis solves by pre-splitting.
// The cell is rebuilt per query with a generation stamp (O(cell) per query); the thesis's
// incremental p-cell update between consecutive queries is not implemented. For locality the
// traversal runs on a copy of the adjacency whose faces ("slots") and vertices are numbered in
// Morton order of their positions; the walk, and so the order of the visits, is that of the
// input numbering (neighbours in corner order 0, 1, 2, depth first).
#include <cstdint>
#include <functional>
#include <vector>

#include "core/edge_map.h"
#include "core/polygon_mesh.h"

CAGEKIT_NAMESPACE_BEGIN

// Edge adjacency of an oriented 2-manifold triangle mesh (possibly with boundary), by corner:
// twin[c] is the corner of the neighbouring face whose half-edge runs the edge of corner c in
// the opposite direction, or detail::kNone on a boundary edge.
struct TriangleAdjacency {
  std::vector<uint32_t> twin;
  std::vector<uint32_t> vertex_corner;  // one corner at each vertex (a boundary one if any), or kNone
  std::vector<uint8_t> feature;         // per corner: the corner's edge is a feature edge
  // Throws Error(invalid_mesh) for non-triangles, invalid indices, non-finite positions, edges
  // with more than two faces or two faces running an edge in the same direction.
  // feature_corners: optional per-corner flags (either half-edge tags the edge).
  void build(const PolygonMesh& triangles, const std::vector<uint8_t>* feature_corners);
  static uint32_t next(uint32_t c) { return c % 3 == 2 ? c - 2 : c + 1; }
  static uint32_t prev(uint32_t c) { return c % 3 == 0 ? c + 2 : c - 1; }
};

enum class LineType : uint8_t { min_curvature = 0, max_curvature = 1, feature = 2, boundary = 3 };
inline bool is_curvature_line(LineType t) { return t == LineType::min_curvature || t == LineType::max_curvature; }
inline LineType opposite_type(LineType t) {
  return t == LineType::min_curvature ? LineType::max_curvature : LineType::min_curvature;
}

// One piece of a line inside one input triangle (for feature and boundary lines: one input
// edge, listed in both adjacent faces). vertex_a / vertex_b: the input vertex the end point
// coincides with, or kNone.
struct LineSegment {
  Vec3 a, b;
  uint32_t face = detail::kNone;
  uint32_t line = detail::kNone;
  uint32_t vertex_a = detail::kNone, vertex_b = detail::kNone;
  double arc = 0.0;       // arc length along its line at `a` (signed: < 0 on a backward pass)
  LineType type = LineType::min_curvature;
  bool trusted = true;    // integrated along the tensor field (false: trusted-direction bridge)
};

class LineSampleDatabase {
 public:
  // The mesh and adjacency must outlive the database and not change.
  LineSampleDatabase(const PolygonMesh& triangles, const TriangleAdjacency& adjacency);

  // Stores the segment and lists it in segment.face (and in `also_face` when not kNone, for
  // segments on an input edge) and at its end vertices. Returns its id.
  uint32_t insert(const LineSegment& segment, uint32_t also_face = detail::kNone);

  // Calls visit(id, distance) for every stored segment within distance r of p (p lies in
  // `face`), each once, over the p-cell of (face, p, r). visit returns false to stop early.
  // Returns the number of faces in the p-cell.
  size_t query(uint32_t face, const Vec3& p, double r, const std::function<bool(uint32_t, double)>& visit);
  // The same answer by scanning every segment (for tests): ids within r of p.
  std::vector<uint32_t> brute_force(const Vec3& p, double r) const;

  const LineSegment& segment(uint32_t id) const { return segments_[id]; }
  // For finishing a line (reversing a backward pass, closing a loop); the faces must not change.
  LineSegment& segment_for_update(uint32_t id) { return segments_[id]; }
  size_t num_segments() const { return segments_.size(); }
  const std::vector<LineSegment>& segments() const { return segments_; }
  // Segment ids listed in face f / at vertex v.
  template <class Fn>
  void for_each_in_face(uint32_t f, Fn&& fn) const {
    for (uint32_t n = slots_[slot_of_face_[f]].head; n != detail::kNone; n = nodes_[n].next) fn(nodes_[n].segment);
  }
  template <class Fn>
  void for_each_at_vertex(uint32_t v, Fn&& fn) const {
    for (uint32_t n = vertex_head_[v]; n != detail::kNone; n = nodes_[n].next) fn(nodes_[n].segment);
  }
  uint64_t queries() const { return queries_; }

 private:
  struct Node {
    uint32_t segment, next;
  };
  // One face of the traversal copy: the slots across its corners' edges (kNone on a boundary),
  // its corners' vertices (renumbered), its segment list and its generation stamp.
  struct Slot {
    uint32_t twin[3];
    uint32_t vertex[3];
    uint32_t head;
    uint32_t stamp;
  };
  void link(uint32_t& head, uint32_t segment);

  const PolygonMesh& mesh_;
  const TriangleAdjacency& adjacency_;
  std::vector<LineSegment> segments_;
  std::vector<Node> nodes_;
  std::vector<Slot> slots_;             // by slot
  std::vector<uint32_t> slot_of_face_;  // input face -> slot
  std::vector<Vec3> positions_;         // by renumbered vertex
  std::vector<uint32_t> vertex_head_;
  std::vector<uint32_t> segment_stamp_;
  std::vector<uint32_t> stack_;
  uint32_t generation_ = 0;
  uint64_t queries_ = 0;
};

CAGEKIT_NAMESPACE_END
