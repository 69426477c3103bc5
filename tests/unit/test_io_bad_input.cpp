// SPDX-License-Identifier: GPL-3.0-or-later
// Hostile input for every reader: truncation at every byte, random corruption (fixed seed),
// hostile counts, limits, non-finite numbers, bad indices and tags, garbage, non-mesh Draco.
// Every case must end in a valid cage or an Error naming the source (and location where there
// is one) - never a crash, a hang or a huge allocation (this suite also runs under ASan+UBSan).
#include <gtest/gtest.h>

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <draco/point_cloud/point_cloud.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "core/io/mesh_io.h"
#include "core/memory_budget.h"
#include "test_support.h"

using namespace cagekit;

namespace {

using Outcome = cagekit_test::ReadOutcome;
using cagekit_test::bytes_of;

Outcome try_read(const std::vector<uint8_t>& bytes, FileFormat format, const std::string& name,
                 const ReadOptions& options = {}) {
  return cagekit_test::try_read_memory(bytes, format, name, options);
}

// The error must carry a status, the source name and every fragment.
void expect_error(const std::vector<uint8_t>& bytes, FileFormat format, Status status,
                  std::initializer_list<const char*> fragments, const std::string& name = "bad.file",
                  const ReadOptions& options = {}) {
  const Outcome out = try_read(bytes, format, name, options);
  ASSERT_FALSE(out.ok) << "accepted: " << std::string(bytes.begin(), bytes.begin() + std::min<size_t>(bytes.size(), 200));
  EXPECT_EQ(out.status, status) << out.message;
  EXPECT_EQ(out.message.rfind(name, 0), 0u) << out.message;
  for (const char* fragment : fragments) EXPECT_NE(out.message.find(fragment), std::string::npos) << out.message;
}

void expect_error(const std::string& text, FileFormat format, Status status,
                  std::initializer_list<const char*> fragments, const std::string& name = "bad.file",
                  const ReadOptions& options = {}) {
  expect_error(bytes_of(text), format, status, fragments, name, options);
}

// A cage a reader returned must be internally consistent.
void expect_sane(const Cage& cage) {
  const PolygonMesh& m = cage.mesh;
  ASSERT_GT(m.num_vertices(), 0u);
  ASSERT_GT(m.num_faces(), 0u);
  ASSERT_EQ(m.face_offsets.front(), 0u);
  ASSERT_EQ(m.face_offsets.back(), m.face_vertices.size());
  for (size_t f = 0; f < m.num_faces(); ++f) ASSERT_GE(m.face_size(f), 3u);
  for (uint32_t v : m.face_vertices) ASSERT_LT(v, m.num_vertices());
  for (const Vec3& p : m.positions) ASSERT_TRUE(is_finite(p));
  for (const EdgeCrease& c : cage.creases) ASSERT_TRUE(c.v0 < m.num_vertices() && c.v1 < m.num_vertices());
  for (const VertexCorner& c : cage.corners) ASSERT_LT(c.vertex, m.num_vertices());
  for (uint32_t h : cage.holes) ASSERT_LT(h, m.num_faces());
}

Cage tagged_cube() {
  Cage cage;
  cage.mesh = cagekit_test::unit_cube_quads();
  cage.creases = {{0, 1, 2.0f}, {1, 3, kSharpnessInfinite}};
  cage.corners = {{7, 3.0f}};
  cage.holes = {2};
  cage.boundary = BoundaryRule::edges_and_corners;
  return cage;
}

struct Sample {
  const char* name;
  FileFormat format;
  std::vector<uint8_t> bytes;
  bool binary;
};

std::vector<Sample> samples() {
  const Cage cube = tagged_cube();
  Cage sphere;
  sphere.mesh = cagekit_test::triangle_sphere(1);
  auto write = [](const Cage& c, FileFormat f, bool ply_binary = true) {
    WriteOptions o;
    o.format = f;
    o.ply_binary = ply_binary;
    return write_cage_to_memory(c, o);
  };
  return {{"cube.obj", FileFormat::obj, write(cube, FileFormat::obj), false},
          {"cube.ply", FileFormat::ply, write(cube, FileFormat::ply), true},
          {"cube_ascii.ply", FileFormat::ply, write(cube, FileFormat::ply, false), false},
          {"cube.off", FileFormat::off, write(cube, FileFormat::off), false},
          {"cube.drc", FileFormat::draco, write(cube, FileFormat::draco), true},
          {"sphere.drc", FileFormat::draco, write(sphere, FileFormat::draco), true}};
}

std::string ply_binary_header(const std::string& vertex_count, const std::string& face_count,
                              const std::string& list = "uchar int") {
  return "ply\nformat binary_little_endian 1.0\nelement vertex " + vertex_count +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " + face_count + "\nproperty list " +
         list + " vertex_indices\nend_header\n";
}

void put_le(std::vector<uint8_t>& out, uint64_t v, int n) {
  for (int i = 0; i < n; ++i) out.push_back(uint8_t(v >> (8 * i)));
}

void put_float(std::vector<uint8_t>& out, float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  put_le(out, u, 4);
}

// A binary PLY triangle with the given coordinates and indices.
std::vector<uint8_t> ply_triangle(const float xyz[9], const int32_t indices[3], uint8_t count = 3) {
  std::vector<uint8_t> out = bytes_of(ply_binary_header("3", "1"));
  for (int i = 0; i < 9; ++i) put_float(out, xyz[i]);
  out.push_back(count);
  for (int k = 0; k < 3; ++k) put_le(out, uint32_t(indices[k]), 4);
  return out;
}

const char* kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

}  // namespace

TEST(io_bad_input, EveryTruncationIsAnErrorOrAValidPrefix) {
  for (const Sample& s : samples()) {
    size_t errors = 0;
    for (size_t length = 0; length < s.bytes.size(); ++length) {
      const std::vector<uint8_t> prefix(s.bytes.begin(), s.bytes.begin() + length);
      const Outcome out = try_read(prefix, s.format, s.name);
      if (out.ok) {
        ASSERT_FALSE(s.binary) << s.name << " accepted a prefix of " << length << " bytes";
        expect_sane(out.cage);
        continue;
      }
      ++errors;
      ASSERT_NE(out.status, Status::success);
      ASSERT_EQ(out.message.rfind(s.name, 0), 0u) << out.message;
      ASSERT_GT(out.message.size(), std::strlen(s.name) + 2) << out.message;
    }
    EXPECT_GT(errors, s.bytes.size() / 2) << s.name;
  }
}

TEST(io_bad_input, RandomCorruptionNeverCrashes) {
  std::mt19937 rng(20240611);
  for (const Sample& s : samples()) {
    size_t accepted = 0;
    for (int round = 0; round < 400; ++round) {
      std::vector<uint8_t> bytes = s.bytes;
      const int edits = 1 + int(rng() % 6);
      for (int e = 0; e < edits; ++e) {
        const size_t at = rng() % bytes.size();
        switch (rng() % 5) {
          case 0: bytes[at] = uint8_t(rng()); break;                        // any byte
          case 1: bytes[at] = uint8_t('0' + rng() % 10); break;             // a digit
          case 2: bytes[at] ^= uint8_t(1u << (rng() % 8)); break;           // a bit flip
          case 3: bytes.erase(bytes.begin() + long(at)); break;             // a deletion
          default: bytes.insert(bytes.begin() + long(at), uint8_t(rng())); // an insertion
        }
        if (bytes.empty()) bytes.push_back('v');
      }
      const Outcome out = try_read(bytes, s.format, s.name);
      if (out.ok) {
        ++accepted;
        expect_sane(out.cage);
      } else {
        ASSERT_NE(out.status, Status::success);
        ASSERT_EQ(out.message.rfind(s.name, 0), 0u) << out.message;
      }
    }
    RecordProperty(std::string(s.name) + "_accepted", int(accepted));
  }
}

TEST(io_bad_input, HostileCountsFailBeforeAllocating) {
  expect_error(ply_binary_header("4000000000", "1") + "tiny", FileFormat::ply, Status::parse_error,
               {"byte", "4000000000", "vertex"});
  std::vector<uint8_t> many_faces = bytes_of(ply_binary_header("3", "4000000000"));
  for (int i = 0; i < 9; ++i) put_float(many_faces, float(i));
  expect_error(many_faces, FileFormat::ply, Status::parse_error, {"byte", "4000000000", "face"});
  expect_error("ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
               "property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n",
               FileFormat::ply, Status::parse_error, {"4000000000"});
  expect_error("ply\nformat ascii 1.0\nelement vertex 18446744073709551615\nproperty float x\nend_header\n",
               FileFormat::ply, Status::parse_error, {});
  expect_error("OFF\n4000000000 1 0\n0 0 0\n", FileFormat::off, Status::parse_error, {"bad.file:2:", "4000000000"});
  expect_error("OFF 3 4000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", FileFormat::off, Status::parse_error,
               {"bad.file:1:"});
  // A face list longer than ReadOptions::max_face_size, and one longer than the file.
  std::vector<uint8_t> huge_list = bytes_of(ply_binary_header("3", "1", "uint int"));
  for (int i = 0; i < 9; ++i) put_float(huge_list, float(i));
  put_le(huge_list, 0xFFFFFFFFu, 4);
  for (int k = 0; k < 3; ++k) put_le(huge_list, 0, 4);
  expect_error(huge_list, FileFormat::ply, Status::limit_exceeded, {"byte", "4294967295"});
  std::vector<uint8_t> long_list = bytes_of(ply_binary_header("3", "1"));
  for (int i = 0; i < 9; ++i) put_float(long_list, float(i));
  put_le(long_list, 200, 1);
  for (int k = 0; k < 3; ++k) put_le(long_list, 0, 4);
  expect_error(long_list, FileFormat::ply, Status::parse_error, {"byte", "200"});
  expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n100000000 0 1 2\n", FileFormat::off, Status::limit_exceeded,
               {"bad.file:6:"});
  std::string big_face = std::string(kTriangleObj) + "f";
  for (int i = 0; i < 70000; ++i) big_face += " 1";
  expect_error(big_face + "\n", FileFormat::obj, Status::limit_exceeded, {"bad.file:4:"});
  expect_error(std::string(kTriangleObj) + "f 1 2 3\nt crease 4000000000/1/0 0 1 2\n", FileFormat::obj,
               Status::parse_error, {"bad.file:5:"});
}

TEST(io_bad_input, ReadOptionsLimitsApplyToEveryFormat) {
  ReadOptions few_vertices;
  few_vertices.max_vertices = 4;
  ReadOptions few_faces;
  few_faces.max_faces = 2;
  for (const Sample& s : samples()) {
    expect_error(s.bytes, s.format, Status::limit_exceeded, {}, s.name, few_vertices);
    expect_error(s.bytes, s.format, Status::limit_exceeded, {}, s.name, few_faces);
  }
  ReadOptions small_faces;
  small_faces.max_face_size = 3;
  expect_error(samples()[0].bytes, FileFormat::obj, Status::limit_exceeded, {}, "cube.obj", small_faces);
  expect_error(samples()[4].bytes, FileFormat::draco, Status::limit_exceeded, {}, "cube.drc", small_faces);
}

TEST(io_bad_input, NonFiniteCoordinatesAreRefused) {
  for (const char* v : {"v nan 0 0\n", "v 0 inf 0\n", "v 0 0 -inf\n", "v 1e999 0 0\n", "v 0 -1e400 0\n"})
    expect_error(std::string("# x\n") + v + "v 1 0 0\nv 0 1 0\nf 1 2 3\n", FileFormat::obj, Status::parse_error,
                 {"bad.obj:2:", "finite"}, "bad.obj");
  expect_error("OFF\n3 1 0\n0 0 0\n1 NaN 0\n0 1 0\n3 0 1 2\n", FileFormat::off, Status::parse_error,
               {"bad.off:4:"}, "bad.off");
  expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 inf\n3 0 1 2\n", FileFormat::off, Status::parse_error,
               {"bad.off:5:", "finite"}, "bad.off");
  expect_error("ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
               "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n",
               FileFormat::ply, Status::parse_error, {"bad.ply:11:", "finite"}, "bad.ply");
  const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, std::nanf(""), 0};
  const int32_t tri[3] = {0, 1, 2};
  expect_error(ply_triangle(xyz, tri), FileFormat::ply, Status::parse_error, {"bad.ply: byte", "finite"}, "bad.ply");
  const float inf[9] = {0, 0, 0, 1, 0, 0, 0, 1, INFINITY};
  expect_error(ply_triangle(inf, tri), FileFormat::ply, Status::parse_error, {"byte"}, "bad.ply");
}

TEST(io_bad_input, BadIndicesNameTheLineOrByte) {
  expect_error(std::string(kTriangleObj) + "f 1 2 9000\n", FileFormat::obj, Status::parse_error,
               {"fandisk.obj:4: face refers to vertex 9000 but only 3 vertices are defined"}, "fandisk.obj");
  expect_error(std::string(kTriangleObj) + "f 0 1 2\n", FileFormat::obj, Status::parse_error, {"bad.obj:4:", "0"},
               "bad.obj");
  expect_error(std::string(kTriangleObj) + "f -4 -1 -2\n", FileFormat::obj, Status::parse_error,
               {"bad.obj:4:", "-4"}, "bad.obj");
  expect_error(std::string(kTriangleObj) + "f 1 2 x\n", FileFormat::obj, Status::parse_error, {"bad.obj:4:"}, "bad.obj");
  expect_error(std::string(kTriangleObj) + "f 1 2 99999999999999999999\n", FileFormat::obj, Status::parse_error,
               {"bad.obj:4:"}, "bad.obj");
  expect_error(std::string(kTriangleObj) + "\nf 1 2\n", FileFormat::obj, Status::parse_error,
               {"bad.obj:5:", "2 vertices"}, "bad.obj");
  expect_error("v 0 0\n", FileFormat::obj, Status::parse_error, {"bad.obj:1:"}, "bad.obj");
  expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", FileFormat::off, Status::parse_error,
               {"bad.off:6:", "vertex 3"}, "bad.off");
  expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1     \n", FileFormat::off, Status::parse_error,
               {"bad.off:6:", "at least 3"}, "bad.off");
  expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", FileFormat::off, Status::parse_error, {"bad.off:6:"},
               "bad.off");
  const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const int32_t out_of_range[3] = {0, 1, 3}, negative[3] = {0, -1, 2}, ok[3] = {0, 1, 2};
  const size_t header = ply_binary_header("3", "1").size();
  const std::string last_index = "byte " + std::to_string(header + 36 + 1 + 8);
  expect_error(ply_triangle(xyz, out_of_range), FileFormat::ply, Status::parse_error,
               {last_index.c_str(), "vertex 3 but only 3"}, "bad.ply");
  expect_error(ply_triangle(xyz, negative), FileFormat::ply, Status::parse_error, {"byte", "-1"}, "bad.ply");
  expect_error(ply_triangle(xyz, ok, 2), FileFormat::ply, Status::parse_error, {"byte", "at least 3"}, "bad.ply");
  expect_error("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
               "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
               FileFormat::ply, Status::parse_error, {"bad.ply:13:", "vertex 7"}, "bad.ply");
}

TEST(io_bad_input, BadObjTagLines) {
  const std::string cube = std::string(reinterpret_cast<const char*>(samples()[0].bytes.data()), samples()[0].bytes.size());
  const std::string base = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  expect_error(base + "t crease 2/1/0 0 3 1\n", FileFormat::obj, Status::parse_error, {"t.obj:5:", "vertex 3"}, "t.obj");
  expect_error(base + "t hole 1/0/0 1\n", FileFormat::obj, Status::parse_error, {"t.obj:5:", "face 1"}, "t.obj");
  expect_error(base + "t corner 1/1/0 -1 1\n", FileFormat::obj, Status::parse_error, {"t.obj:5:"}, "t.obj");
  expect_error(base + "t interpolateboundary 1/0/0 0\n", FileFormat::obj, Status::parse_error,
               {"t.obj:5:", "not supported"}, "t.obj");
  expect_error(base + "t interpolateboundary 1/0/0 3\n", FileFormat::obj, Status::parse_error, {"t.obj:5:", "3"},
               "t.obj");
  expect_error(base + "t crease 3/1/0 0 1 2 1\n", FileFormat::obj, Status::parse_error, {"t.obj:5:"}, "t.obj");
  expect_error(base + "t crease 2/2/0 0 1 1 2\n", FileFormat::obj, Status::parse_error, {"t.obj:5:"}, "t.obj");
  expect_error(base + "t crease 2/1/0 0 1 nan\n", FileFormat::obj, Status::parse_error, {"t.obj:5:"}, "t.obj");
  expect_error(base + "t crease 2/1/0 0 1\n", FileFormat::obj, Status::parse_error, {"t.obj:5:"}, "t.obj");
  expect_error(base + "t crease 2/1/0 0 1 1 extra\n", FileFormat::obj, Status::parse_error, {"t.obj:5:"}, "t.obj");
  expect_error(base + "t crease two/1/0 0 1 1\n", FileFormat::obj, Status::parse_error, {"t.obj:5:"}, "t.obj");
  expect_error(cube + "t crease 2/1/0 0 8 1\n", FileFormat::obj, Status::parse_error, {"vertex 8"}, "t.obj");
}

TEST(io_bad_input, EmptyGarbageAndBinaryInput) {
  for (FileFormat f : {FileFormat::obj, FileFormat::ply, FileFormat::off, FileFormat::draco})
    expect_error(std::vector<uint8_t>{}, f, Status::parse_error, {"no vertices"}, "empty");
  expect_error("# only a comment\nvt 0 0\n", FileFormat::obj, Status::parse_error, {"no vertices"}, "c.obj");
  expect_error("v 0 0 0\nv 1 0 0\n", FileFormat::obj, Status::parse_error, {"no faces"}, "c.obj");
  expect_error("hello world\n", FileFormat::ply, Status::parse_error, {"g.ply:1:"}, "g.ply");
  expect_error("ply\nformat ascii 2.0\nend_header\n", FileFormat::ply, Status::parse_error, {"g.ply:2:"}, "g.ply");
  expect_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", FileFormat::ply, Status::parse_error,
               {"end_header"}, "g.ply");
  expect_error("hello world\n", FileFormat::off, Status::parse_error, {"g.off:1:", "OFF"}, "g.off");
  expect_error("4OFF\n1 1 0\n", FileFormat::off, Status::unsupported_format, {"g.off:1:"}, "g.off");
  expect_error("hello world\n", FileFormat::draco, Status::parse_error, {"Draco"}, "g.drc");
  expect_error("hello world\n", FileFormat::unknown, Status::unsupported_format, {}, "g.bin");
  std::mt19937 rng(7);
  std::vector<uint8_t> noise(4096);
  for (uint8_t& b : noise) b = uint8_t(rng());
  noise[100] = 0;
  for (FileFormat f : {FileFormat::obj, FileFormat::ply, FileFormat::off, FileFormat::draco}) {
    const Outcome out = try_read(noise, f, "noise");
    ASSERT_FALSE(out.ok) << file_format_name(f);
    EXPECT_EQ(out.message.rfind("noise", 0), 0u) << out.message;
  }
  expect_error(noise, FileFormat::obj, Status::parse_error, {"NUL"}, "noise");
}

TEST(io_bad_input, DracoPointCloudsAndBrokenCageKitData) {
  draco::PointCloud cloud;
  cloud.set_num_points(3);
  draco::GeometryAttribute position;
  position.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, 12, 0);
  draco::PointAttribute* pos = cloud.attribute(cloud.AddAttribute(position, true, 3));
  const float xyz[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (uint32_t v = 0; v < 3; ++v) pos->SetAttributeValue(draco::AttributeValueIndex(v), xyz[v]);
  draco::Encoder encoder;
  draco::EncoderBuffer buffer;
  ASSERT_TRUE(encoder.EncodePointCloudToBuffer(cloud, &buffer).ok());
  expect_error(std::vector<uint8_t>(buffer.data(), buffer.data() + buffer.size()), FileFormat::draco,
               Status::parse_error, {"not a mesh"}, "cloud.drc");

  // A triangle with CageKit metadata that lies: bad layout version, bad order blob, no ids,
  // more vertices than points, non-finite isolated vertices.
  auto encode = [&](int version, const std::vector<uint8_t>& blob, bool with_ids = false,
                    const std::vector<double>& isolated = {}) {
    draco::Mesh mesh;
    mesh.set_num_points(3);
    draco::PointAttribute* p = mesh.attribute(mesh.AddAttribute(position, true, 3));
    for (uint32_t v = 0; v < 3; ++v) p->SetAttributeValue(draco::AttributeValueIndex(v), xyz[v]);
    if (with_ids) {
      draco::GeometryAttribute id;
      id.Init(draco::GeometryAttribute::GENERIC, nullptr, 1, draco::DT_UINT32, false, 4, 0);
      const int att = mesh.AddAttribute(id, true, 3);
      for (uint32_t v = 0; v < 3; ++v) mesh.attribute(att)->SetAttributeValue(draco::AttributeValueIndex(v), &v);
      auto name = std::make_unique<draco::AttributeMetadata>();
      name->AddEntryString("name", "cagekit_vertex_id");
      mesh.AddAttributeMetadata(att, std::move(name));
    }
    mesh.AddFace({draco::PointIndex(0), draco::PointIndex(1), draco::PointIndex(2)});
    auto md = std::make_unique<draco::GeometryMetadata>();
    md->AddEntryInt("cagekit.version", version);
    md->AddEntryBinary("cagekit.order", blob);
    if (!isolated.empty()) md->AddEntryDoubleArray("cagekit.isolated_positions", isolated);
    if (with_ids) {
      mesh.metadata()->AddEntryInt("cagekit.version", version);
      mesh.metadata()->AddEntryBinary("cagekit.order", blob);
      if (!isolated.empty()) mesh.metadata()->AddEntryDoubleArray("cagekit.isolated_positions", isolated);
    } else {
      mesh.AddMetadata(std::move(md));
    }
    draco::Encoder e;
    e.SetEncodingMethod(draco::MESH_SEQUENTIAL_ENCODING);  // keeps the point order of this test
    draco::EncoderBuffer b;
    EXPECT_TRUE(e.EncodeMeshToBuffer(mesh, &b).ok());
    return std::vector<uint8_t>(b.data(), b.data() + b.size());
  };
  // Blob: version 1, num_vertices, num_faces, num_triangles, flags.
  EXPECT_EQ(read_cage_from_memory(encode(1, {1, 3, 1, 1, 0}, true).data(), encode(1, {1, 3, 1, 1, 0}, true).size(),
                                  FileFormat::draco, "ok.drc")
                .mesh.num_faces(),
            1u);
  expect_error(encode(2, {1, 3, 1, 1, 0}), FileFormat::draco, Status::version_mismatch, {"version"}, "v.drc");
  expect_error(encode(1, {9, 9, 9}), FileFormat::draco, Status::parse_error, {"cagekit.order"}, "v.drc");
  expect_error(encode(1, {1, 3, 1, 5, 0}), FileFormat::draco, Status::parse_error, {"does not match"}, "v.drc");
  expect_error(encode(1, {1, 3, 1, 1, 0}), FileFormat::draco, Status::parse_error, {"vertex id"}, "v.drc");
  expect_error(encode(1, {1, 0xFF, 0xFF, 0x7F, 1, 1, 0}, true), FileFormat::draco, Status::parse_error,
               {"more vertices than"}, "v.drc");
  expect_error(encode(1, {1, 4, 1, 1, 0}, true), FileFormat::draco, Status::parse_error, {"more vertices than"},
               "v.drc");
  expect_error(encode(1, {1, 4, 1, 1, 0}, true, {0, NAN, 0}), FileFormat::draco, Status::parse_error,
               {"not finite"}, "v.drc");
  expect_error(encode(1, {1, 4, 1, 1, 0}, true, {0, 0, 0, 1}), FileFormat::draco, Status::parse_error,
               {"isolated_positions"}, "v.drc");
  EXPECT_EQ(read_cage_from_memory(encode(1, {1, 4, 1, 1, 0}, true, {5, 6, 7}).data(),
                                  encode(1, {1, 4, 1, 1, 0}, true, {5, 6, 7}).size(), FileFormat::draco, "ok.drc")
                .mesh.positions[3],
            Vec3(5, 6, 7));
}

// libdraco reserves arrays from the counts a stream declares before it checks them; the reader
// checks them against ReadOptions and the memory budget first (CI's fuzz_draco found a 206-byte
// stream declaring 1.18e9 triangles that made libdraco reserve 4.7 GB).
TEST(io_bad_input, DracoDeclaredCountsAreCheckedBeforeDecoding) {
  // The fuzzer's stream: bitstream 1.0, edgebreaker (valence), 0x46464646 triangles.
  const char* hex =
      "445241434f01000101020102800104" "6e4646464646464646464646464646464646464646464646464646464646464646"
      "4646464646464646464646464646464646464646464646464646464646464646464646616d65116361676b69745f76"
      "65727465785f6964000810";
  std::vector<uint8_t> hostile;
  for (const char* c = hex; c[0] && c[1]; c += 2) hostile.push_back(uint8_t(std::stoul(std::string(c, 2), nullptr, 16)));
  ASSERT_EQ(hostile[15], 0x6e);
  ReadOptions fuzz_limits;
  fuzz_limits.max_vertices = fuzz_limits.max_faces = 1u << 20;
  expect_error(hostile, FileFormat::draco, Status::limit_exceeded, {"declares 1179010630 triangles", "max_faces"},
               "oom.drc", fuzz_limits);
  expect_error(hostile, FileFormat::draco, Status::limit_exceeded, {"declares 1179010630 triangles"}, "oom.drc");
  // Under the limit but over the memory budget: refused before libdraco allocates.
  std::vector<uint8_t> big = hostile;
  const uint32_t triangles = 1u << 27, vertices = 3;
  for (int k = 0; k < 4; ++k) {  // bytes 24..32: attribute data, symbols, split symbols
    big[16 + k] = uint8_t(vertices >> (8 * k));
    big[20 + k] = uint8_t(triangles >> (8 * k));
    big[29 + k] = 0;
  }
  {
    const ScopedMemoryBudget budget(uint64_t(1) << 30);
    expect_error(big, FileFormat::draco, Status::out_of_memory, {"decoding the Draco stream"}, "big.drc");
  }
  // More vertices than triangles can carry.
  std::vector<uint8_t> many_vertices = hostile;
  for (int k = 0; k < 4; ++k) {
    many_vertices[16 + k] = uint8_t(0x7fffffffu >> (8 * k));
    many_vertices[20 + k] = uint8_t(1u >> (8 * k));
  }
  expect_error(many_vertices, FileFormat::draco, Status::parse_error, {"vertices for 1 triangles", "more than the 4 "},
               "v.drc", fuzz_limits);

  // Real streams of both connectivity encodings: the declared count is the triangle count, so a
  // limit of exactly that count reads and one less is refused before decoding.
  draco::Mesh mesh;
  const int n = 6;  // (n+1)^2 points, 2 n^2 triangles
  mesh.set_num_points((n + 1) * (n + 1));
  draco::GeometryAttribute position;
  position.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, 12, 0);
  draco::PointAttribute* pos = mesh.attribute(mesh.AddAttribute(position, true, (n + 1) * (n + 1)));
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const float xyz[3] = {float(i), float(j), float((i * j) % 3)};
      pos->SetAttributeValue(draco::AttributeValueIndex(j * (n + 1) + i), xyz);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      mesh.AddFace({draco::PointIndex(a), draco::PointIndex(b), draco::PointIndex(d)});
      mesh.AddFace({draco::PointIndex(a), draco::PointIndex(d), draco::PointIndex(c)});
    }
  for (draco::MeshEncoderMethod method : {draco::MESH_SEQUENTIAL_ENCODING, draco::MESH_EDGEBREAKER_ENCODING}) {
    draco::Encoder e;
    e.SetEncodingMethod(method);
    draco::EncoderBuffer b;
    ASSERT_TRUE(e.EncodeMeshToBuffer(mesh, &b).ok());
    const std::vector<uint8_t> bytes(b.data(), b.data() + b.size());
    ReadOptions exact;
    exact.max_faces = 2 * n * n;
    const Outcome ok = try_read(bytes, FileFormat::draco, "grid.drc", exact);
    ASSERT_TRUE(ok.ok) << ok.message;
    ReadOptions one_less;
    one_less.max_faces = 2 * n * n - 1;
    expect_error(bytes, FileFormat::draco, Status::limit_exceeded, {"declares 72 triangles"}, "grid.drc", one_less);
  }
}

TEST(io_bad_input, UnreadableFilesAreIoErrors) {
  try {
    read_cage_from_file("/nonexistent/dir/mesh.obj");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), Status::io_error);
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/mesh.obj"), std::string::npos);
  }
  try {
    read_cage_from_file(CAGEKIT_BINARY_DIR);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), Status::io_error);
  }
}

// fuzz_draco finding (tests/fuzz/regressions/fuzz_draco/bool-positions-ubsan): a Draco stream
// whose position attribute is declared bool made Draco load arbitrary bytes as bool (undefined
// behaviour). Non-numeric positions are now a parse error before Draco converts anything.
TEST(io_bad_input, DracoBoolPositionsAreRejected) {
  const std::vector<uint8_t> stream = {
      68, 82, 65, 67, 79, 2, 2, 1, 1, 0, 128, 1, 1, 1, 4, 110, 97, 109, 101, 17, 0, 8, 0, 3, 7, 1, 64, 1, 0, 14, 8,
      0, 2, 3, 1, 64, 1, 0, 1, 15, 99, 97, 103, 101, 107, 105, 116, 46, 118, 101, 114, 115, 105, 140, 145, 4, 1, 0,
      0, 0, 0, 0, 4, 2, 1, 2, 0, 0, 1, 31, 255, 1, 17, 239, 1, 17, 2, 255, 0, 0, 0, 0, 0, 1, 0, 11, 3, 0, 8, 0, 1,
      4, 6, 1, 9, 1, 1, 1, 1, 1, 0, 0, 246, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 97, 103, 101, 107, 105,
      116, 46, 98, 111, 117, 110, 100, 97, 114, 121, 4, 0, 0, 0, 0, 24, 99, 97, 103, 101, 107, 105, 116, 46, 99,
      111, 114, 110, 101, 114, 95, 115, 104, 97, 114, 112, 115, 0, 101, 110, 16, 115, 0, 0, 0, 0, 0, 36, 64, 0, 0,
      0, 0, 0, 0, 8, 64, 23, 99, 97, 103, 101, 107, 105, 116, 46, 99, 111, 114, 110, 101, 132, 160, 137, 154, 114,
      116, 105, 99, 101, 115, 8, 0, 0, 0, 0, 7, 0, 0, 0, 24, 99, 97, 103, 101, 107, 105, 116, 46, 99, 114, 101, 97,
      115, 101, 95, 115, 104, 97, 114, 112, 0, 0, 0, 0, 0, 0, 4, 2, 1, 2, 0, 0, 1, 31, 0, 3, 0, 0, 0};
  const Outcome out = try_read(stream, FileFormat::draco, "bool.drc");
  EXPECT_FALSE(out.ok);
  EXPECT_EQ(out.status, Status::parse_error) << out.message;
  EXPECT_NE(out.message.find("non-numeric"), std::string::npos) << out.message;
}
