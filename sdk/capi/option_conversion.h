// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The C option structs -> the C++ options: every field checked once (Error(invalid_argument)
// "cagekit_<struct>.<field> must be …"), shared by the entry points that take the same struct.
#include <cstdint>

#include <cagekit/cagekit.h>

#include "fit/surface_fitter.h"
#include "layout/anisotropic/anisotropic_remesher.h"
#include "layout/simplify/cage_builder.h"
#include "layout/quad/quad_remesher.h"

namespace cagekit_capi {

// NULL = defaults; a struct of an older size gets the defaults for the fields it lacks.
cagekit::FitOptions fit_options_from_c(const cagekit_fit_options* options);
cagekit::CageBuildOptions cage_options_from_c(const cagekit_cage_options* options);

// `input_faces` bounds the quad remesher's seed and pinned-face lists.
cagekit::AnisotropicRemeshOptions anisotropic_options_from_c(const cagekit_anisotropic_options* options);
cagekit::QuadRemeshOptions quad_options_from_c(const cagekit_quad_remesh_options* options, uint64_t input_faces);

// The fit report's pass array (an input inside the output struct), read before the fit so that
// a bad struct_size fails before any work.
struct PassArray {
  uint32_t capacity = 0;
  cagekit_fit_pass* entries = nullptr;
};
PassArray read_pass_array(const cagekit_fit_report* report);
// Writes *report (NULL: nothing) from the C++ report; `final` is the returned state.
void write_fit_report(cagekit_fit_report* report, const PassArray& passes, const cagekit::FitReport& fr);
cagekit_fit_pass fit_pass_to_c(const cagekit::FitPassStatistics& s);
cagekit_fit_two_sided fit_two_sided_to_c(const cagekit::FitPassStatistics& s);

}  // namespace cagekit_capi
