// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Private to sdk/core/io: where the PLY body reader gets its values from. Both sources have the
// same interface so that one templated element loop (ply_reader.cpp) serves all encodings:
//   read_number / read_integer / skip_value, remaining(), min_value_bytes(type), fail(message).
#include <charconv>
#include <cstdint>
#include <string>
#include <string_view>

#include "core/io/byte_reader.h"
#include "core/io/io_internal.h"
#include "core/io/ply_header.h"
#include "core/io/text_scanner.h"

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

class PlyBinarySource {
 public:
  PlyBinarySource(const uint8_t* data, size_t size, size_t offset, bool little_endian, const ReadContext& context)
      : reader_(data, size, offset, little_endian), size_(size), context_(context) {}

  uint64_t remaining() const { return reader_.remaining(); }
  static uint64_t min_value_bytes(PlyType type) { return ply_type_size(type); }
  double fraction() const { return size_ ? double(reader_.offset()) / double(size_) : 1.0; }

  bool read_number(PlyType type, double& out) {
    mark_ = reader_.offset();
    switch (type) {
      case PlyType::float32: { float v; if (!reader_.read(v)) return false; out = v; return true; }
      case PlyType::float64: { double v; if (!reader_.read(v)) return false; out = v; return true; }
      default: { int64_t v; if (!read_int(type, v)) return false; out = double(v); return true; }
    }
  }

  bool read_integer(PlyType type, int64_t& out) {
    mark_ = reader_.offset();
    return read_int(type, out);
  }

  bool skip_value(PlyType type) { return reader_.skip(ply_type_size(type)); }

  bool skip_values(PlyType type, uint64_t count) {
    const uint64_t size = ply_type_size(type);
    return count <= remaining() / size && reader_.skip(count * size);
  }

  [[noreturn]] void fail(const std::string& message, Status status = Status::parse_error) const {
    context_.fail_at_byte(mark_, message, status);
  }
  void mark() { mark_ = reader_.offset(); }

 private:
  bool read_int(PlyType type, int64_t& out) {
    switch (type) {
      case PlyType::int8: { int8_t v; if (!reader_.read(v)) return false; out = v; return true; }
      case PlyType::uint8: { uint8_t v; if (!reader_.read(v)) return false; out = v; return true; }
      case PlyType::int16: { int16_t v; if (!reader_.read(v)) return false; out = v; return true; }
      case PlyType::uint16: { uint16_t v; if (!reader_.read(v)) return false; out = v; return true; }
      case PlyType::int32: { int32_t v; if (!reader_.read(v)) return false; out = v; return true; }
      case PlyType::uint32: { uint32_t v; if (!reader_.read(v)) return false; out = v; return true; }
      default: return false;  // floating-point where an integer is required
    }
  }

  ByteReader reader_;
  size_t size_;
  const ReadContext& context_;
  size_t mark_ = 0;
};

class PlyAsciiSource {
 public:
  PlyAsciiSource(const uint8_t* data, size_t size, size_t offset, size_t first_line, const ReadContext& context)
      : begin_(reinterpret_cast<const char*>(data)),
        p_(begin_ + offset),
        e_(begin_ + size),
        line_(first_line),
        context_(context) {}

  uint64_t remaining() const { return uint64_t(e_ - p_); }
  // A value is at least one character and one separator (the last one may lack the separator).
  static uint64_t min_value_bytes(PlyType) { return 2; }
  double fraction() const { return e_ > begin_ ? double(p_ - begin_) / double(e_ - begin_) : 1.0; }

  bool read_number(PlyType type, double& out) {
    std::string_view token;
    if (!next_token(token)) return false;
    if (ply_type_is_integer(type)) {
      int64_t v;
      if (!parse(token, v)) return false;
      out = double(v);
      return true;
    }
    return parse(token, out);
  }

  bool read_integer(PlyType type, int64_t& out) {
    std::string_view token;
    return ply_type_is_integer(type) && next_token(token) && parse(token, out);
  }

  bool skip_value(PlyType) {
    std::string_view token;
    return next_token(token);
  }

  bool skip_values(PlyType type, uint64_t count) {
    for (uint64_t i = 0; i < count; ++i)
      if (!skip_value(type)) return false;
    return true;
  }

  [[noreturn]] void fail(const std::string& message, Status status = Status::parse_error) const {
    context_.fail_at_line(line_, message, status);
  }
  void mark() {}

 private:
  bool next_token(std::string_view& token) {
    while (p_ < e_ && (is_blank(*p_) || *p_ == '\n')) {
      if (*p_ == '\n') ++line_;
      ++p_;
    }
    if (p_ == e_) return false;
    const char* start = p_;
    while (p_ < e_ && !is_blank(*p_) && *p_ != '\n') ++p_;
    token = std::string_view(start, size_t(p_ - start));
    return true;
  }

  template <class T>
  static bool parse(std::string_view token, T& out) {
    const char* s = token.data();
    const char* e = s + token.size();
    if (s < e && *s == '+') ++s;
    auto r = std::from_chars(s, e, out);
    return r.ec == std::errc() && r.ptr == e;
  }

  const char* begin_;
  const char* p_;
  const char* e_;
  size_t line_;
  const ReadContext& context_;
};

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
