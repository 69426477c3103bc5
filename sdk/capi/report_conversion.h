// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The C++ results -> the C report structs, one table per struct (report_conversion.cpp): each
// row names a C field and the expression of the C++ result `r` it receives, so that a report's
// fields are mapped in one place, next to the others.
#include <cagekit/cagekit.h>

#include "core/mesh_repair.h"
#include "core/mesh_statistics.h"
#include "fit/surface_fitter.h"
#include "layout/anisotropic/anisotropic_remesher.h"
#include "layout/quad/quad_remesher.h"
#include "layout/simplify/cage_builder.h"
#include "pipeline/scan_to_cage.h"
#include "subdiv/limit_patches.h"

namespace cagekit_capi {

cagekit_fit_pass fit_pass_to_c(const cagekit::FitPassStatistics& r);
cagekit_fit_two_sided fit_two_sided_to_c(const cagekit::FitPassStatistics& r);
cagekit_limit_patch limit_patch_to_c(const cagekit::LimitPatch& r);
cagekit_fit_report fit_report_to_c(const cagekit::FitReport& r);
cagekit_repair_report repair_report_to_c(const cagekit::RepairReport& r);
cagekit_mesh_info mesh_info_to_c(const cagekit::MeshStatistics& r);
cagekit_cage_report cage_report_to_c(const cagekit::CageBuildReport& r);
cagekit_anisotropic_report anisotropic_report_to_c(const cagekit::AnisotropicRemeshResult& r);
cagekit_quad_remesh_report quad_report_to_c(const cagekit::QuadRemeshResult& r);
cagekit_scan_to_cage_report scan_to_cage_report_to_c(const cagekit::ScanToCageResult& r, uint32_t limit_levels);

}  // namespace cagekit_capi
