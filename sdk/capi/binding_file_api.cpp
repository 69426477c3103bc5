// SPDX-License-Identifier: GPL-3.0-or-later
// Saved bindings (.ckb): write a binding with its cage, read one back (sdk/multires/binding_file.h).
#include "capi/api_guard.h"
#include "capi/option_rules.h"
#include "core/io/file_io.h"
#include "multires/binding_file.h"

using namespace cagekit_capi;

namespace {

cagekit_status read(cagekit_context context, const char* path, const void* data, size_t size, uint32_t threads,
                    cagekit_binding* out) {
  return guarded(is_live(context) ? context : nullptr, [&] {
    require_not_null(out, "out");
    *out = nullptr;
    checked(context, "context");
    apply(kThreads, threads, "threads", threads);
    std::vector<uint8_t> file;
    const uint8_t* bytes = static_cast<const uint8_t*>(data);
    if (path) {
      file = cagekit::read_whole_file(path);
      bytes = file.data(), size = file.size();
    } else if (!data && size > 0) {
      fail(Status::invalid_argument, "data is NULL but size is " + std::to_string(size));
    }
    cagekit::SavedBinding saved =
        cagekit::read_binding(bytes, size, path ? path : "<memory>", int(threads), context->monitor());
    *out = std::make_unique<cagekit_binding_t>(context, std::move(saved.binding), std::move(saved.cage),
                                               saved.options)
               .release();
  });
}

}  // namespace

extern "C" {

CAGEKIT_API cagekit_status cagekit_binding_write_file(cagekit_binding binding, const char* path) {
  return guarded(context_of(binding), [&] {
    const cagekit_binding_t& b = checked(binding, "binding");
    require_not_null(path, "path");
    cagekit::write_file_atomically(path, cagekit::write_binding(b.binding, b.cage, b.options));
  });
}

CAGEKIT_API cagekit_status cagekit_binding_write_memory(cagekit_binding binding, cagekit_blob* out) {
  return create_from(binding, "binding", out, [&](const cagekit_binding_t& b) {
    return std::make_unique<cagekit_blob_t>(cagekit::write_binding(b.binding, b.cage, b.options));
  });
}

CAGEKIT_API cagekit_status cagekit_binding_read_file(cagekit_context context, const char* path, uint32_t threads,
                                                     cagekit_binding* out) {
  if (!path) {
    return guarded(is_live(context) ? context : nullptr, [&] {
      if (out) *out = nullptr;
      require_not_null(path, "path");
    });
  }
  return read(context, path, nullptr, 0, threads, out);
}

CAGEKIT_API cagekit_status cagekit_binding_read_memory(cagekit_context context, const void* data, size_t size,
                                                       uint32_t threads, cagekit_binding* out) {
  return read(context, nullptr, data, size, threads, out);
}

CAGEKIT_API cagekit_status cagekit_binding_get_cage(cagekit_binding binding, cagekit_cage* out) {
  return create_from(binding, "binding", out, [&](const cagekit_binding_t& b) {
    return std::make_unique<cagekit_cage_t>(b.context, b.cage);
  });
}

}  // extern "C"
