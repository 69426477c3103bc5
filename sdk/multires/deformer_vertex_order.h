// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The order in which the CPU deformer writes the scan's vertices (cells in table order, each
// cell's vertices, then the irregular vertices), as a renumbering a host may apply to its scan.
//
// The deformer's output writes go to the caller's arrays in the scan's vertex order; where that
// order does not follow the cells (a scan whose vertices were appended by refinement, or a scan
// in scanner order), every vertex's position and normal land on different cache lines and the
// stores dominate a full frame. A host that may renumber its scan (e.g. on import) renumbers it
// once by this order and binds again: the writes become sequential and are done with streaming
// stores (bench_deform --cell-order, on 2 cores, 625K-triangle bunny: 226-280 full frames/s with
// double outputs where the scan's own order gives 192-231; tests/bench/RESULTS.md).
// Not in the thesis (§8.6.4 reorders the GPU's index buffer for the vertex cache instead).
//
// Thread-safety: pure function. Errors: none (a binding without a compact table gives the
// identity order).
#include <cstdint>
#include <vector>

#include "multires/scan_binding.h"

CAGEKIT_NAMESPACE_BEGIN

// order[k] = the scan vertex that becomes vertex k: each scan vertex once, in the order the
// deformer first writes it (with a sector split: the scan's own vertices, a copy counting for its
// source), then the scan vertices it never writes. Renumbering the scan with new id of
// order[k] = k keeps every face and position.
std::vector<uint32_t> deformer_vertex_order(const ScanBinding& binding);

CAGEKIT_NAMESPACE_END
