// SPDX-License-Identifier: GPL-3.0-or-later
// The limit surface as bicubic Bezier patches (subdiv/limit_patches.h).

#include "capi/api_guard.h"
#include "capi/option_conversion.h"
#include "subdiv/limit_patches.h"

using namespace cagekit_capi;

extern "C" {

CAGEKIT_API cagekit_status cagekit_limit_patches_create(cagekit_cage cage, const cagekit_limit_patch_options* options,
                                                        cagekit_limit_patches* out) {
  return guarded(context_of(cage), [&] {
    require_not_null(out, "out");
    *out = nullptr;
    cagekit_cage_t& c = checked(cage, "cage");
    const cagekit::LimitPatchOptions lo = limit_patch_options_from_c(options);
    cagekit::LimitPatches patches = cagekit::build_limit_patches(c.cage, lo, c.context->monitor());
    *out = std::make_unique<cagekit_limit_patches_t>(c.context, std::move(patches)).release();
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
    for (uint32_t k = 0; k < n; ++k) {
      const cagekit::LimitPatch& from = p.patches[k];
      cagekit_limit_patch& to = patch_array[k];
      to.ptex_face = from.ptex_face;
      to.cage_face = from.cage_face;
      to.u0 = from.u0;
      to.v0 = from.v0;
      to.u1 = from.u1;
      to.v1 = from.v1;
      to.exact = from.exact ? 1u : 0u;
      to.reserved = 0;
      to.error = from.error;
      for (int i = 0; i < 16; ++i) {
        to.control_points[3 * i] = from.points[i].x;
        to.control_points[3 * i + 1] = from.points[i].y;
        to.control_points[3 * i + 2] = from.points[i].z;
      }
    }
  });
}

}  // extern "C"
