// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Sample-count refinement of the two-step quad-dominant remeshing (not in the thesis, which
// samples every arc independently; README "Refinement by re-selection"): after every region has
// its curve selection (quad_region_selection.h), an arc next to an irregular region gets one
// segment more or less (within ±1 of ⌈len/δ⌉) when re-selecting its one or two regions lowers
// the irregularity of the glued mesh there (non-quad faces, samples without exactly one curve per
// side, anchors of valence != 4), ties broken by Σ E(L); first improvement, arcs in id order, at
// most `passes` sweeps. Arcs next to a region with more than `max_curves` candidate curves are
// not tried (its selection is the costly part). An arc whose regions are unchanged since its
// last try is not tried again.
//
// Each try is screened cheaply first: the regions' networks are rebuilt (bending fits of
// unchanged port pairs from `caches`) and their previous configurations, carried over to the
// new networks, repaired locally (improve_quad_selection with moves at the new ports and at the
// ports that lost their curve). Only a try whose screen lowers the irregularity gets the full
// selection (select_quad_curves, Phases I-III or enumeration); the better of the two
// (irregularity, then E) is kept if it beats the current state.
//
// Threads: the one or two regions of a try run on two threads unless `threads` is 1; the
// result does not depend on the thread count.
//
// Thread-safety: a pure function of its arguments, which it updates (the arcs' samples, the
// regions' networks and selections, the fit caches). Errors: those of the region selection;
// cancelled from the monitor (checked on the calling thread between tries).
#include <vector>

#include "core/task_monitor.h"
#include "layout/quad/quad_curve_network.h"
#include "layout/quad/quad_curve_selection.h"
#include "layout/quad/quad_region_selection.h"
#include "layout/quad/remesh_constraints.h"

CAGEKIT_NAMESPACE_BEGIN

void refine_sample_counts(RemeshConstraints& constraints, RegionQuadMeshes& meshes, const SelectionOptions& options,
                          std::vector<BendingFitCache>& caches, int passes, size_t max_curves, int threads,
                          const TaskMonitor& monitor);

CAGEKIT_NAMESPACE_END
