// SPDX-License-Identifier: GPL-3.0-or-later
// Disk regions for the two-step quad remeshing (issue #19, deliverable 1): a region with a handle
// is cut across it (cut_region_handle, tree-cotree), so every region ends a disk, possibly with
// holes, that LSCM parameterises; regions that are disks already are left alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <set>
#include <vector>

#include "core/status.h"
#include "layout/quad/disk_regions.h"
#include "layout/quad/lscm_parameterization.h"
#include "test_support.h"

using cagekit::PolygonMesh;

namespace {

std::vector<uint32_t> all_faces(const PolygonMesh& m) {
  std::vector<uint32_t> faces(m.num_faces());
  for (uint32_t f = 0; f < faces.size(); ++f) faces[f] = f;
  return faces;
}

std::vector<uint32_t> without(const std::vector<uint32_t>& faces, const std::vector<uint32_t>& removed) {
  const std::set<uint32_t> gone(removed.begin(), removed.end());
  std::vector<uint32_t> out;
  for (uint32_t f : faces)
    if (!gone.count(f)) out.push_back(f);
  return out;
}

// Whether LSCM takes the faces as one disk (possibly with holes).
bool is_disk_with_holes(const PolygonMesh& m, const std::vector<uint32_t>& faces) {
  try {
    cagekit::parameterize_region_lscm(m, faces);
    return true;
  } catch (const cagekit::Error& e) {
    EXPECT_EQ(e.status(), cagekit::Status::invalid_mesh) << e.what();
    return false;
  }
}

}  // namespace

TEST(DiskRegions, ClosedTorusIsCutAcrossItsHandle) {
  const PolygonMesh torus = cagekit_test::triangle_torus(1.0, 0.35, 24, 10);
  const std::vector<uint32_t> faces = all_faces(torus);
  ASSERT_FALSE(is_disk_with_holes(torus, faces));
  const std::vector<uint32_t> band = cagekit::cut_region_handle(torus, faces);
  ASSERT_FALSE(band.empty());
  // A shortest dual cycle by tree depth: around the tube (10 quads = 20 triangles) or along the
  // ring, not most of the torus.
  EXPECT_LE(band.size(), faces.size() / 4);
  // Removing the band leaves a genus-0 surface (a cylinder: closed torus cut along a
  // non-separating loop); the band itself is no disk yet (an annulus), halving splits it.
  EXPECT_TRUE(is_disk_with_holes(torus, without(faces, band)));
}

TEST(DiskRegions, TorusWithAHoleIsCutAndItsRemainderIsADisk) {
  // A torus with one face pair removed: genus 1 with one border loop.
  const PolygonMesh torus = cagekit_test::triangle_torus(1.0, 0.35, 24, 10);
  const std::vector<uint32_t> faces = without(all_faces(torus), {0, 1});
  ASSERT_FALSE(is_disk_with_holes(torus, faces));
  const std::vector<uint32_t> band = cagekit::cut_region_handle(torus, faces);
  ASSERT_FALSE(band.empty());
  EXPECT_LT(band.size(), faces.size() / 2);
  EXPECT_TRUE(is_disk_with_holes(torus, without(faces, band)));
}

TEST(DiskRegions, DisksAndCylindersHaveNoHandleToCut) {
  const PolygonMesh cylinder = cagekit_test::triangle_cylinder(1.0, 2.0, 16, 6);  // genus 0, two borders
  EXPECT_TRUE(cagekit::cut_region_handle(cylinder, all_faces(cylinder)).empty());
  const PolygonMesh sphere = cagekit_test::triangle_sphere(2);
  std::vector<uint32_t> cap = all_faces(sphere);
  cap.pop_back();  // a sphere with one triangle missing: a disk
  EXPECT_TRUE(cagekit::cut_region_handle(sphere, cap).empty());
  EXPECT_TRUE(cagekit::cut_region_handle(sphere, {}).empty());
}

TEST(DiskRegions, EveryRegionOfAOneRegionTorusEndsADisk) {
  const PolygonMesh torus = cagekit_test::triangle_torus(1.0, 0.35, 36, 12);
  std::vector<uint32_t> face_region(torus.num_faces(), 0);
  size_t regions = 1;
  cagekit::DiskRegionReport report;
  const std::vector<cagekit::RegionParameterization> domains =
      cagekit::make_disk_regions(torus, face_region, regions, 0, {}, &report);
  EXPECT_EQ(report.failing_regions, 0u);
  EXPECT_GE(report.handle_cuts, 1u);  // cut across the handle, not only halved
  EXPECT_EQ(regions, 1u + report.split_regions);
  ASSERT_EQ(domains.size(), regions);
  for (size_t r = 0; r < regions; ++r) {
    EXPECT_FALSE(domains[r].faces.empty()) << "region " << r << " has no map";
    EXPECT_EQ(domains[r].flipped_triangles, 0u) << "region " << r;
  }
}

// A region that is still not a disk after the fold rounds is cut on (cheese.off: a genus-2 part
// reached LSCM after 8 rounds); with no topology rounds beyond them it is reported as failing.
TEST(DiskRegions, RegionsThatAreNotDisksAreCutPastTheFoldRounds) {
  const PolygonMesh torus = cagekit_test::triangle_torus(1.0, 0.35, 36, 12);
  for (const int topology_rounds : {0, 6}) {
    std::vector<uint32_t> face_region(torus.num_faces(), 0);
    size_t regions = 1;
    cagekit::DiskRegionOptions options;
    options.max_rounds = 0;         // no split round for folds
    options.split_folded = false;   // (the torus's bands fold a little in LSCM: not this test's point)
    options.max_topology_rounds = topology_rounds;
    cagekit::DiskRegionReport report;
    const std::vector<cagekit::RegionParameterization> domains =
        cagekit::make_disk_regions(torus, face_region, regions, 0, options, &report);
    ASSERT_EQ(domains.size(), regions);
    if (topology_rounds == 0) {
      EXPECT_EQ(report.failing_regions, 1u);
      EXPECT_EQ(regions, 1u);
      EXPECT_TRUE(domains[0].faces.empty());  // no map for the closed torus
      continue;
    }
    EXPECT_EQ(report.failing_regions, 0u);
    EXPECT_GE(report.handle_cuts, 1u);
    EXPECT_EQ(report.fold_splits, 0u);
    for (size_t r = 0; r < regions; ++r) {
      EXPECT_FALSE(domains[r].faces.empty()) << "region " << r << " has no map";
      EXPECT_TRUE(is_disk_with_holes(torus, domains[r].faces)) << "region " << r;
    }
  }
}
