// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Variational Shape Approximation [CSAD04] with the L2,1 metric: the segmentation step of the
// two-step quad-dominant remeshing (thesis §6.3, spec thesis-ch4-6.md §2.2, AC6-9).
//
// A region R_i has a proxy normal N_i; a face f costs E(f, N) = |f| ‖n_f − N‖² and the total
// error is Σ_i Σ_{f∈R_i} E(f, N_i). One Lloyd iteration = (1) each region's seed becomes its
// face of least cost, (2) the seeds flood the mesh through a priority queue of (face, region)
// costs (regions stay edge-connected), (3) each proxy becomes the normalised area-weighted mean
// normal of its faces (the L2,1 optimum, so that region error = 2(|R| − ‖Σ|f| n_f‖)).
//
// Region count: regions are added one at a time (tolerance mode) or in batches of a fraction of
// the current count (count mode, `insertion_batch_fraction`), each seeded at the worst face
// (largest cost) of one of the worst regions (largest error), with `insertion_lloyd_iterations`
// Lloyd iterations after each insertion and a relaxation to convergence at the final count. In count mode this stops
// at `region_count`; in tolerance mode at the first count whose error / total area <= tolerance
// (the errors of all counts are kept in `count_history`).
//
// Teleporting with roll-back (the thesis's change to VSA): at the final count, the region whose
// merge with a neighbour costs least is removed and re-seeded at the worst face of the worst
// region; after `teleport_relaxation_steps` Lloyd iterations the teleport is kept only if the
// total error is lower than before it, else the previous partition and proxies are restored
// exactly. Each attempt is recorded.
//
// Host control: `pinned_regions` are face sets that become regions of their own and never
// change (flooding does not enter them, they are never teleported); `seed_faces` start regions
// at given faces (they then relax like the others).
//
// Thread-safety: a pure function of its arguments; concurrent calls are safe.
// Errors (Error, never abort): invalid_mesh for a mesh that is not a valid triangle mesh
// (require_triangle_mesh); invalid_argument for bad options, fewer faces than regions, a region
// count below (pinned regions + connected components of the unpinned faces), overlapping,
// empty, out-of-range or disconnected pinned sets, seed faces that are pinned or repeated;
// cancelled from the monitor.
#include <cstdint>
#include <vector>

#include "core/polygon_mesh.h"
#include "core/task_monitor.h"

CAGEKIT_NAMESPACE_BEGIN

struct VsaOptions {
  // Count mode (tolerance < 0): the number of regions, pinned ones included.
  // Tolerance mode (tolerance >= 0): the largest number of regions to try.
  int region_count = 30;
  // When >= 0: stop at the first region count with total L2,1 error / total area <= tolerance
  // (dimensionless: a mean of ‖n_f − N‖², 0 for planar regions, at most 4).
  double tolerance = -1.0;
  // Lloyd iterations per relaxation at most; a relaxation also stops when an iteration lowers
  // the error by less than relative_convergence (relative to the total area) or raises it (the
  // lower state is kept).
  int max_lloyd_iterations = 50;
  double relative_convergence = 1e-9;
  // Lloyd iterations after each region insertion (at most max_lloyd_iterations); the final count
  // is then relaxed to convergence. Tolerance mode judges each count by the error after these
  // iterations (the final relaxation only lowers it).
  int insertion_lloyd_iterations = 5;
  // Count mode: regions inserted per step, as a fraction of the current count (at least one;
  // each into a different one of the worst regions, at its worst face), in the spirit of CGAL's
  // hierarchical seeding: ~log(count) insertion steps instead of count. 0: one at a time (the
  // thesis's incremental insertion). With 0.2 the final L2,1 error was equal or lower on 7 of 8
  // shared mesh / count pairs (fandisk 30 and 80, rocker arm 20 and 41, bunny 60, spot 30,
  // cheburashka 40; bunny 25: +4%) at 1.3-3x less time (sdk/layout/quad/README.md, "Speed"). Tolerance mode
  // always inserts one at a time.
  double insertion_batch_fraction = 0.2;
  // Teleport attempts at the final count (0 = no teleporting) and the Lloyd iterations run
  // after a tentative teleport before it is judged ("a few more relaxation steps").
  int teleport_attempts = 10;
  int teleport_relaxation_steps = 5;
  // Host-given regions (fixed) and seeds (each starts one region).
  std::vector<std::vector<uint32_t>> pinned_regions;
  std::vector<uint32_t> seed_faces;
  // Edges no region grows across (sorted edge_key()s, e.g. the host's sharp edges): every patch
  // they enclose is a component of its own and gets at least one region.
  std::vector<uint64_t> barrier_edges;
};

struct VsaTeleport {
  uint32_t removed_region;   // the region removed (its id is reused by the new seed)
  uint32_t target_region;    // the worst region, where the new seed went
  uint32_t seed_face;
  double error_before, error_after;  // total error before the teleport and after the relaxation window
  bool accepted;
};

struct VsaSegmentation {
  std::vector<uint32_t> face_region;   // region of every face
  std::vector<Vec3> proxy_normal;      // per region (unit; zero only for a region of zero area)
  std::vector<double> region_area, region_error;
  std::vector<uint32_t> region_seed;   // the seed face of the last Lloyd iteration
  std::vector<uint8_t> region_pinned;  // 1 for host-pinned regions (ids 0 .. pinned-1)
  double total_error = 0.0;            // Σ region_error (L2,1, model units: area)
  double total_area = 0.0;
  // Total error after every Lloyd iteration (partition + proxy fit) of every relaxation, in
  // order; relaxation_starts[k] is the index in error_history where relaxation k began.
  std::vector<double> error_history;
  std::vector<size_t> relaxation_starts;
  // Lloyd iterations that raised the error and were undone (each ends its relaxation).
  size_t rejected_lloyd_iterations = 0;
  // (region count, relaxed error) for every count reached while adding regions.
  std::vector<std::pair<uint32_t, double>> count_history;
  std::vector<VsaTeleport> teleports;

  size_t num_regions() const { return proxy_normal.size(); }
  // Faces of region r in increasing order.
  std::vector<uint32_t> region_faces(uint32_t r) const;
};

VsaSegmentation segment_vsa(const PolygonMesh& triangles, const VsaOptions& options, const TaskMonitor& monitor = {});

CAGEKIT_NAMESPACE_END
