// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Explicit repair of a polygon mesh (never done implicitly). Order of the steps:
// weld by tolerance -> drop faces with out-of-range indices or non-finite vertices ->
// drop degenerate faces -> drop duplicate faces -> split non-manifold edges and vertices ->
// orient each connected component consistently -> optionally drop unreferenced vertices.
#include <cstdint>

#include "core/polygon_mesh.h"
#include "core/task_monitor.h"

CAGEKIT_NAMESPACE_BEGIN

struct RepairOptions {
  // Vertices closer than this (absolute, in model units) are merged; 0 merges exact duplicates
  // only; negative disables welding.
  double weld_tolerance = 0.0;
  bool drop_invalid_faces = true;       // out-of-range indices or non-finite positions
  bool drop_degenerate_faces = true;
  bool drop_duplicate_faces = true;
  bool split_non_manifold = true;       // edges used by >2 faces and vertices with >1 fan
  bool orient_consistently = true;
  bool remove_unreferenced_vertices = false;
};

struct RepairReport {
  uint64_t welded_vertices = 0;
  uint64_t dropped_invalid_faces = 0;
  uint64_t dropped_degenerate_faces = 0;
  uint64_t dropped_duplicate_faces = 0;
  uint64_t split_vertices = 0;          // vertices added by splitting non-manifold configurations
  uint64_t flipped_faces = 0;
  uint64_t removed_unreferenced_vertices = 0;
};

PolygonMesh repair_mesh(const PolygonMesh& mesh, const RepairOptions& options,
                        RepairReport* report = nullptr, const TaskMonitor& monitor = {});

CAGEKIT_NAMESPACE_END
