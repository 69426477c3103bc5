// SPDX-License-Identifier: GPL-3.0-or-later
// PLY triangle strips (element tristrips, list vertex_indices, -1 between strips): the exact
// triangles with alternating winding, degenerate swaps dropped, consistently oriented; together
// with a face element; ascii and binary with signed and unsigned index types; hostile input.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "core/io/mesh_io.h"
#include "core/mesh_validation.h"
#include "test_support.h"

using namespace cagekit;

namespace {

// A 3 x 3 grid of vertices (rows y = 0, 1, 2) and one more vertex right of the first row:
//   6 7 8
//   3 4 5
//   0 1 2 9
const double kGrid[10][3] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0},
                             {2, 1, 0}, {0, 2, 0}, {1, 2, 0}, {2, 2, 0}, {3, 0, 0}};

// Two strips: the bottom row as two strips of two triangles joined by the degenerate triangles of
// "1 1 4 4" (parity kept), then -1 and the top row.
const std::vector<int64_t> kStrips = {3, 0, 4, 1, 1, 4, 4, 1, 5, 2, -1, 6, 3, 7, 4, 8, 5};
// Triangle k of a strip: (s_k, s_k+1, s_k+2) for even k, (s_k+1, s_k, s_k+2) for odd k.
const std::vector<uint32_t> kStripTriangles = {3, 0, 4, 4, 0, 1, 4, 1, 5, 5, 1, 2,
                                               6, 3, 7, 7, 3, 4, 7, 4, 8, 8, 4, 5};

Cage read_bytes(const std::vector<uint8_t>& bytes, const std::string& name = "strips.ply",
                const ReadOptions& options = {}) {
  return read_cage_from_memory(bytes.data(), bytes.size(), FileFormat::ply, name, options);
}

std::vector<uint8_t> bytes_of(const std::string& text) { return std::vector<uint8_t>(text.begin(), text.end()); }

std::string ascii_ply(int vertices, const std::vector<int64_t>& strip, const std::string& face_element = "") {
  std::string s = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(vertices) +
                  "\nproperty float x\nproperty float y\nproperty float z\n" + face_element +
                  "element tristrips 1\nproperty list int int vertex_indices\nend_header\n";
  for (int v = 0; v < vertices; ++v)
    s += std::to_string(int(kGrid[v][0])) + " " + std::to_string(int(kGrid[v][1])) + " 0\n";
  s += std::to_string(strip.size());
  for (int64_t i : strip) s += " " + std::to_string(i);
  return s + "\n";
}

void put_le(std::vector<uint8_t>& out, uint64_t v, int n) {
  for (int i = 0; i < n; ++i) out.push_back(uint8_t(v >> (8 * i)));
}

// Binary little endian: double x y z, a face element with the triangle (2, 9, 5) first, then the
// strips as `list ushort uint` (unsigned: -1 is stored as 0xFFFFFFFF) with a uchar property before.
std::vector<uint8_t> binary_ply(const std::vector<int64_t>& strip, uint64_t declared_length = ~uint64_t(0)) {
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 10\nproperty double x\nproperty double y\n"
      "property double z\nelement face 1\nproperty list uchar int vertex_indices\n"
      "element tristrips 1\nproperty uchar flags\nproperty list ushort uint vertex_indices\nend_header\n";
  std::vector<uint8_t> out(header.begin(), header.end());
  for (const auto& p : kGrid)
    for (double c : p) {
      uint64_t u;
      std::memcpy(&u, &c, 8);
      put_le(out, u, 8);
    }
  out.push_back(3);
  for (uint32_t v : {2u, 9u, 5u}) put_le(out, v, 4);
  out.push_back(0x5A);
  put_le(out, declared_length == ~uint64_t(0) ? strip.size() : declared_length, 2);
  for (int64_t i : strip) put_le(out, uint64_t(i), 4);
  return out;
}

void expect_clean_orientation(const PolygonMesh& mesh) {
  const ValidationReport report = validate_mesh(mesh);
  EXPECT_TRUE(report.ok()) << report.summary();
  EXPECT_EQ(report.count(MeshIssue::inconsistent_orientation), 0u);
  EXPECT_EQ(report.count(MeshIssue::degenerate_face), 0u);
  for (size_t f = 0; f < mesh.num_faces(); ++f) EXPECT_GT(mesh.face_vector_area(f).z, 0) << "face " << f;
}

Status status_of_read(const std::vector<uint8_t>& bytes, std::string* message, const ReadOptions& options = {}) {
  try {
    read_bytes(bytes, "bad.ply", options);
  } catch (const Error& e) {
    *message = e.what();
    return e.status();
  }
  return Status::success;
}

void expect_error(const std::vector<uint8_t>& bytes, Status status, std::initializer_list<const char*> fragments,
                  const ReadOptions& options = {}) {
  std::string message;
  EXPECT_EQ(status_of_read(bytes, &message, options), status) << message;
  EXPECT_EQ(message.rfind("bad.ply", 0), 0u) << message;
  for (const char* fragment : fragments) EXPECT_NE(message.find(fragment), std::string::npos) << message;
}

}  // namespace

TEST(ply_tristrips, AsciiStripsWithRestartAndDegenerateSwap) {
  const Cage cage = read_bytes(bytes_of(ascii_ply(9, kStrips)));
  ASSERT_EQ(cage.mesh.num_vertices(), 9u);
  ASSERT_EQ(cage.mesh.num_faces(), 8u);
  EXPECT_TRUE(cage.mesh.all_faces_have_size(3));
  EXPECT_EQ(cage.mesh.face_vertices, kStripTriangles);
  expect_clean_orientation(cage.mesh);
  EXPECT_EQ(cage.mesh.positions[8], Vec3(2, 2, 0));
}

TEST(ply_tristrips, BinaryUnsignedIndicesWithAFaceElement) {
  std::vector<int64_t> strip = kStrips;
  for (int64_t& i : strip)
    if (i == -1) i = 0xFFFFFFFF;
  const Cage cage = read_bytes(binary_ply(strip));
  ASSERT_EQ(cage.mesh.num_vertices(), 10u);
  ASSERT_EQ(cage.mesh.num_faces(), 9u);
  std::vector<uint32_t> expected = {2, 9, 5};
  expected.insert(expected.end(), kStripTriangles.begin(), kStripTriangles.end());
  EXPECT_EQ(cage.mesh.face_vertices, expected);
  expect_clean_orientation(cage.mesh);
}

TEST(ply_tristrips, EdgeCasesOfStrips) {
  // Empty strips, strips of one or two indices, repeated separators: no triangles from them.
  const Cage cage = read_bytes(bytes_of(ascii_ply(9, {-1, 0, -1, 0, 1, -1, -1, 3, 0, 4, -1})));
  EXPECT_EQ(cage.mesh.face_vertices, (std::vector<uint32_t>{3, 0, 4}));
  // A strip of degenerate triangles only: no faces.
  std::string message;
  EXPECT_EQ(status_of_read(bytes_of(ascii_ply(9, {0, 0, 1, 1})), &message), Status::parse_error);
  EXPECT_NE(message.find("no faces"), std::string::npos) << message;
  // Several strip entries in one element.
  const std::string two = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                          "property float z\nelement tristrips 2\nproperty list uchar int vertex_indices\n"
                          "end_header\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 3 2\n";
  EXPECT_EQ(read_bytes(bytes_of(two)).mesh.face_vertices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));
}

TEST(ply_tristrips, HostileInput) {
  expect_error(bytes_of(ascii_ply(9, {0, 1, 9})), Status::parse_error, {"bad.ply:", "vertex 9", "9 vertices"});
  expect_error(bytes_of(ascii_ply(9, {0, 1, -2})), Status::parse_error, {"bad.ply:", "vertex -2"});
  std::string bad_list = ascii_ply(9, {0, 1, 2});
  bad_list.replace(bad_list.rfind("3 0 1 2"), 7, "9 0 1 2");
  expect_error(bytes_of(bad_list), Status::parse_error, {"bad.ply:", "tristrips 0"});
  // A 65535-index list in a file that holds 3: refused before reading on.
  expect_error(binary_ply({0, 1, 2}, 0xFFFF), Status::parse_error, {"byte", "65535", "ends first"});
  // More triangles than ReadOptions allow.
  ReadOptions few;
  few.max_faces = 3;
  expect_error(bytes_of(ascii_ply(9, kStrips)), Status::limit_exceeded, {"bad.ply:", "max_faces"}, few);
  few.max_faces = 8;
  EXPECT_EQ(read_bytes(bytes_of(ascii_ply(9, kStrips)), "ok.ply", few).mesh.num_faces(), 8u);
  // Header problems.
  expect_error(bytes_of("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                        "property float z\nend_header\n0 0 0\n"),
               Status::parse_error, {"no 'element face' or 'element tristrips'"});
  expect_error(bytes_of("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                        "property float z\nelement tristrips 1\nproperty list int int strip\nend_header\n0 0 0\n"),
               Status::parse_error, {"bad.ply:7:", "tristrips", "vertex_indices"});
  expect_error(bytes_of("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                        "property float z\nelement tristrips 1\nproperty float vertex_indices\nend_header\n0 0 0\n"),
               Status::parse_error, {"bad.ply:7:", "list of integers"});
  // Every truncation of the binary file is an error.
  const std::vector<uint8_t> whole = binary_ply(kStrips);
  for (size_t length = 0; length < whole.size(); ++length) {
    std::string message;
    ASSERT_NE(status_of_read(std::vector<uint8_t>(whole.begin(), whole.begin() + long(length)), &message),
              Status::success)
        << length;
    ASSERT_EQ(message.rfind("bad.ply", 0), 0u) << message;
  }
}
