// SPDX-License-Identifier: GPL-3.0-or-later
#include "subdiv/topology_refiner_factory.h"

#include <opensubdiv/far/topologyDescriptor.h>

#include <new>
#include <string>
#include <vector>

#include "core/status.h"
#include "subdiv/cage_input_check.h"
#include "subdiv/opensubdiv_error_handler.h"

CAGEKIT_NAMESPACE_BEGIN
namespace subdiv_detail {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

Sdc::Options sdc_options(BoundaryRule rule) {
  Sdc::Options options;
  options.SetVtxBoundaryInterpolation(rule == BoundaryRule::edges_and_corners ? Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER
                                                                                : Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  options.SetCreasingMethod(Sdc::Options::CREASE_UNIFORM);
  options.SetTriangleSubdivision(Sdc::Options::TRI_SUB_CATMARK);
  options.SetFVarLinearInterpolation(Sdc::Options::FVAR_LINEAR_ALL);
  return options;
}

std::unique_ptr<Far::TopologyRefiner> create_topology_refiner(const Cage& cage) {
  check_cage_for_subdivision(cage);
  const PolygonMesh& mesh = cage.mesh;

  // The descriptor takes int arrays; every value was checked to fit above.
  std::vector<int> face_sizes(mesh.num_faces());
  for (size_t f = 0; f < mesh.num_faces(); ++f) face_sizes[f] = static_cast<int>(mesh.face_size(f));
  const std::vector<int> face_vertices(mesh.face_vertices.begin(), mesh.face_vertices.end());
  std::vector<int> crease_pairs;
  std::vector<float> crease_weights;
  crease_pairs.reserve(2 * cage.creases.size());
  crease_weights.reserve(cage.creases.size());
  for (const EdgeCrease& c : cage.creases) {
    crease_pairs.push_back(static_cast<int>(c.v0));
    crease_pairs.push_back(static_cast<int>(c.v1));
    crease_weights.push_back(c.sharpness);
  }
  std::vector<int> corner_vertices;
  std::vector<float> corner_weights;
  for (const VertexCorner& c : cage.corners) {
    corner_vertices.push_back(static_cast<int>(c.vertex));
    corner_weights.push_back(c.sharpness);
  }
  const std::vector<int> holes(cage.holes.begin(), cage.holes.end());

  Far::TopologyDescriptor descriptor;
  descriptor.numVertices = static_cast<int>(mesh.num_vertices());
  descriptor.numFaces = static_cast<int>(mesh.num_faces());
  descriptor.numVertsPerFace = face_sizes.data();
  descriptor.vertIndicesPerFace = face_vertices.data();
  descriptor.numCreases = static_cast<int>(cage.creases.size());
  descriptor.creaseVertexIndexPairs = crease_pairs.data();
  descriptor.creaseWeights = crease_weights.data();
  descriptor.numCorners = static_cast<int>(corner_vertices.size());
  descriptor.cornerVertexIndices = corner_vertices.data();
  descriptor.cornerWeights = corner_weights.data();
  descriptor.numHoles = static_cast<int>(holes.size());
  descriptor.holeIndices = holes.data();

  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  begin_opensubdiv_call();
  std::unique_ptr<Far::TopologyRefiner> refiner(
      Factory::Create(descriptor, Factory::Options(Sdc::SCHEME_CATMARK, sdc_options(cage.boundary))));
  if (!refiner) {
    const std::string why = last_opensubdiv_message();
    fail(Status::invalid_mesh, "OpenSubdiv rejected the cage topology" + (why.empty() ? std::string() : ": " + why));
  }
  fail_on_opensubdiv_error(Status::invalid_mesh, "OpenSubdiv could not read the cage topology");
  return refiner;
}

}  // namespace subdiv_detail
CAGEKIT_NAMESPACE_END
