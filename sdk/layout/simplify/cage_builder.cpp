// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/simplify/cage_builder.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include "core/angles.h"
#include "core/edge_key.h"
#include "core/status.h"
#include "layout/common/planar_polygon.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {


// Compact numbering of the input vertices a level uses.
class VertexNumbering {
 public:
  explicit VertexNumbering(size_t input_vertices) : cage_index_(input_vertices, kUnset) {}
  uint32_t index_of(uint32_t input_vertex) {
    uint32_t& slot = cage_index_[input_vertex];
    if (slot == kUnset) {
      slot = static_cast<uint32_t>(input_vertex_of_.size());
      input_vertex_of_.push_back(input_vertex);
    }
    return slot;
  }
  const std::vector<uint32_t>& input_vertex_of() const { return input_vertex_of_; }

 private:
  static constexpr uint32_t kUnset = 0xffffffffu;
  std::vector<uint32_t> cage_index_;
  std::vector<uint32_t> input_vertex_of_;
};

void copy_positions(const PolygonMesh& input, const std::vector<uint32_t>& input_vertex_of, PolygonMesh* out) {
  out->positions.reserve(input_vertex_of.size());
  for (uint32_t v : input_vertex_of) out->positions.push_back(input.positions[v]);
}


// One level face on its way to cage faces: its projection, triangulation and partition.
struct FaceWork {
  PolygonLoops polygon;
  std::vector<uint32_t> point_to_input;
  std::vector<std::array<uint32_t, 3>> triangles;
  QuadDominantPartition partition;
  std::vector<std::vector<uint32_t>> cycles;  // polygonal_level_mesh: the faces it emits
};

// Sorted keys of the undirected edges (input vertex pairs) used more than twice by the cycles
// the faces emit.
template <typename CyclesOf>
std::vector<uint64_t> overused_edges(const std::vector<FaceWork>& work, CyclesOf&& cycles_of) {
  std::unordered_map<uint64_t, uint32_t> uses;
  for (const FaceWork& w : work)
    for (const auto& cycle : cycles_of(w))
      for (size_t k = 0; k < cycle.size(); ++k)
        ++uses[edge_key(w.point_to_input[cycle[k]], w.point_to_input[cycle[(k + 1) % cycle.size()]])];
  std::vector<uint64_t> shared;
  for (const auto& [key, count] : uses)
    if (count > 2) shared.push_back(key);
  std::sort(shared.begin(), shared.end());
  return shared;
}

// Merges the two cells of a partition on either side of the inner edge (a, b) into one cell (a
// simple polygon, not necessarily convex). Returns false when the edge is not shared by two cells.
bool merge_cells_across(std::vector<std::vector<uint32_t>>& cells, uint32_t a, uint32_t b) {
  size_t ci = cells.size(), cj = cells.size(), ki = 0, kj = 0;
  for (size_t c = 0; c < cells.size(); ++c)
    for (size_t k = 0; k < cells[c].size(); ++k) {
      const uint32_t x = cells[c][k], y = cells[c][(k + 1) % cells[c].size()];
      if (x == a && y == b) ci = c, ki = k;
      if (x == b && y == a) cj = c, kj = k;
    }
  if (ci == cells.size() || cj == cells.size() || ci == cj) return false;
  const auto& i = cells[ci];
  const auto& j = cells[cj];
  std::vector<uint32_t> merged;
  for (size_t k = 1; k <= i.size(); ++k) merged.push_back(i[(ki + k) % i.size()]);     // b ... a
  for (size_t k = 2; k < j.size(); ++k) merged.push_back(j[(kj + k) % j.size()]);      // after a ... before b
  cells[ci] = std::move(merged);
  cells.erase(cells.begin() + static_cast<std::ptrdiff_t>(cj));
  return true;
}

// Rounds of: count the uses of every undirected edge (input vertex pairs) over the cycles the
// faces emit; for an edge with more than two uses, flip it out of the triangulation of each face
// that has it as an inner diagonal (not as a loop edge) and rebuild that face (`rebuild`).
// Returns the number of diagonals flipped out.
template <typename Rebuild, typename CyclesOf>
uint64_t resolve_shared_diagonals(std::vector<FaceWork>& work, Rebuild&& rebuild, CyclesOf&& cycles_of) {
  uint64_t flipped = 0;
  for (int round = 0; round < 4; ++round) {
    const std::vector<uint64_t> shared = overused_edges(work, cycles_of);
    if (shared.empty()) break;
    bool changed_any = false;
    for (size_t f = 0; f < work.size(); ++f) {
      FaceWork& w = work[f];
      if (w.polygon.loops.empty()) continue;
      // Loop edges of the face, and the face's point of each input vertex.
      std::unordered_map<uint64_t, char> loop_edges;
      for (const auto& loop : w.polygon.loops)
        for (size_t k = 0; k < loop.size(); ++k)
          loop_edges[edge_key(w.point_to_input[loop[k]], w.point_to_input[loop[(k + 1) % loop.size()]])] = 1;
      bool changed = false;
      for (const auto& cycle : cycles_of(w))
        for (size_t k = 0; k < cycle.size(); ++k) {
          const uint32_t pa = cycle[k], pb = cycle[(k + 1) % cycle.size()];
          const uint64_t key = edge_key(w.point_to_input[pa], w.point_to_input[pb]);
          if (loop_edges.count(key) || !std::binary_search(shared.begin(), shared.end(), key)) continue;
          auto triangles = w.triangles;
          if (flip_out_edge(w.polygon, triangles, pa, pb) && triangles != w.triangles) {
            w.triangles = std::move(triangles);
            changed = true;
            ++flipped;
          }
        }
      if (changed) {
        rebuild(f);
        changed_any = true;
      }
    }
    if (!changed_any) break;
  }
  return flipped;
}
}  // namespace

PolygonLoops project_face(const PolygonMesh& input, const PolygonalFace& face, const LevelCoordinates& coordinates,
                          std::vector<uint32_t>* input_vertex_of_point) {
  // The same arithmetic as the simplifier's Builder::project / frame_of.
  const auto to_level = [&](const Vec3& p) { return (p - coordinates.origin) * coordinates.scale; };
  const PlaneFrame frame = PlaneFrame::from_normal(to_level(face.centroid), face.normal);
  PolygonLoops polygon;
  input_vertex_of_point->clear();
  for (const auto& loop : face.loops) {
    std::vector<uint32_t> local;
    local.reserve(loop.size());
    for (uint32_t v : loop) {
      local.push_back(static_cast<uint32_t>(polygon.points.size()));
      polygon.points.push_back(frame.project(to_level(input.positions[v])));
      input_vertex_of_point->push_back(v);
    }
    polygon.loops.push_back(std::move(local));
  }
  return polygon;
}

Cage build_quad_dominant_cage(const PolygonMesh& input, const PolygonalLevel& level, const CageBuildOptions& options,
                              CageBuildReport* report, const TaskMonitor& monitor) {
  // Cancel points: every 64 level faces while partitioning (0 .. 0.5 of "cage"), every 2^16 input
  // faces and between the passes of the crease rule (0.5 .. 1).
  const auto report_faces = [&](size_t f, size_t n) {
    if (f % 64 == 0) monitor.report("cage", 0.5 * double(f) / double(n ? n : 1));
  };
  const auto report_input = [&](size_t f, double at) {
    if ((f & 0xffff) == 0) monitor.report("cage", at);
  };
  CageBuildReport local_report;
  CageBuildReport& r = report ? *report : local_report;
  r = CageBuildReport{};
  VertexNumbering numbering(input.num_vertices());
  Cage cage;
  const size_t num_faces = level.faces.size();
  std::vector<FaceWork> work(num_faces);
  for (size_t f = 0; f < num_faces; ++f) {
    report_faces(f, num_faces);
    FaceWork& w = work[f];
    w.polygon = project_face(input, level.faces[f], level.coordinates, &w.point_to_input);
    const PolygonValidity validity = check_polygon_loops(w.polygon);
    if (!validity.ok()) {
      // Every merge result was validated in these coordinates, so only an input polygon that
      // is not injective in its own plane (a twisted quad, say) gets here: it has no CDT, so it
      // becomes one cell as the input had it (its loop is a cycle of input edges).
      if (w.polygon.loops.size() != 1)
        fail(Status::invalid_argument, "build_quad_dominant_cage: level face " + std::to_string(f) +
                                           " (with holes) is not injectively projectable to its plane: " +
                                           validity.message);
      w.partition = QuadDominantPartition{};
      w.partition.cells.push_back(w.polygon.loops[0]);
      w.partition.optimal = true;
      ++r.unprojectable_faces;
      continue;
    }
    triangulate_valid_polygon(w.polygon, w.triangles);
    w.partition = partition_quad_dominant(w.polygon, w.triangles, options.partition);
  }
  // A diagonal chosen inside one face may join two vertices that another face already joins
  // (by an edge or its own diagonal): the cage edge would have more than two faces. Such
  // diagonals are flipped out of their face's triangulation and the face partitioned again.
  r.diagonals_flipped = resolve_shared_diagonals(work, [&](size_t f) {
    work[f].partition = partition_quad_dominant(work[f].polygon, work[f].triangles, options.partition);
  }, [](const FaceWork& w) -> const std::vector<std::vector<uint32_t>>& { return w.partition.cells; });
  // Diagonals that no flip removes (the CDT forces them): the two cells on them become one
  // (possibly non-convex) cell, so the cage stays manifold.
  const auto cells_of = [](const FaceWork& w) -> const std::vector<std::vector<uint32_t>>& {
    return w.partition.cells;
  };
  if (const std::vector<uint64_t> shared = overused_edges(work, cells_of); !shared.empty())
    for (FaceWork& w : work) {
      std::unordered_map<uint64_t, char> loop_edges;
      for (const auto& loop : w.polygon.loops)
        for (size_t k = 0; k < loop.size(); ++k)
          loop_edges[edge_key(w.point_to_input[loop[k]], w.point_to_input[loop[(k + 1) % loop.size()]])] = 1;
      for (bool merged = true; merged;) {
        merged = false;
        for (size_t c = 0; c < w.partition.cells.size() && !merged; ++c) {
          const auto& cycle = w.partition.cells[c];
          for (size_t k = 0; k < cycle.size() && !merged; ++k) {
            const uint32_t pa = cycle[k], pb = cycle[(k + 1) % cycle.size()];
            const uint64_t key = edge_key(w.point_to_input[pa], w.point_to_input[pb]);
            if (!loop_edges.count(key) && std::binary_search(shared.begin(), shared.end(), key) &&
                merge_cells_across(w.partition.cells, pa, pb)) {
              merged = true;
              ++r.cells_merged;
            }
          }
        }
      }
    }
  std::vector<uint32_t> cell;
  for (size_t f = 0; f < num_faces; ++f) {
    const QuadDominantPartition& partition = work[f].partition;
    if (!partition.optimal) ++r.non_optimal_faces;
    for (const auto& points : partition.cells) {
      cell.clear();
      for (uint32_t p : points) cell.push_back(numbering.index_of(work[f].point_to_input[p]));
      cage.mesh.add_face(cell.data(), cell.size());
      r.cluster_of_cage_face.push_back(static_cast<uint32_t>(f));
      switch (cell.size()) {
        case 3: ++r.triangles; break;
        case 4: ++r.quads; break;
        case 5: ++r.pentagons; break;
        default: ++r.other; break;
      }
    }
  }
  copy_positions(input, numbering.input_vertex_of(), &cage.mesh);
  r.input_vertex_of = numbering.input_vertex_of();
  monitor.report("cage", 0.5);

  // Crease tags: cage edges between clusters meeting at a sharp angle, and boundary edges.
  struct EdgeUse {
    uint32_t cluster[2];
    int count = 0;
  };
  std::unordered_map<uint64_t, EdgeUse> uses;
  uses.reserve(cage.mesh.num_face_vertices());
  for (size_t f = 0; f < cage.mesh.num_faces(); ++f) {
    const uint32_t n = cage.mesh.face_size(f);
    for (uint32_t c = 0; c < n; ++c) {
      EdgeUse& use = uses[edge_key(cage.mesh.face_vertex(f, c), cage.mesh.face_vertex(f, (c + 1) % n))];
      if (use.count < 2) use.cluster[use.count] = r.cluster_of_cage_face[f];
      ++use.count;
    }
  }
  const bool clusters_known = level.cluster_of_input_face.size() == input.num_faces();
  const bool by_input = options.crease_rule == CreaseRule::sharp_input && clusters_known;
  const bool by_angle = options.crease_rule == CreaseRule::cluster_angle && options.crease_angle_degrees >= 0;
  // The input edges between two different clusters (each once), per vertex.
  struct BorderEdge {
    uint32_t a, b;
    uint64_t pair;  // edge_key of the two clusters
    double length, angle;
    bool sharp;
    bool host = false;  // one of the host's sharp edges
  };
  std::vector<BorderEdge> border_edges;
  if (clusters_known && (by_input || (by_angle && options.input_crease_angle_degrees >= 0))) {
    std::vector<Vec3> normal(input.num_faces());
    for (size_t f = 0; f < input.num_faces(); ++f) normal[f] = normalized(input.face_vector_area(f));
    monitor.report("cage", 0.55);
    SharpFeatures features;
    if (by_input) features = detect_sharp_features(input, options.features, monitor);
    monitor.report("cage", 0.65);
    std::unordered_map<uint64_t, uint32_t> edge_face;
    edge_face.reserve(input.num_face_vertices());
    for (size_t f = 0; f < input.num_faces(); ++f) {
      report_input(f, 0.65);
      const uint32_t k = input.face_size(f);
      for (uint32_t c = 0; c < k; ++c) {
        const uint32_t a = input.face_vertex(f, c), b = input.face_vertex(f, (c + 1) % k);
        const auto [it, inserted] = edge_face.emplace(edge_key(a, b), static_cast<uint32_t>(f));
        if (inserted) continue;
        const uint32_t g = it->second, ca = level.cluster_of_input_face[f], cb = level.cluster_of_input_face[g];
        if (ca == cb) continue;
        const double angle = std::acos(std::clamp(dot(normal[f], normal[g]), -1.0, 1.0));
        border_edges.push_back({a, b, edge_key(ca, cb), distance(input.positions[a], input.positions[b]), angle, false});
      }
    }
    // A border edge runs along a feature when it is sharp, or zigzags one triangle beside a
    // feature line (edges_along_features: both ends on or next to it, the midpoint no farther).
    monitor.report("cage", 0.8);
    if (by_input) {
      std::vector<std::pair<uint32_t, uint32_t>> ends(border_edges.size());
      for (size_t i = 0; i < border_edges.size(); ++i) ends[i] = {border_edges[i].a, border_edges[i].b};
      const std::vector<uint8_t> along = edges_along_features(input, features, ends, options.features.angle_degrees);
      for (size_t i = 0; i < border_edges.size(); ++i) border_edges[i].sharp = along[i] != 0;
      const std::vector<uint64_t>& host = options.features.host_edges;
      if (!host.empty()) {
        const std::unordered_set<uint64_t> host_set(host.begin(), host.end());
        for (BorderEdge& e : border_edges) e.host = host_set.count(edge_key(e.a, e.b)) != 0;
      }
    }
  }
  // cluster_angle with the input check: the length-weighted mean dihedral angle of the input
  // along each pair of clusters' border.
  std::unordered_map<uint64_t, std::pair<double, double>> border;  // cluster pair -> (sum angle*len, len)
  if (by_angle)
    for (const BorderEdge& e : border_edges) {
      auto& acc = border[e.pair];
      acc.first += e.angle * e.length;
      acc.second += e.length;
    }
  auto input_is_sharp = [&](uint32_t ca, uint32_t cb) {
    if (options.input_crease_angle_degrees < 0) return true;
    const auto it = border.find(edge_key(ca, cb));
    if (it == border.end() || !(it->second.second > 0)) return true;  // no shared input edges: keep the rule
    return it->second.first / it->second.second > radians_from_degrees(options.input_crease_angle_degrees);
  };
  // sharp_input: the chain of border edges each cage edge spans, walked from every cage vertex
  // along the border of one pair of clusters to the next cage vertex; per (cage edge, cluster
  // pair) the sharp and the total length.
  struct BorderChain {
    double sharp = 0.0, total = 0.0;
    double host = 0.0;  // length along the host's sharp edges
    std::vector<uint32_t> vertices;  // input vertices of the chain
  };
  std::map<std::pair<uint64_t, uint64_t>, BorderChain> chain;  // (edge, pair) -> its chain
  if (by_input) {
    std::vector<char> is_cage_vertex(input.num_vertices(), 0);
    for (uint32_t v : r.input_vertex_of) is_cage_vertex[v] = 1;
    std::unordered_map<uint32_t, std::vector<uint32_t>> at_vertex;
    for (uint32_t e = 0; e < border_edges.size(); ++e)
      for (uint32_t v : {border_edges[e].a, border_edges[e].b}) at_vertex[v].push_back(e);
    for (uint32_t e0 = 0; e0 < border_edges.size(); ++e0)
      for (uint32_t start : {border_edges[e0].a, border_edges[e0].b}) {
        if (!is_cage_vertex[start]) continue;
        const uint64_t pair = border_edges[e0].pair;
        double sharp = 0.0, total = 0.0, host = 0.0;
        uint32_t edge = e0, at = start;
        std::vector<uint32_t> vertices{start};
        for (size_t step = 0; step <= border_edges.size(); ++step) {
          const BorderEdge& be = border_edges[edge];
          total += be.length;
          sharp += be.sharp ? be.length : 0.0;
          host += be.host ? be.length : 0.0;
          at = be.a == at ? be.b : be.a;
          vertices.push_back(at);
          if (is_cage_vertex[at]) {
            if (start < at) {  // each chain once (it is walked from both ends)
              BorderChain& acc = chain[{edge_key(start, at), pair}];
              acc.sharp += sharp;
              acc.total += total;
              acc.host += host;
              acc.vertices.insert(acc.vertices.end(), vertices.begin(), vertices.end());
            }
            break;
          }
          // A contour vertex that is not a cage vertex joins exactly two border edges of the pair.
          uint32_t next = UINT32_MAX;
          int candidates = 0;
          for (uint32_t o : at_vertex[at])
            if (o != edge && border_edges[o].pair == pair) next = o, ++candidates;
          if (candidates != 1) break;
          edge = next;
        }
      }
  }
  // The mean normals of each cluster's input faces within band_rings vertex rings of a chain
  // (Σ vector areas): across a feature line they differ by about its angle, across the facets of
  // a faceted or noisy organic scan, whose normals scatter around the smooth surface's, they do
  // not.
  monitor.report("cage", 0.9);
  std::vector<uint32_t> faces_first, faces_around;
  if (by_input) {
    faces_first.assign(input.num_vertices() + 1, 0);
    for (uint32_t v : input.face_vertices) ++faces_first[v + 1];
    for (size_t v = 0; v < input.num_vertices(); ++v) faces_first[v + 1] += faces_first[v];
    faces_around.resize(input.face_vertices.size());
    std::vector<uint32_t> fill(faces_first.begin(), faces_first.end() - 1);
    for (size_t f = 0; f < input.num_faces(); ++f)
      for (uint32_t k = 0; k < input.face_size(f); ++k) faces_around[fill[input.face_vertex(f, k)]++] = uint32_t(f);
  }
  auto band_normals_cos = [&](const std::vector<uint32_t>& chain_vertices, uint32_t ca, uint32_t cb) {
    // From the chain's inner vertices (its ends are cage vertices where other clusters meet).
    std::vector<uint32_t> verts, faces;
    if (chain_vertices.size() >= 3)
      verts.assign(chain_vertices.begin() + 1, chain_vertices.end() - 1);
    else
      verts = chain_vertices;
    std::sort(verts.begin(), verts.end());
    verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
    for (int ring = 0; ring < options.band_rings; ++ring) {
      faces.clear();
      for (uint32_t v : verts)
        for (uint32_t k = faces_first[v]; k < faces_first[v + 1]; ++k) {
          const uint32_t f = faces_around[k], c = level.cluster_of_input_face[f];
          if (c == ca || c == cb) faces.push_back(f);
        }
      std::sort(faces.begin(), faces.end());
      faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
      if (ring + 1 == options.band_rings) break;
      for (uint32_t f : faces)
        for (uint32_t k = 0; k < input.face_size(f); ++k) verts.push_back(input.face_vertex(f, k));
      std::sort(verts.begin(), verts.end());
      verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
    }
    Vec3 na{}, nb{};
    for (uint32_t f : faces) (level.cluster_of_input_face[f] == ca ? na : nb) += input.face_vector_area(f);
    return dot(normalized(na), normalized(nb));
  };
  const double cos_half_feature = std::cos(radians_from_degrees(0.5 * options.features.angle_degrees));
  const double cos_band = std::cos(radians_from_degrees(options.band_fraction * options.features.angle_degrees));
  auto border_is_sharp = [&](uint32_t u, uint32_t w, uint32_t ca, uint32_t cb) {
    const uint32_t iu = r.input_vertex_of[u], iw = r.input_vertex_of[w];
    const auto it = chain.find({edge_key(iu, iw), edge_key(ca, cb)});
    if (it == chain.end() || !(it->second.total > 0.0)) return false;  // not a border chord
    // Along the host's sharp edges: a crease whatever the angles (the host says it is sharp).
    if (it->second.host >= options.sharp_share * it->second.total) return true;
    // The two clusters must also meet at an angle (half the feature angle): a border that runs
    // beside a feature line over flat or smooth surface is not a crease.
    if (!(dot(level.faces[ca].normal, level.faces[cb].normal) < cos_half_feature)) return false;
    if (it->second.sharp < options.sharp_share * it->second.total) return false;
    return options.band_rings <= 0 || band_normals_cos(it->second.vertices, ca, cb) < cos_band;
  };
  const double cos_threshold = std::cos(radians_from_degrees(options.crease_angle_degrees));
  for (const auto& [key, use] : uses) {
    if (use.count > 2) ++r.non_manifold_edges;
    bool sharp = false;
    if (use.count == 1) {
      sharp = options.tag_boundary_edges;
    } else if (use.count == 2 && use.cluster[0] != use.cluster[1]) {
      if (by_input)
        sharp = border_is_sharp(edge_key_first(key), edge_key_second(key), use.cluster[0],
                                use.cluster[1]);
      else if (by_angle)
        sharp = dot(level.faces[use.cluster[0]].normal, level.faces[use.cluster[1]].normal) < cos_threshold &&
                input_is_sharp(use.cluster[0], use.cluster[1]);
    }
    if (sharp) cage.creases.push_back({edge_key_first(key), edge_key_second(key), kSharpnessInfinite});
  }
  std::sort(cage.creases.begin(), cage.creases.end(),
            [](const EdgeCrease& a, const EdgeCrease& b) { return std::tie(a.v0, a.v1) < std::tie(b.v0, b.v1); });
  r.creases = cage.creases.size();
  return cage;
}

PolygonMesh polygonal_level_mesh(const PolygonMesh& input, const PolygonalLevel& level, uint64_t* faces_triangulated,
                                 std::vector<uint32_t>* input_vertex_of) {
  VertexNumbering numbering(input.num_vertices());
  PolygonMesh mesh;
  uint64_t triangulated = 0;
  // Faces with holes are triangulated (CDT); a triangle edge that joins two vertices some other
  // face already joins is flipped out (see resolve_shared_diagonals).
  std::vector<FaceWork> work(level.faces.size());
  auto triangles_as_cycles = [](FaceWork& w) {
    w.cycles.clear();
    for (const auto& t : w.triangles) w.cycles.push_back({t[0], t[1], t[2]});
  };
  for (size_t f = 0; f < level.faces.size(); ++f) {
    FaceWork& w = work[f];
    if (level.faces[f].loops.size() == 1) {
      w.point_to_input = level.faces[f].loops[0];
      w.cycles.emplace_back(w.point_to_input.size());
      for (uint32_t k = 0; k < w.point_to_input.size(); ++k) w.cycles[0][k] = k;
      continue;
    }
    ++triangulated;
    w.polygon = project_face(input, level.faces[f], level.coordinates, &w.point_to_input);
    const PolygonValidity validity = check_polygon_loops(w.polygon);
    if (!validity.ok())  // merge results are valid in the level's coordinates (see project_face)
      fail(Status::invalid_argument, "polygonal_level_mesh: level face " + std::to_string(f) +
                                         " (with holes) is not injectively projectable to its plane: " +
                                         validity.message);
    triangulate_valid_polygon(w.polygon, w.triangles);
    triangles_as_cycles(w);
  }
  resolve_shared_diagonals(work, [&](size_t f) { triangles_as_cycles(work[f]); },
                           [](const FaceWork& w) -> const std::vector<std::vector<uint32_t>>& { return w.cycles; });
  std::vector<uint32_t> face;
  for (const FaceWork& w : work)
    for (const auto& cycle : w.cycles) {
      face.clear();
      for (uint32_t p : cycle) face.push_back(numbering.index_of(w.point_to_input[p]));
      mesh.add_face(face.data(), face.size());
    }
  copy_positions(input, numbering.input_vertex_of(), &mesh);
  if (faces_triangulated) *faces_triangulated = triangulated;
  if (input_vertex_of) *input_vertex_of = numbering.input_vertex_of();
  return mesh;
}

CAGEKIT_NAMESPACE_END
