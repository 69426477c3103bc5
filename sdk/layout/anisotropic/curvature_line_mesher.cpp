// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/anisotropic/curvature_line_mesher.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <unordered_map>
#include <unordered_set>

#include "core/edge_key.h"
#include "core/edge_map.h"
#include "core/mesh_repair.h"
#include "core/status.h"
#include "layout/anisotropic/local_unfolding.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

using detail::kNone;

struct Hit {
  double pos;     // segment index + parameter along the line
  uint32_t node;
};

struct GraphEdge {
  uint32_t a, b;       // output vertices, a -> b along the line
  uint32_t line;
  double pos_a, pos_b; // pos_b > pos_a (closed lines: pos_b may exceed the segment count)
  Vec3 dir_a, dir_b;   // tangents leaving a towards b and leaving b towards a
  bool boundary;
  bool alive = true;
};

class LineGraph {
 public:
  LineGraph(const LineSampling& s, const LineMeshOptions& o) : s_(s), db_(*s.database), o_(o) {}

  void build(const PolygonMesh& mesh, const CurvatureField& field, const TaskMonitor& monitor, LineMesh& out);
  void trace(LineMesh& out, std::vector<std::vector<uint32_t>>& faces);

  std::vector<Vec3> position, normal;  // per output vertex (merged intersections)
  std::vector<uint32_t> face;          // an input triangle the vertex lies on
  std::vector<GraphEdge> edges;

 private:
  Vec3 point_at(uint32_t line, double pos) const;
  Vec3 tangent(uint32_t line, const Vec3& p, double from, double to) const;
  void add_hit(uint32_t line, double pos, uint32_t node) { hits_[line].push_back({pos, node}); }
  Vec3 edge_normal(const PolygonMesh& mesh, uint32_t f, uint32_t va, uint32_t vb, const Vec3& fn) const {
    for (uint32_t k = 0; k < 3; ++k) {
      const uint32_t c = 3 * f + k;
      const uint32_t a = mesh.face_vertices[c], b = mesh.face_vertices[TriangleAdjacency::next(c)];
      if (!((a == va && b == vb) || (a == vb && b == va))) continue;
      const uint32_t t = s_.adjacency->twin[c];
      if (t == kNone) return fn;
      return normalized(fn + face_frame(mesh, t / 3).n);
    }
    return fn;
  }
  void remove_dangling(LineMesh& out);
  bool trace_pass(std::vector<std::vector<uint32_t>>& faces, std::vector<uint8_t>& failed, bool split_repeated);
  bool bridge_annulus(const std::vector<uint32_t>& inner, std::vector<std::vector<uint32_t>>& faces) const;
  size_t unfold(const std::vector<const std::vector<uint32_t>*>& folds, const std::vector<std::vector<uint32_t>>& faces);
  std::vector<std::vector<uint32_t>> inner_loops_;  // rejected clockwise cycles without repeats (last pass)

  const LineSampling& s_;
  const LineSampleDatabase& db_;
  const LineMeshOptions& o_;
  std::vector<std::vector<Hit>> hits_;
};

Vec3 LineGraph::point_at(uint32_t line, double pos) const {
  const auto& segs = s_.lines[line].segments;
  const double n = double(segs.size());
  if (s_.lines[line].closed) pos = std::fmod(std::fmod(pos, n) + n, n);
  pos = std::clamp(pos, 0.0, n);
  size_t k = size_t(pos);
  if (k >= segs.size()) k = segs.size() - 1;
  const LineSegment& sg = db_.segment(segs[k]);
  return sg.a + (pos - double(k)) * (sg.b - sg.a);
}

// Direction in which the line leaves the output vertex at `p` (the merged intersection at line
// position `from`) towards position `to`: the chord from p to the first polyline point at least
// a quarter of the edge's chord away, so the angular order at merged vertices matches the edges.
Vec3 LineGraph::tangent(uint32_t line, const Vec3& p, double from, double to) const {
  const Vec3 q = point_at(line, to);
  const double want = 0.25 * distance(p, q);
  const double dir = to > from ? 1.0 : -1.0;
  double pos = dir > 0 ? std::floor(from) + 1.0 : std::ceil(from) - 1.0;
  for (int guard = 0; guard < 1000000 && (pos - to) * dir < 0.0; ++guard, pos += dir)
    if (distance(point_at(line, pos), p) >= want) return point_at(line, pos) - p;
  return q - p;
}

void LineGraph::build(const PolygonMesh& mesh, const CurvatureField& field, const TaskMonitor& monitor, LineMesh& out) {
  const size_t nl = s_.lines.size();
  hits_.assign(nl, {});
  std::vector<uint32_t> seg_line(db_.num_segments(), kNone), seg_index(db_.num_segments(), 0);
  for (uint32_t l = 0; l < nl; ++l)
    for (uint32_t k = 0; k < s_.lines[l].segments.size(); ++k) {
      seg_line[s_.lines[l].segments[k]] = l;
      seg_index[s_.lines[l].segments[k]] = k;
    }
  std::vector<Vec3> node_p, node_n;
  std::vector<uint32_t> node_f;
  // Intersections inside faces.
  std::vector<uint32_t> ids;
  std::vector<Vec2> a2, b2;
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    if (f % 65536 == 0) monitor.report("meshing: intersections", 0.5 * double(f) / double(mesh.num_faces()));
    ids.clear();
    db_.for_each_in_face(f, [&](uint32_t id) {
      if (seg_line[id] != kNone) ids.push_back(id);
    });
    if (ids.size() < 2) continue;
    const FaceFrame fr = face_frame(mesh, f);
    const bool confident = field.face_confidence[f] >= o_.confidence_threshold;
    a2.resize(ids.size());
    b2.resize(ids.size());
    for (size_t i = 0; i < ids.size(); ++i) {
      const LineSegment& sg = db_.segment(ids[i]);
      a2[i] = {dot(sg.a - fr.origin, fr.u), dot(sg.a - fr.origin, fr.v)};
      b2[i] = {dot(sg.b - fr.origin, fr.u), dot(sg.b - fr.origin, fr.v)};
    }
    for (size_t i = 0; i < ids.size(); ++i)
      for (size_t j = i + 1; j < ids.size(); ++j) {
        const LineSegment &si = db_.segment(ids[i]), &sj = db_.segment(ids[j]);
        if (seg_line[ids[i]] == seg_line[ids[j]]) continue;
        const bool ci = is_curvature_line(si.type), cj = is_curvature_line(sj.type);
        if (!ci && !cj) continue;  // feature/boundary lines meet at input vertices
        if (confident && ci && cj && si.type == sj.type && si.trusted && sj.trusted) continue;
        const Vec2 di = b2[i] - a2[i], dj = b2[j] - a2[j];
        const double den = cross(di, dj);
        if (!(std::fabs(den) > 1e-12 * norm(di) * norm(dj))) continue;  // parallel
        const double t = cross(a2[j] - a2[i], dj) / den, u = cross(a2[j] - a2[i], di) / den;
        const double tol = 1e-9;
        if (t < -tol || t > 1 + tol || u < -tol || u > 1 + tol) continue;
        const double tc = std::clamp(t, 0.0, 1.0), uc = std::clamp(u, 0.0, 1.0);
        const uint32_t node = uint32_t(node_p.size());
        node_p.push_back(si.a + tc * (si.b - si.a));
        // On a crease or boundary line: the mean of the two faces' normals (one at a boundary).
        const LineSegment& edge_seg = !ci ? si : (!cj ? sj : si);
        node_n.push_back(ci && cj ? fr.n : edge_normal(mesh, f, edge_seg.vertex_a, edge_seg.vertex_b, fr.n));
        node_f.push_back(f);
        add_hit(seg_line[ids[i]], seg_index[ids[i]] + tc, node);
        add_hit(seg_line[ids[j]], seg_index[ids[j]] + uc, node);
      }
  }
  // Intersections at input vertices: every line listed there meets the others.
  std::vector<std::pair<uint32_t, double>> at;
  for (uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    at.clear();
    db_.for_each_at_vertex(v, [&](uint32_t id) {
      const uint32_t l = seg_line[id];
      if (l == kNone) return;
      double pos = double(seg_index[id]) + (db_.segment(id).vertex_a == v ? 0.0 : 1.0);
      if (s_.lines[l].closed && pos >= double(s_.lines[l].segments.size())) pos = 0.0;
      for (const auto& e : at)
        if (e.first == l) return;
      at.push_back({l, pos});
    });
    if (at.size() < 2) continue;
    const uint32_t node = uint32_t(node_p.size());
    node_p.push_back(mesh.positions[v]);
    node_n.push_back(field.vertex_normal[v]);
    node_f.push_back(s_.adjacency->vertex_corner[v] / 3);
    for (const auto& e : at) add_hit(e.first, e.second, node);
  }
  out.intersections = node_p.size();
  // Merge intersections closer than the merge distance (spatial hash, cell = distance).
  const double delta = std::max(o_.merge_distance * s_.min_spacing, 1e-12 * s_.bbox_diagonal);
  detail::UnionFind uf(node_p.size());
  std::unordered_map<uint64_t, std::vector<uint32_t>> grid;
  auto key = [&](long long x, long long y, long long z) {
    return (uint64_t(x & 0x1fffff) << 42) | (uint64_t(y & 0x1fffff) << 21) | uint64_t(z & 0x1fffff);
  };
  for (uint32_t i = 0; i < node_p.size(); ++i) {
    const long long x = (long long)std::floor(node_p[i].x / delta), y = (long long)std::floor(node_p[i].y / delta),
                    z = (long long)std::floor(node_p[i].z / delta);
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy)
        for (long long dz = -1; dz <= 1; ++dz) {
          auto it = grid.find(key(x + dx, y + dy, z + dz));
          if (it == grid.end()) continue;
          for (uint32_t j : it->second)
            if (distance(node_p[i], node_p[j]) < delta) uf.unite(i, j);
        }
    grid[key(x, y, z)].push_back(i);
  }
  std::vector<uint32_t> vertex_of(node_p.size(), kNone);
  for (uint32_t i = 0; i < node_p.size(); ++i) {
    const uint32_t r = uf.find(i);
    if (vertex_of[r] == kNone) {
      vertex_of[r] = uint32_t(position.size());
      position.push_back(node_p[r]);
      normal.push_back(node_n[r]);
      face.push_back(node_f[r]);
    }
    vertex_of[i] = vertex_of[r];
  }
  out.merged_vertices = node_p.size() - position.size();
  // Edges between consecutive intersections along each line.
  std::unordered_set<uint64_t> seen;
  for (uint32_t l = 0; l < nl; ++l) {
    auto& h = hits_[l];
    std::sort(h.begin(), h.end(), [](const Hit& x, const Hit& y) { return x.pos < y.pos; });
    std::vector<std::pair<double, uint32_t>> seq;
    for (const Hit& x : h) {
      const uint32_t v = vertex_of[x.node];
      if (seq.empty() || seq.back().second != v) seq.push_back({x.pos, v});
    }
    const bool closed = s_.lines[l].closed;
    if (closed && seq.size() > 1 && seq.front().second == seq.back().second) seq.pop_back();
    const size_t m = seq.size();
    const size_t count = closed ? (m > 2 ? m : 0) : (m > 0 ? m - 1 : 0);
    const double n_seg = double(s_.lines[l].segments.size());
    for (size_t k = 0; k < count; ++k) {
      const auto& [pa, va] = seq[k];
      double pb = seq[(k + 1) % m].first;
      const uint32_t vb = seq[(k + 1) % m].second;
      if (pb <= pa) pb += n_seg;  // wraps around a closed line
      const uint64_t kk = edge_key(va, vb);
      if (va == vb || !seen.insert(kk).second) continue;
      GraphEdge e{va, vb, l, pa, pb, tangent(l, position[va], pa, pb), tangent(l, position[vb], pb, pa),
                  s_.lines[l].type == LineType::boundary};
      edges.push_back(e);
    }
  }
  remove_dangling(out);
}

void LineGraph::remove_dangling(LineMesh& out) {
  std::vector<uint32_t> degree(position.size(), 0);
  std::vector<std::vector<uint32_t>> inc(position.size());
  for (uint32_t e = 0; e < edges.size(); ++e) {
    if (!edges[e].alive) continue;
    ++degree[edges[e].a];
    ++degree[edges[e].b];
    inc[edges[e].a].push_back(e);
    inc[edges[e].b].push_back(e);
  }
  std::vector<uint32_t> queue;
  for (uint32_t v = 0; v < position.size(); ++v)
    if (degree[v] == 1) queue.push_back(v);
  while (!queue.empty()) {
    const uint32_t v = queue.back();
    queue.pop_back();
    for (uint32_t e : inc[v]) {
      if (!edges[e].alive) continue;
      edges[e].alive = false;
      ++out.dangling_edges_removed;
      const uint32_t w = edges[e].a == v ? edges[e].b : edges[e].a;
      --degree[v];
      if (--degree[w] == 1) queue.push_back(w);
    }
  }
}

// One pass of face tracing over the alive edges. failed[h] is set for the half-edges of
// rejected cycles. Returns true when every cycle was accepted.
bool LineGraph::trace_pass(std::vector<std::vector<uint32_t>>& faces, std::vector<uint8_t>& failed,
                           bool split_repeated) {
  const uint32_t nh = uint32_t(2 * edges.size());
  // Outgoing half-edges per vertex, counter-clockwise about the vertex normal.
  std::vector<std::vector<std::pair<double, uint32_t>>> star(position.size());
  for (uint32_t e = 0; e < edges.size(); ++e) {
    if (!edges[e].alive) continue;
    star[edges[e].a].push_back({0.0, 2 * e});
    star[edges[e].b].push_back({0.0, 2 * e + 1});
  }
  std::vector<uint32_t> rank(nh, kNone), origin(nh, kNone);
  for (uint32_t v = 0; v < position.size(); ++v) {
    if (star[v].empty()) continue;
    const Vec3 n = normalized(normal[v]);
    Vec3 b1 = std::fabs(n.x) < 0.9 ? cross(n, Vec3{1, 0, 0}) : cross(n, Vec3{0, 1, 0});
    b1 = normalized(b1);
    const Vec3 b2 = cross(n, b1);
    for (auto& [angle, h] : star[v]) {
      const Vec3 d = (h & 1) ? edges[h / 2].dir_b : edges[h / 2].dir_a;
      angle = std::atan2(dot(d, b2), dot(d, b1));
    }
    std::sort(star[v].begin(), star[v].end());
    for (uint32_t k = 0; k < star[v].size(); ++k) {
      rank[star[v][k].second] = k;
      origin[star[v][k].second] = v;
    }
  }
  auto next = [&](uint32_t h) {
    const uint32_t twin = h ^ 1u;  // outgoing at h's head
    const auto& s = star[origin[twin]];
    return s[(rank[twin] + s.size() - 1) % s.size()].second;
  };
  std::vector<uint8_t> visited(nh, 0);
  bool all_ok = true;
  std::vector<uint32_t> cycle, loop, stack;
  std::vector<std::vector<uint32_t>> sub_cycles;
  std::unordered_map<uint32_t, size_t> first_at;
  for (uint32_t h0 = 0; h0 < nh; ++h0) {
    if (!edges[h0 / 2].alive || visited[h0]) continue;
    cycle.clear();
    bool outside = false;
    for (uint32_t h = h0, guard = 0; guard <= nh; ++guard) {
      visited[h] = 1;
      cycle.push_back(h);
      if (edges[h / 2].boundary && (h & 1)) outside = true;  // against the boundary line: outside
      h = next(h);
      if (h == h0) break;
    }
    if (outside) continue;
    // A cycle through a vertex twice (two regions touching there) is split into simple loops.
    sub_cycles.clear();
    stack.clear();
    first_at.clear();
    for (uint32_t h : cycle) {
      const uint32_t v = origin[h];
      auto it = first_at.find(v);
      if (it != first_at.end() && !split_repeated) {  // rejected whole: mark it and go on
        stack.clear();
        break;
      }
      if (it != first_at.end()) {
        const size_t i = it->second;
        sub_cycles.emplace_back(stack.begin() + long(i), stack.end());
        for (size_t k = i; k < stack.size(); ++k) first_at.erase(origin[stack[k]]);
        stack.resize(i);
      }
      first_at[v] = stack.size();
      stack.push_back(h);
    }
    if (stack.empty()) {
      for (uint32_t h : cycle) failed[h] = 1;
      all_ok = false;
      continue;
    }
    sub_cycles.push_back(stack);
    for (const auto& sub : sub_cycles) {
      loop.clear();
      for (uint32_t h : sub) loop.push_back(origin[h]);
      Vec3 area{}, nsum{};
      for (size_t k = 0; k < loop.size(); ++k) {
        area = area + cross(position[loop[k]], position[loop[(k + 1) % loop.size()]]);
        nsum = nsum + normalized(normal[loop[k]]);
      }
      if (loop.size() < 3 || !(dot(area, nsum) > 0.0)) {
        if (loop.size() >= 3) inner_loops_.push_back(loop);
        for (uint32_t h : sub) failed[h] = 1;
        all_ok = false;
        continue;
      }
      faces.push_back(loop);
    }
  }
  return all_ok;
}

void LineGraph::trace(LineMesh& out, std::vector<std::vector<uint32_t>>& faces) {
  std::vector<uint8_t> failed(2 * edges.size(), 0);
  // While cycles are rejected: delete the edges whose two half-edges both lie on rejected cycles
  // and trace again (the thesis does this once; up to 4 rounds here [J]).
  for (int round = 0; round < 5; ++round) {
    faces.clear();
    inner_loops_.clear();
    std::fill(failed.begin(), failed.end(), 0);
    if (trace_pass(faces, failed, false)) return;
    if (round == 4) break;
    size_t removed = 0;
    for (uint32_t e = 0; e < edges.size(); ++e)
      if (edges[e].alive && failed[2 * e] && failed[2 * e + 1]) {
        edges[e].alive = false;
        ++removed;
      }
    out.inconsistent_edges_removed += removed;
    if (removed == 0) break;
    remove_dangling(out);
  }
  // Last pass [J]: cycles through a vertex twice are split there into simple loops; clockwise
  // loops left are inner boundaries of annular regions (a band no line crosses, e.g. around a
  // crease loop): each is bridged to the face around it. A clockwise loop that no face contains
  // is a fold (lines crossing in an order their end tangents get wrong, e.g. a small inverted
  // triangle): one of its edges is deleted, merging it into the face across, and the pass
  // repeats (up to 4 rounds).
  size_t bridged = 0;
  for (int round = 0;; ++round) {
    faces.clear();
    inner_loops_.clear();
    std::fill(failed.begin(), failed.end(), 0);
    trace_pass(faces, failed, true);
    bridged = 0;
    out.bridged_loops = 0;
    std::vector<const std::vector<uint32_t>*> folds;
    for (const auto& inner : inner_loops_)
      if (bridge_annulus(inner, faces)) {
        bridged += inner.size();
        ++out.bridged_loops;
      } else {
        folds.push_back(&inner);
      }
    if (folds.empty() || round == 4) break;
    const size_t removed = unfold(folds, faces);
    if (removed == 0) break;
    out.fold_edges_removed += removed;
    remove_dangling(out);
  }
  for (uint32_t h = 0; h < failed.size(); ++h)
    if (failed[h] && edges[h / 2].alive) ++out.unclosed_half_edges;
  out.unclosed_half_edges -= std::min(out.unclosed_half_edges, bridged);
}

// For each fold (a clockwise simple loop, vertices in loop order), deletes the one edge whose
// removal merges it with the accepted face across into a counter-clockwise cycle (vector area
// against the summed vertex normals), choosing the smallest such face; boundary and feature
// lines are kept. An island (the loop's other side is the loop itself: a closed chain connected
// to nothing else) is deleted whole. Returns the number of edges deleted.
size_t LineGraph::unfold(const std::vector<const std::vector<uint32_t>*>& folds,
                         const std::vector<std::vector<uint32_t>>& faces) {
  std::unordered_map<uint64_t, uint32_t> edge_of;
  for (uint32_t e = 0; e < edges.size(); ++e)
    if (edges[e].alive) edge_of[edge_key(edges[e].a, edges[e].b)] = e;
  std::unordered_map<uint64_t, uint32_t> face_of;  // directed (a, b) -> face
  for (uint32_t f = 0; f < faces.size(); ++f)
    for (size_t k = 0; k < faces[f].size(); ++k) face_of[directed_edge_key(faces[f][k], faces[f][(k + 1) % faces[f].size()])] = f;
  auto vector_area = [&](const std::vector<uint32_t>& loop, Vec3& area, Vec3& nsum) {
    for (size_t k = 0; k < loop.size(); ++k) {
      area = area + cross(position[loop[k]], position[loop[(k + 1) % loop.size()]]);
      nsum = nsum + normalized(normal[loop[k]]);
    }
  };
  size_t removed = 0;
  for (const std::vector<uint32_t>* fold : folds) {
    const std::vector<uint32_t>& loop = *fold;
    Vec3 loop_area{}, loop_n{};
    vector_area(loop, loop_area, loop_n);
    uint32_t best = kNone;
    size_t best_size = SIZE_MAX;
    bool island = true;  // the face across every edge is the loop itself, reversed
    std::vector<uint32_t> loop_edges;
    for (size_t k = 0; k < loop.size(); ++k) {
      const uint32_t a = loop[k], b = loop[(k + 1) % loop.size()];
      const auto e = edge_of.find(edge_key(a, b));
      const auto f = face_of.find(directed_edge_key(b, a));
      if (e != edge_of.end()) loop_edges.push_back(e->second);
      island &= f != face_of.end() && faces[f->second].size() == loop.size() &&
                std::all_of(loop.begin(), loop.end(), [&](uint32_t v) {
                  return std::find(faces[f->second].begin(), faces[f->second].end(), v) != faces[f->second].end();
                });
      if (e == edge_of.end() || f == face_of.end() || !edges[e->second].alive) continue;
      const GraphEdge& g = edges[e->second];
      if (g.boundary || s_.lines[g.line].type == LineType::feature) continue;
      Vec3 area = loop_area, n = loop_n;
      vector_area(faces[f->second], area, n);
      if (!(dot(area, n) > 0.0) || faces[f->second].size() >= best_size) continue;
      best = e->second;
      best_size = faces[f->second].size();
    }
    if (island && loop_edges.size() == loop.size()) {
      // A closed chain of lines that no other line crosses and no face around it could be bridged
      // to (e.g. a small triangle of a feature fragment and two line ends): dropped, the face
      // around it covers its place.
      for (uint32_t e : loop_edges) edges[e].alive = false;
      removed += loop_edges.size();
      continue;
    }
    if (best == kNone) continue;
    edges[best].alive = false;
    ++removed;
  }
  return removed;
}

// The annulus between a face O and a clockwise loop C inside it (both with the region on their
// left) becomes two faces through two bridges: from the closest pair of vertices c-x, and from
// the vertex c2 of C half-way round to its closest vertex x2 != x of O. O is the smallest face
// whose polygon, projected along its normal, contains C's centroid.
bool LineGraph::bridge_annulus(const std::vector<uint32_t>& inner, std::vector<std::vector<uint32_t>>& faces) const {
  Vec3 centroid{};
  for (uint32_t v : inner) centroid = centroid + position[v];
  centroid = (1.0 / double(inner.size())) * centroid;
  size_t best = faces.size();
  double best_area = 1e300;
  for (size_t f = 0; f < faces.size(); ++f) {
    const auto& o = faces[f];
    Vec3 area{};
    for (size_t k = 0; k < o.size(); ++k) area = area + cross(position[o[k]], position[o[(k + 1) % o.size()]]);
    const double a = norm(area);
    if (!(a > 0.0) || 0.5 * a >= best_area) continue;
    const Vec3 n = (1.0 / a) * area;
    Vec3 b1 = std::fabs(n.x) < 0.9 ? cross(n, Vec3{1, 0, 0}) : cross(n, Vec3{0, 1, 0});
    b1 = normalized(b1);
    const Vec3 b2 = cross(n, b1);
    double winding = 0.0;
    for (size_t k = 0; k < o.size(); ++k) {
      const Vec3 p = position[o[k]] - centroid, q = position[o[(k + 1) % o.size()]] - centroid;
      const Vec2 p2{dot(p, b1), dot(p, b2)}, q2{dot(q, b1), dot(q, b2)};
      winding += std::atan2(cross(p2, q2), dot(p2, q2));
    }
    if (std::fabs(winding) < 3.14159) continue;  // centroid outside
    // ... and near the face's plane (not a face on another part of the model seen through it).
    if (std::fabs(dot(centroid - position[o[0]], n)) > 0.5 * std::sqrt(0.5 * a)) continue;
    bool shares = false;  // C must not touch O
    for (uint32_t v : inner) shares |= std::find(o.begin(), o.end(), v) != o.end();
    if (shares) continue;
    best = f;
    best_area = 0.5 * a;
  }
  if (best == faces.size()) return false;
  const std::vector<uint32_t> o = faces[best];
  size_t ic = 0, ix = 0;
  double d_best = 1e300;
  for (size_t i = 0; i < inner.size(); ++i)
    for (size_t j = 0; j < o.size(); ++j) {
      const double d = distance(position[inner[i]], position[o[j]]);
      if (d < d_best) {
        d_best = d;
        ic = i;
        ix = j;
      }
    }
  const size_t ic2 = (ic + inner.size() / 2) % inner.size();
  size_t ix2 = o.size();
  d_best = 1e300;
  for (size_t j = 0; j < o.size(); ++j) {
    if (j == ix) continue;
    const double d = distance(position[inner[ic2]], position[o[j]]);
    if (d < d_best) {
      d_best = d;
      ix2 = j;
    }
  }
  if (ix2 == o.size() || ic2 == ic) return false;
  // Bridges no longer than the largest line spacing: the loops must be neighbours.
  if (distance(position[inner[ic]], position[o[ix]]) > s_.max_spacing ||
      distance(position[inner[ic2]], position[o[ix2]]) > s_.max_spacing)
    return false;
  auto walk = [](const std::vector<uint32_t>& loop, size_t from, size_t to, std::vector<uint32_t>& out) {
    for (size_t k = from;; k = (k + 1) % loop.size()) {
      out.push_back(loop[k]);
      if (k == to) break;
    }
  };
  std::vector<uint32_t> a, b;
  walk(o, ix, ix2, a);       // O from x to x2, then C from c2 to c
  walk(inner, ic2, ic, a);
  walk(o, ix2, ix, b);       // O from x2 to x, then C from c to c2
  walk(inner, ic, ic2, b);
  faces[best] = std::move(a);
  faces.push_back(std::move(b));
  return true;
}


// Vertices where two fans of faces touch (a pinch between two faces that share only a vertex)
// are split into one copy per fan (core repair), so the output is a 2-manifold; the per-vertex
// data and the line edges follow the copies.
void split_pinched_vertices(LineMesh& out) {
  const size_t before = out.mesh.num_vertices();
  RepairOptions ro;
  ro.weld_tolerance = -1.0;
  ro.drop_invalid_faces = false;
  ro.drop_degenerate_faces = false;
  ro.drop_duplicate_faces = true;
  ro.split_non_manifold = true;
  ro.orient_consistently = false;
  RepairReport report;
  PolygonMesh repaired = repair_mesh(out.mesh, ro, &report);
  if (report.split_vertices == 0 && report.dropped_duplicate_faces == 0) return;
  std::unordered_map<uint64_t, uint32_t> by_position;
  auto key = [](const Vec3& p) {
    uint64_t h = 1469598103934665603ull;
    for (double c : {p.x, p.y, p.z}) {
      uint64_t b;
      std::memcpy(&b, &c, sizeof b);
      h = (h ^ b) * 1099511628211ull;
    }
    return h;
  };
  for (uint32_t v = 0; v < before; ++v) by_position.emplace(key(out.mesh.positions[v]), v);
  std::vector<uint32_t> original(repaired.num_vertices());
  for (uint32_t v = 0; v < repaired.num_vertices(); ++v) {
    if (v < before) {
      original[v] = v;
      continue;
    }
    auto it = by_position.find(key(repaired.positions[v]));
    original[v] = it == by_position.end() ? 0 : it->second;
    out.vertex_normals.push_back(out.vertex_normals[original[v]]);
    out.vertex_face.push_back(out.vertex_face[original[v]]);
  }
  std::unordered_map<uint64_t, std::vector<std::pair<uint32_t, uint32_t>>> copies;  // original edge -> edges
  for (size_t f = 0; f < repaired.num_faces(); ++f)
    for (uint32_t k = 0, n = repaired.face_size(f); k < n; ++k) {
      const uint32_t a = repaired.face_vertex(f, k), b = repaired.face_vertex(f, (k + 1) % n);
      auto& list = copies[edge_key(original[a], original[b])];
      if (std::find(list.begin(), list.end(), std::make_pair(std::min(a, b), std::max(a, b))) == list.end())
        list.push_back({std::min(a, b), std::max(a, b)});
    }
  std::vector<LineMesh::Edge> edges;
  for (const LineMesh::Edge& e : out.edges) {
    auto it = copies.find(edge_key(e.a, e.b));
    if (it == copies.end()) continue;
    for (const auto& [a, b] : it->second) edges.push_back({a, b, e.type});
  }
  out.edges.swap(edges);
  out.mesh = std::move(repaired);
}

}  // namespace

LineMesh mesh_curvature_lines(const PolygonMesh& mesh, const CurvatureField& field, const LineSampling& sampling,
                              const LineMeshOptions& options, const TaskMonitor& monitor) {
  const auto t0 = std::chrono::steady_clock::now();
  if (options.max_face_valence < 3 || !(options.merge_distance >= 0.0) || !std::isfinite(options.merge_distance))
    fail(Status::invalid_argument, "curvature-line meshing: max_face_valence must be >= 3 and merge_distance >= 0");
  if (!sampling.database || !sampling.adjacency || sampling.adjacency->twin.size() != mesh.num_face_vertices() ||
      field.face_confidence.size() != mesh.num_faces() || field.vertex_normal.size() != mesh.num_vertices())
    fail(Status::invalid_argument, "curvature-line meshing: the sampling or field belongs to another mesh");
  LineMesh out;
  LineGraph graph(sampling, options);
  graph.build(mesh, field, monitor, out);
  monitor.report("meshing: faces", 0.6);
  std::vector<std::vector<uint32_t>> loops, faces;
  graph.trace(out, loops);
  monitor.report("meshing: convex partition", 0.8);
  std::unordered_set<uint64_t> existing;
  for (const auto& loop : loops)
    for (size_t k = 0; k < loop.size(); ++k) existing.insert(edge_key(loop[k], loop[(k + 1) % loop.size()]));
  for (const auto& loop : loops)
    partition_face(graph.position, graph.normal, loop, options.max_face_valence, faces, out.partition, &existing);
  // Compact the vertices used by faces.
  std::vector<uint32_t> remap(graph.position.size(), kNone);
  for (auto& f : faces)
    for (uint32_t& v : f) {
      if (remap[v] == kNone) {
        remap[v] = out.mesh.add_vertex(graph.position[v]);
        out.vertex_normals.push_back(normalized(graph.normal[v]));
        out.vertex_face.push_back(graph.face[v]);
      }
      v = remap[v];
    }
  for (const auto& f : faces) out.mesh.add_face(f.data(), f.size());
  for (const GraphEdge& e : graph.edges)
    if (e.alive && remap[e.a] != kNone && remap[e.b] != kNone) {
      const uint32_t k = std::min<uint32_t>(uint32_t(e.pos_a), uint32_t(sampling.lines[e.line].segments.size() - 1));
      out.edges.push_back({remap[e.a], remap[e.b], sampling.database->segment(sampling.lines[e.line].segments[k]).type});
    }
  split_pinched_vertices(out);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  monitor.report("meshing", 1.0);
  return out;
}

CAGEKIT_NAMESPACE_END
