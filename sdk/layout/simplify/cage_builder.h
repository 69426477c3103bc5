// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// From a polygonal level of the simplification hierarchy to a Catmull-Clark control cage
// (thesis §3.4): each face is partitioned into convex quad-dominant cells using only diagonals
// of its constrained Delaunay triangulation, lifted back to the input vertices, and the cage's
// edges get crease tags where the scan is sharp along the border of two clusters (or, by the
// thesis's rule, where neighbouring clusters meet at a sharp angle) and on the mesh boundary, so
// the limit surface keeps the part's sharp features.
#include <cstdint>
#include <vector>

#include "core/cage.h"
#include "core/task_monitor.h"
#include "layout/common/quad_dominant_partition.h"
#include "layout/common/sharp_input_features.h"
#include "layout/simplify/face_merge_simplifier.h"

CAGEKIT_NAMESPACE_BEGIN

// Which cage edges between two clusters become infinitely sharp creases.
enum class CreaseRule {
  // Where the scan itself is sharp (the default): the input edges along the cage edge's border
  // (the chain of input edges between the two clusters that the cage edge spans) run along
  // sharp input features (sharp_input_features.h) for at least `sharp_share` of their length
  // (an input edge runs along a feature when both its ends lie on a sharp edge or one input edge
  // away from one: cluster borders zigzag beside feature lines), and the clusters' proxy normals
  // differ by more than half the feature angle, and the input faces along the border on either
  // side do too (band_rings). Organic scans get smooth cages, CAD parts keep their feature lines.
  sharp_input,
  // The thesis's rule (§3.4): the clusters' proxy normals differ by more than
  // crease_angle_degrees (and, with input_crease_angle_degrees >= 0, the input is sharp enough
  // along the clusters' border on average).
  cluster_angle,
};

struct CageBuildOptions {
  CreaseRule crease_rule = CreaseRule::sharp_input;
  // sharp_input: the definition of a sharp input edge, and the share of a border's length that
  // must be sharp.
  SharpFeatureOptions features;
  double sharp_share = 0.9;  // 0.5 before 2026-12-03 (same CAD figures, denser organic creases)
  // sharp_input: and the mean normals of the two clusters' input faces within band_rings vertex
  // rings of the border differ by more than band_fraction x the feature angle (0 rings: not
  // checked): a faceted organic scan's sharp facet edges are not a crease of its cage.
  int band_rings = 3;
  double band_fraction = 0.75;
  // cluster_angle: a cage edge on the border of two clusters is tagged infinitely sharp when the
  // clusters' proxy normals differ by more than this angle (degrees). Negative: never.
  double crease_angle_degrees = 30.0;
  // cluster_angle: ... and only where the input itself is sharp along the border of the two
  // clusters: the length-weighted mean angle between the normals of the input faces on either
  // side of the input edges that separate the clusters exceeds this angle (degrees). Negative:
  // not checked (clusters' proxy normals alone decide).
  double input_crease_angle_degrees = -1.0;
  // Tag the edges on the mesh boundary (they are creases under the thesis's rule anyway;
  // tagging them keeps them sharp under any boundary rule).
  bool tag_boundary_edges = true;
  PartitionOptions partition;
};

struct CageBuildReport {
  uint64_t quads = 0, triangles = 0, pentagons = 0, other = 0;
  uint64_t creases = 0;
  uint64_t non_optimal_faces = 0;              // level faces whose partition is not proven optimal
  // Cage edges used by more than two cage faces: a diagonal chosen inside one level face that
  // joins the same two vertices as an edge elsewhere (0 expected; reported, not hidden).
  uint64_t non_manifold_edges = 0;
  // Diagonals flipped out of a face's triangulation because another face already joined their
  // two vertices (the face was then partitioned again on the flipped triangulation).
  uint64_t diagonals_flipped = 0;
  // Diagonals no flip could remove: the two cells on them were merged into one cell (possibly
  // non-convex, counted in quads/pentagons/other by its size).
  uint64_t cells_merged = 0;
  // Level faces not injectively projectable to their own plane (only input polygons the
  // simplifier never merged can be: every merge result is validated): emitted as one cell,
  // their loop as the input had it, instead of being triangulated and partitioned.
  uint64_t unprojectable_faces = 0;
  std::vector<uint32_t> input_vertex_of;       // cage vertex -> input vertex
  std::vector<uint32_t> cluster_of_cage_face;  // cage face -> level face (cluster)
};

// `monitor` gets "cage" reports (fraction 0..1) through the per-face partitions and between the
// crease passes over the input (cancel points: a second or two in all on a million-face input).
Cage build_quad_dominant_cage(const PolygonMesh& input, const PolygonalLevel& level,
                              const CageBuildOptions& options = {}, CageBuildReport* report = nullptr,
                              const TaskMonitor& monitor = {});

// The level's faces as a polygon mesh over the used input vertices: faces without holes as
// they are, faces with holes as their constrained Delaunay triangles (polygon meshes cannot hold
// holes). `faces_triangulated` (may be null) receives how many level faces were triangulated.
PolygonMesh polygonal_level_mesh(const PolygonMesh& input, const PolygonalLevel& level,
                                 uint64_t* faces_triangulated = nullptr,
                                 std::vector<uint32_t>* input_vertex_of = nullptr);

// The planar embedding of one level face in its proxy plane, in the level's coordinates (the
// ones the simplifier validated the face in, so its verdict and this one agree bit for bit):
// loop vertices projected, with `input_vertex_of_point` mapping polygon points back to input
// vertices.
PolygonLoops project_face(const PolygonMesh& input, const PolygonalFace& face, const LevelCoordinates& coordinates,
                          std::vector<uint32_t>* input_vertex_of_point);

CAGEKIT_NAMESPACE_END
