// SPDX-License-Identifier: GPL-3.0-or-later
// validate_mesh / validate_cage: each issue kind on a hand-made mesh that has exactly that
// problem, clean meshes, hostile input (out-of-range indices, NaN), record limits, speed.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include "core/mesh_validation.h"
#include "core/status.h"
#include "test_support.h"
#include "../sanitizer/sanitized_build.h"

namespace {

using cagekit::Cage;
using cagekit::MeshIssue;
using cagekit::PolygonMesh;
using cagekit::validate_cage;
using cagekit::validate_mesh;
using cagekit::ValidationReport;
using cagekit::Vec3;

constexpr int kKinds = static_cast<int>(MeshIssue::count_);

PolygonMesh load_obj(const std::string& path) { return cagekit_test::load_mesh(path); }

// Asserts that the report found exactly `count` problems, all of kind `issue`, and that the
// first record (and the first message of that kind) is `message`.
void expect_only(const ValidationReport& r, MeshIssue issue, uint64_t count, const std::string& message) {
  for (int k = 0; k < kKinds; ++k) {
    if (k == static_cast<int>(issue)) EXPECT_EQ(r.counts[k], count) << cagekit::mesh_issue_name(issue);
    else EXPECT_EQ(r.counts[k], 0u) << "unexpected " << cagekit::mesh_issue_name(static_cast<MeshIssue>(k)) << ": "
                                    << r.summary();
  }
  EXPECT_EQ(r.flags(), 1u << static_cast<int>(issue));
  ASSERT_EQ(r.records.size(), count < 16 ? count : 16);
  EXPECT_EQ(r.records[0].issue, issue);
  EXPECT_EQ(r.records[0].message, message);
  EXPECT_EQ(r.first_message[static_cast<int>(issue)], message);
  EXPECT_EQ(r.ok(), issue == MeshIssue::unreferenced_vertex);
}

void expect_clean(const ValidationReport& r) {
  for (int k = 0; k < kKinds; ++k) EXPECT_EQ(r.counts[k], 0u) << r.summary();
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.flags(), 0u);
  EXPECT_TRUE(r.records.empty());
  EXPECT_EQ(r.summary(), "");
}

PolygonMesh single_triangle() {
  PolygonMesh m;
  m.add_vertex(Vec3(0, 0, 0));
  m.add_vertex(Vec3(1, 0, 0));
  m.add_vertex(Vec3(0, 1, 0));
  m.add_face({0, 1, 2});
  return m;
}

TEST(MeshValidation, CleanMeshesAreOk) {
  expect_clean(validate_mesh(cagekit_test::unit_cube_quads()));
  expect_clean(validate_mesh(cagekit_test::triangle_sphere(3)));
  expect_clean(validate_mesh(cagekit_test::quad_grid(7, 5)));
  expect_clean(validate_mesh(single_triangle()));
  expect_clean(validate_mesh(PolygonMesh()));
}

TEST(MeshValidation, IndexOutOfRange) {
  PolygonMesh m = cagekit_test::unit_cube_quads();
  m.add_face({0, 1, 9000});
  expect_only(validate_mesh(m), MeshIssue::index_out_of_range, 1,
              "face 6 refers to vertex 9000 but the mesh has 8 vertices");
  EXPECT_EQ(validate_mesh(m).records[0].element, 6u);
  // A face with several bad indices counts once, naming the first; UINT32_MAX is fine too.
  m.add_face({0xffffffffu, 8, 1});
  const ValidationReport r = validate_mesh(m);
  EXPECT_EQ(r.count(MeshIssue::index_out_of_range), 2u);
  EXPECT_EQ(r.records[1].message, "face 7 refers to vertex 4294967295 but the mesh has 8 vertices");
}

TEST(MeshValidation, NonFinitePosition) {
  PolygonMesh m = cagekit_test::unit_cube_quads();
  m.positions[5].y = std::numeric_limits<double>::quiet_NaN();
  expect_only(validate_mesh(m), MeshIssue::non_finite_position, 1, "vertex 5 has a non-finite position (1, nan, 1)");
  m.positions[2].z = -std::numeric_limits<double>::infinity();
  const ValidationReport r = validate_mesh(m);
  EXPECT_EQ(r.count(MeshIssue::non_finite_position), 2u);
  EXPECT_EQ(r.records[0].message, "vertex 2 has a non-finite position (0, 1, -inf)");
  EXPECT_EQ(r.records[0].element, 2u);
  EXPECT_EQ(r.count(MeshIssue::degenerate_face), 0u);  // no area test on NaN faces
}

TEST(MeshValidation, DegenerateFaceRepeatedVertex) {
  PolygonMesh m = cagekit_test::quad_grid(2, 2);
  m.add_face({0, 1, 1, 4});
  expect_only(validate_mesh(m), MeshIssue::degenerate_face, 1, "face 4 is degenerate: vertex 1 repeats");
  // Non-adjacent repetition, and a long face (sorted check).
  PolygonMesh n = cagekit_test::quad_grid(2, 2);
  n.add_face({0, 1, 4, 1});
  std::vector<uint32_t> big;
  for (uint32_t i = 0; i < 9; ++i) big.push_back(i);
  for (uint32_t i = 0; i < 9; ++i) big.push_back(8 - i);
  n.add_face(big.data(), big.size());
  const ValidationReport r = validate_mesh(n);
  EXPECT_EQ(r.count(MeshIssue::degenerate_face), 2u);
  EXPECT_EQ(r.records[0].message, "face 4 is degenerate: vertex 1 repeats");
  EXPECT_EQ(r.records[1].message, "face 5 is degenerate: vertex 0 repeats");
  EXPECT_EQ(r.flags(), 1u << static_cast<int>(MeshIssue::degenerate_face));
}

TEST(MeshValidation, DegenerateFaceTooFewVertices) {
  PolygonMesh m = cagekit_test::quad_grid(2, 2);
  m.add_face({0, 1});
  expect_only(validate_mesh(m), MeshIssue::degenerate_face, 1, "face 4 is degenerate: it has only 2 vertices");
  m.add_face({3});
  m.add_face(nullptr, 0);
  const ValidationReport r = validate_mesh(m);
  EXPECT_EQ(r.count(MeshIssue::degenerate_face), 3u);
  EXPECT_EQ(r.records[1].message, "face 5 is degenerate: it has only 1 vertex");
  EXPECT_EQ(r.records[2].message, "face 6 is degenerate: it has no vertices");
}

TEST(MeshValidation, DegenerateFaceZeroArea) {
  PolygonMesh m;  // three collinear points
  m.add_vertex(Vec3(0, 0, 0));
  m.add_vertex(Vec3(1, 1, 1));
  m.add_vertex(Vec3(3, 3, 3));
  m.add_face({0, 1, 2});
  expect_only(validate_mesh(m), MeshIssue::degenerate_face, 1, "face 0 has zero area");
  // Collinear after rounding (a third of the way), at a large offset and at a tiny scale.
  for (double scale : {1e-200, 1e-3, 1.0, 1e200}) {
    PolygonMesh t;
    const Vec3 o(1e3 * scale, -7 * scale, 2 * scale);
    t.add_vertex(o);
    t.add_vertex(o + Vec3(3, 1, 0) * scale);
    t.add_vertex(o + Vec3(1, 1.0 / 3.0, 0) * scale);
    t.add_face({0, 1, 2});
    EXPECT_EQ(validate_mesh(t).count(MeshIssue::degenerate_face), 1u) << scale;
    // ... and a thin but real triangle at the same scale is fine.
    t.positions[2] = o + Vec3(1, 0.5, 0) * scale;
    EXPECT_TRUE(validate_mesh(t).ok()) << scale;
  }
  // All vertices at one point; a quad whose vector area cancels out (bow-tie polygon).
  PolygonMesh p;
  for (int i = 0; i < 3; ++i) p.add_vertex(Vec3(2, 2, 2));
  p.add_face({0, 1, 2});
  EXPECT_EQ(validate_mesh(p).records.at(0).message, "face 0 has zero area");
  PolygonMesh q;
  q.add_vertex(Vec3(0, 0, 0));
  q.add_vertex(Vec3(1, 1, 0));
  q.add_vertex(Vec3(1, 0, 0));
  q.add_vertex(Vec3(0, 1, 0));
  q.add_face({0, 1, 2, 3});
  EXPECT_EQ(validate_mesh(q).count(MeshIssue::degenerate_face), 1u);
}

TEST(MeshValidation, DuplicateFace) {
  PolygonMesh m = single_triangle();
  m.add_face({1, 2, 0});  // same cycle, rotated
  expect_only(validate_mesh(m), MeshIssue::duplicate_face, 1, "face 1 duplicates face 0");
  PolygonMesh r = single_triangle();
  r.add_face({2, 1, 0});
  expect_only(validate_mesh(r), MeshIssue::duplicate_face, 1, "face 1 duplicates face 0 (opposite orientation)");
  // On a closed cube: the duplicate is left out of the edge checks, so nothing else is reported.
  PolygonMesh c = cagekit_test::unit_cube_quads();
  c.add_face({5, 7, 3, 1});  // face 5 = {1, 3, 7, 5} reversed
  c.add_face({3, 7, 5, 1});  // face 5 again, same direction
  const ValidationReport rc = validate_mesh(c);
  EXPECT_EQ(rc.count(MeshIssue::duplicate_face), 2u);
  EXPECT_EQ(rc.records.at(0).message, "face 6 duplicates face 5 (opposite orientation)");
  EXPECT_EQ(rc.records.at(1).message, "face 7 duplicates face 5");
  EXPECT_EQ(rc.flags(), 1u << static_cast<int>(MeshIssue::duplicate_face));
  // Same vertex set in another cyclic order is not a duplicate (it is a different polygon).
  PolygonMesh q;
  for (int i = 0; i < 4; ++i) q.add_vertex(Vec3(i & 1, i >> 1, 0));
  q.add_face({0, 1, 3, 2});
  q.add_face({0, 3, 1, 2});
  EXPECT_EQ(validate_mesh(q).count(MeshIssue::duplicate_face), 0u);
}

TEST(MeshValidation, NonManifoldEdge) {
  PolygonMesh book;  // three pages on edge (0,1)
  book.add_vertex(Vec3(0, 0, 0));
  book.add_vertex(Vec3(1, 0, 0));
  book.add_vertex(Vec3(0.5, 1, 0));
  book.add_vertex(Vec3(0.5, -1, 0));
  book.add_vertex(Vec3(0.5, 0, 1));
  book.add_face({0, 1, 2});
  book.add_face({1, 0, 3});
  book.add_face({0, 1, 4});
  expect_only(validate_mesh(book), MeshIssue::non_manifold_edge, 1, "edge (0,1) is used by 3 faces: 0, 1, 2");
  EXPECT_EQ(validate_mesh(book).records[0].element, 0u);
  // Two closed cubes glued along an edge: 4 faces on edge (3,7).
  PolygonMesh c = cagekit_test::unit_cube_quads();
  const uint32_t base = 8;
  for (int i = 0; i < 8; ++i) c.add_vertex(Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1) + Vec3(1, 1, 0));
  const PolygonMesh cube = cagekit_test::unit_cube_quads();
  for (size_t f = 0; f < cube.num_faces(); ++f) {
    std::vector<uint32_t> v(cube.face_begin(f), cube.face_begin(f) + 4);
    for (uint32_t& x : v) x = x == 0 ? 3 : (x == 4 ? 7 : x + base);  // shared: 0->3, 4->7
    c.add_face(v.data(), v.size());
  }
  c.positions.resize(16);
  const ValidationReport r = validate_mesh(c);
  EXPECT_EQ(r.count(MeshIssue::non_manifold_edge), 1u);
  EXPECT_EQ(r.records.at(0).message, "edge (3,7) is used by 4 faces: 3, 5, 8, 10");
  EXPECT_EQ(r.count(MeshIssue::non_manifold_vertex), 0u);
  EXPECT_EQ(r.count(MeshIssue::inconsistent_orientation), 0u);
  EXPECT_EQ(r.count(MeshIssue::unreferenced_vertex), 2u);  // vertices 8 and 12 were replaced
}

TEST(MeshValidation, NonManifoldVertex) {
  PolygonMesh bowtie;
  bowtie.add_vertex(Vec3(0, 0, 0));
  bowtie.add_vertex(Vec3(1, 0, 0));
  bowtie.add_vertex(Vec3(1, 1, 0));
  bowtie.add_vertex(Vec3(-1, 0, 0));
  bowtie.add_vertex(Vec3(-1, -1, 0));
  bowtie.add_face({0, 1, 2});
  bowtie.add_face({0, 3, 4});
  expect_only(validate_mesh(bowtie), MeshIssue::non_manifold_vertex, 1,
              "vertex 0 joins 2 separate fans of faces (non-manifold vertex)");
  // Two cubes touching at one vertex (cube B's corner 0 is cube A's corner 7), three fans
  // with a third triangle touching there too.
  PolygonMesh c = cagekit_test::unit_cube_quads();
  const PolygonMesh cube = cagekit_test::unit_cube_quads();
  for (int i = 1; i < 8; ++i) c.add_vertex(cube.positions[i] + Vec3(1, 1, 1));
  for (size_t f = 0; f < cube.num_faces(); ++f) {
    std::vector<uint32_t> v(cube.face_begin(f), cube.face_begin(f) + 4);
    for (uint32_t& x : v) x = x == 0 ? 7 : x + 7;
    c.add_face(v.data(), v.size());
  }
  const uint32_t a = c.add_vertex(Vec3(3, 1, 1)), b = c.add_vertex(Vec3(3, 2, 1));
  c.add_face({7, a, b});
  const ValidationReport r = validate_mesh(c);
  expect_only(r, MeshIssue::non_manifold_vertex, 1, "vertex 7 joins 3 separate fans of faces (non-manifold vertex)");
  EXPECT_EQ(r.records[0].element, 7u);
}

TEST(MeshValidation, InconsistentOrientation) {
  PolygonMesh g = cagekit_test::quad_grid(2, 1);
  std::reverse(g.face_begin(1), g.face_begin(1) + 4);  // {1,2,5,4} -> {4,5,2,1}
  expect_only(validate_mesh(g), MeshIssue::inconsistent_orientation, 1,
              "faces 0 and 1 traverse edge (1,4) in the same direction (inconsistent orientation)");
  // A sphere with one triangle reversed: its three edges.
  PolygonMesh s = cagekit_test::triangle_sphere(2);
  std::reverse(s.face_begin(10), s.face_begin(10) + 3);
  const ValidationReport r = validate_mesh(s);
  EXPECT_EQ(r.count(MeshIssue::inconsistent_orientation), 3u);
  EXPECT_EQ(r.flags(), 1u << static_cast<int>(MeshIssue::inconsistent_orientation));
  for (const auto& rec : r.records) EXPECT_NE(rec.message.find("10"), std::string::npos) << rec.message;
}

TEST(MeshValidation, UnreferencedVertexIsOnlyAWarning) {
  PolygonMesh m = cagekit_test::unit_cube_quads();
  m.add_vertex(Vec3(5, 5, 5));
  m.add_vertex(Vec3(6, 5, 5));
  const ValidationReport r = validate_mesh(m);
  expect_only(r, MeshIssue::unreferenced_vertex, 2, "vertex 8 is not used by any face");
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.summary(), "unreferenced vertex: 2 (warning) (first: vertex 8 is not used by any face)\n");
}

TEST(MeshValidation, RecordsAreLimitedButCountsComplete) {
  PolygonMesh m = cagekit_test::quad_grid(10, 10);
  for (uint32_t i = 0; i < 100; ++i) m.add_face({i, i + 1, 500 + i});  // 100 out-of-range faces
  m.add_vertex(Vec3(std::nan(""), 0, 0));                                  // non-finite, unreferenced
  const ValidationReport r = validate_mesh(m, 5);
  EXPECT_EQ(r.count(MeshIssue::index_out_of_range), 100u);
  EXPECT_EQ(r.count(MeshIssue::non_finite_position), 1u);
  EXPECT_EQ(r.count(MeshIssue::unreferenced_vertex), 1u);
  ASSERT_EQ(r.records.size(), 5u);
  for (size_t i = 0; i < 5; ++i) EXPECT_EQ(r.records[i].element, 100 + i);
  EXPECT_EQ(r.first_message[static_cast<int>(MeshIssue::non_finite_position)],
            "vertex 121 has a non-finite position (nan, 0, 0)");
  const std::string summary = r.summary();
  EXPECT_NE(summary.find("index out of range: 100 (first: face 100 refers to vertex 500 but the mesh has 122 "
                         "vertices)\n"),
            std::string::npos)
      << summary;
  EXPECT_NE(summary.find("non-finite position: 1 (first: vertex 121"), std::string::npos) << summary;
  EXPECT_FALSE(r.ok());
  EXPECT_TRUE(validate_mesh(m, 0).records.empty());
}

TEST(MeshValidation, MixedHostileInput) {
  // Out-of-range faces are skipped for the topology checks; NaN positions do not disturb them.
  PolygonMesh m = cagekit_test::triangle_sphere(1);
  const uint32_t nv = static_cast<uint32_t>(m.num_vertices());
  m.positions[0] = Vec3(std::nan(""), std::nan(""), std::nan(""));
  m.add_face({1, 2, nv});
  m.add_face({1, 2, nv + 1});  // would be a duplicate / non-manifold edge if it were considered
  m.add_face({nv, nv + 1, nv + 2});
  const ValidationReport r = validate_mesh(m);
  EXPECT_EQ(r.count(MeshIssue::index_out_of_range), 3u);
  EXPECT_EQ(r.count(MeshIssue::non_finite_position), 1u);
  EXPECT_EQ(r.count(MeshIssue::non_manifold_edge), 0u);
  EXPECT_EQ(r.count(MeshIssue::duplicate_face), 0u);
  EXPECT_EQ(r.count(MeshIssue::degenerate_face), 0u);
  EXPECT_EQ(r.count(MeshIssue::inconsistent_orientation), 0u);
}

TEST(MeshValidation, RandomGarbageNeverCrashes) {
  std::mt19937 rng(20240611);
  for (int iter = 0; iter < 300; ++iter) {
    PolygonMesh m;
    const uint32_t nv = rng() % 20;
    for (uint32_t v = 0; v < nv; ++v) {
      Vec3 p(rng() % 4, rng() % 4, rng() % 3);
      if (rng() % 15 == 0) p.y = std::nan("");
      if (rng() % 30 == 0) p.z = HUGE_VAL;
      m.add_vertex(p);
    }
    const uint32_t nf = rng() % 40;
    for (uint32_t f = 0; f < nf; ++f) {
      std::vector<uint32_t> face(rng() % 6);
      for (uint32_t& x : face) x = rng() % (nv + 2);
      m.add_face(face.data(), face.size());
    }
    const ValidationReport r = validate_mesh(m, 4);
    EXPECT_LE(r.records.size(), 4u);
    uint64_t total = 0;
    for (int k = 0; k < kKinds; ++k) total += r.counts[k];
    EXPECT_EQ(r.records.size(), std::min<uint64_t>(total, 4));
    for (int k = 0; k < kKinds; ++k) EXPECT_EQ(r.counts[k] > 0, !r.first_message[k].empty());
  }
}

TEST(MeshValidation, BrokenOffsetsThrowInvalidMesh) {
  PolygonMesh m = cagekit_test::unit_cube_quads();
  m.face_offsets.back() = 3;
  try {
    validate_mesh(m);
    FAIL() << "expected an Error";
  } catch (const cagekit::Error& e) {
    EXPECT_EQ(e.status(), cagekit::Status::invalid_mesh);
    EXPECT_NE(std::string(e.what()).find("face_offsets"), std::string::npos);
  }
  m.face_offsets.clear();
  EXPECT_THROW(validate_mesh(m), cagekit::Error);
}

TEST(MeshValidation, CageTagsAreChecked) {
  Cage c;
  c.mesh = cagekit_test::unit_cube_quads();
  c.creases.push_back({0, 1, 2.0f});   // fine
  c.creases.push_back({2, 0, 10.0f});  // fine, reversed
  c.corners.push_back({7, 1.0f});
  c.holes.push_back(5);
  expect_clean(validate_cage(c));

  Cage d = c;
  d.creases.push_back({0, 3, 1.0f});   // diagonal of face 0: not an edge
  expect_only(validate_cage(d), MeshIssue::index_out_of_range, 1, "crease 2 (0,3) is not an edge of the mesh");
  d = c;
  d.creases.push_back({1, 8, 1.0f});
  expect_only(validate_cage(d), MeshIssue::index_out_of_range, 1,
              "crease 2 refers to vertex 8 but the mesh has 8 vertices");
  d = c;
  d.corners.push_back({12, 1.0f});
  expect_only(validate_cage(d), MeshIssue::index_out_of_range, 1,
              "corner 1 refers to vertex 12 but the mesh has 8 vertices");
  d = c;
  d.holes.push_back(6);
  expect_only(validate_cage(d), MeshIssue::index_out_of_range, 1, "hole 1 refers to face 6 but the mesh has 6 faces");
  d = c;
  d.creases[0].sharpness = -1.0f;
  expect_only(validate_cage(d), MeshIssue::non_finite_position, 1, "crease 0 (0,1) has sharpness -1 (must be >= 0)");
  d = c;
  d.corners[0].sharpness = std::nanf("");
  expect_only(validate_cage(d), MeshIssue::non_finite_position, 1,
              "corner 0 (vertex 7) has sharpness nan (must be >= 0)");
  d = c;
  d.creases[1].sharpness = std::numeric_limits<float>::infinity();  // infinitely sharp: fine
  expect_clean(validate_cage(d));
  // Mesh problems are reported for cages too.
  d = c;
  d.mesh.add_face({0, 1, 40});
  EXPECT_EQ(validate_cage(d).count(MeshIssue::index_out_of_range), 1u);
}

[[maybe_unused]] PolygonMesh big_grid_triangles(int n) {
  PolygonMesh g = cagekit_test::quad_grid(n, n);
  PolygonMesh t;
  t.positions = g.positions;
  t.reserve(g.num_vertices(), 2 * g.num_faces(), 6 * g.num_faces());
  for (size_t f = 0; f < g.num_faces(); ++f) {
    const uint32_t* v = g.face_begin(f);
    t.add_face({v[0], v[1], v[2]});
    t.add_face({v[0], v[2], v[3]});
  }
  return t;
}

// A million faces validate (correctness at scale; the time is printed, not asserted: timing
// belongs in benchmarks, and this one failed a loaded CI machine).
TEST(MeshValidation, MillionFaces) {
  const PolygonMesh quads = cagekit_test::quad_grid(1000, 1000);
  auto t0 = std::chrono::steady_clock::now();
  const ValidationReport r = validate_mesh(quads);
  const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_TRUE(r.ok()) << r.summary();
  std::printf("validate_mesh: 1,000,000 quads in %.0f ms\n", dt * 1e3);
#if defined(NDEBUG) && !CAGEKIT_ASAN_BUILD
  const PolygonMesh tris = big_grid_triangles(710);  // ~1M triangles (Release only: slow in Debug)
  t0 = std::chrono::steady_clock::now();
  const ValidationReport rt = validate_mesh(tris);
  const double dt2 = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_TRUE(rt.ok()) << rt.summary();
  std::printf("validate_mesh: %zu triangles in %.0f ms\n", tris.num_faces(), dt2 * 1e3);
#endif
}

TEST(MeshValidation, StanfordBunny) {
  const std::string path = cagekit_test::shared_mesh_path("stanford-bunny.obj");
  if (path.empty()) GTEST_SKIP() << "../shared/meshes/stanford-bunny.obj not found";
  const PolygonMesh m = load_obj(path);
  const auto t0 = std::chrono::steady_clock::now();
  const ValidationReport r = validate_mesh(m);
  const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("bunny: validate_mesh %.1f ms\n%s", dt * 1e3, r.summary().c_str());
  EXPECT_EQ(r.count(MeshIssue::unreferenced_vertex), 1113u);
  EXPECT_EQ(r.count(MeshIssue::index_out_of_range), 0u);
  EXPECT_EQ(r.count(MeshIssue::non_finite_position), 0u);
  EXPECT_EQ(r.count(MeshIssue::non_manifold_edge), 0u);
  EXPECT_EQ(r.count(MeshIssue::non_manifold_vertex), 0u);
  EXPECT_EQ(r.count(MeshIssue::inconsistent_orientation), 0u);
  EXPECT_EQ(r.count(MeshIssue::duplicate_face), 0u);
}

TEST(MeshValidation, CleanSharedMeshes) {
  for (const char* name : {"fandisk.obj", "rocker-arm.obj", "spot.obj", "cheburashka.obj"}) {
    const std::string path = cagekit_test::shared_mesh_path(name);
    if (path.empty()) GTEST_SKIP() << "../shared/meshes/" << name << " not found";
    const ValidationReport r = validate_mesh(load_obj(path));
    EXPECT_TRUE(r.ok()) << name << ": " << r.summary();
    EXPECT_EQ(r.flags(), 0u) << name << ": " << r.summary();
  }
}

}  // namespace

// Found by fuzz_obj/fuzz_mesh_api: when every face is left out of the edge map (here the only
// face repeats a vertex) the edge map's key array is empty; building it must not offset a null
// pointer (UBSan: "applying non-zero offset to null pointer"). Reproducers: tests/fuzz/regressions/.
TEST(MeshValidation, mesh_whose_only_face_is_degenerate_validates_without_undefined_behaviour) {
  cagekit::PolygonMesh m;
  m.add_vertex({0, 0, 0});
  m.add_vertex({1, 0, 0});
  m.add_vertex({0, 1, 0});
  m.add_face({0, 1, 1});
  const cagekit::ValidationReport r = cagekit::validate_mesh(m);
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.count(cagekit::MeshIssue::degenerate_face), 1u);
}

TEST(MeshValidation, ReportsBetweenItsPassesAndACancelAtAnyReportThrowsCancelled) {
  // Issue 27: each pass takes a fraction of a second on a million faces, so a host's cancel
  // waited for the whole validation. The monitored overload reports between the passes (per
  // face, duplicates, edges, fans) and gives the same report as the plain call.
  cagekit::PolygonMesh mesh = cagekit_test::triangle_sphere(3);
  mesh.add_face({0, 1, 2});  // a duplicate of face 0 (or its reverse): one issue to find
  int reports = 0;
  const cagekit::TaskMonitor counting(
      [&](const char* stage, double fraction) {
        EXPECT_STREQ(stage, "conditioning: validation");
        EXPECT_EQ(fraction, 0.75);
        return ++reports, true;
      },
      nullptr);
  const cagekit::ValidationReport monitored =
      cagekit::validate_mesh(mesh, 16, counting, "conditioning: validation", 0.75);
  const cagekit::ValidationReport plain = cagekit::validate_mesh(mesh, 16);
  EXPECT_EQ(reports, 4);
  EXPECT_EQ(monitored.summary(), plain.summary());
  EXPECT_FALSE(monitored.ok());
  for (int at = 1; at <= reports; ++at) {
    int seen = 0;
    const cagekit::TaskMonitor cancelling([&](const char*, double) { return ++seen < at; }, nullptr);
    try {
      cagekit::validate_mesh(mesh, 16, cancelling, "validation", 0.0);
      ADD_FAILURE() << "no cancel at report " << at;
    } catch (const cagekit::Error& e) {
      EXPECT_EQ(e.status(), cagekit::Status::cancelled) << e.what();
    }
    EXPECT_EQ(seen, at);
  }
}
