// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The C option structs -> the C++ options: every field checked once (Error(invalid_argument)
// "cagekit_<struct>.<field> must be …"), shared by the entry points that take the same struct.
#include <cstdint>

#include <cagekit/cagekit.h>
#include <cagekit/cagekit_gl.h>

#include "core/io/mesh_io.h"
#include "core/mesh_repair.h"
#include "fit/surface_fitter.h"
#include "gpu/gl_deformer.h"
#include "layout/simplify/face_merge_simplifier.h"
#include "multires/scan_binding.h"
#include "pipeline/scan_to_cage.h"
#include "subdiv/limit_bspline_surfaces.h"
#include "subdiv/limit_patches.h"
#include "subdiv/subdivision_surface.h"
#include "subdiv/uniform_refinement.h"
#include "layout/anisotropic/anisotropic_remesher.h"
#include "layout/simplify/cage_builder.h"
#include "layout/quad/quad_remesher.h"

namespace cagekit_capi {

// NULL = defaults; a struct of an older size gets the defaults for the fields it lacks.
cagekit::FitOptions fit_options_from_c(const cagekit_fit_options* options);
cagekit::CageBuildOptions cage_options_from_c(const cagekit_cage_options* options);

cagekit::WriteOptions write_options_from_c(const cagekit_write_options* options);
cagekit::RepairOptions repair_options_from_c(const cagekit_repair_options* options);
cagekit::RefineOptions subdivide_options_from_c(const cagekit_subdivide_options* options);
cagekit::SurfaceOptions surface_options_from_c(const cagekit_surface_options* options);
cagekit::LimitPatchOptions limit_patch_options_from_c(const cagekit_limit_patch_options* options);
cagekit::LimitBSplineOptions limit_surface_options_from_c(const cagekit_limit_surface_options* options);
cagekit::SimplifyOptions simplify_options_from_c(const cagekit_simplify_options* options);
cagekit::BindOptions bind_options_from_c(const cagekit_bind_options* options);
cagekit::GlDeformerOptions gl_deformer_options_from_c(const cagekit_gl_deformer_options* options);
// `input_faces` bounds the quad remesher's seed and pinned-face lists.
cagekit::AnisotropicRemeshOptions anisotropic_options_from_c(const cagekit_anisotropic_options* options);
cagekit::QuadRemeshOptions quad_options_from_c(const cagekit_quad_remesh_options* options, uint64_t input_faces);
cagekit::ScanToCageOptions scan_to_cage_options_from_c(const cagekit_scan_to_cage_options* options,
                                                       uint64_t input_faces);

// Checks the fit report's struct_size (NULL: nothing) before the fit, so that a bad one fails
// before any work.
void check_fit_report(const cagekit_fit_report* report);
// Writes *report (NULL: nothing) from the C++ report; `final` is the returned state.
void write_fit_report(cagekit_fit_report* report, const cagekit::FitReport& fr);
// The fit's pass array (two-call; `x` names its parameters <x>_capacity and <x>_count_out,
// `name` the array). The fit is not repeated for a second call, so before it the array is
// checked against the most states it can measure, max_passes + 1: a short one fails before any
// work. After it, write_pass_array writes the count measured and the entries.
void check_pass_array(int max_passes, uint32_t capacity, uint32_t* count_out, const cagekit_fit_pass* passes,
                      const char* x, const char* name);
void write_pass_array(const cagekit::FitReport& fr, uint32_t capacity, uint32_t* count_out, cagekit_fit_pass* passes,
                      const char* x, const char* name);

}  // namespace cagekit_capi
