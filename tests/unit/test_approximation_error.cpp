// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/status.h"
#include "layout/common/approximation_error.h"
#include "test_support.h"

using cagekit::measure_approximation_error;
using cagekit::PolygonMesh;
using cagekit::Vec3;

TEST(ApproximationError, a_mesh_is_at_distance_zero_from_itself) {
  const PolygonMesh sphere = cagekit_test::triangle_sphere(3);
  const auto e = measure_approximation_error(sphere, sphere);
  EXPECT_NEAR(e.hausdorff_rel, 0.0, 1e-12);
  EXPECT_NEAR(e.hausdorff_sym_rel, 0.0, 1e-12);
  EXPECT_NEAR(e.mean_rel, 0.0, 1e-12);
}

TEST(ApproximationError, offset_plane_is_at_its_offset_relative_to_the_diagonal) {
  const PolygonMesh grid = cagekit_test::quad_grid(4, 4);  // [0,4]^2 at z = 0, diagonal 4*sqrt(2)
  PolygonMesh lifted = grid;
  for (Vec3& p : lifted.positions) p.z += 0.25;
  const auto e = measure_approximation_error(grid, lifted);
  const double expected = 0.25 / (4.0 * std::sqrt(2.0));
  EXPECT_NEAR(e.hausdorff_rel, expected, 1e-12);
  EXPECT_NEAR(e.mean_rel, expected, 1e-12);
  EXPECT_NEAR(e.hausdorff_sym_rel, expected, 1e-12);
}

TEST(ApproximationError, symmetric_distance_sees_what_one_sided_misses) {
  // The approximation is the grid plus a far-away flap: input -> approximation is 0 but the
  // flap is far from the input.
  const PolygonMesh grid = cagekit_test::quad_grid(2, 2);
  PolygonMesh with_flap = grid;
  const uint32_t a = with_flap.add_vertex({0, 0, 0}), b = with_flap.add_vertex({1, 0, 0}),
                 c = with_flap.add_vertex({0, 0, 3});
  with_flap.add_face({a, b, c});
  const auto e = measure_approximation_error(grid, with_flap);
  const double diagonal = 2.0 * std::sqrt(2.0);
  EXPECT_NEAR(e.hausdorff_rel, 0.0, 1e-12);
  EXPECT_NEAR(e.hausdorff_sym_rel, 3.0 / diagonal, 1e-12);
}

TEST(ApproximationError, coarse_sphere_error_matches_the_chord_height) {
  // The octahedron's faces are at distance 1/sqrt(3) from the centre: a unit-sphere vertex set
  // approximated by it is at most 1 - 1/sqrt(3) away (the octahedron's face centres).
  const PolygonMesh fine = cagekit_test::triangle_sphere(4);
  const PolygonMesh octahedron = cagekit_test::triangle_sphere(0);
  const auto e = measure_approximation_error(fine, octahedron);
  const double diagonal = 2.0 * std::sqrt(3.0);
  EXPECT_LE(e.hausdorff_rel, (1.0 - 1.0 / std::sqrt(3.0)) / diagonal + 1e-12);
  EXPECT_GE(e.hausdorff_rel, 0.8 * (1.0 - 1.0 / std::sqrt(3.0)) / diagonal);
}

TEST(SurfaceDistance, reports_while_it_builds_and_a_cancel_at_any_report_leaves_nothing) {
  // 131,072 triangles: the tree's splits sort about 2.2M primitives in all, so it reports at
  // least twice while it builds (about every 2^20), plus once before and once before its search
  // structure (issue 27: a cancel inside a million-triangle tree build waited ~1 s for the next report).
  const PolygonMesh sphere = cagekit_test::triangle_sphere(7);
  int reports = 0;
  const cagekit::TaskMonitor counting(
      [&](const char* stage, double fraction) {
        EXPECT_STREQ(stage, "fit");
        EXPECT_EQ(fraction, 0.25);
        ++reports;
        return true;
      },
      nullptr);
  const cagekit::SurfaceDistance distance(sphere, counting, "fit", 0.25);
  EXPECT_GE(reports, 4);
  EXPECT_NEAR(distance.distance({0, 0, 2}), 1.0, 1e-3);
  EXPECT_NEAR(cagekit::norm(distance.closest_point({0, 0, 2}) - Vec3{0, 0, 1}), 0.0, 1e-3);
  // Cancelled at each report in turn: Error(cancelled) every time (ASan: nothing leaks).
  for (int at = 1; at <= reports; ++at) {
    int seen = 0;
    const cagekit::TaskMonitor cancelling([&](const char*, double) { return ++seen < at; }, nullptr);
    try {
      const cagekit::SurfaceDistance cancelled(sphere, cancelling);
      ADD_FAILURE() << "no cancel at report " << at;
    } catch (const cagekit::Error& e) {
      EXPECT_EQ(e.status(), cagekit::Status::cancelled) << e.what();
    }
    EXPECT_EQ(seen, at);
  }
}

TEST(SurfaceDistance, a_large_mesh_gets_a_thinned_search_structure_and_the_same_exact_distances) {
  // 512 x 512 quads = 2^19 triangles: the search structure takes every second triangle's hint
  // (issue 27: CGAL's one-call build of a hint per triangle took ~0.45 s on a million triangles
  // without a cancel point). Hints only decide where a query starts: distances and closest points
  // are still the exact ones, here known in closed form ([0,512]^2 at z = 0).
  const PolygonMesh grid = cagekit_test::quad_grid(512, 512);
  int reports = 0;
  const cagekit::TaskMonitor counting([&](const char*, double) { return ++reports, true; }, nullptr);
  const cagekit::SurfaceDistance distance(grid, counting);
  EXPECT_GE(reports, 4);  // before the tree, inside it, before the hints are gathered, before their KD-tree
  uint64_t state = 12345;
  auto uniform = [&](double lo, double hi) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return lo + (hi - lo) * double(state >> 11) / double(1ull << 53);
  };
  for (int i = 0; i < 2000; ++i) {
    const Vec3 q{uniform(-40, 552), uniform(-40, 552), uniform(-30, 30)};
    const Vec3 foot{std::clamp(q.x, 0.0, 512.0), std::clamp(q.y, 0.0, 512.0), 0.0};
    ASSERT_NEAR(distance.distance(q), cagekit::norm(q - foot), 1e-9) << q.x << " " << q.y << " " << q.z;
    ASSERT_NEAR(cagekit::norm(distance.closest_point(q) - foot), 0.0, 1e-9) << q.x << " " << q.y << " " << q.z;
  }
  // And a cancel at the report before the hints' KD-tree still ends in Error(cancelled).
  int seen = 0;
  const cagekit::TaskMonitor cancelling([&](const char*, double) { return ++seen < reports; }, nullptr);
  EXPECT_THROW(
      {
        try {
          const cagekit::SurfaceDistance cancelled(grid, cancelling);
        } catch (const cagekit::Error& e) {
          EXPECT_EQ(e.status(), cagekit::Status::cancelled);
          throw;
        }
      },
      cagekit::Error);
}
