// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/anisotropic/line_sample_database.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/status.h"
#include "layout/anisotropic/morton_order.h"
#include "layout/common/triangle_mesh_input.h"

CAGEKIT_NAMESPACE_BEGIN

void TriangleAdjacency::build(const PolygonMesh& mesh, const std::vector<uint8_t>* feature_corners) {
  require_triangle_mesh(mesh, "curvature-line sampling");
  if (feature_corners && feature_corners->size() != mesh.num_face_vertices())
    fail(Status::invalid_argument, "curvature-line sampling: feature flags must have one entry per face corner");
  detail::EdgeMap map;
  build_edge_map(map, mesh, std::vector<uint8_t>(mesh.num_faces(), 1));
  require_oriented_manifold_edges(map, "curvature-line sampling");
  const size_t nc = mesh.num_face_vertices();
  twin.assign(nc, detail::kNone);
  feature.assign(nc, 0);
  for (size_t e = 0; e < map.num_edges(); ++e) {
    const uint32_t* h = map.corners_begin(e);
    bool tagged = false;
    for (const uint32_t* it = h; it != map.corners_end(e); ++it)
      if (feature_corners && (*feature_corners)[*it]) tagged = true;
    for (const uint32_t* it = h; it != map.corners_end(e); ++it) feature[*it] = tagged;
    if (map.valence(e) == 2) {
      twin[h[0]] = h[1];
      twin[h[1]] = h[0];
    }
  }
  vertex_corner.assign(mesh.num_vertices(), detail::kNone);
  for (uint32_t c = 0; c < nc; ++c) {
    const uint32_t v = mesh.face_vertices[c];
    if (vertex_corner[v] == detail::kNone || twin[c] == detail::kNone) vertex_corner[v] = c;
  }
}

namespace {

// point_segment_distance (core/vec3.h) squared: the same arithmetic up to the square root, so
// sqrt of it is point_segment_distance's value bit for bit.
inline double point_segment_distance2(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 x = p - closest_point_on_segment(p, a, b);
  return dot(x, x);
}

}  // namespace

LineSampleDatabase::LineSampleDatabase(const PolygonMesh& mesh, const TriangleAdjacency& adjacency)
    : mesh_(mesh), adjacency_(adjacency) {
  const size_t nf = mesh.num_faces(), nv = mesh.num_vertices();
  vertex_head_.assign(nv, detail::kNone);
  // Traversal copy in Morton order (faces by centroid, vertices by position).
  const BoundingBox box = mesh.bounding_box();
  const std::vector<uint32_t> vertex_order = detail::morton_order(mesh.positions, box);
  std::vector<uint32_t> vertex_slot(nv);
  positions_.resize(nv);
  for (size_t i = 0; i < nv; ++i) {
    vertex_slot[vertex_order[i]] = uint32_t(i);
    positions_[i] = mesh.positions[vertex_order[i]];
  }
  std::vector<uint32_t> face_order;
  {
    std::vector<Vec3> centroid(nf);
    for (size_t f = 0; f < nf; ++f)
      centroid[f] = (1.0 / 3.0) * (mesh.positions[mesh.face_vertices[3 * f]] + mesh.positions[mesh.face_vertices[3 * f + 1]] +
                                   mesh.positions[mesh.face_vertices[3 * f + 2]]);
    face_order = detail::morton_order(centroid, box);
  }
  slot_of_face_.resize(nf);
  for (size_t i = 0; i < nf; ++i) slot_of_face_[face_order[i]] = uint32_t(i);
  slots_.resize(nf);
  for (size_t i = 0; i < nf; ++i) {
    const uint32_t f = face_order[i];
    Slot& sl = slots_[i];
    for (uint32_t k = 0; k < 3; ++k) {
      const uint32_t t = adjacency.twin[3 * f + k];
      sl.twin[k] = t == detail::kNone ? detail::kNone : slot_of_face_[t / 3];
      sl.vertex[k] = vertex_slot[mesh.face_vertices[3 * f + k]];
    }
    sl.head = detail::kNone;
    sl.stamp = 0;
  }
}

void LineSampleDatabase::link(uint32_t& head, uint32_t segment) {
  nodes_.push_back({segment, head});
  head = uint32_t(nodes_.size() - 1);
}

uint32_t LineSampleDatabase::insert(const LineSegment& s, uint32_t also_face) {
  if (s.face >= slots_.size() || (also_face != detail::kNone && also_face >= slots_.size()))
    fail(Status::internal_error, "line-sample database: segment face out of range");
  if (segments_.size() >= 0xfffffff0u) fail(Status::limit_exceeded, "line-sample database: too many segments");
  const uint32_t id = uint32_t(segments_.size());
  segments_.push_back(s);
  segment_stamp_.push_back(0);
  link(slots_[slot_of_face_[s.face]].head, id);
  if (also_face != detail::kNone && also_face != s.face) link(slots_[slot_of_face_[also_face]].head, id);
  if (s.vertex_a != detail::kNone) link(vertex_head_[s.vertex_a], id);
  if (s.vertex_b != detail::kNone && s.vertex_b != s.vertex_a) link(vertex_head_[s.vertex_b], id);
  return id;
}

size_t LineSampleDatabase::query(uint32_t face, const Vec3& p, double r,
                                 const std::function<bool(uint32_t, double)>& visit) {
  ++queries_;
  if (face >= slots_.size()) fail(Status::internal_error, "line-sample database: query face out of range");
  if (++generation_ == 0) {  // wrapped: clear the stamps once every 2^32 queries
    for (Slot& sl : slots_) sl.stamp = 0;
    std::fill(segment_stamp_.begin(), segment_stamp_.end(), 0);
    generation_ = 1;
  }
  // Distances are compared squared where that decides (sqrt is monotone and correctly rounded:
  // outside these relative margins of r² the comparison of sqrt(d2) with r cannot differ);
  // within them, and for every visit, the square root is taken as point_segment_distance does.
  const double r2 = r * r, r2_lo = r2 * (1.0 - 1e-9), r2_hi = r2 * (1.0 + 1e-9);
  auto beyond = [&](double d2) { return d2 > r2_hi || (d2 >= r2_lo && std::sqrt(d2) > r); };     // d > r
  auto within = [&](double d2) { return d2 < r2_lo || (d2 <= r2_hi && std::sqrt(d2) <= r); };  // d <= r
  size_t cell = 0;
  stack_.clear();
  const uint32_t start = slot_of_face_[face];
  stack_.push_back(start);
  slots_[start].stamp = generation_;
  while (!stack_.empty()) {
    const Slot& sl = slots_[stack_.back()];
    stack_.pop_back();
    ++cell;
    for (uint32_t n = sl.head; n != detail::kNone; n = nodes_[n].next) {
      const uint32_t id = nodes_[n].segment;
      if (segment_stamp_[id] == generation_) continue;
      segment_stamp_[id] = generation_;
      const double d2 = point_segment_distance2(p, segments_[id].a, segments_[id].b);
      if (!within(d2)) continue;
      if (!visit(id, std::sqrt(d2))) return cell;
    }
    for (uint32_t k = 0; k < 3; ++k) {
      const uint32_t g = sl.twin[k];
      if (g == detail::kNone) continue;
      Slot& sg = slots_[g];
      if (sg.stamp == generation_) continue;
      const Vec3& a = positions_[sl.vertex[k]];
      const Vec3& b = positions_[sl.vertex[k == 2 ? 0 : k + 1]];
      if (beyond(point_segment_distance2(p, a, b))) continue;
      sg.stamp = generation_;
      stack_.push_back(g);
    }
  }
  return cell;
}

std::vector<uint32_t> LineSampleDatabase::brute_force(const Vec3& p, double r) const {
  std::vector<uint32_t> out;
  for (uint32_t id = 0; id < segments_.size(); ++id)
    if (point_segment_distance(p, segments_[id].a, segments_[id].b) <= r) out.push_back(id);
  return out;
}

CAGEKIT_NAMESPACE_END
