// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Reading and writing meshes and cages: OBJ (with OpenSubdiv-style `t crease` / `t corner` /
// `t hole` tag lines), PLY (ascii, binary little/big endian; faces and triangle strips), OFF,
// Draco (.drc); STL (binary and ascii) is read only.
//
// Every reader treats its input as hostile: truncated data, corrupt numbers, NaN/Inf, indices
// out of range and element counts that cannot fit in the remaining bytes are reported as an
// Error (Status::parse_error / limit_exceeded) whose message names the source and the line
// (text formats) or byte offset (binary formats), e.g. "part.ply: byte 1234: ...".
// Readers never allocate more than the input can justify.
//
// Meshes are exchanged as Cage values: a plain mesh is a cage without tags.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/cage.h"
#include "core/task_monitor.h"

CAGEKIT_NAMESPACE_BEGIN

// Values match the C header's cagekit_file_format.
enum class FileFormat : int {
  unknown = 0,  // by file extension when writing, by extension then content sniffing when reading
  obj = 1,
  ply = 2,      // reading accepts ascii and binary; writing follows WriteOptions::ply_binary
  off = 3,
  draco = 4,
  stl = 5,      // read only: binary or ascii triangle soups, bit-identical corners welded
};

const char* file_format_name(FileFormat format);
// From a path's extension (.obj .ply .off .drc .stl, case-insensitive); unknown if none matches.
FileFormat file_format_from_path(const std::string& path);
// From the content ("ply\n", "OFF", "DRACO"; binary STL when the size is exactly 84 + 50 * the
// triangle count at byte 80, ascii STL for "solid" followed by "facet"; otherwise OBJ if it
// looks like text with v/f lines); unknown if none.
FileFormat sniff_file_format(const uint8_t* data, size_t size);

struct ReadOptions {
  // Hard ceilings, on top of the "counts must fit in the remaining bytes" rule. Draco streams
  // store triangles: there max_faces bounds the triangles the stream declares (a CageKit polygon
  // file's fan triangles), checked before libdraco allocates for them.
  uint64_t max_vertices = uint64_t(1) << 28;
  uint64_t max_faces = uint64_t(1) << 28;
  uint32_t max_face_size = 1u << 16;
};

struct WriteOptions {
  FileFormat format = FileFormat::unknown;
  bool ply_binary = true;
  int draco_position_bits = 14;   // 1..30; Draco quantization of positions
  int draco_speed = 5;            // 0 (best compression) .. 10 (fastest); Draco encoder speed
  int obj_precision = 9;          // significant digits of positions in OBJ/PLY ascii/OFF
};

struct WriteReport {
  size_t bytes = 0;
  // Largest distance between a written and the original position (Draco quantization);
  // 0 for lossless text output up to obj_precision rounding, which is also measured.
  double max_position_error = 0;
};

// `source_name` is used in error messages only (a file name, or e.g. "<memory>").
Cage read_cage_from_memory(const uint8_t* data, size_t size, FileFormat format,
                           const std::string& source_name, const ReadOptions& options = {},
                           const TaskMonitor& monitor = {});
Cage read_cage_from_file(const std::string& path, FileFormat format = FileFormat::unknown,
                         const ReadOptions& options = {}, const TaskMonitor& monitor = {});

// format must be set (not unknown). Formats without tags (PLY, OFF) write the polygon mesh
// only; the caller decides whether that is acceptable (see format_keeps_tags()). STL is
// Status::unsupported_format ("STL: writing is not supported").
std::vector<uint8_t> write_cage_to_memory(const Cage& cage, const WriteOptions& options,
                                          WriteReport* report = nullptr, const TaskMonitor& monitor = {});
// Writes atomically: to a temporary file beside `path`, renamed over it only on success,
// so a failure never leaves a partial output file. options.format unknown = from extension.
void write_cage_to_file(const std::string& path, const Cage& cage, const WriteOptions& options,
                        WriteReport* report = nullptr, const TaskMonitor& monitor = {});

bool format_keeps_tags(FileFormat format);

CAGEKIT_NAMESPACE_END
