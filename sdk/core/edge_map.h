// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Private helpers shared by validation, repair and statistics (not part of the public API):
// an undirected edge map over a selection of faces with half-edge adjacency, built once in
// O(n + V) with a counting sort on the smaller endpoint (plus tiny per-vertex sorts, so
// O(n log n) in the worst case), a union-find, and per-face predicates.
//
// Vocabulary: a "corner" is an index c into PolygonMesh::face_vertices; the half-edge of
// corner c goes from face_vertices[c] to the vertex of the next corner of the same face.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/polygon_mesh.h"

CAGEKIT_NAMESPACE_BEGIN
namespace detail {

constexpr uint32_t kNone = 0xffffffffu;

// Throws Error(Status::invalid_mesh) when face_offsets is not a valid offsets array for
// face_vertices (empty, first offset not 0, decreasing, or last offset != face_vertices.size()).
void check_mesh_arrays(const PolygonMesh& mesh);

// First vertex that occurs twice in v[0..n), or kNone.
uint32_t find_repeated_vertex(const uint32_t* v, uint32_t n);

// True when face f (all indices valid, all positions finite, >= 3 vertices) has a zero
// vector area relative to its size (|area| <= 1e-12 * (largest coordinate extent)^2).
// Faces whose extent overflows are never reported as zero-area.
bool face_has_zero_area(const PolygonMesh& mesh, size_t f);

// Canonical key of a face with distinct vertices for duplicate detection: the vertex cycle
// rotated to start at its smallest vertex and read in the direction of the smaller neighbour.
// `reversed` tells whether the face's own order is the opposite direction.
void canonical_face(const uint32_t* v, uint32_t n, std::vector<uint32_t>& out, bool& reversed);

// For every face with include[f] != 0 and a duplicate (same canonical cycle) among the
// included faces before it, duplicate_of[f] is that earlier face; otherwise kNone.
// reversed_dup[f] != 0 when the duplicate runs in the opposite direction.
void find_duplicate_faces(const PolygonMesh& mesh, const std::vector<uint8_t>& include,
                          std::vector<uint32_t>& duplicate_of, std::vector<uint8_t>& reversed_dup);

class UnionFind {
 public:
  UnionFind() = default;
  explicit UnionFind(size_t n) { reset(n); }
  void reset(size_t n);
  uint32_t find(uint32_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  // Returns true when x and y were in different sets.
  bool unite(uint32_t x, uint32_t y);

 private:
  std::vector<uint32_t> parent_;
  std::vector<uint8_t> rank_;
};

struct EdgeMap {
  const PolygonMesh* mesh = nullptr;
  std::vector<uint32_t> corner_face;     // face of every corner (all faces)
  std::vector<uint32_t> corner_edge;     // edge of each corner's half-edge; kNone if not included
  std::vector<uint32_t> edge_offsets{0}; // edge e owns edge_corners[edge_offsets[e]..[e+1])
  std::vector<uint32_t> edge_corners;    // half-edges grouped by edge, in face order per edge
  std::vector<uint32_t> edge_lo, edge_hi;  // endpoints, lo < hi
  std::vector<uint32_t> vertex_first_edge; // edges with edge_lo == v: [first[v], first[v+1])

  size_t num_edges() const { return edge_lo.size(); }
  uint32_t valence(size_t e) const { return edge_offsets[e + 1] - edge_offsets[e]; }
  const uint32_t* corners_begin(size_t e) const { return edge_corners.data() + edge_offsets[e]; }
  const uint32_t* corners_end(size_t e) const { return edge_corners.data() + edge_offsets[e + 1]; }

  uint32_t next_corner(uint32_t c) const {
    const uint32_t f = corner_face[c];
    return c + 1 == mesh->face_offsets[f + 1] ? mesh->face_offsets[f] : c + 1;
  }
  uint32_t prev_corner(uint32_t c) const {
    const uint32_t f = corner_face[c];
    return c == mesh->face_offsets[f] ? mesh->face_offsets[f + 1] - 1 : c - 1;
  }
  uint32_t from(uint32_t c) const { return mesh->face_vertices[c]; }
  uint32_t to(uint32_t c) const { return mesh->face_vertices[next_corner(c)]; }
  // True when the half-edge of corner c runs from the edge's lo endpoint to its hi endpoint.
  bool forward(uint32_t c) const { return from(c) < to(c); }
  // The corners of the half-edge's face that sit at the edge's lo / hi endpoint.
  uint32_t corner_at_lo(uint32_t c) const { return forward(c) ? c : next_corner(c); }
  uint32_t corner_at_hi(uint32_t c) const { return forward(c) ? next_corner(c) : c; }

  // Edge joining a and b (either order), or kNone.
  uint32_t find_edge(uint32_t a, uint32_t b) const;
};

// Builds the map over the faces with include[f] != 0. Those faces must have valid indices
// (< num_vertices), at least 3 vertices and no repeated vertex. The map keeps a pointer to
// `mesh`, which must outlive it and not change.
void build_edge_map(EdgeMap& map, const PolygonMesh& mesh, const std::vector<uint8_t>& include);

// Joins, at each vertex, the corners of the faces that share an edge there, over every edge
// for which glue(e) is true. Afterwards each union-find class of corners is one fan of faces.
template <class Glue>
void glue_fans(const EdgeMap& map, UnionFind& corners, Glue glue) {
  for (size_t e = 0; e < map.num_edges(); ++e) {
    if (map.valence(e) < 2 || !glue(e)) continue;
    const uint32_t* h = map.corners_begin(e);
    const uint32_t lo0 = map.corner_at_lo(h[0]), hi0 = map.corner_at_hi(h[0]);
    for (const uint32_t* it = h + 1; it != map.corners_end(e); ++it) {
      corners.unite(lo0, map.corner_at_lo(*it));
      corners.unite(hi0, map.corner_at_hi(*it));
    }
  }
}

}  // namespace detail
CAGEKIT_NAMESPACE_END
