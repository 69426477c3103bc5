// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The first phase of the scan-to-cage journey: turn what a user brings (STL soups, shuffled
// orientations, non-manifold scans, zero-area faces, several pieces) into a valid manifold mesh
// the methods accept, and say what was changed. Built on core's repair_mesh (weld within a
// tolerance, drop degenerate and duplicate faces, split non-manifold edges and vertices, orient
// every component), without its drop-invalid-faces step: out-of-range indices and NaN/Inf
// positions are corrupt input and stay clean errors. Not in the thesis, whose inputs are clean.
#include <cstdint>
#include <string>

#include "core/mesh_repair.h"
#include "core/polygon_mesh.h"
#include "core/task_monitor.h"

CAGEKIT_NAMESPACE_BEGIN

enum class ComponentMode {
  all,      // keep every connected component (the default)
  largest,  // keep only the component with the most faces (scans with stray pieces)
};

struct ConditioningOptions {
  // false: nothing is changed and an invalid mesh is refused (Status::invalid_mesh).
  bool repair = true;
  ComponentMode components = ComponentMode::all;
  // Vertices closer than this x the bounding-box diagonal are welded (STL soups store every
  // corner per triangle; exporters round them differently); 0 welds exact duplicates only.
  double weld_tolerance_relative = 1e-7;
};

struct ConditioningReport {
  uint64_t input_vertices = 0, input_faces = 0;
  uint64_t vertices = 0, faces = 0;  // after conditioning
  RepairReport repair;
  uint64_t components = 0;          // connected components (by shared vertices) after repair
  uint64_t dropped_components = 0;  // ComponentMode::largest
  uint64_t dropped_component_faces = 0;
  // True when the mesh was changed in any way.
  bool changed() const;
  // "welded 12 vertices, dropped 3 degenerate faces, ..." or "nothing to change".
  std::string summary() const;
};

// Returns the conditioned mesh. Throws Error(invalid_mesh) for out-of-range indices or
// non-finite positions (naming the first), for an invalid mesh with repair off, and when no face
// is left ("nothing left after conditioning: ..."); Error(invalid_argument) for a negative or
// non-finite tolerance; cancelled via the monitor. Logs one info line naming every change.
PolygonMesh condition_input(const PolygonMesh& scan, const ConditioningOptions& options,
                            ConditioningReport* report = nullptr, const TaskMonitor& monitor = {});

CAGEKIT_NAMESPACE_END
