// SPDX-License-Identifier: GPL-3.0-or-later
// Draco (.drc) reader. Files written by CageKit (draco_layout.h) come back with their original
// vertex order, polygons, face order and tags; any other Draco mesh is read as triangles over
// its position values. Point clouds are refused ("not a mesh").
#include <draco/compression/decode.h>
#include <draco/compression/point_cloud/point_cloud_decoder.h>
#include <draco/core/varint_decoding.h>
#include <draco/mesh/mesh.h>
#include <draco/metadata/metadata_decoder.h>

#include <cmath>
#include <string>

#include "core/io/draco_layout.h"
#include "core/io/io_internal.h"
#include "core/memory_budget.h"

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

namespace {

// The counts a Draco mesh stream declares ahead of its connectivity. libdraco sizes its arrays
// from them before it reads (or checks) anything else: a few bytes can declare a billion
// triangles and make it reserve gigabytes (found by fuzz_draco). Read here exactly as
// libdraco 1.5 reads them (PointCloudDecoder::Decode, then the connectivity decoders).
struct DeclaredCounts {
  uint64_t triangles = 0;
  uint64_t vertices = 0;  // edgebreaker: encoded vertices + split symbols; sequential: points
  bool edgebreaker = false;
};

template <typename T>
bool read_count(draco::DecoderBuffer& buffer, bool fixed_width, uint64_t& out) {
  T value = 0;
  const bool ok = fixed_width ? buffer.Decode(&value) : draco::DecodeVarint(&value, &buffer);
  out = value;
  return ok;
}

// False when the stream ends or is malformed before the counts: libdraco then fails by itself.
bool peek_declared_counts(const uint8_t* data, size_t size, DeclaredCounts& counts) {
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(data), size);
  draco::DracoHeader header;
  if (!draco::PointCloudDecoder::DecodeHeader(&buffer, &header).ok()) return false;
  if (header.encoder_type != draco::TRIANGULAR_MESH) return false;
  const uint16_t version = DRACO_BITSTREAM_VERSION(header.version_major, header.version_minor);
  buffer.set_bitstream_version(version);
  if (version >= DRACO_BITSTREAM_VERSION(1, 3) && (header.flags & METADATA_FLAG_MASK)) {
    draco::GeometryMetadata metadata;
    if (!draco::MetadataDecoder().DecodeGeometryMetadata(&buffer, &metadata)) return false;
  }
  if (header.encoder_method == draco::MESH_SEQUENTIAL_ENCODING) {
    const bool fixed = version < DRACO_BITSTREAM_VERSION(2, 2);
    return read_count<uint32_t>(buffer, fixed, counts.triangles) &&
           read_count<uint32_t>(buffer, fixed, counts.vertices);
  }
  if (header.encoder_method != draco::MESH_EDGEBREAKER_ENCODING) return false;
  counts.edgebreaker = true;
  uint8_t traversal = 0;
  if (!buffer.Decode(&traversal)) return false;
  const bool fixed = version < DRACO_BITSTREAM_VERSION(2, 0);
  uint64_t unused = 0, encoded_vertices = 0, symbols = 0, split_symbols = 0;
  if (version < DRACO_BITSTREAM_VERSION(2, 2) && !read_count<uint32_t>(buffer, fixed, unused)) return false;
  if (!read_count<uint32_t>(buffer, fixed, encoded_vertices)) return false;
  if (!read_count<uint32_t>(buffer, fixed, counts.triangles)) return false;
  counts.vertices = encoded_vertices;
  uint8_t attribute_data = 0;
  if (!buffer.Decode(&attribute_data)) return true;
  if (!read_count<uint32_t>(buffer, fixed, symbols)) return true;
  if (!read_count<uint32_t>(buffer, fixed, split_symbols)) return true;
  counts.vertices = encoded_vertices + split_symbols;
  return true;
}

// Draco streams store triangles: ReadOptions::max_faces bounds the triangles a stream declares
// (for a CageKit polygon file that is its fan triangles). A valid edgebreaker stream has at most
// three vertices per triangle plus one per split symbol (at most one per triangle); a sequential
// stream's points are at most three per triangle plus isolated points (up to max_vertices).
void check_declared_counts(const uint8_t* data, size_t size, const ReadContext& context) {
  DeclaredCounts counts;
  if (!peek_declared_counts(data, size, counts)) return;
  if (counts.triangles > context.options.max_faces)
    context.fail_here("the Draco stream declares " + std::to_string(counts.triangles) +
                          " triangles, more than ReadOptions::max_faces",
                      Status::limit_exceeded);
  const uint64_t vertex_bound = counts.edgebreaker ? estimate_product(4, counts.triangles)
                                                  : estimate_sum(context.options.max_vertices,
                                                                 estimate_product(3, counts.triangles));
  if (counts.vertices > vertex_bound)
    context.fail_here("the Draco stream declares " + std::to_string(counts.vertices) + " vertices for " +
                          std::to_string(counts.triangles) + " triangles, more than the " +
                          std::to_string(vertex_bound) + " " +
                          (counts.edgebreaker ? "they can have (corrupt connectivity header)"
                                              : "they and ReadOptions::max_vertices allow"),
                      counts.edgebreaker ? Status::parse_error : Status::limit_exceeded);
  // libdraco's corner table, traversal and attribute arrays: about 64 bytes per triangle and 48
  // per vertex at their peak.
  check_memory_estimate(estimate_sum(estimate_product(counts.triangles, 64), estimate_product(counts.vertices, 48)),
                        (context.source + ": decoding the Draco stream").c_str());
}

std::unique_ptr<draco::Mesh> decode_mesh(const uint8_t* data, size_t size, const ReadContext& context) {
  if (size == 0) context.fail_here("empty file: no vertices");
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(data), size);
  auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
  if (!type.ok()) context.fail_here(std::string("not a Draco file: ") + type.status().error_msg());
  if (type.value() == draco::POINT_CLOUD) context.fail_here("a Draco point cloud, not a mesh");
  if (type.value() != draco::TRIANGULAR_MESH) context.fail_here("not a Draco mesh");
  check_declared_counts(data, size, context);
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) context.fail_here(std::string("corrupt Draco data: ") + decoded.status().error_msg());
  if (!decoded.value()) context.fail_here("corrupt Draco data");
  return std::move(decoded).value();
}

const draco::PointAttribute& position_attribute(const draco::Mesh& mesh, const ReadContext& context) {
  const draco::PointAttribute* pos = mesh.GetNamedAttribute(draco::GeometryAttribute::POSITION);
  if (!pos || pos->size() == 0) context.fail_here("Draco mesh has no positions: no vertices");
  if (pos->num_components() < 3) context.fail_here("Draco positions have fewer than 3 components");
  // Draco converts values by reading them as their declared type: bool data would be loaded
  // from arbitrary bytes (undefined behaviour; found by fuzz_draco). Positions must be numeric.
  switch (pos->data_type()) {
    case draco::DT_INT8: case draco::DT_UINT8: case draco::DT_INT16: case draco::DT_UINT16:
    case draco::DT_INT32: case draco::DT_UINT32: case draco::DT_INT64: case draco::DT_UINT64:
    case draco::DT_FLOAT32: case draco::DT_FLOAT64:
      break;
    default:
      context.fail_here("Draco positions have a non-numeric data type (" + std::to_string(int(pos->data_type())) + ")");
  }
  return *pos;
}

Vec3 read_position(const draco::PointAttribute& pos, draco::AttributeValueIndex value, const ReadContext& context) {
  double xyz[3] = {0, 0, 0};
  if (value.value() >= pos.size() || !pos.ConvertValue<double>(value, 3, xyz))
    context.fail_here("corrupt Draco position data");
  const Vec3 p(xyz[0], xyz[1], xyz[2]);
  if (!is_finite(p)) context.fail_here("position " + std::to_string(value.value()) + " is not finite");
  return p;
}

// Point -> index of its position value (plain Draco files) or original vertex (CageKit files).
uint32_t mapped_value(const draco::PointAttribute& att, draco::PointIndex point, const draco::Mesh& mesh,
                      const ReadContext& context) {
  if (point.value() >= mesh.num_points()) context.fail_here("corrupt Draco connectivity");
  const draco::AttributeValueIndex value = att.mapped_index(point);
  if (value.value() >= att.size()) context.fail_here("corrupt Draco attribute mapping");
  return value.value();
}

void check_counts(uint64_t vertices, uint64_t faces, const ReadContext& context) {
  if (vertices > context.options.max_vertices)
    context.fail_here(std::to_string(vertices) + " vertices exceed ReadOptions::max_vertices", Status::limit_exceeded);
  if (faces > context.options.max_faces)
    context.fail_here(std::to_string(faces) + " faces exceed ReadOptions::max_faces", Status::limit_exceeded);
}

Cage read_plain_mesh(const draco::Mesh& mesh, const ReadContext& context) {
  const draco::PointAttribute& pos = position_attribute(mesh, context);
  check_counts(pos.size(), mesh.num_faces(), context);
  Cage cage;
  cage.mesh.positions.reserve(pos.size());
  for (uint32_t v = 0; v < pos.size(); ++v)
    cage.mesh.positions.push_back(read_position(pos, draco::AttributeValueIndex(v), context));
  cage.mesh.reserve(pos.size(), mesh.num_faces(), size_t(mesh.num_faces()) * 3);
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    const draco::Mesh::Face& face = mesh.face(draco::FaceIndex(f));
    uint32_t corners[3];
    for (int k = 0; k < 3; ++k) corners[k] = mapped_value(pos, face[k], mesh, context);
    cage.mesh.add_face(corners, 3);
  }
  return cage;
}

// ---- CageKit files -------------------------------------------------------------------------

const draco::PointAttribute& vertex_id_attribute(const draco::Mesh& mesh, const ReadContext& context) {
  const int id = mesh.GetAttributeIdByMetadataEntry("name", kDracoVertexIdName);
  const draco::PointAttribute* att = id >= 0 ? mesh.attribute(id) : nullptr;
  if (!att || att->data_type() != draco::DT_UINT32 || att->num_components() != 1)
    context.fail_here("CageKit Draco file without a valid vertex id attribute");
  return *att;
}

// Vertices that no Draco point came back for (used by no face) are stored as exact doubles,
// in increasing index order.
void place_isolated_vertices(const std::vector<double>& xyz, const std::vector<uint8_t>& seen, Cage& cage,
                             const ReadContext& context) {
  size_t next = 0;
  for (uint32_t v = 0; v < seen.size(); ++v) {
    if (seen[v]) continue;
    if (next + 3 > xyz.size()) context.fail_here("vertex " + std::to_string(v) + " is missing from the Draco data");
    const Vec3 p(xyz[next], xyz[next + 1], xyz[next + 2]);
    if (!is_finite(p)) context.fail_here("isolated vertex " + std::to_string(v) + " is not finite");
    cage.mesh.positions[v] = p;
    next += 3;
  }
  if (next != xyz.size()) context.fail_here("inconsistent cagekit.isolated_positions metadata");
}

// Original vertex of every decoded point, and the positions in original order.
std::vector<uint32_t> read_vertices(const draco::Mesh& mesh, const draco::GeometryMetadata& md,
                                    const DracoOrder& order, Cage& cage, const ReadContext& context) {
  const draco::PointAttribute& pos = position_attribute(mesh, context);
  const draco::PointAttribute& ids = vertex_id_attribute(mesh, context);
  std::vector<double> isolated;
  md.GetEntryDoubleArray(kDracoIsolatedPositionsKey, &isolated);
  // Every vertex is a decoded point or an isolated position: nothing is allocated beyond that.
  if (order.num_vertices > uint64_t(mesh.num_points()) + isolated.size() / 3)
    context.fail_here("more vertices than the Draco data holds");
  std::vector<uint32_t> original(mesh.num_points());
  std::vector<uint8_t> seen(order.num_vertices, 0);
  cage.mesh.positions.assign(order.num_vertices, Vec3());
  for (uint32_t p = 0; p < mesh.num_points(); ++p) {
    uint32_t v = 0;
    const draco::AttributeValueIndex id_value(mapped_value(ids, draco::PointIndex(p), mesh, context));
    if (!ids.ConvertValue<uint32_t>(id_value, 1, &v) || v >= order.num_vertices)
      context.fail_here("corrupt vertex id " + std::to_string(v) + " of Draco point " + std::to_string(p));
    original[p] = v;
    if (!seen[v]) {
      seen[v] = 1;
      const uint32_t value = mapped_value(pos, draco::PointIndex(p), mesh, context);
      cage.mesh.positions[v] = read_position(pos, draco::AttributeValueIndex(value), context);
    }
  }
  place_isolated_vertices(isolated, seen, cage, context);
  return original;
}

// Rebuilds the polygons from the fan triangles (draco_layout.h).
void read_polygons(const draco::Mesh& mesh, const DracoOrder& order, const std::vector<uint32_t>& original,
                   Cage& cage, const ReadContext& context) {
  // corners[3 t + k]: corner k of original triangle t.
  std::vector<uint32_t> corners(size_t(order.num_triangles) * 3);
  for (uint32_t j = 0; j < order.num_triangles; ++j) {
    const draco::Mesh::Face& face = mesh.face(draco::FaceIndex(j));
    const uint32_t t = order.original_triangle.empty() ? j : order.original_triangle[j];
    const uint32_t r = order.rotation.empty() ? 0 : order.rotation[j];
    for (uint32_t k = 0; k < 3; ++k) {
      const draco::PointIndex point = face[(k + r) % 3];
      if (point.value() >= mesh.num_points()) context.fail_here("corrupt Draco connectivity");
      corners[3 * size_t(t) + k] = original[point.value()];
    }
  }
  PolygonMesh& m = cage.mesh;
  m.reserve(order.num_vertices, order.num_faces, size_t(order.num_triangles) + 2 * size_t(order.num_faces));
  size_t t = 0;
  for (uint32_t f = 0; f < order.num_faces; ++f) {
    const uint32_t size = order.face_sizes.empty() ? 3 : order.face_sizes[f];
    const uint32_t* first = &corners[3 * t];
    m.face_vertices.insert(m.face_vertices.end(), first, first + 3);
    for (uint32_t i = 1; i + 2 < size; ++i) {
      const uint32_t* tri = &corners[3 * (t + i)];
      if (tri[0] != first[0] || tri[1] != m.face_vertices.back())
        context.fail_here("face " + std::to_string(f) + " cannot be rebuilt from its triangles (corrupt data)");
      m.face_vertices.push_back(tri[2]);
    }
    t += size - 2;
    m.face_offsets.push_back(uint32_t(m.face_vertices.size()));
  }
}

template <class T>
std::vector<T> metadata_array(const draco::GeometryMetadata& md, const char* key);

template <>
std::vector<int32_t> metadata_array(const draco::GeometryMetadata& md, const char* key) {
  std::vector<int32_t> values;
  md.GetEntryIntArray(key, &values);
  return values;
}

template <>
std::vector<double> metadata_array(const draco::GeometryMetadata& md, const char* key) {
  std::vector<double> values;
  md.GetEntryDoubleArray(key, &values);
  return values;
}

float checked_sharpness(double s, const ReadContext& context) {
  if (!std::isfinite(s) || s < 0 || s > 3.0e38) context.fail_here("invalid sharpness in Draco metadata");
  return float(s);
}

uint32_t checked_index(int32_t bits, size_t count, const char* what, const ReadContext& context) {
  const uint32_t index = uint32_t(bits);
  if (index >= count) context.fail_here(std::string("tag refers to ") + what + " " + std::to_string(index) +
                                        " that does not exist");
  return index;
}

void read_tags(const draco::GeometryMetadata& md, Cage& cage, const ReadContext& context) {
  const size_t nv = cage.mesh.num_vertices(), nf = cage.mesh.num_faces();
  const auto crease_vertices = metadata_array<int32_t>(md, kDracoCreaseVerticesKey);
  const auto crease_sharpness = metadata_array<double>(md, kDracoCreaseSharpnessKey);
  if (crease_vertices.size() != 2 * crease_sharpness.size()) context.fail_here("inconsistent crease metadata");
  for (size_t i = 0; i < crease_sharpness.size(); ++i)
    cage.creases.push_back({checked_index(crease_vertices[2 * i], nv, "vertex", context),
                            checked_index(crease_vertices[2 * i + 1], nv, "vertex", context),
                            checked_sharpness(crease_sharpness[i], context)});
  const auto corner_vertices = metadata_array<int32_t>(md, kDracoCornerVerticesKey);
  const auto corner_sharpness = metadata_array<double>(md, kDracoCornerSharpnessKey);
  if (corner_vertices.size() != corner_sharpness.size()) context.fail_here("inconsistent corner metadata");
  for (size_t i = 0; i < corner_vertices.size(); ++i)
    cage.corners.push_back({checked_index(corner_vertices[i], nv, "vertex", context),
                            checked_sharpness(corner_sharpness[i], context)});
  for (int32_t h : metadata_array<int32_t>(md, kDracoHolesKey)) cage.holes.push_back(checked_index(h, nf, "face", context));
  int32_t boundary = 0;
  md.GetEntryInt(kDracoBoundaryKey, &boundary);
  if (boundary != int(BoundaryRule::edges_only) && boundary != int(BoundaryRule::edges_and_corners))
    context.fail_here("unknown boundary rule " + std::to_string(boundary) + " in Draco metadata");
  cage.boundary = BoundaryRule(boundary);
}

Cage read_cagekit_mesh(const draco::Mesh& mesh, const draco::GeometryMetadata& md, const ReadContext& context) {
  std::vector<uint8_t> blob;
  if (!md.GetEntryBinary(kDracoOrderKey, &blob)) context.fail_here("CageKit Draco file without cagekit.order");
  DracoOrder order;
  std::string error;
  const Status status = decode_draco_order(blob, mesh.num_faces(), context.options, order, error);
  if (status != Status::success) context.fail_here(error, status);
  Cage cage;
  const std::vector<uint32_t> original = read_vertices(mesh, md, order, cage, context);
  context.monitor.report("reading", 0.8);
  read_polygons(mesh, order, original, cage, context);
  read_tags(md, cage, context);
  return cage;
}

}  // namespace

Cage read_draco(const uint8_t* data, size_t size, const ReadContext& context) {
  context.monitor.report("reading", 0.0);
  const std::unique_ptr<draco::Mesh> mesh = decode_mesh(data, size, context);
  context.monitor.report("reading", 0.5);
  const draco::GeometryMetadata* md = mesh->GetMetadata();
  int32_t version = 0;
  Cage cage;
  if (md && md->GetEntryInt(kDracoVersionKey, &version)) {
    if (version != kDracoLayoutVersion)
      context.fail_here("CageKit Draco layout version " + std::to_string(version) + " is not supported",
                        Status::version_mismatch);
    cage = read_cagekit_mesh(*mesh, *md, context);
  } else {
    cage = read_plain_mesh(*mesh, context);
  }
  check_not_empty(cage, context);
  context.monitor.report("reading", 1.0);
  return cage;
}

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
