// SPDX-License-Identifier: GPL-3.0-or-later
// PLY header parsing.
#include "core/io/ply_header.h"

#include <charconv>
#include <cstring>

#include "core/io/text_scanner.h"

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

size_t ply_type_size(PlyType type) {
  switch (type) {
    case PlyType::int8:
    case PlyType::uint8: return 1;
    case PlyType::int16:
    case PlyType::uint16: return 2;
    case PlyType::int32:
    case PlyType::uint32:
    case PlyType::float32: return 4;
    case PlyType::float64: return 8;
  }
  return 1;
}

bool ply_type_is_integer(PlyType type) { return type != PlyType::float32 && type != PlyType::float64; }

int PlyElement::find(const char* property_name) const {
  for (size_t i = 0; i < properties.size(); ++i)
    if (properties[i].name == property_name) return static_cast<int>(i);
  return -1;
}

namespace {

bool parse_type(std::string_view name, PlyType& type) {
  static const struct {
    const char* a;
    const char* b;
    PlyType type;
  } names[] = {{"char", "int8", PlyType::int8},         {"uchar", "uint8", PlyType::uint8},
               {"short", "int16", PlyType::int16},      {"ushort", "uint16", PlyType::uint16},
               {"int", "int32", PlyType::int32},        {"uint", "uint32", PlyType::uint32},
               {"float", "float32", PlyType::float32},  {"double", "float64", PlyType::float64}};
  for (const auto& n : names)
    if (name == n.a || name == n.b) {
      type = n.type;
      return true;
    }
  return false;
}

class HeaderParser {
 public:
  HeaderParser(const uint8_t* data, size_t size, const ReadContext& context)
      : lines_(reinterpret_cast<const char*>(data), reinterpret_cast<const char*>(data) + size), context_(context) {}

  PlyHeader run() {
    std::string_view line;
    if (!lines_.next(line) || line != "ply") context_.fail_at_line(1, "missing 'ply' magic line");
    bool have_format = false;
    while (lines_.next(line)) {
      FieldCursor fields(line, false);
      const std::string_view keyword = fields.field();
      if (keyword == "end_header") {
        if (!have_format) fail("missing 'format' line");
        header_.body_offset = lines_.offset();
        header_.body_line = lines_.line_number() + 1;
        return std::move(header_);
      }
      if (keyword == "format") {
        parse_format(fields);
        have_format = true;
      } else if (keyword == "element") {
        parse_element(fields);
      } else if (keyword == "property") {
        parse_property(fields);
      } else if (keyword != "comment" && keyword != "obj_info" && !keyword.empty()) {
        fail("unknown header keyword '" + std::string(keyword.substr(0, 40)) + "'");
      }
    }
    fail("header has no 'end_header' line");
  }

 private:
  [[noreturn]] void fail(const std::string& message) const { context_.fail_at_line(lines_.line_number(), message); }

  void parse_format(FieldCursor& fields) {
    const std::string_view encoding = fields.field();
    if (encoding == "ascii") header_.encoding = PlyEncoding::ascii;
    else if (encoding == "binary_little_endian") header_.encoding = PlyEncoding::binary_little_endian;
    else if (encoding == "binary_big_endian") header_.encoding = PlyEncoding::binary_big_endian;
    else fail("unknown PLY format '" + std::string(encoding.substr(0, 40)) + "'");
    if (fields.field() != "1.0") fail("unsupported PLY version (only 1.0)");
  }

  void parse_element(FieldCursor& fields) {
    PlyElement element;
    element.name = std::string(fields.field());
    element.line = lines_.line_number();
    const std::string_view count = fields.field();
    auto r = std::from_chars(count.data(), count.data() + count.size(), element.count);
    if (element.name.empty() || count.empty() || r.ec != std::errc() || r.ptr != count.data() + count.size() ||
        !fields.at_end())
      fail("expected 'element <name> <count>'");
    for (const PlyElement& e : header_.elements)
      if (e.name == element.name) fail("element '" + element.name + "' is declared twice");
    header_.elements.push_back(std::move(element));
  }

  void parse_property(FieldCursor& fields) {
    if (header_.elements.empty()) fail("property before any element");
    PlyProperty property;
    std::string_view type = fields.field();
    if (type == "list") {
      property.is_list = true;
      if (!parse_type(fields.field(), property.count_type) || !ply_type_is_integer(property.count_type))
        fail("list count type must be an integer type");
      type = fields.field();
    }
    if (!parse_type(type, property.type)) fail("unknown property type '" + std::string(type.substr(0, 40)) + "'");
    property.name = std::string(fields.field());
    if (property.name.empty() || !fields.at_end()) fail("expected 'property <type> <name>'");
    header_.elements.back().properties.push_back(std::move(property));
  }

  LineScanner lines_;
  const ReadContext& context_;
  PlyHeader header_;
};

}  // namespace

PlyHeader parse_ply_header(const uint8_t* data, size_t size, const ReadContext& context) {
  static const uint8_t empty = 0;
  return HeaderParser(size ? data : &empty, size, context).run();
}

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
