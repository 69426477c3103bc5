// SPDX-License-Identifier: GPL-3.0-or-later
// Uniform Catmull-Clark refinement (thesis §2.2.2-2.2.5, spec acceptance criteria 1-3, 8, 9)
// and limit positions/normals of cage vertices.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/status.h"
#include "subdiv/uniform_refinement.h"
#include "test_support.h"

namespace {

using cagekit::BoundaryRule;
using cagekit::Cage;
using cagekit::EdgeCrease;
using cagekit::Error;
using cagekit::PolygonMesh;
using cagekit::RefineOptions;
using cagekit::Status;
using cagekit::Vec3;
using cagekit::VertexCorner;

using Edge = std::pair<uint32_t, uint32_t>;

Edge make_edge(uint32_t a, uint32_t b) { return a < b ? Edge(a, b) : Edge(b, a); }

std::set<Edge> mesh_edges(const PolygonMesh& m) {
  std::set<Edge> edges;
  for (size_t f = 0; f < m.num_faces(); ++f)
    for (uint32_t i = 0, n = m.face_size(f); i < n; ++i)
      edges.insert(make_edge(m.face_vertex(f, i), m.face_vertex(f, (i + 1) % n)));
  return edges;
}

std::vector<uint32_t> vertex_valences(const PolygonMesh& m) {
  std::vector<uint32_t> valence(m.num_vertices(), 0);
  for (const Edge& e : mesh_edges(m)) {
    ++valence[e.first];
    ++valence[e.second];
  }
  return valence;
}

// Extraordinary vertices of a closed mesh: valence != 4.
std::vector<bool> extraordinary(const PolygonMesh& m) {
  const auto valence = vertex_valences(m);
  std::vector<bool> ev(m.num_vertices());
  for (size_t v = 0; v < ev.size(); ++v) ev[v] = valence[v] != 4;
  return ev;
}

size_t count_true(const std::vector<bool>& flags) { return static_cast<size_t>(std::count(flags.begin(), flags.end(), true)); }

Cage cage_of(PolygonMesh mesh) {
  Cage cage;
  cage.mesh = std::move(mesh);
  return cage;
}

Cage refine(const Cage& cage, int levels, bool limit = false) {
  RefineOptions options;
  options.levels = levels;
  options.limit_positions = limit;
  return cagekit::refine_uniform(cage, options);
}

// A pentagonal prism: two pentagons and five quads, closed, outward-oriented.
PolygonMesh pentagonal_prism() {
  PolygonMesh m;
  for (int z = 0; z < 2; ++z)
    for (int i = 0; i < 5; ++i) {
      const double a = 2.0 * M_PI * i / 5.0;
      m.add_vertex(Vec3(std::cos(a), std::sin(a), z));
    }
  m.add_face({4, 3, 2, 1, 0});
  m.add_face({5, 6, 7, 8, 9});
  for (uint32_t i = 0; i < 5; ++i) {
    const uint32_t j = (i + 1) % 5;
    m.add_face({i, j, j + 5, i + 5});
  }
  return m;
}

struct Counts {
  size_t v, e, f, fv;
};

Counts counts_of(const PolygonMesh& m) { return {m.num_vertices(), mesh_edges(m).size(), m.num_faces(), m.num_face_vertices()}; }

// |CV'| = |CV| + |CE| + |CF|, |CF'| = sum of face sizes, |CE'| = 2|CE| + sum of face sizes.
Counts next_counts(const Counts& c) { return {c.v + c.e + c.f, 2 * c.e + c.fv, c.fv, 4 * c.fv}; }

class SubdivRefinementCounts : public ::testing::TestWithParam<int> {};

PolygonMesh counting_mesh(int which) {
  switch (which) {
    case 0: return cagekit_test::unit_cube_quads();
    case 1: return cagekit_test::triangle_sphere(1);
    default: return pentagonal_prism();
  }
}

TEST_P(SubdivRefinementCounts, vertex_edge_face_counts_follow_the_split_rules) {
  const Cage cage = cage_of(counting_mesh(GetParam()));
  Counts expected = counts_of(cage.mesh);
  for (int level = 1; level <= 3; ++level) {
    expected = next_counts(expected);
    const Cage refined = refine(cage, level);
    const Counts got = counts_of(refined.mesh);
    EXPECT_EQ(got.v, expected.v) << "level " << level;
    EXPECT_EQ(got.e, expected.e) << "level " << level;
    EXPECT_EQ(got.f, expected.f) << "level " << level;
    EXPECT_TRUE(refined.mesh.all_faces_have_size(4)) << "level " << level;
  }
}

TEST_P(SubdivRefinementCounts, extraordinary_vertices_grow_by_the_non_quad_faces_then_stay) {
  const Cage cage = cage_of(counting_mesh(GetParam()));
  size_t non_quads = 0;
  for (size_t f = 0; f < cage.mesh.num_faces(); ++f) non_quads += cage.mesh.face_size(f) != 4;
  const size_t ev0 = count_true(extraordinary(cage.mesh));
  for (int level = 1; level <= 3; ++level) {
    const Cage refined = refine(cage, level);
    const auto ev = extraordinary(refined.mesh);
    EXPECT_EQ(count_true(ev), ev0 + non_quads) << "level " << level;  // thesis fact (b)
    if (level < 2) continue;
    for (size_t f = 0; f < refined.mesh.num_faces(); ++f) {  // thesis fact (c)
      int evs = 0;
      for (uint32_t i = 0; i < 4; ++i) evs += ev[refined.mesh.face_vertex(f, i)];
      ASSERT_LE(evs, 1) << "face " << f << " at level " << level;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(CubeSpherePrism, SubdivRefinementCounts, ::testing::Values(0, 1, 2));

TEST(SubdivUniformRefinement, inherited_vertices_keep_their_indices_and_level_zero_is_the_cage) {
  Cage cage = cage_of(cagekit_test::unit_cube_quads());
  const Cage same = refine(cage, 0);
  EXPECT_EQ(same.mesh.positions, cage.mesh.positions);
  EXPECT_EQ(same.mesh.face_vertices, cage.mesh.face_vertices);
  const Cage refined = refine(cage, 2);
  // The cube's corners move inwards by the smooth rule (2.10) but keep indices 0..7 (eq. 2.1):
  // at level 2 vertex i is still the vertex of valence 3 nearest to the original corner i.
  const auto valence = vertex_valences(refined.mesh);
  for (uint32_t v = 0; v < 8; ++v) {
    EXPECT_EQ(valence[v], 3u);
    const Vec3 d = refined.mesh.positions[v] - Vec3(0.5, 0.5, 0.5);
    const Vec3 c = cage.mesh.positions[v] - Vec3(0.5, 0.5, 0.5);
    EXPECT_GT(cagekit::dot(d, c), 0.0);
  }
}

TEST(SubdivUniformRefinement, one_step_reproduces_the_thesis_rules_on_a_cube) {
  const Cage cage = cage_of(cagekit_test::unit_cube_quads());
  const Cage refined = refine(cage, 1);
  // (2.10) for a valence-3 corner of the unit cube: c' = (3*1*c + sum c_ij + sum f'_ij) / 9.
  const Vec3 c = cage.mesh.positions[0];
  const Vec3 neighbours = Vec3(1, 0, 0) + Vec3(0, 1, 0) + Vec3(0, 0, 1);
  const Vec3 faces = Vec3(0.5, 0.5, 0) + Vec3(0.5, 0, 0.5) + Vec3(0, 0.5, 0.5);
  const Vec3 expected = (3.0 * c + neighbours + faces) * (1.0 / 9.0);
  EXPECT_NEAR(cagekit::distance(refined.mesh.positions[0], expected), 0.0, 1e-15);
  // (2.4) face points and (2.6) edge points exist among the new vertices.
  auto has_point = [&](const Vec3& p) {
    for (const Vec3& q : refined.mesh.positions)
      if (cagekit::distance(p, q) < 1e-15) return true;
    return false;
  };
  EXPECT_TRUE(has_point(Vec3(0.5, 0.5, 0)));
  // Edge (0,0,0)-(1,0,0): faces z=0 and y=0 have centres (0.5,0.5,0) and (0.5,0,0.5).
  EXPECT_TRUE(has_point((Vec3(0, 0, 0) + Vec3(1, 0, 0) + Vec3(0.5, 0.5, 0) + Vec3(0.5, 0, 0.5)) * 0.25));
}

// Vertices of the refined unit cube that lie on one of its 12 edges (two coordinates in {0,1}).
bool on_cube_edge(const Vec3& p, double tol) {
  int fixed = 0;
  for (int i = 0; i < 3; ++i) fixed += std::abs(p[i]) < tol || std::abs(p[i] - 1.0) < tol;
  return fixed >= 2;
}

bool on_same_cube_edge(const Vec3& a, const Vec3& b, double tol) {
  if (!on_cube_edge(a, tol) || !on_cube_edge(b, tol)) return false;
  int shared = 0;
  for (int i = 0; i < 3; ++i) {
    const bool a_fixed = std::abs(a[i]) < tol || std::abs(a[i] - 1.0) < tol;
    shared += a_fixed && std::abs(a[i] - b[i]) < tol;
  }
  return shared >= 2;
}

Cage fully_creased_cube(float sharpness) {
  Cage cage = cage_of(cagekit_test::unit_cube_quads());
  for (const Edge& e : mesh_edges(cage.mesh)) cage.creases.push_back({e.first, e.second, sharpness});
  return cage;
}

TEST(SubdivUniformRefinement, infinitely_sharp_cube_edges_stay_exactly_the_cube_edges) {
  const Cage cage = fully_creased_cube(cagekit::kSharpnessInfinite);
  for (int level = 1; level <= 3; ++level) {
    const Cage refined = refine(cage, level);
    const size_t expected = 12u << level;
    ASSERT_EQ(refined.creases.size(), expected) << "level " << level;
    std::set<Edge> creased;
    for (const EdgeCrease& c : refined.creases) {
      EXPECT_EQ(c.sharpness, cagekit::kSharpnessInfinite);
      creased.insert(make_edge(c.v0, c.v1));
    }
    std::set<Edge> on_edges;
    for (const Edge& e : mesh_edges(refined.mesh))
      if (on_same_cube_edge(refined.mesh.positions[e.first], refined.mesh.positions[e.second], 1e-12))
        on_edges.insert(e);
    EXPECT_EQ(creased, on_edges) << "level " << level;
    // The cube's vertices are corners (three creases): they never move (2.8).
    for (uint32_t v = 0; v < 8; ++v) EXPECT_EQ(refined.mesh.positions[v], cage.mesh.positions[v]);
  }
}

TEST(SubdivUniformRefinement, semi_sharp_creases_decay_by_one_per_level) {
  const Cage cage = fully_creased_cube(2.0f);
  const Cage level1 = refine(cage, 1);
  ASSERT_EQ(level1.creases.size(), 24u);
  for (const EdgeCrease& c : level1.creases) EXPECT_FLOAT_EQ(c.sharpness, 1.0f);
  EXPECT_TRUE(refine(cage, 2).creases.empty());
  EXPECT_TRUE(refine(cage, 3).creases.empty());
}

TEST(SubdivUniformRefinement, corners_stay_on_their_vertices) {
  Cage cage = cage_of(cagekit_test::quad_grid(4, 4, [](double x, double y) { return 0.1 * x * y; }));
  const uint32_t corner = 2 * 5 + 2;  // an interior vertex
  cage.corners.push_back({corner, cagekit::kSharpnessInfinite});
  cage.corners.push_back({7, 1.5f});  // semi-sharp: 0.5 at level 1, gone at level 2
  for (int level = 1; level <= 3; ++level) {
    const Cage refined = refine(cage, level);
    ASSERT_FALSE(refined.corners.empty());
    EXPECT_EQ(refined.corners[0].vertex, corner);
    EXPECT_EQ(refined.corners[0].sharpness, cagekit::kSharpnessInfinite);
    EXPECT_EQ(refined.mesh.positions[corner], cage.mesh.positions[corner]);
    EXPECT_EQ(refined.corners.size(), level == 1 ? 2u : 1u);
    if (level == 1) {
      EXPECT_EQ(refined.corners[1].vertex, 7u);
      EXPECT_FLOAT_EQ(refined.corners[1].sharpness, 0.5f);
    }
  }
}

TEST(SubdivUniformRefinement, holes_become_the_children_of_the_hole_face) {
  Cage cage = cage_of(cagekit_test::unit_cube_quads());
  cage.holes.push_back(0);  // the z = 0 face
  const Cage level1 = refine(cage, 1);
  ASSERT_EQ(level1.holes.size(), 4u);
  // The children of face 0 are the four faces around its face point (0.5, 0.5, 0).
  for (uint32_t f : level1.holes) {
    bool has_face_point = false;
    for (uint32_t i = 0; i < 4; ++i)
      has_face_point |= cagekit::distance(level1.mesh.positions[level1.mesh.face_vertex(f, i)], Vec3(0.5, 0.5, 0)) < 1e-15;
    EXPECT_TRUE(has_face_point) << "hole face " << f;
  }
  const Cage level3 = refine(cage, 3);
  EXPECT_EQ(level3.holes.size(), 64u);
  std::set<uint32_t> distinct(level3.holes.begin(), level3.holes.end());
  EXPECT_EQ(distinct.size(), 64u);
}

TEST(SubdivUniformRefinement, limit_of_a_fully_creased_cube_stays_on_the_straight_edges) {
  const Cage cage = fully_creased_cube(cagekit::kSharpnessInfinite);
  const Cage refined = refine(cage, 3, /*limit=*/true);
  std::set<uint32_t> crease_vertices;
  for (const EdgeCrease& c : refined.creases) crease_vertices.insert({c.v0, c.v1});
  ASSERT_EQ(crease_vertices.size(), 8u + 12u * 7u);
  for (uint32_t v : crease_vertices) EXPECT_TRUE(on_cube_edge(refined.mesh.positions[v], 1e-14)) << v;
}

TEST(SubdivUniformRefinement, boundary_rule_edges_only_moves_one_face_corners_edges_and_corners_pins_them) {
  Cage cage = cage_of(cagekit_test::quad_grid(3, 3));
  const Vec3 corner = cage.mesh.positions[0];
  cage.boundary = BoundaryRule::edges_only;
  EXPECT_NE(refine(cage, 2).mesh.positions[0], corner);  // thesis: a boundary vertex, (2.9)
  cage.boundary = BoundaryRule::edges_and_corners;
  EXPECT_EQ(refine(cage, 2).mesh.positions[0], corner);
}

TEST(SubdivUniformRefinement, limit_positions_converge_like_deep_refinement) {
  const Cage cage = cage_of(cagekit_test::triangle_sphere(1));
  std::vector<Vec3> limit, normals;
  cagekit::limit_positions_and_normals(cage, &limit, &normals);
  double previous_gap = 1e300;
  for (int level = 1; level <= 5; ++level) {
    const Cage refined = refine(cage, level);
    double gap = 0;
    for (size_t v = 0; v < cage.mesh.num_vertices(); ++v)
      gap = std::max(gap, cagekit::distance(refined.mesh.positions[v], limit[v]));
    EXPECT_LT(gap, 0.7 * previous_gap) << "level " << level;  // geometric convergence (criterion 9)
    previous_gap = gap;
  }
  EXPECT_LT(previous_gap, 1e-2);
  // Limit positions after refinement agree with those of the cage vertices.
  const Cage limit3 = refine(cage, 3, /*limit=*/true);
  for (size_t v = 0; v < cage.mesh.num_vertices(); ++v)
    EXPECT_NEAR(cagekit::distance(limit3.mesh.positions[v], limit[v]), 0.0, 1e-12);
  const Cage limit0 = refine(cage, 0, /*limit=*/true);
  for (size_t v = 0; v < cage.mesh.num_vertices(); ++v)
    EXPECT_NEAR(cagekit::distance(limit0.mesh.positions[v], limit[v]), 0.0, 1e-12);
}

TEST(SubdivUniformRefinement, limit_normals_are_unit_and_point_outwards) {
  const Cage sphere = cage_of(cagekit_test::triangle_sphere(1));
  std::vector<Vec3> limit, normals;
  cagekit::limit_positions_and_normals(sphere, &limit, &normals);
  for (size_t v = 0; v < limit.size(); ++v) {
    EXPECT_NEAR(cagekit::norm(normals[v]), 1.0, 1e-12);
    // Symmetric sphere: the normal is radial.
    EXPECT_NEAR(cagekit::dot(normals[v], cagekit::normalized(limit[v])), 1.0, 1e-9) << v;
  }
  const Cage plane = cage_of(cagekit_test::quad_grid(3, 2, [](double, double) { return 0.25; }));
  cagekit::limit_positions_and_normals(plane, &limit, &normals);
  for (size_t v = 0; v < limit.size(); ++v) {
    EXPECT_NEAR(cagekit::distance(normals[v], Vec3(0, 0, 1)), 0.0, 1e-12) << v;
    EXPECT_NEAR(limit[v].z, 0.25, 1e-15);
  }
}

// (2.16)/(2.17) against the thesis formulas on an all-quad cage (where they hold at level 0).
TEST(SubdivUniformRefinement, limit_positions_match_the_thesis_masks) {
  const Cage cube = cage_of(cagekit_test::unit_cube_quads());
  std::vector<Vec3> limit;
  cagekit::limit_positions_and_normals(cube, &limit, nullptr);
  // Vertex 0 at the origin, valence r = 3: S = (r^2 c + 4 sum c_ij + sum diag) / (r (r + 5)).
  const Vec3 edge_sum = Vec3(1, 0, 0) + Vec3(0, 1, 0) + Vec3(0, 0, 1);
  const Vec3 diagonal_sum = Vec3(1, 1, 0) + Vec3(1, 0, 1) + Vec3(0, 1, 1);
  const Vec3 expected = (4.0 * edge_sum + diagonal_sum) * (1.0 / 24.0);
  EXPECT_NEAR(cagekit::distance(limit[0], expected), 0.0, 1e-15);

  Cage grid = cage_of(cagekit_test::quad_grid(2, 1, [](double x, double) { return x * x; }));
  cagekit::limit_positions_and_normals(grid, &limit, nullptr);
  // Vertex 1 = (1,0,1) is a boundary vertex between (0,0,0) and (2,0,4): (2.16).
  const Vec3 boundary = (2.0 / 3.0) * Vec3(1, 0, 1) + (1.0 / 6.0) * (Vec3(0, 0, 0) + Vec3(2, 0, 4));
  EXPECT_NEAR(cagekit::distance(limit[1], boundary), 0.0, 1e-15);
}

TEST(SubdivUniformRefinement, reports_progress_and_can_be_cancelled) {
  const Cage cage = cage_of(cagekit_test::unit_cube_quads());
  std::vector<double> fractions;
  cagekit::TaskMonitor monitor([&](const char* stage, double f) {
    EXPECT_STREQ(stage, "subdivide");
    fractions.push_back(f);
    return true;
  }, nullptr);
  RefineOptions options;
  options.levels = 3;
  cagekit::refine_uniform(cage, options, monitor);
  EXPECT_EQ(fractions, (std::vector<double>{0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0}));

  cagekit::TaskMonitor cancel([](const char*, double f) { return f < 0.5; }, nullptr);
  try {
    cagekit::refine_uniform(cage, options, cancel);
    FAIL() << "expected cancellation";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), Status::cancelled);
  }
}

Status status_of_refining(const Cage& cage, int levels = 1) {
  try {
    refine(cage, levels);
  } catch (const Error& e) {
    return e.status();
  }
  return Status::success;
}

TEST(SubdivUniformRefinement, rejects_bad_input_with_an_error_never_a_crash) {
  const Cage good = cage_of(cagekit_test::unit_cube_quads());
  EXPECT_EQ(status_of_refining(good, -1), Status::invalid_argument);
  EXPECT_EQ(status_of_refining(good, cagekit::kMaxUniformLevels + 1), Status::invalid_argument);

  Cage bad = good;
  bad.mesh.face_vertices[5] = 8;  // out of range
  EXPECT_EQ(status_of_refining(bad), Status::invalid_mesh);
  bad = good;
  bad.mesh.face_vertices[5] = bad.mesh.face_vertices[4];  // repeated vertex
  EXPECT_EQ(status_of_refining(bad), Status::invalid_mesh);
  bad = good;
  bad.mesh.add_face({0, 1});  // two vertices
  EXPECT_EQ(status_of_refining(bad), Status::invalid_mesh);
  bad = good;
  bad.mesh.face_offsets.back() = 5;  // malformed offsets
  EXPECT_EQ(status_of_refining(bad), Status::invalid_mesh);
  bad = good;
  bad.mesh.face_offsets = {};  // broken invariant
  EXPECT_EQ(status_of_refining(bad), Status::invalid_mesh);
  bad = good;
  bad.mesh.positions[3].y = std::nan("");
  EXPECT_EQ(status_of_refining(bad), Status::invalid_mesh);
  bad = good;
  bad.creases.push_back({0, 7, cagekit::kSharpnessInfinite});  // a diagonal, not an edge
  EXPECT_EQ(status_of_refining(bad), Status::invalid_mesh);
  bad = good;
  bad.creases.push_back({0, 1, -1.0f});
  EXPECT_EQ(status_of_refining(bad), Status::invalid_mesh);
  bad = good;
  bad.corners.push_back({8, 1.0f});
  EXPECT_EQ(status_of_refining(bad), Status::invalid_mesh);
  bad = good;
  bad.holes.push_back(6);
  EXPECT_EQ(status_of_refining(bad), Status::invalid_mesh);
  bad = good;
  bad.boundary = static_cast<BoundaryRule>(7);
  EXPECT_EQ(status_of_refining(bad), Status::invalid_mesh);
  EXPECT_EQ(status_of_refining(cage_of(PolygonMesh())), Status::invalid_mesh);
}

TEST(SubdivUniformRefinement, hostile_sizes_fail_before_allocating) {
  // 100 x 100 quads = 40,000 face-vertices; 4^8 times that exceeds 2^31.
  const Cage grid = cage_of(cagekit_test::quad_grid(100, 100));
  EXPECT_EQ(status_of_refining(grid, 8), Status::limit_exceeded);
  // A cage whose faces claim 2^31 face-vertices without having them is malformed, not huge.
  Cage liar = cage_of(cagekit_test::unit_cube_quads());
  liar.mesh.face_offsets.back() = 0x80000000u;
  EXPECT_NE(status_of_refining(liar), Status::success);
}

TEST(SubdivUniformRefinement, accepts_non_manifold_and_unreferenced_vertices) {
  PolygonMesh fin;  // three quads around one edge, plus an unused vertex
  for (int i = 0; i < 8; ++i) fin.add_vertex(Vec3(i % 2, (i / 2) % 2, i / 4));
  fin.add_vertex(Vec3(5, 5, 5));
  fin.add_face({0, 1, 3, 2});
  fin.add_face({0, 1, 5, 4});
  fin.add_face({1, 0, 6, 7});
  const Cage refined = refine(cage_of(fin), 2);
  EXPECT_EQ(refined.mesh.num_faces(), 48u);
  for (const Vec3& p : refined.mesh.positions) EXPECT_TRUE(cagekit::is_finite(p));
  std::vector<Vec3> limit, normals;
  EXPECT_NO_THROW(cagekit::limit_positions_and_normals(cage_of(fin), &limit, &normals));
  ASSERT_EQ(limit.size(), 9u);
  EXPECT_EQ(limit[8], fin.positions[8]);  // the unused vertex stays, without a normal
  EXPECT_EQ(normals[8], Vec3());
  for (int v = 0; v < 8; ++v) EXPECT_TRUE(cagekit::is_finite(limit[v]) && cagekit::is_finite(normals[v]));
}

// Random polygon soups over few vertices: non-manifold edges and vertices, inconsistent
// orientation, random tags. Every call either succeeds with finite output or throws an Error.
TEST(SubdivUniformRefinement, random_soups_never_crash) {
  std::mt19937 rng(20240611);
  int succeeded = 0;
  for (int trial = 0; trial < 150; ++trial) {
    Cage cage;
    cage.mesh = cagekit_test::random_polygon_soup(rng);
    const uint32_t nv = static_cast<uint32_t>(cage.mesh.num_vertices());
    const int nf = static_cast<int>(cage.mesh.num_faces());
    const auto edges = mesh_edges(cage.mesh);
    for (const Edge& e : edges)
      if (rng() % 4 == 0) cage.creases.push_back({e.first, e.second, static_cast<float>(rng() % 12)});
    if (rng() % 3 == 0) cage.corners.push_back({static_cast<uint32_t>(rng() % nv), 3.0f});
    if (rng() % 4 == 0) cage.holes.push_back(static_cast<uint32_t>(rng() % nf));
    cage.boundary = rng() % 2 ? BoundaryRule::edges_only : BoundaryRule::edges_and_corners;
    try {
      const Cage refined = refine(cage, 2, /*limit=*/trial % 2 == 0);
      for (const Vec3& p : refined.mesh.positions) ASSERT_TRUE(cagekit::is_finite(p)) << "trial " << trial;
      std::vector<Vec3> limit, normals;
      cagekit::limit_positions_and_normals(cage, &limit, &normals);
      for (const Vec3& p : limit) ASSERT_TRUE(cagekit::is_finite(p)) << "trial " << trial;
      ++succeeded;
    } catch (const Error& e) {
      EXPECT_NE(e.status(), Status::internal_error) << "trial " << trial << ": " << e.what();
      std::cout << "trial " << trial << " rejected: " << e.what() << "\n";
    }
  }
  std::cout << succeeded << " of 150 random soups accepted\n";
  EXPECT_GT(succeeded, 100);
}

// A tiny OBJ reader (v and f only) for the timing check; the SDK's reader lives in core/io.
PolygonMesh read_obj(const std::string& path) {
  PolygonMesh m;
  std::ifstream in(path);
  std::string line;
  std::vector<uint32_t> face;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v") {
      Vec3 p;
      s >> p.x >> p.y >> p.z;
      m.add_vertex(p);
    } else if (tag == "f") {
      face.clear();
      std::string token;
      while (s >> token) {
        const long index = std::stol(token.substr(0, token.find('/')));
        face.push_back(static_cast<uint32_t>(index < 0 ? static_cast<long>(m.num_vertices()) + index : index - 1));
      }
      m.add_face(face.data(), face.size());
    }
  }
  return m;
}

TEST(SubdivUniformRefinement, fandisk_to_level_two_timing) {
  const std::string path = cagekit_test::shared_mesh_path("fandisk.obj");
  if (path.empty()) GTEST_SKIP() << "fandisk.obj not present";
  const Cage cage = cage_of(read_obj(path));
  ASSERT_EQ(cage.mesh.num_faces(), 12946u);
  const auto start = std::chrono::steady_clock::now();
  const Cage refined = refine(cage, 2);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(refined.mesh.num_faces(), 12946u * 3u * 4u);
  std::cout << "fandisk level 2 (" << refined.mesh.num_faces() << " quads): " << seconds * 1e3 << " ms\n";
  RecordProperty("fandisk_level2_ms", std::to_string(seconds * 1e3));
}

}  // namespace
