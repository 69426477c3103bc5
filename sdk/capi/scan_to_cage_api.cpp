// SPDX-License-Identifier: GPL-3.0-or-later
// The scan-to-cage journey: cagekit_scan_to_cage, the C shim over pipeline/scan_to_cage.h.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "capi/api_guard.h"
#include "capi/option_conversion.h"
#include "capi/report_conversion.h"
#include "pipeline/scan_to_cage.h"

using namespace cagekit_capi;

extern "C" {

CAGEKIT_API cagekit_status cagekit_scan_to_cage(cagekit_mesh scan, const cagekit_scan_to_cage_options* options,
                                                cagekit_cage* cage_out, cagekit_cage* limit_out,
                                                cagekit_scan_to_cage_report* report, cagekit_fit_report* fit_report,
                                                uint32_t fit_pass_capacity, uint32_t* fit_pass_count_out,
                                                cagekit_fit_pass* fit_passes) {
  return guarded(context_of(scan), [&] {
    require_not_null(cage_out, "cage_out");
    *cage_out = nullptr;
    if (limit_out) *limit_out = nullptr;
    cagekit_mesh_t& m = checked(scan, "scan");
    const cagekit::ScanToCageOptions o = scan_to_cage_options_from_c(options, m.mesh.num_faces());
    check_fit_report(fit_report);
    // Every fit of the journey (remedies and refit included) has o.fit.max_passes.
    check_pass_array(o.fit.max_passes, fit_pass_capacity, fit_pass_count_out, fit_passes, "fit_pass", "fit_passes");
    if (report) {  // a bad struct_size fails before any work
      cagekit_scan_to_cage_report probe{};
      probe.struct_size = sizeof(probe);
      write_versioned(report, probe, "cagekit_scan_to_cage_report");
    }
    cagekit::ScanToCageResult r = cagekit::scan_to_cage(m.mesh, o, m.context->monitor());
    auto cage = std::make_unique<cagekit_cage_t>(m.context, std::move(r.cage));
    std::unique_ptr<cagekit_cage_t> limit;
    if (limit_out) limit = std::make_unique<cagekit_cage_t>(m.context, r.limit);
    r.cage = cage->cage;  // for the report's cage figures
    write_versioned(report, scan_to_cage_report_to_c(r, uint32_t(o.limit_levels)), "cagekit_scan_to_cage_report");
    write_fit_report(fit_report, r.fit);
    write_pass_array(r.fit, fit_pass_capacity, fit_pass_count_out, fit_passes, "fit_pass", "fit_passes");
    *cage_out = cage.release();
    if (limit_out) *limit_out = limit.release();
  });
}

}  // extern "C"
