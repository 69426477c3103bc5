// SPDX-License-Identifier: GPL-3.0-or-later
// The cage builder on hand-made polygonal levels (independent of the simplifier).
#include <gtest/gtest.h>

#include <set>

#include "core/mesh_validation.h"
#include "layout/cage_builder.h"
#include "test_support.h"

using namespace cagekit;

namespace {

PolygonalFace face_of(std::vector<std::vector<uint32_t>> loops, Vec3 normal, Vec3 centroid, double area) {
  PolygonalFace f;
  f.loops = std::move(loops);
  f.normal = normal;
  f.centroid = centroid;
  f.area = area;
  return f;
}

// The six sides of the unit cube (vertices as in test_support's unit_cube_quads) as a level.
PolygonalLevel cube_level() {
  PolygonalLevel level;
  level.faces = {face_of({{0, 2, 3, 1}}, {0, 0, -1}, {0.5, 0.5, 0}, 1), face_of({{4, 5, 7, 6}}, {0, 0, 1}, {0.5, 0.5, 1}, 1),
                 face_of({{0, 1, 5, 4}}, {0, -1, 0}, {0.5, 0, 0.5}, 1), face_of({{2, 6, 7, 3}}, {0, 1, 0}, {0.5, 1, 0.5}, 1),
                 face_of({{0, 4, 6, 2}}, {-1, 0, 0}, {0, 0.5, 0.5}, 1), face_of({{1, 3, 7, 5}}, {1, 0, 0}, {1, 0.5, 0.5}, 1)};
  level.cluster_of_input_face = {0, 1, 2, 3, 4, 5};
  level.num_vertices = 8;
  return level;
}

}  // namespace

TEST(CageBuilder, cube_sides_become_six_quads_with_twelve_sharp_edges) {
  const PolygonMesh cube = cagekit_test::unit_cube_quads();
  CageBuildReport report;
  const Cage cage = build_quad_dominant_cage(cube, cube_level(), {}, &report);
  EXPECT_EQ(cage.mesh.num_faces(), 6u);
  EXPECT_EQ(report.quads, 6u);
  EXPECT_EQ(report.triangles + report.pentagons + report.other, 0u);
  EXPECT_EQ(cage.creases.size(), 12u);
  EXPECT_EQ(report.creases, 12u);
  EXPECT_TRUE(validate_cage(cage).ok());
  // Cage vertices are input vertices at their input positions.
  ASSERT_EQ(report.input_vertex_of.size(), cage.mesh.num_vertices());
  for (size_t v = 0; v < cage.mesh.num_vertices(); ++v)
    EXPECT_EQ(cage.mesh.positions[v], cube.positions[report.input_vertex_of[v]]);
}

TEST(CageBuilder, crease_angle_threshold_decides_the_tags) {
  const PolygonMesh cube = cagekit_test::unit_cube_quads();
  CageBuildOptions options;
  options.crease_angle_degrees = 95.0;  // the cube's sides meet at 90 degrees
  EXPECT_EQ(build_quad_dominant_cage(cube, cube_level(), options).creases.size(), 0u);
  options.crease_angle_degrees = 85.0;
  EXPECT_EQ(build_quad_dominant_cage(cube, cube_level(), options).creases.size(), 12u);
  options.crease_angle_degrees = -1.0;
  EXPECT_EQ(build_quad_dominant_cage(cube, cube_level(), options).creases.size(), 0u);
}

TEST(CageBuilder, l_shaped_face_becomes_two_quads_and_boundary_is_tagged) {
  // An L-shaped hexagon in the plane z = 0: its optimal partition is two quads.
  PolygonMesh input;
  for (Vec3 p : {Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{2, 1, 0}, Vec3{1, 1, 0}, Vec3{1, 2, 0}, Vec3{0, 2, 0}})
    input.add_vertex(p);
  input.add_face({0, 1, 2, 3, 4, 5});
  PolygonalLevel level;
  level.faces = {face_of({{0, 1, 2, 3, 4, 5}}, {0, 0, 1}, {0.8, 0.8, 0}, 3)};
  level.cluster_of_input_face = {0};
  CageBuildReport report;
  const Cage cage = build_quad_dominant_cage(input, level, {}, &report);
  EXPECT_EQ(report.quads, 2u);
  EXPECT_EQ(cage.mesh.num_faces(), 2u);
  EXPECT_EQ(cage.creases.size(), 6u);  // the six boundary edges, not the inner diagonal
  CageBuildOptions untagged;
  untagged.tag_boundary_edges = false;
  EXPECT_EQ(build_quad_dominant_cage(input, level, untagged).creases.size(), 0u);
}

TEST(CageBuilder, face_with_a_hole_is_partitioned_into_convex_cells_without_new_vertices) {
  // A square frame: outer square 0..3 (CCW) and a square hole 4..7 (CW), z = 0.
  PolygonMesh input;
  for (Vec3 p : {Vec3{0, 0, 0}, Vec3{3, 0, 0}, Vec3{3, 3, 0}, Vec3{0, 3, 0}, Vec3{1, 1, 0}, Vec3{1, 2, 0},
                 Vec3{2, 2, 0}, Vec3{2, 1, 0}})
    input.add_vertex(p);
  input.add_face({0, 1, 2, 3});  // the input's faces do not matter to the builder
  PolygonalLevel level;
  level.faces = {face_of({{0, 1, 2, 3}, {4, 5, 6, 7}}, {0, 0, 1}, {1.5, 1.5, 0}, 8)};
  level.cluster_of_input_face = {0};
  CageBuildReport report;
  const Cage cage = build_quad_dominant_cage(input, level, {}, &report);
  EXPECT_EQ(cage.mesh.num_vertices(), 8u);
  EXPECT_EQ(report.quads, 4u);  // 8 CDT triangles pair up into 4 quads
  EXPECT_EQ(report.triangles + report.pentagons + report.other, 0u);
  EXPECT_TRUE(validate_cage(cage).ok());
  // The polygonal level mesh triangulates the face with a hole.
  uint64_t triangulated = 0;
  const PolygonMesh level_mesh = polygonal_level_mesh(input, level, &triangulated);
  EXPECT_EQ(triangulated, 1u);
  EXPECT_EQ(level_mesh.num_faces(), 8u);
  EXPECT_TRUE(level_mesh.all_faces_have_size(3));
}
