// SPDX-License-Identifier: GPL-3.0-or-later
// Sharp features (thesis §8.5.2, AC-8.8): vertices duplicated per smooth sector, with coincident
// positions and per-sector normals — core/sector_split.h and the binding's sector split.
#include <gtest/gtest.h>

#include <cmath>

#include "core/sector_split.h"
#include "core/status.h"
#include "multires/cpu_deformer.h"
#include "multires/scan_binding.h"
#include "subdiv/uniform_refinement.h"
#include "test_support.h"

using namespace cagekit;

namespace {

constexpr double kDegree = 3.141592653589793 / 180.0;

// Average of the unit normals of the faces around bound vertex v in `mesh` (its sector).
Vec3 sector_normal(const PolygonMesh& mesh, uint32_t v) {
  Vec3 sum;
  for (size_t f = 0; f < mesh.num_faces(); ++f)
    for (uint32_t k = 0; k < mesh.face_size(f); ++k)
      if (mesh.face_vertex(f, k) == v) sum += mesh.face_vector_area(f);
  return normalized(sum);
}

}  // namespace

TEST(SectorSplit, cube_corners_get_three_sectors_edges_two) {
  const PolygonMesh cube = cagekit_test::unit_cube_quads();
  const SectorSplit sharp = split_vertices_by_sector(cube, 45);
  EXPECT_EQ(sharp.mesh.num_vertices(), 24u);  // every corner once per adjacent face
  EXPECT_EQ(sharp.num_input_vertices, 8u);
  ASSERT_EQ(sharp.source_vertex.size(), 24u);
  for (uint32_t v = 0; v < 8; ++v) EXPECT_EQ(sharp.source_vertex[v], v);  // stable numbering
  for (uint32_t v = 0; v < 24; ++v) EXPECT_EQ(sharp.mesh.positions[v].x, cube.positions[sharp.source_vertex[v]].x);
  EXPECT_EQ(sharp.mesh.face_offsets, cube.face_offsets);
  const SectorSplit smooth = split_vertices_by_sector(cube, 100);  // 90 degree edges are below it
  EXPECT_EQ(smooth.mesh.num_vertices(), 8u);
  EXPECT_EQ(smooth.mesh.face_vertices, cube.face_vertices);
  // A refined box: sides' interior vertices stay, edge vertices get 2 copies, corners 3.
  RefineOptions three;
  three.levels = 3;
  const PolygonMesh box = refine_uniform(cagekit_test::creased_unit_cube(), three).mesh;  // 386 vertices
  const SectorSplit split = split_vertices_by_sector(box, 30);
  const size_t edge_vertices = 12 * 7, corners = 8;
  EXPECT_EQ(split.mesh.num_vertices(), box.num_vertices() + edge_vertices + 2 * corners);
  EXPECT_THROW(split_vertices_by_sector(box, std::nan("")), Error);
  EXPECT_THROW(split_vertices_by_sector(box, 181), Error);
}

TEST(SectorSplit, binding_keeps_one_normal_per_smooth_sector) {
  const Cage cage = cagekit_test::creased_unit_cube();
  RefineOptions three;
  three.levels = 3;
  const PolygonMesh scan = refine_uniform(cage, three).mesh;
  BindOptions plain, split;
  split.sharp_angle_degrees = 30;
  const ScanBinding a = bind_scan_to_cage(cage, scan, plain), b = bind_scan_to_cage(cage, scan, split);
  ASSERT_EQ(a.num_vertices(), scan.num_vertices());
  ASSERT_GT(b.num_vertices(), scan.num_vertices());
  ASSERT_EQ(b.source_vertex.size(), b.num_vertices());
  EXPECT_EQ(b.scan_vertex_count, scan.num_vertices());
  PolygonMesh bound;
  bound.face_offsets = b.face_offsets, bound.face_vertices = b.face_vertices;
  bound.positions.resize(b.num_vertices());
  for (size_t i = 0; i < b.num_vertices(); ++i) bound.positions[i] = scan.positions[b.source_vertex[i]];
  // Moved cage: copies stay coincident; every copy's normal is its own sector's; without the
  // split the edge vertices get one averaged normal (45 degrees off both sides, undeformed).
  for (int moved = 0; moved < 2; ++moved) {
    std::vector<Vec3> control = cage.mesh.positions;
    if (moved) control[6] += Vec3{0.15, 0.1, 0.2};
    std::vector<Vec3> pa(a.num_vertices()), na(pa.size()), pb(b.num_vertices()), nb(pb.size());
    CpuDeformer(a, 1).deform(control, pa.data(), na.data());
    CpuDeformer(b, 1).deform(control, pb.data(), nb.data());
    PolygonMesh deformed = bound;
    deformed.positions = pb;
    double worst_gap = 0, worst_split = 0, worst_plain = 0;
    for (size_t i = 0; i < b.num_vertices(); ++i) {
      worst_gap = std::max(worst_gap, norm(pb[i] - pb[b.source_vertex[i]]));
      const Vec3 ref = sector_normal(deformed, uint32_t(i));
      worst_split = std::max(worst_split, std::atan2(norm(cross(nb[i], ref)), dot(nb[i], ref)) / kDegree);
      if (i >= b.scan_vertex_count)  // a copy: its scan vertex's single normal in the plain binding
        worst_plain = std::max(worst_plain, std::atan2(norm(cross(na[b.source_vertex[i]], ref)),
                                                       dot(na[b.source_vertex[i]], ref)) / kDegree);
    }
    std::printf("%s: %zu scan vertices -> %zu bound (%zu copies); copies %.2g apart; per-sector normals "
                "%.3g deg from their sector's faces (one averaged normal: %.1f deg)\n",
                moved ? "cage corner moved" : "undeformed", scan.num_vertices(), b.num_vertices(),
                b.num_vertices() - scan.num_vertices(), worst_gap, worst_split, worst_plain);
    EXPECT_LT(worst_gap, 1e-12);
    EXPECT_GT(worst_plain, 30.0);
    // Undeformed the reconstructed normal is the sector's average by construction. Moved (a
    // corner pulled by 0.27 of the edge length on this coarse 386-vertex box), the approximate
    // normals (8.11) and the deformed faces' average differ where the sides bend most (measured
    // 15 deg at worst), still far closer than one averaged normal per vertex (60 deg).
    if (!moved)
      EXPECT_LT(worst_split, 1e-6);
    else
      EXPECT_LT(worst_split, 0.5 * worst_plain);
  }
  BindOptions bad;
  bad.sharp_angle_degrees = 200;
  EXPECT_THROW(bind_scan_to_cage(cage, scan, bad), Error);
}
