// SPDX-License-Identifier: GPL-3.0-or-later
// File formats: names, extensions, content sniffing, which formats keep cage tags.
#include <algorithm>
#include <cctype>
#include <cstring>
#include <string_view>

#include "core/io/io_internal.h"
#include "core/io/text_scanner.h"

CAGEKIT_NAMESPACE_BEGIN

const char* file_format_name(FileFormat format) {
  switch (format) {
    case FileFormat::obj: return "OBJ";
    case FileFormat::ply: return "PLY";
    case FileFormat::off: return "OFF";
    case FileFormat::draco: return "Draco";
    case FileFormat::stl: return "STL";
    case FileFormat::unknown: break;
  }
  return "unknown";
}

FileFormat file_format_from_path(const std::string& path) {
  const size_t dot = path.find_last_of('.');
  const size_t slash = path.find_last_of("/\\");
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return FileFormat::unknown;
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == "obj") return FileFormat::obj;
  if (ext == "ply") return FileFormat::ply;
  if (ext == "off") return FileFormat::off;
  if (ext == "drc") return FileFormat::draco;
  if (ext == "stl") return FileFormat::stl;
  return FileFormat::unknown;
}

namespace {

bool is_off_keyword(std::string_view word) {
  // [ST][C][N]OFF: texture coordinates, colours, normals per vertex.
  if (word.size() >= 2 && word.substr(0, 2) == "ST") word.remove_prefix(2);
  if (!word.empty() && word.front() == 'C') word.remove_prefix(1);
  if (!word.empty() && word.front() == 'N') word.remove_prefix(1);
  return word == "OFF";
}

bool is_obj_keyword(std::string_view word) {
  static const char* const keywords[] = {"v", "vt", "vn", "vp", "f", "l", "p", "g", "o", "s",
                                         "usemtl", "mtllib", "t"};
  for (const char* k : keywords)
    if (word == k) return true;
  return false;
}

bool equals_ignoring_case(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
  return true;
}

// Ascii STL: "solid [name]" and then a "facet" (any case) within the probed bytes, so that a
// text file that merely starts with the word "solid" is not taken for STL.
bool looks_like_ascii_stl(std::string_view first_word, const char* text, size_t probe) {
  if (!equals_ignoring_case(first_word, "solid")) return false;
  const std::string_view head(text, probe);
  for (size_t at = head.find_first_of("fF"); at != std::string_view::npos; at = head.find_first_of("fF", at + 1))
    if (equals_ignoring_case(head.substr(at, 5), "facet")) return true;
  return false;
}

// The first word of the first line that is neither blank nor a comment, within the first 4 KiB.
std::string_view first_statement(const char* text, size_t size) {
  io_detail::LineScanner lines(text, text + std::min<size_t>(size, 4096));
  std::string_view line;
  while (lines.next(line)) {
    io_detail::FieldCursor fields(line);
    if (!fields.at_end()) return fields.field();
  }
  return {};
}

}  // namespace

FileFormat sniff_file_format(const uint8_t* data, size_t size) {
  if (data == nullptr || size == 0) return FileFormat::unknown;
  const char* text = reinterpret_cast<const char*>(data);
  if (size >= 5 && std::memcmp(text, "DRACO", 5) == 0) return FileFormat::draco;
  if (size >= 4 && std::memcmp(text, "ply", 3) == 0 && (text[3] == '\n' || text[3] == '\r'))
    return FileFormat::ply;
  // Binary STL has no magic (its 80-byte header is free text, often "solid ..."): the exact
  // size rule decides, before the text checks.
  if (io_detail::is_binary_stl_size(data, size)) return FileFormat::stl;
  const size_t probe = std::min<size_t>(size, 4096);
  if (std::memchr(text, 0, probe) != nullptr) return FileFormat::unknown;  // binary
  const std::string_view word = first_statement(text, size);
  if (looks_like_ascii_stl(word, text, probe)) return FileFormat::stl;
  if (is_off_keyword(word)) return FileFormat::off;
  if (is_obj_keyword(word)) return FileFormat::obj;
  return FileFormat::unknown;
}

bool format_keeps_tags(FileFormat format) {
  return format == FileFormat::obj || format == FileFormat::draco;
}

CAGEKIT_NAMESPACE_END
