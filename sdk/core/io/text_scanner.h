// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Private to sdk/core/io: fast scanning of text formats held in memory (OBJ, OFF, PLY headers
// and ascii bodies). Lines end in \n or \r\n; '#' starts a comment where the format says so.
// Numbers are parsed with std::from_chars (no locale, no allocation); a leading '+' is accepted.
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>

#include "core/namespace.h"

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

// Blanks separate fields within a line; a stray '\r' counts as one.
inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Splits a buffer into lines, counting them from 1.
class LineScanner {
 public:
  LineScanner(const char* begin, const char* end) : pos_(begin), begin_(begin), end_(end) {}

  // The next line without its terminator ("\n" or "\r\n"); false at the end of the buffer.
  bool next(std::string_view& line) {
    if (pos_ >= end_) return false;
    const char* start = pos_;
    const void* nl = std::memchr(pos_, '\n', static_cast<size_t>(end_ - pos_));
    const char* stop = nl ? static_cast<const char*>(nl) : end_;
    pos_ = nl ? stop + 1 : end_;
    if (stop > start && stop[-1] == '\r') --stop;
    ++line_number_;
    line = std::string_view(start, static_cast<size_t>(stop - start));
    return true;
  }

  size_t line_number() const { return line_number_; }
  size_t offset() const { return static_cast<size_t>(pos_ - begin_); }
  size_t remaining() const { return static_cast<size_t>(end_ - pos_); }
  double fraction() const {
    return end_ > begin_ ? static_cast<double>(pos_ - begin_) / static_cast<double>(end_ - begin_) : 1.0;
  }
  const char* position() const { return pos_; }

 private:
  const char* pos_;
  const char* begin_;
  const char* end_;
  size_t line_number_ = 0;
};

// Reads whitespace-separated fields of one line. A '#' at the start of a field ends the line
// when comments are enabled.
class FieldCursor {
 public:
  explicit FieldCursor(std::string_view line, bool hash_comments = true)
      : p_(line.data()), e_(line.data() + line.size()), comments_(hash_comments) {}

  // True when only blanks (and a comment) remain.
  bool at_end() {
    skip_blanks();
    return p_ == e_ || (comments_ && *p_ == '#');
  }

  // The next field, or an empty view at the end of the line.
  std::string_view field() {
    if (at_end()) return {};
    const char* start = p_;
    while (p_ < e_ && !is_blank(*p_)) ++p_;
    return std::string_view(start, static_cast<size_t>(p_ - start));
  }

  // A number that must end at a blank, the end of the line or (when `stop` is set) that char.
  bool read_double(double& value, char stop = 0) {
    if (at_end()) return false;
    const char* s = p_;
    if (*s == '+' && s + 1 < e_ && *(s + 1) != '-') ++s;
    auto result = std::from_chars(s, e_, value);
    if (result.ec == std::errc::result_out_of_range) {
      return finish_out_of_range(s, result.ptr, value, stop);
    }
    if (result.ec != std::errc()) return false;
    return finish(result.ptr, stop);
  }

  bool read_int(int64_t& value, char stop = 0) {
    if (at_end()) return false;
    const char* s = p_;
    if (*s == '+' && s + 1 < e_ && *(s + 1) != '-') ++s;
    auto result = std::from_chars(s, e_, value);
    if (result.ec != std::errc()) return false;
    return finish(result.ptr, stop);
  }

  // After a number read with stop = '/': skips "/vt/vn" parts of an OBJ face corner.
  void skip_to_blank() {
    while (p_ < e_ && !is_blank(*p_)) ++p_;
  }

  const char* position() const { return p_; }

 private:
  void skip_blanks() {
    while (p_ < e_ && is_blank(*p_)) ++p_;
  }
  bool finish(const char* end, char stop) {
    if (end < e_ && !is_blank(*end) && !(stop && *end == stop) && !(comments_ && *end == '#')) return false;
    p_ = end;
    return true;
  }
  // from_chars leaves `value` alone when the number does not fit a double: an underflow reads
  // as 0, an overflow as an infinity (which the readers then refuse as non-finite).
  bool finish_out_of_range(const char* s, const char* end, double& value, char stop) {
    const char* ex = s;
    while (ex < end && *ex != 'e' && *ex != 'E') ++ex;
    const bool negative_exponent = ex + 1 < end && ex[1] == '-';
    const bool negative = *s == '-';
    value = negative_exponent ? (negative ? -0.0 : 0.0) : (negative ? -HUGE_VAL : HUGE_VAL);
    return finish(end, stop);
  }

  const char* p_;
  const char* e_;
  bool comments_;
};

// Line number (1-based) of byte `offset` in [begin, begin + offset).
inline size_t line_of_offset(const char* begin, size_t offset) {
  size_t line = 1;
  for (size_t i = 0; i < offset; ++i)
    if (begin[i] == '\n') ++line;
  return line;
}

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
