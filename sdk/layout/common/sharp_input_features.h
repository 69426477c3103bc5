// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Sharp input features: the one definition of "the scan is sharp here" that every method's
// crease tags follow (simplify's cage edges, the quad remesher's region boundaries, the
// anisotropic remesher's feature lines). The thesis tags features by a dihedral-angle threshold
// (ch. 5 §5.3 feature lines, ch. 6 §6.4 region boundaries; spec thesis-ch4-6.md §1.3 [J]); a
// scan's noise also makes sharp dihedral angles, so an edge counts only when
//   1. the angle between its two faces' unit normals exceeds angle_degrees (the raw test),
//   2. the angle between its two *side normals* still exceeds confirm_fraction * angle_degrees:
//      the area-weighted mean normals of the faces within side_rings vertex rings of the edge on
//      either side of it (a face's side told by its centroid's position across the edge, not by
//      its normal). Along a feature line each side is one surface and the angle stays; on a
//      noisy or coarsely faceted scan the faces' normals scatter and their means do not (a
//      bilateral normal filter was tried first: it keeps large-angle noise, e.g. femur.off's
//      3,000 raw sharp edges, because its range weight treats them as features), and
//   3. it lies on a feature line at least min_length_rel * (bounding-box diagonal) long (and of
//      min_edges edges): the sharp edges joined into lines at each vertex, straightest
//      continuation first, where a line turns by less than max_turn_degrees. Lines end at corners
//      (three features meeting at right angles continue none), isolated noisy edges and the
//      zigzag webs of faceted organic scans give short lines and are dropped, feature lines
//      (also closed ones, e.g. a hole's rim) stay, and a noisy spur beside a line does not cut it;
//   4. it stands out from the surface beside it: the edges beside a sharp edge (the other
//      two-face edges at its ends, on the side its far end lies on, except raw sharp ones and a
//      zigzagging line's rungs) bend on the smoother side by at most max_side_bend_fraction of
//      its own angle on average, averaged (length-weighted) over its feature network (the sharp
//      edges joined through shared vertices). A CAD part's feature has at least one flat or
//      finely tessellated side (a chamfer between two 32-segment cylinders: 0.12); a coarsely
//      faceted organic scan bends everywhere, and the edges that pass 40 degrees there (a low-poly
//      hand's finger crevices, a bull's flanks) have sides that bend nearly as much (0.2 - 0.5).
//      Over the corpus's 48 classified meshes, simplify's organic crease density goes from 8.8 to
//      4.7 % of cage edges with every CAD mesh's creases unchanged (tests/bench/RESULTS.md).
// Only edges with exactly two faces can be sharp (border and non-manifold edges are tagged by
// the methods' own rules).
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/edge_key.h"
#include "core/polygon_mesh.h"
#include "core/task_monitor.h"

CAGEKIT_NAMESPACE_BEGIN

struct SharpFeatureOptions {
  double angle_degrees = 40.0;   // dihedral threshold, in [0, 180]
  int side_rings = 1;            // rings of the side normals' neighbourhood, in [0, 8] (0: test 1 alone)
  double confirm_fraction = 0.5;   // of angle_degrees, for the filtered normals, in [0, 1]
  double min_length_rel = 0.02;  // per feature line, of the bounding-box diagonal, >= 0
  uint32_t min_edges = 1;        // per feature line
  double max_turn_degrees = 60.0;  // a feature line continues through a vertex where it turns less, in [0, 180]
  double max_side_bend_fraction = 0.15;  // test 4, in [0, 1] (1: off)
  // The host's sharp edges (edge_key()s of mesh edges, e.g. the edges a Blender user marked
  // sharp): sharp whatever the tests say. detect = false: these alone (no angle test).
  std::vector<uint64_t> host_edges;
  bool detect = true;
};

struct SharpFeatures {
  std::vector<uint64_t> edges;  // sorted edge_key()s of the sharp edges
  std::vector<uint8_t> corner_flags;  // per corner of the mesh: 1 where the corner's half-edge is sharp
  uint64_t raw_edges = 0;       // edges passing test 1
  uint64_t noise_edges = 0;     // of those, failing test 2
  uint64_t short_edges = 0;     // of those passing 2, dropped by test 3
  uint64_t faceted_edges = 0;   // of those passing 3, dropped by test 4
  uint64_t host_edges = 0;      // the host's sharp edges (each counted once, detected or not)
  double length = 0.0;          // total length of the sharp edges

  bool contains(uint32_t a, uint32_t b) const { return std::binary_search(edges.begin(), edges.end(), edge_key(a, b)); }
};

// Sharp features of `mesh` (polygons; a face's normal is its vector area's direction), plus the
// host's edges. Faces must be valid polygons (indices in range, >= 3 distinct vertices, finite
// positions): else Error(invalid_mesh); options out of range, or a host edge that is not an
// edge of `mesh`: Error(invalid_argument). Degenerate faces (zero
// area) have no normal and make no edge sharp. O(faces x neighbours x passes). `monitor` gets a
// report (stage "sharp features") between the passes: a cancel there throws Error(cancelled).
SharpFeatures detect_sharp_features(const PolygonMesh& mesh, const SharpFeatureOptions& options = {},
                                    const TaskMonitor& monitor = {});


// Per input edge (edges[i] = {a, b}, vertices of `mesh`): 1 when it runs along the sharp features
// of `features` (detected on `mesh` with angle_degrees), so that a cluster or region border
// made of such edges follows a feature line. It does when
//   1. it is a sharp edge, or
//   2. a path over the sharp edges joins its ends (each end on a feature, or sharing an edge
//      with a vertex on one, that edge counted) no longer than twice the edge: a border that
//      zigzags one triangle beside a line, cuts a feature's corner or is a curved line's chord;
//   3. or its midpoint is no farther from the sharp edges at its ends than its farther end is,
//      plus a quarter of its length (beside a line with a gap), or
//   4. both ends are on features and its own dihedral angle exceeds half angle_degrees (the rungs
//      of a line that zigzags over a dense tessellation, where the lines take every other edge).
// An edge that only joins two feature lines does not: the axial edge of a coarsely tessellated
// bore, from the front rim to the back rim, or a diagonal across a flat strip between two.
// O(edges x feature vertices within twice the edge's length + mesh size).
std::vector<uint8_t> edges_along_features(const PolygonMesh& mesh, const SharpFeatures& features,
                                          const std::vector<std::pair<uint32_t, uint32_t>>& edges,
                                          double angle_degrees);

CAGEKIT_NAMESPACE_END
