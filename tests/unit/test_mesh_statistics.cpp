// SPDX-License-Identifier: GPL-3.0-or-later
// compute_mesh_statistics: counts, boundary loops, components, Euler characteristic and genus on
// generated meshes with known topology and on the shared real meshes.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/mesh_statistics.h"
#include "core/status.h"
#include "test_support.h"

namespace {

using cagekit::Cage;
using cagekit::compute_mesh_statistics;
using cagekit::Error;
using cagekit::MeshStatistics;
using cagekit::PolygonMesh;
using cagekit::Status;
using cagekit::TaskMonitor;
using cagekit::Vec3;

PolygonMesh load_obj(const std::string& path) { return cagekit_test::load_mesh(path); }

Cage cage_of(PolygonMesh m) {
  Cage c;
  c.mesh = std::move(m);
  return c;
}

MeshStatistics stats(const PolygonMesh& m) { return compute_mesh_statistics(cage_of(m)); }

// n x m quads on a torus (major radius 2, minor 0.5), outward-oriented.
PolygonMesh quad_torus(int n, int m) {
  PolygonMesh t;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = 2 * M_PI * i / n, v = 2 * M_PI * j / m;
      t.add_vertex(Vec3((2 + 0.5 * std::cos(v)) * std::cos(u), (2 + 0.5 * std::cos(v)) * std::sin(u), 0.5 * std::sin(v)));
    }
  auto id = [&](int i, int j) { return static_cast<uint32_t>(((i + n) % n) * m + (j + m) % m); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) t.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return t;
}

// Appends `b` to `a` (vertices renumbered), translated by `shift`.
void append(PolygonMesh& a, const PolygonMesh& b, const Vec3& shift) {
  const uint32_t base = static_cast<uint32_t>(a.num_vertices());
  for (const Vec3& p : b.positions) a.add_vertex(p + shift);
  for (size_t f = 0; f < b.num_faces(); ++f) {
    std::vector<uint32_t> v(b.face_begin(f), b.face_begin(f) + b.face_size(f));
    for (uint32_t& x : v) x += base;
    a.add_face(v.data(), v.size());
  }
}

TEST(MeshStatistics, UnitCube) {
  const MeshStatistics s = stats(cagekit_test::unit_cube_quads());
  EXPECT_EQ(s.vertices, 8u);
  EXPECT_EQ(s.faces, 6u);
  EXPECT_EQ(s.edges, 12u);
  EXPECT_EQ(s.quads, 6u);
  EXPECT_EQ(s.triangles, 0u);
  EXPECT_EQ(s.other_polygons, 0u);
  EXPECT_EQ(s.boundary_edges, 0u);
  EXPECT_EQ(s.boundary_loops, 0u);
  EXPECT_EQ(s.components, 1u);
  EXPECT_EQ(s.unreferenced_vertices, 0u);
  EXPECT_EQ(s.invalid_faces, 0u);
  EXPECT_EQ(s.euler_characteristic, 2);
  EXPECT_EQ(s.genus, 0);
  EXPECT_TRUE(s.manifold);
  EXPECT_FALSE(s.bbox.empty);
  EXPECT_EQ(s.bbox.min, Vec3(0, 0, 0));
  EXPECT_EQ(s.bbox.max, Vec3(1, 1, 1));
  EXPECT_NEAR(s.bbox_diagonal, std::sqrt(3.0), 1e-15);
  EXPECT_EQ(s.creases + s.corners + s.holes, 0u);
}

TEST(MeshStatistics, GridHasOneBoundaryLoop) {
  const MeshStatistics s = stats(cagekit_test::quad_grid(4, 3));
  EXPECT_EQ(s.vertices, 20u);
  EXPECT_EQ(s.faces, 12u);
  EXPECT_EQ(s.edges, 4u * 4 + 3 * 5);
  EXPECT_EQ(s.boundary_edges, 14u);
  EXPECT_EQ(s.boundary_loops, 1u);
  EXPECT_EQ(s.components, 1u);
  EXPECT_EQ(s.euler_characteristic, 1);
  EXPECT_EQ(s.genus, 0);
  EXPECT_TRUE(s.manifold);
  EXPECT_NEAR(s.bbox_diagonal, 5.0, 1e-15);
}

TEST(MeshStatistics, GridWithAHoleHasTwoBoundaryLoops) {
  const PolygonMesh g = cagekit_test::quad_grid(3, 3);
  PolygonMesh annulus;
  annulus.positions = g.positions;
  for (size_t f = 0; f < g.num_faces(); ++f)
    if (f != 4) annulus.add_face(g.face_begin(f), g.face_size(f));  // the middle quad
  const MeshStatistics s = stats(annulus);
  EXPECT_EQ(s.boundary_edges, 16u);
  EXPECT_EQ(s.boundary_loops, 2u);
  EXPECT_EQ(s.euler_characteristic, 0);
  EXPECT_EQ(s.genus, 0);
  EXPECT_TRUE(s.manifold);
}

TEST(MeshStatistics, TriangleSphere) {
  const PolygonMesh sphere = cagekit_test::triangle_sphere(3);
  const MeshStatistics s = stats(sphere);
  EXPECT_EQ(s.faces, 8u * 64);
  EXPECT_EQ(s.triangles, 8u * 64);
  EXPECT_EQ(s.edges, 3u * 8 * 64 / 2);
  EXPECT_EQ(s.vertices, 258u);  // V = E - F + 2
  EXPECT_EQ(s.euler_characteristic, 2);
  EXPECT_EQ(s.genus, 0);
  EXPECT_EQ(s.boundary_loops, 0u);
  EXPECT_TRUE(s.manifold);
  EXPECT_NEAR(s.bbox_diagonal, 2 * std::sqrt(3.0), 1e-12);
}

TEST(MeshStatistics, ReportsBetweenItsPassesAndStopsOnACancel) {
  const PolygonMesh sphere = cagekit_test::triangle_sphere(3);
  std::vector<double> fractions;
  const TaskMonitor counting(
      [&](const char* stage, double fraction) {
        EXPECT_STREQ(stage, "statistics");
        fractions.push_back(fraction);
        return true;
      },
      nullptr);
  const MeshStatistics s = compute_mesh_statistics(sphere, counting);
  EXPECT_EQ(s.edges, 3u * 8 * 64 / 2);
  ASSERT_EQ(fractions.size(), 4u);
  for (size_t k = 1; k < fractions.size(); ++k) EXPECT_GT(fractions[k], fractions[k - 1]);
  int seen = 0;
  const TaskMonitor cancelling([&](const char*, double) { return ++seen < 2; }, nullptr);
  try {
    compute_mesh_statistics(sphere, cancelling);
    ADD_FAILURE() << "no cancel";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), Status::cancelled);
  }
}

TEST(MeshStatistics, QuadTorusHasGenusOne) {
  for (int n : {3, 8, 17}) {
    const MeshStatistics s = stats(quad_torus(n, n + 2));
    EXPECT_EQ(s.faces, static_cast<uint64_t>(n * (n + 2)));
    EXPECT_EQ(s.edges, static_cast<uint64_t>(2 * n * (n + 2)));
    EXPECT_EQ(s.euler_characteristic, 0);
    EXPECT_EQ(s.genus, 1) << n;
    EXPECT_EQ(s.boundary_loops, 0u);
    EXPECT_EQ(s.components, 1u);
    EXPECT_TRUE(s.manifold);
  }
}

TEST(MeshStatistics, TwoDisjointCubesAreTwoComponents) {
  PolygonMesh m = cagekit_test::unit_cube_quads();
  append(m, cagekit_test::unit_cube_quads(), Vec3(3, 0, 0));
  const MeshStatistics s = stats(m);
  EXPECT_EQ(s.components, 2u);
  EXPECT_EQ(s.euler_characteristic, 4);
  EXPECT_EQ(s.genus, 0);
  EXPECT_EQ(s.edges, 24u);
  EXPECT_TRUE(s.manifold);
  EXPECT_EQ(s.bbox.max, Vec3(4, 1, 1));
}

TEST(MeshStatistics, GenusIsSummedOverComponents) {
  // A torus, a cube and a grid: chi = 0 + 2 + 1, genus 1 + 0 + 0, one boundary loop.
  PolygonMesh m = quad_torus(6, 5);
  append(m, cagekit_test::unit_cube_quads(), Vec3(10, 0, 0));
  append(m, cagekit_test::quad_grid(2, 2), Vec3(20, 0, 0));
  const MeshStatistics s = stats(m);
  EXPECT_EQ(s.components, 3u);
  EXPECT_EQ(s.euler_characteristic, 3);
  EXPECT_EQ(s.boundary_loops, 1u);
  EXPECT_EQ(s.genus, 1);
  EXPECT_TRUE(s.manifold);
}

TEST(MeshStatistics, MixedPolygonsAndUnreferencedVertices) {
  PolygonMesh m;
  for (int i = 0; i < 9; ++i) m.add_vertex(Vec3(i % 3, i / 3, 0));
  m.add_vertex(Vec3(7, 7, 7));  // unreferenced
  m.add_face({0, 1, 4});
  m.add_face({0, 4, 3});
  m.add_face({1, 2, 5, 4});
  m.add_face({3, 4, 5, 8, 7, 6});
  const MeshStatistics s = stats(m);
  EXPECT_EQ(s.triangles, 2u);
  EXPECT_EQ(s.quads, 1u);
  EXPECT_EQ(s.other_polygons, 1u);
  EXPECT_EQ(s.unreferenced_vertices, 1u);
  EXPECT_EQ(s.euler_characteristic, 9 - 12 + 4);
  EXPECT_EQ(s.boundary_loops, 1u);
  EXPECT_EQ(s.genus, 0);
  EXPECT_TRUE(s.manifold);
  EXPECT_EQ(s.bbox.max, Vec3(7, 7, 7));  // the box covers every finite vertex
}

TEST(MeshStatistics, NonManifoldMeshesGetGenusMinusOne) {
  PolygonMesh bowtie;  // two triangles sharing only vertex 0
  bowtie.add_vertex(Vec3(0, 0, 0));
  bowtie.add_vertex(Vec3(1, 0, 0));
  bowtie.add_vertex(Vec3(1, 1, 0));
  bowtie.add_vertex(Vec3(-1, 0, 0));
  bowtie.add_vertex(Vec3(-1, -1, 0));
  bowtie.add_face({0, 1, 2});
  bowtie.add_face({0, 3, 4});
  MeshStatistics s = stats(bowtie);
  EXPECT_FALSE(s.manifold);
  EXPECT_EQ(s.genus, -1);
  EXPECT_EQ(s.components, 1u);
  EXPECT_EQ(s.boundary_edges, 6u);
  EXPECT_EQ(s.boundary_loops, 2u);  // the figure-eight boundary is two closed walks

  PolygonMesh book;  // three triangles on edge (0,1)
  book.add_vertex(Vec3(0, 0, 0));
  book.add_vertex(Vec3(1, 0, 0));
  book.add_vertex(Vec3(0.5, 1, 0));
  book.add_vertex(Vec3(0.5, -1, 0));
  book.add_vertex(Vec3(0.5, 0, 1));
  book.add_face({0, 1, 2});
  book.add_face({1, 0, 3});
  book.add_face({0, 1, 4});
  s = stats(book);
  EXPECT_FALSE(s.manifold);
  EXPECT_EQ(s.genus, -1);
  EXPECT_EQ(s.edges, 7u);
  EXPECT_EQ(s.boundary_edges, 6u);
  EXPECT_EQ(s.components, 1u);
  EXPECT_EQ(s.boundary_loops, 2u);
}

TEST(MeshStatistics, MoebiusStripIsManifoldButHasNoGenus) {
  PolygonMesh m;
  const int n = 12;
  for (int i = 0; i < n; ++i) {
    const double u = 2 * M_PI * i / n, w = 0.3 * std::cos(u / 2), h = 0.3 * std::sin(u / 2);
    m.add_vertex(Vec3((1 + w) * std::cos(u), (1 + w) * std::sin(u), h));
    m.add_vertex(Vec3((1 - w) * std::cos(u), (1 - w) * std::sin(u), -h));
  }
  for (uint32_t i = 0; i + 1 < n; ++i) m.add_face({2 * i, 2 * i + 1, 2 * i + 3, 2 * i + 2});
  m.add_face({2 * (n - 1), 2 * (n - 1) + 1, 0, 1});  // the half twist
  const MeshStatistics s = stats(m);
  EXPECT_TRUE(s.manifold);
  EXPECT_EQ(s.boundary_loops, 1u);
  EXPECT_EQ(s.euler_characteristic, 0);
  EXPECT_EQ(s.genus, -1);  // not orientable
}

TEST(MeshStatistics, InvalidFacesAreIgnoredInTopology) {
  PolygonMesh m = cagekit_test::unit_cube_quads();
  m.add_face({0, 1, 99});     // out of range
  m.add_face({0, 1});         // too small
  m.add_face({2, 3, 3});      // repeated vertex
  m.positions[7].x = std::nan("");
  const MeshStatistics s = stats(m);
  EXPECT_EQ(s.faces, 9u);
  EXPECT_EQ(s.invalid_faces, 3u);
  EXPECT_EQ(s.edges, 12u);
  EXPECT_EQ(s.euler_characteristic, 2);
  EXPECT_FALSE(s.manifold);
  EXPECT_EQ(s.genus, -1);
  EXPECT_EQ(s.triangles, 2u);
  EXPECT_EQ(s.other_polygons, 1u);
  EXPECT_EQ(s.bbox.max, Vec3(1, 1, 1));  // NaN vertex left out of the box
}

TEST(MeshStatistics, EmptyMesh) {
  const MeshStatistics s = stats(PolygonMesh());
  EXPECT_EQ(s.vertices + s.faces + s.edges + s.components + s.boundary_loops, 0u);
  EXPECT_EQ(s.euler_characteristic, 0);
  EXPECT_TRUE(s.bbox.empty);
  EXPECT_EQ(s.bbox_diagonal, 0.0);
}

TEST(MeshStatistics, CageTagCounts) {
  Cage c = cage_of(cagekit_test::unit_cube_quads());
  c.creases.push_back({0, 1, 2.0f});
  c.creases.push_back({1, 3, cagekit::kSharpnessInfinite});
  c.corners.push_back({7, 3.0f});
  c.holes.push_back(5);
  const MeshStatistics s = compute_mesh_statistics(c);
  EXPECT_EQ(s.creases, 2u);
  EXPECT_EQ(s.corners, 1u);
  EXPECT_EQ(s.holes, 1u);
  EXPECT_EQ(s.genus, 0);
}

TEST(MeshStatistics, BrokenOffsetsThrowInvalidMesh) {
  PolygonMesh m = cagekit_test::unit_cube_quads();
  m.face_offsets[3] = 100;
  try {
    stats(m);
    FAIL() << "expected an Error";
  } catch (const cagekit::Error& e) {
    EXPECT_EQ(e.status(), cagekit::Status::invalid_mesh);
  }
}

MeshStatistics shared_stats(const std::string& name, double* seconds = nullptr) {
  const PolygonMesh m = load_obj(cagekit_test::shared_mesh_path(name));
  const auto t0 = std::chrono::steady_clock::now();
  MeshStatistics s = stats(m);
  const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (seconds) *seconds = dt;
  std::printf("%s: V=%llu F=%llu E=%llu boundary loops=%llu components=%llu unreferenced=%llu chi=%lld genus=%lld "
              "manifold=%d (%.1f ms)\n",
              name.c_str(), (unsigned long long)s.vertices, (unsigned long long)s.faces, (unsigned long long)s.edges,
              (unsigned long long)s.boundary_loops, (unsigned long long)s.components,
              (unsigned long long)s.unreferenced_vertices, (long long)s.euler_characteristic, (long long)s.genus,
              int(s.manifold), dt * 1e3);
  return s;
}

TEST(MeshStatistics, StanfordBunny) {
  if (cagekit_test::shared_mesh_path("stanford-bunny.obj").empty())
    GTEST_SKIP() << "../shared/meshes/stanford-bunny.obj not found";
  const MeshStatistics s = shared_stats("stanford-bunny.obj");
  EXPECT_EQ(s.faces, 69451u);
  EXPECT_EQ(s.triangles, 69451u);
  EXPECT_EQ(s.boundary_loops, 5u);
  EXPECT_EQ(s.unreferenced_vertices, 1113u);
  EXPECT_TRUE(s.manifold);
  EXPECT_EQ(s.components, 1u);
  EXPECT_EQ(s.genus, 0);
  EXPECT_EQ(s.euler_characteristic, 2 - 5);  // a sphere with five holes
}

TEST(MeshStatistics, FandiskIsClosedGenusZero) {
  if (cagekit_test::shared_mesh_path("fandisk.obj").empty()) GTEST_SKIP() << "../shared/meshes/fandisk.obj not found";
  const MeshStatistics s = shared_stats("fandisk.obj");
  EXPECT_EQ(s.faces, 12946u);
  EXPECT_EQ(s.boundary_edges, 0u);
  EXPECT_EQ(s.boundary_loops, 0u);
  EXPECT_TRUE(s.manifold);
  EXPECT_EQ(s.components, 1u);
  EXPECT_EQ(s.euler_characteristic, 2);
  EXPECT_EQ(s.genus, 0);
  EXPECT_EQ(s.unreferenced_vertices, 0u);
}

TEST(MeshStatistics, OtherSharedMeshes) {
  const struct {
    const char* name;
    int64_t genus;
  } meshes[] = {{"rocker-arm.obj", 1}, {"spot.obj", 0}, {"cheburashka.obj", 0}};
  for (const auto& mesh : meshes) {
    if (cagekit_test::shared_mesh_path(mesh.name).empty())
      GTEST_SKIP() << "../shared/meshes/" << mesh.name << " not found";
    const MeshStatistics s = shared_stats(mesh.name);
    EXPECT_TRUE(s.manifold) << mesh.name;
    EXPECT_EQ(s.boundary_loops, 0u) << mesh.name;
    EXPECT_EQ(s.components, 1u) << mesh.name;
    EXPECT_EQ(s.genus, mesh.genus) << mesh.name;
    EXPECT_EQ(s.euler_characteristic, 2 - 2 * mesh.genus) << mesh.name;
  }
}

}  // namespace
