// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/line_sample_database.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/status.h"
#include "layout/triangle_mesh_input.h"

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

double point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double dd = dot(d, d);
  double t = dd > 0.0 ? dot(p - a, d) / dd : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return distance(p, a + t * d);
}

LineSampleDatabase::LineSampleDatabase(const PolygonMesh& mesh, const TriangleAdjacency& adjacency)
    : mesh_(mesh), adjacency_(adjacency) {
  face_head_.assign(mesh.num_faces(), detail::kNone);
  vertex_head_.assign(mesh.num_vertices(), detail::kNone);
  face_stamp_.assign(mesh.num_faces(), 0);
}

void LineSampleDatabase::link(std::vector<uint32_t>& head, uint32_t key, uint32_t segment) {
  nodes_.push_back({segment, head[key]});
  head[key] = uint32_t(nodes_.size() - 1);
}

uint32_t LineSampleDatabase::insert(const LineSegment& s, uint32_t also_face) {
  if (s.face >= face_head_.size() || (also_face != detail::kNone && also_face >= face_head_.size()))
    fail(Status::internal_error, "line-sample database: segment face out of range");
  if (segments_.size() >= 0xfffffff0u) fail(Status::limit_exceeded, "line-sample database: too many segments");
  const uint32_t id = uint32_t(segments_.size());
  segments_.push_back(s);
  segment_stamp_.push_back(0);
  link(face_head_, s.face, id);
  if (also_face != detail::kNone && also_face != s.face) link(face_head_, also_face, id);
  if (s.vertex_a != detail::kNone) link(vertex_head_, s.vertex_a, id);
  if (s.vertex_b != detail::kNone && s.vertex_b != s.vertex_a) link(vertex_head_, s.vertex_b, id);
  return id;
}

size_t LineSampleDatabase::query(uint32_t face, const Vec3& p, double r,
                                 const std::function<bool(uint32_t, double)>& visit) {
  ++queries_;
  if (face >= face_head_.size()) fail(Status::internal_error, "line-sample database: query face out of range");
  if (++generation_ == 0) {  // wrapped: clear the stamps once every 2^32 queries
    std::fill(face_stamp_.begin(), face_stamp_.end(), 0);
    std::fill(segment_stamp_.begin(), segment_stamp_.end(), 0);
    generation_ = 1;
  }
  size_t cell = 0;
  stack_.clear();
  stack_.push_back(face);
  face_stamp_[face] = generation_;
  while (!stack_.empty()) {
    const uint32_t f = stack_.back();
    stack_.pop_back();
    ++cell;
    for (uint32_t n = face_head_[f]; n != detail::kNone; n = nodes_[n].next) {
      const uint32_t id = nodes_[n].segment;
      if (segment_stamp_[id] == generation_) continue;
      segment_stamp_[id] = generation_;
      const double d = point_segment_distance(p, segments_[id].a, segments_[id].b);
      if (d <= r && !visit(id, d)) return cell;
    }
    for (uint32_t k = 0; k < 3; ++k) {
      const uint32_t c = 3 * f + k;
      const uint32_t t = adjacency_.twin[c];
      if (t == detail::kNone) continue;
      const uint32_t g = t / 3;
      if (face_stamp_[g] == generation_) continue;
      const Vec3& a = mesh_.positions[mesh_.face_vertices[c]];
      const Vec3& b = mesh_.positions[mesh_.face_vertices[TriangleAdjacency::next(c)]];
      if (point_segment_distance(p, a, b) > r) continue;
      face_stamp_[g] = generation_;
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
