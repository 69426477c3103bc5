// SPDX-License-Identifier: GPL-3.0-or-later
// Uniform Catmull-Clark refinement (thesis §2.2.2-2.2.3) on OpenSubdiv Far: the topology with
// TopologyRefiner::RefineUniform, the positions with PrimvarRefiner::Interpolate in double
// precision, the optional limit positions with PrimvarRefiner::Limit.
#include "core/memory_budget.h"
#include "subdiv/uniform_refinement.h"

#include <opensubdiv/far/primvarRefiner.h>

#include <climits>
#include <cstdint>
#include <string>
#include <vector>

#include "core/status.h"
#include "subdiv/cage_input_check.h"
#include "subdiv/opensubdiv_error_handler.h"
#include "subdiv/primvar_point.h"
#include "subdiv/topology_refiner_factory.h"

CAGEKIT_NAMESPACE_BEGIN
namespace {

namespace Far = OpenSubdiv::Far;
using subdiv_detail::PrimvarPoint;

// After one step every face is a quad, so level L >= 1 has 4^L times the face-vertices of level
// 0. Checked before OpenSubdiv allocates anything, so hostile requests fail fast.
void check_refined_size(const Cage& cage, int levels) {
  if (levels == 0) return;
  const uint64_t face_vertices = static_cast<uint64_t>(cage.mesh.num_face_vertices()) << (2 * levels);
  if (face_vertices > static_cast<uint64_t>(INT_MAX))
    fail(Status::limit_exceeded, "refining " + std::to_string(cage.mesh.num_face_vertices()) + " face-vertices " +
                                     std::to_string(levels) + " times gives " + std::to_string(face_vertices) +
                                     " face-vertices, more than 2^31 - 1");
  // OpenSubdiv's refiner keeps every level (~4/3 of the last) at ~48 bytes per face-vertex
  // (topology + positions), plus the output mesh.
  check_memory_estimate(estimate_product(face_vertices, 48 * 4 / 3 + 12), "uniform subdivision");
}

// Crease tags of the last level: the descendants of the cage's tagged edges that are still
// sharp (semi-sharp sharpness decays by one per level). Edges OpenSubdiv sharpens implicitly
// (boundary, non-manifold) are not emitted as tags: the rules apply to them anyway.
std::vector<EdgeCrease> refined_creases(const Far::TopologyRefiner& refiner, const Cage& cage) {
  const int last = refiner.GetMaxLevel();
  std::vector<Far::Index> edges;
  const Far::TopologyLevel& base = refiner.GetLevel(0);
  std::vector<char> seen(base.GetNumEdges(), 0);
  for (const EdgeCrease& c : cage.creases) {
    const Far::Index e = base.FindEdge(static_cast<Far::Index>(c.v0), static_cast<Far::Index>(c.v1));
    if (e >= 0 && !seen[e]) {
      seen[e] = 1;
      edges.push_back(e);
    }
  }
  for (int level = 0; level < last; ++level) {
    const Far::TopologyLevel& parent = refiner.GetLevel(level);
    std::vector<Far::Index> children;
    children.reserve(2 * edges.size());
    for (Far::Index e : edges) {
      if (parent.GetEdgeSharpness(e) <= 0.0f) continue;  // decayed: its children are smooth
      for (Far::Index child : parent.GetEdgeChildEdges(e)) children.push_back(child);
    }
    edges.swap(children);
  }
  const Far::TopologyLevel& level = refiner.GetLevel(last);
  std::vector<EdgeCrease> creases;
  creases.reserve(edges.size());
  for (Far::Index e : edges) {
    const float sharpness = level.GetEdgeSharpness(e);
    if (sharpness <= 0.0f) continue;
    const auto v = level.GetEdgeVertices(e);
    creases.push_back({static_cast<uint32_t>(v[0]), static_cast<uint32_t>(v[1]), sharpness});
  }
  return creases;
}

// Corner tags follow their vertex (each vertex has one child vertex per level).
std::vector<VertexCorner> refined_corners(const Far::TopologyRefiner& refiner, const Cage& cage) {
  const int last = refiner.GetMaxLevel();
  std::vector<char> seen(cage.mesh.num_vertices(), 0);
  std::vector<VertexCorner> corners;
  for (const VertexCorner& c : cage.corners) {
    if (seen[c.vertex]) continue;
    seen[c.vertex] = 1;
    Far::Index v = static_cast<Far::Index>(c.vertex);
    for (int level = 0; level < last; ++level) v = refiner.GetLevel(level).GetVertexChildVertex(v);
    const float sharpness = refiner.GetLevel(last).GetVertexSharpness(v);
    if (sharpness > 0.0f) corners.push_back({static_cast<uint32_t>(v), sharpness});
  }
  return corners;
}

PolygonMesh refined_mesh(const Far::TopologyLevel& level, std::vector<Vec3> positions) {
  PolygonMesh mesh;
  mesh.positions = std::move(positions);
  const int num_faces = level.GetNumFaces();
  mesh.face_offsets.resize(static_cast<size_t>(num_faces) + 1);
  mesh.face_vertices.resize(static_cast<size_t>(level.GetNumFaceVertices()));
  uint32_t offset = 0;
  for (int f = 0; f < num_faces; ++f) {
    mesh.face_offsets[f] = offset;
    for (Far::Index v : level.GetFaceVertices(f)) mesh.face_vertices[offset++] = static_cast<uint32_t>(v);
  }
  mesh.face_offsets[num_faces] = offset;
  return mesh;
}

}  // namespace

Cage refine_uniform(const Cage& cage, const RefineOptions& options, const TaskMonitor& monitor) {
  const int levels = options.levels;
  if (levels < 0 || levels > kMaxUniformLevels)
    fail(Status::invalid_argument, "refinement levels must be in [0, " + std::to_string(kMaxUniformLevels) +
                                       "], got " + std::to_string(levels));
  check_refined_size(cage, levels);
  monitor.report("subdivide", 0.0);

  if (levels == 0) {
    subdiv_detail::check_cage_for_subdivision(cage);
    Cage result = cage;
    if (options.limit_positions) limit_positions_and_normals(cage, &result.mesh.positions, nullptr);
    monitor.report("subdivide", 1.0);
    return result;
  }

  auto refiner = subdiv_detail::create_topology_refiner(cage);
  Far::TopologyRefiner::UniformOptions uniform(levels);
  // The last level's edges are needed only to carry crease tags, and its full neighbourhoods
  // for limit positions; without either the cheaper minimal last level suffices (~1.8x faster).
  uniform.fullTopologyInLastLevel = !cage.creases.empty() || options.limit_positions;
  subdiv_detail::begin_opensubdiv_call();
  refiner->RefineUniform(uniform);
  if (refiner->GetMaxLevel() != levels)
    fail(Status::internal_error, "OpenSubdiv did not refine the cage: " + subdiv_detail::last_opensubdiv_message());

  Far::PrimvarRefinerReal<double> primvar(*refiner);
  std::vector<PrimvarPoint> coarse = subdiv_detail::to_primvar(cage.mesh.positions), fine;
  for (int level = 1; level <= levels; ++level) {
    fine.assign(refiner->GetLevel(level).GetNumVertices(), PrimvarPoint());
    primvar.Interpolate(level, coarse, fine);
    coarse.swap(fine);
    monitor.report("subdivide", static_cast<double>(level) / levels);
  }
  if (options.limit_positions) {
    fine.assign(coarse.size(), PrimvarPoint());
    primvar.Limit(coarse, fine);
    coarse.swap(fine);
  }
  subdiv_detail::fail_on_opensubdiv_error(Status::invalid_mesh, "OpenSubdiv could not refine the cage");
  std::vector<Vec3> positions(coarse.size());
  for (size_t i = 0; i < coarse.size(); ++i) positions[i] = coarse[i].p;
  std::vector<PrimvarPoint>().swap(coarse);
  std::vector<PrimvarPoint>().swap(fine);

  const Far::TopologyLevel& last = refiner->GetLevel(levels);
  Cage result;
  result.mesh = refined_mesh(last, std::move(positions));
  result.creases = refined_creases(*refiner, cage);
  result.corners = refined_corners(*refiner, cage);
  for (int f = 0; f < last.GetNumFaces(); ++f)
    if (last.IsFaceHole(f)) result.holes.push_back(static_cast<uint32_t>(f));
  result.boundary = cage.boundary;
  return result;
}

CAGEKIT_NAMESPACE_END
