// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Builds an OpenSubdiv Far::TopologyRefiner (Catmull-Clark) from a Cage: faces, crease edges,
// corner vertices, hole faces and the boundary rule.
#include <opensubdiv/far/topologyRefiner.h>
#include <opensubdiv/sdc/options.h>

#include <memory>

#include "core/cage.h"

CAGEKIT_NAMESPACE_BEGIN
namespace subdiv_detail {

// Sdc options of a cage: uniform creasing (semi-sharp sharpness decreases by one per level),
// Catmull-Clark rules on triangles, and the boundary rule
//   edges_only        -> VTX_BOUNDARY_EDGE_ONLY   (the thesis: boundary corners not pinned)
//   edges_and_corners -> VTX_BOUNDARY_EDGE_AND_CORNER.
OpenSubdiv::Sdc::Options sdc_options(BoundaryRule rule);

// Validates the cage (check_cage_for_subdivision) and returns its unrefined topology refiner.
// Throws Error(Status::invalid_mesh) with OpenSubdiv's message when its factory rejects the
// topology, limit_exceeded for sizes OpenSubdiv cannot index.
std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> create_topology_refiner(const Cage& cage);

}  // namespace subdiv_detail
CAGEKIT_NAMESPACE_END
