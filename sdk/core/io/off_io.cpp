// SPDX-License-Identifier: GPL-3.0-or-later
// OFF reader and writer. Reading accepts [ST][C][N]OFF headers (extra per-vertex columns and
// per-face colours after the indices are ignored), counts on the header line or the next one,
// and '#' comments. Indices are 0-based.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "core/io/io_internal.h"
#include "core/io/text_scanner.h"
#include "core/io/text_writer.h"

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

namespace {

// Shortest possible lines: "x y z\n" and "3 a b c\n".
constexpr uint64_t kMinVertexBytes = 6;
constexpr uint64_t kMinFaceBytes = 8;

class OffReader {
 public:
  OffReader(const char* text, size_t size, const ReadContext& context)
      : text_(text), lines_(text, text + size), context_(context), progress_(context.monitor, "reading") {}

  Cage run() {
    const void* nul = std::memchr(text_, 0, lines_.remaining());
    if (nul)
      context_.fail_at_line(line_of_offset(text_, size_t(static_cast<const char*>(nul) - text_)),
                            "NUL byte: binary OFF is not supported");
    uint64_t nv = 0, nf = 0;
    read_header(nv, nf);
    read_vertices(nv);
    read_faces(nf, nv);
    check_not_empty(cage_, context_);
    return std::move(cage_);
  }

 private:
  // The next line that is not blank or a comment; false at the end of the input.
  bool next_content_line(std::string_view& line) {
    while (lines_.next(line))
      if (!FieldCursor(line).at_end()) return true;
    return false;
  }

  // [ST][C][N][4][n]OFF; the 4 and n variants (other dimensions) are refused.
  void check_keyword(std::string_view keyword) const {
    std::string_view k = keyword;
    auto strip = [&k](std::string_view prefix) {
      const bool found = k.substr(0, prefix.size()) == prefix;
      if (found) k.remove_prefix(prefix.size());
      return found;
    };
    strip("ST");
    strip("C");
    strip("N");
    const bool four_d = strip("4");  // both prefixes are stripped, whichever is present
    const bool n_d = strip("n");
    const bool other_dimension = four_d || n_d;
    if (k != "OFF") context_.fail_at_line(lines_.line_number(), "missing OFF header");
    if (other_dimension)
      context_.fail_at_line(lines_.line_number(), "'" + std::string(keyword) + "' (not 3D) is not supported",
                            Status::unsupported_format);
  }

  void read_header(uint64_t& nv, uint64_t& nf) {
    std::string_view line;
    if (!next_content_line(line)) context_.fail_here("empty file: no vertices");
    FieldCursor fields(line);
    check_keyword(fields.field());
    if (fields.at_end()) {
      if (!next_content_line(line)) context_.fail_at_line(lines_.line_number(), "missing vertex and face counts");
      fields = FieldCursor(line);
    } else if (fields.field() == "BINARY") {
      context_.fail_at_line(lines_.line_number(), "binary OFF is not supported", Status::unsupported_format);
    } else {
      fields = FieldCursor(line);
      fields.field();
    }
    read_counts(fields, nv, nf);
  }

  void read_counts(FieldCursor& fields, uint64_t& nv, uint64_t& nf) {
    const size_t line = lines_.line_number();
    int64_t counts[2] = {0, 0};
    for (int64_t& c : counts)
      if (!fields.read_int(c) || c < 0) context_.fail_at_line(line, "expected vertex and face counts");
    nv = uint64_t(counts[0]);
    nf = uint64_t(counts[1]);
    // Each vertex and face needs a line of its own: counts that cannot fit are corrupt.
    const uint64_t room = lines_.remaining() + 1;
    if (nv > room / kMinVertexBytes || nf > room / kMinFaceBytes ||
        nv * kMinVertexBytes + nf * kMinFaceBytes > room)
      context_.fail_at_line(line, "declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                                      " faces but only " + std::to_string(lines_.remaining()) + " bytes follow");
    context_.check_limit(nv, context_.options.max_vertices, "vertices", line, true);
    context_.check_limit(nf, context_.options.max_faces, "faces", line, true);
    cage_.mesh.reserve(size_t(nv), size_t(nf), size_t(nf) * 3);
  }

  void read_vertices(uint64_t nv) {
    std::string_view line;
    for (uint64_t v = 0; v < nv; ++v) {
      if (!next_content_line(line))
        context_.fail_at_line(lines_.line_number(), "file ends after " + std::to_string(v) + " of " +
                                                        std::to_string(nv) + " vertices");
      FieldCursor fields(line);
      Vec3 p;
      for (int axis = 0; axis < 3; ++axis) {
        if (!fields.read_double(p[axis]))
          context_.fail_at_line(lines_.line_number(), "vertex coordinate is missing or not a number");
        if (!std::isfinite(p[axis]))
          context_.fail_at_line(lines_.line_number(), "vertex coordinate is not finite (NaN or infinity)");
      }
      cage_.mesh.positions.push_back(p);
      progress_.tick(lines_.fraction());
    }
  }

  void read_faces(uint64_t nf, uint64_t nv) {
    std::string_view line;
    PolygonMesh& mesh = cage_.mesh;
    for (uint64_t f = 0; f < nf; ++f) {
      if (!next_content_line(line))
        context_.fail_at_line(lines_.line_number(), "file ends after " + std::to_string(f) + " of " +
                                                        std::to_string(nf) + " faces");
      const size_t ln = lines_.line_number();
      FieldCursor fields(line);
      int64_t n = 0;
      if (!fields.read_int(n)) context_.fail_at_line(ln, "face vertex count is missing or not an integer");
      if (n < 3) context_.fail_at_line(ln, "face has " + std::to_string(n) + " vertices; at least 3 are needed");
      if (uint64_t(n) > context_.options.max_face_size)
        context_.fail_at_line(ln, "face has " + std::to_string(n) + " vertices, more than ReadOptions::max_face_size",
                              Status::limit_exceeded);
      for (int64_t k = 0; k < n; ++k) {
        int64_t index = -1;
        if (!fields.read_int(index))
          context_.fail_at_line(ln, "face declares " + std::to_string(n) + " vertices but index " +
                                        std::to_string(k + 1) + " is missing or not an integer");
        if (index < 0 || uint64_t(index) >= nv)
          context_.fail_at_line(ln, "face refers to vertex " + std::to_string(index) + " but only " +
                                        std::to_string(nv) + " vertices are defined (indices are 0-based)");
        mesh.face_vertices.push_back(uint32_t(index));
      }
      context_.check_limit(mesh.face_vertices.size(), UINT32_MAX, "face corners", ln, true);
      mesh.face_offsets.push_back(uint32_t(mesh.face_vertices.size()));
      progress_.tick(lines_.fraction());
    }
  }

  const char* text_;
  LineScanner lines_;
  const ReadContext& context_;
  ProgressTicker progress_;
  Cage cage_;
};

}  // namespace

Cage read_off(const uint8_t* data, size_t size, const ReadContext& context) {
  static const char empty = 0;
  const char* text = size ? reinterpret_cast<const char*>(data) : &empty;
  return OffReader(text, size, context).run();
}

double write_off(const Cage& cage, const WriteOptions& options, const TaskMonitor& monitor,
                 std::vector<uint8_t>& out) {
  const PolygonMesh& mesh = cage.mesh;
  TextWriter w(out, options.obj_precision);
  ProgressTicker progress(monitor, "writing");
  out.reserve(mesh.num_vertices() * 40 + mesh.num_face_vertices() * 8 + 64);
  w.text("OFF\n");
  w.uint(mesh.num_vertices());
  w.ch(' ');
  w.uint(mesh.num_faces());
  w.text(" 0\n");
  return write_ascii_vertices_and_faces(mesh, progress, w);
}

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
