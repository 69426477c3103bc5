// SPDX-License-Identifier: GPL-3.0-or-later
// PLY reader (ascii, binary little/big endian): the vertex element's x y z (any numeric type),
// the face element's vertex_indices (or vertex_index) list and the tristrips element's
// vertex_indices list (triangle strips, as in the Stanford scans and VCG tools); every other
// property and element is skipped. Element counts are checked against the bytes left before
// anything is reserved.
//
// Triangle strips: -1 ends a strip (for unsigned index types its all-ones value, the same bits).
// Triangle k of a strip s0 s1 s2 ... is (s_k, s_k+1, s_k+2) for even k and (s_k+1, s_k, s_k+2)
// for odd k, so that all have the strip's orientation; triangles with a repeated index (the
// degenerate swaps that turn a strip) are dropped but still count for the alternation.
#include <cmath>
#include <string>

#include "core/io/ply_header.h"
#include "core/io/ply_sources.h"

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

namespace {

// What the reader wants from the vertex, face and tristrips elements (either or both of the last two).
struct PlyPlan {
  const PlyElement* vertex = nullptr;
  const PlyElement* face = nullptr;
  const PlyElement* strips = nullptr;
  int xyz[3] = {-1, -1, -1};
  int indices = -1;        // in face
  int strip_indices = -1;  // in strips
};

// The vertex_indices (or vertex_index) list of an element; parse_error when missing or not integers.
int find_index_list(const PlyElement& e, const ReadContext& context) {
  int k = e.find("vertex_indices");
  if (k < 0) k = e.find("vertex_index");
  if (k < 0) context.fail_at_line(e.line, e.name + " element has no 'vertex_indices' list");
  const PlyProperty& list = e.properties[size_t(k)];
  if (!list.is_list || !ply_type_is_integer(list.type))
    context.fail_at_line(e.line, "'vertex_indices' of " + e.name + " must be a list of integers");
  return k;
}

PlyPlan make_plan(const PlyHeader& header, const ReadContext& context) {
  PlyPlan plan;
  for (const PlyElement& e : header.elements) {
    if (e.name == "vertex") plan.vertex = &e;
    if (e.name == "face") plan.face = &e;
    if (e.name == "tristrips") plan.strips = &e;
  }
  if (!plan.vertex) context.fail_here("no 'element vertex' in the header: no vertices");
  const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    plan.xyz[a] = plan.vertex->find(axes[a]);
    if (plan.xyz[a] < 0 || plan.vertex->properties[size_t(plan.xyz[a])].is_list)
      context.fail_at_line(plan.vertex->line, std::string("vertex element has no scalar property '") + axes[a] + "'");
  }
  if (!plan.face && !plan.strips) context.fail_here("no 'element face' or 'element tristrips' in the header: no faces");
  if (plan.face) plan.indices = find_index_list(*plan.face, context);
  if (plan.strips) plan.strip_indices = find_index_list(*plan.strips, context);
  return plan;
}

template <class Source>
class PlyBodyReader {
 public:
  PlyBodyReader(Source& source, const PlyHeader& header, const ReadContext& context)
      : source_(source), header_(header), context_(context), plan_(make_plan(header, context)),
        progress_(context.monitor, "reading") {}

  Cage run() {
    for (const PlyElement& e : header_.elements) {
      check_count(e);
      if (&e == plan_.vertex) read_vertices(e);
      else if (&e == plan_.face) read_faces(e);
      else if (&e == plan_.strips) read_strips(e);
      else skip_element(e);
    }
    check_not_empty(cage_, context_);
    return std::move(cage_);
  }

 private:
  // Each instance takes at least this many bytes, so a count that cannot fit is corrupt.
  uint64_t min_instance_bytes(const PlyElement& e) const {
    uint64_t bytes = 0;
    for (const PlyProperty& p : e.properties)
      bytes += Source::min_value_bytes(p.is_list ? p.count_type : p.type);
    if (&e == plan_.face) bytes += 3 * Source::min_value_bytes(e.properties[size_t(plan_.indices)].type);
    return bytes;
  }

  void check_count(const PlyElement& e) {
    source_.mark();
    const uint64_t need = min_instance_bytes(e);
    if (need > 0 && e.count > (source_.remaining() + 1) / need)
      source_.fail("element '" + e.name + "' declares " + std::to_string(e.count) + " entries but only " +
                   std::to_string(source_.remaining()) + " bytes remain (each entry needs at least " +
                   std::to_string(need) + ")");
    if (&e == plan_.vertex && e.count > context_.options.max_vertices)
      source_.fail(std::to_string(e.count) + " vertices exceed ReadOptions::max_vertices", Status::limit_exceeded);
    if (&e == plan_.face && e.count > context_.options.max_faces)
      source_.fail(std::to_string(e.count) + " faces exceed ReadOptions::max_faces", Status::limit_exceeded);
  }

  void skip_property(const PlyProperty& p) {
    if (!p.is_list) {
      if (!source_.skip_value(p.type)) source_.fail("file ends inside element data");
      return;
    }
    int64_t count = 0;
    if (!source_.read_integer(p.count_type, count) || count < 0)
      source_.fail("list length of property '" + p.name + "' is missing or negative");
    if (!source_.skip_values(p.type, uint64_t(count)))
      source_.fail("list of " + std::to_string(count) + " values of '" + p.name + "' runs past the end of the file");
  }

  void skip_element(const PlyElement& e) {
    if (e.properties.empty()) return;  // instances without properties take no bytes
    for (uint64_t i = 0; i < e.count; ++i) {
      for (const PlyProperty& p : e.properties) skip_property(p);
      progress_.tick(source_.fraction());
    }
  }

  void read_vertices(const PlyElement& e) {
    cage_.mesh.positions.reserve(size_t(e.count));
    for (uint64_t i = 0; i < e.count; ++i) {
      Vec3 p;
      for (size_t k = 0; k < e.properties.size(); ++k) {
        const PlyProperty& prop = e.properties[k];
        const int axis = int(k) == plan_.xyz[0] ? 0 : int(k) == plan_.xyz[1] ? 1 : int(k) == plan_.xyz[2] ? 2 : -1;
        if (axis < 0) {
          skip_property(prop);
          continue;
        }
        double value = 0;
        if (!source_.read_number(prop.type, value)) source_.fail("vertex " + std::to_string(i) + ": coordinate '" +
                                                                 prop.name + "' is missing or not a number");
        if (!std::isfinite(value)) source_.fail("vertex " + std::to_string(i) + ": coordinate is not finite");
        p[axis] = value;
      }
      cage_.mesh.positions.push_back(p);
      progress_.tick(source_.fraction());
    }
  }

  void read_face_list(const PlyProperty& list, uint64_t face, uint64_t num_vertices) {
    PolygonMesh& mesh = cage_.mesh;
    int64_t count = 0;
    if (!source_.read_integer(list.count_type, count)) source_.fail("face " + std::to_string(face) + ": list length missing");
    if (count < 3) source_.fail("face " + std::to_string(face) + " has " + std::to_string(count) +
                                " vertices; at least 3 are needed");
    if (uint64_t(count) > context_.options.max_face_size)
      source_.fail("face " + std::to_string(face) + " has " + std::to_string(count) +
                   " vertices, more than ReadOptions::max_face_size", Status::limit_exceeded);
    if (uint64_t(count) * Source::min_value_bytes(list.type) > source_.remaining() + 1)
      source_.fail("face " + std::to_string(face) + " declares " + std::to_string(count) +
                   " vertices but the file ends first");
    for (int64_t k = 0; k < count; ++k) {
      int64_t index = -1;
      if (!source_.read_integer(list.type, index)) source_.fail("face " + std::to_string(face) + ": index missing");
      if (index < 0 || uint64_t(index) >= num_vertices)
        source_.fail("face " + std::to_string(face) + " refers to vertex " + std::to_string(index) + " but only " +
                     std::to_string(num_vertices) + " vertices are defined");
      mesh.face_vertices.push_back(uint32_t(index));
    }
    if (mesh.face_vertices.size() > UINT32_MAX) source_.fail("too many face corners", Status::limit_exceeded);
    mesh.face_offsets.push_back(uint32_t(mesh.face_vertices.size()));
  }

  // Appends the triangles of one tristrips list (one or more strips separated by -1).
  void read_strip_list(const PlyProperty& list, uint64_t entry, uint64_t num_vertices) {
    PolygonMesh& mesh = cage_.mesh;
    const std::string where = "tristrips " + std::to_string(entry);
    int64_t count = 0;
    if (!source_.read_integer(list.count_type, count) || count < 0)
      source_.fail(where + ": list length is missing or negative");
    if (uint64_t(count) > (source_.remaining() + 1) / Source::min_value_bytes(list.type))
      source_.fail(where + " declares " + std::to_string(count) + " indices but the file ends first");
    // For unsigned index types the strip separator -1 is stored as all ones.
    const int64_t restart = list.type == PlyType::uint8    ? int64_t(UINT8_MAX)
                            : list.type == PlyType::uint16 ? int64_t(UINT16_MAX)
                            : list.type == PlyType::uint32 ? int64_t(UINT32_MAX)
                                                           : -1;
    uint32_t strip[2] = {0, 0};
    uint64_t in_strip = 0;  // indices of the current strip read so far
    for (int64_t k = 0; k < count; ++k) {
      int64_t index = -1;
      if (!source_.read_integer(list.type, index)) source_.fail(where + ": index missing");
      if (index == restart || index == -1) {
        in_strip = 0;
        continue;
      }
      if (index < 0 || uint64_t(index) >= num_vertices)
        source_.fail(where + " refers to vertex " + std::to_string(index) + " but only " +
                     std::to_string(num_vertices) + " vertices are defined");
      const uint32_t c = uint32_t(index);
      if (in_strip >= 2) {
        // Triangle number in_strip - 2 of the strip: odd ones swap their first two corners.
        const bool odd = (in_strip - 2) % 2 == 1;
        const uint32_t a = odd ? strip[1] : strip[0], b = odd ? strip[0] : strip[1];
        if (a != b && b != c && a != c) {
          if (mesh.num_faces() + 1 > context_.options.max_faces)
            source_.fail(where + ": more than ReadOptions::max_faces (" +
                         std::to_string(context_.options.max_faces) + ") faces", Status::limit_exceeded);
          if (mesh.face_vertices.size() + 3 > UINT32_MAX) source_.fail("too many face corners", Status::limit_exceeded);
          mesh.face_vertices.insert(mesh.face_vertices.end(), {a, b, c});
          mesh.face_offsets.push_back(uint32_t(mesh.face_vertices.size()));
        }
      }
      strip[0] = strip[1];
      strip[1] = c;
      ++in_strip;
      progress_.tick(source_.fraction());  // a strip can hold a whole scan
    }
  }

  void read_strips(const PlyElement& e) {
    const uint64_t num_vertices = plan_.vertex->count;
    for (uint64_t i = 0; i < e.count; ++i) {
      for (size_t k = 0; k < e.properties.size(); ++k) {
        if (int(k) == plan_.strip_indices) read_strip_list(e.properties[k], i, num_vertices);
        else skip_property(e.properties[k]);
      }
      progress_.tick(source_.fraction());
    }
  }

  void read_faces(const PlyElement& e) {
    const uint64_t num_vertices = plan_.vertex->count;  // known from the header, even if faces come first
    cage_.mesh.face_offsets.reserve(size_t(e.count) + 1);
    cage_.mesh.face_vertices.reserve(size_t(e.count) * 3);
    for (uint64_t i = 0; i < e.count; ++i) {
      for (size_t k = 0; k < e.properties.size(); ++k) {
        if (int(k) == plan_.indices) read_face_list(e.properties[k], i, num_vertices);
        else skip_property(e.properties[k]);
      }
      progress_.tick(source_.fraction());
    }
  }

  Source& source_;
  const PlyHeader& header_;
  const ReadContext& context_;
  PlyPlan plan_;
  ProgressTicker progress_;
  Cage cage_;
};

}  // namespace

Cage read_ply(const uint8_t* data, size_t size, const ReadContext& context) {
  const PlyHeader header = parse_ply_header(data, size, context);
  if (header.encoding == PlyEncoding::ascii) {
    PlyAsciiSource source(data, size, header.body_offset, header.body_line, context);
    return PlyBodyReader<PlyAsciiSource>(source, header, context).run();
  }
  PlyBinarySource source(data, size, header.body_offset, header.encoding == PlyEncoding::binary_little_endian,
                         context);
  return PlyBodyReader<PlyBinarySource>(source, header, context).run();
}

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
