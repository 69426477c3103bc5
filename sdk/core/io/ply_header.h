// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Private to sdk/core/io: the PLY header (format line, elements, scalar and list properties).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/io/io_internal.h"

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

enum class PlyType : uint8_t { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

size_t ply_type_size(PlyType type);
bool ply_type_is_integer(PlyType type);

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::float32;  // the item type for lists
  bool is_list = false;
  PlyType count_type = PlyType::uint8;  // lists only
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
  size_t line = 0;  // header line that declared it
  int find(const char* property_name) const;
};

enum class PlyEncoding { ascii, binary_little_endian, binary_big_endian };

struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::ascii;
  std::vector<PlyElement> elements;
  size_t body_offset = 0;  // first byte after "end_header" and its line end
  size_t body_line = 0;    // line number of the first body line (ascii)
};

// Parses the header; parse_error with the line number on anything malformed.
PlyHeader parse_ply_header(const uint8_t* data, size_t size, const ReadContext& context);

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
