// SPDX-License-Identifier: GPL-3.0-or-later
// The two-step quad-dominant remesher end to end; see quad_remesher.h.
#include "layout/quad/quad_remesher.h"
#include "layout/quad/disk_regions.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include "core/edge_key.h"
#include "core/edge_map.h"
#include "core/mesh_validation.h"
#include "core/status.h"
#include "layout/common/polygon_corners.h"
#include "layout/common/quad_dominant_partition.h"
#include "layout/quad/lscm_parameterization.h"
#include "layout/quad/quad_region_selection.h"
#include "layout/quad/remesh_constraints.h"
#include "layout/quad/sample_count_refinement.h"
#include "layout/common/sharp_input_features.h"
#include "layout/common/triangle_mesh_input.h"
#include "layout/quad/vsa_segmentation.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

void check_options(const QuadRemeshOptions& o) {
  const char* who = "quad-dominant remeshing: ";
  if (o.regions < 0) fail(Status::invalid_argument, std::string(who) + "regions must be >= 0 (0: by tolerance)");
  if (o.regions == 0 && (!(o.region_tolerance >= 0.0) || !std::isfinite(o.region_tolerance) || o.max_regions < 1))
    fail(Status::invalid_argument, std::string(who) + "region tolerance must be finite and >= 0, max regions >= 1");
  if (!(o.regions_per_feature_patch >= 0.0) || !std::isfinite(o.regions_per_feature_patch))
    fail(Status::invalid_argument, std::string(who) + "regions per feature patch must be finite and >= 0");
  if (!(o.edge_length > 0.0) || !(o.edge_length <= 1.0))
    fail(Status::invalid_argument, std::string(who) + "edge length must be in (0, 1] (relative to the bbox diagonal)");
  for (double w : {o.triangle_weight, o.pentagon_weight, o.t_joint_weight})
    if (!(w > 0.0) || !std::isfinite(w))
      fail(Status::invalid_argument, std::string(who) + "the triangle, pentagon and T-joint weights must be positive");
  if (std::isnan(o.crease_angle_degrees) || o.crease_angle_degrees > 180.0)
    fail(Status::invalid_argument, std::string(who) + "crease angle must be <= 180 degrees (< 0: no creases)");
  if (o.relaxation_iterations < 0 || o.relaxation_iterations > 100000)
    fail(Status::invalid_argument, std::string(who) + "relaxation iterations must be in [0, 100000]");
  if (o.threads < 0 || o.threads > 1024) fail(Status::invalid_argument, std::string(who) + "threads must be in [0, 1024]");
  if (o.sample_refinement_passes < 0 || o.sample_refinement_max_curves < 0)
    fail(Status::invalid_argument, std::string(who) + "sample refinement passes and max curves must be >= 0");
  if (o.layout_attempts < 1 || o.layout_attempts > 1000)
    fail(Status::invalid_argument, std::string(who) + "layout attempts must be in [1, 1000]");
  if (!(o.retry_few_failing_share >= 0.0) || !(o.retry_few_failing_share <= 1.0))
    fail(Status::invalid_argument, std::string(who) + "the retry's few-failing share must be in [0, 1]");
}

// Constrained points of all arcs with global ids: the anchors first (in RegionBoundaries::anchors
// order), then every arc's interior samples.
struct GlobalSamples {
  std::vector<Vec3> positions;
  std::vector<uint32_t> arc_first;  // id of arc a's sample 1

  uint32_t id(const RemeshConstraints& c, uint32_t arc, size_t k) const {
    const std::vector<uint32_t>& v = c.boundaries.arcs[arc].vertices;
    const size_t last = c.arcs[arc].samples.position.size() - 1;
    if (k == 0 || k == last) {
      const uint32_t vertex = k == 0 ? v.front() : v.back();
      const auto it = std::lower_bound(c.boundaries.anchors.begin(), c.boundaries.anchors.end(), vertex);
      return uint32_t(it - c.boundaries.anchors.begin());
    }
    return arc_first[arc] + uint32_t(k - 1);
  }
  // Sample ids of arc a from first to last.
  std::vector<uint32_t> arc_ids(const RemeshConstraints& c, uint32_t arc) const {
    std::vector<uint32_t> out;
    for (size_t k = 0; k < c.arcs[arc].samples.position.size(); ++k) out.push_back(id(c, arc, k));
    return out;
  }
};

GlobalSamples global_samples(const PolygonMesh& tri, const RemeshConstraints& c) {
  GlobalSamples g;
  for (uint32_t v : c.boundaries.anchors) g.positions.push_back(tri.positions[v]);
  for (uint32_t a = 0; a < c.arcs.size(); ++a) {
    g.arc_first.push_back(uint32_t(g.positions.size()));
    const std::vector<Vec3>& p = c.arcs[a].samples.position;
    for (size_t k = 1; k + 1 < p.size(); ++k) g.positions.push_back(p[k]);
  }
  return g;
}

// Global sample ids of region r's network points (the loops' samples concatenated in the order of
// RemeshConstraints::loop_samples_uv: each arc first to last or reversed, without its last point).
std::vector<uint32_t> region_point_ids(const RemeshConstraints& c, const GlobalSamples& g, uint32_t r) {
  std::vector<uint32_t> out;
  for (const RegionLoop& loop : c.boundaries.region_loops[r])
    for (size_t k = 0; k < loop.arcs.size(); ++k) {
      std::vector<uint32_t> ids = g.arc_ids(c, loop.arcs[k]);
      if (loop.reversed[k]) std::reverse(ids.begin(), ids.end());
      out.insert(out.end(), ids.begin(), ids.end() - 1);
    }
  return out;
}

double cross2(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// Laplacian relaxation of the region mesh's inner vertices (vertex_point < 0) in Ω; see the header.
void relax_region(const QuadSelection& s, int sweeps, std::vector<Vec2>& uv) {
  uv = s.vertices;
  const size_t n = uv.size();
  std::vector<std::vector<uint32_t>> neighbours(n), faces_of(n);
  for (uint32_t f = 0; f < s.faces.size(); ++f) {
    const std::vector<uint32_t>& face = s.faces[f];
    for (size_t k = 0; k < face.size(); ++k) {
      const uint32_t a = face[k], b = face[(k + 1) % face.size()];
      neighbours[a].push_back(b);
      neighbours[b].push_back(a);
      faces_of[a].push_back(f);
    }
  }
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  std::vector<Vec2> polygon;
  // Signed area > 0 and, at v and its two neighbours on the face, convex corners stay convex.
  auto acceptable = [&](uint32_t v) {
    for (uint32_t f : faces_of[v]) {
      const std::vector<uint32_t>& face = s.faces[f];
      const size_t m = face.size();
      polygon.clear();
      for (uint32_t w : face) polygon.push_back(uv[w]);
      if (!(plane2::signed_area(polygon) > 0.0)) return false;
      const size_t i = size_t(std::find(face.begin(), face.end(), v) - face.begin());
      for (size_t d : {m - 1, size_t(0), size_t(1)}) {
        const size_t k = (i + d) % m;
        const uint32_t a = face[(k + m - 1) % m], b = face[k], c = face[(k + 1) % m];
        const bool was_convex = cross2(s.vertices[a], s.vertices[b], s.vertices[c]) > 0.0;
        if (was_convex && !(cross2(uv[a], uv[b], uv[c]) > 0.0)) return false;
      }
    }
    return true;
  };
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    for (uint32_t v = 0; v < n; ++v) {
      if (s.vertex_point[v] >= 0 || neighbours[v].empty()) continue;
      Vec2 target{0.0, 0.0};
      for (uint32_t w : neighbours[v]) target = target + uv[w];
      target = target * (1.0 / double(neighbours[v].size()));
      const Vec2 old = uv[v];
      uv[v] = target;
      if (acceptable(v)) continue;
      uv[v] = (old + target) * 0.5;
      if (!acceptable(v)) uv[v] = old;
    }
  }
}

// A region's parameterised input triangles in Ω_i, for point location.
struct RegionLocator {
  const PolygonMesh* tri = nullptr;
  const RegionParameterization* domain = nullptr;
  std::vector<Vec3> face_normals;  // of the input mesh

  struct Hit {
    uint32_t face = 0;
    std::array<double, 3> weights{};
    bool inside = false;
  };

  // Closest point of triangle (a, b, c) to q, as barycentric weights, and its squared distance.
  static double closest(const Vec2& q, const Vec2& a, const Vec2& b, const Vec2& c, std::array<double, 3>& w) {
    const double area = cross2(a, b, c);
    if (area != 0.0) {
      const double wa = cross2(q, b, c) / area, wb = cross2(a, q, c) / area, wc = 1.0 - wa - wb;
      if (wa >= 0.0 && wb >= 0.0 && wc >= 0.0) {
        w = {wa, wb, wc};
        return 0.0;
      }
    }
    double best = HUGE_VAL;
    const Vec2* p[3] = {&a, &b, &c};
    for (int e = 0; e < 3; ++e) {
      const Vec2& u = *p[e];
      const Vec2& v = *p[(e + 1) % 3];
      const Vec2 d = v - u;
      const double len2 = dot(d, d);
      const double t = len2 > 0.0 ? std::clamp(dot(q - u, d) / len2, 0.0, 1.0) : 0.0;
      const Vec2 x = u + d * t;
      const Vec2 r = q - x;
      const double d2 = dot(r, r);
      if (d2 < best) {
        best = d2;
        w = {0.0, 0.0, 0.0};
        w[size_t(e)] = 1.0 - t;
        w[size_t((e + 1) % 3)] = t;
      }
    }
    return best;
  }

  Hit locate(const Vec2& q) const {
    Hit hit;
    double best = HUGE_VAL;
    for (uint32_t f : domain->faces) {
      const uint32_t* v = tri->face_begin(f);
      std::array<double, 3> w{};
      const double d2 = closest(q, domain->uv_of(v[0]), domain->uv_of(v[1]), domain->uv_of(v[2]), w);
      if (d2 < best) {
        best = d2;
        hit.face = f;
        hit.weights = w;
        if (d2 == 0.0) break;
      }
    }
    hit.inside = best == 0.0;
    return hit;
  }

  Vec3 position(const Hit& h) const {
    const uint32_t* v = tri->face_begin(h.face);
    return h.weights[0] * tri->positions[v[0]] + h.weights[1] * tri->positions[v[1]] + h.weights[2] * tri->positions[v[2]];
  }
};

// Per piece [t_k, t_{k+1}] between consecutive samples of an arc: the share of the length of
// the arc's input edges whose middle (in the arc-length parameter s of the cubic) lies in it that
// is a sharp input feature; a piece containing no edge middle takes the edge around its middle.
std::vector<double> piece_sharp_share(const SharpFeatures& features, const RegionArc& arc,
                                      const ArcConstraint& constraint) {
  const std::vector<double>& t = constraint.samples.t;
  const size_t pieces = t.size() - 1;
  std::vector<double> sharp(pieces, 0.0), length(pieces, 0.0);
  std::vector<uint8_t> edge_sharp(arc.vertices.size() - 1, 0);
  for (size_t k = 0; k + 1 < arc.vertices.size(); ++k) {
    edge_sharp[k] = features.contains(arc.vertices[k], arc.vertices[k + 1]);
    const double middle = 0.5 * (constraint.s[k] + constraint.s[k + 1]);
    const size_t piece = std::min<size_t>(
        pieces - 1, size_t(std::max<long>(0, long(std::upper_bound(t.begin(), t.end(), middle) - t.begin()) - 1)));
    const double l = constraint.s[k + 1] - constraint.s[k];
    sharp[piece] += edge_sharp[k] ? l : 0.0;
    length[piece] += l;
  }
  std::vector<double> out(pieces, 0.0);
  for (size_t p = 0; p < pieces; ++p) {
    if (length[p] > 0.0) {
      out[p] = sharp[p] / length[p];
      continue;
    }
    const double middle = 0.5 * (t[p] + t[p + 1]);
    const size_t k = std::min<size_t>(
        edge_sharp.size() - 1,
        size_t(std::max<long>(0, long(std::upper_bound(constraint.s.begin(), constraint.s.end(), middle) -
                                       constraint.s.begin()) - 1)));
    out[p] = edge_sharp[k];
  }
  return out;
}

}  // namespace


// Where the glued faces of the regions' layouts coincide or fold onto each other: a face that
// repeats a vertex, two faces over the same vertex set, an undirected edge of more than two faces
// or a directed edge of two. Each conflict names the regions of its faces: (r, r) for a face
// that repeats a vertex (r's boundary touches itself there), (a, b) for faces of two regions.
struct GlueConflict {
  uint32_t region = 0, other = 0;
  uint32_t u = 0, v = 0;  // the glued vertices the conflict spans (an edge's ends, a face's farthest two)
  bool operator<(const GlueConflict& c) const {
    return std::tie(region, other, u, v) < std::tie(c.region, c.other, c.u, c.v);
  }
  bool operator==(const GlueConflict& c) const {
    return std::tie(region, other, u, v) == std::tie(c.region, c.other, c.u, c.v);
  }
};

std::vector<GlueConflict> glue_conflicts(const PolygonMesh& mesh, const std::vector<uint32_t>& face_region) {
  std::vector<GlueConflict> out;
  auto add_group = [&](const std::vector<uint32_t>& faces, uint32_t u, uint32_t v) {
    for (size_t i = 0; i < faces.size(); ++i)
      for (size_t j = i + 1; j < faces.size(); ++j) {
        const uint32_t a = face_region[faces[i]], b = face_region[faces[j]];
        if (a != b) out.push_back({std::min(a, b), std::max(a, b), u, v});
      }
  };
  auto farthest_pair = [&](uint32_t f) {
    std::pair<uint32_t, uint32_t> best{mesh.face_vertex(f, 0), mesh.face_vertex(f, 0)};
    double d = -1.0;
    for (uint32_t i = 0; i < mesh.face_size(f); ++i)
      for (uint32_t j = i + 1; j < mesh.face_size(f); ++j) {
        const uint32_t a = mesh.face_vertex(f, i), b = mesh.face_vertex(f, j);
        const double e = norm(mesh.positions[a] - mesh.positions[b]);
        if (e > d) d = e, best = {a, b};
      }
    return best;
  };
  std::unordered_map<std::string, uint32_t> by_vertices;
  std::unordered_map<uint64_t, std::vector<uint32_t>> undirected, directed;
  std::vector<uint32_t> key;
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t n = mesh.face_size(f);
    key.assign(mesh.face_begin(f), mesh.face_begin(f) + n);
    std::sort(key.begin(), key.end());
    if (std::adjacent_find(key.begin(), key.end()) != key.end())
      out.push_back({face_region[f], face_region[f], *std::adjacent_find(key.begin(), key.end()), 0});
    const auto [it, inserted] =
        by_vertices.emplace(std::string(reinterpret_cast<const char*>(key.data()), key.size() * sizeof(uint32_t)), f);
    if (!inserted) {
      const auto [u, v] = farthest_pair(f);
      add_group({f, it->second}, u, v);
    }
    for (uint32_t k = 0; k < n; ++k) {
      const uint32_t a = mesh.face_vertex(f, k), b = mesh.face_vertex(f, (k + 1) % n);
      undirected[edge_key(a, b)].push_back(f);
      directed[directed_edge_key(a, b)].push_back(f);
    }
  }
  for (const auto& [edge, faces] : undirected)
    if (faces.size() > 2) add_group(faces, edge_key_first(edge), edge_key_second(edge));
  for (const auto& [edge, faces] : directed)
    if (faces.size() > 1) add_group(faces, edge_key_first(edge), edge_key_second(edge));
  // A vertex whose faces form two or more fans (joined through the edges at it): faces of
  // different fans conflict there.
  struct Corner { uint32_t vertex, face, prev, next; };
  std::vector<Corner> corners;
  corners.reserve(mesh.face_vertices.size());
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t n = mesh.face_size(f);
    for (uint32_t k = 0; k < n; ++k)
      corners.push_back({mesh.face_vertex(f, k), f, mesh.face_vertex(f, (k + n - 1) % n), mesh.face_vertex(f, (k + 1) % n)});
  }
  std::sort(corners.begin(), corners.end(), [](const Corner& a, const Corner& b) {
    return a.vertex != b.vertex ? a.vertex < b.vertex : a.face < b.face;
  });
  std::vector<uint32_t> parent;
  std::unordered_map<uint32_t, uint32_t> by_neighbour;
  for (size_t begin = 0, end = 0; begin < corners.size(); begin = end) {
    for (end = begin; end < corners.size() && corners[end].vertex == corners[begin].vertex;) ++end;
    if (end - begin < 2) continue;
    parent.resize(end - begin);
    for (uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
    auto root = [&](uint32_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    by_neighbour.clear();
    for (uint32_t i = 0; i < end - begin; ++i)
      for (const uint32_t w : {corners[begin + i].prev, corners[begin + i].next}) {
        const auto [it, inserted] = by_neighbour.emplace(w, i);
        if (!inserted) parent[root(i)] = root(it->second);
      }
    const uint32_t fan0 = root(0);
    std::vector<uint32_t> first, others;
    for (uint32_t i = 0; i < end - begin; ++i) (root(i) == fan0 ? first : others).push_back(corners[begin + i].face);
    if (others.empty()) continue;
    const uint32_t v = corners[begin].vertex;
    for (const uint32_t a : first)
      for (const uint32_t b : others) {
        const uint32_t ra = face_region[a], rb = face_region[b];
        out.push_back({std::min(ra, rb), std::max(ra, rb), v, v});
      }
  }
  // Hash-map order is not the same everywhere: sort (by regions, then vertices) so the same
  // conflict is picked on every platform.
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// The regions' layouts glued into one polygon mesh, with what the local repairs need: per face
// its region and the input normal under its centroid, per face corner its place in the region's
// parameter domain.
struct GluedLayout {
  PolygonMesh mesh;
  std::vector<uint32_t> region;       // per face
  std::vector<Vec3> reference_normal; // per face
  std::vector<Vec2> corner_uv;      // per entry of mesh.face_vertices

  void add_face(const std::vector<uint32_t>& ids, const std::vector<Vec2>& uv, uint32_t r, const Vec3& normal) {
    mesh.add_face(ids.data(), ids.size());
    corner_uv.insert(corner_uv.end(), uv.begin(), uv.end());
    region.push_back(r);
    reference_normal.push_back(normal);
  }
};

// Local repairs of glue conflicts (before any region is split and laid out again): a face that
// repeats a vertex consecutively drops the repeat (one that repeats it elsewhere is left to the
// region split at the pinch); of two faces over the
// same vertices (a region one face wide on each side of a thin part: both span it from one
// shared boundary stretch to the other) the one of the larger region gets a vertex inside, at
// its parameter-domain centroid on the input surface; an edge that is interior to two regions (both
// have a chord between the same two boundary samples) is removed in the larger region, whose two
// faces at it become one polygon with a vertex inside. A polygon with a vertex m inside becomes
// quads (v_2i, v_2i+1, v_2i+2, m) and, for an odd count, one triangle. Returns the faces repaired.
size_t mend_glue_conflicts(GluedLayout& g, const PolygonMesh& tri, const RemeshConstraints& constraints,
                           const std::vector<Vec3>& normals) {
  PolygonMesh& mesh = g.mesh;
  size_t mended = 0;
  std::vector<size_t> faces_in(constraints.domains.size(), 0);
  for (const uint32_t r : g.region) ++faces_in[r];
  // 1. Repeated vertices.
  {
    GluedLayout out;
    out.mesh.positions = mesh.positions;
    std::vector<uint32_t> ids;
    std::vector<Vec2> uv;
    for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
      const uint32_t n = mesh.face_size(f), begin = mesh.face_offsets[f];
      ids.clear();
      uv.clear();
      for (uint32_t k = 0; k < n; ++k) {
        const uint32_t v = mesh.face_vertex(f, k);
        if (!ids.empty() && ids.back() == v) continue;
        ids.push_back(v);
        uv.push_back(g.corner_uv[begin + k]);
      }
      while (ids.size() > 1 && ids.back() == ids.front()) ids.pop_back(), uv.pop_back();
      const bool changed = ids.size() != n;
      mended += changed;
      if (ids.size() >= 3) out.add_face(ids, uv, g.region[f], g.reference_normal[f]);
    }
    g = std::move(out);
  }
  // 2. Faces to open up, in rounds (a repair can leave another conflict next to it): first the
  // regions' shared chords, then coinciding pairs among the faces not yet changed.
  for (int round = 0; round < 4; ++round) {
    std::unordered_map<std::string, std::vector<uint32_t>> by_vertices;
    std::unordered_map<uint64_t, std::vector<uint32_t>> undirected;
    std::vector<uint32_t> key;
    std::vector<uint8_t> used(mesh.num_faces(), 0);
    std::vector<std::vector<uint32_t>> groups;  // faces merged into one polygon with a vertex inside
    for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
      const uint32_t n = mesh.face_size(f);
      key.assign(mesh.face_begin(f), mesh.face_begin(f) + n);
      std::sort(key.begin(), key.end());
      by_vertices[std::string(reinterpret_cast<const char*>(key.data()), key.size() * sizeof(uint32_t))].push_back(f);
      for (uint32_t k = 0; k < n; ++k)
        undirected[edge_key(mesh.face_vertex(f, k), mesh.face_vertex(f, (k + 1) % n))].push_back(f);
    }
    std::vector<uint64_t> crowded;
    for (const auto& [edge, faces] : undirected)
      if (faces.size() > 2) crowded.push_back(edge);
    std::sort(crowded.begin(), crowded.end());  // the same repairs on every platform
    for (const uint64_t edge : crowded) {
      const std::vector<uint32_t>& faces = undirected[edge];
      uint32_t best_a = 0xffffffffu, best_b = 0xffffffffu;
      for (size_t i = 0; i < faces.size(); ++i)
        for (size_t j = i + 1; j < faces.size(); ++j) {
          const uint32_t a = faces[i], b = faces[j];
          if (a == b || g.region[a] != g.region[b] || used[a] || used[b]) continue;
          if (best_a == 0xffffffffu || faces_in[g.region[a]] > faces_in[g.region[best_a]]) best_a = a, best_b = b;
        }
      if (best_a == 0xffffffffu) continue;
      used[best_a] = used[best_b] = 1;
      groups.push_back({best_a, best_b});
    }
    std::vector<std::vector<uint32_t>> coinciding;
    for (const auto& [vertices, faces] : by_vertices)
      if (faces.size() > 1) coinciding.push_back(faces);
    std::sort(coinciding.begin(), coinciding.end());
    for (const std::vector<uint32_t>& faces : coinciding) {
      uint32_t pick = 0xffffffffu;
      for (const uint32_t f : faces) {
        if (used[f]) {
          pick = 0xffffffffu;  // one of them changes already: look again next round
          break;
        }
        if (pick == 0xffffffffu || faces_in[g.region[f]] > faces_in[g.region[pick]]) pick = f;
      }
      if (pick == 0xffffffffu) continue;
      used[pick] = 1;
      groups.push_back({pick});
    }
    if (groups.empty()) break;
    std::vector<int32_t> group_of(mesh.num_faces(), -1);
    for (size_t k = 0; k < groups.size(); ++k)
      for (const uint32_t f : groups[k]) group_of[f] = int32_t(k);
    GluedLayout out;
    out.mesh.positions = mesh.positions;
    auto corners = [&](uint32_t f) {
      std::vector<std::pair<uint32_t, Vec2>> c;
      for (uint32_t k = 0; k < mesh.face_size(f); ++k)
        c.push_back({mesh.face_vertex(f, k), g.corner_uv[mesh.face_offsets[f] + k]});
      return c;
    };
    auto keep = [&](uint32_t f) {  // face f as it is
      std::vector<uint32_t> ids;
      std::vector<Vec2> uv;
      for (const auto& [v, p] : corners(f)) ids.push_back(v), uv.push_back(p);
      out.add_face(ids, uv, g.region[f], g.reference_normal[f]);
    };
    for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
      if (group_of[f] < 0) {
        keep(f);
        continue;
      }
      const std::vector<uint32_t>& group = groups[size_t(group_of[f])];
      if (group.front() != f) continue;  // emitted with the group's first face
      std::vector<std::pair<uint32_t, Vec2>> loop = corners(f);
      if (group.size() == 2) {
        // Join the two faces across their shared edge u -> v (v -> u in the other).
        const std::vector<std::pair<uint32_t, Vec2>> other = corners(group[1]);
        const size_t n = loop.size(), m = other.size();
        size_t i = n, j = m;
        for (size_t a = 0; a < n && i == n; ++a)
          for (size_t b = 0; b < m; ++b)
            if (loop[a].first == other[(b + 1) % m].first && loop[(a + 1) % n].first == other[b].first) {
              i = a, j = b;
              break;
            }
        if (i == n) {  // they share the edge with one orientation only: leave both as they are
          for (const uint32_t h : group) keep(h);
          continue;
        }
        // loop from v = loop[i+1] around to u = loop[i], then other from u's successor to v's predecessor.
        std::vector<std::pair<uint32_t, Vec2>> joined;
        for (size_t k = 1; k <= n; ++k) joined.push_back(loop[(i + k) % n]);
        for (size_t k = 2; k < m; ++k) joined.push_back(other[(j + k) % m]);
        loop = std::move(joined);
      }
      const uint32_t region = g.region[f];
      Vec2 centroid{0.0, 0.0};
      for (const auto& c : loop) centroid = centroid + c.second;
      centroid = centroid * (1.0 / double(loop.size()));
      RegionLocator locator{&tri, &constraints.domains[region], {}};
      const RegionLocator::Hit hit = locator.locate(centroid);
      const Vec3 centre = locator.position(hit);
      // The new faces, each checked against the input normal under its centroid: a repair that
      // folds a face is not made (the conflict is then left to the region split).
      const size_t n = loop.size();
      std::vector<std::vector<size_t>> pieces;  // corners of loop; n stands for the new vertex
      for (size_t k = 0; k + 1 < n; k += 2) pieces.push_back({k, k + 1, (k + 2) % n, n});
      if (n % 2 == 1) pieces.push_back({n - 1, 0, n});
      std::vector<Vec3> piece_normal;
      bool folds = false;
      for (const std::vector<size_t>& piece : pieces) {
        std::vector<Vec3> points;
        Vec2 c{0.0, 0.0};
        for (const size_t k : piece) {
          points.push_back(k == n ? centre : out.mesh.positions[loop[k].first]);
          c = c + (k == n ? centroid : loop[k].second);
        }
        std::vector<uint32_t> local(points.size());
        for (uint32_t k = 0; k < local.size(); ++k) local[k] = k;
        const Vec3 expected = normals[locator.locate(c * (1.0 / double(piece.size()))).face];
        folds = folds || !(dot(loop_normal(points, local), expected) > 0.0);
        piece_normal.push_back(expected);
      }
      if (folds) {
        for (const uint32_t h : group) keep(h);
        continue;
      }
      const uint32_t inside = out.mesh.add_vertex(centre);
      for (size_t k = 0; k < pieces.size(); ++k) {
        std::vector<uint32_t> ids;
        std::vector<Vec2> uv;
        for (const size_t c : pieces[k]) {
          ids.push_back(c == n ? inside : loop[c].first);
          uv.push_back(c == n ? centroid : loop[c].second);
        }
        out.add_face(ids, uv, region, piece_normal[k]);
      }
      mended += group.size();
    }
    g = std::move(out);
  }
  return mended;
}

// Flipped triangles in the LSCM map of two regions' faces together, as make_disk_regions would
// parameterise them after a merge (SIZE_MAX: not a disk, possibly with holes, at all).
size_t merged_map_flips(const PolygonMesh& tri, const std::vector<uint32_t>& face_region, uint32_t a, uint32_t b) {
  std::vector<uint32_t> faces;
  for (uint32_t f = 0; f < face_region.size(); ++f)
    if (face_region[f] == a || face_region[f] == b) faces.push_back(f);
  try {
    return parameterize_region_lscm(tri, faces).flipped_triangles;
  } catch (const Error& e) {
    if (e.status() != Status::invalid_mesh) throw;
    return SIZE_MAX;
  }
}

// Merges each listed region into the neighbouring region with which it shares the longest
// boundary (never into a pinned one; a region with no such neighbour stays), then renumbers the
// regions densely in their order. Returns the number merged. When the merged region's LSCM map
// would fold (or the two are not a disk together), make_disk_regions would split it again,
// along the same Voronoi cells, giving the sliver back (femur.off: a 3-triangle sliver split off
// a 5-triangle region with 2 flipped triangles, merged back, split off again, until the retries
// ran out): then the neighbour whose merged map has the fewest flipped triangles is taken, the
// longest shared boundary breaking ties.
size_t merge_into_neighbours(const PolygonMesh& tri, std::vector<uint32_t>& face_region, size_t& region_count,
                             size_t pinned, const std::vector<uint32_t>& regions) {
  if (regions.empty()) return 0;
  std::unordered_map<uint64_t, std::pair<uint32_t, uint32_t>> edge_faces;  // edge -> (face, face)
  for (uint32_t f = 0; f < tri.num_faces(); ++f)
    for (uint32_t k = 0; k < 3; ++k) {
      const uint64_t key = edge_key(tri.face_vertex(f, k), tri.face_vertex(f, (k + 1) % 3));
      auto [it, inserted] = edge_faces.emplace(key, std::make_pair(f, 0xffffffffu));
      if (!inserted) it->second.second = f;
    }
  std::vector<uint8_t> listed(region_count, 0);
  for (const uint32_t r : regions) listed[r] = 1;
  // Shared boundary length per (listed region, neighbour).
  std::unordered_map<uint64_t, double> shared;
  for (const auto& [key, faces] : edge_faces) {
    if (faces.second == 0xffffffffu) continue;
    const uint32_t a = face_region[faces.first], b = face_region[faces.second];
    if (a == b) continue;
    const double length = norm(tri.positions[edge_key_first(key)] - tri.positions[edge_key_second(key)]);
    if (listed[a] && b >= pinned) shared[directed_edge_key(a, b)] += length;
    if (listed[b] && a >= pinned) shared[directed_edge_key(b, a)] += length;
  }
  // Per listed region its neighbours, longest shared boundary first (ties: smaller id).
  std::vector<std::vector<std::pair<double, uint32_t>>> neighbours(region_count);
  for (const auto& [key, length] : shared)
    if (length > 0.0) neighbours[edge_key_first(key)].push_back({length, uint32_t(edge_key_second(key))});
  std::vector<uint32_t> target(region_count);
  for (uint32_t r = 0; r < region_count; ++r) {
    target[r] = r;
    std::vector<std::pair<double, uint32_t>>& list = neighbours[r];
    if (list.empty()) continue;
    std::sort(list.begin(), list.end(), [](const std::pair<double, uint32_t>& x, const std::pair<double, uint32_t>& y) {
      return x.first > y.first || (x.first == y.first && x.second < y.second);
    });
    size_t fewest = merged_map_flips(tri, face_region, r, list[0].second);
    target[r] = list[0].second;
    for (size_t k = 1; k < list.size() && fewest > 0; ++k) {
      const size_t flips = merged_map_flips(tri, face_region, r, list[k].second);
      if (flips < fewest) fewest = flips, target[r] = list[k].second;
    }
  }
  // A listed region merged into another listed region that is itself merged: follow the chain
  // (cycles stop at their smallest member).
  size_t merged = 0;
  for (uint32_t r = 0; r < region_count; ++r) {
    if (target[r] == r) continue;
    uint32_t t = target[r];
    for (size_t hops = 0; target[t] != t && hops < region_count; ++hops) t = target[t];
    if (target[t] != t) t = std::min(r, t);
    target[r] = t;
  }
  for (uint32_t r = 0; r < region_count; ++r) merged += target[r] != r;
  if (merged == 0) return 0;
  std::vector<uint32_t> id(region_count, 0xffffffffu);
  uint32_t next = 0;
  for (uint32_t r = 0; r < region_count; ++r)
    if (target[r] == r) id[r] = next++;
  for (uint32_t& r : face_region) r = id[target[r]];
  region_count = next;
  return merged;
}

// Edge-connected components of the faces.
size_t count_face_components(const PolygonMesh& mesh) {
  std::vector<uint32_t> parent(mesh.num_vertices());
  for (uint32_t v = 0; v < parent.size(); ++v) parent[v] = v;
  auto find = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  // Faces sharing an edge share its two vertices; components of vertices joined by face edges
  // equal edge-connected face components except at non-manifold vertices (not in a
  // conditioned mesh), where they can only be fewer.
  for (size_t f = 0; f < mesh.num_faces(); ++f)
    for (uint32_t k = 1; k < mesh.face_size(f); ++k)
      parent[find(mesh.face_vertex(f, k))] = find(mesh.face_vertex(f, 0));
  std::vector<uint8_t> root(mesh.num_vertices(), 0);
  size_t components = 0;
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t x = find(mesh.face_vertex(f, 0));
    components += !root[x];
    root[x] = 1;
  }
  return components;
}

// Vertex components of the faces (one id per vertex a face uses, 0xffffffff for the others) and
// the Euler characteristic V - E + F over the used vertices.
struct FaceTopology {
  std::vector<uint32_t> component;  // per vertex
  size_t components = 0;
  int64_t euler = 0;
};

FaceTopology face_topology(const PolygonMesh& mesh) {
  FaceTopology t;
  std::vector<uint32_t> parent(mesh.num_vertices());
  for (uint32_t v = 0; v < parent.size(); ++v) parent[v] = v;
  auto find = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::unordered_set<uint64_t> edges;
  std::vector<uint8_t> used(mesh.num_vertices(), 0);
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t n = mesh.face_size(uint32_t(f));
    for (uint32_t k = 0; k < n; ++k) {
      const uint32_t a = mesh.face_vertex(uint32_t(f), k), b = mesh.face_vertex(uint32_t(f), (k + 1) % n);
      used[a] = 1;
      edges.insert(edge_key(a, b));
      parent[find(a)] = find(b);
    }
  }
  t.component.assign(mesh.num_vertices(), 0xffffffffu);
  std::unordered_map<uint32_t, uint32_t> id;
  int64_t vertices = 0;
  for (uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    if (!used[v]) continue;
    ++vertices;
    t.component[v] = id.emplace(find(v), uint32_t(id.size())).first->second;
  }
  t.components = id.size();
  t.euler = vertices - int64_t(edges.size()) + int64_t(mesh.num_faces());
  return t;
}

// Feature patches: the faces joined across every edge that is not a sharp input feature; those
// holding at least kFeaturePatchAreaShare of the area are counted (fillets' slivers and noise
// islands are not).
constexpr double kFeaturePatchAreaShare = 5e-3;
size_t count_feature_patches(const PolygonMesh& mesh, const SharpFeatures& features) {
  const size_t nf = mesh.num_faces();
  detail::UnionFind patch(nf);
  detail::EdgeMap map;
  build_edge_map(map, mesh, std::vector<uint8_t>(nf, 1));
  for (size_t e = 0; e < map.num_edges(); ++e) {
    if (features.contains(map.edge_lo[e], map.edge_hi[e])) continue;
    for (const uint32_t* c = map.corners_begin(e) + 1; c < map.corners_end(e); ++c)
      patch.unite(map.corner_face[*map.corners_begin(e)], map.corner_face[*c]);
  }
  std::vector<double> area(nf, 0.0);
  double total = 0.0;
  for (size_t f = 0; f < nf; ++f) {
    const double a = norm(mesh.face_vector_area(f));
    area[patch.find(uint32_t(f))] += a;
    total += a;
  }
  size_t patches = 0;
  for (size_t f = 0; f < nf; ++f) patches += patch.find(uint32_t(f)) == f && area[f] >= kFeaturePatchAreaShare * total;
  return patches;
}

// The phases of remesh_quad_dominant (the pipeline of thesis ch. 6), in the order it runs them.
namespace {

// The input as triangles: polygons fan-triangulated, the input faces in order.
PolygonMesh triangulated_input(const PolygonMesh& input) {
  PolygonMesh tri = fan_triangulated(input, "quad-dominant remeshing");
  require_triangle_mesh(tri, "quad-dominant remeshing");
  return tri;
}

// The segmentation's options: the host's pinned regions and seeds as fan triangles, and the region
// count (or the tolerance and the largest count).
VsaOptions vsa_options(const PolygonMesh& input, const QuadRemeshOptions& o) {
  VsaOptions vo;
  if (!o.pinned_regions.empty() || !o.seed_faces.empty()) {
    // Input faces -> their fan triangles (fan_triangulated keeps the face order).
    std::vector<uint32_t> first_triangle(input.num_faces() + 1, 0);
    for (size_t f = 0; f < input.num_faces(); ++f)
      first_triangle[f + 1] = first_triangle[f] + (input.face_size(f) - 2);
    auto check_face = [&](uint32_t f, const std::string& what) {
      if (f >= input.num_faces())
        fail(Status::invalid_argument, "quad-dominant remeshing: " + what + " face " + std::to_string(f) +
                                           " is out of range (the mesh has " + std::to_string(input.num_faces()) +
                                           " faces)");
    };
    for (size_t k = 0; k < o.pinned_regions.size(); ++k) {
      std::vector<uint32_t> triangles;
      for (uint32_t f : o.pinned_regions[k]) {
        check_face(f, "pinned region " + std::to_string(k));
        for (uint32_t t = first_triangle[f]; t < first_triangle[f + 1]; ++t) triangles.push_back(t);
      }
      vo.pinned_regions.push_back(std::move(triangles));
    }
    for (uint32_t f : o.seed_faces) {
      check_face(f, "seed");
      vo.seed_faces.push_back(first_triangle[f]);
    }
  }
  if (o.regions > 0) {
    vo.region_count = o.regions;
  } else {
    vo.region_count = o.max_regions;
    vo.tolerance = o.region_tolerance;
  }
  return vo;
}

// The sharp input features (for the region count and, at the end, the creases); none when
// creases are off.
SharpFeatures sharp_input_features(const PolygonMesh& tri, const QuadRemeshOptions& o) {
  SharpFeatureOptions feature_options;
  feature_options.angle_degrees = std::clamp(o.crease_angle_degrees, 0.0, 180.0);
  feature_options.detect = o.crease_angle_degrees >= 0.0;
  feature_options.host_edges = o.sharp_edges;
  const bool use_features = feature_options.detect || !o.sharp_edges.empty();
  return use_features ? detect_sharp_features(tri, feature_options) : SharpFeatures{};
}

// Patches the host's sharp edges enclose (faces joined across every other edge): each needs a
// region of its own.
size_t count_sharp_edge_patches(const PolygonMesh& tri, const std::vector<uint64_t>& sorted_sharp_edges) {
  FaceAdjacency adjacency;
  build_face_adjacency(adjacency, tri, sorted_sharp_edges);
  const size_t nf = tri.num_faces();
  std::vector<uint8_t> seen(nf, 0);
  size_t patches = 0;
  for (uint32_t s = 0; s < nf; ++s) {
    if (seen[s]) continue;
    ++patches;
    std::vector<uint32_t> stack{s};
    seen[s] = 1;
    while (!stack.empty()) {
      const uint32_t f = stack.back();
      stack.pop_back();
      for (uint32_t k = adjacency.offsets[f]; k < adjacency.offsets[f + 1]; ++k)
        if (!seen[adjacency.neighbours[k]]) seen[adjacency.neighbours[k]] = 1, stack.push_back(adjacency.neighbours[k]);
    }
  }
  return patches;
}

// VSA (thesis §6.3). A region count that cannot be met is adjusted (and reported), not refused:
// without pinned regions or seeds, at least one region per connected component (each needs its
// own) and, below the feature patches, regions_per_feature_patch per patch; at most one per
// triangle.
VsaSegmentation segment_regions(const PolygonMesh& tri, const SharpFeatures& features, const QuadRemeshOptions& o,
                                VsaOptions& vo, const TaskMonitor& monitor, QuadRemeshResult& r) {
  const bool use_features = o.crease_angle_degrees >= 0.0 || !o.sharp_edges.empty();
  if (!o.sharp_edges.empty()) {
    vo.barrier_edges = o.sharp_edges;
    std::sort(vo.barrier_edges.begin(), vo.barrier_edges.end());
    vo.barrier_edges.erase(std::unique(vo.barrier_edges.begin(), vo.barrier_edges.end()), vo.barrier_edges.end());
  }
  if (o.pinned_regions.empty() && o.seed_faces.empty()) {
    const size_t components =
        vo.barrier_edges.empty() ? count_face_components(tri) : count_sharp_edge_patches(tri, vo.barrier_edges);
    size_t wanted = std::max<size_t>(size_t(vo.region_count), components);
    size_t patches = 0;
    if (o.regions > 0 && o.regions_per_feature_patch > 0.0 && use_features && !features.edges.empty()) {
      patches = count_feature_patches(tri, features);
      const double by_patches = std::ceil(o.regions_per_feature_patch * double(patches));
      if (wanted < patches) wanted = std::max(wanted, std::min(size_t(std::max(o.max_regions, 1)), size_t(by_patches)));
    }
    vo.region_count = int(std::min<size_t>(wanted, tri.num_faces()));
    if (uint64_t(vo.region_count) != r.requested_regions)
      monitor.log(LogLevel::info, "quad-dominant remeshing: " + std::to_string(r.requested_regions) +
                                      " regions requested, " + std::to_string(vo.region_count) + " used (" +
                                      std::to_string(components) + " components, " + std::to_string(patches) +
                                      " feature patches, " + std::to_string(tri.num_faces()) + " triangles)");
  }
  if (size_t(vo.region_count) > tri.num_faces())
    fail(Status::invalid_argument, "quad-dominant remeshing: " + std::to_string(vo.region_count) +
                                       " regions requested but the mesh has " + std::to_string(tri.num_faces()) +
                                       " triangles");
  const VsaSegmentation segmentation = segment_vsa(tri, vo, monitor);
  r.l21_error = segmentation.total_area > 0.0 ? segmentation.total_error / segmentation.total_area : 0.0;
  return segmentation;
}

// What every layout attempt uses: the sample spacing δ, the element weights of the selection, the
// input's triangle normals, and the input's topology (the glued layout must keep its components
// and Euler characteristic).
struct LayoutSettings {
  ConstraintOptions constraints;
  SelectionOptions selection;
  std::vector<Vec3> normals;
  FaceTopology input_topology;
};

LayoutSettings layout_settings(const PolygonMesh& tri, const QuadRemeshOptions& o) {
  LayoutSettings s;
  s.constraints.spacing = spacing_from_bbox_fraction(tri, o.edge_length);
  s.selection.weights.triangle = o.triangle_weight;
  s.selection.weights.pentagon = o.pentagon_weight;
  s.selection.weights.t_joint = o.t_joint_weight;
  std::vector<double> areas;
  triangle_normals_and_areas(tri, s.normals, areas);
  s.input_topology = face_topology(tri);
  return s;
}

// One layout of the regions: their count, constraints (arcs, samples, LSCM domains), curve
// networks and selections, the samples with global ids, and the glued mesh.
struct RegionLayout {
  size_t region_count = 0;
  RemeshConstraints constraints;
  RegionQuadMeshes meshes;
  GlobalSamples samples;
  PolygonMesh glued;
  std::vector<Vec3> reference_normal;  // per glued face: the input normal under its centroid
};

// What the layout attempts carry from one to the next.
struct LayoutRetries {
  // The first layout whose only fault is a face folded against the input (kept until a retry
  // does better; returned, with flipped_faces reported, when none does).
  struct FoldedLayout {
    bool kept = false;
    std::vector<uint32_t> face_region;
    RegionLayout layout;
    uint64_t mended_faces = 0;
  } folded_layout;
  SelectionMemo memo;  // the regions a retry did not change are not selected again
  size_t previous_failures = SIZE_MAX;  // failing regions of the previous attempt
  bool previous_glued = false;          // whether the previous attempt got as far as gluing
  std::vector<uint8_t> kept_in_conflict;  // per region: kept whole when a glue conflict split its partner
  std::vector<uint32_t> repeat_partners;  // kept-whole partners in conflict again: merged into a neighbour
};

// The regions made disks with injective LSCM maps (thesis §6.4.3, disk_regions.h); splits made
// for it are counted and reported.
std::vector<RegionParameterization> disk_region_domains(const PolygonMesh& tri, const QuadRemeshOptions& o,
                                                        const TaskMonitor& monitor, size_t& region_count,
                                                        QuadRemeshResult& r) {
  DiskRegionReport disk;
  std::vector<RegionParameterization> domains =
      make_disk_regions(tri, r.face_region, region_count, o.pinned_regions.size(), {}, &disk, monitor);
  r.split_regions += disk.split_regions;
  if (disk.split_regions > 0)
    monitor.log(LogLevel::info, "quad-dominant remeshing: " + std::to_string(disk.split_regions) +
                                    " region split(s) for disk-like regions (" +
                                    std::to_string(disk.topology_splits) + " closed or with handles, " +
                                    std::to_string(disk.fold_splits) + " folded maps), " +
                                    std::to_string(region_count) + " regions");
  return domains;
}

// Every region's curve network and selection (thesis §6.5-6.7), then, when all of them
// succeeded, the sample-count refinement. Returns the regions that failed.
std::vector<RegionFailure> select_region_curves(const LayoutSettings& settings, const QuadRemeshOptions& o,
                                                const TaskMonitor& monitor, SelectionMemo& memo, RegionLayout& layout,
                                                QuadRemeshResult& r) {
  std::vector<BendingFitCache> fit_caches;  // for the refinement's rebuilds of the same regions
  std::vector<RegionFailure> failures;
  layout.meshes = select_region_quads(layout.constraints, CurveNetworkOptions{}, settings.selection, o.threads, monitor,
                                      o.sample_refinement_passes > 0 ? &fit_caches : nullptr, &failures, &memo);
  for (uint32_t region = 0; region < layout.meshes.selections.size(); ++region)
    if (layout.meshes.selections[region].invalid_faces > 0)
      failures.push_back({region, "quad-dominant remeshing: region " + std::to_string(region) + " has " +
                                      std::to_string(layout.meshes.selections[region].invalid_faces) +
                                      " invalid (flipped or hole) faces"});
  if (failures.empty() && o.sample_refinement_passes > 0) {
    const auto refinement_start = std::chrono::steady_clock::now();
    refine_sample_counts(layout.constraints, layout.meshes, settings.selection, fit_caches, o.sample_refinement_passes,
                         size_t(o.sample_refinement_max_curves), o.threads, monitor);
    r.refinement_seconds += seconds_since(refinement_start);
  }
  return failures;
}

// Post-processing (thesis §6.8): the regions' layouts glued by their shared samples, each
// region's mesh relaxed in its domain and its inner vertices placed on the input surface, then
// the glue conflicts mended. With `glue` false (a region failed) only the samples.
GluedLayout glue_regions(const PolygonMesh& tri, const std::vector<Vec3>& normals, const QuadRemeshOptions& o,
                         bool glue, const TaskMonitor& monitor, RegionLayout& layout, QuadRemeshResult& r) {
  layout.samples = global_samples(tri, layout.constraints);
  GluedLayout glued;
  glued.mesh.positions = layout.samples.positions;
  const size_t regions = layout.constraints.domains.size();
  for (uint32_t region = 0; glue && region < regions; ++region) {
    monitor.report("post-processing", 0.9 * double(region) / double(std::max<size_t>(1, regions)));
    const QuadSelection& s = layout.meshes.selections[region];
    const std::vector<uint32_t> point_ids = region_point_ids(layout.constraints, layout.samples, region);
    if (point_ids.size() != layout.meshes.networks[region].points.size())
      fail(Status::internal_error, "quad-dominant remeshing: region " + std::to_string(region) +
                                       ": network points do not match the constrained samples");
    std::vector<Vec2> uv;
    relax_region(s, o.relaxation_iterations, uv);
    RegionLocator locator{&tri, &layout.constraints.domains[region], {}};
    std::vector<uint32_t> global(uv.size());
    for (size_t v = 0; v < uv.size(); ++v) {
      if (s.vertex_point[v] >= 0) {
        global[v] = point_ids[size_t(s.vertex_point[v])];
        continue;
      }
      const RegionLocator::Hit hit = locator.locate(uv[v]);
      r.outside_domain_vertices += !hit.inside;
      global[v] = glued.mesh.add_vertex(locator.position(hit));
    }
    for (const std::vector<uint32_t>& face : s.faces) {
      std::vector<uint32_t> ids;
      std::vector<Vec2> corner_uv;
      Vec2 centroid{0.0, 0.0};
      for (uint32_t v : face) {
        ids.push_back(global[v]);
        corner_uv.push_back(uv[v]);
        centroid = centroid + uv[v];
      }
      glued.add_face(ids, corner_uv, region, normals[locator.locate(centroid * (1.0 / double(face.size()))).face]);
    }
  }
  if (glue) r.mended_faces = mend_glue_conflicts(glued, tri, layout.constraints, normals);
  return glued;
}

// The faults of a glued layout (`glued_region`: per glued face its region), as failures of the
// regions to split. Faces of two regions that coincide or fold onto each other (a duplicate face,
// an edge of three faces, a repeated vertex): the region of each pair with more triangles is
// split so that the boundary chains the two share go to different parts; a region whose boundary
// touches itself is split at that vertex (`conflict_split`: per region to split, the conflict it
// is split at). Without such conflicts: faces folded against the input, and a layout that does
// not keep the input's topology. Returns whether the layout's only fault is folded faces.
bool find_layout_faults(const RegionLayout& layout, const std::vector<uint32_t>& glued_region,
                        const std::vector<uint32_t>& face_region, const FaceTopology& input_topology, size_t pinned,
                        LayoutRetries& retries, std::vector<RegionFailure>& failures,
                        std::vector<GlueConflict>& conflict_split) {
  const size_t region_count = layout.region_count;
  const PolygonMesh& glued = layout.glued;
  std::vector<uint32_t> triangles_in(region_count, 0);
  for (const uint32_t region : face_region) ++triangles_in[region];
  // A partner kept whole in an earlier conflict that conflicts again (with the split region
  // or a part of it) is merged into its neighbour instead (polygon_mesh.off: a 4-triangle
  // island region inside region 0 whose hole region 0's layout covers, whichever is split).
  std::vector<uint8_t>& kept_in_conflict = retries.kept_in_conflict;
  std::vector<uint32_t>& repeat_partners = retries.repeat_partners;
  kept_in_conflict.resize(region_count, 0);
  repeat_partners.clear();
  for (GlueConflict c : glue_conflicts(glued, glued_region)) {
    if (c.region != c.other && triangles_in[c.other] > triangles_in[c.region]) std::swap(c.region, c.other);
    if (c.region != c.other && kept_in_conflict[c.other] && c.other >= pinned) repeat_partners.push_back(c.other);
    conflict_split.push_back(c);
  }
  for (const GlueConflict& c : conflict_split)
    if (c.region != c.other) kept_in_conflict[c.other] = 1;
  std::sort(repeat_partners.begin(), repeat_partners.end());
  repeat_partners.erase(std::unique(repeat_partners.begin(), repeat_partners.end()), repeat_partners.end());
  // One split per region: at a pinch if it has one, else between its first conflict's ends.
  std::stable_sort(conflict_split.begin(), conflict_split.end(), [](const GlueConflict& x, const GlueConflict& y) {
    if (x.region != y.region) return x.region < y.region;
    return (x.other == x.region) > (y.other == y.region);
  });
  conflict_split.erase(std::unique(conflict_split.begin(), conflict_split.end(),
                                   [](const GlueConflict& x, const GlueConflict& y) { return x.region == y.region; }),
                       conflict_split.end());
  // A face that folds against the input surface under it (a region's face flipped where the
  // region is thin): its region is split; if no retry unfolds them, the first such layout is
  // kept (flipped_faces reports them; the fit and the journey's checks judge the surface).
  if (conflict_split.empty()) {
    std::vector<uint8_t> folded(region_count, 0);
    std::vector<uint32_t> loop;
    for (uint32_t f = 0; f < glued.num_faces(); ++f) {
      loop.assign(glued.face_begin(f), glued.face_begin(f) + glued.face_size(f));
      if (!(dot(loop_normal(glued.positions, loop), layout.reference_normal[f]) > 0.0)) folded[glued_region[f]] = 1;
    }
    for (uint32_t rg = 0; rg < region_count; ++rg)
      if (folded[rg]) failures.push_back({rg, "region " + std::to_string(rg) + " has a face folded against the input"});
  }
  const size_t fold_failures = failures.size();
  // A layout that does not keep the input's topology (a region whose faces fill one of its
  // holes apart from the rest: the holes of a thin plate closed, a pillow left over them):
  // the regions whose faces lie in more than one component of the glued mesh are split.
  if (conflict_split.empty()) {
    const FaceTopology glued_topology = face_topology(glued);
    if (glued_topology.components != input_topology.components || glued_topology.euler != input_topology.euler) {
      std::vector<uint32_t> region_component(region_count, 0xffffffffu);
      std::vector<uint8_t> spread(region_count, 0);
      for (uint32_t f = 0; f < glued.num_faces(); ++f) {
        const uint32_t c = glued_topology.component[glued.face_vertex(f, 0)], rg = glued_region[f];
        if (region_component[rg] == 0xffffffffu) region_component[rg] = c;
        else if (region_component[rg] != c) spread[rg] = 1;
      }
      size_t listed = 0;
      for (uint32_t rg = 0; rg < region_count; ++rg)
        if (spread[rg]) {
          failures.push_back({rg, "region " + std::to_string(rg) +
                                      "'s faces fall apart in the glued mesh (it does not keep the input's "
                                      "topology)"});
          ++listed;
        }
      // Else the regions whose own faces do not have the Euler characteristic of a disk with
      // their holes (2 - loops): a layout that closes a tunnel inside one region (femur.off: an
      // annulus around a small tunnel laid out as a closed surface of 4 faces).
      if (listed == 0) {
        std::vector<std::unordered_set<uint32_t>> vertices(region_count);
        std::vector<std::unordered_set<uint64_t>> edges(region_count);
        std::vector<int64_t> faces(region_count, 0);
        for (uint32_t f = 0; f < glued.num_faces(); ++f) {
          const uint32_t rg = glued_region[f], n = glued.face_size(f);
          ++faces[rg];
          for (uint32_t k = 0; k < n; ++k) {
            vertices[rg].insert(glued.face_vertex(f, k));
            edges[rg].insert(edge_key(glued.face_vertex(f, k), glued.face_vertex(f, (k + 1) % n)));
          }
        }
        for (uint32_t rg = 0; rg < region_count; ++rg) {
          if (faces[rg] == 0 || rg >= layout.constraints.boundaries.region_loops.size()) continue;
          const int64_t euler = int64_t(vertices[rg].size()) - int64_t(edges[rg].size()) + faces[rg];
          const int64_t disk = 2 - int64_t(layout.constraints.boundaries.region_loops[rg].size());
          if (euler == disk) continue;
          failures.push_back({rg, "region " + std::to_string(rg) + "'s faces have Euler characteristic " +
                                      std::to_string(euler) + ", not " + std::to_string(disk) +
                                      " (it does not keep the input's topology)"});
          ++listed;
        }
      }
      if (listed == 0)
        failures.push_back({0, "the glued mesh has " + std::to_string(glued_topology.components) +
                                   " components and Euler characteristic " + std::to_string(glued_topology.euler) +
                                   ", the input " + std::to_string(input_topology.components) + " and " +
                                   std::to_string(input_topology.euler)});
    }
  }
  const bool only_folds = fold_failures > 0 && failures.size() == fold_failures;
  for (const GlueConflict& c : conflict_split)
    failures.push_back({c.region, "region " + std::to_string(c.region) +
                                      (c.region == c.other ? "'s boundary touches itself, its faces repeat a vertex"
                                                           : "'s faces coincide with or fold onto region " +
                                                                 std::to_string(c.other) + "'s")});
  return only_folds;
}

// Regions merged and split for the next layout attempt.
struct RegionChanges {
  size_t split = 0, merged = 0;
  bool none() const { return split == 0 && merged == 0; }
};

// After a failed layout, unless the retries are over: the sliver regions (no area in their
// loop) and repeated conflict partners merged into a neighbour, or, if none was merged, every
// failing region split in two (at its glue conflict when it has one).
RegionChanges merge_or_split_regions(const PolygonMesh& tri, const QuadRemeshOptions& o, int attempt, bool glued,
                                     const std::vector<RegionFailure>& failures,
                                     const std::vector<GlueConflict>& conflict_split, RegionLayout& layout,
                                     LayoutRetries& retries, std::vector<uint32_t>& face_region) {
  size_t& region_count = layout.region_count;
  size_t split = 0, merged = 0;
  // A retry that did not lower the number of failing regions ends the retries (cheese.off:
  // every split region's parts fail again, 4 layouts of 300 regions cost 30 s).
  // A retry that merges a repeated conflict partner is made even when the count did not drop.
  // An attempt that got as far as gluing after one whose selection failed made progress whatever
  // its count: the selection failures stopped the previous attempt before the glued layout's
  // faults could be counted (femur.off: a sliver merged, then a folded face and a closed tunnel).
  // A glued layout with few failing regions (at most retry_few_failing_share of them) is retried
  // whatever its count: each split mends its regions locally, and a part or a neighbour failing
  // next is no sign that the splits do not converge (femur.off: 6, 1, 2, 2, 1, 6, 2 failing of
  // about 170 regions; b9_mesh.off at 157 regions: 14, 10, 1, 4, 4, 2, then none). Only the
  // regions a split changed are selected again (the memo).
  // Once a layout whose only fault is folded faces is kept (a result exists), retries need the
  // count to drop again, as before (cheese.off at 200 regions: 3, then 24 folding regions kept).
  const bool few = glued && !retries.folded_layout.kept &&
                   double(failures.size()) <= o.retry_few_failing_share * double(region_count);
  const bool retry = attempt + 1 < o.layout_attempts &&
                     (few || failures.size() < retries.previous_failures || (glued && !retries.previous_glued) ||
                      (!retries.repeat_partners.empty() && failures.size() <= retries.previous_failures));
  retries.previous_failures = failures.size();
  retries.previous_glued = glued;
  if (retry) {
    std::vector<uint32_t> slivers;
    for (const RegionFailure& failure : failures)
      if (failure.degenerate_boundary && failure.region >= o.pinned_regions.size()) slivers.push_back(failure.region);
    slivers.insert(slivers.end(), retries.repeat_partners.begin(), retries.repeat_partners.end());
    merged = merge_into_neighbours(tri, face_region, region_count, o.pinned_regions.size(), slivers);
    if (merged > 0) retries.kept_in_conflict.clear();  // the regions were renumbered
  }
  if (retry && merged == 0)
    for (const RegionFailure& failure : failures) {
      if (failure.region < o.pinned_regions.size()) continue;
      size_t size = 0;
      for (const uint32_t region : face_region) size += region == failure.region;
      const auto conflict = std::lower_bound(
          conflict_split.begin(), conflict_split.end(), failure.region,
          [](const GlueConflict& c, uint32_t region) { return c.region < region; });
      std::vector<uint32_t> second;
      if (conflict != conflict_split.end() && conflict->region == failure.region)
        second = conflict->other == failure.region
                     ? split_region_at_pinch(tri, face_region, failure.region)
                     : split_region_between(tri, face_region, failure.region, layout.glued.positions[conflict->u],
                                            layout.glued.positions[conflict->v]);
      else {
        std::vector<uint32_t> faces;
        for (uint32_t f = 0; f < face_region.size(); ++f)
          if (face_region[f] == failure.region) faces.push_back(f);
        second = split_region_in_two(tri, faces);
      }
      if (second.empty() || second.size() == size) continue;
      for (const uint32_t f : second) face_region[f] = uint32_t(region_count);
      ++region_count;
      ++split;
    }
  return {split, merged};
}

// When no retry changes the regions any more: the kept layout whose only fault is folded faces
// becomes the result.
void take_folded_layout(const TaskMonitor& monitor, LayoutRetries::FoldedLayout& folded_layout, RegionLayout& layout,
                        QuadRemeshResult& r) {
  monitor.log(LogLevel::info, "quad-dominant remeshing: the retries did not unfold every face; the first layout "
                              "with folded faces only is kept");
  layout = std::move(folded_layout.layout);
  r.face_region = std::move(folded_layout.face_region);
  r.mended_faces = folded_layout.mended_faces;
}

// The failures of the last layout as the error (no retry changed the regions).
[[noreturn]] void fail_layout(const std::vector<RegionFailure>& failures) {
  std::string message = failures.front().message;
  if (failures.size() > 1) message += " (and " + std::to_string(failures.size() - 1) + " more regions)";
  fail(Status::internal_error,
       message.rfind("quad-dominant", 0) == 0 ? message : "quad-dominant remeshing: " + message);
}

// A layout redone: counted, and reported with its first failure.
void record_retry(const std::vector<RegionFailure>& failures, const RegionChanges& changes, const TaskMonitor& monitor,
                  QuadRemeshResult& r) {
  const size_t split = changes.split, merged = changes.merged;
  r.split_regions += split;
  r.merged_regions += merged;
  r.layout_retries += 1;
  const std::string& first_message = failures.front().message;
  monitor.log(LogLevel::info, (first_message.rfind("quad-dominant", 0) == 0 ? "" : "quad-dominant remeshing: ") +
                                  first_message +
                                  (failures.size() > 1 ? " (and " + std::to_string(failures.size() - 1) + " more)"
                                                       : std::string()) +
                                  "; " + std::to_string(merged) + " sliver region(s) merged, " +
                                  std::to_string(split) + " region(s) split, layout redone");
}

// Simple cycles of a closed loop of point ids that may pass a point more than once (a region
// boundary that touches itself): each repeat closes the cycle walked since the point's previous
// visit. Positions index `ids`.
std::vector<std::vector<uint32_t>> simple_cycles(const std::vector<uint32_t>& ids) {
  std::vector<std::vector<uint32_t>> cycles;
  std::vector<uint32_t> stack;  // positions
  std::unordered_map<uint32_t, size_t> depth;  // id -> index in stack
  for (uint32_t k = 0; k < ids.size(); ++k) {
    const auto it = depth.find(ids[k]);
    if (it != depth.end()) {
      const size_t from = it->second;
      cycles.emplace_back(stack.begin() + long(from), stack.end());
      for (size_t i = from + 1; i < stack.size(); ++i) depth.erase(ids[stack[i]]);
      stack.resize(from + 1);
      continue;
    }
    depth[ids[k]] = stack.size();
    stack.push_back(k);
  }
  cycles.push_back(stack);
  cycles.erase(std::remove_if(cycles.begin(), cycles.end(), [](const std::vector<uint32_t>& c) { return c.size() < 3; }),
               cycles.end());
  return cycles;
}

// The cells of a planar polygon with holes (positions into `uv`): the quad-dominant partition of
// thesis §3.4 (no Steiner points, convex cells) when the polygon is valid in the domain, else,
// for a polygon without holes, the loop itself as one cell. Empty when neither applies.
std::vector<std::vector<uint32_t>> polygon_cells(const std::vector<Vec2>& uv, const std::vector<std::vector<uint32_t>>& loops) {
  PolygonLoops polygon;
  std::vector<uint32_t> position;  // polygon point -> position in uv
  for (const std::vector<uint32_t>& loop : loops) {
    polygon.loops.emplace_back();
    for (uint32_t k : loop) {
      polygon.loops.back().push_back(uint32_t(polygon.points.size()));
      polygon.points.push_back(uv[k]);
      position.push_back(k);
    }
  }
  std::vector<std::vector<uint32_t>> cells;
  if (check_polygon_loops(polygon).ok()) {
    std::vector<std::array<uint32_t, 3>> triangles;
    triangulate_valid_polygon(polygon, triangles);
    for (std::vector<uint32_t> cell : partition_quad_dominant(polygon, triangles).cells) {
      for (uint32_t& p : cell) p = position[p];
      cells.push_back(std::move(cell));
    }
  } else if (loops.size() == 1) {
    cells.push_back(loops[0]);
  }
  return cells;
}

// Region `region`'s layout replaced by the simplest valid one over its samples: the cells of its
// domain polygon (polygon_cells; a boundary that touches itself cut into simple cycles first). No
// inner vertex. False when the region has none (an invalid domain with holes).
bool use_polygon_cells(RegionLayout& layout, uint32_t region) {
  const std::vector<uint32_t> ids = region_point_ids(layout.constraints, layout.samples, region);
  std::vector<Vec2> uv;
  std::vector<std::vector<uint32_t>> loops;
  CurveNetwork network;
  for (size_t l = 0; l < layout.constraints.boundaries.region_loops[region].size(); ++l) {
    network.loop_begin.push_back(uint32_t(uv.size()));
    loops.emplace_back();
    for (const Vec2& p : layout.constraints.loop_samples_uv(region, l)) {
      loops.back().push_back(uint32_t(uv.size()));
      uv.push_back(p);
    }
  }
  network.loop_begin.push_back(uint32_t(uv.size()));
  if (ids.size() != uv.size()) return false;
  std::vector<std::vector<uint32_t>> cells;
  const std::vector<std::vector<uint32_t>> cycles = loops.size() == 1 ? simple_cycles(ids) : loops;
  if (loops.size() == 1 && !(cycles.size() == 1 && cycles[0].size() == ids.size())) {
    for (const std::vector<uint32_t>& cycle : cycles)
      for (std::vector<uint32_t>& cell : polygon_cells(uv, {cycle})) cells.push_back(std::move(cell));
  } else {
    cells = polygon_cells(uv, loops);
  }
  if (cells.empty()) return false;
  network.points.resize(uv.size());
  QuadSelection selection;
  selection.vertices = uv;
  for (uint32_t k = 0; k < uv.size(); ++k) {
    network.points[k].uv = uv[k];
    selection.vertex_point.push_back(int64_t(k));
  }
  for (const std::vector<uint32_t>& cell : cells) {
    const size_t n = cell.size();
    selection.quads += n == 4, selection.triangles += n == 3, selection.pentagons += n == 5, selection.larger += n > 5;
  }
  selection.faces = std::move(cells);
  // The totals lose the replaced selection (the cells have no energy of the selection's).
  RegionQuadMeshes& meshes = layout.meshes;
  meshes.energy -= meshes.selections[region].energy;
  meshes.faces += selection.faces.size() - meshes.selections[region].faces.size();
  meshes.quads += selection.quads - meshes.selections[region].quads;
  meshes.networks[region] = std::move(network);
  meshes.selections[region] = std::move(selection);
  return true;
}

// The last resort (issue 19), when no retry changes the regions any more: every failing region
// gets the simplest valid layout over its samples (use_polygon_cells), and the layout is glued
// and its faults found again, for a few rounds (a region next to one given cells can fail
// next). True when a layout without faults came out, or one whose only faults are folded faces
// that no further round changes (what take_folded_layout accepts too); the regions given cells
// are reported in partitioned_regions.
bool lay_out_failing_regions_by_cells(const PolygonMesh& tri, const LayoutSettings& settings,
                                      const QuadRemeshOptions& o, const TaskMonitor& monitor,
                                      std::vector<RegionFailure> failures, LayoutRetries& retries, RegionLayout& layout,
                                      QuadRemeshResult& r) {
  constexpr int kRounds = 4;
  if (layout.meshes.selections.size() != layout.region_count) return false;
  std::vector<uint8_t> partitioned(layout.region_count, 0);
  for (int round = 0; round < kRounds; ++round) {
    size_t added = 0;
    for (const RegionFailure& failure : failures) {
      const uint32_t region = failure.region;
      if (region >= layout.region_count || partitioned[region]) continue;
      if (!use_polygon_cells(layout, region)) return false;
      partitioned[region] = 1;
      ++added;
    }
    GluedLayout glued = glue_regions(tri, settings.normals, o, true, monitor, layout, r);
    layout.glued = std::move(glued.mesh);
    layout.reference_normal = std::move(glued.reference_normal);
    failures.clear();
    std::vector<GlueConflict> conflict_split;
    const bool only_folds = find_layout_faults(layout, glued.region, r.face_region, settings.input_topology,
                                               o.pinned_regions.size(), retries, failures, conflict_split);
    if (failures.empty() || (only_folds && added == 0)) {
      r.partitioned_regions = uint64_t(std::count(partitioned.begin(), partitioned.end(), uint8_t(1)));
      monitor.log(LogLevel::info, "quad-dominant remeshing: " + std::to_string(r.partitioned_regions) +
                                      " region(s) whose layout failed laid out by the quad-dominant partition of "
                                      "their domain polygon" +
                                      (failures.empty() ? std::string() : std::string(" (folded faces left)")));
      return true;
    }
    if (added == 0) return false;
  }
  return false;
}

// Steps 1-4 of ch. 6 and the gluing (§6.8), per layout attempt: disk regions with their LSCM
// domains, arcs and samples, every region's curve network and selection, the glued mesh and its
// faults. A region whose network, selection or glued faces fail is split in two (or merged into
// a neighbour) and the layout redone, at most o.layout_attempts times.
RegionLayout lay_out_regions(const PolygonMesh& tri, const VsaSegmentation& segmentation, const QuadRemeshOptions& o,
                             const TaskMonitor& monitor, QuadRemeshResult& r) {
  r.face_region = segmentation.face_region;
  RegionLayout layout;
  layout.region_count = segmentation.num_regions();
  const LayoutSettings settings = layout_settings(tri, o);
  LayoutRetries retries;
  for (int attempt = 0;; ++attempt) {
    auto t = std::chrono::steady_clock::now();
    std::vector<RegionParameterization> domains = disk_region_domains(tri, o, monitor, layout.region_count, r);
    layout.constraints =
        compute_remesh_constraints(tri, r.face_region, layout.region_count, settings.constraints, monitor, &domains);
    r.constraint_seconds += seconds_since(t);

    t = std::chrono::steady_clock::now();
    std::vector<RegionFailure> failures = select_region_curves(settings, o, monitor, retries.memo, layout, r);
    r.selection_seconds += seconds_since(t);
    const bool selected = failures.empty();  // every region selected: the layout is glued

    t = std::chrono::steady_clock::now();
    GluedLayout glued = glue_regions(tri, settings.normals, o, selected, monitor, layout, r);
    layout.glued = std::move(glued.mesh);
    layout.reference_normal = std::move(glued.reference_normal);
    std::vector<GlueConflict> conflict_split;  // per region to split (by region): the conflict it is split at
    bool only_folds = false;  // this layout's only fault: faces folded against the input
    if (selected)
      only_folds = find_layout_faults(layout, glued.region, r.face_region, settings.input_topology,
                                      o.pinned_regions.size(), retries, failures, conflict_split);
    r.postprocess_seconds += seconds_since(t);
    if (failures.empty()) break;

    if (only_folds && !retries.folded_layout.kept)
      retries.folded_layout = {true, r.face_region, layout, r.mended_faces};
    const RegionChanges changes =
        merge_or_split_regions(tri, o, attempt, selected, failures, conflict_split, layout, retries, r.face_region);
    if (changes.none() && retries.folded_layout.kept) {
      take_folded_layout(monitor, retries.folded_layout, layout, r);
      break;
    }
    if (changes.none()) {
      if (lay_out_failing_regions_by_cells(tri, settings, o, monitor, failures, retries, layout, r)) break;
      fail_layout(failures);
    }
    record_retry(failures, changes, monitor, r);
  }
  return layout;
}

// The layout's figures in the result.
void report_layout(const RegionLayout& layout, QuadRemeshResult& r) {
  r.regions = layout.region_count;
  r.energy = layout.meshes.energy;
  for (const QuadSelection& s : layout.meshes.selections) r.phase1_energy += s.phase1_energy;
  r.arcs = layout.constraints.arcs.size();
  for (const ArcConstraint& arc : layout.constraints.arcs) r.arc_segments.push_back(uint32_t(arc.samples.t.size() - 1));
  r.samples = layout.samples.positions.size();
}

// The glued mesh as the cage's mesh, without the samples no face uses (none expected: every
// boundary edge of a region is a face edge). Returns the cage vertex of every glued vertex
// (0xffffffff: dropped).
std::vector<uint32_t> move_glued_mesh_into(PolygonMesh& glued, PolygonMesh& mesh) {
  std::vector<uint32_t> remap(glued.num_vertices(), 0xffffffffu);
  for (uint32_t& v : glued.face_vertices) {
    if (remap[v] == 0xffffffffu) remap[v] = mesh.add_vertex(glued.positions[v]);
    v = remap[v];
  }
  mesh.face_offsets = glued.face_offsets;
  mesh.face_vertices = glued.face_vertices;
  return remap;
}

// Faces whose normal disagrees with the input normal under their centroid (flipped_faces).
uint64_t count_flipped_faces(const PolygonMesh& mesh, const std::vector<Vec3>& reference_normal) {
  uint64_t flipped = 0;
  std::vector<uint32_t> loop;
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    loop.assign(mesh.face_begin(f), mesh.face_begin(f) + mesh.face_size(f));
    flipped += !(dot(loop_normal(mesh.positions, loop), reference_normal[f]) > 0.0);
  }
  return flipped;
}

// Unit vertex normals from the faces' vector areas (for the quality figures).
std::vector<Vec3> area_weighted_vertex_normals(const PolygonMesh& mesh) {
  std::vector<Vec3> vertex_normals(mesh.num_vertices(), Vec3{});
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const Vec3 area = mesh.face_vector_area(f);
    for (uint32_t k = 0; k < mesh.face_size(f); ++k) vertex_normals[mesh.face_vertex(f, k)] += area;
  }
  for (Vec3& n : vertex_normals) n = normalized(n);
  return vertex_normals;
}

// Creases on sharp interior arcs. A region boundary is made of input edges and VSA splits at
// features, so a piece's input edges count when they are sharp edges themselves (a boundary
// beside a feature, one triangle off, is not creased: counting edges with both ends near a
// feature, the organic meshes' crease density rose from 4.7 % to 8.6 %; edges_along_features,
// 2.8 -> 8.5 %).
void tag_creases(const RegionLayout& layout, const SharpFeatures& features, const std::vector<uint32_t>& remap,
                 QuadRemeshResult& r) {
  const RemeshConstraints& constraints = layout.constraints;
  std::unordered_set<uint64_t> tagged;
  for (uint32_t a = 0; a < constraints.arcs.size(); ++a) {
    const RegionArc& arc = constraints.boundaries.arcs[a];
    if (arc.right_region == kMeshBorder) continue;
    const std::vector<double> share = piece_sharp_share(features, arc, constraints.arcs[a]);
    const std::vector<uint32_t> ids = layout.samples.arc_ids(constraints, a);
    bool sharp = false;
    for (size_t k = 0; k + 1 < ids.size(); ++k) {
      if (!(share[k] >= 0.5)) continue;
      sharp = true;
      const uint32_t v0 = remap[ids[k]], v1 = remap[ids[k + 1]];
      if (v0 == 0xffffffffu || v1 == 0xffffffffu || !tagged.insert(edge_key(v0, v1)).second) continue;
      r.cage.creases.push_back({v0, v1, kSharpnessInfinite});
    }
    r.crease_arcs += sharp;
  }
}

// The cage checked (an invalid one is an internal error) and its quality measured.
void validate_and_measure(const std::vector<Vec3>& vertex_normals, QuadRemeshResult& r) {
  const ValidationReport check = validate_cage(r.cage, 4);
  if (!check.ok())
    fail(Status::internal_error, "quad-dominant remeshing produced an invalid mesh: " + check.summary());
  static_cast<RemeshQuality&>(r) = measure_remesh_quality(r.cage.mesh, vertex_normals);
}

void log_timing(const QuadRemeshResult& r, size_t region_count, const TaskMonitor& monitor) {
  char timing[256];
  std::snprintf(timing, sizeof timing,
                "quad-dominant remeshing: %zu faces, %zu regions in %.2f s (segmentation %.2f, disk regions and "
                "constraints %.2f, selection %.2f of which sample-count refinement %.2f, post-processing %.2f; %llu "
                "layout retries)",
                r.cage.mesh.num_faces(), region_count, r.seconds, r.segmentation_seconds, r.constraint_seconds,
                r.selection_seconds, r.refinement_seconds, r.postprocess_seconds, (unsigned long long)r.layout_retries);
  monitor.log(LogLevel::info, timing);
}


// One segmentation's regions laid out (§6.4-6.8, retried) and made into the cage: the glued
// mesh, its creases, validation and quality figures.
void build_cage(const PolygonMesh& tri, const VsaSegmentation& segmentation, const SharpFeatures& features,
                const QuadRemeshOptions& o, const TaskMonitor& monitor, QuadRemeshResult& r) {
  RegionLayout layout = lay_out_regions(tri, segmentation, o, monitor, r);
  report_layout(layout, r);
  const auto t = std::chrono::steady_clock::now();
  const std::vector<uint32_t> remap = move_glued_mesh_into(layout.glued, r.cage.mesh);
  r.flipped_faces = count_flipped_faces(r.cage.mesh, layout.reference_normal);
  const std::vector<Vec3> vertex_normals = area_weighted_vertex_normals(r.cage.mesh);
  if (o.crease_angle_degrees >= 0.0 || !o.sharp_edges.empty()) tag_creases(layout, features, remap, r);
  r.creases = r.cage.creases.size();
  monitor.report("post-processing", 0.95);
  validate_and_measure(vertex_normals, r);
  r.postprocess_seconds += seconds_since(t);
}

// Re-seeding (QuadRemeshOptions::reseed_factors): the next region count after a segmentation
// whose layout failed, or 0 when there is none (no factor left, or not more regions than the
// failed segmentation had).
size_t reseed_region_count(const QuadRemeshOptions& o, size_t reseeds, size_t first_count, size_t failed_count,
                           size_t triangles) {
  if (reseeds >= o.reseed_factors.size() || !(o.reseed_factors[reseeds] > 0.0)) return 0;
  const double wanted = std::ceil(o.reseed_factors[reseeds] * double(first_count));
  const size_t count = wanted >= double(triangles) ? triangles : size_t(wanted);
  return count > failed_count ? count : 0;
}

}  // namespace

QuadRemeshResult remesh_quad_dominant(const PolygonMesh& input, const QuadRemeshOptions& o, const TaskMonitor& monitor) {
  const auto start = std::chrono::steady_clock::now();
  check_options(o);
  const PolygonMesh tri = triangulated_input(input);
  QuadRemeshResult r;

  // Segmentation (§6.3).
  VsaOptions vo = vsa_options(input, o);
  r.requested_regions = uint64_t(vo.region_count);
  const SharpFeatures features = sharp_input_features(tri, o);
  VsaSegmentation segmentation = segment_regions(tri, features, o, vo, monitor, r);
  r.segmentation_seconds = seconds_since(start);
  const size_t first_count = segmentation.num_regions();

  // Disk regions, arcs and samples, curve networks and selections, gluing (§6.4-6.8), retried,
  // and the cage; a layout that no retry makes valid is re-seeded with more regions.
  for (size_t reseeds = 0;; ++reseeds) {
    QuadRemeshResult attempt = r;  // the figures before the layout (times accumulate)
    try {
      build_cage(tri, segmentation, features, o, monitor, attempt);
      r = std::move(attempt);
      break;
    } catch (const Error& e) {
      const size_t count =
          e.status() == Status::internal_error
              ? reseed_region_count(o, reseeds, first_count, segmentation.num_regions(), tri.num_faces())
              : 0;
      if (count == 0) throw;
      monitor.log(LogLevel::info, std::string(e.what()) + "; re-seeded with " + std::to_string(count) +
                                      " regions (" + std::to_string(segmentation.num_regions()) + " before)");
      r.constraint_seconds = attempt.constraint_seconds;
      r.selection_seconds = attempt.selection_seconds;
      r.refinement_seconds = attempt.refinement_seconds;
      r.postprocess_seconds = attempt.postprocess_seconds;
      const auto t = std::chrono::steady_clock::now();
      vo.region_count = int(count);
      vo.tolerance = -1.0;  // count mode
      segmentation = segment_vsa(tri, vo, monitor);
      r.l21_error = segmentation.total_area > 0.0 ? segmentation.total_error / segmentation.total_area : 0.0;
      r.reseeded_regions = count;
      r.segmentation_seconds += seconds_since(t);
    }
  }
  monitor.report("post-processing", 1.0);
  r.seconds = seconds_since(start);
  log_timing(r, r.regions, monitor);
  return r;
}

CAGEKIT_NAMESPACE_END
