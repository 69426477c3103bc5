// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Stage II of the anisotropic remesher (thesis §5.5, spec thesis-ch4-6.md §1.3): sampling the
// input triangle mesh with lines of minimum and maximum principal curvature, plus feature lines
// (chains of tagged edges) and boundary lines (one per boundary loop).
//
// - Seeding (§5.5.1): a few sparse random seeds in the most confident anisotropic faces; while a
//   line is integrated, seeds for the opposite type are dropped whenever the arc length since
//   the last seed reaches D(p) of (5.10), with κ of the line's own type. Lines are started at the
//   collected seeds (FIFO) until none can be added without violating the density.
// - Density (5.10): D(p) = 2 sqrt(ε (2/|κ(p)| − ε)), clamped to [min_spacing, max_spacing].
// - Integration (5.11): RK4 in the local unfolding Ω (local_unfolding.h), step h = step_fraction
//   · D; after every step the database is queried with r = collision_factor · D(p) (κ of the
//   opposite type) for samples of the same type; a hit stops the pass, then the line is traced
//   from its seed in the opposite direction. Samples are inserted as integration proceeds.
// - Trusted directions (§5.5.5): in faces with Λ(f) < Λ_min the line goes straight in Ω (a
//   geodesic) along t_tr, the mean of the last trusted directions; on re-entering a confident
//   face it continues as a min line if |t_tr·t_min| >= |t_tr·t_max|, else as a max line. In
//   unreliable faces the type-less test stops the line when the length-weighted mean direction
//   of the other lines' segments within r is closer than π/4 to t_tr.
#include <cstdint>
#include <memory>
#include <vector>

#include "core/polygon_mesh.h"
#include "core/task_monitor.h"
#include "layout/anisotropic/curvature_tensor_field.h"
#include "layout/anisotropic/line_sample_database.h"

CAGEKIT_NAMESPACE_BEGIN

struct LineSamplingOptions {
  // ε of (5.10), relative to the bounding-box diagonal (> 0).
  double tolerance = 0.002;
  // Clamps of D (relative to the bbox diagonal). max_spacing also caps the query radius (the
  // thesis's "e.g. 5% of the bounding box diagonal"). min_spacing <= 0: 2 mean edge lengths.
  double min_spacing = 0.0;
  double max_spacing = 0.05;
  double confidence_threshold = 0.86602540378443865;  // Λ_min = cos(π/6)
  // Feature chains shorter than this many min spacings become no feature lines (and do not stop
  // curvature lines); they stay barriers of the tensor estimate [J].
  double min_feature_length = 2.0;
  double step_fraction = 0.2;      // h = step_fraction · D(p) [J]
  double collision_factor = 0.8;   // query radius r = collision_factor · D(p) [J]
  int trusted_history = 4;         // directions averaged into t_tr [J]
  int initial_seeds = 8;           // sparse random seeds [J]
  uint32_t random_seed = 1;
  size_t max_lines = 200000;       // hard bounds: never loop forever
  size_t max_segments = 5000000;  // ~0.5 GB of segments and list nodes
  int max_steps_per_pass = 200000;
};

// A sampled line: its segments in order along the line (a -> b of each is the line's direction).
struct SampledLine {
  LineType type = LineType::min_curvature;  // type at the seed (curvature lines may switch)
  bool closed = false;                      // last point == first point
  std::vector<uint32_t> segments;
};

struct LineSampling {
  std::shared_ptr<TriangleAdjacency> adjacency;
  std::shared_ptr<LineSampleDatabase> database;
  std::vector<SampledLine> lines;
  // Parameters used (model units) and counters.
  double epsilon = 0.0, min_spacing = 0.0, max_spacing = 0.0, bbox_diagonal = 0.0;
  size_t seeds_tried = 0, seeds_rejected = 0, steps = 0;
  bool truncated = false;
  size_t features_dropped = 0;  // feature chains shorter than min_feature_length  // max_lines or max_segments was reached: sampling stopped early
  size_t lines_by_type[4] = {0, 0, 0, 0};
  double seconds = 0.0;
};

// D of (5.10) with the clamps.
double line_spacing(double kappa, double epsilon, double min_spacing, double max_spacing);

// Samples `triangles` (an oriented 2-manifold triangle mesh, possibly with boundary) with lines.
// field: estimate_curvature_field of the same mesh; feature_corners: optional per-corner feature
// flags (use field.barrier_edges' feature part or detect_feature_edges). Errors: invalid_mesh
// (not triangles, non-manifold or inconsistently oriented edges, non-finite positions, empty),
// invalid_argument (bad options, field of another mesh), cancelled (monitor). Reaching max_lines
// or max_segments is not an error: sampling stops and `truncated` is set.
LineSampling sample_curvature_lines(const PolygonMesh& triangles, const CurvatureField& field,
                                    const LineSamplingOptions& options,
                                    const std::vector<uint8_t>* feature_corners = nullptr,
                                    const TaskMonitor& monitor = {});

CAGEKIT_NAMESPACE_END
