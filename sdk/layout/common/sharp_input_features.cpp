// SPDX-License-Identifier: GPL-3.0-or-later
// Sharp input features (the shared crease definition); see sharp_input_features.h.
#include "layout/common/sharp_input_features.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>
#include <unordered_map>

#include "core/angles.h"
#include "core/edge_map.h"
#include "core/status.h"
#include "layout/common/feature_edges.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

// An input edge runs along the features when a path over them joins its ends at most this many
// times its length (a corner cut: sqrt(2); the chord of a curved line: about 1).
constexpr double kDetourFactor = 2.0;
// Else it follows them when its midpoint is no farther from them than its farther end plus this
// share of its length (an edge joining two feature lines: about a half).
constexpr double kMidpointSlack = 0.25;
// Else, between two feature vertices, when it bends by this share of the feature angle.
constexpr double kRungFraction = 0.5;

void check_input(const PolygonMesh& mesh, const SharpFeatureOptions& o) {
  if (!(o.angle_degrees >= 0.0 && o.angle_degrees <= 180.0))
    fail(Status::invalid_argument, "sharp features: the angle must be in [0, 180] degrees");
  if (o.side_rings < 0 || o.side_rings > 8)
    fail(Status::invalid_argument, "sharp features: side rings must be in [0, 8]");
  if (!(o.confirm_fraction >= 0.0 && o.confirm_fraction <= 1.0))
    fail(Status::invalid_argument, "sharp features: the confirming fraction must be in [0, 1]");
  if (!(o.max_turn_degrees >= 0.0 && o.max_turn_degrees <= 180.0))
    fail(Status::invalid_argument, "sharp features: the maximum turn must be in [0, 180] degrees");
  if (!(o.max_side_bend_fraction >= 0.0 && o.max_side_bend_fraction <= 1.0))
    fail(Status::invalid_argument, "sharp features: the side bend fraction must be in [0, 1]");
  if (!(o.min_length_rel >= 0.0) || !std::isfinite(o.min_length_rel))
    fail(Status::invalid_argument, "sharp features: the minimum length must be finite and >= 0");
  check_feature_input(mesh, "sharp features");
}

// Faces around each vertex (CSR: faces of v are around[first[v] .. first[v + 1])).
struct VertexFaces {
  std::vector<uint32_t> first, around;
  explicit VertexFaces(const PolygonMesh& mesh) : first(mesh.num_vertices() + 1, 0), around(mesh.face_vertices.size()) {
    for (uint32_t v : mesh.face_vertices) ++first[v + 1];
    for (size_t v = 0; v + 1 < first.size(); ++v) first[v + 1] += first[v];
    std::vector<uint32_t> fill(first.begin(), first.end() - 1);
    for (size_t f = 0; f < mesh.num_faces(); ++f)
      for (uint32_t k = 0; k < mesh.face_size(f); ++k) around[fill[mesh.face_vertex(f, k)]++] = uint32_t(f);
  }
};

// Unit direction in face f's plane, perpendicular to the edge a -> b, pointing into the face
// (from the edge towards the face's centroid).
Vec3 into_face(const Vec3& a, const Vec3& b, const Vec3& centroid) {
  const Vec3 e = normalized(b - a), c = centroid - a;
  return normalized(c - e * dot(c, e));
}

}  // namespace

namespace {
// The side normals of edge (a, b) between faces f0 and f1: the area-weighted mean normal of the
// faces within `rings` vertex rings of the edge on f0's side and on f1's side, each face's side
// told by its centroid's position across the edge (not by its normal, which would bias the
// means towards the two faces' own normals). The angle between them is the edge's dihedral
// angle measured over a neighbourhood: noise averages out, a feature line keeps its angle.
double side_angle_cos(const PolygonMesh& mesh, const VertexFaces& vf, const std::vector<Vec3>& normal,
                      const std::vector<double>& area, const std::vector<Vec3>& centroid, uint32_t a, uint32_t b,
                      uint32_t f0, uint32_t f1, int rings, std::vector<uint32_t>& faces, std::vector<uint32_t>& verts) {
  const Vec3 &pa = mesh.positions[a], &pb = mesh.positions[b];
  const Vec3 mid = (pa + pb) * 0.5;
  const Vec3 side = into_face(pa, pb, centroid[f0]) - into_face(pa, pb, centroid[f1]);
  verts.assign({a, b});
  faces.clear();
  for (int ring = 0; ring < rings; ++ring) {
    const size_t known = verts.size();
    for (size_t i = 0; i < known; ++i)
      for (uint32_t k = vf.first[verts[i]]; k < vf.first[verts[i] + 1]; ++k) faces.push_back(vf.around[k]);
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    if (ring + 1 == rings) break;
    for (uint32_t f : faces)
      for (uint32_t k = 0; k < mesh.face_size(f); ++k) verts.push_back(mesh.face_vertex(f, k));
    std::sort(verts.begin(), verts.end());
    verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  }
  Vec3 n0{}, n1{};
  for (uint32_t g : faces) {
    const double s = dot(centroid[g] - mid, side);
    if (g == f0 || (g != f1 && s > 0.0)) n0 += normal[g] * area[g];
    else if (g == f1 || s < 0.0) n1 += normal[g] * area[g];
  }
  return dot(normalized(n0), normalized(n1));
}
}  // namespace

namespace {
// Test 4's measure for sharp edge e (its dihedral angle bend[e]): the mean dihedral angle of the
// edges beside it, on its smoother side, as a fraction of its own. The edges beside it are the
// other two-face edges at its two ends, each on the side of e its far end lies on, leaving out
// the raw sharp ones (other features) and the rungs of a feature line that zigzags over a dense
// tessellation (bending by half the feature angle between two vertices on raw sharp edges). A
// side without such edges is flat: 0.
double side_bend_fraction(const PolygonMesh& mesh, const detail::EdgeMap& map, const std::vector<uint32_t>& first,
                          const std::vector<uint32_t>& around, const std::vector<uint8_t>& raw,
                          const std::vector<uint8_t>& on_raw, const std::vector<double>& bend,
                          const std::vector<Vec3>& centroid, double angle_degrees, size_t e) {
  const uint32_t* h = map.corners_begin(e);
  const uint32_t lo = map.edge_lo[e], hi = map.edge_hi[e];
  const Vec3 &pa = mesh.positions[lo], &pb = mesh.positions[hi], mid = (pa + pb) * 0.5;
  const Vec3 side = into_face(pa, pb, centroid[map.corner_face[h[0]]]) - into_face(pa, pb, centroid[map.corner_face[h[1]]]);
  double sum[2] = {0.0, 0.0};
  int count[2] = {0, 0};
  for (uint32_t v : {lo, hi})
    for (uint32_t k = first[v]; k < first[v + 1]; ++k) {
      const uint32_t x = around[k];
      if (x == e || raw[x] || bend[x] < 0.0) continue;
      const uint32_t w = map.edge_lo[x] == v ? map.edge_hi[x] : map.edge_lo[x];
      if (bend[x] >= 0.5 * angle_degrees && on_raw[v] && on_raw[w]) continue;  // a rung
      const int s = dot(mesh.positions[w] - mid, side) > 0.0 ? 0 : 1;
      sum[s] += bend[x];
      ++count[s];
    }
  const double smoother = std::min(count[0] ? sum[0] / count[0] : 0.0, count[1] ? sum[1] / count[1] : 0.0);
  return smoother / bend[e];
}

// Per edge, 1 where it is sharp (after tests 1-2) and its feature network (the sharp edges
// connected through shared vertices) has a length-weighted mean side_bend_fraction above
// `max_fraction`: the web of a coarsely faceted smooth surface, not a feature line.
std::vector<uint8_t> faceted_networks(const PolygonMesh& mesh, const detail::EdgeMap& map, const std::vector<uint8_t>& raw,
                                      const std::vector<uint8_t>& sharp, const std::vector<double>& bend,
                                      const std::vector<Vec3>& centroid, const std::vector<double>& edge_length,
                                      double angle_degrees, double max_fraction) {
  const size_t nv = mesh.num_vertices(), ne = map.num_edges();
  std::vector<uint8_t> faceted(ne, 0);
  if (max_fraction >= 1.0) return faceted;  // the fraction never exceeds 1: nothing to drop
  std::vector<uint32_t> first(nv + 1, 0), around(2 * ne);  // edges at each vertex (CSR)
  for (size_t e = 0; e < ne; ++e) ++first[map.edge_lo[e] + 1], ++first[map.edge_hi[e] + 1];
  for (size_t v = 0; v < nv; ++v) first[v + 1] += first[v];
  {
    std::vector<uint32_t> fill(first.begin(), first.end() - 1);
    for (size_t e = 0; e < ne; ++e) around[fill[map.edge_lo[e]]++] = uint32_t(e), around[fill[map.edge_hi[e]]++] = uint32_t(e);
  }
  std::vector<uint8_t> on_raw(nv, 0);
  for (size_t e = 0; e < ne; ++e)
    if (raw[e]) on_raw[map.edge_lo[e]] = on_raw[map.edge_hi[e]] = 1;
  detail::UnionFind network(nv);
  for (size_t e = 0; e < ne; ++e)
    if (sharp[e]) network.unite(map.edge_lo[e], map.edge_hi[e]);
  std::vector<double> length(nv, 0.0), weighted(nv, 0.0);  // per network (its root vertex)
  for (size_t e = 0; e < ne; ++e) {
    if (!sharp[e]) continue;
    const uint32_t root = network.find(map.edge_lo[e]);
    length[root] += edge_length[e];
    weighted[root] += edge_length[e] *
                      side_bend_fraction(mesh, map, first, around, raw, on_raw, bend, centroid, angle_degrees, e);
  }
  for (size_t e = 0; e < ne; ++e) {
    if (!sharp[e]) continue;
    const uint32_t root = network.find(map.edge_lo[e]);
    faceted[e] = weighted[root] > max_fraction * length[root];
  }
  return faceted;
}
}  // namespace

namespace {

// The host's edges joined to `out` (sorted keys, corner flags, length); each must be a mesh edge.
void add_host_edges(const PolygonMesh& mesh, const std::vector<uint64_t>& host, SharpFeatures& out) {
  std::vector<uint64_t> keys = host;
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  std::vector<uint8_t> found(keys.size(), 0);
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t n = mesh.face_size(f);
    for (uint32_t k = 0; k < n; ++k) {
      const uint32_t a = mesh.face_vertex(f, k), b = mesh.face_vertex(f, (k + 1) % n);
      const auto it = std::lower_bound(keys.begin(), keys.end(), edge_key(a, b));
      if (it == keys.end() || *it != edge_key(a, b)) continue;
      out.corner_flags[mesh.face_offsets[f] + k] = 1;
      found[size_t(it - keys.begin())] = 1;
    }
  }
  std::vector<uint64_t> added;
  for (size_t i = 0; i < keys.size(); ++i) {
    const uint32_t a = edge_key_first(keys[i]), b = edge_key_second(keys[i]);
    if (!found[i])
      fail(Status::invalid_argument, "sharp features: host edge (" + std::to_string(a) + ", " + std::to_string(b) +
                                         ") is not an edge of the mesh");
    if (std::binary_search(out.edges.begin(), out.edges.end(), keys[i])) continue;
    added.push_back(keys[i]);
    out.length += norm(mesh.positions[b] - mesh.positions[a]);
  }
  out.host_edges = keys.size();
  std::vector<uint64_t> merged;
  std::merge(out.edges.begin(), out.edges.end(), added.begin(), added.end(), std::back_inserter(merged));
  out.edges.swap(merged);
}

SharpFeatures detected_sharp_features(const PolygonMesh& mesh, const SharpFeatureOptions& o, const TaskMonitor& monitor) {
  SharpFeatures out;
  out.corner_flags.assign(mesh.num_face_vertices(), 0);
  const size_t nf = mesh.num_faces();
  if (nf == 0) return out;
  std::vector<Vec3> normal(nf);
  std::vector<double> area(nf);
  for (size_t f = 0; f < nf; ++f) {
    const Vec3 a = mesh.face_vector_area(f);
    area[f] = norm(a);
    normal[f] = detail::face_has_zero_area(mesh, f) ? Vec3{} : normalized(a);
  }
  detail::EdgeMap map;
  build_edge_map(map, mesh, std::vector<uint8_t>(nf, 1));
  const double cos_raw = std::cos(radians_from_degrees(o.angle_degrees));
  const double cos_confirm = std::cos(radians_from_degrees(o.confirm_fraction * o.angle_degrees));
  auto faces_of = [&](size_t e, uint32_t& f0, uint32_t& f1) {
    const uint32_t* h = map.corners_begin(e);
    f0 = map.corner_face[h[0]], f1 = map.corner_face[h[1]];
  };
  monitor.report("sharp features", 0.2);
  // 1. The raw test.
  std::vector<uint8_t> sharp(map.num_edges(), 0);
  std::vector<double> bend(map.num_edges(), -1.0);  // dihedral angle in degrees; -1: no two faces with normals
  for (size_t e = 0; e < map.num_edges(); ++e) {
    if (map.valence(e) != 2) continue;
    uint32_t f0, f1;
    faces_of(e, f0, f1);
    if (dot(normal[f0], normal[f0]) == 0.0 || dot(normal[f1], normal[f1]) == 0.0) continue;
    bend[e] = degrees_from_radians(std::acos(std::clamp(dot(normal[f0], normal[f1]), -1.0, 1.0)));
    if (dot(normal[f0], normal[f1]) < cos_raw) sharp[e] = 1, ++out.raw_edges;
  }
  if (out.raw_edges == 0) return out;
  const std::vector<uint8_t> raw = sharp;
  std::vector<Vec3> centroid(nf, Vec3{});
  for (size_t f = 0; f < nf; ++f) {
    for (uint32_t k = 0; k < mesh.face_size(f); ++k) centroid[f] += mesh.positions[mesh.face_vertex(f, k)];
    centroid[f] = centroid[f] * (1.0 / double(mesh.face_size(f)));
  }
  monitor.report("sharp features", 0.4);
  // 2. Confirmed on the side normals (a neighbourhood's mean on either side).
  if (o.side_rings > 0) {
    const VertexFaces vf(mesh);
    std::vector<uint32_t> faces, verts;
    for (size_t e = 0; e < map.num_edges(); ++e) {
      if (!sharp[e]) continue;
      uint32_t f0, f1;
      faces_of(e, f0, f1);
      const double c = side_angle_cos(mesh, vf, normal, area, centroid, map.edge_lo[e], map.edge_hi[e], f0, f1,
                                      o.side_rings, faces, verts);
      if (!(c < cos_confirm)) sharp[e] = 0, ++out.noise_edges;
    }
  }
  monitor.report("sharp features", 0.6);
  // 3. Feature lines: at each vertex the sharp edges are paired into continuations, straightest
  // first, where the line turns by less than max_turn_degrees; paired edges form one line. Lines
  // then end at corners (no straight continuation), at ends, and where a noisy web zigzags; a
  // line (or a closed loop) shorter than the minimum is dropped, a spur beside a feature line does
  // not cut the line.
  const double min_length = o.min_length_rel * mesh.bounding_box().diagonal();
  const double cos_turn = -std::cos(radians_from_degrees(o.max_turn_degrees));  // dot of the two outgoing directions
  std::vector<uint32_t> first_at(mesh.num_vertices() + 1, 0), at;
  for (size_t e = 0; e < map.num_edges(); ++e)
    if (sharp[e]) ++first_at[map.edge_lo[e] + 1], ++first_at[map.edge_hi[e] + 1];
  for (size_t v = 0; v < mesh.num_vertices(); ++v) first_at[v + 1] += first_at[v];
  at.resize(first_at.back());
  {
    std::vector<uint32_t> fill(first_at.begin(), first_at.end() - 1);
    for (size_t e = 0; e < map.num_edges(); ++e)
      if (sharp[e]) at[fill[map.edge_lo[e]]++] = uint32_t(e), at[fill[map.edge_hi[e]]++] = uint32_t(e);
  }
  detail::UnionFind chains(map.num_edges());
  std::vector<std::pair<double, std::pair<uint32_t, uint32_t>>> pairs;
  std::vector<Vec3> out_dir;
  std::vector<char> paired;
  for (uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    const uint32_t n = first_at[v + 1] - first_at[v];
    if (n < 2) continue;
    out_dir.clear();
    for (uint32_t k = first_at[v]; k < first_at[v + 1]; ++k) {
      const uint32_t e = at[k], w = map.edge_lo[e] == v ? map.edge_hi[e] : map.edge_lo[e];
      out_dir.push_back(normalized(mesh.positions[w] - mesh.positions[v]));
    }
    pairs.clear();
    for (uint32_t i = 0; i < n; ++i)
      for (uint32_t j = i + 1; j < n; ++j) {
        const double d = dot(out_dir[i], out_dir[j]);
        if (d < cos_turn) pairs.push_back({d, {i, j}});
      }
    std::sort(pairs.begin(), pairs.end());
    paired.assign(n, 0);
    for (const auto& [d, ij] : pairs) {
      if (paired[ij.first] || paired[ij.second]) continue;
      paired[ij.first] = paired[ij.second] = 1;
      chains.unite(at[first_at[v] + ij.first], at[first_at[v] + ij.second]);
    }
  }
  std::vector<double> chain_length(map.num_edges(), 0.0), edge_length(map.num_edges(), 0.0);
  std::vector<uint32_t> chain_edges(map.num_edges(), 0);
  for (size_t e = 0; e < map.num_edges(); ++e) {
    if (!sharp[e]) continue;
    edge_length[e] = distance(mesh.positions[map.edge_lo[e]], mesh.positions[map.edge_hi[e]]);
    const uint32_t c = chains.find(uint32_t(e));
    chain_length[c] += edge_length[e];
    ++chain_edges[c];
  }
  monitor.report("sharp features", 0.8);
  // 4. The networks that stand out from the surface beside them (see side_bend_fraction).
  const std::vector<uint8_t> faceted =
      faceted_networks(mesh, map, raw, sharp, bend, centroid, edge_length, o.angle_degrees, o.max_side_bend_fraction);
  for (size_t e = 0; e < map.num_edges(); ++e) {
    if (!sharp[e]) continue;
    const uint32_t c = chains.find(uint32_t(e));
    if (chain_length[c] < min_length || chain_edges[c] < o.min_edges) {
      sharp[e] = 0, ++out.short_edges;
      continue;
    }
    if (faceted[e]) {
      sharp[e] = 0, ++out.faceted_edges;
      continue;
    }
    out.edges.push_back(edge_key(map.edge_lo[e], map.edge_hi[e]));
    out.length += edge_length[e];
  }
  std::sort(out.edges.begin(), out.edges.end());
  for (size_t c = 0; c < out.corner_flags.size(); ++c)
    if (map.corner_edge[c] != detail::kNone) out.corner_flags[c] = sharp[map.corner_edge[c]];
  return out;
}

}  // namespace

SharpFeatures detect_sharp_features(const PolygonMesh& mesh, const SharpFeatureOptions& o, const TaskMonitor& monitor) {
  check_input(mesh, o);
  monitor.report("sharp features", 0.0);
  SharpFeatures out;
  if (o.detect) {
    out = detected_sharp_features(mesh, o, monitor);
  } else {
    out.corner_flags.assign(mesh.num_face_vertices(), 0);
  }
  if (!o.host_edges.empty()) add_host_edges(mesh, o.host_edges, out);
  return out;
}

std::vector<uint8_t> edges_along_features(const PolygonMesh& mesh, const SharpFeatures& features,
                                          const std::vector<std::pair<uint32_t, uint32_t>>& edges, double angle_degrees) {
  std::vector<uint8_t> along(edges.size(), 0);
  if (features.edges.empty()) return along;
  const size_t nv = mesh.num_vertices();
  // The feature graph (sharp edges at each vertex, CSR) and, per vertex next to a feature, its
  // neighbours on one.
  std::vector<uint32_t> sharp_first(nv + 1, 0), sharp_other(2 * features.edges.size());
  for (uint64_t e : features.edges) ++sharp_first[edge_key_first(e) + 1], ++sharp_first[edge_key_second(e) + 1];
  for (size_t v = 0; v < nv; ++v) sharp_first[v + 1] += sharp_first[v];
  {
    std::vector<uint32_t> fill(sharp_first.begin(), sharp_first.end() - 1);
    for (uint64_t e : features.edges) {
      const uint32_t a = edge_key_first(e), b = edge_key_second(e);
      sharp_other[fill[a]++] = b;
      sharp_other[fill[b]++] = a;
    }
  }
  auto on_feature = [&](uint32_t v) { return sharp_first[v] < sharp_first[v + 1]; };
  std::vector<std::vector<uint32_t>> feature_neighbours(nv);
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t k = mesh.face_size(f);
    for (uint32_t c = 0; c < k; ++c) {
      const uint32_t a = mesh.face_vertex(f, c), b = mesh.face_vertex(f, (c + 1) % k);
      if (on_feature(b) && !on_feature(a)) feature_neighbours[a].push_back(b);
      if (on_feature(a) && !on_feature(b)) feature_neighbours[b].push_back(a);
    }
  }
  // Entry points of a vertex into the feature graph, with the distance to get there.
  std::vector<std::pair<uint32_t, double>> sources, targets;
  auto entries = [&](uint32_t v, std::vector<std::pair<uint32_t, double>>& out) {
    out.clear();
    if (on_feature(v)) {
      out.push_back({v, 0.0});
      return;
    }
    for (uint32_t w : feature_neighbours[v]) out.push_back({w, distance(mesh.positions[v], mesh.positions[w])});
  };
  // Bounded Dijkstra over the feature graph; `cost` is reset through `touched` after each query.
  std::vector<double> cost(nv, INFINITY);
  std::vector<uint32_t> touched;
  using Item = std::pair<double, uint32_t>;
  std::vector<Item> heap;
  std::unordered_multimap<uint64_t, size_t> bent;  // edges left for the dihedral test -> index
  for (size_t i = 0; i < edges.size(); ++i) {
    const auto [a, b] = edges[i];
    if (features.contains(a, b)) {
      along[i] = 1;
      continue;
    }
    entries(a, sources);
    entries(b, targets);
    if (sources.empty() || targets.empty()) continue;
    const double budget = kDetourFactor * distance(mesh.positions[a], mesh.positions[b]);
    heap.clear();
    for (const auto& [v, d] : sources)
      if (d < cost[v]) {
        if (cost[v] == INFINITY) touched.push_back(v);
        cost[v] = d;
        heap.push_back({-d, v});
        std::push_heap(heap.begin(), heap.end());
      }
    while (!heap.empty()) {
      std::pop_heap(heap.begin(), heap.end());
      const auto [negative, v] = heap.back();
      heap.pop_back();
      if (-negative > cost[v]) continue;
      for (uint32_t k = sharp_first[v]; k < sharp_first[v + 1]; ++k) {
        const uint32_t w = sharp_other[k];
        const double d = cost[v] + distance(mesh.positions[v], mesh.positions[w]);
        if (d > budget || !(d < cost[w])) continue;
        if (cost[w] == INFINITY) touched.push_back(w);
        cost[w] = d;
        heap.push_back({-d, w});
        std::push_heap(heap.begin(), heap.end());
      }
    }
    for (const auto& [w, d] : targets)
      if (cost[w] + d <= budget) along[i] = 1;
    for (uint32_t v : touched) cost[v] = INFINITY;
    touched.clear();
    if (along[i]) continue;
    // No such path (a feature line with a gap where its angle dips, or a border beside a line
    // that the next one joins): the edge still follows a feature when its midpoint is no farther
    // from the sharp edges at its ends than its farther end is, plus a quarter of its length.
    const Vec3 &pa = mesh.positions[a], &pb = mesh.positions[b], mid = (pa + pb) * 0.5;
    double da = INFINITY, db = INFINITY, dm = INFINITY;
    for (const auto* entry : {&sources, &targets})
      for (const auto& [v, unused] : *entry)
        for (uint32_t k = sharp_first[v]; k < sharp_first[v + 1]; ++k) {
          const Vec3 &s0 = mesh.positions[v], &s1 = mesh.positions[sharp_other[k]];
          da = std::min(da, point_segment_distance(pa, s0, s1));
          db = std::min(db, point_segment_distance(pb, s0, s1));
          dm = std::min(dm, point_segment_distance(mid, s0, s1));
        }
    along[i] = dm <= std::max(da, db) + kMidpointSlack * distance(pa, pb);
    if (!along[i] && on_feature(a) && on_feature(b)) bent.emplace(edge_key(a, b), i);
  }
  // Last, an edge between two feature vertices that bends by half the feature angle itself but
  // was left out of the lines: the rungs of a feature line that zigzags over a dense
  // tessellation, where the lines take every other edge and the rungs share the bend (fandisk_large:
  // 32-39 degrees); a rung across a flat or gently curved strip between two lines bends less.
  if (!bent.empty()) {
    std::unordered_map<uint64_t, std::pair<Vec3, int>> first_normal;  // edge -> first face's normal
    const double cos_angle = std::cos(radians_from_degrees(kRungFraction * angle_degrees));
    for (size_t f = 0; f < mesh.num_faces(); ++f) {
      const uint32_t k = mesh.face_size(f);
      for (uint32_t c = 0; c < k; ++c) {
        const uint64_t key = edge_key(mesh.face_vertex(f, c), mesh.face_vertex(f, (c + 1) % k));
        const auto range = bent.equal_range(key);
        if (range.first == range.second) continue;
        const Vec3 n = normalized(mesh.face_vector_area(f));
        auto [it, inserted] = first_normal.emplace(key, std::make_pair(n, 1));
        if (inserted) continue;
        if (++it->second.second != 2) continue;  // a third face: not a two-face edge
        if (dot(it->second.first, n) < cos_angle)
          for (auto e = range.first; e != range.second; ++e) along[e->second] = 1;
      }
    }
    for (const auto& [key, seen] : first_normal)  // undo edges that turned out to have > 2 faces
      if (seen.second > 2)
        for (auto [e, end] = bent.equal_range(key); e != end; ++e) along[e->second] = 0;
  }
  return along;
}

CAGEKIT_NAMESPACE_END
