// SPDX-License-Identifier: GPL-3.0-or-later
// STL reader, binary and ascii. STL is a triangle soup: every facet stores its own three
// corners, so corners at bit-identical positions are welded into one vertex here (a hash of the
// exact coordinates; -0 and +0 are the same position). Welding within a tolerance is left to
// mesh repair. Facet normals and the binary attribute word are ignored.
//
// Binary or ascii: a file is binary when its size is exactly 84 + 50 * (the uint32 at byte 80),
// whatever its header says (many binary headers start with "solid"); otherwise it is ascii when
// it starts with "solid", and binary (and then refused, naming both sizes) when it does not.
#include <charconv>
#include <cmath>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "core/io/byte_reader.h"
#include "core/io/io_internal.h"
#include "core/io/text_scanner.h"

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

namespace {

constexpr size_t kHeaderBytes = 80;
constexpr size_t kCountBytes = 4;
constexpr uint64_t kTriangleBytes = 50;  // normal, 3 corners (12 floats), uint16 attribute

uint32_t read_le32(const uint8_t* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

bool is_space(char c) { return is_blank(c) || c == '\n'; }

bool equals_ignoring_case(std::string_view a, const char* b) {
  const size_t n = std::strlen(b);
  if (a.size() != n) return false;
  for (size_t i = 0; i < n; ++i) {
    char c = a[i];
    if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
    if (c != b[i]) return false;
  }
  return true;
}

// "solid" (any case) after optional white space, followed by white space or the end.
bool starts_with_solid(const char* text, size_t size) {
  size_t i = 0;
  while (i < size && is_space(text[i])) ++i;
  if (size - i < 5 || !equals_ignoring_case(std::string_view(text + i, 5), "solid")) return false;
  return size - i == 5 || is_space(text[i + 5]);
}

// A token quoted for a message: at most 40 characters, unprintable bytes as '?'.
std::string quoted(std::string_view token) {
  std::string out = "'";
  for (char c : token.substr(0, 40)) out += (c >= 0x20 && c < 0x7f) ? c : '?';
  if (token.size() > 40) out += "...";
  return out + "'";
}

std::string binary_size_mismatch(uint32_t count, size_t size) {
  return "declares " + std::to_string(count) + " triangles, which take 84 + 50 * " +
         std::to_string(count) + " = " + std::to_string(84 + kTriangleBytes * count) + " bytes, but the file has " +
         std::to_string(size) + " bytes";
}

// Merges corners at exactly the same position into one vertex of `mesh`. Open addressing over
// vertex indices (4 bytes a slot, at most half full), so the table costs little beside the mesh.
class CornerWelder {
 public:
  CornerWelder(PolygonMesh& mesh, const ReadContext& context, size_t expected_vertices)
      : mesh_(mesh), context_(context) {
    size_t capacity = 64;
    while (capacity < 2 * expected_vertices) capacity *= 2;
    slots_.assign(capacity, kEmpty);
  }

  // The vertex at exactly `p`, added when new; limit_exceeded (at `location`, a line or byte
  // offset) when a new vertex would pass ReadOptions::max_vertices.
  uint32_t vertex_at(const Vec3& p, size_t location, bool is_line) {
    size_t slot = hash(p) & (slots_.size() - 1);
    for (;; slot = (slot + 1) & (slots_.size() - 1)) {
      const uint32_t v = slots_[slot];
      if (v == kEmpty) break;
      const Vec3& q = mesh_.positions[v];
      if (q.x == p.x && q.y == p.y && q.z == p.z) return v;
    }
    const uint64_t index = mesh_.positions.size();
    context_.check_limit(index + 1, context_.options.max_vertices, "vertices", location, is_line);
    context_.check_limit(index + 1, kEmpty - 1, "vertices", location, is_line);
    slots_[slot] = uint32_t(index);
    mesh_.positions.push_back(p);
    if (2 * mesh_.positions.size() > slots_.size()) grow();
    return uint32_t(index);
  }

 private:
  static constexpr uint32_t kEmpty = UINT32_MAX;

  static uint64_t bits(double d) {
    d += 0.0;  // -0 becomes +0: equal positions must hash alike
    uint64_t u;
    std::memcpy(&u, &d, sizeof u);
    return u;
  }
  static size_t hash(const Vec3& p) {
    uint64_t h = bits(p.x) * 0x9E3779B97F4A7C15ull;
    h = (h ^ (h >> 29) ^ bits(p.y)) * 0xBF58476D1CE4E5B9ull;
    h = (h ^ (h >> 31) ^ bits(p.z)) * 0x94D049BB133111EBull;
    return size_t(h ^ (h >> 32));
  }

  void grow() {
    std::vector<uint32_t> bigger(slots_.size() * 2, kEmpty);
    const size_t mask = bigger.size() - 1;
    for (size_t v = 0; v < mesh_.positions.size(); ++v) {
      size_t slot = hash(mesh_.positions[v]) & mask;
      while (bigger[slot] != kEmpty) slot = (slot + 1) & mask;
      bigger[slot] = uint32_t(v);
    }
    slots_.swap(bigger);
  }

  PolygonMesh& mesh_;
  const ReadContext& context_;
  std::vector<uint32_t> slots_;
};

// The final check of both encodings: an STL without facets has no vertices either, so say "no faces".
void check_has_facets(const Cage& cage, const ReadContext& context) {
  if (cage.mesh.num_faces() == 0) context.fail_here("no faces: the STL file has no facets");
}

// Files of exactly the binary size, and files that do not start with "solid" (the messages then
// say that it is not ascii STL either).
Cage read_binary(const uint8_t* data, size_t size, const ReadContext& context) {
  if (size < kHeaderBytes + kCountBytes)
    context.fail_at_byte(0, "not an STL file: it does not start with 'solid' (ascii STL) and its " +
                                std::to_string(size) + " bytes are fewer than the 84 of a binary STL header and "
                                "triangle count");
  const uint32_t count = read_le32(data + kHeaderBytes);
  // The count is checked against the bytes present before anything is reserved.
  if (kHeaderBytes + kCountBytes + kTriangleBytes * count != size)
    context.fail_at_byte(kHeaderBytes,
                         "binary STL " + binary_size_mismatch(count, size) + " (nor does it start with 'solid' like ascii STL)");
  context.check_limit(count, context.options.max_faces, "faces", kHeaderBytes, false);
  context.check_limit(uint64_t(count) * 3, UINT32_MAX, "face corners", kHeaderBytes, false);

  Cage cage;
  PolygonMesh& mesh = cage.mesh;
  mesh.face_offsets.reserve(size_t(count) + 1);
  mesh.face_vertices.reserve(size_t(count) * 3);
  mesh.positions.reserve(size_t(count) / 2 + 3);  // a closed mesh has about half as many vertices as triangles
  CornerWelder welder(mesh, context, size_t(count) / 2 + 3);
  ProgressTicker progress(context.monitor, "reading");
  ByteReader reader(data, size, kHeaderBytes + kCountBytes, true);
  for (uint32_t t = 0; t < count; ++t) {
    reader.skip(12);  // facet normal: recomputed from the corners when needed
    for (int corner = 0; corner < 3; ++corner) {
      const size_t at = reader.offset();
      float xyz[3] = {0, 0, 0};
      for (float& c : xyz) reader.read(c);  // the size rule guarantees the bytes
      if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
        context.fail_at_byte(at, "triangle " + std::to_string(t) + ", corner " + std::to_string(corner) +
                                     ": coordinate is not finite (NaN or infinity)");
      mesh.face_vertices.push_back(welder.vertex_at(Vec3(xyz[0], xyz[1], xyz[2]), at, false));
    }
    reader.skip(2);  // attribute byte count (colour in some exporters)
    mesh.face_offsets.push_back(uint32_t(mesh.face_vertices.size()));
    progress.tick(double(reader.offset()) / double(size));
  }
  check_has_facets(cage, context);
  return cage;
}

// solid name / facet normal n n n / outer loop / vertex x y z (3 times) / endloop / endfacet ... /
// endsolid name; several solids may follow each other. Keywords in any case, any white space
// between tokens; the names are the rest of their line.
class AsciiReader {
 public:
  AsciiReader(const char* text, size_t size, const ReadContext& context)
      : begin_(text), p_(text), e_(text + size), context_(context), progress_(context.monitor, "reading") {}

  Cage run(const std::string& binary_reading) {
    const void* nul = std::memchr(begin_, 0, size_t(e_ - begin_));
    if (nul)
      context_.fail_at_line(line_of_offset(begin_, size_t(static_cast<const char*>(nul) - begin_)),
                            "NUL byte in an ascii STL file (starts with 'solid')" +
                                (binary_reading.empty() ? std::string() : "; as binary STL it " + binary_reading));
    std::string_view token;
    next_token(token);  // "solid", checked by the caller
    do {
      read_solid();
      if (!next_token(token)) break;
      if (!equals_ignoring_case(token, "solid"))
        fail("expected 'solid' or the end of the file after 'endsolid', found " + quoted(token));
    } while (true);
    check_has_facets(cage_, context_);
    return std::move(cage_);
  }

 private:
  [[noreturn]] void fail(const std::string& message) const { context_.fail_at_line(token_line_, message); }

  bool next_token(std::string_view& token) {
    while (p_ < e_ && is_space(*p_)) {
      if (*p_ == '\n') ++line_;
      ++p_;
    }
    token_line_ = line_;
    if (p_ == e_) return false;
    const char* start = p_;
    while (p_ < e_ && !is_space(*p_)) ++p_;
    token = std::string_view(start, size_t(p_ - start));
    return true;
  }

  // The solid's name (after "solid" / "endsolid") is free text up to the end of the line.
  void skip_rest_of_line() {
    while (p_ < e_ && *p_ != '\n') ++p_;
  }

  void expect(const char* keyword, const char* after) {
    std::string_view token;
    if (!next_token(token)) fail(std::string("file ends inside a facet: expected '") + keyword + "' after " + after);
    if (!equals_ignoring_case(token, keyword))
      fail(std::string("expected '") + keyword + "' after " + after + ", found " + quoted(token));
  }

  // A number token; out-of-range values (1e999) read as infinities.
  double number(const char* what) {
    std::string_view token;
    if (!next_token(token)) fail(std::string("file ends inside a facet: ") + what + " is missing");
    const char* s = token.data();
    const char* e = s + token.size();
    if (s < e && *s == '+') ++s;
    double value = 0;
    const auto r = std::from_chars(s, e, value);
    if (r.ptr != e || (r.ec != std::errc() && r.ec != std::errc::result_out_of_range))
      fail(std::string(what) + " is not a number: " + quoted(token));
    if (r.ec == std::errc::result_out_of_range) {
      const std::string_view digits(s, size_t(e - s));
      const size_t ex = digits.find_first_of("eE");
      const bool underflow = ex != std::string_view::npos && ex + 1 < digits.size() && digits[ex + 1] == '-';
      value = underflow ? 0.0 : HUGE_VAL;
    }
    return value;
  }

  void read_solid() {
    skip_rest_of_line();
    std::string_view token;
    for (;;) {
      if (!next_token(token)) fail("file ends without 'endsolid'");
      if (equals_ignoring_case(token, "endsolid")) {
        skip_rest_of_line();
        return;
      }
      if (!equals_ignoring_case(token, "facet")) fail("expected 'facet' or 'endsolid', found " + quoted(token));
      read_facet();
    }
  }

  void read_facet() {
    const size_t facet_line = token_line_;
    expect("normal", "'facet'");
    for (int k = 0; k < 3; ++k) number("facet normal component");  // ignored (not even checked for NaN)
    expect("outer", "'facet normal'");
    expect("loop", "'outer'");
    uint32_t corners[3];
    int count = 0;
    std::string_view token;
    for (;;) {
      if (!next_token(token)) fail("file ends inside a facet: expected 'vertex' or 'endloop'");
      if (equals_ignoring_case(token, "endloop")) break;
      if (!equals_ignoring_case(token, "vertex")) fail("expected 'vertex' or 'endloop', found " + quoted(token));
      if (count == 3) fail("facet has more than 3 vertices (STL facets are triangles)");
      const size_t line = token_line_;
      Vec3 p;
      for (int axis = 0; axis < 3; ++axis) p[axis] = number("vertex coordinate");
      if (!is_finite(p)) context_.fail_at_line(line, "vertex coordinate is not finite (NaN or infinity)");
      corners[count++] = welder_.vertex_at(p, line, true);
    }
    if (count != 3)
      fail("facet has " + std::to_string(count) + " vertices; STL facets are triangles (3)");
    expect("endfacet", "'endloop'");
    PolygonMesh& mesh = cage_.mesh;
    context_.check_limit(mesh.num_faces() + 1, context_.options.max_faces, "faces", facet_line, true);
    context_.check_limit(mesh.face_vertices.size() + 3, UINT32_MAX, "face corners", facet_line, true);
    mesh.face_vertices.insert(mesh.face_vertices.end(), corners, corners + 3);
    mesh.face_offsets.push_back(uint32_t(mesh.face_vertices.size()));
    progress_.tick(double(p_ - begin_) / double(e_ - begin_));
  }

  const char* begin_;
  const char* p_;
  const char* e_;
  size_t line_ = 1;
  size_t token_line_ = 1;
  const ReadContext& context_;
  ProgressTicker progress_;
  Cage cage_;
  CornerWelder welder_{cage_.mesh, context_, 1024};
};

}  // namespace

bool is_binary_stl_size(const uint8_t* data, size_t size) {
  return data != nullptr && size >= kHeaderBytes + kCountBytes &&
         kHeaderBytes + kCountBytes + kTriangleBytes * read_le32(data + kHeaderBytes) == size;
}

Cage read_stl(const uint8_t* data, size_t size, const ReadContext& context) {
  static const char empty = 0;
  const char* text = size ? reinterpret_cast<const char*>(data) : &empty;
  if (is_binary_stl_size(data, size) || !starts_with_solid(text, size)) return read_binary(data, size, context);
  const std::string binary_reading =
      size >= kHeaderBytes + kCountBytes ? binary_size_mismatch(read_le32(data + kHeaderBytes), size) : std::string();
  return AsciiReader(text, size, context).run(binary_reading);
}

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
