// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Feature (sharp) edges of a polygon mesh by dihedral angle (thesis ch. 5 speaks only of
// "tagged edges"; spec thesis-ch4-6.md §1.3 [J]: a dihedral-angle threshold).
//
// Flags are per corner, as the host gives them: flags[c] != 0 tags the edge of corner c's
// half-edge (from face_vertices[c] to the next corner's vertex). An edge is a feature when any
// of its half-edges is tagged, so a host may tag one side or both.
#include <cstdint>
#include <vector>

#include "core/edge_map.h"
#include "core/polygon_mesh.h"

CAGEKIT_NAMESPACE_BEGIN

// Per-edge flags over `map` (edge-indexed): 1 where the angle between the unit normals of the
// edge's two faces exceeds angle_degrees. face_normals: unit normal per face of map.mesh (a zero
// vector for degenerate faces: such edges are not flagged). Edges of other valence than 2 are
// not flagged here (the curvature field treats them as barriers anyway).
std::vector<uint8_t> dihedral_feature_edges(const detail::EdgeMap& map, const std::vector<Vec3>& face_normals,
                                            double angle_degrees);

// Per-corner flags (size mesh.num_face_vertices()) of the edges whose dihedral angle exceeds
// angle_degrees, both half-edges of a flagged edge set. Faces must be valid polygons (indices in
// range, >= 3 distinct vertices, finite positions); otherwise Error(invalid_mesh).
// angle_degrees must be in [0, 180] (Error(invalid_argument)).
std::vector<uint8_t> detect_feature_edges(const PolygonMesh& mesh, double angle_degrees);

// Throws Error(invalid_mesh), the message starting with `who`, unless every face of `mesh` is a
// valid polygon: indices in range, >= 3 distinct vertices, finite positions (the input rule of
// the feature detectors here and in sharp_input_features.h).
void check_feature_input(const PolygonMesh& mesh, const char* who);

CAGEKIT_NAMESPACE_END
