// SPDX-License-Identifier: GPL-3.0-or-later
// renumber_vertices (core/vertex_renumbering.h): positions moved, faces remapped, the same
// geometry; bad orders and bad faces are errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include "core/status.h"
#include "core/vertex_renumbering.h"
#include "test_support.h"

using namespace cagekit;

TEST(VertexRenumbering, permutes_positions_and_remaps_faces) {
  const PolygonMesh mesh = cagekit_test::unit_cube_quads();
  std::vector<uint32_t> order(mesh.num_vertices());
  std::iota(order.begin(), order.end(), 0u);
  std::mt19937 rng(7);
  std::shuffle(order.begin(), order.end(), rng);
  const PolygonMesh out = renumber_vertices(mesh, order);
  ASSERT_EQ(out.num_vertices(), mesh.num_vertices());
  ASSERT_EQ(out.face_offsets, mesh.face_offsets);
  for (uint32_t k = 0; k < order.size(); ++k) EXPECT_EQ(out.positions[k], mesh.positions[order[k]]);
  // Every face has the same corner positions in the same order.
  for (size_t e = 0; e < mesh.face_vertices.size(); ++e)
    EXPECT_EQ(out.positions[out.face_vertices[e]], mesh.positions[mesh.face_vertices[e]]);
  // The identity order gives the same mesh.
  std::iota(order.begin(), order.end(), 0u);
  const PolygonMesh same = renumber_vertices(mesh, order);
  EXPECT_EQ(same.positions, mesh.positions);
  EXPECT_EQ(same.face_vertices, mesh.face_vertices);
}

TEST(VertexRenumbering, bad_orders_and_faces_are_errors) {
  const PolygonMesh mesh = cagekit_test::unit_cube_quads();
  const uint32_t n = uint32_t(mesh.num_vertices());
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  auto status_of = [&](const PolygonMesh& m, const std::vector<uint32_t>& o) {
    try {
      renumber_vertices(m, o);
    } catch (const Error& e) {
      return e.status();
    }
    return Status::success;
  };
  std::vector<uint32_t> shorter(order.begin(), order.end() - 1), twice = order, out_of_range = order;
  twice[1] = twice[0];
  out_of_range[2] = n;
  EXPECT_EQ(status_of(mesh, shorter), Status::invalid_argument);
  EXPECT_EQ(status_of(mesh, twice), Status::invalid_argument);
  EXPECT_EQ(status_of(mesh, out_of_range), Status::invalid_argument);
  PolygonMesh bad_face = mesh;
  bad_face.face_vertices[3] = n + 5;
  EXPECT_EQ(status_of(bad_face, order), Status::invalid_mesh);
  EXPECT_EQ(status_of(mesh, order), Status::success);
}
