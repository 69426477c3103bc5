// SPDX-License-Identifier: GPL-3.0-or-later
// samples/step_export (issue 25, deliverable 4): the SDK's B-spline surfaces (one per ptex face)
// through OpenCASCADE: faces -> sewn shell -> outward solid when closed -> STEP -> read back with
// the same face count, validity, and every sampled surface / limit point on the read shape.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "pipeline/scan_to_cage.h"
#include "step_export.h"
#include "subdiv/limit_bspline_surfaces.h"
#include "subdiv/subdivision_surface.h"
#include "test_support.h"
#include "../sanitizer/sanitized_build.h"

namespace {

using cagekit::Cage;
using cagekit::LimitBSplineOptions;
using cagekit::LimitBSplineSurface;
using cagekit::LimitBSplineSurfaces;
using cagekit::SubdivisionSurface;

std::vector<cagekit_step::BSplineSurface> plain(const LimitBSplineSurfaces& r) {
  std::vector<cagekit_step::BSplineSurface> out;
  for (const LimitBSplineSurface& s : r.surfaces) {
    cagekit_step::BSplineSurface p;
    p.degree_u = s.degree_u;
    p.degree_v = s.degree_v;
    p.knots_u = s.knots_u;
    p.knots_v = s.knots_v;
    p.num_u = s.num_u;
    p.num_v = s.num_v;
    for (const cagekit::Vec3& q : s.points) p.points.insert(p.points.end(), {q.x, q.y, q.z});
    out.push_back(std::move(p));
  }
  return out;
}

std::string temp_path(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(CAGEKIT_BINARY_DIR) / "test_step_export_out";
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

// An n x n grid of parameters per surface: the B-spline surface's points (through the plain data,
// independent of the SDK's evaluator) and the limit surface's points.
void samples(const LimitBSplineSurfaces& r, const std::vector<cagekit_step::BSplineSurface>& data,
             const SubdivisionSurface& limit, int n, std::vector<std::array<double, 3>>& on_surfaces,
             std::vector<std::array<double, 3>>& on_limit) {
  for (size_t k = 0; k < r.surfaces.size(); ++k)
    for (int b = 0; b < n; ++b)
      for (int a = 0; a < n; ++a) {
        const double u = double(a) / (n - 1), v = double(b) / (n - 1);
        std::array<double, 3> p;
        ASSERT_TRUE(cagekit_step::evaluate(data[k], u, v, p));
        const cagekit::Vec3 sdk = cagekit::evaluate_bspline_surface(r.surfaces[k], u, v).position;
        ASSERT_NEAR(p[0], sdk.x, 1e-12 * r.bbox_diagonal);
        ASSERT_NEAR(p[1], sdk.y, 1e-12 * r.bbox_diagonal);
        ASSERT_NEAR(p[2], sdk.z, 1e-12 * r.bbox_diagonal);
        on_surfaces.push_back(p);
        const cagekit::Vec3 q = limit.evaluate(r.surfaces[k].ptex_face, u, v).position;
        on_limit.push_back({q.x, q.y, q.z});
      }
}

struct RoundTrip {
  cagekit_step::WriteReport written;
  cagekit_step::ReadReport surfaces, limit;
};

// Builds the surfaces at `tolerance`, writes them as STEP, reads them back twice (distances to
// the surfaces' samples and to the limit surface's samples).
// n x n samples per surface (the distance queries dominate on large files).
RoundTrip round_trip(const Cage& cage, double tolerance, const std::string& name, LimitBSplineSurfaces& r,
                     int n = 9) {
  LimitBSplineOptions options;
  options.tolerance = tolerance;
  r = cagekit::build_limit_bspline_surfaces(cage, options);
  const std::vector<cagekit_step::BSplineSurface> data = plain(r);
  cagekit_step::WriteOptions write;
  write.sewing_tolerance = 1e-7 * r.bbox_diagonal;
  RoundTrip t;
  const std::string path = temp_path(name + ".step");
  t.written = cagekit_step::write_step(data, path, write);
  const SubdivisionSurface limit(cage);
  std::vector<std::array<double, 3>> on_surfaces, on_limit;
  samples(r, data, limit, n, on_surfaces, on_limit);
  if (t.written.ok) {
    t.surfaces = cagekit_step::read_step(path, on_surfaces);
    t.limit = cagekit_step::read_step(path, on_limit);
  }
  std::printf("%s: %zu surfaces (error %.3g of the diagonal) -> %u faces, %u free edges, %u shells, closed %d, "
              "solid %d, valid %d, %llu bytes, sewing %.3f s, write %.3f s; read back: %u faces, %u solids, valid %d, "
              "max distance to the surfaces' samples %.3g, to the limit's %.3g of the diagonal (%u points)\n",
              name.c_str(), r.surfaces.size(), r.max_error / r.bbox_diagonal, t.written.faces, t.written.free_edges,
              t.written.shells, t.written.closed, t.written.solid, t.written.valid,
              static_cast<unsigned long long>(t.written.bytes), t.written.sewing_seconds, t.written.write_seconds,
              t.surfaces.faces, t.surfaces.solids, t.surfaces.valid, t.surfaces.max_distance / r.bbox_diagonal,
              t.limit.max_distance / r.bbox_diagonal, t.limit.points_checked);
  return t;
}

void expect_closed_valid_solid(const RoundTrip& t, const LimitBSplineSurfaces& r) {
  ASSERT_TRUE(t.written.ok) << t.written.error;
  EXPECT_EQ(t.written.faces, r.surfaces.size());
  EXPECT_EQ(t.written.free_edges, 0u);
  EXPECT_EQ(t.written.multiple_edges, 0u);
  EXPECT_EQ(t.written.shells, 1u);
  EXPECT_TRUE(t.written.closed);
  EXPECT_TRUE(t.written.solid);
  EXPECT_TRUE(t.written.valid);
  EXPECT_GT(t.written.bytes, 0u);
  ASSERT_TRUE(t.surfaces.ok) << t.surfaces.error;
  ASSERT_TRUE(t.limit.ok) << t.limit.error;
  EXPECT_EQ(t.surfaces.faces, r.surfaces.size());
  EXPECT_EQ(t.surfaces.solids, 1u);
  EXPECT_TRUE(t.surfaces.valid);
  EXPECT_EQ(t.surfaces.points_checked, r.surfaces.size() * 81);
  // The surfaces travel exactly (STEP writes 15+ significant digits).
  EXPECT_LE(t.surfaces.max_distance, 1e-7 * r.bbox_diagonal);
  // The limit surface is within the build's measured error (itself within the tolerance).
  EXPECT_LE(t.limit.max_distance, r.max_error + 1e-7 * r.bbox_diagonal);
  EXPECT_LE(t.limit.max_distance, r.tolerance + 1e-7 * r.bbox_diagonal);
}

TEST(StepExport, all_regular_torus_is_a_valid_closed_solid_and_reads_back) {
  const Cage torus = cagekit_test::cage_of(cagekit_test::quad_torus(8, 6));
  LimitBSplineSurfaces r;
  const RoundTrip t = round_trip(torus, 1e-4, "torus", r);
  ASSERT_EQ(r.surfaces.size(), 48u);
  expect_closed_valid_solid(t, r);
  EXPECT_LE(t.limit.max_distance, 1e-7 * r.bbox_diagonal);  // every surface is exact
}

TEST(StepExport, cube_smooth_and_creased_are_valid_closed_solids) {
  LimitBSplineSurfaces r;
  const RoundTrip smooth = round_trip(cagekit_test::cage_of(cagekit_test::unit_cube_quads()), 1e-3, "cube", r);
  ASSERT_EQ(r.surfaces.size(), 6u);
  expect_closed_valid_solid(smooth, r);
  const RoundTrip creased = round_trip(cagekit_test::creased_unit_cube(), 1e-4, "creased_cube", r);
  ASSERT_EQ(r.surfaces.size(), 6u);
  expect_closed_valid_solid(creased, r);
}

TEST(StepExport, torus_with_triangles_has_one_face_per_ptex_face) {
  // Two triangles: n-gon sub-faces next to quads (a quad side meets two sub-faces, split at its
  // middle by the sewing).
  const Cage torus = cagekit_test::cage_of(cagekit_test::quad_torus(8, 6, true));
  uint32_t ptex = 0;
  for (uint32_t f = 0; f < torus.mesh.num_faces(); ++f)
    ptex += torus.mesh.face_size(f) == 4 ? 1 : torus.mesh.face_size(f);
  LimitBSplineSurfaces r;
  const RoundTrip t = round_trip(torus, 1e-4, "torus_tri", r);
  ASSERT_EQ(r.surfaces.size(), ptex);
  expect_closed_valid_solid(t, r);
}

TEST(StepExport, open_grid_is_an_open_valid_shell_without_solid) {
  const Cage grid = cagekit_test::cage_of(
      cagekit_test::quad_grid(4, 3, [](double x, double y) { return 0.3 * std::sin(x) * std::cos(0.7 * y); }));
  LimitBSplineSurfaces r;
  const RoundTrip t = round_trip(grid, 1e-4, "grid", r);
  ASSERT_TRUE(t.written.ok) << t.written.error;
  ASSERT_EQ(r.surfaces.size(), 12u);
  EXPECT_EQ(t.written.faces, 12u);
  EXPECT_EQ(t.written.free_edges, 2u * (4 + 3));  // the boundary
  EXPECT_EQ(t.written.shells, 1u);
  EXPECT_FALSE(t.written.closed);
  EXPECT_FALSE(t.written.solid);
  EXPECT_TRUE(t.written.valid);
  ASSERT_TRUE(t.surfaces.ok) << t.surfaces.error;
  EXPECT_EQ(t.surfaces.faces, 12u);
  EXPECT_EQ(t.surfaces.solids, 0u);
  EXPECT_EQ(t.surfaces.shells, 1u);
  EXPECT_TRUE(t.surfaces.valid);
  EXPECT_LE(t.surfaces.max_distance, 1e-7 * r.bbox_diagonal);
  EXPECT_LE(t.limit.max_distance, r.max_error + 1e-7 * r.bbox_diagonal);
}

TEST(StepExport, bad_input_is_reported_not_thrown) {
  cagekit_step::BSplineSurface s;
  s.knots_u = {0, 0, 0, 0, 1, 1, 1, 1};
  s.knots_v = s.knots_u;
  s.num_u = s.num_v = 4;
  s.points.assign(3 * 16, 0.0);
  for (uint32_t j = 0; j < 4; ++j)
    for (uint32_t i = 0; i < 4; ++i) {
      s.points[3 * (j * 4 + i)] = i;
      s.points[3 * (j * 4 + i) + 1] = j;
    }
  const std::string path = temp_path("bad.step");
  cagekit_step::WriteOptions options;
  EXPECT_TRUE(cagekit_step::write_step({s}, path, options).ok);  // one flat face: an open shell
  cagekit_step::BSplineSurface short_knots = s;
  short_knots.knots_u.pop_back();
  cagekit_step::WriteReport w = cagekit_step::write_step({s, short_knots}, path, options);
  EXPECT_FALSE(w.ok);
  EXPECT_NE(w.error.find("surface 1: u knot vector"), std::string::npos) << w.error;
  cagekit_step::BSplineSurface decreasing = s;
  decreasing.knots_v[5] = 0.5;
  EXPECT_FALSE(cagekit_step::write_step({decreasing}, path, options).ok);
  cagekit_step::BSplineSurface nan_point = s;
  nan_point.points[7] = std::nan("");
  EXPECT_FALSE(cagekit_step::write_step({nan_point}, path, options).ok);
  EXPECT_FALSE(cagekit_step::write_step({}, path, options).ok);
  options.sewing_tolerance = 0;
  EXPECT_FALSE(cagekit_step::write_step({s}, path, options).ok);
  options.sewing_tolerance = 1e-6;
  EXPECT_FALSE(cagekit_step::write_step({s}, temp_path("no_such_folder/x.step"), options).ok);
  const cagekit_step::ReadReport missing = cagekit_step::read_step(temp_path("missing.step"), {});
  EXPECT_FALSE(missing.ok);
  EXPECT_FALSE(missing.error.empty());
}

// The fitted cage of `cagekit pipeline fandisk.obj OUT --faces 200` (the same library call) at
// 1e-3 (the CI tolerance; 1e-4 costs as much again): the figures are printed; only the
// face counts and the round trip are asserted (the current surfaces are known to fold there).
TEST(StepExport, fandisk_pipeline_cage_figures) {
#if CAGEKIT_SANITIZED_BUILD
  GTEST_SKIP() << "Release only";
#endif
  const std::string path = cagekit_test::shared_mesh_path("fandisk.obj");
  if (path.empty()) GTEST_SKIP() << "../shared/meshes/fandisk.obj not present";
  cagekit::ScanToCageOptions options;
  options.target = 200;
  const Cage cage = cagekit::scan_to_cage(cagekit_test::load_mesh(path), options).cage;
  for (double tolerance : {1e-3}) {
    LimitBSplineSurfaces r;
    const auto start = std::chrono::steady_clock::now();
    const RoundTrip t = round_trip(cage, tolerance, tolerance == 1e-3 ? "fandisk_1e-3" : "fandisk_1e-4", r, 3);
    std::printf("  level %d, %u over tolerance, max normal jump %.3g deg, %.2f s in all\n", r.level,
                r.over_tolerance_count, r.max_normal_jump_deg,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    ASSERT_TRUE(t.written.ok) << t.written.error;
    EXPECT_EQ(t.written.faces, r.surfaces.size());
    ASSERT_TRUE(t.surfaces.ok) << t.surfaces.error;
    EXPECT_EQ(t.surfaces.faces, r.surfaces.size());
    EXPECT_LE(t.surfaces.max_distance, 1e-7 * r.bbox_diagonal);
  }
}

}  // namespace
