// SPDX-License-Identifier: GPL-3.0-or-later
// File and memory I/O of meshes and cages, and the blob handle that carries encoded bytes.

#include "capi/api_guard.h"
#include "capi/mesh_conversion.h"
#include "capi/option_conversion.h"
#include "core/io/mesh_io.h"
#include "core/mesh_validation.h"

using namespace cagekit_capi;

namespace {

cagekit::FileFormat checked_format(const cagekit_file_format& format) {
  const int32_t raw = raw_enum(format);
  if (raw < CAGEKIT_FORMAT_AUTO || raw > CAGEKIT_FORMAT_STL)
    fail(Status::invalid_argument, "format is not a cagekit_file_format");
  return static_cast<cagekit::FileFormat>(raw);
}


void write_report(cagekit_write_report* report, const cagekit::WriteReport& r) {
  if (!report) return;
  cagekit_write_report out{};
  out.struct_size = sizeof(out);
  out.bytes = r.bytes;
  out.max_position_error = r.max_position_error;
  write_versioned(report, out, "cagekit_write_report");
}

cagekit::Cage read_cage(cagekit_context_t& context, const char* path, const void* data, size_t size,
                        const cagekit_file_format& format) {
  const cagekit::FileFormat f = checked_format(format);
  if (path) return cagekit::read_cage_from_file(path, f, {}, context.monitor());
  if (size > 0) require_not_null(data, "data");
  return cagekit::read_cage_from_memory(static_cast<const uint8_t*>(data), size, f, "<memory>", {},
                                        context.monitor());
}

void warn_if_tags_dropped(cagekit_context_t& context, const cagekit::Cage& cage, const cagekit::WriteOptions& o,
                          const char* path) {
  cagekit::FileFormat f = o.format;
  if (f == cagekit::FileFormat::unknown && path) f = cagekit::file_format_from_path(path);
  if (f == cagekit::FileFormat::stl) return;  // the write is refused: no warning about tags
  if (cage.has_tags() && !cagekit::format_keeps_tags(f))
    context.log_message(CAGEKIT_LOG_WARNING, std::string("the cage's tags are not stored in ") +
                                                 cagekit::file_format_name(f) + " files");
}

cagekit_status write_file(cagekit_context context, const cagekit::Cage& cage, const char* path,
                          const cagekit_write_options* options, cagekit_write_report* report) {
  return guarded(context, [&] {
    require_not_null(path, "path");
    const cagekit::WriteOptions o = write_options_from_c(options);
    warn_if_tags_dropped(*context, cage, o, path);
    cagekit::WriteReport r;
    cagekit::write_cage_to_file(path, cage, o, &r, context->monitor());
    write_report(report, r);
  });
}

cagekit_status write_memory(cagekit_context context, const cagekit::Cage& cage, const cagekit_write_options* options,
                            cagekit_blob* out, cagekit_write_report* report) {
  return guarded(context, [&] {
    const cagekit::WriteOptions o = write_options_from_c(options);
    if (o.format == cagekit::FileFormat::unknown)
      fail(Status::invalid_argument, "options->format must name a format when writing to memory");
    warn_if_tags_dropped(*context, cage, o, nullptr);
    cagekit::WriteReport r;
    std::vector<uint8_t> bytes = cagekit::write_cage_to_memory(cage, o, &r, context->monitor());
    write_report(report, r);
    *out = std::make_unique<cagekit_blob_t>(std::move(bytes)).release();
  });
}

}  // namespace

extern "C" {

CAGEKIT_API const void* cagekit_blob_data(cagekit_blob blob) {
  return is_live(blob) ? static_cast<const void*>(blob->bytes.data()) : nullptr;
}
CAGEKIT_API size_t cagekit_blob_size(cagekit_blob blob) { return is_live(blob) ? blob->bytes.size() : 0; }
CAGEKIT_API void cagekit_blob_retain(cagekit_blob blob) { retain_handle(blob); }
CAGEKIT_API void cagekit_blob_release(cagekit_blob blob) { release_handle(blob); }

CAGEKIT_API cagekit_status cagekit_mesh_read_file(cagekit_context context, const char* path,
                                                  cagekit_file_format format, cagekit_mesh* out) {
  return guarded(is_live(context) ? context : nullptr, [&] {
    require_not_null(out, "out");
    *out = nullptr;
    require_not_null(path, "path");
    *out = make_mesh_handle(context, read_cage(checked(context, "context"), path, nullptr, 0, format).mesh);
  });
}

CAGEKIT_API cagekit_status cagekit_mesh_read_memory(cagekit_context context, const void* data, size_t size,
                                                    cagekit_file_format format, cagekit_mesh* out) {
  return guarded(is_live(context) ? context : nullptr, [&] {
    require_not_null(out, "out");
    *out = nullptr;
    *out = make_mesh_handle(context, read_cage(checked(context, "context"), nullptr, data, size, format).mesh);
  });
}

CAGEKIT_API cagekit_status cagekit_cage_read_file(cagekit_context context, const char* path,
                                                  cagekit_file_format format, cagekit_cage* out) {
  return guarded(is_live(context) ? context : nullptr, [&] {
    require_not_null(out, "out");
    *out = nullptr;
    require_not_null(path, "path");
    cagekit::Cage cage = read_cage(checked(context, "context"), path, nullptr, 0, format);
    const cagekit::ValidationReport report = cagekit::validate_cage(cage, 1);
    if (!report.ok()) fail(Status::invalid_mesh, std::string(path) + ": not a valid cage: " + report.summary());
    *out = std::make_unique<cagekit_cage_t>(context, std::move(cage)).release();
  });
}

CAGEKIT_API cagekit_status cagekit_cage_read_memory(cagekit_context context, const void* data, size_t size,
                                                    cagekit_file_format format, cagekit_cage* out) {
  return guarded(is_live(context) ? context : nullptr, [&] {
    require_not_null(out, "out");
    *out = nullptr;
    cagekit::Cage cage = read_cage(checked(context, "context"), nullptr, data, size, format);
    const cagekit::ValidationReport report = cagekit::validate_cage(cage, 1);
    if (!report.ok()) fail(Status::invalid_mesh, "<memory>: not a valid cage: " + report.summary());
    *out = std::make_unique<cagekit_cage_t>(context, std::move(cage)).release();
  });
}

CAGEKIT_API cagekit_status cagekit_mesh_write_file(cagekit_mesh mesh, const char* path,
                                                   const cagekit_write_options* options,
                                                   cagekit_write_report* report) {
  if (!is_live(mesh)) return guarded(nullptr, [&] { checked(mesh, "mesh"); });
  cagekit::Cage cage;
  cagekit_status status = guarded(mesh->context, [&] { cage.mesh = mesh->mesh; });
  return CAGEKIT_FAILED(status) ? status : write_file(mesh->context, cage, path, options, report);
}

CAGEKIT_API cagekit_status cagekit_mesh_write_memory(cagekit_mesh mesh, const cagekit_write_options* options,
                                                     cagekit_blob* out, cagekit_write_report* report) {
  if (out) *out = nullptr;
  if (!is_live(mesh)) return guarded(nullptr, [&] { checked(mesh, "mesh"); });
  if (!out) return guarded(mesh->context, [&] { require_not_null(out, "out"); });
  cagekit::Cage cage;
  cagekit_status status = guarded(mesh->context, [&] { cage.mesh = mesh->mesh; });
  return CAGEKIT_FAILED(status) ? status : write_memory(mesh->context, cage, options, out, report);
}

CAGEKIT_API cagekit_status cagekit_cage_write_file(cagekit_cage cage, const char* path,
                                                   const cagekit_write_options* options,
                                                   cagekit_write_report* report) {
  if (!is_live(cage)) return guarded(nullptr, [&] { checked(cage, "cage"); });
  return write_file(cage->context, cage->cage, path, options, report);
}

CAGEKIT_API cagekit_status cagekit_cage_write_memory(cagekit_cage cage, const cagekit_write_options* options,
                                                     cagekit_blob* out, cagekit_write_report* report) {
  if (out) *out = nullptr;
  if (!is_live(cage)) return guarded(nullptr, [&] { checked(cage, "cage"); });
  if (!out) return guarded(cage->context, [&] { require_not_null(out, "out"); });
  return write_memory(cage->context, cage->cage, options, out, report);
}

}  // extern "C"
