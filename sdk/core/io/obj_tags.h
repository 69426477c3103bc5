// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Private to sdk/core/io: OpenSubdiv-style tag lines in OBJ files (regression/shapes syntax):
//   t crease 2/1/0 v0 v1 sharpness        (2k vertex indices, 1 or k sharpness values)
//   t corner 1/1/0 v sharpness            (k vertex indices, 1 or k sharpness values)
//   t hole 1/0/0 f                        (k face indices)
//   t interpolateboundary 1/0/0 n         (1 = edges and corners, 2 = edges only)
// Indices are 0-based, as in OpenSubdiv's shape files.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/io/io_internal.h"
#include "core/io/text_scanner.h"
#include "core/io/text_writer.h"

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

struct ObjTagLine {
  enum class Kind { crease, corner, hole, interpolate_boundary };
  Kind kind = Kind::crease;
  size_t line = 0;
  std::vector<int64_t> ints;
  std::vector<double> floats;
};

// Parses the fields after "t". Returns false (and logs a warning) for tag names CageKit does not
// use; throws parse_error for malformed known tags.
bool parse_obj_tag(FieldCursor& fields, size_t line, const ReadContext& context, ObjTagLine& out);

// Checks indices against the final mesh and stores the tags in `cage`.
void apply_obj_tags(const std::vector<ObjTagLine>& tags, Cage& cage, const ReadContext& context);

// Appends the tag lines of `cage` (one crease / corner / hole per line; the boundary rule only
// when it is not the default).
void write_obj_tags(const Cage& cage, TextWriter& writer);

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
