// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The basis rows (8.3) of a scan binding: the non-zero basis functions phi_j and their
// derivatives at every vertex's foot point, evaluated on the limit surface and stored sparsely
// in the ScanBinding (row_offsets / control_index / phi, phi_u, phi_v, and with exact normals
// phi_uu, phi_uv, phi_vv). Shared by bind_scan_to_cage and the binding-file reader, so a saved
// and reloaded binding has bit-identical rows.
#include <vector>

#include "core/task_monitor.h"
#include "fit/closest_point_on_limit_surface.h"
#include "multires/scan_binding.h"
#include "subdiv/subdivision_surface.h"

CAGEKIT_NAMESPACE_BEGIN

// surface.basis() at every foot point, on `threads` threads; progress "bind" from f0 to f1.
std::vector<BasisWeights> evaluate_basis_rows(const SubdivisionSurface& surface, const std::vector<FootPoint>& feet,
                                              int threads, const TaskMonitor& monitor, double f0, double f1);

// Flattens `rows` (one per vertex) into the binding's sparse row arrays (replacing them); the
// second-derivative arrays only with `second_derivatives`.
void store_basis_rows(ScanBinding& binding, const std::vector<BasisWeights>& rows, bool second_derivatives);

CAGEKIT_NAMESPACE_END
