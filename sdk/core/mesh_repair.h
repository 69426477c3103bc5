// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Explicit repair of a polygon mesh (never done implicitly). Order of the steps:
// weld by tolerance -> drop faces with out-of-range indices or non-finite vertices ->
// drop degenerate faces -> drop duplicate faces -> split non-manifold edges and vertices ->
// orient each connected component consistently -> optionally drop unreferenced vertices.
// Welding and dropping non-finite vertices renumber the vertices (kept in their original
// order); splitting appends copies at the end. Orientation keeps, per component, the
// orientation of the majority of its faces (ties: that of its first face).
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
                                        // (and by cutting non-orientable components, see below)
  uint64_t flipped_faces = 0;
  uint64_t removed_unreferenced_vertices = 0;
  // Vertices with NaN/Inf coordinates removed by the drop_invalid_faces step (once the faces
  // using them are gone they are removed too, so that the result validates).
  uint64_t removed_non_finite_vertices = 0;
  // Components that cannot be oriented (a Moebius strip): the orientation of the majority of
  // their faces is kept and, with split_non_manifold, they are cut open along the conflicting
  // edges (the vertices added are counted in split_vertices).
  uint64_t non_orientable_components = 0;
};

PolygonMesh repair_mesh(const PolygonMesh& mesh, const RepairOptions& options,
                        RepairReport* report = nullptr, const TaskMonitor& monitor = {});

CAGEKIT_NAMESPACE_END
