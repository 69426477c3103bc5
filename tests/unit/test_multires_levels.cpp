// SPDX-License-Identifier: GPL-3.0-or-later
// Multiresolution (thesis Fig. 8.3): the same scan bound to a cage and to that cage refined once
// (the same limit surface, more control points). The two bindings agree, both reproduce the
// scan, and an edit of one fine control point changes a smaller region than one coarse point.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fit/surface_fitter.h"
#include "multires/cpu_deformer.h"
#include "multires/scan_binding.h"
#include "subdiv/uniform_refinement.h"
#include "test_support.h"

using namespace cagekit;

TEST(MultiresLevels, coarse_and_finer_cage_bind_the_same_scan) {
  PolygonMesh scan = cagekit_test::triangle_sphere(4);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> bump(-0.01, 0.01);
  for (Vec3& p : scan.positions) p = p * (1.0 + bump(rng));
  Cage cube;
  cube.mesh = cagekit_test::unit_cube_quads();
  for (Vec3& p : cube.mesh.positions) p = (p - Vec3{0.5, 0.5, 0.5}) * 1.2;
  FitOptions fit;
  fit.max_passes = 3;
  RefineOptions once;
  once.levels = 1;
  const Cage coarse = fit_cage_to_mesh(refine_uniform(cube, once), scan, fit);
  const Cage fine = refine_uniform(coarse, once);  // same limit surface, 4x the faces
  BindOptions options;
  options.mode = DisplacementMode::local_frame;
  const ScanBinding a = bind_scan_to_cage(coarse, scan, options), b = bind_scan_to_cage(fine, scan, options);
  ASSERT_EQ(a.num_vertices(), b.num_vertices());
  const double diagonal = a.bbox_diagonal;
  std::vector<Vec3> pa(a.num_vertices()), pb(pa.size());
  CpuDeformer(a, 1).deform(coarse.mesh.positions, pa.data(), nullptr);
  CpuDeformer(b, 1).deform(fine.mesh.positions, pb.data(), nullptr);
  double worst_a = 0, worst_b = 0, worst_foot = 0, worst_d = 0;
  for (size_t i = 0; i < scan.num_vertices(); ++i) {
    worst_a = std::max(worst_a, norm(pa[i] - scan.positions[i]));
    worst_b = std::max(worst_b, norm(pb[i] - scan.positions[i]));
    worst_foot = std::max(worst_foot, norm(a.foot_points[i].position - b.foot_points[i].position));
    worst_d = std::max(worst_d, std::abs(a.displacement[i] - b.displacement[i]));
  }
  // Local edits: move the control point nearest to (1, 0, 0) on each level by 5% of the diagonal.
  auto moved_vertices = [&](const ScanBinding& binding, const Cage& cage) {
    uint32_t nearest = 0;
    for (uint32_t j = 1; j < cage.mesh.num_vertices(); ++j)
      if (norm(cage.mesh.positions[j] - Vec3{1, 0, 0}) < norm(cage.mesh.positions[nearest] - Vec3{1, 0, 0}))
        nearest = j;
    std::vector<Vec3> control = cage.mesh.positions;
    CpuDeformer deformer(binding, 1);
    std::vector<Vec3> before(binding.num_vertices()), after(before.size());
    deformer.deform(control, before.data(), nullptr);
    control[nearest] += Vec3{0.05 * diagonal, 0, 0};
    deformer.deform(control, after.data(), nullptr);
    size_t count = 0;
    for (size_t i = 0; i < before.size(); ++i) count += norm(after[i] - before[i]) > 1e-12 * diagonal;
    return count;
  };
  const size_t coarse_region = moved_vertices(a, coarse), fine_region = moved_vertices(b, fine);
  std::printf("coarse cage %zu / fine cage %zu vertices: reproduction %.2g / %.2g of the diagonal; foot points "
              "%.2g apart, displacements %.2g apart; one control point moved: %zu / %zu scan vertices follow\n",
              coarse.mesh.num_vertices(), fine.mesh.num_vertices(), worst_a / diagonal, worst_b / diagonal,
              worst_foot / diagonal, worst_d / diagonal, coarse_region, fine_region);
  EXPECT_LT(worst_a, 1e-5 * diagonal);  // the bar (the compact float32 path: ~1e-7)
  EXPECT_LT(worst_b, 1e-5 * diagonal);
  EXPECT_LT(worst_foot, 1e-6 * diagonal);  // the same limit surface, projected independently
  EXPECT_LT(worst_d, 1e-6 * diagonal);
  EXPECT_GT(fine_region, 0u);
  EXPECT_LT(2 * fine_region, coarse_region);  // the finer level edits a smaller region
}
