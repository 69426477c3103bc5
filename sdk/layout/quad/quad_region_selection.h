// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Steps 3-4 of the two-step quad-dominant remeshing over every region of a segmentation: per
// region, the curve network in its LSCM domain (quad_curve_network.h) from
// RemeshConstraints::loop_samples_uv, then the curve selection (quad_curve_selection.h).
// Regions are independent; they run on `threads` workers, largest first, and the result does
// not depend on the thread count.
//
// Thread-safety: pure function. Errors: those of build_curve_network and select_quad_curves
// (with the region id in the message); invalid_argument for threads < 0; cancelled from the
// monitor (checked between regions on the calling thread's worker).
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/task_monitor.h"
#include "layout/quad/quad_curve_network.h"
#include "layout/quad/quad_curve_selection.h"
#include "layout/quad/remesh_constraints.h"

CAGEKIT_NAMESPACE_BEGIN

struct RegionQuadMeshes {
  std::vector<CurveNetwork> networks;     // per region
  std::vector<QuadSelection> selections;  // per region
  double energy = 0.0;                    // Σ E(L) over the regions
  size_t faces = 0, quads = 0;            // over the region meshes (the glued mesh has the same faces)
};

// `fit_caches` (optional): resized to one BendingFitCache per region and filled by the network
// builds, for later rebuilds of the same regions (the remesher's sample-count refinement).
// `failures` (optional): a region whose network or selection fails (other than by cancel or
// out-of-memory) is recorded here (region id, message) and left with an empty network and
// selection, instead of failing the whole call with "region r: ...".
// A region whose outer loop of samples has no positive area in its domain (a sliver narrower
// than the sample spacing: its samples are collinear) is recorded with degenerate_boundary set,
// without building its network: such a region is merged into a neighbour, not split.
struct RegionFailure {
  uint32_t region = 0;
  std::string message;
  bool degenerate_boundary = false;
};

// `memo` (optional): the network and selection of each region by its sample loops (the exact
// domain coordinates). A region whose loops are bit-identical to a memoised one's gets the same
// result without a rebuild (the selection is a pure function of the loops and the options, which
// must stay the same across calls sharing a memo): the remesher's layout retries redo only the
// regions a split or merge changed. Failing regions are not memoised. Thread-safe within a call.
struct SelectionMemo {
  struct Entry {
    CurveNetwork network;
    QuadSelection selection;
    BendingFitCache fit_cache;
  };
  std::mutex mutex;
  std::unordered_map<std::string, Entry> entries;
  uint64_t hits = 0;
};
RegionQuadMeshes select_region_quads(const RemeshConstraints& constraints, const CurveNetworkOptions& network_options,
                                     const SelectionOptions& selection_options, int threads = 1,
                                     const TaskMonitor& monitor = {},
                                     std::vector<BendingFitCache>* fit_caches = nullptr,
                                     std::vector<RegionFailure>* failures = nullptr, SelectionMemo* memo = nullptr);

CAGEKIT_NAMESPACE_END
