// SPDX-License-Identifier: GPL-3.0-or-later
// OBJ reader: v / f / t lines; every other statement (vt, vn, g, o, s, usemtl, ...) is ignored.
#include <cmath>
#include <cstring>
#include <string>

#include "core/io/io_internal.h"
#include "core/io/obj_tags.h"
#include "core/io/text_scanner.h"

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

namespace {

class ObjReader {
 public:
  ObjReader(const char* text, size_t size, const ReadContext& context)
      : text_(text), size_(size), context_(context), progress_(context.monitor, "reading") {}

  Cage run() {
    reject_binary();
    LineScanner lines(text_, text_ + size_);
    std::string_view line;
    while (lines.next(line)) {
      parse_line(line, lines.line_number());
      progress_.tick(lines.fraction());
    }
    check_forward_indices();
    apply_obj_tags(tags_, cage_, context_);
    check_not_empty(cage_, context_);
    return std::move(cage_);
  }

 private:
  void reject_binary() const {
    const void* nul = size_ ? std::memchr(text_, 0, size_) : nullptr;
    if (nul)
      context_.fail_at_line(line_of_offset(text_, static_cast<size_t>(static_cast<const char*>(nul) - text_)),
                            "NUL byte: binary data is not an OBJ file");
  }

  void parse_line(std::string_view line, size_t line_number) {
    FieldCursor fields(line);
    if (fields.at_end()) return;
    const std::string_view keyword = fields.field();
    if (keyword == "v") parse_vertex(fields, line_number);
    else if (keyword == "f") parse_face(fields, line_number);
    else if (keyword == "t") parse_tag(fields, line_number);
    // Everything else (vt, vn, vp, g, o, s, usemtl, mtllib, l, p, ...) carries nothing for a cage.
  }

  void parse_vertex(FieldCursor& fields, size_t line) {
    Vec3 p;
    for (int axis = 0; axis < 3; ++axis) {
      double value = 0;
      if (!fields.read_double(value))
        context_.fail_at_line(line, "vertex coordinate " + std::to_string(axis + 1) + " is missing or not a number");
      if (!std::isfinite(value)) context_.fail_at_line(line, "vertex coordinate is not finite (NaN or infinity)");
      p[axis] = value;
    }
    // An optional w (and the r g b some writers append) are ignored.
    context_.check_limit(cage_.mesh.num_vertices() + 1, context_.options.max_vertices, "vertices", line, true);
    cage_.mesh.positions.push_back(p);
  }

  uint32_t resolve_index(int64_t index, size_t line) {
    const uint64_t defined = cage_.mesh.num_vertices();
    if (index == 0) context_.fail_at_line(line, "vertex index 0 is invalid (OBJ indices start at 1)");
    if (index < 0) {
      if (static_cast<uint64_t>(-(index + 1)) >= defined)
        context_.fail_at_line(line, "relative vertex index " + std::to_string(index) + " refers before the first vertex (" +
                                        std::to_string(defined) + " vertices defined so far)");
      return static_cast<uint32_t>(defined - static_cast<uint64_t>(-(index + 1)) - 1);
    }
    // Positive indices may refer to vertices defined later in the file; checked at the end.
    if (static_cast<uint64_t>(index) > context_.options.max_vertices || index > int64_t(UINT32_MAX))
      context_.fail_at_line(line, "face refers to vertex " + std::to_string(index) + ", beyond the vertex limit");
    if (static_cast<uint64_t>(index) > max_index_) {
      max_index_ = static_cast<uint64_t>(index);
      max_index_line_ = line;
    }
    return static_cast<uint32_t>(index - 1);
  }

  void parse_face(FieldCursor& fields, size_t line) {
    PolygonMesh& mesh = cage_.mesh;
    const size_t first = mesh.face_vertices.size();
    while (!fields.at_end()) {
      int64_t index = 0;
      if (!fields.read_int(index, '/')) context_.fail_at_line(line, "face vertex is not an integer index");
      mesh.face_vertices.push_back(resolve_index(index, line));
      fields.skip_to_blank();  // "/vt/vn"
      if (mesh.face_vertices.size() - first > context_.options.max_face_size)
        context_.fail_at_line(line, "face has more than " + std::to_string(context_.options.max_face_size) +
                                        " vertices (ReadOptions::max_face_size)", Status::limit_exceeded);
    }
    const size_t count = mesh.face_vertices.size() - first;
    if (count < 3) context_.fail_at_line(line, "face has " + std::to_string(count) + " vertices; at least 3 are needed");
    context_.check_limit(mesh.num_faces() + 1, context_.options.max_faces, "faces", line, true);
    context_.check_limit(mesh.face_vertices.size(), UINT32_MAX, "face corners", line, true);
    mesh.face_offsets.push_back(static_cast<uint32_t>(mesh.face_vertices.size()));
  }

  void parse_tag(FieldCursor& fields, size_t line) {
    ObjTagLine tag;
    if (parse_obj_tag(fields, line, context_, tag)) tags_.push_back(std::move(tag));
  }

  void check_forward_indices() const {
    const uint64_t defined = cage_.mesh.num_vertices();
    if (max_index_ > defined)
      context_.fail_at_line(max_index_line_, "face refers to vertex " + std::to_string(max_index_) + " but only " +
                                                 std::to_string(defined) + " vertices are defined");
  }

  const char* text_;
  size_t size_;
  const ReadContext& context_;
  ProgressTicker progress_;
  Cage cage_;
  std::vector<ObjTagLine> tags_;
  uint64_t max_index_ = 0;
  size_t max_index_line_ = 0;
};

}  // namespace

Cage read_obj(const uint8_t* data, size_t size, const ReadContext& context) {
  return ObjReader(reinterpret_cast<const char*>(data), size, context).run();
}

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
