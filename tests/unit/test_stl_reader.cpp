// SPDX-License-Identifier: GPL-3.0-or-later
// The STL reader: binary and ascii files written here from generated closed meshes read back
// welded (the original vertex and face counts, exactly the written positions), binary files
// whose header starts with "solid", format detection, and hostile input (truncation at every
// byte, hostile triangle counts, limits, NaN/Inf, malformed ascii structure, NUL bytes, random
// corruption). The corpus STL files (../shared/corpus/stl) must read as welded meshes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "core/io/mesh_io.h"
#include "core/mesh_validation.h"
#include "test_support.h"

using namespace cagekit;

namespace {

using Outcome = cagekit_test::ReadOutcome;
using cagekit_test::bytes_of;

Outcome try_read(const std::vector<uint8_t>& bytes, const std::string& name = "bad.stl",
                 FileFormat format = FileFormat::stl, const ReadOptions& options = {}) {
  return cagekit_test::try_read_memory(bytes, format, name, options);
}

// The error must carry the status, start with the source name and contain every fragment.
void expect_error(const std::vector<uint8_t>& bytes, Status status, std::initializer_list<const char*> fragments,
                  const ReadOptions& options = {}) {
  const Outcome out = try_read(bytes, "bad.stl", FileFormat::stl, options);
  ASSERT_FALSE(out.ok) << "accepted: " << std::string(bytes.begin(), bytes.begin() + std::min<size_t>(bytes.size(), 300));
  EXPECT_EQ(out.status, status) << out.message;
  EXPECT_EQ(out.message.rfind("bad.stl", 0), 0u) << out.message;
  for (const char* fragment : fragments) EXPECT_NE(out.message.find(fragment), std::string::npos) << out.message;
}

void expect_error(const std::string& text, Status status, std::initializer_list<const char*> fragments,
                  const ReadOptions& options = {}) {
  expect_error(bytes_of(text), status, fragments, options);
}

void put_le(std::vector<uint8_t>& out, uint64_t v, int n) {
  for (int i = 0; i < n; ++i) out.push_back(uint8_t(v >> (8 * i)));
}

void put_float(std::vector<uint8_t>& out, float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  put_le(out, u, 4);
}

// `d` rounded to float. Through a volatile: GCC 12.2's SLP vectorizer drops the rounding of
// `p = Vec3(float(p.x), float(p.y), float(p.z))` for x and y in a loop (wrong code at -O2/-O3;
// only z was rounded), which this test found.
double to_float(double d) {
  volatile float f = float(d);
  return f;
}

// A closed triangle mesh whose positions are exactly representable as floats (binary STL).
PolygonMesh float_sphere(int levels) {
  PolygonMesh m = cagekit_test::triangle_sphere(levels);
  for (Vec3& p : m.positions) p = Vec3(to_float(p.x), to_float(p.y), to_float(p.z));
  return m;
}

// Binary STL of a triangle mesh: `header` (padded with spaces to 80 bytes), the count, then per
// triangle a normal (here a constant; readers ignore it), the corners and the attribute word.
std::vector<uint8_t> binary_stl(const PolygonMesh& m, const std::string& header = "binary STL written by a test") {
  std::vector<uint8_t> out(header.begin(), header.end());
  out.resize(80, ' ');
  put_le(out, m.num_faces(), 4);
  for (size_t f = 0; f < m.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) put_float(out, k == 2 ? 1.0f : 0.0f);
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = m.positions[m.face_vertex(f, k)];
      put_float(out, float(p.x));
      put_float(out, float(p.y));
      put_float(out, float(p.z));
    }
    put_le(out, 0x1234, 2);
  }
  return out;
}

// Ascii STL with 17 significant digits (exact doubles); `upper` writes the keywords in capitals
// with CRLF line ends and tabs, as some exporters do.
std::string ascii_stl(const PolygonMesh& m, bool upper = false, const std::string& name = "test part") {
  auto kw = [upper](std::string s) {
    if (upper)
      for (char& c : s) c = char(std::toupper(static_cast<unsigned char>(c)));
    return s;
  };
  const char* nl = upper ? "\r\n" : "\n";
  std::ostringstream out;
  out.precision(17);
  out << kw("solid") << " " << name << nl;
  for (size_t f = 0; f < m.num_faces(); ++f) {
    out << (upper ? "\t" : "  ") << kw("facet normal") << " 0 0 1" << nl << "    " << kw("outer loop") << nl;
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = m.positions[m.face_vertex(f, k)];
      out << (upper ? "\t\t" : "      ") << kw("vertex") << " " << p.x << " " << p.y << " " << p.z << nl;
    }
    out << "    " << kw("endloop") << nl << "  " << kw("endfacet") << nl;
  }
  out << kw("endsolid") << " " << name << nl;
  return out.str();
}

// The read mesh has the original's vertex and face counts and, face by face and corner by
// corner, exactly the original positions; it validates clean (closed, consistently oriented).
void expect_same_mesh(const PolygonMesh& original, const PolygonMesh& read) {
  ASSERT_EQ(read.num_faces(), original.num_faces());
  ASSERT_EQ(read.num_vertices(), original.num_vertices()) << "corners were not welded";
  ASSERT_TRUE(read.all_faces_have_size(3));
  for (size_t f = 0; f < original.num_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(read.positions[read.face_vertex(f, k)], original.positions[original.face_vertex(f, k)])
          << "face " << f << " corner " << k;
  const ValidationReport report = validate_mesh(read);
  EXPECT_TRUE(report.ok()) << report.summary();
  EXPECT_EQ(report.count(MeshIssue::inconsistent_orientation), 0u);
  EXPECT_EQ(report.count(MeshIssue::unreferenced_vertex), 0u);
}

const char* kTriangle =
    "solid t\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n endloop\n"
    "endfacet\nendsolid t\n";

// kTriangle with line `line` (1-based) replaced.
std::string triangle_with_line(int line, const std::string& replacement) {
  std::istringstream in(kTriangle);
  std::string out, l;
  for (int n = 1; std::getline(in, l); ++n) out += (n == line ? replacement : l) + "\n";
  return out;
}

}  // namespace

TEST(stl_reader, BinaryReadsBackWeldedWithExactPositions) {
  const PolygonMesh sphere = float_sphere(2);  // 66 vertices, 128 triangles
  const std::vector<uint8_t> bytes = binary_stl(sphere);
  ASSERT_EQ(bytes.size(), 84 + 50 * sphere.num_faces());
  for (FileFormat f : {FileFormat::stl, FileFormat::unknown}) {
    const Outcome out = try_read(bytes, "sphere.stl", f);
    ASSERT_TRUE(out.ok) << out.message;
    expect_same_mesh(sphere, out.cage.mesh);
    EXPECT_FALSE(out.cage.has_tags());
  }
  // Vertices are numbered in order of first appearance in the file.
  const Outcome out = try_read(bytes);
  EXPECT_EQ(out.cage.mesh.face_vertices[0], 0u);
  EXPECT_EQ(out.cage.mesh.face_vertices[1], 1u);
  EXPECT_EQ(out.cage.mesh.face_vertices[2], 2u);
}

TEST(stl_reader, BinaryWhoseHeaderStartsWithSolidIsBinary) {
  const PolygonMesh sphere = float_sphere(1);
  for (const char* header : {"solid sphere", "solid", "SOLID facet normal outer loop vertex"}) {
    const std::vector<uint8_t> bytes = binary_stl(sphere, header);
    EXPECT_EQ(sniff_file_format(bytes.data(), bytes.size()), FileFormat::stl) << header;
    const Outcome out = try_read(bytes, "solid.stl", FileFormat::unknown);
    ASSERT_TRUE(out.ok) << header << ": " << out.message;
    expect_same_mesh(sphere, out.cage.mesh);
  }
  // Header padded with NUL bytes instead of spaces, as many exporters do.
  std::vector<uint8_t> bytes = binary_stl(sphere, "solid x");
  std::fill(bytes.begin() + 7, bytes.begin() + 80, uint8_t(0));
  const Outcome out = try_read(bytes, "nul.stl", FileFormat::unknown);
  ASSERT_TRUE(out.ok) << out.message;
  expect_same_mesh(sphere, out.cage.mesh);
}

TEST(stl_reader, AsciiReadsBackWeldedWithExactPositions) {
  const PolygonMesh sphere = cagekit_test::triangle_sphere(2);  // full double precision
  for (bool upper : {false, true}) {
    const std::string text = ascii_stl(sphere, upper);
    EXPECT_EQ(sniff_file_format(reinterpret_cast<const uint8_t*>(text.data()), text.size()), FileFormat::stl);
    const Outcome out = try_read(bytes_of(text), "sphere.stl", FileFormat::unknown);
    ASSERT_TRUE(out.ok) << out.message;
    expect_same_mesh(sphere, out.cage.mesh);
  }
}

TEST(stl_reader, AsciiSyntaxVariants) {
  // Two solids, no names, tokens split over lines, a '+' sign, exponents, leading blank lines.
  const std::string text =
      "\n\nsolid\nfacet normal 0 0 1 outer loop vertex 0 0 0\nvertex +1e0 0 0\nvertex\n0\n1\n0\nendloop endfacet\n"
      "endsolid\nsolid second one\n  facet normal nan nan nan\n outer loop\n vertex 1 0 0\n vertex 1 1 0\n"
      " vertex 0 1 0\n endloop\n endfacet\nendsolid second one\n";
  const Outcome out = try_read(bytes_of(text));
  ASSERT_TRUE(out.ok) << out.message;
  const PolygonMesh& m = out.cage.mesh;
  ASSERT_EQ(m.num_faces(), 2u);
  ASSERT_EQ(m.num_vertices(), 4u);
  EXPECT_EQ(m.face_vertices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));
  EXPECT_EQ(m.positions[3], Vec3(1, 1, 0));
  // -0 and +0 are the same position: one vertex (the first one written is kept).
  const Outcome zero = try_read(bytes_of(
      "solid z\nfacet normal 0 0 1\nouter loop\nvertex -0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
      "facet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 0 -0.0 0\nvertex 1 1 0\nendloop\nendfacet\nendsolid z\n"));
  ASSERT_TRUE(zero.ok) << zero.message;
  EXPECT_EQ(zero.cage.mesh.num_vertices(), 4u);
  EXPECT_TRUE(std::signbit(zero.cage.mesh.positions[0].x));
}

TEST(stl_reader, FormatNamesExtensionsAndSniffing) {
  EXPECT_EQ(file_format_from_path("scan.stl"), FileFormat::stl);
  EXPECT_EQ(file_format_from_path("dir/SCAN.STL"), FileFormat::stl);
  EXPECT_EQ(file_format_from_path("x.Stl"), FileFormat::stl);
  EXPECT_STREQ(file_format_name(FileFormat::stl), "STL");
  EXPECT_FALSE(format_keeps_tags(FileFormat::stl));
  const std::string tri = kTriangle;
  EXPECT_EQ(sniff_file_format(reinterpret_cast<const uint8_t*>(tri.data()), tri.size()), FileFormat::stl);
  const std::string words = "solid objects are not STL files\n";
  EXPECT_EQ(sniff_file_format(reinterpret_cast<const uint8_t*>(words.data()), words.size()), FileFormat::unknown);
  // One byte more or less than the size rule: not recognised as binary STL.
  std::vector<uint8_t> bytes = binary_stl(float_sphere(0), "");
  std::fill(bytes.begin(), bytes.begin() + 80, uint8_t(0));
  EXPECT_EQ(sniff_file_format(bytes.data(), bytes.size()), FileFormat::stl);
  bytes.push_back(0);
  EXPECT_EQ(sniff_file_format(bytes.data(), bytes.size()), FileFormat::unknown);
  bytes.resize(bytes.size() - 2);
  EXPECT_EQ(sniff_file_format(bytes.data(), bytes.size()), FileFormat::unknown);
}

TEST(stl_reader, WritingIsRefused) {
  Cage cube;
  cube.mesh = cagekit_test::unit_cube_quads();
  WriteOptions options;
  options.format = FileFormat::stl;
  try {
    write_cage_to_memory(cube, options);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), Status::unsupported_format);
    EXPECT_NE(std::string(e.what()).find("STL: writing is not supported"), std::string::npos) << e.what();
  }
  const std::string path = std::string(CAGEKIT_BINARY_DIR) + "/stl_reader_refused.stl";
  EXPECT_EQ(cagekit_test::status_of([&] { write_cage_to_file(path, cube, {}); }), Status::unsupported_format);
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(stl_reader, EveryTruncationIsAnError) {
  const std::vector<uint8_t> binary = binary_stl(float_sphere(0), "solid but binary");
  for (size_t length = 0; length < binary.size(); ++length) {
    const Outcome out = try_read(std::vector<uint8_t>(binary.begin(), binary.begin() + long(length)));
    ASSERT_FALSE(out.ok) << "binary prefix of " << length << " bytes accepted";
    ASSERT_EQ(out.message.rfind("bad.stl", 0), 0u) << out.message;
  }
  // Ascii: every prefix fails, except those that cut only the name after the last "endsolid".
  const std::string text = ascii_stl(float_sphere(0));
  const size_t last = text.rfind("endsolid") + std::strlen("endsolid");
  for (size_t length = 0; length < text.size(); ++length) {
    const Outcome out = try_read(bytes_of(text.substr(0, length)));
    if (out.ok) {
      ASSERT_GE(length, last) << "ascii prefix of " << length << " bytes accepted";
      EXPECT_EQ(out.cage.mesh.num_faces(), 8u);
      continue;
    }
    ASSERT_NE(out.status, Status::success);
    ASSERT_EQ(out.message.rfind("bad.stl", 0), 0u) << out.message;
  }
}

TEST(stl_reader, HostileBinaryCountsFailBeforeAllocating) {
  std::vector<uint8_t> bytes(80, uint8_t(' '));
  put_le(bytes, 0xFFFFFFFFu, 4);  // 4 billion triangles in an 84-byte file
  expect_error(bytes, Status::parse_error, {"byte 80", "4294967295", "214748364834", "84 bytes"});
  // The same with a header starting with "solid" is read as ascii, fails there, and names both.
  std::vector<uint8_t> solid = bytes;
  std::memcpy(solid.data(), "solid", 5);
  solid[10] = 0;
  expect_error(solid, Status::parse_error, {"NUL", "4294967295"});
  // One triangle declared, two present; two declared, one present.
  const PolygonMesh sphere = float_sphere(0);
  std::vector<uint8_t> more = binary_stl(sphere);
  more[80] = 7;
  expect_error(more, Status::parse_error, {"byte 80", "declares 7 triangles", "434 bytes", "484 bytes"});
  more[80] = 9;
  expect_error(more, Status::parse_error, {"declares 9 triangles", "534 bytes"});
  expect_error(std::vector<uint8_t>(83, uint8_t('x')), Status::parse_error, {"83 bytes", "84"});
  // Counts that fit the bytes but exceed ReadOptions.
  ReadOptions few;
  few.max_faces = 7;
  expect_error(binary_stl(sphere), Status::limit_exceeded, {"byte 80", "8 faces", "limit of 7"}, few);
  ReadOptions few_vertices;
  few_vertices.max_vertices = 5;
  expect_error(binary_stl(sphere), Status::limit_exceeded, {"6 vertices", "limit of 5"}, few_vertices);
  expect_error(ascii_stl(sphere), Status::limit_exceeded, {"bad.stl:", "8 faces"}, few);
  expect_error(ascii_stl(sphere), Status::limit_exceeded, {"bad.stl:", "6 vertices"}, few_vertices);
}

TEST(stl_reader, NonFiniteCoordinates) {
  const PolygonMesh sphere = float_sphere(0);
  for (float bad : {NAN, INFINITY, -INFINITY}) {
    std::vector<uint8_t> bytes = binary_stl(sphere);
    // Triangle 3, corner 1, y: after the header and count, 3 triangles, the normal, corner 0, x.
    // The message names the corner's first byte: 84 + 3 * 50 + 12 + 12 = 258.
    std::memcpy(bytes.data() + 84 + 3 * 50 + 12 + 12 + 4, &bad, 4);
    expect_error(bytes, Status::parse_error, {"byte 258", "triangle 3, corner 1", "not finite"});
  }
  expect_error(triangle_with_line(5, "vertex 1 nan 0"), Status::parse_error, {"bad.stl:5:", "not finite"});
  expect_error(triangle_with_line(5, "vertex 1 inf 0"), Status::parse_error, {"bad.stl:5:", "not finite"});
  expect_error(triangle_with_line(5, "vertex 1 1e999 0"), Status::parse_error, {"bad.stl:5:", "not finite"});
  // An underflow is 0, a tiny number, not an error.
  const Outcome tiny = try_read(bytes_of(triangle_with_line(5, "vertex 1 1e-999 0")));
  ASSERT_TRUE(tiny.ok) << tiny.message;
  EXPECT_EQ(tiny.cage.mesh.positions[1], Vec3(1, 0, 0));
}

TEST(stl_reader, MalformedAsciiStructure) {
  const Outcome ok = try_read(bytes_of(kTriangle));
  ASSERT_TRUE(ok.ok) << ok.message;
  EXPECT_EQ(ok.cage.mesh.num_faces(), 1u);
  expect_error(triangle_with_line(2, "facet 0 0 1"), Status::parse_error, {"bad.stl:2:", "'normal'"});
  expect_error(triangle_with_line(2, "facet normal 0 0"), Status::parse_error, {"bad.stl:3:", "not a number"});
  expect_error(triangle_with_line(3, " outer"), Status::parse_error, {"bad.stl:4:", "'loop'"});
  expect_error(triangle_with_line(3, " inner loop"), Status::parse_error, {"bad.stl:3:", "'outer'"});
  expect_error(triangle_with_line(4, "  vertex 0 0"), Status::parse_error, {"bad.stl:5:", "not a number"});
  expect_error(triangle_with_line(4, "  vertex 0 0 x"), Status::parse_error, {"bad.stl:4:", "not a number", "'x'"});
  expect_error(triangle_with_line(4, "  vertex 0 0 0 0"), Status::parse_error, {"bad.stl:4:", "'0'"});
  expect_error(triangle_with_line(4, "  vertex 0 0 1.5.2"), Status::parse_error, {"bad.stl:4:"});
  expect_error(triangle_with_line(6, "  vertex 0 1 1\n  vertex 1 1 1"), Status::parse_error,
               {"bad.stl:7:", "more than 3 vertices"});
  expect_error(triangle_with_line(6, ""), Status::parse_error, {"bad.stl:7:", "facet has 2 vertices"});
  expect_error(triangle_with_line(7, ""), Status::parse_error, {"bad.stl:8:", "'endloop'"});
  expect_error(triangle_with_line(8, "endfacets"), Status::parse_error, {"bad.stl:8:", "'endfacet'"});
  expect_error(triangle_with_line(9, ""), Status::parse_error, {"without 'endsolid'"});
  expect_error(triangle_with_line(9, "endsolid t\njunk"), Status::parse_error, {"bad.stl:10:", "'junk'"});
  expect_error(triangle_with_line(2, "face normal 0 0 1"), Status::parse_error, {"bad.stl:2:", "'face'"});
  std::string with_nul = kTriangle;
  with_nul[std::string(kTriangle).find("1 0 0")] = '\0';
  expect_error(bytes_of(with_nul), Status::parse_error, {"bad.stl:5:", "NUL"});
}

TEST(stl_reader, EmptyFilesHaveNoFaces) {
  expect_error("solid empty\nendsolid empty\n", Status::parse_error, {"no faces"});
  expect_error("solid", Status::parse_error, {"endsolid"});
  std::vector<uint8_t> zero(80, uint8_t(' '));
  put_le(zero, 0, 4);
  expect_error(zero, Status::parse_error, {"no faces"});
  expect_error(std::vector<uint8_t>{}, Status::parse_error, {"empty"});
  expect_error("hello\n", Status::parse_error, {"not an STL file", "6 bytes"});
}

TEST(stl_reader, RandomCorruptionNeverCrashes) {
  std::mt19937 rng(20261201);
  const std::vector<std::vector<uint8_t>> samples = {binary_stl(float_sphere(1), "solid sphere"),
                                                     bytes_of(ascii_stl(float_sphere(1)))};
  for (const std::vector<uint8_t>& sample : samples) {
    for (int round = 0; round < 400; ++round) {
      std::vector<uint8_t> bytes = sample;
      const int edits = 1 + int(rng() % 6);
      for (int e = 0; e < edits; ++e) {
        const size_t at = rng() % bytes.size();
        switch (rng() % 5) {
          case 0: bytes[at] = uint8_t(rng()); break;
          case 1: bytes[at] = uint8_t('0' + rng() % 10); break;
          case 2: bytes[at] ^= uint8_t(1u << (rng() % 8)); break;
          case 3: bytes.erase(bytes.begin() + long(at)); break;
          default: bytes.insert(bytes.begin() + long(at), uint8_t(rng()));
        }
        if (bytes.empty()) bytes.push_back('s');
      }
      const Outcome out = try_read(bytes);
      if (!out.ok) {
        ASSERT_NE(out.status, Status::success);
        ASSERT_EQ(out.message.rfind("bad.stl", 0), 0u) << out.message;
        continue;
      }
      const PolygonMesh& m = out.cage.mesh;
      ASSERT_GT(m.num_faces(), 0u);
      ASSERT_TRUE(m.all_faces_have_size(3));
      for (uint32_t v : m.face_vertices) ASSERT_LT(v, m.num_vertices());
      for (const Vec3& p : m.positions) ASSERT_TRUE(is_finite(p));
    }
  }
}

TEST(stl_reader, ReportsProgressAndCancels) {
  PolygonMesh grid = cagekit_test::quad_grid(200, 200);  // 80,000 triangles: over 2^16
  PolygonMesh triangles;
  triangles.positions = grid.positions;
  for (size_t f = 0; f < grid.num_faces(); ++f) {
    const uint32_t* q = grid.face_begin(f);
    triangles.add_face({q[0], q[1], q[2]});
    triangles.add_face({q[0], q[2], q[3]});
  }
  for (const std::vector<uint8_t>& bytes : {binary_stl(triangles), bytes_of(ascii_stl(triangles))}) {
    int calls = 0;
    TaskMonitor counting([&calls](const char* stage, double f) {
      ++calls;
      return std::strcmp(stage, "reading") == 0 && f >= 0 && f <= 1;
    }, nullptr);
    const Cage back = read_cage_from_memory(bytes.data(), bytes.size(), FileFormat::stl, "<big>", {}, counting);
    EXPECT_EQ(back.mesh.num_faces(), triangles.num_faces());
    EXPECT_EQ(back.mesh.num_vertices(), triangles.num_vertices());
    EXPECT_GE(calls, 1);
    TaskMonitor cancel([](const char*, double) { return false; }, nullptr);
    EXPECT_EQ(cagekit_test::status_of([&] {
                read_cage_from_memory(bytes.data(), bytes.size(), FileFormat::stl, "<big>", {}, cancel);
              }),
              Status::cancelled);
  }
}

// The corpus STL files are triangle soups: after reading, every distinct corner position is one
// vertex (counted here independently of the reader), so there are far fewer vertices than the
// 3 per face of the soup.
TEST(stl_reader, CorpusFilesReadWelded) {
  namespace fs = std::filesystem;
  const fs::path folder = fs::path(CAGEKIT_SHARED_CORPUS) / "stl";
  if (!fs::is_directory(folder)) GTEST_SKIP() << folder << " not present";
  size_t files = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.path().extension() != ".stl") continue;
    ++files;
    const std::string path = entry.path().string();
    SCOPED_TRACE(path);
    Cage cage;
    ASSERT_NO_THROW(cage = read_cage_from_file(path));
    const PolygonMesh& m = cage.mesh;
    ASSERT_GT(m.num_faces(), 0u);
    EXPECT_LT(m.num_vertices(), m.num_faces()) << "not welded";
    // Distinct corners, counted from the file's own numbers.
    std::set<std::tuple<double, double, double>> corners;
    std::ifstream in(path, std::ios::binary);
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    uint32_t count = 0;
    if (bytes.size() >= 84) std::memcpy(&count, bytes.data() + 80, 4);
    if (bytes.size() >= 84 && bytes.size() == 84 + 50 * uint64_t(count)) {
      for (uint32_t t = 0; t < count; ++t)
        for (int k = 0; k < 3; ++k) {
          float xyz[3];
          std::memcpy(xyz, bytes.data() + 84 + 50 * size_t(t) + 12 + 12 * k, 12);
          corners.emplace(xyz[0] + 0.0, xyz[1] + 0.0, xyz[2] + 0.0);
        }
      EXPECT_EQ(m.num_faces(), count);
    } else {
      std::istringstream text(std::string(bytes.begin(), bytes.end()));
      std::string word;
      size_t facets = 0;
      while (text >> word) {
        if (word == "facet") ++facets;
        if (word != "vertex") continue;
        double x, y, z;
        text >> x >> y >> z;
        corners.emplace(x + 0.0, y + 0.0, z + 0.0);
      }
      EXPECT_EQ(m.num_faces(), facets);
    }
    EXPECT_EQ(m.num_vertices(), corners.size());
    const ValidationReport report = validate_mesh(m);
    EXPECT_EQ(report.count(MeshIssue::unreferenced_vertex), 0u);
    EXPECT_EQ(report.count(MeshIssue::index_out_of_range), 0u);
    EXPECT_EQ(report.count(MeshIssue::non_finite_position), 0u);
    std::printf("%s: %zu vertices, %zu faces, %s\n", entry.path().filename().c_str(), m.num_vertices(),
                m.num_faces(), report.ok() ? "valid" : report.summary().c_str());
  }
  EXPECT_GT(files, 0u);
}
