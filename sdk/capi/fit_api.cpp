// SPDX-License-Identifier: GPL-3.0-or-later
// Fitting a cage's limit surface to a scan (thesis ch. 7): cagekit_cage_fit.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "capi/api_guard.h"
#include "capi/option_conversion.h"
#include "fit/crease_feature_rows.h"
#include "fit/surface_fitter.h"
#include "layout/common/sharp_input_features.h"

using namespace cagekit_capi;

extern "C" {

CAGEKIT_API cagekit_status cagekit_cage_fit(cagekit_cage cage, cagekit_mesh scan, const cagekit_fit_options* options,
                                            cagekit_cage* out, cagekit_fit_report* report, uint32_t pass_capacity,
                                            uint32_t* pass_count_out, cagekit_fit_pass* passes) {
  return create_from(cage, "cage", out, [&](cagekit_cage_t& c) {
    const cagekit_mesh_t& s = checked(scan, "scan");
    const cagekit::FitOptions fit_options = fit_options_from_c(options);
    check_fit_report(report);
    check_pass_array(fit_options.max_passes, pass_capacity, pass_count_out, passes, "pass", "passes");
    if (s.mesh.num_vertices() == 0) fail(Status::invalid_argument, "scan has no vertices");

    // The scan's sharp edges for the crease-feature rows (the definition every method's creases
    // follow); a scan whose faces that detection refuses is fitted without them.
    std::vector<cagekit::FeatureSegment> features;
    if (fit_options.crease_feature_reach > 0 && !c.cage.creases.empty()) {
      try {
        features = cagekit::feature_segments(s.mesh, cagekit::detect_sharp_features(s.mesh).edges);
      } catch (const cagekit::Error& e) {
        if (e.status() != Status::invalid_mesh) throw;
      }
    }
    cagekit::FitReport fr;
    cagekit::Cage fitted =
        cagekit::fit_cage_to_mesh(c.cage, s.mesh, fit_options, &fr, c.context->monitor(), &features);
    auto handle = std::make_unique<cagekit_cage_t>(c.context, std::move(fitted));
    write_fit_report(report, fr);
    write_pass_array(fr, pass_capacity, pass_count_out, passes, "pass", "passes");
    return handle;
  });
}

}  // extern "C"
