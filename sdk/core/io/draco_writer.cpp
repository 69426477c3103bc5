// SPDX-License-Identifier: GPL-3.0-or-later
// Draco (.drc) writer: fan-triangulated polygons, a vertex id attribute and cage metadata
// (draco_layout.h). The encoder reorders points and triangles, so the writer decodes what it
// encoded, records how the decoded triangles map back to the original polygons, encodes again
// with that record, and finally reads the result back with the reader to prove that the cage
// comes back exactly and to measure the true position error.
#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>

#include "core/io/draco_layout.h"
#include "core/io/io_internal.h"

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

namespace {

using Triangle = std::array<uint32_t, 3>;

// The fan triangles of all faces, in face order (draco_layout.h).
std::vector<Triangle> fan_triangles(const PolygonMesh& mesh) {
  std::vector<Triangle> triangles;
  triangles.reserve(mesh.num_face_vertices() - 2 * mesh.num_faces());
  for (size_t f = 0; f < mesh.num_faces(); ++f)
    mesh.for_each_fan_triangle(f, [&](uint32_t a, uint32_t b, uint32_t c) { triangles.push_back({a, b, c}); });
  return triangles;
}

std::unique_ptr<draco::Mesh> build_mesh(const PolygonMesh& polygons, const std::vector<Triangle>& triangles) {
  auto mesh = std::make_unique<draco::Mesh>();
  const uint32_t nv = uint32_t(polygons.num_vertices());
  mesh->set_num_points(nv);
  draco::GeometryAttribute position;
  position.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, 12, 0);
  draco::PointAttribute* pos = mesh->attribute(mesh->AddAttribute(position, true, nv));
  draco::GeometryAttribute vertex_id;
  vertex_id.Init(draco::GeometryAttribute::GENERIC, nullptr, 1, draco::DT_UINT32, false, 4, 0);
  const int id_att = mesh->AddAttribute(vertex_id, true, nv);
  draco::PointAttribute* ids = mesh->attribute(id_att);
  for (uint32_t v = 0; v < nv; ++v) {
    const Vec3& p = polygons.positions[v];
    const float xyz[3] = {float(p.x), float(p.y), float(p.z)};
    pos->SetAttributeValue(draco::AttributeValueIndex(v), xyz);
    ids->SetAttributeValue(draco::AttributeValueIndex(v), &v);
  }
  auto id_metadata = std::make_unique<draco::AttributeMetadata>();
  id_metadata->AddEntryString("name", kDracoVertexIdName);
  mesh->AddAttributeMetadata(id_att, std::move(id_metadata));
  for (const Triangle& t : triangles)
    mesh->AddFace({draco::PointIndex(t[0]), draco::PointIndex(t[1]), draco::PointIndex(t[2])});
  return mesh;
}

// Empty on failure (the caller tries the next method).
std::vector<uint8_t> encode(const draco::Mesh& mesh, const WriteOptions& options, int method) {
  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, options.draco_position_bits);
  encoder.SetSpeedOptions(options.draco_speed, options.draco_speed);
  encoder.SetEncodingMethod(method);
  draco::EncoderBuffer buffer;
  if (!encoder.EncodeMeshToBuffer(mesh, &buffer).ok()) return {};
  return std::vector<uint8_t>(buffer.data(), buffer.data() + buffer.size());
}

// The rotation of (a, b, c) that is lexicographically smallest: equal for all rotations.
Triangle canonical(const Triangle& t) {
  const Triangle r1 = {t[1], t[2], t[0]}, r2 = {t[2], t[0], t[1]};
  return std::min({t, r1, r2});
}

// Matches decoded triangles (as original vertex ids) to original fan triangles.
class TriangleMatcher {
 public:
  explicit TriangleMatcher(const std::vector<Triangle>& originals) : originals_(originals) {
    entries_.reserve(originals.size());
    for (uint32_t t = 0; t < originals.size(); ++t) entries_.push_back({canonical(originals[t]), t});
    std::sort(entries_.begin(), entries_.end());
    cursor_.assign(entries_.size(), 0);
  }

  // Original triangle index and rotation r with decoded[(k + r) % 3] == original[k]; false if none is left.
  bool match(const Triangle& decoded, uint32_t& original, uint32_t& rotation) {
    const Triangle key = canonical(decoded);
    auto it = std::lower_bound(entries_.begin(), entries_.end(), std::make_pair(key, uint32_t(0)));
    if (it == entries_.end() || it->first != key) return false;
    const size_t group = size_t(it - entries_.begin());
    const size_t slot = group + cursor_[group];
    if (slot >= entries_.size() || entries_[slot].first != key) return false;
    ++cursor_[group];
    original = entries_[slot].second;
    const Triangle& o = originals_[original];
    for (rotation = 0; rotation < 3; ++rotation)
      if (decoded[rotation] == o[0] && decoded[(rotation + 1) % 3] == o[1] && decoded[(rotation + 2) % 3] == o[2])
        return true;
    return false;
  }

 private:
  const std::vector<Triangle>& originals_;
  std::vector<std::pair<Triangle, uint32_t>> entries_;
  std::vector<uint32_t> cursor_;
};

// Decodes `bytes` and works out the DracoOrder and the vertices no point came back for
// (edgebreaker drops vertices that no face uses); false if the encoder lost or changed triangles
// (degenerate or flipped ones).
bool map_decoded(const std::vector<uint8_t>& bytes, const PolygonMesh& polygons, const std::vector<Triangle>& originals,
                 DracoOrder& order, std::vector<uint32_t>& isolated) {
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok() || decoded.value()->num_faces() != originals.size()) return false;
  const draco::Mesh& mesh = *decoded.value();
  const int id_att = mesh.GetAttributeIdByMetadataEntry("name", kDracoVertexIdName);
  if (id_att < 0) return false;
  const draco::PointAttribute& ids = *mesh.attribute(id_att);
  std::vector<uint32_t> original(mesh.num_points());
  std::vector<uint8_t> seen(polygons.num_vertices(), 0);
  for (uint32_t p = 0; p < mesh.num_points(); ++p) {
    if (!ids.ConvertValue<uint32_t>(ids.mapped_index(draco::PointIndex(p)), 1, &original[p]) ||
        original[p] >= seen.size())
      return false;
    seen[original[p]] = 1;
  }
  isolated.clear();
  for (uint32_t v = 0; v < seen.size(); ++v)
    if (!seen[v]) isolated.push_back(v);
  order.num_vertices = uint32_t(polygons.num_vertices());
  order.num_faces = uint32_t(polygons.num_faces());
  order.num_triangles = uint32_t(originals.size());
  order.original_triangle.resize(originals.size());
  order.rotation.resize(originals.size());
  TriangleMatcher matcher(originals);
  bool identity = true, unrotated = true;
  for (uint32_t j = 0; j < mesh.num_faces(); ++j) {
    const draco::Mesh::Face& face = mesh.face(draco::FaceIndex(j));
    for (int k = 0; k < 3; ++k)
      if (face[k].value() >= original.size()) return false;
    const Triangle t = {original[face[0].value()], original[face[1].value()], original[face[2].value()]};
    if (!matcher.match(t, order.original_triangle[j], order.rotation[j])) return false;
    identity = identity && order.original_triangle[j] == j;
    unrotated = unrotated && order.rotation[j] == 0;
  }
  if (identity) order.original_triangle.clear();
  if (unrotated) order.rotation.clear();
  if (!polygons.all_faces_have_size(3))
    for (size_t f = 0; f < polygons.num_faces(); ++f) order.face_sizes.push_back(polygons.face_size(f));
  return true;
}

std::vector<int32_t> as_int32(const std::vector<uint32_t>& values) {
  return std::vector<int32_t>(values.begin(), values.end());  // uint32 bits, read back as uint32
}

// Vertices that no face uses travel as exact doubles, in increasing index order.
void add_isolated_vertices(draco::GeometryMetadata& md, const PolygonMesh& mesh, const std::vector<uint32_t>& isolated) {
  if (isolated.empty()) return;
  std::vector<double> xyz;
  xyz.reserve(3 * isolated.size());
  for (uint32_t v : isolated) xyz.insert(xyz.end(), {mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z});
  md.AddEntryDoubleArray(kDracoIsolatedPositionsKey, xyz);
}

void add_cage_metadata(draco::Mesh& mesh, const Cage& cage, const DracoOrder& order,
                       const std::vector<uint32_t>& isolated) {
  draco::GeometryMetadata& md = *mesh.metadata();  // exists: the vertex id attribute has metadata
  md.AddEntryInt(kDracoVersionKey, kDracoLayoutVersion);
  add_isolated_vertices(md, cage.mesh, isolated);
  md.AddEntryInt(kDracoBoundaryKey, int32_t(cage.boundary));
  std::vector<uint32_t> crease_vertices, corner_vertices;
  std::vector<double> crease_sharpness, corner_sharpness;
  for (const EdgeCrease& c : cage.creases) {
    crease_vertices.insert(crease_vertices.end(), {c.v0, c.v1});
    crease_sharpness.push_back(c.sharpness);
  }
  for (const VertexCorner& c : cage.corners) {
    corner_vertices.push_back(c.vertex);
    corner_sharpness.push_back(c.sharpness);
  }
  if (!cage.creases.empty()) {
    md.AddEntryIntArray(kDracoCreaseVerticesKey, as_int32(crease_vertices));
    md.AddEntryDoubleArray(kDracoCreaseSharpnessKey, crease_sharpness);
  }
  if (!cage.corners.empty()) {
    md.AddEntryIntArray(kDracoCornerVerticesKey, as_int32(corner_vertices));
    md.AddEntryDoubleArray(kDracoCornerSharpnessKey, corner_sharpness);
  }
  if (!cage.holes.empty()) md.AddEntryIntArray(kDracoHolesKey, as_int32(cage.holes));
  md.AddEntryBinary(kDracoOrderKey, encode_draco_order(order));
}

bool same_cage(const Cage& a, const Cage& b) {
  auto same_crease = [](const EdgeCrease& x, const EdgeCrease& y) {
    return x.v0 == y.v0 && x.v1 == y.v1 && x.sharpness == y.sharpness;
  };
  auto same_corner = [](const VertexCorner& x, const VertexCorner& y) {
    return x.vertex == y.vertex && x.sharpness == y.sharpness;
  };
  return a.mesh.num_vertices() == b.mesh.num_vertices() && a.mesh.face_offsets == b.mesh.face_offsets &&
         a.mesh.face_vertices == b.mesh.face_vertices && a.holes == b.holes && a.boundary == b.boundary &&
         std::equal(a.creases.begin(), a.creases.end(), b.creases.begin(), b.creases.end(), same_crease) &&
         std::equal(a.corners.begin(), a.corners.end(), b.corners.begin(), b.corners.end(), same_corner);
}

void check_float_range(const PolygonMesh& mesh) {
  for (const Vec3& p : mesh.positions)
    if (std::fabs(p.x) > FLT_MAX || std::fabs(p.y) > FLT_MAX || std::fabs(p.z) > FLT_MAX)
      fail(Status::invalid_mesh, "a position is out of the float range that Draco stores");
}

}  // namespace

double write_draco(const Cage& cage, const WriteOptions& options, const TaskMonitor& monitor,
                   std::vector<uint8_t>& out) {
  check_float_range(cage.mesh);
  const std::vector<Triangle> triangles = fan_triangles(cage.mesh);
  const ReadOptions unlimited{UINT64_MAX, UINT64_MAX, UINT32_MAX};
  const std::string self_check = "<Draco self-check>";
  const TaskMonitor quiet;
  // Edgebreaker compresses best; the sequential method keeps degenerate triangles that
  // edgebreaker drops.
  for (int method : {draco::MESH_EDGEBREAKER_ENCODING, draco::MESH_SEQUENTIAL_ENCODING}) {
    monitor.report("writing", 0.1);
    std::unique_ptr<draco::Mesh> mesh = build_mesh(cage.mesh, triangles);
    DracoOrder order;
    std::vector<uint32_t> isolated;
    const std::vector<uint8_t> first = encode(*mesh, options, method);
    if (first.empty() || !map_decoded(first, cage.mesh, triangles, order, isolated)) continue;
    monitor.report("writing", 0.5);
    add_cage_metadata(*mesh, cage, order, isolated);
    std::vector<uint8_t> bytes = encode(*mesh, options, method);
    if (bytes.empty()) continue;
    monitor.report("writing", 0.8);
    Cage back;
    try {
      back = read_draco(bytes.data(), bytes.size(), ReadContext{self_check, unlimited, quiet});
    } catch (const Error&) {
      continue;
    }
    if (!same_cage(cage, back)) continue;
    out.insert(out.end(), bytes.begin(), bytes.end());
    return max_position_distance(cage.mesh.positions, back.mesh.positions);
  }
  fail(Status::invalid_mesh, "Draco cannot store this mesh exactly (encoding failed)");
}

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
