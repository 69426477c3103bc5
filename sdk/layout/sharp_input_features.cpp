// SPDX-License-Identifier: GPL-3.0-or-later
// Sharp input features (the shared crease definition); see sharp_input_features.h.
#include "layout/sharp_input_features.h"

#include <cmath>
#include <string>

#include "core/edge_map.h"
#include "core/status.h"
#include "layout/feature_edges.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

constexpr double kPi = 3.14159265358979323846;

void check_input(const PolygonMesh& mesh, const SharpFeatureOptions& o) {
  if (!(o.angle_degrees >= 0.0 && o.angle_degrees <= 180.0))
    fail(Status::invalid_argument, "sharp features: the angle must be in [0, 180] degrees");
  if (o.side_rings < 0 || o.side_rings > 8)
    fail(Status::invalid_argument, "sharp features: side rings must be in [0, 8]");
  if (!(o.confirm_fraction >= 0.0 && o.confirm_fraction <= 1.0))
    fail(Status::invalid_argument, "sharp features: the confirming fraction must be in [0, 1]");
  if (!(o.max_turn_degrees >= 0.0 && o.max_turn_degrees <= 180.0))
    fail(Status::invalid_argument, "sharp features: the maximum turn must be in [0, 180] degrees");
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

SharpFeatures detect_sharp_features(const PolygonMesh& mesh, const SharpFeatureOptions& o) {
  check_input(mesh, o);
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
  const double cos_raw = std::cos(o.angle_degrees * kPi / 180.0);
  const double cos_confirm = std::cos(o.confirm_fraction * o.angle_degrees * kPi / 180.0);
  auto faces_of = [&](size_t e, uint32_t& f0, uint32_t& f1) {
    const uint32_t* h = map.corners_begin(e);
    f0 = map.corner_face[h[0]], f1 = map.corner_face[h[1]];
  };
  // 1. The raw test.
  std::vector<uint8_t> sharp(map.num_edges(), 0);
  for (size_t e = 0; e < map.num_edges(); ++e) {
    if (map.valence(e) != 2) continue;
    uint32_t f0, f1;
    faces_of(e, f0, f1);
    if (dot(normal[f0], normal[f0]) == 0.0 || dot(normal[f1], normal[f1]) == 0.0) continue;
    if (dot(normal[f0], normal[f1]) < cos_raw) sharp[e] = 1, ++out.raw_edges;
  }
  // 2. Confirmed on the side normals (a neighbourhood's mean on either side).
  if (o.side_rings > 0 && out.raw_edges > 0) {
    const VertexFaces vf(mesh);
    std::vector<Vec3> centroid(nf, Vec3{});
    for (size_t f = 0; f < nf; ++f) {
      for (uint32_t k = 0; k < mesh.face_size(f); ++k) centroid[f] += mesh.positions[mesh.face_vertex(f, k)];
      centroid[f] = centroid[f] * (1.0 / double(mesh.face_size(f)));
    }
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
  // 3. Feature lines: at each vertex the sharp edges are paired into continuations, straightest
  // first, where the line turns by less than max_turn_degrees; paired edges form one line. Lines
  // then end at corners (no straight continuation), at ends, and where a noisy web zigzags; a
  // line (or a closed loop) shorter than the minimum is dropped, a spur beside a feature line does
  // not cut the line.
  const double min_length = o.min_length_rel * mesh.bounding_box().diagonal();
  const double cos_turn = -std::cos(o.max_turn_degrees * kPi / 180.0);  // dot of the two outgoing directions
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
  for (size_t e = 0; e < map.num_edges(); ++e) {
    if (!sharp[e]) continue;
    const uint32_t c = chains.find(uint32_t(e));
    if (chain_length[c] < min_length || chain_edges[c] < o.min_edges) {
      sharp[e] = 0, ++out.short_edges;
      continue;
    }
    out.edges.push_back(SharpFeatures::key(map.edge_lo[e], map.edge_hi[e]));
    out.length += edge_length[e];
  }
  std::sort(out.edges.begin(), out.edges.end());
  for (size_t c = 0; c < out.corner_flags.size(); ++c)
    if (map.corner_edge[c] != detail::kNone) out.corner_flags[c] = sharp[map.corner_edge[c]];
  return out;
}

std::vector<uint8_t> vertices_near_features(const PolygonMesh& mesh, const SharpFeatures& features) {
  std::vector<uint8_t> on(mesh.num_vertices(), 0);
  for (uint64_t e : features.edges) on[uint32_t(e >> 32)] = on[uint32_t(e)] = 1;
  std::vector<uint8_t> near = on;
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t k = mesh.face_size(f);
    for (uint32_t c = 0; c < k; ++c) {
      const uint32_t a = mesh.face_vertex(f, c), b = mesh.face_vertex(f, (c + 1) % k);
      if (on[a]) near[b] = 1;
      if (on[b]) near[a] = 1;
    }
  }
  return near;
}

CAGEKIT_NAMESPACE_END
