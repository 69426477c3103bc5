// SPDX-License-Identifier: GPL-3.0-or-later
// Remesh quality figures (sdk/layout/common/remesh_quality.h), the definitions shared by the remeshers'
// reports and tests/bench/bench_remesh: face and valence counts, alignment of edges with the
// principal directions, sharp input edges followed by output edges.
#include <gtest/gtest.h>

#include <cmath>

#include "layout/common/approximation_error.h"
#include "layout/anisotropic/curvature_tensor_field.h"
#include "layout/common/feature_edges.h"
#include "layout/anisotropic/principal_alignment.h"
#include "layout/common/remesh_quality.h"
#include "test_support.h"

using cagekit::AlignmentSample;
using cagekit::PolygonMesh;
using cagekit::Vec3;

namespace {

const double kPi = 3.14159265358979323846;

// The quad cube with every face split into two triangles.
PolygonMesh triangulated(const PolygonMesh& quads) {
  PolygonMesh tri;
  tri.positions = quads.positions;
  for (size_t f = 0; f < quads.num_faces(); ++f) {
    const uint32_t* v = quads.face_begin(f);
    for (uint32_t k = 1; k + 1 < quads.face_size(f); ++k) tri.add_face({v[0], v[k], v[k + 1]});
  }
  return tri;
}

}  // namespace

TEST(RemeshQuality, FiguresOfAGridAndACube) {
  // 3 x 3 open grid: 16 vertices, 4 interior ones, all of valence 4.
  const cagekit::PolygonMeshFigures grid = cagekit::polygon_mesh_figures(cagekit_test::quad_grid(3, 3));
  EXPECT_EQ(grid.faces, 9u);
  EXPECT_EQ(grid.quads, 9u);
  EXPECT_EQ(grid.vertices, 16u);
  EXPECT_EQ(grid.interior_vertices, 4u);
  EXPECT_EQ(grid.valence4_vertices, 4u);
  EXPECT_EQ(grid.edges.size(), 24u);
  EXPECT_EQ(grid.max_face_valence, 4u);
  EXPECT_EQ(grid.max_vertex_valence, 4u);
  EXPECT_DOUBLE_EQ(grid.valence4_pct(), 100.0);
  // Closed cube: 8 interior vertices of valence 3; triangulated: no quads.
  const cagekit::PolygonMeshFigures cube = cagekit::polygon_mesh_figures(cagekit_test::unit_cube_quads());
  EXPECT_EQ(cube.interior_vertices, 8u);
  EXPECT_EQ(cube.valence4_vertices, 0u);
  EXPECT_EQ(cube.edges.size(), 12u);
  for (uint32_t uses : cube.edge_uses) EXPECT_EQ(uses, 2u);
  const cagekit::PolygonMeshFigures tri = cagekit::polygon_mesh_figures(triangulated(cagekit_test::unit_cube_quads()));
  EXPECT_EQ(tri.faces, 12u);
  EXPECT_EQ(tri.quads, 0u);
  EXPECT_DOUBLE_EQ(tri.quads_pct(), 0.0);
}

TEST(RemeshQuality, AlignmentOnACylinderMeasuresTheAngleToTheNearerDirection) {
  const PolygonMesh cyl = cagekit_test::triangle_cylinder(1.0, 4.0, 64, 64);
  cagekit::CurvatureOptions co;
  co.disk_radius = 3.0;
  const cagekit::CurvatureField field = cagekit::estimate_curvature_field(cyl, co);
  // An interior face (away from the open ends): its axis direction is z, the circle direction is
  // tangent to the circle.
  std::vector<Vec3> probe = {{1.0, 0.0, 2.0}};
  const uint32_t f = cagekit::nearest_faces(cyl, probe)[0];
  ASSERT_NE(f, UINT32_MAX);
  auto measure = [&](const Vec3& chord) {
    return cagekit::measure_principal_alignment(field, {AlignmentSample{chord, f, f}});
  };
  // The face's directions are those at its centroid: the axis z and the circle's tangent there.
  Vec3 c{};
  for (uint32_t k = 0; k < 3; ++k) c = c + (1.0 / 3.0) * cyl.positions[cyl.face_vertex(f, k)];
  const double phi = std::atan2(c.y, c.x);
  const Vec3 axis{0, 0, 1}, tangent{-std::sin(phi), std::cos(phi), 0};
  auto tilted = [&](const Vec3& from, const Vec3& to, double degrees) {
    return std::cos(degrees * kPi / 180.0) * from + std::sin(degrees * kPi / 180.0) * to;
  };
  EXPECT_LT(measure(axis).mean_deg, 1.0);
  EXPECT_LT(measure(tangent).mean_deg, 1.0);
  EXPECT_NEAR(measure(tilted(axis, tangent, 30)).mean_deg, 30.0, 1.0);
  EXPECT_NEAR(measure(tilted(tangent, axis, -20)).mean_deg, 20.0, 1.0);  // no sign
  EXPECT_NEAR(measure(tilted(axis, tangent, 45)).mean_deg, 45.0, 1.0);   // at most 45° from the nearer one
  EXPECT_NEAR(measure(-1.0 * tilted(tangent, axis, 10)).mean_deg, 10.0, 1.0);
  // Faces out of range are not measured; the mean is over measured samples only.
  const cagekit::PrincipalAlignment two = cagekit::measure_principal_alignment(
      field, {AlignmentSample{axis, f, f}, AlignmentSample{tangent + axis, f, uint32_t(cyl.num_faces())}});
  EXPECT_EQ(two.samples, 2u);
  EXPECT_EQ(two.measured, 1u);
  EXPECT_LT(two.mean_deg, 1.0);
}

TEST(RemeshQuality, SharpEdgesFollowedByOutputEdges) {
  const PolygonMesh input = triangulated(cagekit_test::unit_cube_quads());
  const std::vector<uint8_t> sharp = cagekit::detect_feature_edges(input, 40.0);
  // The quad cube follows all 12 cube edges (the diagonals are not sharp).
  const cagekit::FeatureAlignment same = cagekit::measure_feature_alignment(input, sharp, cagekit_test::unit_cube_quads());
  EXPECT_EQ(same.sharp_edges, 12u);
  EXPECT_EQ(same.followed, 12u);
  EXPECT_DOUBLE_EQ(same.delta, 1.0);
  // Shifted by 0.3 along x (> delta / 4): only the 4 edges along x still lie on output edges.
  PolygonMesh shifted = cagekit_test::unit_cube_quads();
  for (Vec3& p : shifted.positions) p.x += 0.3;
  const cagekit::FeatureAlignment moved = cagekit::measure_feature_alignment(input, sharp, shifted);
  EXPECT_EQ(moved.sharp_edges, 12u);
  EXPECT_EQ(moved.followed, 4u);
  EXPECT_NEAR(moved.share(), 4.0 / 12.0, 1e-12);
  // Shifted by 0.3 along x, y and z: every sharp edge's midpoint is at least 0.36 from every
  // output edge, more than delta / 4.
  for (Vec3& p : shifted.positions) p.y += 0.3, p.z += 0.3;
  EXPECT_EQ(cagekit::measure_feature_alignment(input, sharp, shifted).followed, 0u);
  // No sharp edges: share 1 by convention.
  const cagekit::FeatureAlignment none =
      cagekit::measure_feature_alignment(input, std::vector<uint8_t>(input.num_face_vertices(), 0), shifted);
  EXPECT_EQ(none.sharp_edges, 0u);
  EXPECT_DOUBLE_EQ(none.share(), 1.0);
}
