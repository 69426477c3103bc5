// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Contour refinement of a simplified level: puts input vertices of the clusters' borders back
// into the level's loops where the border strays from the level edge.
//
// Chapter 3 decimates every valence-2 contour vertex (§3.3.3), so a level edge is a straight
// chord across what is in the input a curved border chain of many edges between two clusters.
// At the coarsest levels those chords dominate the distance between input and output. This
// post-process (not in the thesis; the same idea as the chord subdivision of VSA's meshing step,
// Cohen-Steiner et al. 2004 §5) splits each level edge by Douglas-Peucker on its border chain:
// the chain vertex farthest from the chord is inserted while that distance exceeds the
// tolerance. Faces keep their clusters and proxies; every added vertex is an input vertex at its
// input position; both faces along an edge get the same vertices (the chain is processed in a
// canonical direction), so the result is as much a mesh as the level. A face whose refined
// loops would fail the injectivity test (§3.3.1) keeps its level edges unrefined (and so do its
// neighbours on those edges).
#include <cstdint>

#include "core/polygon_mesh.h"
#include "layout/simplify/face_merge_simplifier.h"

CAGEKIT_NAMESPACE_BEGIN

struct ContourRefinementReport {
  uint64_t vertices_added = 0;   // loop vertices added over all faces (a shared vertex counts per face)
  uint64_t edges_refined = 0;    // level edges (per face side) that got vertices
  uint64_t edges_coarsened = 0;  // level edge sides refined with a larger tolerance (a face was invalid)
  uint64_t edges_frozen = 0;     // level edge sides left unrefined because a face would be invalid
  uint64_t edges_no_chain = 0;   // level edge sides whose border chain was not found (left as is)
};

// `chord_tolerance` in model units (> 0, finite). Returns the refined level (cluster map and
// proxies copied; num_vertices updated). Error(invalid_argument) for a bad tolerance.
PolygonalLevel refine_level_contours(const PolygonMesh& input, const PolygonalLevel& level, double chord_tolerance,
                                     ContourRefinementReport* report = nullptr);

CAGEKIT_NAMESPACE_END
