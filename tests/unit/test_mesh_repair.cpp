// SPDX-License-Identifier: GPL-3.0-or-later
// repair_mesh: every step on a mesh with that defect (counts, exact result, validation after),
// welding a triangle soup back into a sphere, orientation fixes, non-orientable surfaces, and
// hundreds of random garbage meshes that must all validate after a default repair.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/mesh_repair.h"
#include "core/mesh_statistics.h"
#include "core/mesh_validation.h"
#include "core/status.h"
#include "test_support.h"

namespace {

using cagekit::Cage;
using cagekit::MeshIssue;
using cagekit::MeshStatistics;
using cagekit::PolygonMesh;
using cagekit::repair_mesh;
using cagekit::RepairOptions;
using cagekit::RepairReport;
using cagekit::validate_mesh;
using cagekit::ValidationReport;
using cagekit::Vec3;

PolygonMesh load_obj(const std::string& path) { return cagekit_test::load_mesh(path); }

MeshStatistics stats(const PolygonMesh& m) {
  Cage c;
  c.mesh = m;
  return cagekit::compute_mesh_statistics(c);
}

PolygonMesh repaired(const PolygonMesh& m, RepairReport& rep, const RepairOptions& options = {}) {
  return repair_mesh(m, options, &rep);
}

void expect_valid(const PolygonMesh& m) {
  const ValidationReport r = validate_mesh(m);
  EXPECT_TRUE(r.ok()) << r.summary();
}

void expect_same(const PolygonMesh& a, const PolygonMesh& b) {
  EXPECT_EQ(a.positions.size(), b.positions.size());
  for (size_t i = 0; i < std::min(a.positions.size(), b.positions.size()); ++i) EXPECT_EQ(a.positions[i], b.positions[i]);
  EXPECT_EQ(a.face_offsets, b.face_offsets);
  EXPECT_EQ(a.face_vertices, b.face_vertices);
}

uint64_t total(const RepairReport& r) {
  return r.welded_vertices + r.dropped_invalid_faces + r.dropped_degenerate_faces + r.dropped_duplicate_faces +
         r.split_vertices + r.flipped_faces + r.removed_unreferenced_vertices + r.removed_non_finite_vertices +
         r.non_orientable_components;
}

void append(PolygonMesh& a, const PolygonMesh& b, const Vec3& shift) {
  const uint32_t base = static_cast<uint32_t>(a.num_vertices());
  for (const Vec3& p : b.positions) a.add_vertex(p + shift);
  for (size_t f = 0; f < b.num_faces(); ++f) {
    std::vector<uint32_t> v(b.face_begin(f), b.face_begin(f) + b.face_size(f));
    for (uint32_t& x : v) x += base;
    a.add_face(v.data(), v.size());
  }
}

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

// A quad strip of n quads closed with a half twist.
PolygonMesh moebius_strip(int n) {
  PolygonMesh m;
  for (int i = 0; i < n; ++i) {
    const double u = 2 * M_PI * i / n, w = 0.3 * std::cos(u / 2), h = 0.3 * std::sin(u / 2);
    m.add_vertex(Vec3((1 + w) * std::cos(u), (1 + w) * std::sin(u), h));
    m.add_vertex(Vec3((1 - w) * std::cos(u), (1 - w) * std::sin(u), -h));
  }
  for (uint32_t i = 0; i + 1 < static_cast<uint32_t>(n); ++i) m.add_face({2 * i, 2 * i + 1, 2 * i + 3, 2 * i + 2});
  const uint32_t last = 2 * static_cast<uint32_t>(n - 1);
  m.add_face({last, last + 1, 0, 1});  // the half twist
  return m;
}

// Closed quad Klein bottle: a torus grid whose i-wrap reflects j. Positions are random (the
// surface cannot be embedded anyway; random points keep every quad's area non-zero).
PolygonMesh klein_bottle(int n, int m) {
  PolygonMesh k;
  std::mt19937 rng(static_cast<uint32_t>(n * 100 + m));
  std::uniform_real_distribution<double> d(-1, 1);
  for (int i = 0; i < n * m; ++i) k.add_vertex(Vec3(d(rng), d(rng), d(rng)));
  auto id = [&](int i, int j) {
    j = (j % m + m) % m;
    if (i == n) return static_cast<uint32_t>((m - j) % m);  // (0, -j)
    return static_cast<uint32_t>(i * m + j);
  };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) k.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return k;
}

// Cube B shares cube A's vertices listed in `shared` (pairs B index -> A index).
PolygonMesh two_cubes(const Vec3& shift, std::vector<std::pair<uint32_t, uint32_t>> shared) {
  PolygonMesh m = cagekit_test::unit_cube_quads();
  const PolygonMesh cube = cagekit_test::unit_cube_quads();
  std::vector<uint32_t> map(8);
  for (uint32_t i = 0; i < 8; ++i) {
    const auto it = std::find_if(shared.begin(), shared.end(), [&](auto& p) { return p.first == i; });
    map[i] = it != shared.end() ? it->second : m.add_vertex(cube.positions[i] + shift);
  }
  for (size_t f = 0; f < cube.num_faces(); ++f) {
    std::vector<uint32_t> v(cube.face_begin(f), cube.face_begin(f) + 4);
    for (uint32_t& x : v) x = map[x];
    m.add_face(v.data(), v.size());
  }
  return m;
}

TEST(MeshRepair, CleanMeshesAreUnchanged) {
  for (const PolygonMesh& m : {cagekit_test::unit_cube_quads(), cagekit_test::triangle_sphere(3),
                               cagekit_test::quad_grid(6, 4), quad_torus(7, 5)}) {
    RepairReport rep;
    const PolygonMesh out = repaired(m, rep);
    EXPECT_EQ(total(rep), 0u);
    expect_same(out, m);
  }
}

PolygonMesh triangle_soup(const PolygonMesh& m, double jitter, std::mt19937* rng) {
  PolygonMesh soup;
  std::uniform_real_distribution<double> d(-jitter, jitter);
  for (size_t f = 0; f < m.num_faces(); ++f) {
    std::vector<uint32_t> v;
    for (uint32_t i = 0; i < m.face_size(f); ++i) {
      Vec3 p = m.positions[m.face_vertex(f, i)];
      if (rng) p += Vec3(d(*rng), d(*rng), d(*rng));
      v.push_back(soup.add_vertex(p));
    }
    soup.add_face(v.data(), v.size());
  }
  return soup;
}

void expect_same_statistics(const MeshStatistics& a, const MeshStatistics& b) {
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.faces, b.faces);
  EXPECT_EQ(a.edges, b.edges);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.boundary_edges, b.boundary_edges);
  EXPECT_EQ(a.boundary_loops, b.boundary_loops);
  EXPECT_EQ(a.components, b.components);
  EXPECT_EQ(a.unreferenced_vertices, b.unreferenced_vertices);
  EXPECT_EQ(a.euler_characteristic, b.euler_characteristic);
  EXPECT_EQ(a.genus, b.genus);
  EXPECT_EQ(a.manifold, b.manifold);
  EXPECT_NEAR(a.bbox_diagonal, b.bbox_diagonal, 1e-9);
}

TEST(MeshRepair, WeldTriangleSoupBackIntoTheSphere) {
  const PolygonMesh sphere = cagekit_test::triangle_sphere(3);
  std::mt19937 rng(7);
  const PolygonMesh soup = triangle_soup(sphere, 1e-11, &rng);
  ASSERT_EQ(soup.num_vertices(), 3 * sphere.num_faces());
  EXPECT_EQ(stats(soup).components, sphere.num_faces());

  RepairOptions opt;
  opt.weld_tolerance = 1e-9;
  RepairReport rep;
  const PolygonMesh out = repaired(soup, rep, opt);
  EXPECT_EQ(out.num_vertices(), sphere.num_vertices());
  EXPECT_EQ(rep.welded_vertices, soup.num_vertices() - sphere.num_vertices());
  EXPECT_EQ(rep.dropped_degenerate_faces + rep.dropped_duplicate_faces + rep.split_vertices + rep.flipped_faces, 0u);
  expect_valid(out);
  expect_same_statistics(stats(out), stats(sphere));
  // Each welded vertex is within the tolerance of a sphere vertex.
  for (size_t f = 0; f < out.num_faces(); ++f)
    for (uint32_t i = 0; i < 3; ++i)
      EXPECT_LT(cagekit::distance(out.positions[out.face_vertex(f, i)], sphere.positions[sphere.face_vertex(f, i)]), 1e-9);

  // Exact duplicates are welded by the default tolerance 0; jittered ones are not.
  RepairReport exact;
  const PolygonMesh out0 = repaired(triangle_soup(sphere, 0, nullptr), exact);
  expect_same_statistics(stats(out0), stats(sphere));
  RepairReport none;
  const PolygonMesh kept = repaired(soup, none);
  EXPECT_EQ(none.welded_vertices, 0u);
  EXPECT_EQ(kept.num_vertices(), soup.num_vertices());
  // A negative tolerance disables welding altogether.
  opt.weld_tolerance = -1;
  RepairReport off;
  EXPECT_EQ(repaired(triangle_soup(sphere, 0, nullptr), off, opt).num_vertices(), soup.num_vertices());
  EXPECT_EQ(off.welded_vertices, 0u);
}

TEST(MeshRepair, WeldAtExtremeScales) {
  const PolygonMesh sphere = cagekit_test::triangle_sphere(2);
  struct Case {
    double scale, offset, tol;
  } cases[] = {
      {1.0, 0.0, 1e-300},    // tolerance far below the coordinates' resolution
      {1e3, 1e9, 1e-3},      // far from the origin: cells beyond 2^31
      {1e-280, 0.0, 1e-290}, // tiny model, tiny tolerance
      {1e290, 0.0, 1e280},   // huge model
  };
  for (const Case& c : cases) {
    PolygonMesh m = sphere;
    for (Vec3& p : m.positions) p = p * c.scale + Vec3(c.offset, -c.offset, c.offset);
    PolygonMesh soup = triangle_soup(m, 0, nullptr);
    RepairOptions opt;
    opt.weld_tolerance = c.tol;
    RepairReport rep;
    const PolygonMesh out = repaired(soup, rep, opt);
    EXPECT_EQ(out.num_vertices(), sphere.num_vertices()) << c.scale << " " << c.tol;
    EXPECT_EQ(rep.dropped_degenerate_faces, 0u) << c.scale << " " << c.tol;
    expect_valid(out);
  }
  // Near zero, distinct points closer than a tiny tolerance still merge.
  PolygonMesh z;
  z.add_vertex(Vec3(0, 0, 0));
  z.add_vertex(Vec3(1e-301, 0, -1e-301));
  z.add_vertex(Vec3(1e-299, 0, 0));
  RepairOptions opt;
  opt.weld_tolerance = 1e-300;
  RepairReport rep;
  EXPECT_EQ(repaired(z, rep, opt).num_vertices(), 2u);
  // Far out (loose cells, compared pairwise): a chain 0 - 0.5 - 1.25 merges, 3 stays apart.
  PolygonMesh f;
  for (double x : {0.0, 0.5, 1.25, 3.0}) f.add_vertex(Vec3(1e12 + x, 0, 0));
  opt.weld_tolerance = 1e-3 * 800;  // 0.8
  EXPECT_EQ(repaired(f, rep, opt).num_vertices(), 2u);
}

TEST(MeshRepair, WeldIsTransitiveAndKeepsTheFirstPosition) {
  PolygonMesh m;
  m.add_vertex(Vec3(0, 0, 0));
  m.add_vertex(Vec3(5, 0, 0));
  m.add_vertex(Vec3(0.6, 0, 0));  // within 1 of vertex 0
  m.add_vertex(Vec3(1.2, 0, 0));  // within 1 of vertex 2 only
  m.add_vertex(Vec3(5, 0.999, 0));
  m.add_vertex(Vec3(5, 0, 1.001));  // just too far from vertex 1
  RepairOptions opt;
  opt.weld_tolerance = 1.0;
  RepairReport rep;
  const PolygonMesh out = repaired(m, rep, opt);
  EXPECT_EQ(rep.welded_vertices, 3u);
  ASSERT_EQ(out.num_vertices(), 3u);
  EXPECT_EQ(out.positions[0], Vec3(0, 0, 0));
  EXPECT_EQ(out.positions[1], Vec3(5, 0, 0));
  EXPECT_EQ(out.positions[2], Vec3(5, 0, 1.001));
  // A huge tolerance collapses the sphere: every face degenerates.
  opt.weld_tolerance = 10;
  const PolygonMesh sphere = cagekit_test::triangle_sphere(2);
  const PolygonMesh dot = repaired(sphere, rep, opt);
  EXPECT_EQ(dot.num_vertices(), 1u);
  EXPECT_EQ(dot.num_faces(), 0u);
  EXPECT_EQ(rep.dropped_degenerate_faces, sphere.num_faces());
  expect_valid(dot);
}

TEST(MeshRepair, WeldOnALargeDenseMesh) {
  // 1M-vertex grid with a tolerance of about a cell: the grid hash keeps this quick.
  const PolygonMesh g = cagekit_test::quad_grid(300, 300);
  RepairOptions opt;
  opt.weld_tolerance = 0.25;  // grid spacing is 1: nothing to weld
  RepairReport rep;
  const auto t0 = std::chrono::steady_clock::now();
  const PolygonMesh out = repaired(g, rep, opt);
  std::printf("weld of %zu vertices: %.0f ms\n", g.num_vertices(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() * 1e3);
  EXPECT_EQ(total(rep), 0u);
  expect_same(out, g);
}

TEST(MeshRepair, DropInvalidFaces) {
  PolygonMesh m = cagekit_test::unit_cube_quads();
  const uint32_t nan_used = m.add_vertex(Vec3(0.5, std::nan(""), 0.5));
  m.add_vertex(Vec3(HUGE_VAL, 0, 0));  // unreferenced and non-finite
  m.add_face({0, 1, 50});
  m.add_face({0, 1, nan_used});
  RepairReport rep;
  const PolygonMesh out = repaired(m, rep);
  EXPECT_EQ(rep.dropped_invalid_faces, 2u);
  EXPECT_EQ(rep.removed_non_finite_vertices, 2u);
  EXPECT_EQ(total(rep), 4u);
  expect_same(out, cagekit_test::unit_cube_quads());
  expect_valid(out);

  RepairOptions keep;
  keep.drop_invalid_faces = false;
  const PolygonMesh kept = repaired(m, rep, keep);
  EXPECT_EQ(rep.dropped_invalid_faces, 0u);
  EXPECT_EQ(kept.num_faces(), m.num_faces());
  const ValidationReport r = validate_mesh(kept);
  EXPECT_EQ(r.count(MeshIssue::index_out_of_range), 1u);
  EXPECT_EQ(r.count(MeshIssue::non_finite_position), 2u);
}

TEST(MeshRepair, DropDegenerateFaces) {
  PolygonMesh m = cagekit_test::quad_grid(2, 2);
  m.add_face({0, 1, 1, 4});  // repeated vertex
  m.add_face({0, 1});        // too small
  m.add_face({0, 1, 2});     // collinear: zero area
  m.add_face(nullptr, 0);    // empty
  RepairReport rep;
  const PolygonMesh out = repaired(m, rep);
  EXPECT_EQ(rep.dropped_degenerate_faces, 4u);
  EXPECT_EQ(total(rep), 4u);
  expect_same(out, cagekit_test::quad_grid(2, 2));
  expect_valid(out);
}

TEST(MeshRepair, DropDuplicateFaces) {
  PolygonMesh m = cagekit_test::unit_cube_quads();
  m.add_face({5, 7, 3, 1});  // face 5 reversed
  m.add_face({7, 5, 1, 3});  // face 5 rotated
  RepairReport rep;
  const PolygonMesh out = repaired(m, rep);
  EXPECT_EQ(rep.dropped_duplicate_faces, 2u);
  EXPECT_EQ(total(rep), 2u);
  expect_same(out, cagekit_test::unit_cube_quads());
}

TEST(MeshRepair, SplitNonManifoldEdgeOfABook) {
  PolygonMesh book;
  book.add_vertex(Vec3(0, 0, 0));
  book.add_vertex(Vec3(1, 0, 0));
  book.add_vertex(Vec3(0.5, 1, 0));
  book.add_vertex(Vec3(0.5, -1, 0));
  book.add_vertex(Vec3(0.5, 0, 1));
  book.add_face({0, 1, 2});
  book.add_face({1, 0, 3});
  book.add_face({0, 1, 4});
  RepairReport rep;
  const PolygonMesh out = repaired(book, rep);
  EXPECT_EQ(rep.split_vertices, 2u);
  EXPECT_EQ(total(rep), 2u);
  expect_valid(out);
  // The consistent pair keeps edge (0,1); the third page gets copies of 0 and 1.
  ASSERT_EQ(out.num_vertices(), 7u);
  EXPECT_EQ(std::vector<uint32_t>(out.face_vertices.begin(), out.face_vertices.begin() + 6),
            (std::vector<uint32_t>{0, 1, 2, 1, 0, 3}));
  EXPECT_EQ(std::vector<uint32_t>(out.face_vertices.begin() + 6, out.face_vertices.end()),
            (std::vector<uint32_t>{5, 6, 4}));
  EXPECT_EQ(out.positions[5], book.positions[0]);
  EXPECT_EQ(out.positions[6], book.positions[1]);
  const MeshStatistics s = stats(out);
  EXPECT_EQ(s.components, 2u);
  EXPECT_TRUE(s.manifold);
}

TEST(MeshRepair, SplitTwoCubesSharingAnEdge) {
  // Cube B (shifted by (1,1,0)) shares A's edge (3,7): its corners 0 and 4.
  const PolygonMesh m = two_cubes(Vec3(1, 1, 0), {{0, 3}, {4, 7}});
  ASSERT_EQ(validate_mesh(m).count(MeshIssue::non_manifold_edge), 1u);
  RepairReport rep;
  const PolygonMesh out = repaired(m, rep);
  EXPECT_EQ(rep.split_vertices, 2u);
  EXPECT_EQ(total(rep), 2u);
  expect_valid(out);
  const MeshStatistics s = stats(out);
  EXPECT_EQ(s.components, 2u);  // two whole closed cubes again
  EXPECT_EQ(s.boundary_edges, 0u);
  EXPECT_EQ(s.genus, 0);
  EXPECT_EQ(s.euler_characteristic, 4);
  EXPECT_TRUE(s.manifold);
}

TEST(MeshRepair, SplitNonManifoldVertices) {
  // Two cubes touching at a corner: one copy.
  PolygonMesh m = two_cubes(Vec3(1, 1, 1), {{0, 7}});
  RepairReport rep;
  PolygonMesh out = repaired(m, rep);
  EXPECT_EQ(rep.split_vertices, 1u);
  EXPECT_EQ(total(rep), 1u);
  expect_valid(out);
  MeshStatistics s = stats(out);
  EXPECT_EQ(s.components, 2u);
  EXPECT_EQ(s.euler_characteristic, 4);
  EXPECT_EQ(s.genus, 0);
  // Three grids around one vertex (a fan of fans): two copies.
  PolygonMesh fans;
  const PolygonMesh g = cagekit_test::quad_grid(2, 2);
  append(fans, g, Vec3(0, 0, 0));
  append(fans, g, Vec3(-2, -2, -1));
  append(fans, g, Vec3(-2, 0, 1));
  // Grid 1's corner 8 and grid 2's corner 2 are replaced by grid 0's corner 0.
  for (uint32_t& v : fans.face_vertices)
    if (v == 9 + 8 || v == 18 + 2) v = 0;
  ASSERT_EQ(validate_mesh(fans).count(MeshIssue::non_manifold_vertex), 1u);
  out = repaired(fans, rep);
  EXPECT_EQ(rep.split_vertices, 2u);
  expect_valid(out);
  s = stats(out);
  EXPECT_EQ(s.components, 3u);
  EXPECT_EQ(s.boundary_loops, 3u);
  EXPECT_EQ(s.unreferenced_vertices, 2u);  // the two replaced grid corners
}

TEST(MeshRepair, OrientationFlipsExactlyTheReversedFaces) {
  const PolygonMesh sphere = cagekit_test::triangle_sphere(3);
  for (int first_reversed : {0, 1}) {
    PolygonMesh m = sphere;
    uint64_t reversed = 0;
    for (size_t f = 0; f < m.num_faces(); ++f)
      if (f % 7 == 3 || (first_reversed && f == 0)) {
        std::reverse(m.face_begin(f) + 1, m.face_begin(f) + 3);  // keeps the first vertex
        ++reversed;
      }
    ASSERT_GT(validate_mesh(m).count(MeshIssue::inconsistent_orientation), 0u);
    RepairReport rep;
    const PolygonMesh out = repaired(m, rep);
    EXPECT_EQ(rep.flipped_faces, reversed);
    EXPECT_EQ(total(rep), reversed);
    expect_same(out, sphere);  // exactly the original faces, first vertex kept
  }
  // Where most faces of a component are reversed, the majority wins: the others flip.
  PolygonMesh g = cagekit_test::quad_grid(4, 4);
  for (size_t f = 0; f < 10; ++f) std::reverse(g.face_begin(f) + 1, g.face_begin(f) + 4);
  RepairReport rep;
  const PolygonMesh out = repaired(g, rep);
  EXPECT_EQ(rep.flipped_faces, 6u);
  expect_valid(out);
  const PolygonMesh grid = cagekit_test::quad_grid(4, 4);
  for (size_t f = 0; f < 16; ++f) {  // every face now runs the reversed way {a, d, c, b}
    EXPECT_EQ(out.face_vertex(f, 0), grid.face_vertex(f, 0));
    EXPECT_EQ(out.face_vertex(f, 1), grid.face_vertex(f, 3));
    EXPECT_EQ(out.face_vertex(f, 3), grid.face_vertex(f, 1));
  }
  // Each component on its own: a cube with one face reversed next to a clean torus.
  PolygonMesh two = cagekit_test::unit_cube_quads();
  std::reverse(two.face_begin(2) + 1, two.face_begin(2) + 4);
  append(two, quad_torus(5, 4), Vec3(5, 0, 0));
  const PolygonMesh out2 = repaired(two, rep);
  EXPECT_EQ(rep.flipped_faces, 1u);
  expect_valid(out2);
}

TEST(MeshRepair, MoebiusStripIsCutOpen) {
  const PolygonMesh m = moebius_strip(12);
  ASSERT_EQ(validate_mesh(m).count(MeshIssue::inconsistent_orientation), 1u);
  RepairReport rep;
  std::vector<std::string> warnings;
  const cagekit::TaskMonitor monitor(nullptr, [&](cagekit::LogLevel level, const std::string& msg) {
    if (level == cagekit::LogLevel::warning) warnings.push_back(msg);
  });
  const PolygonMesh out = repair_mesh(m, RepairOptions(), &rep, monitor);
  EXPECT_EQ(rep.non_orientable_components, 1u);
  EXPECT_EQ(rep.split_vertices, 2u);  // the two ends of the conflicting rung
  EXPECT_LE(rep.flipped_faces, 6u);   // the majority keeps its orientation
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("non-orientable"), std::string::npos);
  expect_valid(out);
  const MeshStatistics s = stats(out);
  EXPECT_EQ(s.components, 1u);
  EXPECT_EQ(s.boundary_loops, 1u);  // now a plain strip: a disk
  EXPECT_EQ(s.euler_characteristic, 1);
  EXPECT_EQ(s.genus, 0);

  // Without splitting, the strip stays non-orientable: reported, no crash.
  RepairOptions no_split;
  no_split.split_non_manifold = false;
  const PolygonMesh same = repaired(m, rep, no_split);
  EXPECT_EQ(rep.non_orientable_components, 1u);
  EXPECT_EQ(rep.split_vertices, 0u);
  EXPECT_EQ(validate_mesh(same).count(MeshIssue::inconsistent_orientation), 1u);
}

TEST(MeshRepair, KleinBottleIsCutUntilOrientable) {
  const PolygonMesh k = klein_bottle(6, 5);
  const MeshStatistics before = stats(k);
  ASSERT_TRUE(before.manifold);
  ASSERT_EQ(before.euler_characteristic, 0);
  ASSERT_EQ(before.genus, -1);
  RepairReport rep;
  const PolygonMesh out = repaired(k, rep);
  EXPECT_EQ(rep.non_orientable_components, 1u);
  EXPECT_GT(rep.split_vertices, 0u);
  EXPECT_EQ(out.num_faces(), k.num_faces());
  expect_valid(out);
  EXPECT_GE(stats(out).genus, 0);
}

TEST(MeshRepair, RemoveUnreferencedVertices) {
  PolygonMesh m;
  m.add_vertex(Vec3(9, 9, 9));  // unused, before the cube's vertices
  append(m, cagekit_test::unit_cube_quads(), Vec3(0, 0, 0));
  m.add_vertex(Vec3(8, 8, 8));
  RepairOptions opt;
  opt.remove_unreferenced_vertices = true;
  RepairReport rep;
  const PolygonMesh out = repaired(m, rep, opt);
  EXPECT_EQ(rep.removed_unreferenced_vertices, 2u);
  EXPECT_EQ(total(rep), 2u);
  expect_same(out, cagekit_test::unit_cube_quads());
  EXPECT_EQ(validate_mesh(out).flags(), 0u);
  // Off by default.
  EXPECT_EQ(repaired(m, rep).num_vertices(), 10u);
}

TEST(MeshRepair, AllStepsTogether) {
  // A sphere with every defect at once.
  PolygonMesh m = cagekit_test::triangle_sphere(2);
  const size_t nv = m.num_vertices(), nf = m.num_faces();
  m.add_vertex(m.positions[3]);                        // exact duplicate of vertex 3 (welded)
  m.add_vertex(Vec3(std::nan(""), 0, 0));              // non-finite
  m.add_face({0, 1, static_cast<uint32_t>(nv + 7)});   // out of range
  m.add_face({2, 2, 5});                               // degenerate
  const std::vector<uint32_t> face4(m.face_begin(4), m.face_begin(4) + 3);
  m.add_face(face4.data(), 3);                         // duplicate of face 4
  std::reverse(m.face_begin(9) + 1, m.face_begin(9) + 3);
  RepairReport rep;
  RepairOptions opt;
  opt.remove_unreferenced_vertices = true;
  const PolygonMesh out = repaired(m, rep, opt);
  EXPECT_EQ(rep.welded_vertices, 1u);
  EXPECT_EQ(rep.dropped_invalid_faces, 1u);
  EXPECT_EQ(rep.removed_non_finite_vertices, 1u);
  EXPECT_EQ(rep.dropped_degenerate_faces, 1u);
  EXPECT_EQ(rep.dropped_duplicate_faces, 1u);
  EXPECT_EQ(rep.flipped_faces, 1u);
  EXPECT_EQ(rep.split_vertices, 0u);
  EXPECT_EQ(rep.removed_unreferenced_vertices, 0u);
  EXPECT_EQ(out.num_faces(), nf);
  expect_same(out, cagekit_test::triangle_sphere(2));
}

// Random garbage: small vertex pools (exact duplicate positions, NaN/Inf), random faces of
// 0..7 vertices with some out-of-range indices, copied and reversed faces, shared fans.
PolygonMesh garbage(std::mt19937& rng) {
  PolygonMesh m;
  const uint32_t nv = 1 + rng() % 24;
  for (uint32_t v = 0; v < nv; ++v) {
    Vec3 p(rng() % 3, rng() % 3, rng() % 3);
    const uint32_t r = rng() % 40;
    if (r == 0) p.x = std::nan("");
    if (r == 1) p.z = -HUGE_VAL;
    if (r == 2) p = Vec3(1e308, -1e308, 1e-310);
    m.add_vertex(p);
  }
  const uint32_t nf = rng() % 60;
  for (uint32_t f = 0; f < nf; ++f) {
    const uint32_t kind = rng() % 10;
    if (kind == 0 && m.num_faces() > 0) {  // copy (maybe reversed) of an earlier face
      const size_t g = rng() % m.num_faces();
      std::vector<uint32_t> v(m.face_begin(g), m.face_begin(g) + m.face_size(g));
      if (rng() % 2) std::reverse(v.begin(), v.end());
      m.add_face(v.data(), v.size());
      continue;
    }
    if (kind == 1 && m.num_faces() > 0) {  // a face on an earlier face's edge (fans, books)
      const size_t g = rng() % m.num_faces();
      if (m.face_size(g) >= 2) {
        const uint32_t i = rng() % m.face_size(g);
        m.add_face({m.face_vertex(g, i), m.face_vertex(g, (i + 1) % m.face_size(g)), static_cast<uint32_t>(rng() % nv)});
        continue;
      }
    }
    std::vector<uint32_t> v(kind < 6 ? 3 : rng() % 8);
    for (uint32_t& x : v) x = rng() % (nv + (rng() % 8 == 0 ? 3 : 0));
    m.add_face(v.data(), v.size());
  }
  return m;
}

// A real surface, damaged: reversed faces, duplicated faces, glued vertices, stray indices.
PolygonMesh damaged(std::mt19937& rng) {
  PolygonMesh m;
  switch (rng() % 4) {
    case 0: m = cagekit_test::triangle_sphere(1 + rng() % 2); break;
    case 1: m = quad_torus(3 + rng() % 5, 3 + rng() % 4); break;
    case 2: m = cagekit_test::quad_grid(1 + rng() % 6, 1 + rng() % 6); break;
    default: m = klein_bottle(3 + rng() % 4, 3 + rng() % 3); break;
  }
  const uint32_t nv = static_cast<uint32_t>(m.num_vertices());
  const size_t nf = m.num_faces();
  for (size_t f = 0; f < nf; ++f)
    if (rng() % 5 == 0) std::reverse(m.face_begin(f), m.face_begin(f) + m.face_size(f));
  for (int i = rng() % 4; i > 0; --i) {  // glue two vertices: pinches, books, degenerate faces
    const uint32_t a = rng() % nv, b = rng() % nv;
    for (uint32_t& v : m.face_vertices)
      if (v == b) v = a;
  }
  for (int i = rng() % 3; i > 0; --i) {
    const size_t g = rng() % nf;
    std::vector<uint32_t> v(m.face_begin(g), m.face_begin(g) + m.face_size(g));
    m.add_face(v.data(), v.size());
  }
  if (rng() % 3 == 0) m.face_vertices[rng() % m.face_vertices.size()] = nv + rng() % 5;
  if (rng() % 3 == 0) m.positions[rng() % nv].y = std::nan("");
  return m;
}

TEST(MeshRepair, RandomGarbageAlwaysValidatesAfterRepair) {
  std::mt19937 rng(1234567);
  uint64_t non_trivial = 0, split = 0, non_orientable = 0;
  for (int iter = 0; iter < 600; ++iter) {
    const PolygonMesh m = iter % 2 ? garbage(rng) : damaged(rng);
    RepairOptions opt;
    if (iter % 3 == 1) opt.weld_tolerance = 0.9;
    if (iter % 5 == 2) opt.weld_tolerance = -1;
    opt.remove_unreferenced_vertices = iter % 4 == 0;
    RepairReport rep;
    PolygonMesh out;
    ASSERT_NO_THROW(out = repair_mesh(m, opt, &rep)) << "iteration " << iter;
    const ValidationReport r = validate_mesh(out);
    ASSERT_TRUE(r.ok()) << "iteration " << iter << "\n" << r.summary();
    if (opt.remove_unreferenced_vertices) {
      EXPECT_EQ(r.flags(), 0u) << "iteration " << iter;
    }
    const MeshStatistics s = stats(out);
    EXPECT_TRUE(s.manifold) << "iteration " << iter;
    non_trivial += !validate_mesh(m).ok();
    split += rep.split_vertices > 0;
    non_orientable += rep.non_orientable_components > 0;
    // Any subset of the steps must not crash either.
    RepairOptions partial;
    partial.weld_tolerance = (rng() % 2) ? 0.0 : -1.0;
    partial.drop_invalid_faces = rng() % 2;
    partial.drop_degenerate_faces = rng() % 2;
    partial.drop_duplicate_faces = rng() % 2;
    partial.split_non_manifold = rng() % 2;
    partial.orient_consistently = rng() % 2;
    partial.remove_unreferenced_vertices = rng() % 2;
    ASSERT_NO_THROW(repair_mesh(m, partial)) << "iteration " << iter;
  }
  std::printf("garbage: %llu invalid inputs, %llu needed splits, %llu non-orientable\n",
              (unsigned long long)non_trivial, (unsigned long long)split, (unsigned long long)non_orientable);
  EXPECT_GT(non_trivial, 500u);
  EXPECT_GT(split, 100u);
  EXPECT_GT(non_orientable, 10u);
}

TEST(MeshRepair, CancelAndBadArguments) {
  const cagekit::TaskMonitor cancel([](const char*, double f) { return f < 0.5; }, nullptr);
  try {
    repair_mesh(cagekit_test::unit_cube_quads(), RepairOptions(), nullptr, cancel);
    FAIL() << "expected cancellation";
  } catch (const cagekit::Error& e) {
    EXPECT_EQ(e.status(), cagekit::Status::cancelled);
  }
  RepairOptions opt;
  opt.weld_tolerance = std::nan("");
  try {
    repair_mesh(cagekit_test::unit_cube_quads(), opt);
    FAIL() << "expected invalid_argument";
  } catch (const cagekit::Error& e) {
    EXPECT_EQ(e.status(), cagekit::Status::invalid_argument);
  }
  PolygonMesh broken = cagekit_test::unit_cube_quads();
  broken.face_offsets[2] = 1;
  EXPECT_THROW(repair_mesh(broken, RepairOptions()), cagekit::Error);
}

TEST(MeshRepair, StanfordBunny) {
  const std::string path = cagekit_test::shared_mesh_path("stanford-bunny.obj");
  if (path.empty()) GTEST_SKIP() << "../shared/meshes/stanford-bunny.obj not found";
  const PolygonMesh m = load_obj(path);
  RepairOptions opt;
  opt.remove_unreferenced_vertices = true;
  RepairReport rep;
  const auto t0 = std::chrono::steady_clock::now();
  const PolygonMesh out = repair_mesh(m, opt, &rep);
  const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("bunny: repair_mesh %.1f ms: welded %llu, degenerate %llu, duplicate %llu, split %llu, flipped %llu, "
              "unreferenced %llu\n",
              dt * 1e3, (unsigned long long)rep.welded_vertices, (unsigned long long)rep.dropped_degenerate_faces,
              (unsigned long long)rep.dropped_duplicate_faces, (unsigned long long)rep.split_vertices,
              (unsigned long long)rep.flipped_faces, (unsigned long long)rep.removed_unreferenced_vertices);
  EXPECT_EQ(rep.removed_unreferenced_vertices, 1113u);
  EXPECT_EQ(rep.dropped_invalid_faces + rep.split_vertices + rep.flipped_faces, 0u);
  const ValidationReport r = validate_mesh(out);
  EXPECT_TRUE(r.ok()) << r.summary();
  EXPECT_EQ(r.flags(), 0u);
  const MeshStatistics s = stats(out);
  EXPECT_EQ(s.boundary_loops, 5u);
  EXPECT_EQ(s.unreferenced_vertices, 0u);
  EXPECT_TRUE(s.manifold);
  EXPECT_EQ(s.genus, 0);
  EXPECT_EQ(out.num_vertices(), m.num_vertices() - 1113 - rep.welded_vertices);
}

}  // namespace
