// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Structure-preserving face-merge simplification (thesis chapter 3, [MK05a]): greedy merging of
// adjacent polygonal faces by the combined L2/L2,1 priority (3.2)-(3.5) with the valence/angle
// tie-break (3.8), every result injectively projectable to its proxy plane (§3.3), contour
// decimation of valence-2 vertices (3.6)-(3.7), until no valid operation is left. The sequence
// of operations is recorded as a progressive hierarchy that can be browsed in both directions.
//
// Vertices of every level are input vertices at their input positions.
#include <cstdint>
#include <memory>
#include <vector>

#include "core/polygon_mesh.h"
#include "core/task_monitor.h"
#include "layout/common/planar_polygon.h"

CAGEKIT_NAMESPACE_BEGIN

struct SimplifyOptions {
  // Weight of the tie-break factors (3.8); the thesis leaves it open ("some small weight").
  double tie_break_epsilon = 0.01;
  // Debug/test aid: before every committed operation, re-evaluate every valid operation from
  // scratch and throw Error(internal_error) unless the committed one has the minimum priority.
  // O(n) validity checks per operation: small meshes only.
  bool verify_greedy_order = false;
  // Input edges (edge_key()s of mesh edges, e.g. the host's sharp edges) that stay borders of
  // every level: no merge crosses one. A border made of them is still straightened (a vertex
  // between two of them may go, its chord then stays a border); a vertex where such a line meets
  // an unlocked border stays. An edge that is not an input edge: Error(invalid_argument).
  std::vector<uint64_t> locked_edges;
};

// One face of a level: an outer loop and holes, as INPUT vertex indices (loops[0] outer,
// counter-clockwise about `normal`; holes clockwise), with its proxy (3.1).
struct PolygonalFace {
  std::vector<std::vector<uint32_t>> loops;
  Vec3 normal;     // N: area-weighted unit normal (recursive, (3.1))
  Vec3 centroid;   // B: area-weighted centroid
  double area = 0; // sigma: total input area of the cluster
};

// The coordinates the simplifier projects and validates faces in: input positions (and face
// centroids) as (p - origin) * scale. A face's planar embedding (project_face) must be computed
// in these same coordinates: the injectivity verdict of a nearly degenerate polygon can differ
// in the last bit between two coordinate systems, so a face validated in one could fail the
// check (and the triangulation) in another. Identity for levels that did not come from the
// simplifier.
struct LevelCoordinates {
  Vec3 origin;
  double scale = 1;
};

struct PolygonalLevel {
  std::vector<PolygonalFace> faces;
  LevelCoordinates coordinates;
  std::vector<uint32_t> cluster_of_input_face;  // input face -> index into faces
  uint64_t num_vertices = 0;                    // distinct input vertices used by the loops
  double l2_error = 0;                          // sum of (3.3) terms of the committed faces, normalised
  double l21_error = 0;                         // sum of (3.4) terms, normalised
};

// Work counters of one hierarchy build (diagnostics and tests: they show how the cost grows).
struct SimplifyStats {
  uint64_t triangulations = 0;         // faces triangulated from scratch (CDT of the whole face)
  uint64_t triangulated_vertices = 0;  // sum of the loop vertex counts of those faces
  uint64_t incremental_updates = 0;    // faces whose CDT moments were updated without a CDT
};

class SimplificationHierarchy {
 public:
  // Runs the simplification to the coarsest level. The input must be a valid mesh (no
  // non-manifold edges/vertices, consistent orientation); throws Error(invalid_mesh) otherwise.
  // Long operation: monitor.report("simplify", fraction) and cancellation.
  SimplificationHierarchy(const PolygonMesh& input, const SimplifyOptions& options = {},
                          const TaskMonitor& monitor = {});
  ~SimplificationHierarchy();
  SimplificationHierarchy(SimplificationHierarchy&&) noexcept;
  SimplificationHierarchy& operator=(SimplificationHierarchy&&) noexcept;

  // Level 0 is the input; level num_levels()-1 the coarsest. Each level is one committed
  // operation (a merge together with the valence-2 removals it triggered, or a boundary
  // vertex removal) away from its neighbours.
  size_t num_levels() const;
  size_t current_level() const;
  // Moves to `level` applying/undoing recorded operations: constant time per level stepped.
  void go_to_level(size_t level);

  // Face and vertex counts of any level without moving there (recorded at build time).
  uint64_t face_count(size_t level) const;
  uint64_t vertex_count(size_t level) const;
  double error(size_t level) const;  // normalised priority of the operation that made `level`
  // The finest level with at most `faces` faces / `vertices` vertices, or the coarsest level
  // if none has so few; the coarsest level whose error is <= max_error.
  size_t level_for_face_count(uint64_t faces) const;
  size_t level_for_vertex_count(uint64_t vertices) const;
  size_t level_for_error(double max_error) const;

  // The current level's faces and the cluster map.
  PolygonalLevel extract() const;
  const SimplifyStats& stats() const;
  const PolygonMesh& input() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

CAGEKIT_NAMESPACE_END
