// SPDX-License-Identifier: GPL-3.0-or-later
// Fitting layer (thesis ch. 7): closest points on the limit surface (§7.4), least-squares
// control-vertex step (§7.5) and the alternating fit (§7.2).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include "core/status.h"
#include "fit/closest_point_on_limit_surface.h"
#include "fit/least_squares_system.h"
#include "fit/ptex_adjacency.h"
#include "fit/surface_fitter.h"
#include "layout/cage_builder.h"
#include "layout/face_merge_simplifier.h"
#include "subdiv/subdivision_surface.h"
#include "test_support.h"

using namespace cagekit;

namespace {

// A cube cage centred at the origin with half-size `half` (all vertices valence 3:
// extraordinary, evaluated exactly by Stam's method).
Cage centred_cube(double half) {
  Cage cage;
  cage.mesh = cagekit_test::unit_cube_quads();
  for (Vec3& p : cage.mesh.positions) p = (p - Vec3{0.5, 0.5, 0.5}) * (2 * half);
  return cage;
}

// A cube cage refined once by hand into 24 quads with a bumpy shape: regular and
// extraordinary vertices, non-symmetric geometry.
Cage bumpy_cage() {
  const Cage cage = centred_cube(0.5);
  // The 26-vertex cage of the cube split 2x2 per face.
  Cage out;
  std::vector<Vec3> pts;
  auto index_of = [&](const Vec3& p) {
    for (size_t i = 0; i < pts.size(); ++i)
      if (distance(pts[i], p) < 1e-9) return uint32_t(i);
    pts.push_back(p);
    return uint32_t(pts.size() - 1);
  };
  const PolygonMesh& cube = cage.mesh;
  for (size_t f = 0; f < cube.num_faces(); ++f) {
    const Vec3 a = cube.positions[cube.face_vertex(f, 0)], b = cube.positions[cube.face_vertex(f, 1)],
               c = cube.positions[cube.face_vertex(f, 2)], d = cube.positions[cube.face_vertex(f, 3)];
    auto at = [&](double s, double t) { return (1 - s) * (1 - t) * a + s * (1 - t) * b + s * t * c + (1 - s) * t * d; };
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        out.mesh.add_face({index_of(at(i * 0.5, j * 0.5)), index_of(at((i + 1) * 0.5, j * 0.5)),
                           index_of(at((i + 1) * 0.5, (j + 1) * 0.5)), index_of(at(i * 0.5, (j + 1) * 0.5))});
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.08, 0.08);
  for (Vec3& p : pts) p = p + Vec3{jitter(rng), jitter(rng), jitter(rng)} + Vec3{0.3 * p.x * p.y, 0, 0};
  out.mesh.positions = pts;
  return out;
}

struct Sample {
  uint32_t face;
  double u, v;
};

std::vector<Sample> random_parameters(const SubdivisionSurface& surface, size_t count, double margin,
                                      unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<uint32_t> face(0, surface.num_ptex_faces() - 1);
  std::uniform_real_distribution<double> uv(margin, 1 - margin);
  std::vector<Sample> out(count);
  for (Sample& s : out) s = {face(rng), uv(rng), uv(rng)};
  return out;
}

}  // namespace

// (d) Points offset along the normal come back to their parameter and offset.
TEST(FitClosestPoint, normal_offsets_project_back_to_their_parameter) {
  const Cage cage = bumpy_cage();
  const SubdivisionSurface surface(cage);
  const PtexAdjacency adjacency(cage.mesh, surface);
  const LimitSurfaceProjector projector(surface, &adjacency, cage.mesh.positions);
  double worst_t = 0, worst_d = 0;
  for (const Sample& s : random_parameters(surface, 300, 0.05, 11)) {
    const SurfacePoint sp = surface.evaluate(s.face, s.u, s.v);
    const Vec3 n = normalized(cross(sp.du, sp.dv));
    for (double d : {1e-3, -1e-3, 0.0}) {
      const FootPoint foot = projector.project(sp.position + d * n);
      ASSERT_EQ(foot.ptex_face, s.face);
      worst_t = std::max({worst_t, std::abs(foot.u - s.u), std::abs(foot.v - s.v)});
      worst_d = std::max(worst_d, std::abs(foot.distance - std::abs(d)));
    }
  }
  std::printf("closest point: worst parameter error %.3g, worst distance error %.3g\n", worst_t, worst_d);
  EXPECT_LT(worst_t, 1e-8);
  EXPECT_LT(worst_d, 1e-10);
}

// (a) Samples on a known limit surface, cage perturbed.
struct KnownSurface {
  Cage truth, initial;
  std::vector<Sample> parameters;
  std::vector<Vec3> samples;
};

KnownSurface known_surface() {
  KnownSurface k;
  k.truth = bumpy_cage();
  const SubdivisionSurface surface(k.truth);
  k.parameters = random_parameters(surface, 1500, 0.0, 3);
  for (const Sample& s : k.parameters) k.samples.push_back(surface.evaluate(s.face, s.u, s.v).position);
  k.initial = k.truth;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-0.03, 0.03);
  for (Vec3& p : k.initial.mesh.positions) p = p + Vec3{jitter(rng), jitter(rng), jitter(rng)};
  return k;
}

double worst_control_error(const Cage& a, const Cage& b) {
  double worst = 0;
  for (size_t i = 0; i < a.mesh.num_vertices(); ++i)
    worst = std::max(worst, distance(a.mesh.positions[i], b.mesh.positions[i]));
  return worst;
}

// (a) With the tangential part of the residuals dropped (tangential_weight = 0: tangent-distance
// steps, Gauss-Newton-like), the fit recovers the control points (quadratic convergence measured:
// 1.8e-11 after 6 steps; weight 1e-4: 2.8e-5 after 10, weight 0.01: 0.019 after 10).
TEST(FitSurface, tangent_weighted_fit_recovers_the_control_points_of_a_known_surface) {
  const KnownSurface k = known_surface();
  FitOptions options;
  options.fairing = 0;
  options.tangential_weight = 0.0;
  options.max_passes = 6;
  options.tolerance = 0;
  FitReport report;
  const Cage fitted = fit_cage_to_points(k.initial, k.samples, options, &report);
  for (size_t i = 0; i < report.passes.size(); ++i)
    std::printf("known surface, tangent-weighted: iteration %zu rms %.3g max %.3g (relative)\n", i,
                report.passes[i].rms_relative, report.passes[i].max_relative);
  const double worst = worst_control_error(fitted, k.truth);
  std::printf("known surface, tangent-weighted: worst control-point error %.3g, %.2f s\n", worst, report.seconds);
  EXPECT_LT(worst, 1e-6);
  EXPECT_LT(report.passes.back().max_relative, 1e-7);
}

// The control-vertex step alone, at the true foot points, is exact.
TEST(FitSurface, least_squares_step_at_the_true_parameters_recovers_the_control_points) {
  const KnownSurface k = known_surface();
  const SubdivisionSurface surface(k.initial);
  std::vector<FootPoint> feet;
  for (const Sample& s : k.parameters) {
    FootPoint f;
    f.ptex_face = s.face;
    f.u = s.u;
    f.v = s.v;
    feet.push_back(f);
  }
  Cage solved = k.initial;
  solved.mesh.positions = solve_control_points(surface, k.initial, k.initial.mesh.positions, k.samples, feet,
                                               std::vector<bool>(k.initial.mesh.num_vertices(), false), {});
  const double worst = worst_control_error(solved, k.truth);
  std::printf("least squares at the true parameters: worst control-point error %.3g\n", worst);
  EXPECT_LT(worst, 1e-8);
}

// The alternating fit (thesis §7.2) from a perturbed cage: monotone, and it approaches the truth.
TEST(FitSurface, alternating_fit_approaches_a_known_surface) {
  const KnownSurface k = known_surface();
  FitOptions options;
  options.fairing = 0;
  options.max_passes = 10;
  options.tolerance = 0;
  FitReport report;
  const Cage fitted = fit_cage_to_points(k.initial, k.samples, options, &report);
  for (size_t i = 0; i < report.passes.size(); ++i)
    std::printf("known surface: iteration %zu rms %.3g max %.3g (relative)\n", i, report.passes[i].rms_relative,
                report.passes[i].max_relative);
  const double before = worst_control_error(k.initial, k.truth), after = worst_control_error(fitted, k.truth);
  std::printf("known surface: worst control-point error %.3g -> %.3g, %.2f s\n", before, after, report.seconds);
  for (size_t i = 1; i < report.passes.size(); ++i)
    EXPECT_LE(report.passes[i].rms_relative, report.passes[i - 1].rms_relative * (1 + 1e-9) + 1e-15);
  // The distance drops; the control points do not converge to the truth within 10 steps: the
  // point-distance alternation converges linearly and slowly, and tangential sliding of the
  // control points barely changes the surface (printed, not asserted).
  EXPECT_LT(report.passes.back().rms_relative, 0.15 * report.passes.front().rms_relative);
  EXPECT_LT(report.passes.back().max_relative, 0.25 * report.passes.front().max_relative);
}

// (b) A unit sphere fitted from a cube cage of half-size 0.6.
TEST(FitSurface, sphere_from_a_cube_cage) {
  const PolygonMesh sphere = cagekit_test::triangle_sphere(5);
  const std::vector<Vec3>& samples = sphere.positions;
  FitReport report;
  FitOptions options;
  options.tolerance = 0;
  const Cage fitted = fit_cage_to_points(centred_cube(0.6), samples, options, &report);
  ASSERT_EQ(report.passes.size(), 6u);
  for (size_t k = 0; k < report.passes.size(); ++k)
    std::printf("sphere (%zu samples): iteration %zu rms %.4g%% max %.4g%% of the bbox diagonal\n",
                samples.size(), k, 100 * report.passes[k].rms_relative, 100 * report.passes[k].max_relative);
  std::printf("sphere: %.2f s\n", report.seconds);
  // Measured: 14.33% -> 0.5202% -> 0.4948% and then flat (to 4 digits) with the default options.
  for (size_t k = 1; k < report.passes.size(); ++k) {
    EXPECT_LE(report.passes[k].max_relative, report.passes[k - 1].max_relative * (1 + 1e-9));
    EXPECT_LE(report.passes[k].rms_relative, report.passes[k - 1].rms_relative * (1 + 1e-9));
  }
  EXPECT_LT(report.passes[1].max_relative, 0.1 * report.passes[0].max_relative);
  EXPECT_LT(report.passes.back().max_relative, 0.006);
  EXPECT_EQ(fitted.mesh.num_faces(), 6u);
}

// (c) A real scan: a cage from the simplifier fitted to the scan's vertices. Face budget 310 gives
// a 562-face / 616-vertex cage (the thesis: 612 vertices, 5 steps, 0.81% max deviation; measured
// here 0.67% max, 0.123% rms of the bbox diagonal).
TEST(FitSurface, bunny_cage_from_the_simplifier) {
  const std::string path = cagekit_test::shared_mesh_path("stanford-bunny.obj");
  if (path.empty()) GTEST_SKIP() << "../shared/meshes/stanford-bunny.obj not present";
  const PolygonMesh scan = cagekit_test::load_mesh(path);
  SimplificationHierarchy hierarchy(scan);
  hierarchy.go_to_level(hierarchy.level_for_face_count(310));
  const Cage cage = build_quad_dominant_cage(scan, hierarchy.extract());
  FitReport report;
  const Cage fitted = fit_cage_to_points(cage, scan.positions, {}, &report);
  std::printf("bunny: cage %zu faces / %zu vertices, %zu samples\n", cage.mesh.num_faces(),
              cage.mesh.num_vertices(), scan.positions.size());
  for (size_t k = 0; k < report.passes.size(); ++k)
    std::printf("bunny: iteration %zu rms %.4g%% max %.4g%% (thesis: 612 vertices, 5 steps: max 0.81%%), %.2f s\n",
                k, 100 * report.passes[k].rms_relative, 100 * report.passes[k].max_relative, report.passes[k].seconds);
  std::printf("bunny: thesis L2 (7.1) %.4g -> %.4g (thesis, its own scan and scale: 46.2), %.2f s total\n",
              report.passes.front().l2, report.passes.back().l2, report.seconds);
  for (size_t k = 1; k < report.passes.size(); ++k) EXPECT_LT(report.passes[k].rms_relative, report.passes[k - 1].rms_relative);
  EXPECT_LT(report.passes.back().max_relative, report.passes.front().max_relative);
  EXPECT_LT(report.passes.back().rms_relative, 0.5 * report.passes.front().rms_relative);
  EXPECT_LT(report.passes.back().max_relative, 0.0081);
  EXPECT_EQ(fitted.mesh.num_vertices(), cage.mesh.num_vertices());
}

TEST(FitSurface, crease_vertices_can_be_kept_on_their_samples) {
  const KnownSurface k = known_surface();
  Cage initial = k.initial;
  const uint32_t a = initial.mesh.face_vertex(0, 0), b = initial.mesh.face_vertex(0, 1);
  initial.creases.push_back({a, b, kSharpnessInfinite});
  FitOptions options;
  options.max_passes = 2;
  options.tolerance = 0;
  options.keep_crease_vertices_on_samples = true;
  const Cage fitted = fit_cage_to_points(initial, k.samples, options);
  EXPECT_EQ(fitted.mesh.positions[a], initial.mesh.positions[a]);
  EXPECT_EQ(fitted.mesh.positions[b], initial.mesh.positions[b]);
  size_t moved = 0;
  for (size_t i = 0; i < initial.mesh.num_vertices(); ++i) moved += fitted.mesh.positions[i] != initial.mesh.positions[i];
  EXPECT_EQ(moved, initial.mesh.num_vertices() - 2);
  EXPECT_EQ(fitted.creases.size(), 1u);
}

TEST(FitSurface, result_does_not_depend_on_the_thread_count) {
  const std::vector<Vec3> samples = cagekit_test::triangle_sphere(3).positions;
  FitOptions one, many;
  one.threads = 1;
  many.threads = 3;
  FitReport r1, r3;
  const Cage a = fit_cage_to_points(centred_cube(0.6), samples, one, &r1);
  const Cage b = fit_cage_to_points(centred_cube(0.6), samples, many, &r3);
  EXPECT_EQ(a.mesh.positions, b.mesh.positions);
  ASSERT_EQ(r1.passes.size(), r3.passes.size());
  for (size_t k = 0; k < r1.passes.size(); ++k) EXPECT_EQ(r1.passes[k].l2, r3.passes[k].l2);
}

TEST(FitSurface, cancel_and_bad_input) {
  const Cage cube = centred_cube(0.6);
  const std::vector<Vec3> samples = cagekit_test::triangle_sphere(2).positions;
  const TaskMonitor cancel([](const char*, double) { return false; }, nullptr);
  try {
    fit_cage_to_points(cube, samples, {}, nullptr, cancel);
    FAIL() << "not cancelled";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), Status::cancelled);
  }
  try {
    fit_cage_to_points(cube, {}, {});
    FAIL() << "empty samples accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), Status::invalid_argument);
  }
  FitOptions bad;
  bad.fairing = -1;
  EXPECT_THROW(fit_cage_to_points(cube, samples, bad), Error);
  FitOptions bad_weight;
  bad_weight.tangential_weight = 2;
  EXPECT_THROW(fit_cage_to_points(cube, samples, bad_weight), Error);
}
