// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The two-step quad-dominant remesher of thesis chapter 6 end to end (spec thesis-ch4-6.md
// §2-§4): VSA segmentation (vsa_segmentation.h) -> constraints: anchors, arcs, cubic fits,
// samples at spacing δ, LSCM domains (remesh_constraints.h) -> per region the curve network and
// the curve selection (quad_region_selection.h) -> post-processing (thesis §6.8):
//  - Laplacian relaxation of every region's inner vertices (curve crossings) in its LSCM domain
//    Ω_i, the boundary samples fixed: Gauss-Seidel sweeps moving a vertex to the mean of its
//    neighbours in the region mesh; a move (or, failing that, half of it) is taken only if every
//    face around the vertex keeps a positive signed area in Ω_i and no convex corner of those
//    faces next to the vertex becomes reflex, so relaxation never folds a region mesh;
//  - mapping to 3D: an inner vertex is located in the region's parameterised input triangles
//    (the closest one, clamped, when it lies outside all of them: the boundary samples are points
//    of the planar cubics C̄, which may leave Ω_i slightly) and placed by barycentric
//    interpolation of their 3D positions; boundary samples keep their 3D positions on the arc
//    cubics (6.1);
//  - gluing: the region meshes share their boundary samples (the same samples for both
//    neighbours by construction), so the glued mesh is one polygon mesh;
//  - crease tags (infinitely sharp) on the cage edges of interior arcs: the edge between
//    samples c_k and c_{k+1} is tagged when at least half the length of the arc's input edges
//    whose middles lie in [t_k, t_{k+1}] (arc-length parameter of the cubic) are sharp input
//    features (sharp_input_features.h, angle `crease_angle_degrees`: the definition all
//    methods share; so a feature line that fades out along an arc, as on fandisk, is tagged as
//    far as it is sharp, and a faceted organic scan's noise is not).
//
// Thread-safety: a pure function (selection runs `threads` workers over the regions).
// Errors: invalid_mesh for an input that is not an oriented 2-manifold triangle mesh after fan
// triangulation (faces with < 3 or repeated vertices, bad indices, non-finite positions,
// non-manifold or inconsistently oriented edges) or that has a region with a handle (LSCM needs
// disks, possibly with holes); invalid_argument for bad options or more regions than faces;
// cancelled from the monitor; internal_error if the glued mesh is not a valid 2-manifold (a
// region whose selection left a face around an unreached hole loop, for instance).
#include <cstdint>
#include <vector>

#include "core/cage.h"
#include "core/polygon_mesh.h"
#include "core/task_monitor.h"
#include "layout/common/remesh_quality.h"

CAGEKIT_NAMESPACE_BEGIN

struct QuadRemeshOptions {
  // |S|: the number of VSA regions (>= 1). 0: tolerance mode, the first count up to
  // max_regions whose L2,1 error / area is <= region_tolerance.
  int regions = 30;
  double region_tolerance = 0.01;
  int max_regions = 200;
  // A region count (regions > 0) below the number of feature patches (faces joined across edges
  // that are not sharp input features, sharp_input_features.h, each with at least 0.5 % of the
  // area) is raised to this many regions per patch, capped at max_regions: fewer regions than
  // patches leave sharp features inside regions, where they are not creased (pinion.off, 33
  // patches: 30 regions crease 62 % of its sharp length, 43 regions 92 %, 50 (the rule) all of it; VSA needs
  // the slack on curved patches). A count at or above the patch count is kept (a cube's 6).
  // 0: off (the thesis's fixed count).
  double regions_per_feature_patch = 1.5;
  double edge_length = 0.05;  // δ, the boundary sample spacing relative to the bbox diagonal, (0, 1]
  // Table 6.1's w△ / w_PT / w_T (> 0).
  double triangle_weight = 40.0, pentagon_weight = 40.0, t_joint_weight = 100.0;
  double crease_angle_degrees = 40.0;  // dihedral angle of a sharp region-boundary piece; < 0: no creases
  int relaxation_iterations = 20;      // Gauss-Seidel sweeps of the Laplacian relaxation (>= 0)
  int threads = 0;                     // selection workers (0 = hardware concurrency)
  // Sample-count refinement after the selection (not in the thesis): an arc next to an irregular
  // region gets one sample more or less when re-selecting its regions makes the glued mesh more
  // regular there (non-quad faces, boundary samples and anchors of valence != 4). Each try is
  // screened by a local repair of the regions' previous configurations; only promising ones get
  // the full selection (sdk/layout/quad/README.md, "Speed"). Sweeps over the arcs (0: none); arcs next
  // to a region with more than `max_curves` candidate curves are skipped.
  int sample_refinement_passes = 1;
  int sample_refinement_max_curves = 200;
  // Host control of the segmentation (VsaOptions, in ids of the input's faces; a polygon stands
  // for all of its fan triangles): each pinned set becomes a region of its own that never changes
  // (edge-connected, disjoint; counted in `regions`), each seed face starts a region.
  std::vector<std::vector<uint32_t>> pinned_regions;
  std::vector<uint32_t> seed_faces;
  // The host's sharp edges (edge_key()s of input edges): region borders of the segmentation (no
  // region grows across one; each patch they enclose gets a region) and crease tags where the
  // region boundaries follow them (also with crease_angle_degrees < 0).
  std::vector<uint64_t> sharp_edges;
  // Re-seeding (not in the thesis): when no layout of the segmentation's regions comes out valid
  // (every retry and the last resort failed), the segmentation is redone with this many times
  // the regions it had, in turn, and laid out again (capped at the triangle count; a count not
  // above the previous one ends the re-seeding). Smaller regions are disks with injective maps
  // more often and span thin walls less. Empty: off (the failure is the error).
  std::vector<double> reseed_factors = {10.0 / 3.0, 20.0 / 3.0};
  // Layouts per segmentation, the first and its retries (>= 1). A retry is made when the number
  // of failing regions dropped, and also, whatever it did, when the layout was glued and at most
  // retry_few_failing_share of its regions fail (0: only when it dropped, as before 2026-12-06:
  // 4 layouts, share 0).
  int layout_attempts = 8;
  double retry_few_failing_share = 0.1;
};

// The RemeshQuality part: faces, vertices, quads, valences, min scaled Jacobian of cage.mesh.
struct QuadRemeshResult : RemeshQuality {
  Cage cage;              // the glued mesh; sharp region-boundary edges tagged infinitely sharp
  uint64_t regions = 0;   // regions used: VSA's, then split until each is a disk (disk_regions.h)
  uint64_t requested_regions = 0;  // the count asked for (raised to the component count and by
                                   // regions_per_feature_patch, capped at the triangle count, when
                                   // no regions are pinned or seeded)
  uint64_t split_regions = 0;      // splits made: for disk-like regions with injective maps, and
                                   // of regions whose layout failed (the layout is then redone)
  uint64_t merged_regions = 0;     // sliver regions (no area in their sample loop) merged into a neighbour
  uint64_t layout_retries = 0;     // layouts redone after such splits or merges
  uint64_t mended_faces = 0;       // faces of the final layout repaired where two regions' faces
                                   // coincided or a face repeated a vertex (mend_glue_conflicts)
  // The last resort (not in the thesis): regions whose layout still failed when no retry changed
  // the regions any more, each laid out by the quad-dominant partition (thesis §3.4, no Steiner
  // points) of its polygon of samples in its domain, or by the polygon itself when that is not a
  // valid planar polygon but a single loop (a loop touching itself is cut into simple cycles
  // first); the layout is then glued and checked again like any other.
  uint64_t partitioned_regions = 0;
  // The region count of the re-seeded segmentation whose layout is the result (reseed_factors);
  // 0 when the first segmentation's layout was (the figures above are those of the layout returned).
  uint64_t reseeded_regions = 0;
  // The VSA region of every triangle of the fan-triangulated input (input faces in order, a face
  // of n corners giving n - 2 triangles); the host's pinned regions are ids 0 .. pinned - 1.
  std::vector<uint32_t> face_region;
  uint64_t arcs = 0, samples = 0;  // arcs after splitting; constrained points (anchors included)
  // Per arc, its final number of sample segments (after the allocation and the refinement);
  // resample_arc(constraints, a, arc_segments[a]) reproduces the samples from the constraints.
  std::vector<uint32_t> arc_segments;
  uint64_t creases = 0;            // tagged cage edges
  uint64_t crease_arcs = 0;        // interior arcs with at least one tagged edge
  // Output faces whose normal disagrees (dot <= 0) with the normal of the input triangle under
  // the face's centroid in Ω_i (0 expected).
  uint64_t flipped_faces = 0;
  uint64_t outside_domain_vertices = 0;  // inner vertices placed on the closest triangle (outside Ω_i)
  double l21_error = 0.0;                // VSA error / total area
  // Σ E(L) over the regions: final, and of each region's starting configuration (Phase I, or for
  // a region last changed by a screened refinement try, the configuration its repair started from)
  double energy = 0.0, phase1_energy = 0.0;
  double segmentation_seconds = 0.0, constraint_seconds = 0.0, selection_seconds = 0.0;
  double refinement_seconds = 0.0;  // the sample-count refinement's share of selection_seconds
  double postprocess_seconds = 0.0, seconds = 0.0;
};

// Remeshes `input` (faces with more than 3 vertices are fan-triangulated). Progress stages:
// "vsa segmentation", "remesh constraints", "quad region selection", "post-processing".
QuadRemeshResult remesh_quad_dominant(const PolygonMesh& input, const QuadRemeshOptions& options,
                                      const TaskMonitor& monitor = {});

CAGEKIT_NAMESPACE_END
