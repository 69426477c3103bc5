// SPDX-License-Identifier: GPL-3.0-or-later
// LimitPatches: the limit surface as bicubic Bezier patches for CAD kernels (hosts issue,
// deliverable 3): exact where the surface is polynomial, within the tolerance elsewhere, squares
// that tile every ptex face, creases on patch borders.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "core/status.h"
#include "subdiv/limit_patches.h"
#include "subdiv/subdivision_surface.h"
#include "test_support.h"

namespace {

using cagekit::Cage;
using cagekit::LimitPatch;
using cagekit::LimitPatches;
using cagekit::LimitPatchOptions;
using cagekit::PolygonMesh;
using cagekit::Status;
using cagekit::SubdivisionSurface;
using cagekit::Vec3;
using cagekit_test::status_of;

using cagekit_test::cage_of;
using cagekit_test::quad_torus;

// The unit cube with only the 4 edges of its top face (z = 1) creased: its top corners are crease
// vertices of valence 3, where the surface uses Gregory end caps.
Cage top_creased_cube() {
  Cage c = cage_of(cagekit_test::unit_cube_quads());
  for (uint32_t f = 0; f < c.mesh.num_faces(); ++f) {
    const uint32_t n = c.mesh.face_size(f);
    bool top = true;
    for (uint32_t i = 0; i < n; ++i) top = top && c.mesh.positions[c.mesh.face_vertex(f, i)].z == 1.0;
    if (!top) continue;
    for (uint32_t i = 0; i < n; ++i)
      c.creases.push_back({c.mesh.face_vertex(f, i), c.mesh.face_vertex(f, (i + 1) % n)});
  }
  return c;
}

struct NamedCage {
  std::string name;
  Cage cage;
};

std::vector<NamedCage> test_cages() {
  std::vector<NamedCage> cages;
  cages.push_back({"cube (valence-3 Stam patches)", cage_of(cagekit_test::unit_cube_quads())});
  cages.push_back({"creased cube (Gregory end caps, sharp edges)", cagekit_test::creased_unit_cube()});
  cages.push_back({"cube with a creased top face (Gregory end caps at crease vertices)", top_creased_cube()});
  cages.push_back({"triangle sphere (n-gon ptex faces, valence 3/4/6)", cage_of(cagekit_test::triangle_sphere(1))});
  cages.push_back({"open grid (boundary)", cage_of(cagekit_test::quad_grid(4, 3, [](double x, double y) {
                     return 0.3 * std::sin(x) * std::cos(0.7 * y);
                   }))});
  cages.push_back({"torus (all regular)", cage_of(quad_torus(8, 6))});
  return cages;
}

double patch_area(const LimitPatch& p) { return (p.u1 - p.u0) * (p.v1 - p.v0); }

TEST(LimitPatches, exact_where_polynomial_within_tolerance_elsewhere_and_tiling_every_ptex_face) {
  for (const NamedCage& k : test_cages()) {
    LimitPatchOptions options;
    options.tolerance = 1e-4;
    const LimitPatches lp = cagekit::build_limit_patches(k.cage, options);
    const SubdivisionSurface surface(k.cage, cagekit::limit_patch_surface_options());
    std::cout << k.name << ": " << lp.patches.size() << " patches (" << lp.exact_count << " exact, "
              << lp.approximated_count << " approximated), max error / diagonal " << lp.max_error / lp.bbox_diagonal
              << "\n";
    ASSERT_EQ(lp.patches.size(), size_t(lp.exact_count) + lp.approximated_count) << k.name;
    EXPECT_GT(lp.exact_count, 0u) << k.name;
    EXPECT_EQ(lp.over_tolerance_count, 0u) << k.name;
    EXPECT_LE(lp.max_error, lp.tolerance) << k.name;
    EXPECT_NEAR(lp.tolerance, 1e-4 * lp.bbox_diagonal, 1e-15);

    // The squares tile each ptex face: dyadic squares inside [0,1]^2 whose areas sum to 1 (the
    // quadtree never emits overlapping squares, so area 1 means full coverage).
    std::vector<double> area(surface.num_ptex_faces(), 0.0);
    for (const LimitPatch& p : lp.patches) {
      ASSERT_LT(p.ptex_face, surface.num_ptex_faces());
      EXPECT_EQ(p.cage_face, surface.base_face_of_ptex(p.ptex_face));
      EXPECT_GE(p.u0, 0.0);
      EXPECT_GE(p.v0, 0.0);
      EXPECT_LE(p.u1, 1.0);
      EXPECT_LE(p.v1, 1.0);
      EXPECT_DOUBLE_EQ(p.u1 - p.u0, p.v1 - p.v0);
      area[p.ptex_face] += patch_area(p);
    }
    for (uint32_t f = 0; f < surface.num_ptex_faces(); ++f) EXPECT_NEAR(area[f], 1.0, 1e-12) << k.name << " " << f;

    // Off the sample grid: exact patches to rounding, approximated ones near their error,
    // including their borders (where sharp creases and neighbouring patches are).
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    double worst_exact = 0, worst_approx = 0;
    for (const LimitPatch& p : lp.patches)
      for (int trial = 0; trial < 12; ++trial) {
        double s = unit(rng), t = unit(rng);
        if (trial < 4) (trial % 2 ? s : t) = double(trial / 2);  // on a border
        const Vec3 x = cagekit::evaluate_limit_patch(p, s, t);
        const Vec3 y = surface.evaluate(p.ptex_face, p.u0 + s * (p.u1 - p.u0), p.v0 + t * (p.v1 - p.v0)).position;
        const double e = cagekit::distance(x, y) / lp.bbox_diagonal;
        (p.exact ? worst_exact : worst_approx) = std::max(p.exact ? worst_exact : worst_approx, e);
      }
    std::cout << "  off-grid error / diagonal: exact " << worst_exact << ", approximated " << worst_approx << "\n";
    EXPECT_LT(worst_exact, 1e-12) << k.name;
    EXPECT_LT(worst_approx, 1.5e-4) << k.name;
    for (const LimitPatch& p : lp.patches)
      if (p.exact) {
        EXPECT_LT(p.error, 1e-12 * lp.bbox_diagonal) << k.name;
      }
  }
}

TEST(LimitPatches, all_regular_torus_is_one_exact_patch_per_face) {
  const Cage torus = cage_of(quad_torus(8, 6));
  const LimitPatches lp = cagekit::build_limit_patches(torus, LimitPatchOptions());
  EXPECT_EQ(lp.patches.size(), torus.mesh.num_faces());
  EXPECT_EQ(lp.approximated_count, 0u);
  EXPECT_EQ(lp.max_error, 0.0);
}

TEST(LimitPatches, tighter_tolerance_gives_more_patches_and_smaller_error) {
  const Cage cube = cage_of(cagekit_test::unit_cube_quads());
  size_t previous_count = 0;
  double previous_error = 1e300;
  for (double tol : {1e-2, 1e-3, 1e-4, 1e-5}) {
    LimitPatchOptions options;
    options.tolerance = tol;
    const LimitPatches lp = cagekit::build_limit_patches(cube, options);
    std::cout << "cube tolerance " << tol << ": " << lp.patches.size() << " patches, max error / diagonal "
              << lp.max_error / lp.bbox_diagonal << "\n";
    EXPECT_LE(lp.max_error, tol * lp.bbox_diagonal);
    EXPECT_GE(lp.patches.size(), previous_count);
    EXPECT_LE(lp.max_error, previous_error);
    previous_count = lp.patches.size();
    previous_error = lp.max_error;
  }
  EXPECT_GT(previous_count, 24u * 4u);  // the Stam squares were split
}

TEST(LimitPatches, shared_borders_meet_within_twice_the_tolerance) {
  // Neighbouring patches of one ptex face: the patch points at matching border locations.
  for (const NamedCage& k : test_cages()) {
    LimitPatchOptions options;
    options.tolerance = 1e-4;
    const LimitPatches lp = cagekit::build_limit_patches(k.cage, options);
    double worst = 0;
    size_t checked = 0;
    for (const LimitPatch& a : lp.patches)
      for (const LimitPatch& b : lp.patches) {
        if (&a == &b || a.ptex_face != b.ptex_face || a.u1 != b.u0) continue;  // b right of a
        const double lo = std::max(a.v0, b.v0), hi = std::min(a.v1, b.v1);
        if (!(hi > lo)) continue;
        for (int i = 0; i <= 8; ++i) {
          const double v = lo + (hi - lo) * i / 8.0;
          const Vec3 pa = cagekit::evaluate_limit_patch(a, 1.0, (v - a.v0) / (a.v1 - a.v0));
          const Vec3 pb = cagekit::evaluate_limit_patch(b, 0.0, (v - b.v0) / (b.v1 - b.v0));
          worst = std::max(worst, cagekit::distance(pa, pb));
          ++checked;
        }
      }
    std::cout << k.name << ": " << checked << " border points, largest gap / diagonal " << worst / lp.bbox_diagonal
              << "\n";
    EXPECT_LE(worst, 2 * lp.tolerance) << k.name;
    if (lp.approximated_count > 0) {
      EXPECT_GT(checked, 100u) << k.name;
    }
  }
}

TEST(LimitPatches, results_do_not_depend_on_threads) {
  const Cage cage = cage_of(cagekit_test::triangle_sphere(1));
  LimitPatchOptions one, two;
  two.threads = 2;
  const LimitPatches a = cagekit::build_limit_patches(cage, one), b = cagekit::build_limit_patches(cage, two);
  ASSERT_EQ(a.patches.size(), b.patches.size());
  for (size_t i = 0; i < a.patches.size(); ++i) {
    EXPECT_EQ(a.patches[i].ptex_face, b.patches[i].ptex_face);
    EXPECT_EQ(a.patches[i].u0, b.patches[i].u0);
    EXPECT_EQ(a.patches[i].v0, b.patches[i].v0);
    for (int k = 0; k < 16; ++k) EXPECT_EQ(a.patches[i].points[k].x, b.patches[i].points[k].x);
  }
}

TEST(LimitPatches, bad_options_limits_and_cancellation) {
  const Cage cube = cage_of(cagekit_test::unit_cube_quads());
  auto with = [&](auto&& set) {
    LimitPatchOptions o;
    set(o);
    return status_of([&] { cagekit::build_limit_patches(cube, o); });
  };
  EXPECT_EQ(with([](LimitPatchOptions& o) { o.tolerance = 0; }), Status::invalid_argument);
  EXPECT_EQ(with([](LimitPatchOptions& o) { o.tolerance = -1; }), Status::invalid_argument);
  EXPECT_EQ(with([](LimitPatchOptions& o) { o.tolerance = std::nan(""); }), Status::invalid_argument);
  EXPECT_EQ(with([](LimitPatchOptions& o) { o.tolerance = INFINITY; }), Status::invalid_argument);
  EXPECT_EQ(with([](LimitPatchOptions& o) { o.max_depth = -1; }), Status::invalid_argument);
  EXPECT_EQ(with([](LimitPatchOptions& o) { o.max_depth = cagekit::kMaxLimitPatchDepth + 1; }),
            Status::invalid_argument);
  EXPECT_EQ(with([](LimitPatchOptions& o) { o.threads = 0; }), Status::invalid_argument);
  EXPECT_EQ(with([](LimitPatchOptions& o) { o.max_patches = 0; }), Status::invalid_argument);
  EXPECT_EQ(with([](LimitPatchOptions& o) {
              o.tolerance = 1e-12;
              o.max_patches = 50;
            }),
            Status::limit_exceeded);
  EXPECT_EQ(with([](LimitPatchOptions& o) {
              o.tolerance = 1e-12;
              o.max_patches = 50;
              o.threads = 2;
            }),
            Status::limit_exceeded);
  // A cage with a NaN position is refused by the surface.
  Cage bad = cube;
  bad.mesh.positions[3].y = std::nan("");
  EXPECT_NE(status_of([&] { cagekit::build_limit_patches(bad, LimitPatchOptions()); }), Status::success);

  int calls = 0;
  const cagekit::TaskMonitor cancel_later(
      [&](const char*, double) { return ++calls < 5; }, nullptr);
  LimitPatchOptions tight;
  tight.tolerance = 1e-9;
  tight.threads = 2;
  EXPECT_EQ(status_of([&] { cagekit::build_limit_patches(cube, tight, cancel_later); }), Status::cancelled);
  EXPECT_EQ(calls, 5);
}

}  // namespace
