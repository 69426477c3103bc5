// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The constraints of the two-step quad-dominant remeshing (thesis §6.4, spec thesis-ch4-6.md
// §2.3-2.5), assembled from a segmentation: the region boundaries (anchors, arcs, loops), per arc
// the 3D cubic (6.1) and its samples at spacing about δ (⌈len/δ⌉ ± 1 segments, chosen jointly
// over the arcs by allocate_arc_segments; shared by both neighbouring regions), per
// region its LSCM domain Ω_i and, per arc of the region, the planar pre-image C̄ fitted to the
// arc's (u, v) with the same 3D parameters s_j, evaluated at the same t_k (§6.4.3).
//
// This is the input of the curve network (§6.5): for region i, loop l, its constrained points
// are loop_samples(i, l) in 3D and loop_samples_uv(i, l) in Ω_i, in loop order (region on the
// left, so the outer loop runs counter-clockwise in Ω_i and holes clockwise), every anchor once.
//
// Thread-safety: pure functions. Errors: those of compute_region_boundaries, fit_arc_cubic,
// sample_arc_cubic and parameterize_region_lscm (e.g. invalid_mesh for a region with a handle);
// invalid_argument for spacing <= 0; cancelled from the monitor.
#include <cstdint>
#include <vector>

#include "core/polygon_mesh.h"
#include "core/task_monitor.h"
#include "core/vec2.h"
#include "layout/quad/arc_fit.h"
#include "layout/quad/lscm_parameterization.h"
#include "layout/quad/region_boundaries.h"

CAGEKIT_NAMESPACE_BEGIN

struct ArcConstraint {
  std::vector<double> s;   // arc-length parameters of the arc's vertices
  ArcCubic cubic;          // (6.1) in 3D
  double fit_rms = 0.0;    // arc_fit_rms of the cubic
  double fit_max_deviation = 0.0;  // max over the arc's vertices of ‖v_i − C(s_i)‖
  ArcSamples samples;      // c_0 .. c_{r+1} and their t_k
  uint32_t base_segments = 1;  // max(1, ⌈len(C)/δ⌉): the segment count at spacing at most δ
};

struct RegionArcDomain {
  uint32_t arc = 0;        // arc id
  ArcCubic planar;         // C̄ in Ω_i (z = 0), fitted to the arc's (u, v) in the arc's direction
  std::vector<Vec2> samples_uv;  // C̄(t_k), arc direction; ends = the anchors' (u, v)
};

struct RemeshConstraints {
  // The region boundaries, with the arcs split where a cubic fits them poorly, and each region's
  // loops reordered so that the outer loop (largest signed area in Ω_i: counter-clockwise) is
  // first; the holes follow, longest first.
  RegionBoundaries boundaries;
  std::vector<ArcConstraint> arcs;               // per arc of `boundaries`
  std::vector<RegionParameterization> domains;   // per region
  // Per region, one entry per arc on its loops, in the order of region_loops flattened.
  std::vector<std::vector<RegionArcDomain>> region_arcs;
  // The input's border loops (its holes and open borders) as the mesh-border arcs on each, chained
  // at their anchors (sorted by arc id), and per arc its border loop (kMeshBorder: an interior arc).
  std::vector<std::vector<uint32_t>> border_loops;
  std::vector<uint32_t> arc_border_loop;

  std::vector<Vec3> loop_samples(uint32_t region, size_t loop) const;
  std::vector<Vec2> loop_samples_uv(uint32_t region, size_t loop) const;
};

struct ConstraintOptions {
  double spacing = 0.0;  // δ in model units (> 0); see spacing_from_bbox_fraction
  // An arc whose cubic has an RMS distance (arc_fit_rms) above max_fit_rms * δ is split at its
  // middle vertex (by arc length) into two arcs, recursively (spec §2.4 [J]: one cubic fits a
  // very curved arc poorly). The RMS, not the largest vertex deviation, is the criterion: the
  // zig-zag of a region boundary along input edges deviates by about half an edge length from
  // any smooth curve, and splitting cannot remove it. <= 0: never split.
  double max_fit_rms = 0.25;
  // Joint choice of the arcs' sample counts (not in the thesis, which samples every arc
  // independently at spacing δ): each arc's number of segments (interior samples + 1) is chosen
  // within ±1 of ⌈len/δ⌉ so that every region's boundary has an even number of samples (a
  // quad-only mesh of the region needs it) and, on a region with four corners, opposite sides
  // get equal counts. See allocate_arc_segments. false: ⌈len/δ⌉ per arc.
  bool balance_samples = true;
  // Internal angle in Ω_i (radians, between the chords of C̄ from the anchor to the points δ
  // along its two arcs) below which an anchor is a corner of its region (sides are separated there).
  double corner_angle = 2.6;  // ~149°
};

// The border loop of `arc` (if it is a mesh-border arc) keeps >= 3 samples and, with two arcs, a
// sample inside each (compute_remesh_constraints guarantees both; a hole with fewer is closed by
// the glued faces on either side). true for an interior arc; std::out_of_range for a bad arc id.
bool border_loop_is_polygon(const RemeshConstraints& constraints, uint32_t arc);

// Re-samples arc `arc` with `segments` (>= 1) equidistant segments: its 3D samples and, in both
// neighbouring regions, C̄(t_k) (ends kept at the anchors' (u, v)). Errors: invalid_argument for
// an arc id out of range or segments == 0.
void resample_arc(RemeshConstraints& constraints, uint32_t arc, uint32_t segments);

// The fewest constrained points on one loop of `region` (Σ of its arcs' segment counts; the
// curve network needs >= 3 per loop; compute_remesh_constraints guarantees that). UINT64_MAX
// for a region without loops; std::out_of_range for a bad region id.
uint64_t fewest_loop_points(const RemeshConstraints& constraints, uint32_t region);

// Every loop of `region` can be a curve-network polygon: >= 3 constrained points, and a sample
// inside each arc of a two-arc loop (compute_remesh_constraints guarantees both).
bool loops_are_polygons(const RemeshConstraints& constraints, uint32_t region);

// The sample-count problem: per arc the ideal number of segments len/δ and per region its sides
// (runs of arcs between two corners; a loop without corners is one side). A region with
// `quad_like` (exactly four sides, one loop) also pays for unequal opposite sides.
struct SegmentAllocationRegion {
  std::vector<std::vector<uint32_t>> sides;  // arc ids; every arc of the region exactly once
  bool quad_like = false;
};

struct SegmentAllocationOptions {
  double odd_cost = 4.0;       // per region with an odd boundary sample count
  double mismatch_cost = 8.0;  // per unit of |side_0 − side_2| + |side_1 − side_3| (quad-like)
  double deviation_cost = 1.0; // per unit of |n_a − b_a| on an arc
  int max_change = 1;          // n_a within ±max_change of b_a (>= 0)
  int anneal_steps = 20000;    // randomised single-arc moves after the greedy descent (fixed seed)
};

// Per arc a segment count n_a with max(1, b_a − max_change) <= n_a <= b_a + max_change,
// b_a = max(1, ⌈ideal_a⌉) (ideal within 1e-9 of an integer counts as that integer), minimising
// Σ_regions (odd_cost·[odd] + mismatch_cost·mismatch) + deviation_cost·Σ_arcs |n_a − b_a|:
// greedy single-arc descent from n = b, then simulated annealing over single-arc moves from the
// best found (deterministic: fixed seed); the best configuration seen is returned, never worse
// than n = b. Errors: invalid_argument for an arc id out of range or a non-finite / negative ideal.
std::vector<uint32_t> allocate_arc_segments(const std::vector<double>& ideal,
                                            const std::vector<SegmentAllocationRegion>& regions,
                                            const SegmentAllocationOptions& options = {});

// The cost allocate_arc_segments minimises (for tests and reports).
double segment_allocation_cost(const std::vector<uint32_t>& segments, const std::vector<double>& ideal,
                               const std::vector<SegmentAllocationRegion>& regions,
                               const SegmentAllocationOptions& options = {});

// δ = fraction * bounding-box diagonal (the thesis gives δ as 2%-10% of the diagonal).
double spacing_from_bbox_fraction(const PolygonMesh& mesh, double fraction);

// `domains` (optional): the regions' LSCM maps already computed (make_disk_regions, in region
// order), moved from; an empty entry is computed here.
RemeshConstraints compute_remesh_constraints(const PolygonMesh& triangles, const std::vector<uint32_t>& face_region,
                                             size_t num_regions, const ConstraintOptions& options,
                                             const TaskMonitor& monitor = {},
                                             std::vector<RegionParameterization>* domains = nullptr);

CAGEKIT_NAMESPACE_END
