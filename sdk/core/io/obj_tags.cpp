// SPDX-License-Identifier: GPL-3.0-or-later
// OpenSubdiv-style "t" tag lines of OBJ files (see obj_tags.h for the syntax).
#include "core/io/obj_tags.h"

#include <cfloat>
#include <cmath>
#include <initializer_list>
#include <string>

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

namespace {

using Kind = ObjTagLine::Kind;

bool tag_kind(std::string_view name, Kind& kind) {
  if (name == "crease") kind = Kind::crease;
  else if (name == "corner") kind = Kind::corner;
  else if (name == "hole") kind = Kind::hole;
  else if (name == "interpolateboundary") kind = Kind::interpolate_boundary;
  else return false;
  return true;
}

// "nints/nfloats/nstrings" (the string count may be omitted).
bool parse_counts(std::string_view text, int64_t counts[3]) {
  counts[0] = counts[1] = counts[2] = 0;
  int n = 0;
  const char* p = text.data();
  const char* e = p + text.size();
  while (n < 3) {
    auto r = std::from_chars(p, e, counts[n]);
    if (r.ec != std::errc() || counts[n] < 0) return false;
    ++n;
    p = r.ptr;
    if (p == e) break;
    if (*p != '/') return false;
    ++p;
  }
  return p == e && n >= 2;
}

void check_arity(const ObjTagLine& tag, std::string_view name, const ReadContext& context) {
  const size_t ni = tag.ints.size(), nf = tag.floats.size();
  const std::string n(name);
  switch (tag.kind) {
    case Kind::crease:
      if (ni < 2 || ni % 2 != 0 || !(nf == 1 || nf == ni / 2))
        context.fail_at_line(tag.line, "'t crease' needs 2k vertex indices and 1 or k sharpness values");
      break;
    case Kind::corner:
      if (ni < 1 || !(nf == 1 || nf == ni))
        context.fail_at_line(tag.line, "'t corner' needs k vertex indices and 1 or k sharpness values");
      break;
    case Kind::hole:
      if (ni < 1 || nf != 0) context.fail_at_line(tag.line, "'t hole' needs face indices and no floats");
      break;
    case Kind::interpolate_boundary:
      if (ni != 1 || nf != 0) context.fail_at_line(tag.line, "'t " + n + "' needs exactly one integer");
      if (tag.ints[0] == 0)
        context.fail_at_line(tag.line, "'t interpolateboundary 0' (no boundary interpolation) is not supported; "
                                       "use 1 (edges and corners) or 2 (edges only)");
      if (tag.ints[0] != 1 && tag.ints[0] != 2)
        context.fail_at_line(tag.line, "'t interpolateboundary' value " + std::to_string(tag.ints[0]) +
                                           " is not 1 (edges and corners) or 2 (edges only)");
      break;
  }
}

void read_arguments(FieldCursor& fields, const int64_t counts[3], ObjTagLine& out, const ReadContext& context) {
  // The counts are only compared with what the line holds; nothing is reserved from them.
  for (int64_t i = 0; i < counts[0]; ++i) {
    int64_t v = 0;
    if (!fields.read_int(v))
      context.fail_at_line(out.line, "tag declares " + std::to_string(counts[0]) + " integers but integer " +
                                         std::to_string(i + 1) + " is missing or not an integer");
    out.ints.push_back(v);
  }
  for (int64_t i = 0; i < counts[1]; ++i) {
    double v = 0;
    if (!fields.read_double(v) || !std::isfinite(v) || std::fabs(v) > FLT_MAX)
      context.fail_at_line(out.line, "tag declares " + std::to_string(counts[1]) + " floats but float " +
                                         std::to_string(i + 1) + " is missing or not a finite number");
    out.floats.push_back(v);
  }
  for (int64_t i = 0; i < counts[2]; ++i)
    if (fields.field().empty()) context.fail_at_line(out.line, "tag declares more strings than the line holds");
  if (!fields.at_end()) context.fail_at_line(out.line, "tag line has more values than its counts declare");
}

// OpenSubdiv clamps negative sharpness to 0 (regression/common/far_utils.h); so do we.
float sharpness_value(double s) { return s < 0 ? 0.0f : static_cast<float>(s); }

uint32_t checked_index(int64_t value, size_t count, const char* what, const ObjTagLine& tag,
                       const ReadContext& context) {
  if (value < 0 || static_cast<uint64_t>(value) >= count)
    context.fail_at_line(tag.line, std::string("tag refers to ") + what + " " + std::to_string(value) + " but only " +
                                       std::to_string(count) + " " + what + "s are defined (indices are 0-based)");
  return static_cast<uint32_t>(value);
}

}  // namespace

bool parse_obj_tag(FieldCursor& fields, size_t line, const ReadContext& context, ObjTagLine& out) {
  const std::string_view name = fields.field();
  if (name.empty()) context.fail_at_line(line, "'t' line without a tag name");
  out = ObjTagLine{};
  out.line = line;
  if (!tag_kind(name, out.kind)) {
    context.monitor.log(LogLevel::warning, context.source + ":" + std::to_string(line) + ": tag '" +
                                               std::string(name) + "' is not used by CageKit and was ignored");
    return false;
  }
  int64_t counts[3];
  if (!parse_counts(fields.field(), counts))
    context.fail_at_line(line, "tag '" + std::string(name) + "' needs argument counts like 2/1/0");
  read_arguments(fields, counts, out, context);
  check_arity(out, name, context);
  return true;
}

void apply_obj_tags(const std::vector<ObjTagLine>& tags, Cage& cage, const ReadContext& context) {
  const size_t nv = cage.mesh.num_vertices(), nf = cage.mesh.num_faces();
  for (const ObjTagLine& tag : tags) {
    switch (tag.kind) {
      case Kind::crease:
        for (size_t i = 0; i + 1 < tag.ints.size(); i += 2) {
          const double s = tag.floats.size() == 1 ? tag.floats[0] : tag.floats[i / 2];
          cage.creases.push_back({checked_index(tag.ints[i], nv, "vertex", tag, context),
                                  checked_index(tag.ints[i + 1], nv, "vertex", tag, context), sharpness_value(s)});
        }
        break;
      case Kind::corner:
        for (size_t i = 0; i < tag.ints.size(); ++i) {
          const double s = tag.floats.size() == 1 ? tag.floats[0] : tag.floats[i];
          cage.corners.push_back({checked_index(tag.ints[i], nv, "vertex", tag, context), sharpness_value(s)});
        }
        break;
      case Kind::hole:
        for (int64_t f : tag.ints) cage.holes.push_back(checked_index(f, nf, "face", tag, context));
        break;
      case Kind::interpolate_boundary:
        cage.boundary = tag.ints[0] == 1 ? BoundaryRule::edges_and_corners : BoundaryRule::edges_only;
        break;
    }
  }
}

void write_obj_tags(const Cage& cage, TextWriter& w) {
  // One "t NAME i/f/s ints... floats..." line.
  auto tag = [&w](const char* head, std::initializer_list<uint32_t> ints, const float* sharpness) {
    w.text(head);
    for (uint32_t i : ints) {
      w.ch(' ');
      w.uint(i);
    }
    if (sharpness) {
      w.ch(' ');
      w.shortest(*sharpness);
    }
    w.ch('\n');
  };
  for (const EdgeCrease& c : cage.creases) tag("t crease 2/1/0", {c.v0, c.v1}, &c.sharpness);
  for (const VertexCorner& c : cage.corners) tag("t corner 1/1/0", {c.vertex}, &c.sharpness);
  for (uint32_t h : cage.holes) tag("t hole 1/0/0", {h}, nullptr);
  if (cage.boundary == BoundaryRule::edges_and_corners) w.text("t interpolateboundary 1/0/0 1\n");
}

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
