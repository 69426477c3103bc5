// SPDX-License-Identifier: GPL-3.0-or-later
// The per-call memory budget (core/memory_budget.h): estimates are checked against the budget
// installed on the calling thread, big steps of every layer refuse to start, and the budget does
// not leak into other threads or outlive its scope.
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <thread>

#include "core/memory_budget.h"
#include "core/polygon_mesh.h"
#include "core/status.h"
#include "fit/surface_fitter.h"
#include "layout/simplify/face_merge_simplifier.h"
#include "subdiv/subdivision_surface.h"
#include "subdiv/uniform_refinement.h"
#include "test_support.h"

using namespace cagekit;
using cagekit_test::status_of;

namespace {
RefineOptions levels(int n) {
  RefineOptions o;
  o.levels = n;
  return o;
}

}  // namespace

TEST(MemoryBudget, estimates_above_the_budget_fail_with_out_of_memory) {
  EXPECT_EQ(memory_budget(), 0u);
  check_memory_estimate(UINT64_MAX, "anything");  // unlimited by default
  {
    const ScopedMemoryBudget budget(1 << 20);
    EXPECT_EQ(memory_budget(), 1u << 20);
    check_memory_estimate(1 << 20, "exactly the budget");
    try {
      check_memory_estimate((1 << 20) + 1, "a big step");
      FAIL() << "not refused";
    } catch (const Error& e) {
      EXPECT_EQ(e.status(), Status::out_of_memory);
      EXPECT_NE(std::string(e.what()).find("a big step"), std::string::npos);
      EXPECT_NE(std::string(e.what()).find("memory budget of 1 MiB"), std::string::npos);
    }
    {
      const ScopedMemoryBudget inner(0);
      check_memory_estimate(UINT64_MAX, "unlimited inside");
    }
    EXPECT_EQ(memory_budget(), 1u << 20);
    // Other threads are not affected.
    uint64_t seen = 1;
    std::thread([&] { seen = memory_budget(); }).join();
    EXPECT_EQ(seen, 0u);
  }
  EXPECT_EQ(memory_budget(), 0u);
  EXPECT_EQ(estimate_product(UINT64_MAX / 2, 3), UINT64_MAX);
  EXPECT_EQ(estimate_sum(UINT64_MAX - 1, 2), UINT64_MAX);
}

TEST(MemoryBudget, every_layer_refuses_big_steps_and_accepts_small_ones) {
  const PolygonMesh sphere = cagekit_test::triangle_sphere(4);  // 2048 triangles
  Cage cube;
  cube.mesh = cagekit_test::unit_cube_quads();
  const ScopedMemoryBudget budget(4 << 20);  // 4 MiB
  PolygonMesh mesh;
  EXPECT_EQ(status_of([&] { mesh.reserve(size_t(1) << 30, 1, 3); }), Status::out_of_memory);
  EXPECT_EQ(status_of([&] { mesh.reserve(1000, 1000, 3000); }), Status::success);
  EXPECT_EQ(status_of([&] { refine_uniform(cube, levels(2)); }), Status::success);
  EXPECT_EQ(status_of([&] { refine_uniform(cube, levels(8)); }), Status::out_of_memory);
  EXPECT_EQ(status_of([&] { SimplificationHierarchy h(sphere); }), Status::success);
  {
    const ScopedMemoryBudget tiny(1 << 10);
    EXPECT_EQ(status_of([&] { SimplificationHierarchy h(sphere); }), Status::out_of_memory);
    EXPECT_EQ(status_of([&] { SubdivisionSurface s(cube); }), Status::out_of_memory);
    EXPECT_EQ(status_of([&] { fit_cage_to_points(cube, sphere.positions); }), Status::out_of_memory);
  }
  EXPECT_EQ(status_of([&] { SubdivisionSurface s(cube); }), Status::success);
}
