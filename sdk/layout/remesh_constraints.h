// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The constraints of the two-step quad-dominant remeshing (thesis §6.4, spec thesis-ch4-6.md
// §2.3-2.5), assembled from a segmentation: the region boundaries (anchors, arcs, loops), per arc
// the 3D cubic (6.1) and its samples at spacing δ (shared by both neighbouring regions), per
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
#include <array>
#include <cstdint>
#include <vector>

#include "core/polygon_mesh.h"
#include "core/task_monitor.h"
#include "layout/arc_fit.h"
#include "layout/lscm_parameterization.h"
#include "layout/region_boundaries.h"

CAGEKIT_NAMESPACE_BEGIN

struct ArcConstraint {
  std::vector<double> s;   // arc-length parameters of the arc's vertices
  ArcCubic cubic;          // (6.1) in 3D
  double fit_rms = 0.0;    // arc_fit_rms of the cubic
  double fit_max_deviation = 0.0;  // max over the arc's vertices of ‖v_i − C(s_i)‖
  ArcSamples samples;      // c_0 .. c_{r+1} and their t_k
};

struct RegionArcDomain {
  uint32_t arc = 0;        // arc id
  ArcCubic planar;         // C̄ in Ω_i (z = 0), fitted to the arc's (u, v) in the arc's direction
  std::vector<std::array<double, 2>> samples_uv;  // C̄(t_k), arc direction; ends = the anchors' (u, v)
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

  std::vector<Vec3> loop_samples(uint32_t region, size_t loop) const;
  std::vector<std::array<double, 2>> loop_samples_uv(uint32_t region, size_t loop) const;
};

struct ConstraintOptions {
  double spacing = 0.0;  // δ in model units (> 0); see spacing_from_bbox_fraction
  // An arc whose cubic has an RMS distance (arc_fit_rms) above max_fit_rms * δ is split at its
  // middle vertex (by arc length) into two arcs, recursively (spec §2.4 [J]: one cubic fits a
  // very curved arc poorly). The RMS, not the largest vertex deviation, is the criterion: the
  // zig-zag of a region boundary along input edges deviates by about half an edge length from
  // any smooth curve, and splitting cannot remove it. <= 0: never split.
  double max_fit_rms = 0.25;
};

// δ = fraction * bounding-box diagonal (the thesis gives δ as 2%-10% of the diagonal).
double spacing_from_bbox_fraction(const PolygonMesh& mesh, double fraction);

RemeshConstraints compute_remesh_constraints(const PolygonMesh& triangles, const std::vector<uint32_t>& face_region,
                                             size_t num_regions, const ConstraintOptions& options,
                                             const TaskMonitor& monitor = {});

CAGEKIT_NAMESPACE_END
