// SPDX-License-Identifier: GPL-3.0-or-later
// The limit surface as bicubic Bezier patches (subdiv/limit_patches.h).

#include "capi/api_guard.h"
#include "capi/option_conversion.h"
#include "capi/report_conversion.h"
#include "subdiv/limit_patches.h"

using namespace cagekit_capi;

extern "C" {

CAGEKIT_API cagekit_status cagekit_limit_patches_create(cagekit_cage cage, const cagekit_limit_patch_options* options,
                                                        cagekit_limit_patches* out) {
  return create_from(cage, "cage", out, [&](cagekit_cage_t& c) {
    const cagekit::LimitPatchOptions lo = limit_patch_options_from_c(options);
    cagekit::LimitPatches patches = cagekit::build_limit_patches(c.cage, lo, c.context->monitor());
    return std::make_unique<cagekit_limit_patches_t>(c.context, std::move(patches));
  });
}

CAGEKIT_API void cagekit_limit_patches_retain(cagekit_limit_patches patches) { retain_handle(patches); }
CAGEKIT_API void cagekit_limit_patches_release(cagekit_limit_patches patches) { release_handle(patches); }

CAGEKIT_API cagekit_status cagekit_limit_patches_get_info(cagekit_limit_patches patches,
                                                          cagekit_limit_patch_info* info) {
  return guarded(context_of(patches), [&] {
    const cagekit::LimitPatches& p = checked(patches, "patches").patches;
    require_not_null(info, "info");
    cagekit_limit_patch_info i{};
    i.struct_size = sizeof(i);
    i.patch_count = static_cast<uint32_t>(p.patches.size());
    i.exact_count = p.exact_count;
    i.approximated_count = p.approximated_count;
    i.over_tolerance_count = p.over_tolerance_count;
    i.max_error = p.max_error;
    i.max_error_rel = p.bbox_diagonal > 0 ? p.max_error / p.bbox_diagonal : 0.0;
    i.bbox_diagonal = p.bbox_diagonal;
    i.tolerance = p.tolerance;
    write_versioned(info, i, "cagekit_limit_patch_info");
  });
}

CAGEKIT_API cagekit_status cagekit_limit_patches_get(cagekit_limit_patches patches, uint32_t patch_capacity,
                                                     uint32_t* patch_count_out, cagekit_limit_patch* patch_array) {
  return guarded(context_of(patches), [&] {
    const cagekit::LimitPatches& p = checked(patches, "patches").patches;
    const auto n = static_cast<uint32_t>(p.patches.size());  // at most 2^20 (build_limit_patches)
    if (!two_call_check("patch", n, patch_capacity, patch_count_out, {{"patch_array", patch_array}})) return;
    for (uint32_t k = 0; k < n; ++k) patch_array[k] = limit_patch_to_c(p.patches[k]);
  });
}

}  // extern "C"
