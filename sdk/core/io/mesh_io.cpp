// SPDX-License-Identifier: GPL-3.0-or-later
// The public entry points of mesh_io.h: format dispatch, whole-file reading, atomic writing.
#include "core/memory_budget.h"
#include "core/io/mesh_io.h"

#include <new>

#include "core/io/file_io.h"
#include "core/io/io_internal.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

Cage dispatch_read(const uint8_t* data, size_t size, FileFormat format, const io_detail::ReadContext& context) {
  switch (format) {
    case FileFormat::obj: return io_detail::read_obj(data, size, context);
    case FileFormat::ply: return io_detail::read_ply(data, size, context);
    case FileFormat::off: return io_detail::read_off(data, size, context);
    case FileFormat::draco: return io_detail::read_draco(data, size, context);
    case FileFormat::stl: return io_detail::read_stl(data, size, context);
    case FileFormat::unknown: break;
  }
  context.fail_here("unknown file format", Status::unsupported_format);
}

double dispatch_write(const Cage& cage, const WriteOptions& options, const TaskMonitor& monitor,
                      std::vector<uint8_t>& out) {
  switch (options.format) {
    case FileFormat::obj: return io_detail::write_obj(cage, options, monitor, out);
    case FileFormat::ply: return io_detail::write_ply(cage, options, monitor, out);
    case FileFormat::off: return io_detail::write_off(cage, options, monitor, out);
    case FileFormat::draco: return io_detail::write_draco(cage, options, monitor, out);
    case FileFormat::stl: break;  // refused in write_cage_to_memory
    case FileFormat::unknown: break;
  }
  fail(Status::invalid_argument, "WriteOptions::format must name a file format");
}

}  // namespace

Cage read_cage_from_memory(const uint8_t* data, size_t size, FileFormat format, const std::string& source_name,
                           const ReadOptions& options, const TaskMonitor& monitor) {
  const io_detail::ReadContext context{source_name, options, monitor};
  if (data == nullptr && size != 0) context.fail_here("no data (null pointer)", Status::invalid_argument);
  if (size == 0) context.fail_here("empty file: no vertices");
  if (format == FileFormat::unknown) format = sniff_file_format(data, size);
  if (format == FileFormat::unknown)
    context.fail_here("cannot tell the file format (not OBJ, PLY, OFF, Draco or STL)", Status::unsupported_format);
  // Decoded size: text formats expand to at most ~4x their bytes; Draco streams are assumed to
  // expand at most 32x (position quantisation + edgebreaker connectivity reach ~25x).
  check_memory_estimate(estimate_product(size, format == FileFormat::draco ? 32 : 4),
                        ("reading " + source_name).c_str());
  try {
    return dispatch_read(data, size, format, context);
  } catch (const std::bad_alloc&) {
    context.fail_here("out of memory while reading", Status::out_of_memory);
  }
}

Cage read_cage_from_file(const std::string& path, FileFormat format, const ReadOptions& options,
                         const TaskMonitor& monitor) {
  const std::vector<uint8_t> bytes = read_whole_file(path);
  if (format == FileFormat::unknown) format = file_format_from_path(path);
  return read_cage_from_memory(bytes.data(), bytes.size(), format, path, options, monitor);
}

std::vector<uint8_t> write_cage_to_memory(const Cage& cage, const WriteOptions& options, WriteReport* report,
                                          const TaskMonitor& monitor) {
  // Before validating the mesh: the answer does not depend on it.
  if (options.format == FileFormat::stl)
    fail(Status::unsupported_format, "STL: writing is not supported (write .obj, .ply, .off or .drc)");
  io_detail::validate_for_writing(cage, options);
  std::vector<uint8_t> out;
  double error = 0;
  try {
    error = dispatch_write(cage, options, monitor, out);
  } catch (const std::bad_alloc&) {
    fail(Status::out_of_memory, "out of memory while writing");
  }
  if (report) {
    report->bytes = out.size();
    report->max_position_error = error;
  }
  return out;
}

void write_cage_to_file(const std::string& path, const Cage& cage, const WriteOptions& options, WriteReport* report,
                        const TaskMonitor& monitor) {
  WriteOptions resolved = options;
  if (resolved.format == FileFormat::unknown) resolved.format = file_format_from_path(path);
  if (resolved.format == FileFormat::unknown)
    fail(Status::unsupported_format, path + ": cannot tell the format from the extension (use .obj .ply .off .drc)");
  const std::vector<uint8_t> bytes = write_cage_to_memory(cage, resolved, report, monitor);
  write_file_atomically(path, bytes);
}

CAGEKIT_NAMESPACE_END
