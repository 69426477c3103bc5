// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Private to sdk/core/io: appending numbers to a byte buffer for the text writers, with the
// position error of the printed value measured on the way (printed text parsed back).
#include <charconv>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "core/vec3.h"

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

class TextWriter {
 public:
  TextWriter(std::vector<uint8_t>& out, int precision) : out_(out), precision_(precision) {}

  void text(std::string_view s) { out_.insert(out_.end(), s.begin(), s.end()); }
  void ch(char c) { out_.push_back(static_cast<uint8_t>(c)); }

  void uint(uint64_t v) {
    char buf[24];
    auto r = std::to_chars(buf, buf + sizeof(buf), v);
    out_.insert(out_.end(), buf, r.ptr);
  }

  // %.{precision}g; returns the value the text reads back as.
  double real(double v) {
    char buf[40];
    auto r = std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::general, precision_);
    out_.insert(out_.end(), buf, r.ptr);
    double back = v;
    std::from_chars(buf, r.ptr, back);
    return back;
  }

  // Shortest text that reads back as exactly `v` (sharpness values).
  void shortest(float v) {
    char buf[40];
    auto r = std::to_chars(buf, buf + sizeof(buf), v);
    out_.insert(out_.end(), buf, r.ptr);
  }

  // "x y z" (separated by single spaces); returns the distance of the printed point from p.
  double point(const Vec3& p) {
    Vec3 back;
    back.x = real(p.x);
    ch(' ');
    back.y = real(p.y);
    ch(' ');
    back.z = real(p.z);
    return distance(back, p);
  }

 private:
  std::vector<uint8_t>& out_;
  int precision_;
};

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
