// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The anisotropic remesher of thesis chapter 5 end to end (spec thesis-ch4-6.md §1): curvature
// tensor field (Stage I) -> curvature, feature and boundary lines (Stage II) -> quad-dominant
// polygon mesh (Stage III), returned as a cage whose feature-line edges are infinitely sharp
// creases, with the quality figures the C API and `cagekit remesh` report.
#include <cstdint>

#include "core/cage.h"
#include "core/polygon_mesh.h"
#include "core/task_monitor.h"
#include "layout/anisotropic/curvature_tensor_field.h"
#include "layout/common/remesh_quality.h"

CAGEKIT_NAMESPACE_BEGIN

struct AnisotropicRemeshOptions {
  double tolerance = 0.002;            // ε of (5.10), relative to the bbox diagonal (> 0)
  double feature_angle_degrees = 40.0; // dihedral angle above which edges are feature lines; < 0: none
  int max_face_valence = 5;            // >= 3
  double disk_radius_bbox = 0.01;      // curvature averaging radius / bbox diagonal (thesis: 1%), capped at
                                       // 6 mean edge lengths; <= 0: 3 mean edge lengths
  int threads = 0;                     // curvature field workers (0 = hardware concurrency)
  // The host's sharp edges (edge_key()s of input edges): feature lines (and crease tags) whatever
  // their angle, also with feature_angle_degrees < 0.
  std::vector<uint64_t> sharp_edges;
};

// The RemeshQuality part: faces, vertices, quads, valences, min scaled Jacobian of cage.mesh.
struct AnisotropicRemeshResult : RemeshQuality {
  Cage cage;  // the output mesh; feature-line edges tagged infinitely sharp
  uint64_t creases = 0;        // output edges on feature lines
  uint64_t regions = 0;        // connected regions of confident input faces (Λ >= cos π/6)
  uint64_t lines = 0;          // sampled lines of all types
  uint64_t holes = 0;          // half-edges left on rejected face cycles (0 expected)
  double mean_alignment_deg = 0.0;   // curvature-line edges vs the nearer principal direction (confident ends)
  double field_seconds = 0.0, sampling_seconds = 0.0, meshing_seconds = 0.0, seconds = 0.0;
};

// Remeshes `input`, a polygon mesh (faces with more than 3 vertices are fan-triangulated) that
// must be an oriented 2-manifold with finite positions, possibly with boundary. Errors:
// invalid_mesh (faces with < 3 or repeated vertices, bad indices, non-manifold or inconsistently
// oriented edges, non-finite positions, empty or zero-extent mesh), invalid_argument (options),
// cancelled (monitor). An input on which no two lines intersect gives an empty cage, not an error.
AnisotropicRemeshResult remesh_anisotropic(const PolygonMesh& input, const AnisotropicRemeshOptions& options,
                                           const TaskMonitor& monitor = {});

// The curvature-field options remesh_anisotropic uses on `triangles` (its fan-triangulated input)
// with `options`: the radius of options.disk_radius_bbox capped at 6 mean edge lengths, the
// threads, no detection of its own (the remesher passes its feature edges as host flags). For
// measuring other outputs against the same field (tests/bench/bench_remesh).
CurvatureOptions anisotropic_curvature_options(const PolygonMesh& triangles, const AnisotropicRemeshOptions& options);

CAGEKIT_NAMESPACE_END
