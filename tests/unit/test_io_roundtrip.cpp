// SPDX-License-Identifier: GPL-3.0-or-later
// Round trips of generated meshes and cages through every format (memory and files), hand-written
// files with the syntax variants each reader must accept, and the fandisk Draco size/error check.
#include <gtest/gtest.h>

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/io/mesh_io.h"
#include "test_support.h"

using namespace cagekit;
using cagekit_test::quad_grid;
using cagekit_test::shared_mesh_path;
using cagekit_test::triangle_sphere;
using cagekit_test::unit_cube_quads;

namespace {

// The unit cube with every edge creased (varied sharpness), two corners, a hole and the
// non-default boundary rule.
Cage tagged_cube() {
  Cage cage;
  cage.mesh = unit_cube_quads();
  const uint32_t edges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                 {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  for (int e = 0; e < 12; ++e) cage.creases.push_back({edges[e][0], edges[e][1], 0.25f * float(e + 1)});
  cage.creases[11].sharpness = kSharpnessInfinite;
  cage.corners = {{0, kSharpnessInfinite}, {7, 2.5f}};
  cage.holes = {3};
  cage.boundary = BoundaryRule::edges_and_corners;
  return cage;
}

Cage plain(const PolygonMesh& mesh) {
  Cage cage;
  cage.mesh = mesh;
  return cage;
}

// A closed heptagonal prism: two heptagons, side quads, one side split into two triangles and two
// sides cut into a pentagon and a triangle, listed in a scrambled order with rotated first
// corners, so face sizes, order and first corners are all non-trivial.
PolygonMesh mixed_polygons() {
  PolygonMesh m;
  const int n = 7;
  for (int ring = 0; ring < 2; ++ring)
    for (int i = 0; i < n; ++i)
      m.add_vertex(Vec3(std::cos(6.283185307179586 * i / n), std::sin(6.283185307179586 * i / n), ring ? 1.5 : 0.0));
  auto b = [](int i) { return uint32_t(i % 7); };
  auto t = [](int i) { return uint32_t(7 + i % 7); };
  std::vector<std::vector<uint32_t>> faces;
  faces.push_back({t(2), t(3), t(4), t(5), t(6), t(0), t(1)});  // top, rotated
  faces.push_back({b(0), t(0), t(6), b(6)});                      // side 6
  faces.push_back({b(1), b(2), t(2)});                            // side 1 split
  faces.push_back({b(3), t(3), t(2), b(2)});                      // side 2, rotated quad
  faces.push_back({t(2), t(1), b(1)});                            // side 1 split (second half)
  faces.push_back({b(6), b(5), b(4), b(3), b(2), b(1), b(0)});    // bottom
  faces.push_back({b(3), b(4), b(5), t(5), t(4)});                // sides 3 and 4: a pentagon...
  faces.push_back({b(3), t(4), t(3)});                            // ...and a triangle
  faces.push_back({t(6), t(5), b(5), b(6)});                      // side 5
  faces.push_back({b(0), b(1), t(1), t(0)});                      // side 0
  for (const auto& f : faces) m.add_face(f.data(), f.size());
  return m;
}

std::vector<uint8_t> write(const Cage& cage, FileFormat format, WriteReport* report = nullptr,
                           WriteOptions options = {}) {
  options.format = format;
  return write_cage_to_memory(cage, options, report);
}

Cage read(const std::vector<uint8_t>& bytes, FileFormat format) {
  return read_cage_from_memory(bytes.data(), bytes.size(), format, "<test>");
}

Cage read_text(const std::string& text, FileFormat format, const std::string& name = "<test>") {
  return read_cage_from_memory(reinterpret_cast<const uint8_t*>(text.data()), text.size(), format, name);
}

std::string temp_path(const std::string& name) { return std::string(CAGEKIT_BINARY_DIR) + "/io_roundtrip_" + name; }

size_t file_size(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  return in ? size_t(in.tellg()) : 0;
}

void expect_same_connectivity(const PolygonMesh& a, const PolygonMesh& b) {
  ASSERT_EQ(a.num_vertices(), b.num_vertices());
  ASSERT_EQ(a.num_faces(), b.num_faces());
  EXPECT_EQ(a.face_offsets, b.face_offsets);
  EXPECT_EQ(a.face_vertices, b.face_vertices);
}

double measured_error(const PolygonMesh& a, const PolygonMesh& b) {
  double worst = 0;
  for (size_t v = 0; v < a.num_vertices(); ++v) worst = std::max(worst, distance(a.positions[v], b.positions[v]));
  return worst;
}

void expect_same_tags(const Cage& a, const Cage& b) {
  ASSERT_EQ(a.creases.size(), b.creases.size());
  for (size_t i = 0; i < a.creases.size(); ++i) {
    EXPECT_EQ(a.creases[i].v0, b.creases[i].v0);
    EXPECT_EQ(a.creases[i].v1, b.creases[i].v1);
    EXPECT_EQ(a.creases[i].sharpness, b.creases[i].sharpness);
  }
  ASSERT_EQ(a.corners.size(), b.corners.size());
  for (size_t i = 0; i < a.corners.size(); ++i) {
    EXPECT_EQ(a.corners[i].vertex, b.corners[i].vertex);
    EXPECT_EQ(a.corners[i].sharpness, b.corners[i].sharpness);
  }
  EXPECT_EQ(a.holes, b.holes);
  EXPECT_EQ(a.boundary, b.boundary);
}

// Quantization bound of Draco: half a step per axis over the largest bbox extent, plus float rounding.
double draco_bound(const PolygonMesh& mesh, int bits) {
  const BoundingBox box = mesh.bounding_box();
  const Vec3 extent = box.max - box.min;
  const double range = std::max({extent.x, extent.y, extent.z});
  return range / std::pow(2.0, bits) * std::sqrt(3.0) * 1.01 + 1e-6 * norm(box.max - box.min);
}

std::vector<Cage> sample_cages() {
  return {plain(triangle_sphere(2)), plain(quad_grid(5, 3, [](double x, double y) { return 0.1 * x * y; })),
          tagged_cube(), plain(mixed_polygons())};
}

}  // namespace

TEST(io_roundtrip, ObjIsExactAt17DigitsAndKeepsTags) {
  WriteOptions options;
  options.obj_precision = 17;
  for (const Cage& cage : sample_cages()) {
    WriteReport report;
    const Cage back = read(write(cage, FileFormat::obj, &report, options), FileFormat::obj);
    expect_same_connectivity(cage.mesh, back.mesh);
    EXPECT_EQ(cage.mesh.positions, back.mesh.positions);
    EXPECT_EQ(report.max_position_error, 0.0);
    expect_same_tags(cage, back);
  }
}

TEST(io_roundtrip, ObjReportsTheRoundingErrorOfLowPrecision) {
  Cage cage = plain(triangle_sphere(2));
  WriteOptions options;
  options.obj_precision = 4;
  WriteReport report;
  const Cage back = read(write(cage, FileFormat::obj, &report, options), FileFormat::obj);
  EXPECT_GT(report.max_position_error, 0.0);
  EXPECT_LT(report.max_position_error, 1e-3);
  EXPECT_DOUBLE_EQ(report.max_position_error, measured_error(cage.mesh, back.mesh));
}

TEST(io_roundtrip, PlyBinaryIsExactAndAsciiWithinPrecision) {
  for (const Cage& cage : sample_cages()) {
    WriteOptions options;
    options.ply_binary = true;
    WriteReport report;
    const std::vector<uint8_t> bytes = write(cage, FileFormat::ply, &report, options);
    EXPECT_EQ(report.bytes, bytes.size());
    const Cage binary = read(bytes, FileFormat::ply);
    expect_same_connectivity(cage.mesh, binary.mesh);
    EXPECT_EQ(cage.mesh.positions, binary.mesh.positions);
    EXPECT_EQ(report.max_position_error, 0.0);
    EXPECT_FALSE(binary.has_tags());

    options.ply_binary = false;
    options.obj_precision = 17;
    const Cage ascii = read(write(cage, FileFormat::ply, &report, options), FileFormat::ply);
    expect_same_connectivity(cage.mesh, ascii.mesh);
    EXPECT_EQ(cage.mesh.positions, ascii.mesh.positions);
  }
}

TEST(io_roundtrip, OffKeepsConnectivityAndPositions) {
  WriteOptions options;
  options.obj_precision = 17;
  for (const Cage& cage : sample_cages()) {
    const Cage back = read(write(cage, FileFormat::off, nullptr, options), FileFormat::off);
    expect_same_connectivity(cage.mesh, back.mesh);
    EXPECT_EQ(cage.mesh.positions, back.mesh.positions);
  }
}

TEST(io_roundtrip, DracoKeepsPolygonsOrderTagsAndReportsTheTrueError) {
  for (int bits : {8, 14, 20}) {
    for (const Cage& cage : sample_cages()) {
      WriteOptions options;
      options.draco_position_bits = bits;
      WriteReport report;
      const std::vector<uint8_t> bytes = write(cage, FileFormat::draco, &report, options);
      EXPECT_EQ(report.bytes, bytes.size());
      const Cage back = read(bytes, FileFormat::draco);
      expect_same_connectivity(cage.mesh, back.mesh);
      expect_same_tags(cage, back);
      const double error = measured_error(cage.mesh, back.mesh);
      EXPECT_DOUBLE_EQ(report.max_position_error, error) << bits << " bits";
      EXPECT_LE(report.max_position_error, draco_bound(cage.mesh, bits)) << bits << " bits";
    }
  }
}

TEST(io_roundtrip, DracoErrorIsMeasuredNotAssumed) {
  const Cage sphere = plain(triangle_sphere(3));
  WriteOptions options;
  options.draco_position_bits = 8;
  WriteReport coarse, fine;
  write(sphere, FileFormat::draco, &coarse, options);
  options.draco_position_bits = 16;
  write(sphere, FileFormat::draco, &fine, options);
  EXPECT_GT(coarse.max_position_error, 0.0);
  EXPECT_GT(coarse.max_position_error, 10 * fine.max_position_error);
  EXPECT_LE(coarse.max_position_error, draco_bound(sphere.mesh, 8));
}

TEST(io_roundtrip, DracoKeepsMixedFaceSizesAndOrder) {
  const Cage cage = plain(mixed_polygons());
  const Cage back = read(write(cage, FileFormat::draco), FileFormat::draco);
  ASSERT_EQ(back.mesh.num_faces(), 10u);
  for (size_t f = 0; f < cage.mesh.num_faces(); ++f) EXPECT_EQ(back.mesh.face_size(f), cage.mesh.face_size(f));
  expect_same_connectivity(cage.mesh, back.mesh);
}

TEST(io_roundtrip, DracoKeepsIsolatedVerticesDegenerateAndNonManifoldFaces) {
  Cage isolated = tagged_cube();
  isolated.mesh.add_vertex(Vec3(5, 5, 5));  // referenced by no face
  Cage odd = tagged_cube();
  odd.mesh.add_vertex(Vec3(0.5, -1, 0));
  odd.mesh.add_face({0, 1, 8});     // a fin: edge (0,1) now has three faces
  odd.mesh.add_face({0, 1, 8});     // the same face twice
  odd.mesh.add_face({2, 2, 3, 6});  // a repeated vertex
  for (const Cage& cage : {isolated, odd}) {
    const Cage back = read(write(cage, FileFormat::draco), FileFormat::draco);
    expect_same_connectivity(cage.mesh, back.mesh);
    expect_same_tags(cage, back);
  }
}

TEST(io_roundtrip, FilesInEveryFormat) {
  const Cage cage = tagged_cube();
  WriteOptions options;
  options.obj_precision = 17;
  for (const char* ext : {"obj", "ply", "off", "drc"}) {
    const std::string path = temp_path(std::string("cube.") + ext);
    WriteReport report;
    write_cage_to_file(path, cage, options, &report);
    EXPECT_EQ(report.bytes, file_size(path));
    const Cage back = read_cage_from_file(path);
    expect_same_connectivity(cage.mesh, back.mesh);
    const FileFormat format = file_format_from_path(path);
    if (format_keeps_tags(format)) expect_same_tags(cage, back);
    else EXPECT_FALSE(back.has_tags());
    std::remove(path.c_str());
  }
}

TEST(io_roundtrip, CreasedQuadCubeObjToDracoToObj) {
  const std::string obj = temp_path("creased.obj"), drc = temp_path("creased.drc"), obj2 = temp_path("creased2.obj");
  const Cage cage = tagged_cube();
  write_cage_to_file(obj, cage, {});
  write_cage_to_file(drc, read_cage_from_file(obj), {});
  write_cage_to_file(obj2, read_cage_from_file(drc), {});
  const Cage back = read_cage_from_file(obj2);
  EXPECT_EQ(back.mesh.num_faces(), 6u);
  EXPECT_TRUE(back.mesh.all_faces_have_size(4));
  expect_same_connectivity(cage.mesh, back.mesh);
  expect_same_tags(cage, back);
  for (const std::string& p : {obj, drc, obj2}) std::remove(p.c_str());
}

TEST(io_roundtrip, FandiskDracoIsTenTimesSmallerAndAccurate) {
  const std::string path = shared_mesh_path("fandisk.obj");
  if (path.empty()) GTEST_SKIP() << "../shared/meshes/fandisk.obj not present";
  const Cage cage = read_cage_from_file(path);
  ASSERT_EQ(cage.mesh.num_faces(), 12946u);
  const std::string drc = temp_path("fandisk.drc");
  WriteOptions options;
  options.draco_position_bits = 14;
  WriteReport report;
  write_cage_to_file(drc, cage, options, &report);
  const size_t obj_size = file_size(path), drc_size = file_size(drc);
  RecordProperty("drc_bytes", int(drc_size));
  std::printf("fandisk: OBJ %zu bytes, DRC %zu bytes (%.1fx), max error %.3g (bbox diagonal %.3g)\n", obj_size,
              drc_size, double(obj_size) / double(drc_size), report.max_position_error,
              cage.mesh.bounding_box().diagonal());
  EXPECT_LE(drc_size * 10, obj_size);
  EXPECT_LE(report.max_position_error, 1e-4 * cage.mesh.bounding_box().diagonal());
  const Cage back = read_cage_from_file(drc);
  expect_same_connectivity(cage.mesh, back.mesh);
  EXPECT_DOUBLE_EQ(report.max_position_error, measured_error(cage.mesh, back.mesh));
  std::remove(drc.c_str());
}

TEST(io_roundtrip, ReadsForeignDracoTriangleMeshes) {
  // A Draco mesh written without CageKit's metadata: 2 triangles over 4 points.
  draco::Mesh mesh;
  mesh.set_num_points(4);
  draco::GeometryAttribute position;
  position.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, 12, 0);
  draco::PointAttribute* pos = mesh.attribute(mesh.AddAttribute(position, true, 4));
  const float xyz[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  for (uint32_t v = 0; v < 4; ++v) pos->SetAttributeValue(draco::AttributeValueIndex(v), xyz[v]);
  mesh.AddFace({draco::PointIndex(0), draco::PointIndex(1), draco::PointIndex(2)});
  mesh.AddFace({draco::PointIndex(0), draco::PointIndex(2), draco::PointIndex(3)});
  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 16);
  draco::EncoderBuffer buffer;
  ASSERT_TRUE(encoder.EncodeMeshToBuffer(mesh, &buffer).ok());
  const std::vector<uint8_t> bytes(buffer.data(), buffer.data() + buffer.size());
  EXPECT_EQ(sniff_file_format(bytes.data(), bytes.size()), FileFormat::draco);
  const Cage cage = read(bytes, FileFormat::unknown);
  EXPECT_EQ(cage.mesh.num_vertices(), 4u);
  EXPECT_EQ(cage.mesh.num_faces(), 2u);
  EXPECT_TRUE(cage.mesh.all_faces_have_size(3));
  EXPECT_FALSE(cage.has_tags());
}

// ---- Hand-written files: syntax variants ------------------------------------------------------

TEST(io_obj_syntax, IndexFormsNegativeIndicesIgnoredStatementsAndCrlf) {
  const std::string text =
      "# comment\r\nmtllib a.mtl\r\no thing\r\ng group\r\ns 1\r\nusemtl red\r\n"
      "v 0 0 0\r\nv 1 0 0 1.0\r\nv 1 1 0\r\nv 0 1 0\r\nvt 0 0\r\nvn 0 0 1\r\n"
      "f 1/1/1 2/2/1 3/3/1 # trailing comment\r\n"
      "f -4//1 -2//1 -1//1\r\n"
      "f 1/1 3/3 4/4\r\n";
  const Cage cage = read_text(text, FileFormat::obj);
  ASSERT_EQ(cage.mesh.num_vertices(), 4u);
  ASSERT_EQ(cage.mesh.num_faces(), 3u);
  EXPECT_EQ(cage.mesh.face_vertices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 0, 2, 3}));
  EXPECT_EQ(cage.mesh.positions[1], Vec3(1, 0, 0));
}

TEST(io_obj_syntax, ForwardReferencesAndPlusSigns) {
  const Cage cage = read_text("f 1 2 3\nv +1 0 0\nv 0 +1.5e0 0\nv 0 0 1\n", FileFormat::obj);
  EXPECT_EQ(cage.mesh.num_faces(), 1u);
  EXPECT_EQ(cage.mesh.positions[1], Vec3(0, 1.5, 0));
}

TEST(io_obj_syntax, OpenSubdivTagLines) {
  const std::string text =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
      "f 1 2 3 4\nf 2 5 6 3\n"
      "t crease 2/1/0 0 1 5.0\n"
      "t crease 4/1/0 1 4 4 5 2\n"    // two edges, one sharpness
      "t crease 4/2/0 5 2 2 3 1 3\n"  // two edges, two sharpnesses
      "t corner 2/1/0 0 4 10\n"
      "t hole 1/0/0 1\n"
      "t interpolateboundary 1/0/0 1\n"
      "t facevaryinginterpolateboundary 1/0/0 2\n";  // not used by CageKit: ignored
  const Cage cage = read_text(text, FileFormat::obj);
  ASSERT_EQ(cage.creases.size(), 5u);
  EXPECT_EQ(cage.creases[0].v0, 0u);
  EXPECT_EQ(cage.creases[0].v1, 1u);
  EXPECT_EQ(cage.creases[0].sharpness, 5.0f);
  EXPECT_EQ(cage.creases[2].v0, 4u);
  EXPECT_EQ(cage.creases[2].sharpness, 2.0f);
  EXPECT_EQ(cage.creases[3].sharpness, 1.0f);
  EXPECT_EQ(cage.creases[4].sharpness, 3.0f);
  ASSERT_EQ(cage.corners.size(), 2u);
  EXPECT_EQ(cage.corners[1].vertex, 4u);
  EXPECT_EQ(cage.holes, std::vector<uint32_t>{1});
  // OpenSubdiv's shape files: 1 = edges and corners (catmark_edgecorner), 2 = edges only.
  EXPECT_EQ(cage.boundary, BoundaryRule::edges_and_corners);
  EXPECT_EQ(read_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt interpolateboundary 1/0/0 2\n", FileFormat::obj).boundary,
            BoundaryRule::edges_only);
}

TEST(io_ply_syntax, BigEndianWithExtraPropertiesAndElements) {
  // Vertices: float x, uchar red, double y, list uchar int junk, short z; face: uint flags first,
  // then list ushort uint vertex_indices; an extra "edge" element before and a "material" after.
  std::string header =
      "ply\nformat binary_big_endian 1.0\ncomment hand written\nobj_info test\n"
      "element edge 2\nproperty int a\nproperty int b\n"
      "element vertex 4\nproperty float x\nproperty uchar red\nproperty double y\n"
      "property list uchar int junk\nproperty short z\n"
      "element face 2\nproperty uint flags\nproperty list ushort uint vertex_indices\n"
      "element material 1\nproperty list uint float values\nend_header\n";
  std::vector<uint8_t> bytes(header.begin(), header.end());
  auto be = [&bytes](uint64_t v, int n) {
    for (int i = n - 1; i >= 0; --i) bytes.push_back(uint8_t(v >> (8 * i)));
  };
  auto bef = [&be](float f) { uint32_t u; std::memcpy(&u, &f, 4); be(u, 4); };
  auto bed = [&be](double d) { uint64_t u; std::memcpy(&u, &d, 8); be(u, 8); };
  for (int i = 0; i < 2; ++i) be(uint64_t(i), 4), be(uint64_t(i + 1), 4);  // edges
  const double xyz[4][3] = {{0, 0, 0}, {1.5, 0, 1}, {1.5, 2.25, -3}, {0, 2.25, 0}};
  for (const auto& p : xyz) {
    bef(float(p[0]));
    be(200, 1);
    bed(p[1]);
    be(2, 1), be(7, 4), be(8, 4);  // junk list of 2 ints
    be(uint64_t(int64_t(p[2])) & 0xFFFF, 2);
  }
  be(0xDEADBEEF, 4), be(3, 2), be(0, 4), be(1, 4), be(2, 4);
  be(1, 4), be(3, 2), be(0, 4), be(2, 4), be(3, 4);
  be(2, 4), bef(0.5f), bef(0.25f);
  const Cage cage = read_cage_from_memory(bytes.data(), bytes.size(), FileFormat::unknown, "<be>");
  ASSERT_EQ(cage.mesh.num_vertices(), 4u);
  ASSERT_EQ(cage.mesh.num_faces(), 2u);
  EXPECT_EQ(cage.mesh.positions[2], Vec3(1.5, 2.25, -3));
  EXPECT_EQ(cage.mesh.face_vertices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
}

TEST(io_ply_syntax, AsciiWithFacesFirstAndVertexIndexName) {
  const std::string text =
      "ply\r\nformat ascii 1.0\r\nelement face 1\r\nproperty list uchar int vertex_index\r\nproperty uchar red\r\n"
      "element vertex 4\r\nproperty int x\r\nproperty int y\r\nproperty float z\r\nproperty float nx\r\n"
      "end_header\r\n4 0 1 2 3 255\r\n0 0 0 1\r\n1 0 0 1\r\n1 1 0.5 1\r\n0 1 0 1\r\n";
  const Cage cage = read_text(text, FileFormat::ply);
  ASSERT_EQ(cage.mesh.num_faces(), 1u);
  EXPECT_EQ(cage.mesh.face_size(0), 4u);
  EXPECT_EQ(cage.mesh.positions[2], Vec3(1, 1, 0.5));
}

TEST(io_off_syntax, CommentsColoursAndHeaderCounts) {
  const Cage a = read_text("# leading comment\nOFF\n# counts next\n4 1 0\n0 0 0\n1 0 0\n1 1 0 # c\n\n0 1 0\n"
                           "4 0 1 2 3 255 0 0\n",
                           FileFormat::unknown);
  EXPECT_EQ(a.mesh.num_faces(), 1u);
  EXPECT_EQ(a.mesh.face_size(0), 4u);
  const Cage b = read_text("COFF 3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 0 1 2\n",
                           FileFormat::off);
  EXPECT_EQ(b.mesh.positions[1], Vec3(1, 0, 0));
  EXPECT_EQ(b.mesh.face_vertices, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(io_formats, NamesExtensionsAndSniffing) {
  EXPECT_EQ(file_format_from_path("a/b.OBJ"), FileFormat::obj);
  EXPECT_EQ(file_format_from_path("x.ply"), FileFormat::ply);
  EXPECT_EQ(file_format_from_path("x.off"), FileFormat::off);
  EXPECT_EQ(file_format_from_path("x.drc"), FileFormat::draco);
  EXPECT_EQ(file_format_from_path("dir.obj/x"), FileFormat::unknown);
  EXPECT_STREQ(file_format_name(FileFormat::draco), "Draco");
  const Cage cube = tagged_cube();
  for (FileFormat f : {FileFormat::obj, FileFormat::ply, FileFormat::off, FileFormat::draco}) {
    const std::vector<uint8_t> bytes = write(cube, f);
    EXPECT_EQ(sniff_file_format(bytes.data(), bytes.size()), f) << file_format_name(f);
    EXPECT_EQ(read(bytes, FileFormat::unknown).mesh.num_faces(), 6u);
  }
  EXPECT_TRUE(format_keeps_tags(FileFormat::obj));
  EXPECT_TRUE(format_keeps_tags(FileFormat::draco));
  EXPECT_FALSE(format_keeps_tags(FileFormat::ply));
  EXPECT_FALSE(format_keeps_tags(FileFormat::off));
}

TEST(io_files, FailedWritesLeaveNoOutputAndNoTemporaryFiles) {
  const std::string path = temp_path("atomic.obj");
  write_cage_to_file(path, tagged_cube(), {});
  const size_t before = file_size(path);
  Cage broken = tagged_cube();
  broken.mesh.face_vertices[0] = 99;  // out of range: refused before anything is written
  try {
    write_cage_to_file(path, broken, {});
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), Status::invalid_mesh);
  }
  EXPECT_EQ(file_size(path), before);
  try {
    write_cage_to_file(temp_path("no/such/dir/x.obj"), tagged_cube(), {});
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), Status::io_error);
    EXPECT_NE(std::string(e.what()).find("no/such/dir"), std::string::npos);
  }
  std::remove(path.c_str());
}

TEST(io_files, FailedRenameRemovesTheTemporaryFile) {
  namespace fs = std::filesystem;
  const fs::path target = temp_path("a_directory.obj");
  fs::create_directories(target / "inside");  // renaming a file over a non-empty directory fails
  try {
    write_cage_to_file(target.string(), tagged_cube(), {});
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), Status::io_error);
  }
  for (const auto& entry : fs::directory_iterator(target.parent_path()))
    EXPECT_EQ(entry.path().filename().string().find("io_roundtrip_a_directory.obj.tmp"), std::string::npos);
  fs::remove_all(target);
}

TEST(io_progress, ReportsAndCancels) {
  const Cage big = plain(quad_grid(256, 256));  // 66049 vertices + 65536 faces: over 2^16 lines
  const std::vector<uint8_t> bytes = write(big, FileFormat::obj);
  int calls = 0;
  TaskMonitor counting([&calls](const char*, double f) { ++calls; return f >= 0 && f <= 1; }, nullptr);
  const Cage back = read_cage_from_memory(bytes.data(), bytes.size(), FileFormat::obj, "<big>", {}, counting);
  EXPECT_EQ(back.mesh.num_faces(), big.mesh.num_faces());
  EXPECT_GE(calls, 2);
  TaskMonitor cancel([](const char*, double) { return false; }, nullptr);
  for (FileFormat f : {FileFormat::obj, FileFormat::ply, FileFormat::off, FileFormat::draco}) {
    const std::vector<uint8_t> data = write(f == FileFormat::draco ? tagged_cube() : big, f);
    try {
      read_cage_from_memory(data.data(), data.size(), f, "<big>", {}, cancel);
      FAIL() << "expected cancellation";
    } catch (const Error& e) {
      EXPECT_EQ(e.status(), Status::cancelled);
    }
  }
}
