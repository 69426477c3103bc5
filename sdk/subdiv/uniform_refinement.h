// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Uniform Catmull-Clark refinement of a cage (thesis §2.2.2–2.2.3) on OpenSubdiv Far.
// OpenSubdiv applies rule (2.6) on every untagged edge; the thesis's rule (2.7) is not
// implemented (see sdk/subdiv/README.md).
//
// Thread-safety: both functions only read their arguments and keep no state; they may run
// concurrently (also on the same cage). OpenSubdiv's error callback is process-global: CageKit
// installs a silent one on first use.
// Errors: Error(invalid_mesh) for a cage that cannot be subdivided (bad indices or offsets, faces
// with < 3 or repeated vertices, non-finite positions, tags naming missing edges/vertices/faces,
// negative/NaN sharpness), invalid_argument for levels outside [0, kMaxUniformLevels],
// limit_exceeded for hostile sizes, cancelled when the monitor asks to stop.
#include <vector>

#include "core/cage.h"
#include "core/task_monitor.h"

CAGEKIT_NAMESPACE_BEGIN

struct RefineOptions {
  int levels = 1;                 // 0..kMaxUniformLevels
  bool limit_positions = false;   // push the refined vertices onto the limit surface (2.15–2.17)
};

constexpr int kMaxUniformLevels = 8;

// Returns the level-`levels` control mesh: all quads for levels >= 1; crease tags of the result
// are the refined tags (infinitely sharp stays infinitely sharp on both sub-edges, semi-sharp
// sharpness decreases by one per level as in OpenSubdiv); corners stay on their vertices,
// holes become the child faces of hole faces. Hostile sizes (the result would exceed 2^31
// face-vertices) fail with Status::limit_exceeded before allocating.
Cage refine_uniform(const Cage& cage, const RefineOptions& options, const TaskMonitor& monitor = {});

// Limit positions and unit normals of the cage's own vertices (thesis (2.15)–(2.17), (2.14)),
// computed after one refinement step so that non-quad faces are handled. Either output may be
// null. A vertex used by no face keeps its position and gets a zero normal.
void limit_positions_and_normals(const Cage& cage, std::vector<Vec3>* positions, std::vector<Vec3>* normals);

CAGEKIT_NAMESPACE_END
