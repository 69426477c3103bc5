// SPDX-License-Identifier: GPL-3.0-or-later
// limit_positions_and_normals (declared in uniform_refinement.h): thesis (2.14)-(2.17).
#include <opensubdiv/far/primvarRefiner.h>

#include "core/status.h"
#include "subdiv/opensubdiv_error_handler.h"
#include "subdiv/primvar_point.h"
#include "subdiv/topology_refiner_factory.h"
#include "subdiv/uniform_refinement.h"

CAGEKIT_NAMESPACE_BEGIN

namespace Far = OpenSubdiv::Far;

void limit_positions_and_normals(const Cage& cage, std::vector<Vec3>* positions, std::vector<Vec3>* normals) {
  auto refiner = subdiv_detail::create_topology_refiner(cage);
  // The limit masks of Sdc (like (2.17)) assume quads around the vertex, so they are applied
  // after one refinement step, to the child of each cage vertex: it has the same limit point
  // and the same tangent plane.
  Far::TopologyRefiner::UniformOptions uniform(1);
  uniform.fullTopologyInLastLevel = true;
  subdiv_detail::begin_opensubdiv_call();
  refiner->RefineUniform(uniform);
  if (refiner->GetMaxLevel() != 1)
    fail(Status::internal_error, "OpenSubdiv did not refine the cage: " + subdiv_detail::last_opensubdiv_message());

  using subdiv_detail::PrimvarPoint;
  const std::vector<PrimvarPoint> level0 = subdiv_detail::to_primvar(cage.mesh.positions);
  std::vector<PrimvarPoint> level1(refiner->GetLevel(1).GetNumVertices());
  std::vector<PrimvarPoint> limit(level1.size()), tangent1(level1.size()), tangent2(level1.size());
  Far::PrimvarRefinerReal<double> primvar(*refiner);
  primvar.Interpolate(1, level0, level1);
  primvar.Limit(level1, limit, tangent1, tangent2);

  subdiv_detail::fail_on_opensubdiv_error(Status::invalid_mesh, "OpenSubdiv could not compute limit positions");
  const Far::TopologyLevel& base = refiner->GetLevel(0);
  const size_t n = cage.mesh.num_vertices();
  if (positions) positions->resize(n);
  if (normals) normals->resize(n);
  for (size_t v = 0; v < n; ++v) {
    const Far::Index child = base.GetVertexChildVertex(static_cast<Far::Index>(v));
    if (positions) (*positions)[v] = limit[child].p;
    // (2.14): the normal is the cross product of the two limit tangents; zero where the
    // tangents are degenerate (e.g. a vertex used by no face).
    if (normals) (*normals)[v] = normalized(cross(tangent1[child].p, tangent2[child].p));
  }
}

CAGEKIT_NAMESPACE_END
