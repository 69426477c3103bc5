// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/cage_builder.h"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <unordered_map>

CAGEKIT_NAMESPACE_BEGIN

namespace {

constexpr double kPi = 3.14159265358979323846;

uint64_t edge_key(uint32_t a, uint32_t b) {
  if (a > b) std::swap(a, b);
  return (uint64_t(a) << 32) | b;
}

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

}  // namespace

PolygonLoops project_face(const PolygonMesh& input, const PolygonalFace& face,
                          std::vector<uint32_t>* input_vertex_of_point) {
  const PlaneFrame frame = PlaneFrame::from_normal(face.centroid, face.normal);
  PolygonLoops polygon;
  input_vertex_of_point->clear();
  for (const auto& loop : face.loops) {
    std::vector<uint32_t> local;
    local.reserve(loop.size());
    for (uint32_t v : loop) {
      local.push_back(static_cast<uint32_t>(polygon.points.size()));
      polygon.points.push_back(frame.project(input.positions[v]));
      input_vertex_of_point->push_back(v);
    }
    polygon.loops.push_back(std::move(local));
  }
  return polygon;
}

Cage build_quad_dominant_cage(const PolygonMesh& input, const PolygonalLevel& level, const CageBuildOptions& options,
                              CageBuildReport* report) {
  CageBuildReport local_report;
  CageBuildReport& r = report ? *report : local_report;
  r = CageBuildReport{};
  VertexNumbering numbering(input.num_vertices());
  Cage cage;
  std::vector<uint32_t> point_to_input, cell;
  for (size_t f = 0; f < level.faces.size(); ++f) {
    const PolygonLoops polygon = project_face(input, level.faces[f], &point_to_input);
    const auto triangles = triangulate_polygon(polygon);
    const QuadDominantPartition partition = partition_quad_dominant(polygon, triangles, options.partition);
    if (!partition.optimal) ++r.non_optimal_faces;
    for (const auto& points : partition.cells) {
      cell.clear();
      for (uint32_t p : points) cell.push_back(numbering.index_of(point_to_input[p]));
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
  const double cos_threshold = std::cos(options.crease_angle_degrees * kPi / 180.0);
  for (const auto& [key, use] : uses) {
    if (use.count > 2) ++r.non_manifold_edges;
    bool sharp = false;
    if (use.count == 1) {
      sharp = options.tag_boundary_edges;
    } else if (use.count == 2 && use.cluster[0] != use.cluster[1] && options.crease_angle_degrees >= 0) {
      sharp = dot(level.faces[use.cluster[0]].normal, level.faces[use.cluster[1]].normal) < cos_threshold;
    }
    if (sharp) cage.creases.push_back({static_cast<uint32_t>(key >> 32), static_cast<uint32_t>(key), kSharpnessInfinite});
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
  std::vector<uint32_t> face, point_to_input;
  for (const PolygonalFace& f : level.faces) {
    if (f.loops.size() == 1) {
      face.clear();
      for (uint32_t v : f.loops[0]) face.push_back(numbering.index_of(v));
      mesh.add_face(face.data(), face.size());
      continue;
    }
    ++triangulated;
    const PolygonLoops polygon = project_face(input, f, &point_to_input);
    for (const auto& t : triangulate_polygon(polygon)) {
      const uint32_t tri[3] = {numbering.index_of(point_to_input[t[0]]), numbering.index_of(point_to_input[t[1]]),
                               numbering.index_of(point_to_input[t[2]])};
      mesh.add_face(tri, 3);
    }
  }
  copy_positions(input, numbering.input_vertex_of(), &mesh);
  if (faces_triangulated) *faces_triangulated = triangulated;
  if (input_vertex_of) *input_vertex_of = numbering.input_vertex_of();
  return mesh;
}

CAGEKIT_NAMESPACE_END
