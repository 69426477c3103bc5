// SPDX-License-Identifier: GPL-3.0-or-later
// Two-step quad-dominant remeshing, steps 1-2 (thesis §6.3-6.4, spec thesis-ch4-6.md §2.2-2.5,
// AC6-9): VSA L2,1 segmentation with tentative teleporting, region boundaries (anchors, arcs,
// loops), the (6.1) arc cubics and their shared samples, and the per-region LSCM domains.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <set>

#include "core/edge_key.h"
#include "core/edge_map.h"
#include "layout/quad/arc_fit.h"
#include "layout/quad/lscm_parameterization.h"
#include "layout/quad/region_boundaries.h"
#include "layout/quad/remesh_constraints.h"
#include "layout/quad/vsa_segmentation.h"
#include "test_support.h"

using cagekit::PolygonMesh;
using cagekit::Status;
using cagekit::Vec3;
using cagekit::VsaOptions;
using cagekit::VsaSegmentation;
using cagekit_test::status_of;

namespace {

const double kPi = 3.14159265358979323846;

// Closed box [0, n]^3 scaled by s, every side an n x n grid of triangulated quads, outward,
// translated by `offset` (appended to m).
void append_box(PolygonMesh& m, int n, double s, const Vec3& offset = {}) {
  std::map<long, uint32_t> ids;
  auto vid = [&](int x, int y, int z) {
    const long key = (long(x) * (n + 1) + y) * (n + 1) + z;
    auto it = ids.find(key);
    if (it != ids.end()) return it->second;
    const uint32_t id = m.add_vertex(Vec3(x * s, y * s, z * s) + offset);
    ids.emplace(key, id);
    return id;
  };
  // For each side: axis a fixed at 0 or n, (b, c) the in-plane axes ordered for an outward normal.
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int b = (axis + 1) % 3, c = (axis + 2) % 3;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          uint32_t q[4];
          const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
          for (int k = 0; k < 4; ++k) {
            int p[3];
            p[axis] = side * n, p[b] = i + di[k], p[c] = j + dj[k];
            q[k] = vid(p[0], p[1], p[2]);
          }
          if (side == 1) {
            m.add_face({q[0], q[1], q[2]});
            m.add_face({q[0], q[2], q[3]});
          } else {
            m.add_face({q[0], q[2], q[1]});
            m.add_face({q[0], q[3], q[2]});
          }
        }
    }
}

PolygonMesh box(int n, double s) {
  PolygonMesh m;
  append_box(m, n, s);
  return m;
}

// Triangulated open grid over [0, nx] x [0, ny] with height z(x, y).
PolygonMesh triangle_grid(int nx, int ny, double (*height)(double, double) = nullptr) {
  const PolygonMesh quads = cagekit_test::quad_grid(nx, ny, height);
  PolygonMesh m;
  m.positions = quads.positions;
  for (size_t f = 0; f < quads.num_faces(); ++f) {
    const uint32_t* q = quads.face_begin(f);
    m.add_face({q[0], q[1], q[2]});
    m.add_face({q[0], q[2], q[3]});
  }
  return m;
}

// Torus with ring radius 3 and tube radius 1, nu x nv triangulated quads, outward.
PolygonMesh triangle_torus(int nu, int nv) {
  PolygonMesh torus;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * kPi * i / nu, v = 2 * kPi * j / nv;
      torus.add_vertex(Vec3((3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v)));
    }
  auto id = [&](int i, int j) { return uint32_t((i % nu) * nv + (j % nv)); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      torus.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      torus.add_face({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return torus;
}

Vec3 face_normal(const PolygonMesh& m, size_t f) { return cagekit::normalized(m.face_vector_area(f)); }

// Every region edge-connected (through edges shared by two faces of the region).
bool regions_connected(const PolygonMesh& m, const std::vector<uint32_t>& face_region, size_t regions) {
  cagekit::detail::EdgeMap map;
  build_edge_map(map, m, std::vector<uint8_t>(m.num_faces(), 1));
  cagekit::detail::UnionFind uf(m.num_faces());
  for (size_t e = 0; e < map.num_edges(); ++e)
    if (map.valence(e) == 2) {
      const uint32_t a = map.corner_face[map.corners_begin(e)[0]], b = map.corner_face[map.corners_begin(e)[1]];
      if (face_region[a] == face_region[b]) uf.unite(a, b);
    }
  std::vector<uint32_t> root(regions, cagekit::detail::kNone);
  for (uint32_t f = 0; f < m.num_faces(); ++f) {
    uint32_t& r = root[face_region[f]];
    if (r == cagekit::detail::kNone) r = uf.find(f);
    if (r != uf.find(f)) return false;
  }
  return true;
}

PolygonMesh load_shared(const std::string& name) {
  const std::string path = cagekit_test::shared_mesh_path(name);
  return path.empty() ? PolygonMesh{} : cagekit_test::load_mesh(path);
}

Vec3 face_centroid(const PolygonMesh& m, uint32_t f) {
  return (m.positions[m.face_vertex(f, 0)] + m.positions[m.face_vertex(f, 1)] + m.positions[m.face_vertex(f, 2)]) *
         (1.0 / 3.0);
}

// VSA with `count` regions and default options.
VsaSegmentation segment(const PolygonMesh& m, int count) {
  VsaOptions options;
  options.region_count = count;
  return cagekit::segment_vsa(m, options);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// VSA segmentation

TEST(VsaSegmentation, CubeWithSixRegionsGivesItsSixSidesWithZeroError) {
  const PolygonMesh m = box(5, 2.0);
  const VsaSegmentation seg = segment(m, 6);
  ASSERT_EQ(seg.num_regions(), 6u);
  EXPECT_NEAR(seg.total_area, 6 * 100.0, 1e-9);
  EXPECT_LT(seg.total_error, 1e-12 * seg.total_area);
  std::set<std::tuple<int, int, int>> normals;
  for (uint32_t r = 0; r < 6; ++r) {
    const std::vector<uint32_t> faces = seg.region_faces(r);
    EXPECT_EQ(faces.size(), 50u) << "region " << r;
    for (uint32_t f : faces) EXPECT_LT(cagekit::distance(face_normal(m, f), seg.proxy_normal[r]), 1e-12);
    const Vec3& n = seg.proxy_normal[r];
    normals.insert({int(std::lround(n.x)), int(std::lround(n.y)), int(std::lround(n.z))});
  }
  EXPECT_EQ(normals.size(), 6u);
}

TEST(VsaSegmentation, DisconnectedMeshGetsRegionsInEveryComponent) {
  PolygonMesh m;
  append_box(m, 3, 1.0);
  append_box(m, 3, 1.0, Vec3(5, 0, 0));
  const VsaSegmentation seg = segment(m, 12);
  ASSERT_EQ(seg.num_regions(), 12u);
  EXPECT_LT(seg.total_error, 1e-12 * seg.total_area);
  EXPECT_TRUE(regions_connected(m, seg.face_region, 12));
  EXPECT_EQ(status_of([&] { segment(m, 1); }), Status::invalid_argument);  // fewer regions than components
}

TEST(VsaSegmentation, BarrierEdgesAreRegionBordersAndEnclosedPatchesGetRegions) {
  // A smooth cylinder cut by two barrier rings (at a quarter and at half its height): no region
  // has faces on two sides of a ring, every patch gets a region, and fewer regions than patches
  // are refused as fewer than components are (each patch is a component of its own).
  const int around = 24, along = 16;
  const PolygonMesh m = cagekit_test::triangle_cylinder(1.0, 4.0, around, along);
  VsaOptions options;
  options.region_count = 5;
  for (const int row : {along / 4, along / 2})
    for (int i = 0; i < around; ++i)
      options.barrier_edges.push_back(cagekit::edge_key(uint32_t(row * around + i),
                                                        uint32_t(row * around + (i + 1) % around)));
  std::sort(options.barrier_edges.begin(), options.barrier_edges.end());
  const VsaSegmentation seg = cagekit::segment_vsa(m, options);
  ASSERT_EQ(seg.num_regions(), 5u);
  auto band = [&](size_t f) {  // 0 below the first ring, 1 between, 2 above the second
    double z = 0;
    for (uint32_t k = 0; k < 3; ++k) z += m.positions[m.face_vertex(f, k)].z / 3.0;
    return z < 1.0 ? 0 : z < 2.0 ? 1 : 2;
  };
  std::map<uint32_t, std::set<int>> bands_of_region;
  for (size_t f = 0; f < m.num_faces(); ++f) bands_of_region[seg.face_region[f]].insert(band(f));
  std::set<int> covered;
  for (const auto& [region, bands] : bands_of_region) {
    EXPECT_EQ(bands.size(), 1u) << "region " << region << " crosses a barrier";
    covered.insert(*bands.begin());
  }
  EXPECT_EQ(covered.size(), 3u);
  options.region_count = 2;  // three patches
  EXPECT_EQ(status_of([&] { cagekit::segment_vsa(m, options); }), Status::invalid_argument);
}

TEST(VsaSegmentation, BadInputGivesPreciseErrors) {
  const PolygonMesh cube = box(1, 1.0);  // 12 triangles
  VsaOptions options;
  options.region_count = 13;
  EXPECT_EQ(status_of([&] { cagekit::segment_vsa(cube, options); }), Status::invalid_argument);
  options.region_count = 0;
  EXPECT_EQ(status_of([&] { cagekit::segment_vsa(cube, options); }), Status::invalid_argument);
  options.region_count = 6;
  EXPECT_EQ(status_of([&] { cagekit::segment_vsa(cagekit_test::quad_grid(2, 2), options); }), Status::invalid_mesh);
  EXPECT_EQ(status_of([&] { cagekit::segment_vsa(PolygonMesh{}, options); }), Status::invalid_mesh);
  PolygonMesh bad = cube;
  bad.face_vertices[4] = 99;
  EXPECT_EQ(status_of([&] { cagekit::segment_vsa(bad, options); }), Status::invalid_mesh);
  bad = cube;
  bad.positions[0].x = std::nan("");
  EXPECT_EQ(status_of([&] { cagekit::segment_vsa(bad, options); }), Status::invalid_mesh);
  options.pinned_regions = {{0, 1}, {1, 2}};  // face 1 twice
  EXPECT_EQ(status_of([&] { cagekit::segment_vsa(cube, options); }), Status::invalid_argument);
  options.pinned_regions = {{0, 11}};  // not edge-connected (opposite sides)
  EXPECT_EQ(status_of([&] { cagekit::segment_vsa(cube, options); }), Status::invalid_argument);
  options.pinned_regions = {{0}};
  options.seed_faces = {0};  // pinned
  EXPECT_EQ(status_of([&] { cagekit::segment_vsa(cube, options); }), Status::invalid_argument);
  options.pinned_regions.clear();
  options.seed_faces = {1, 2, 3, 4, 5, 6, 7};  // more seeds than regions
  EXPECT_EQ(status_of([&] { cagekit::segment_vsa(cube, options); }), Status::invalid_argument);
  options.seed_faces.clear();
  for (double fraction : {-0.5, std::nan(""), HUGE_VAL}) {
    VsaOptions batch = options;
    batch.insertion_batch_fraction = fraction;
    EXPECT_EQ(status_of([&] { cagekit::segment_vsa(cube, batch); }), Status::invalid_argument) << fraction;
  }
  const cagekit::TaskMonitor cancel([](const char*, double) { return false; }, nullptr);
  EXPECT_EQ(status_of([&] { cagekit::segment_vsa(box(4, 1.0), options, cancel); }), Status::cancelled);
}

TEST(VsaSegmentation, DegenerateTrianglesAndOpenBoundariesAreHandled) {
  // An open, folded grid (two planes at 90 degrees) with a few zero-area triangles: vertex 7
  // moved onto vertex 8 makes the triangles around that edge degenerate.
  PolygonMesh m = triangle_grid(8, 4, [](double x, double) { return x > 4 ? x - 4 : 0.0; });
  m.positions[7] = m.positions[8];
  const VsaSegmentation seg = segment(m, 2);
  ASSERT_EQ(seg.num_regions(), 2u);
  EXPECT_TRUE(regions_connected(m, seg.face_region, 2));
  // The two planes: every face with a defined normal is in the region of its plane.
  for (uint32_t f = 0; f < m.num_faces(); ++f) {
    const Vec3 n = face_normal(m, f);
    if (cagekit::norm(n) == 0.0) continue;
    EXPECT_LT(cagekit::distance(n, seg.proxy_normal[seg.face_region[f]]), 1e-9) << "face " << f;
  }
}

TEST(VsaSegmentation, FandiskThirtyRegions) {
  const PolygonMesh m = load_shared("fandisk.obj");
  if (m.num_faces() == 0) GTEST_SKIP() << "../shared/meshes/fandisk.obj not present";
  VsaOptions options;
  options.region_count = 30;
  const auto t0 = std::chrono::steady_clock::now();
  const VsaSegmentation seg = cagekit::segment_vsa(m, options);
  const double seconds = seconds_since(t0);
  ASSERT_EQ(seg.num_regions(), 30u);
  ASSERT_EQ(seg.face_region.size(), m.num_faces());
  for (uint32_t r : seg.face_region) ASSERT_LT(r, 30u);  // every face in exactly one region
  EXPECT_TRUE(regions_connected(m, seg.face_region, 30));
  // Monotone within every relaxation.
  for (size_t k = 0; k < seg.relaxation_starts.size(); ++k) {
    const size_t end = k + 1 < seg.relaxation_starts.size() ? seg.relaxation_starts[k + 1] : seg.error_history.size();
    for (size_t i = seg.relaxation_starts[k] + 1; i < end; ++i)
      EXPECT_LE(seg.error_history[i], seg.error_history[i - 1]) << "relaxation " << k << " iteration " << i;
  }
  // Teleporting never increases the error: accepted teleports lower it, and the result is at
  // most the error before teleporting.
  size_t accepted = 0;
  for (const cagekit::VsaTeleport& t : seg.teleports) {
    if (t.accepted) {
      ++accepted;
      EXPECT_LT(t.error_after, t.error_before);
    } else {
      EXPECT_GE(t.error_after, t.error_before);
    }
  }
  EXPECT_LE(seg.total_error, seg.count_history.back().second);
  double sum = 0.0;
  for (double e : seg.region_error) sum += e;
  EXPECT_NEAR(sum, seg.total_error, 1e-9 * seg.total_area);
  std::printf("fandisk 30 regions: %.3f s, L2,1 error / area %.5f (before teleporting %.5f), %zu teleports "
              "(%zu accepted), %zu Lloyd iterations, %zu undone\n",
              seconds, seg.total_error / seg.total_area, seg.count_history.back().second / seg.total_area,
              seg.teleports.size(), accepted, seg.error_history.size(), seg.rejected_lloyd_iterations);
}

TEST(VsaSegmentation, BatchInsertionReachesTheCountWithAComparableError) {
  const PolygonMesh m = load_shared("fandisk.obj");
  if (m.num_faces() == 0) GTEST_SKIP() << "../shared/meshes/fandisk.obj not present";
  VsaOptions one, batch;
  one.region_count = batch.region_count = 40;
  one.insertion_batch_fraction = 0.0;
  batch.insertion_batch_fraction = 0.2;
  const VsaSegmentation a = cagekit::segment_vsa(m, one), b = cagekit::segment_vsa(m, batch);
  for (const VsaSegmentation* s : {&a, &b}) {
    ASSERT_EQ(s->num_regions(), 40u);
    EXPECT_TRUE(regions_connected(m, s->face_region, 40));
  }
  // One count per insertion step: every count from 1 to 40 one at a time, fewer steps in batches
  // (each adding at most a fifth of the regions present, at least one).
  EXPECT_EQ(a.count_history.size(), 40u);
  EXPECT_LT(b.count_history.size(), a.count_history.size());
  for (size_t k = 1; k < b.count_history.size(); ++k) {
    const uint32_t before = b.count_history[k - 1].first, after = b.count_history[k].first;
    EXPECT_GE(after, before + 1);
    EXPECT_LE(after, std::max<uint32_t>(before + 1, before + before / 5));
  }
  // The final partitions are comparable (the batch one within 10% of the one-at-a-time error).
  EXPECT_LE(b.total_error, 1.1 * a.total_error);
}

TEST(VsaSegmentation, RejectedTeleportsRestoreThePartitionExactly) {
  const PolygonMesh m = load_shared("fandisk.obj");
  if (m.num_faces() == 0) GTEST_SKIP() << "../shared/meshes/fandisk.obj not present";
  // Find region counts whose first teleport attempts are rejected; with only those attempts the
  // result must equal the run without teleporting bit for bit (AC6-9).
  size_t compared = 0;
  for (int count = 8; count <= 30 && compared < 2; count += 2) {
    VsaOptions options;
    options.region_count = count;
    const VsaSegmentation teleported = cagekit::segment_vsa(m, options);
    size_t leading_rejections = 0;
    while (leading_rejections < teleported.teleports.size() && !teleported.teleports[leading_rejections].accepted)
      ++leading_rejections;
    if (leading_rejections == 0) continue;
    options.teleport_attempts = 0;
    const VsaSegmentation plain = cagekit::segment_vsa(m, options);
    options.teleport_attempts = int(leading_rejections);
    const VsaSegmentation rolled_back = cagekit::segment_vsa(m, options);
    ASSERT_EQ(rolled_back.teleports.size(), leading_rejections);
    EXPECT_EQ(rolled_back.face_region, plain.face_region) << count << " regions";
    EXPECT_EQ(rolled_back.total_error, plain.total_error) << count << " regions";
    for (size_t r = 0; r < plain.num_regions(); ++r) EXPECT_EQ(rolled_back.proxy_normal[r], plain.proxy_normal[r]);
    EXPECT_EQ(rolled_back.error_history, plain.error_history);
    std::printf("%d regions: %zu rejected teleports rolled back exactly\n", count, leading_rejections);
    ++compared;
  }
  EXPECT_GT(compared, 0u) << "no region count with a rejected first teleport";
}

TEST(VsaSegmentation, PinnedRegionsKeepTheirFacesAndSeedsStartRegions) {
  const PolygonMesh m = load_shared("fandisk.obj");
  if (m.num_faces() == 0) GTEST_SKIP() << "../shared/meshes/fandisk.obj not present";
  VsaOptions first;
  first.region_count = 12;
  const VsaSegmentation base = cagekit::segment_vsa(m, first);
  // Pin two regions of a coarse segmentation (whatever their shape) and ask for 20 regions.
  VsaOptions options;
  options.region_count = 20;
  options.pinned_regions = {base.region_faces(3), base.region_faces(7)};
  options.seed_faces = {base.region_seed[0], base.region_seed[1]};
  const VsaSegmentation seg = cagekit::segment_vsa(m, options);
  ASSERT_EQ(seg.num_regions(), 20u);
  EXPECT_EQ(seg.region_faces(0), options.pinned_regions[0]);
  EXPECT_EQ(seg.region_faces(1), options.pinned_regions[1]);
  EXPECT_EQ(seg.region_pinned[0], 1);
  EXPECT_EQ(seg.region_pinned[1], 1);
  EXPECT_EQ(seg.region_pinned[2], 0);
  EXPECT_TRUE(regions_connected(m, seg.face_region, 20));
  for (const cagekit::VsaTeleport& t : seg.teleports) EXPECT_GE(t.removed_region, 2u);
}

TEST(VsaSegmentation, ToleranceModeStopsAtTheFirstCountMeetingIt) {
  const PolygonMesh m = load_shared("fandisk.obj");
  if (m.num_faces() == 0) GTEST_SKIP() << "../shared/meshes/fandisk.obj not present";
  VsaOptions options;
  options.region_count = 60;
  options.tolerance = 0.01;
  const VsaSegmentation seg = cagekit::segment_vsa(m, options);
  ASSERT_GE(seg.count_history.size(), 2u);
  const double limit = options.tolerance * seg.total_area;
  EXPECT_LE(seg.count_history.back().second, limit);
  for (size_t i = 0; i + 1 < seg.count_history.size(); ++i) EXPECT_GT(seg.count_history[i].second, limit);
  EXPECT_EQ(seg.num_regions(), seg.count_history.back().first);
  EXPECT_LE(seg.total_error, limit);
  EXPECT_LT(seg.num_regions(), 60u);
  std::printf("fandisk tolerance 0.01: %zu regions\n", seg.num_regions());
}

// ---------------------------------------------------------------------------------------------
// Region boundaries

namespace {

// Checks the structural invariants of region boundaries against the mesh and segmentation:
// every region-boundary edge is in exactly one arc, arcs run between anchors through non-anchors
// with constant sides, every arc is used once per side by the loops, loops are closed chains of
// edges with the region on the left.
void expect_consistent_boundaries(const PolygonMesh& m, const std::vector<uint32_t>& face_region, size_t regions,
                                  const cagekit::RegionBoundaries& b) {
  cagekit::detail::EdgeMap map;
  build_edge_map(map, m, std::vector<uint8_t>(m.num_faces(), 1));
  // Directed half-edges (a -> b) with their region.
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> half_edge_region;
  for (uint32_t c = 0; c < m.num_face_vertices(); ++c) half_edge_region[{map.from(c), map.to(c)}] = face_region[map.corner_face[c]];
  std::map<std::pair<uint32_t, uint32_t>, int> arc_edges;
  for (size_t a = 0; a < b.arcs.size(); ++a) {
    const cagekit::RegionArc& arc = b.arcs[a];
    ASSERT_GE(arc.vertices.size(), 2u);
    EXPECT_NE(arc.vertices.front(), arc.vertices.back()) << "arc " << a;
    EXPECT_TRUE(b.is_anchor(arc.vertices.front()));
    EXPECT_TRUE(b.is_anchor(arc.vertices.back()));
    for (size_t i = 1; i + 1 < arc.vertices.size(); ++i) EXPECT_FALSE(b.is_anchor(arc.vertices[i])) << "arc " << a;
    for (size_t i = 0; i + 1 < arc.vertices.size(); ++i) {
      const uint32_t p = arc.vertices[i], q = arc.vertices[i + 1];
      ++arc_edges[std::minmax(p, q)];
      auto left = half_edge_region.find({p, q});
      ASSERT_TRUE(left != half_edge_region.end()) << "arc " << a << " edge " << p << "-" << q;
      EXPECT_EQ(left->second, arc.left_region);
      auto right = half_edge_region.find({q, p});
      EXPECT_EQ(right == half_edge_region.end() ? cagekit::kMeshBorder : right->second, arc.right_region);
    }
  }
  size_t boundary_edges = 0;
  for (size_t e = 0; e < map.num_edges(); ++e) {
    const uint32_t* h = map.corners_begin(e);
    const bool boundary = map.valence(e) == 1 || face_region[map.corner_face[h[0]]] != face_region[map.corner_face[h[1]]];
    const auto it = arc_edges.find({map.edge_lo[e], map.edge_hi[e]});
    EXPECT_EQ(it == arc_edges.end() ? 0 : it->second, boundary ? 1 : 0) << "edge " << map.edge_lo[e] << "-" << map.edge_hi[e];
    boundary_edges += boundary;
  }
  EXPECT_EQ(arc_edges.size(), boundary_edges);
  std::vector<int> uses(b.arcs.size(), 0);
  ASSERT_EQ(b.region_loops.size(), regions);
  for (uint32_t r = 0; r < regions; ++r) {
    EXPECT_GE(b.region_loops[r].size(), 1u) << "region " << r;
    for (const cagekit::RegionLoop& loop : b.region_loops[r]) {
      for (size_t k = 0; k < loop.arcs.size(); ++k) {
        ++uses[loop.arcs[k]];
        const cagekit::RegionArc& arc = b.arcs[loop.arcs[k]];
        EXPECT_EQ(loop.reversed[k] ? arc.right_region : arc.left_region, r);
      }
      const std::vector<uint32_t> v = b.loop_vertices(loop);
      for (size_t i = 0; i < v.size(); ++i) {
        auto it = half_edge_region.find({v[i], v[(i + 1) % v.size()]});
        ASSERT_TRUE(it != half_edge_region.end());
        EXPECT_EQ(it->second, r) << "loop of region " << r << " does not keep the region on its left";
      }
    }
  }
  for (size_t a = 0; a < b.arcs.size(); ++a)
    EXPECT_EQ(uses[a], b.arcs[a].right_region == cagekit::kMeshBorder ? 1 : 2) << "arc " << a;
}

}  // namespace

TEST(RegionBoundaries, CubeSidesMeetAtEightAnchorsAlongTwelveArcs) {
  const PolygonMesh m = box(4, 1.0);
  const VsaSegmentation seg = segment(m, 6);
  const cagekit::RegionBoundaries b = cagekit::compute_region_boundaries(m, seg.face_region, 6);
  EXPECT_EQ(b.anchors.size(), 8u);
  for (uint8_t inserted : b.anchor_inserted) EXPECT_EQ(inserted, 0);
  for (uint32_t a : b.anchors) {
    const Vec3& p = m.positions[a];
    EXPECT_TRUE((p.x == 0 || p.x == 4) && (p.y == 0 || p.y == 4) && (p.z == 0 || p.z == 4));
  }
  ASSERT_EQ(b.arcs.size(), 12u);
  for (const cagekit::RegionArc& arc : b.arcs) EXPECT_EQ(arc.vertices.size(), 5u);
  for (uint32_t r = 0; r < 6; ++r) {
    ASSERT_EQ(b.region_loops[r].size(), 1u);
    EXPECT_EQ(b.region_loops[r][0].arcs.size(), 4u);
    EXPECT_NEAR(b.region_loops[r][0].length, 16.0, 1e-12);
    EXPECT_EQ(b.region_genus(r), 0);
  }
  expect_consistent_boundaries(m, seg.face_region, 6, b);
}

TEST(RegionBoundaries, ClosedChainsWithoutAnchorsAreSplitIntoThreeArcs) {
  // Sphere: a polar cap inside the rest (one anchor-free circle); open grid as one region (the
  // anchor-free mesh border); a grid with a disk region in the middle (a region with a hole).
  const PolygonMesh sphere = cagekit_test::triangle_sphere(3);
  std::vector<uint32_t> cap(sphere.num_faces());
  for (uint32_t f = 0; f < sphere.num_faces(); ++f) {
    const Vec3 c = face_centroid(sphere, f);
    cap[f] = c.z > 0.6 ? 1 : 0;
  }
  const cagekit::RegionBoundaries b = cagekit::compute_region_boundaries(sphere, cap, 2);
  EXPECT_EQ(b.anchors.size(), 3u);
  EXPECT_EQ(b.arcs.size(), 3u);
  for (uint8_t inserted : b.anchor_inserted) EXPECT_EQ(inserted, 1);
  expect_consistent_boundaries(sphere, cap, 2, b);

  const PolygonMesh grid = triangle_grid(6, 6);
  std::vector<uint32_t> one(grid.num_faces(), 0);
  const cagekit::RegionBoundaries g = cagekit::compute_region_boundaries(grid, one, 1);
  EXPECT_EQ(g.arcs.size(), 3u);
  for (const cagekit::RegionArc& arc : g.arcs) EXPECT_EQ(arc.right_region, cagekit::kMeshBorder);
  EXPECT_EQ(g.region_genus(0), 0);
  expect_consistent_boundaries(grid, one, 1, g);

  std::vector<uint32_t> holed(grid.num_faces(), 0);
  for (uint32_t f = 0; f < grid.num_faces(); ++f) {
    const Vec3 c = face_centroid(grid, f);
    holed[f] = std::abs(c.x - 3) < 1 && std::abs(c.y - 3) < 1 ? 1 : 0;
  }
  const cagekit::RegionBoundaries h = cagekit::compute_region_boundaries(grid, holed, 2);
  ASSERT_EQ(h.region_loops[0].size(), 2u);  // outer border + the hole around region 1
  EXPECT_EQ(h.region_loops[1].size(), 1u);
  EXPECT_EQ(h.region_genus(0), 0);
  EXPECT_EQ(h.arcs.size(), 6u);
  expect_consistent_boundaries(grid, holed, 2, h);
}

TEST(RegionBoundaries, VertexWhereTwoRegionsMeetTwiceIsAnAnchor) {
  // Checkerboard of 2x2 quadrants on a 4x4 grid: regions A B / B A meet at the centre vertex
  // twice (A B A B around it). The centre and the four border points where the region changes
  // are anchors; 4 interior arcs, 4 border arcs; each region has two loops (its two quadrants).
  const PolygonMesh m = triangle_grid(4, 4);
  std::vector<uint32_t> region(m.num_faces());
  for (uint32_t f = 0; f < m.num_faces(); ++f) {
    const Vec3 c = face_centroid(m, f);
    region[f] = (c.x < 2) != (c.y < 2) ? 1 : 0;
  }
  const cagekit::RegionBoundaries b = cagekit::compute_region_boundaries(m, region, 2);
  EXPECT_EQ(b.anchors, (std::vector<uint32_t>{2, 10, 12, 14, 22}));
  EXPECT_EQ(b.arcs.size(), 8u);
  EXPECT_EQ(b.region_loops[0].size(), 2u);
  EXPECT_EQ(b.region_loops[1].size(), 2u);
  expect_consistent_boundaries(m, region, 2, b);
}

TEST(RegionBoundaries, SplitArcKeepsLoopsConsistent) {
  const PolygonMesh m = box(4, 1.0);
  const VsaSegmentation seg = segment(m, 6);
  cagekit::RegionBoundaries b = cagekit::compute_region_boundaries(m, seg.face_region, 6);
  const uint32_t middle = b.arcs[0].vertices[2];
  cagekit::split_arc(b, 0, 2);
  ASSERT_EQ(b.arcs.size(), 13u);
  EXPECT_EQ(b.anchors.size(), 9u);
  EXPECT_TRUE(b.is_anchor(middle));
  EXPECT_EQ(b.arcs[0].vertices.back(), middle);
  EXPECT_EQ(b.arcs[12].vertices.front(), middle);
  expect_consistent_boundaries(m, seg.face_region, 6, b);
  EXPECT_EQ(status_of([&] { cagekit::split_arc(b, 0, 0); }), Status::invalid_argument);
  EXPECT_EQ(status_of([&] { cagekit::split_arc(b, 99, 1); }), Status::invalid_argument);
}

TEST(RegionBoundaries, BadInputGivesPreciseErrors) {
  const PolygonMesh m = box(1, 1.0);
  EXPECT_EQ(status_of([&] { cagekit::compute_region_boundaries(m, std::vector<uint32_t>(5, 0), 1); }),
            Status::invalid_argument);
  EXPECT_EQ(status_of([&] { cagekit::compute_region_boundaries(m, std::vector<uint32_t>(12, 3), 2); }),
            Status::invalid_argument);
  PolygonMesh fin = m;  // a third face on edge 0-1: non-manifold
  const uint32_t extra = fin.add_vertex(Vec3(0.5, -1, 0.5));
  fin.add_face({fin.face_vertex(0, 0), fin.face_vertex(0, 1), extra});
  EXPECT_EQ(status_of([&] { cagekit::compute_region_boundaries(fin, std::vector<uint32_t>(13, 0), 1); }),
            Status::invalid_mesh);
}

TEST(RegionBoundaries, FandiskThirtyRegionsAreConsistent) {
  const PolygonMesh m = load_shared("fandisk.obj");
  if (m.num_faces() == 0) GTEST_SKIP() << "../shared/meshes/fandisk.obj not present";
  const VsaSegmentation seg = segment(m, 30);
  const cagekit::RegionBoundaries b = cagekit::compute_region_boundaries(m, seg.face_region, 30);
  expect_consistent_boundaries(m, seg.face_region, 30, b);
  size_t holes = 0;
  for (uint32_t r = 0; r < 30; ++r) {
    EXPECT_EQ(b.region_genus(r), 0) << "region " << r;
    holes += b.region_loops[r].size() - 1;
  }
  std::printf("fandisk 30 regions: %zu anchors, %zu arcs, %zu holes\n", b.anchors.size(), b.arcs.size(), holes);
}

// ---------------------------------------------------------------------------------------------
// Arc cubics (6.1) and samples

TEST(ArcFit, CircleArcIsFittedClosely) {
  // A 90-degree arc of radius 1 in 32 edges: a cubic fits it to ~1e-4.
  std::vector<Vec3> points;
  for (int i = 0; i <= 32; ++i) {
    const double a = 0.5 * kPi * i / 32;
    points.push_back(Vec3(std::cos(a), std::sin(a), 0.0));
  }
  const std::vector<double> s = cagekit::arc_length_parameters(points);
  const cagekit::ArcCubic c = cagekit::fit_arc_cubic(points, s);
  EXPECT_EQ(c.control[0], points.front());
  EXPECT_EQ(c.control[3], points.back());
  const double rms = cagekit::arc_fit_rms(c, points, s);
  EXPECT_LT(rms, 2e-3);
  const cagekit::ArcSamples samples = cagekit::sample_arc_cubic(c, 0.1);
  // len ≈ π/2 → r = ⌈15.7⌉ − 1 = 15 interior samples.
  ASSERT_EQ(samples.position.size(), 17u);
  EXPECT_EQ(samples.position.front(), points.front());
  EXPECT_EQ(samples.position.back(), points.back());
  for (const Vec3& p : samples.position) EXPECT_NEAR(cagekit::norm(p), 1.0, 3e-3);
  // (6.1) optimality: moving either inner control point raises the residual.
  for (int k = 1; k <= 2; ++k)
    for (const Vec3& d : {Vec3(1e-3, 0, 0), Vec3(0, -1e-3, 0), Vec3(0, 0, 1e-3), Vec3(-7e-4, 7e-4, 0)}) {
      cagekit::ArcCubic moved = c;
      moved.control[k] += d;
      EXPECT_GT(cagekit::arc_fit_rms(moved, points, s), rms);
    }
  // Equidistant in arc length: consecutive chords equal to ~1e-3 relative.
  for (size_t k = 1; k + 1 < samples.position.size(); ++k) {
    const double a = cagekit::distance(samples.position[k - 1], samples.position[k]);
    const double b = cagekit::distance(samples.position[k], samples.position[k + 1]);
    EXPECT_NEAR(a, b, 2e-3 * a);
  }
  std::printf("quarter circle: rms %.2e\n", rms);
}

TEST(ArcFit, ReproducesAStraightLineAndIsExactForLinearData) {
  // Unevenly spaced points on a line: the cubic is the line parameterised by arc length, so the
  // fit error is 0 and samples are equidistant points of the segment.
  std::vector<Vec3> points = {Vec3(0, 0, 0), Vec3(0.1, 0.2, 0.2), Vec3(1, 2, 2), Vec3(1.2, 2.4, 2.4), Vec3(3, 6, 6)};
  const std::vector<double> s = cagekit::arc_length_parameters(points);
  const cagekit::ArcCubic c = cagekit::fit_arc_cubic(points, s);
  EXPECT_LT(cagekit::arc_fit_rms(c, points, s), 1e-12);
  EXPECT_NEAR(cagekit::arc_cubic_length(c), 9.0, 1e-10);
  const cagekit::ArcSamples samples = cagekit::sample_arc_cubic(c, 1.8);  // r = ⌈9 / 1.8⌉ - 1 = 4
  ASSERT_EQ(samples.position.size(), 6u);
  for (size_t k = 0; k < samples.position.size(); ++k)
    EXPECT_LT(cagekit::distance(samples.position[k], Vec3(3, 6, 6) * (double(k) / 5)), 1e-9);
  // A very long spacing gives the two end points only.
  EXPECT_EQ(cagekit::sample_arc_cubic(c, 100.0).position.size(), 2u);
  EXPECT_EQ(status_of([&] { cagekit::sample_arc_cubic(c, 0.0); }), Status::invalid_argument);
  EXPECT_EQ(status_of([&] { cagekit::fit_arc_cubic({Vec3()}, {0.0}); }), Status::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// LSCM

TEST(Lscm, PlanarRegionMapsBySimilarity) {
  // A rotated, tilted planar grid with jittered vertices: LSCM reproduces it up to a similarity.
  PolygonMesh m = triangle_grid(10, 7);
  const Vec3 ex = cagekit::normalized(Vec3(1, 2, 0.5)), ey = cagekit::normalized(cagekit::cross(Vec3(0.3, -0.2, 1), ex));
  for (size_t v = 0; v < m.num_vertices(); ++v) {
    const double jx = 0.2 * std::sin(7.1 * v), jy = 0.2 * std::cos(3.3 * v);
    m.positions[v] = ex * (m.positions[v].x + jx) + ey * (m.positions[v].y + jy) + Vec3(5, -2, 1);
  }
  std::vector<uint32_t> faces(m.num_faces());
  for (uint32_t f = 0; f < faces.size(); ++f) faces[f] = f;
  const cagekit::RegionParameterization p = cagekit::parameterize_region_lscm(m, faces);
  EXPECT_EQ(p.flipped_triangles, 0u);
  EXPECT_LT(p.max_conformal_distortion - 1.0, 1e-6);
  // Every pairwise distance scales by the same factor (1: the pins keep their 3D distance).
  for (uint32_t a = 0; a < m.num_vertices(); a += 7)
    for (uint32_t b = a + 1; b < m.num_vertices(); b += 5) {
      const auto& pa = p.uv_of(a);
      const auto& pb = p.uv_of(b);
      EXPECT_NEAR(std::hypot(pa.x - pb.x, pa.y - pb.y), cagekit::distance(m.positions[a], m.positions[b]), 1e-6);
    }
  // The outer boundary runs counter-clockwise.
  const cagekit::RegionBoundaries b = cagekit::compute_region_boundaries(m, std::vector<uint32_t>(m.num_faces(), 0), 1);
  EXPECT_GT(cagekit::signed_domain_area(p, b.loop_vertices(b.region_loops[0][0])), 0.0);
}

TEST(Lscm, CurvedRegionHasNoFlipsAndBoundedDistortion) {
  // A spherical cap of 120 degrees opening (a bowl, Gaussian curvature 1) and a cylinder patch.
  const PolygonMesh sphere = cagekit_test::triangle_sphere(4);
  std::vector<uint32_t> cap;
  for (uint32_t f = 0; f < sphere.num_faces(); ++f) {
    const Vec3 c = face_centroid(sphere, f);
    if (c.z > 0.5) cap.push_back(f);
  }
  const cagekit::RegionParameterization p = cagekit::parameterize_region_lscm(sphere, cap);
  EXPECT_EQ(p.flipped_triangles, 0u);
  EXPECT_LT(p.mean_conformal_distortion, 1.1);
  EXPECT_LT(p.max_conformal_distortion, 1.6);
  PolygonMesh cylinder = triangle_grid(24, 8);
  for (Vec3& q : cylinder.positions) {
    const double a = q.x / 24 * kPi;  // half a cylinder of radius 24/π
    q = Vec3(24 / kPi * std::cos(a), q.y, 24 / kPi * std::sin(a));
  }
  std::vector<uint32_t> all(cylinder.num_faces());
  for (uint32_t f = 0; f < all.size(); ++f) all[f] = f;
  const cagekit::RegionParameterization c = cagekit::parameterize_region_lscm(cylinder, all);
  EXPECT_EQ(c.flipped_triangles, 0u);
  EXPECT_LT(c.mean_conformal_distortion, 1.05);  // developable: only the chord discretisation
  std::printf("cap: mean %.4f max %.4f; half cylinder: mean %.4f max %.4f\n", p.mean_conformal_distortion,
              p.max_conformal_distortion, c.mean_conformal_distortion, c.max_conformal_distortion);
}

TEST(Lscm, ZeroAreaTrianglesGetNoConstraintButAPosition) {
  // Interior vertex 16 = (2, 2) moved onto its neighbour 17 = (3, 2): the two triangles on edge
  // 16-17 have zero area. The others are still mapped by one similarity, which puts 16 onto 17.
  PolygonMesh m = triangle_grid(6, 5);
  m.positions[16] = m.positions[17];
  std::vector<uint32_t> faces(m.num_faces());
  for (uint32_t f = 0; f < faces.size(); ++f) faces[f] = f;
  const cagekit::RegionParameterization p = cagekit::parameterize_region_lscm(m, faces);
  EXPECT_EQ(p.flipped_triangles, 0u);
  EXPECT_LT(p.max_conformal_distortion - 1.0, 1e-6);
  for (const auto& uv : p.uv) EXPECT_TRUE(std::isfinite(uv.x) && std::isfinite(uv.y));
  EXPECT_NEAR(std::hypot(p.uv_of(16).x - p.uv_of(17).x, p.uv_of(16).y - p.uv_of(17).y), 0.0, 1e-6);
  EXPECT_NEAR(std::hypot(p.uv_of(0).x - p.uv_of(6).x, p.uv_of(0).y - p.uv_of(6).y), 6.0, 1e-6);
}

TEST(Lscm, RegionsThatAreNoDisksAreRefused) {
  const PolygonMesh cube = box(2, 1.0);
  std::vector<uint32_t> all(cube.num_faces());
  for (uint32_t f = 0; f < all.size(); ++f) all[f] = f;
  EXPECT_EQ(status_of([&] { cagekit::parameterize_region_lscm(cube, all); }), Status::invalid_mesh);  // closed
  EXPECT_EQ(status_of([&] { cagekit::parameterize_region_lscm(cube, {0, 40}); }), Status::invalid_mesh);  // disconnected
  EXPECT_EQ(status_of([&] { cagekit::parameterize_region_lscm(cube, {}); }), Status::invalid_argument);
  EXPECT_EQ(status_of([&] { cagekit::parameterize_region_lscm(cube, {1, 1}); }), Status::invalid_argument);
  EXPECT_EQ(status_of([&] { cagekit::parameterize_region_lscm(cube, {1000}); }), Status::invalid_argument);
  // A torus minus one quad: genus 1 with one hole.
  const PolygonMesh torus = triangle_torus(12, 8);
  std::vector<uint32_t> band;
  for (uint32_t f = 2; f < torus.num_faces(); ++f) band.push_back(f);
  EXPECT_EQ(status_of([&] { cagekit::parameterize_region_lscm(torus, band); }), Status::invalid_mesh);
}

// ---------------------------------------------------------------------------------------------
// Assembled constraints on real meshes

namespace {

void check_real_mesh_constraints(const char* name, int regions, double delta_fraction) {
  const PolygonMesh m = load_shared(name);
  if (m.num_faces() == 0) GTEST_SKIP() << "../shared/meshes/" << name << " not present";
  VsaOptions options;
  options.region_count = regions;
  const auto t0 = std::chrono::steady_clock::now();
  const VsaSegmentation seg = cagekit::segment_vsa(m, options);
  const double t_vsa = seconds_since(t0);
  const auto t1 = std::chrono::steady_clock::now();
  cagekit::ConstraintOptions constraint_options;
  constraint_options.spacing = cagekit::spacing_from_bbox_fraction(m, delta_fraction);
  const cagekit::RemeshConstraints c =
      cagekit::compute_remesh_constraints(m, seg.face_region, seg.num_regions(), constraint_options);
  const double t_constraints = seconds_since(t1);
  const double diagonal = m.bounding_box().diagonal();
  // Samples are shared: the loops of the two neighbours of every interior arc list the same
  // points (in opposite order).
  for (size_t a = 0; a < c.boundaries.arcs.size(); ++a) {
    const cagekit::RegionArc& arc = c.boundaries.arcs[a];
    if (arc.right_region == cagekit::kMeshBorder) continue;
    std::vector<std::vector<Vec3>> seen;
    for (uint32_t r : {arc.left_region, arc.right_region})
      for (size_t l = 0; l < c.boundaries.region_loops[r].size(); ++l) {
        const cagekit::RegionLoop& loop = c.boundaries.region_loops[r][l];
        const std::vector<Vec3> samples = c.loop_samples(r, l);
        size_t offset = 0;
        for (size_t k = 0; k < loop.arcs.size(); ++k) {
          const size_t count = c.arcs[loop.arcs[k]].samples.position.size();
          if (loop.arcs[k] == a) {
            std::vector<Vec3> piece;
            for (size_t i = 0; i < count; ++i) piece.push_back(samples[(offset + i) % samples.size()]);
            if (loop.reversed[k]) std::reverse(piece.begin(), piece.end());
            seen.push_back(piece);
          }
          offset += count - 1;
        }
      }
    ASSERT_EQ(seen.size(), 2u) << "arc " << a;
    EXPECT_EQ(seen[0], seen[1]) << "arc " << a;
    EXPECT_EQ(seen[0].front(), m.positions[arc.vertices.front()]);
    EXPECT_EQ(seen[0].back(), m.positions[arc.vertices.back()]);
  }
  // Arcs that a cubic fitted poorly were split: the loops still cover every boundary edge once.
  expect_consistent_boundaries(m, seg.face_region, seg.num_regions(), c.boundaries);
  const cagekit::RegionBoundaries unsplit = cagekit::compute_region_boundaries(m, seg.face_region, seg.num_regions());
  double worst_rms = 0.0, worst_deviation = 0.0;
  size_t samples = 0;
  for (const cagekit::ArcConstraint& arc : c.arcs) {
    worst_rms = std::max(worst_rms, arc.fit_rms);
    worst_deviation = std::max(worst_deviation, arc.fit_max_deviation);
    samples += arc.samples.t.size() - 1;
  }
  for (size_t a = 0; a < c.arcs.size(); ++a) {
    if (c.boundaries.arcs[a].vertices.size() < 3) continue;
    EXPECT_LE(c.arcs[a].fit_rms, constraint_options.max_fit_rms * constraint_options.spacing) << "arc " << a;
  }
  size_t flipped = 0, flipped_regions = 0;
  double worst_mean = 1.0, worst_max = 1.0;
  for (uint32_t r = 0; r < seg.num_regions(); ++r) {
    const cagekit::RegionParameterization& p = c.domains[r];
    flipped += p.flipped_triangles;
    flipped_regions += p.flipped_triangles > 0;
    worst_mean = std::max(worst_mean, p.mean_conformal_distortion);
    worst_max = std::max(worst_max, p.max_conformal_distortion);
    // The outer loop runs counter-clockwise in the domain, holes clockwise; the domain samples
    // of the loops start and end at the anchors' (u, v).
    const auto& loops = c.boundaries.region_loops[r];
    for (size_t l = 0; l < loops.size(); ++l) {
      const double area = cagekit::signed_domain_area(p, c.boundaries.loop_vertices(loops[l]));
      if (l == 0) {
        EXPECT_GT(area, 0.0) << name << " region " << r;
      } else {
        EXPECT_LT(area, 0.0) << name << " region " << r << " hole " << l;
      }
      EXPECT_EQ(c.loop_samples_uv(r, l).size(), c.loop_samples(r, l).size());
    }
  }
  EXPECT_LT(worst_mean, 1.5) << name;
  std::printf("%s %d regions: VSA %.2f s (L2,1/area %.4f), constraints %.2f s; %zu anchors, %zu arcs (%zu before "
              "splitting), %zu samples at delta %.0f%%, worst arc rms %.4f%% and max vertex deviation %.4f%% of diag; LSCM: %zu flipped triangles in %zu regions, "
              "worst region mean distortion %.3f, worst triangle %.3f\n",
              name, regions, t_vsa, seg.total_error / seg.total_area, t_constraints, c.boundaries.anchors.size(),
              c.boundaries.arcs.size(), unsplit.arcs.size(), samples, 100 * delta_fraction, 100 * worst_rms / diagonal, 100 * worst_deviation / diagonal, flipped,
              flipped_regions, worst_mean, worst_max);
}

}  // namespace

TEST(RemeshConstraints, CubeSidesShareTheirSamplesAndCancelCleanly) {
  const PolygonMesh m = box(4, 0.25);  // the unit cube, 4 x 4 quads per side
  const VsaSegmentation seg = segment(m, 6);
  cagekit::ConstraintOptions constraint_options;
  constraint_options.spacing = 0.25;
  const cagekit::RemeshConstraints c = cagekit::compute_remesh_constraints(m, seg.face_region, 6, constraint_options);
  ASSERT_EQ(c.arcs.size(), 12u);
  for (const cagekit::ArcConstraint& arc : c.arcs) {
    EXPECT_LT(arc.fit_rms, 1e-12);                // straight cube edges
    ASSERT_EQ(arc.samples.position.size(), 5u);  // length 1 / 0.25: 3 interior samples
  }
  for (uint32_t r = 0; r < 6; ++r) {
    // Each side: a unit square in its domain, its 16 boundary samples on the square's outline.
    const std::vector<cagekit::Vec2> uv = c.loop_samples_uv(r, 0);
    ASSERT_EQ(uv.size(), 16u);
    double area = 0.0;
    for (size_t i = 0; i < uv.size(); ++i) {
      const auto& p = uv[i];
      const auto& q = uv[(i + 1) % uv.size()];
      area += 0.5 * (p.x * q.y - p.y * q.x);
      EXPECT_NEAR(std::hypot(q.x - p.x, q.y - p.y), 0.25, 1e-8);
    }
    EXPECT_NEAR(area, 1.0, 1e-8);  // the 1e-10 regularising Laplacian shrinks it by ~1.5e-9
    EXPECT_EQ(c.loop_samples(r, 0).size(), 16u);
  }
  const cagekit::TaskMonitor cancel([](const char*, double) { return false; }, nullptr);
  EXPECT_EQ(status_of([&] { cagekit::compute_remesh_constraints(m, seg.face_region, 6, constraint_options, cancel); }),
            Status::cancelled);
  constraint_options.spacing = 0.0;
  EXPECT_EQ(status_of([&] { cagekit::compute_remesh_constraints(m, seg.face_region, 6, constraint_options); }),
            Status::invalid_argument);
}

TEST(RemeshConstraints, EveryLoopKeepsThreePointsAtCoarseSpacing) {
  // A flat square split into its left and right halves: each half's loop is two arcs (its part
  // of the border and the shared arc) between the two anchors; with δ larger than the square
  // every arc wants one segment, a 2-point loop the curve network cannot use — each loop must
  // get >= 3 points.
  const PolygonMesh m = triangle_grid(8, 8);
  std::vector<uint32_t> face_region(m.num_faces());
  const double mid = 0.5 * (m.bounding_box().min.x + m.bounding_box().max.x);
  for (size_t f = 0; f < m.num_faces(); ++f) {
    double x = 0.0;
    for (uint32_t k = 0; k < 3; ++k) x += m.positions[m.face_vertex(f, k)].x / 3.0;
    face_region[f] = x < mid ? 0 : 1;
  }
  for (bool balance : {true, false}) {
    cagekit::ConstraintOptions constraint_options;
    constraint_options.spacing = 2.0 * m.bounding_box().diagonal();
    constraint_options.balance_samples = balance;
    const cagekit::RemeshConstraints c = cagekit::compute_remesh_constraints(m, face_region, 2, constraint_options);
    for (uint32_t r = 0; r < 2; ++r) {
      ASSERT_EQ(c.boundaries.region_loops[r].size(), 1u);
      EXPECT_EQ(c.boundaries.region_loops[r][0].arcs.size(), 2u) << "the case needs a loop of two arcs";
      EXPECT_GE(cagekit::fewest_loop_points(c, r), 3u) << "region " << r << (balance ? " balanced" : "");
    }
  }
}

TEST(RemeshConstraints, TorusRegionsAreDisksOrAnnuliWithValidDomains) {
  // A closed genus-1 surface: with a few regions some wrap around the tube or the ring
  // (annuli: two loops, genus 0); every region gets a flip-free LSCM domain.
  const PolygonMesh m = triangle_torus(48, 24);
  for (int count : {4, 8, 16}) {
    const VsaSegmentation seg = segment(m, count);
    cagekit::ConstraintOptions constraint_options;
    constraint_options.spacing = 0.5;
    const cagekit::RemeshConstraints c =
        cagekit::compute_remesh_constraints(m, seg.face_region, seg.num_regions(), constraint_options);
    expect_consistent_boundaries(m, seg.face_region, seg.num_regions(), c.boundaries);
    size_t annuli = 0;
    for (uint32_t r = 0; r < seg.num_regions(); ++r) {
      EXPECT_EQ(c.boundaries.region_genus(r), 0);
      annuli += c.boundaries.region_loops[r].size() == 2;
      EXPECT_EQ(c.domains[r].flipped_triangles, 0u) << count << " regions, region " << r;
      const auto& loops = c.boundaries.region_loops[r];
      for (size_t l = 0; l < loops.size(); ++l) {
        const double area = cagekit::signed_domain_area(c.domains[r], c.boundaries.loop_vertices(loops[l]));
        EXPECT_EQ(area > 0.0, l == 0) << count << " regions, region " << r << " loop " << l;
      }
    }
    std::printf("torus %d regions: %zu annuli, %zu arcs, L2,1/area %.4f\n", count, annuli, c.arcs.size(),
                seg.total_error / seg.total_area);
  }
  // One region: the whole closed torus has no boundary to parameterise.
  cagekit::ConstraintOptions constraint_options;
  constraint_options.spacing = 0.5;
  EXPECT_EQ(status_of([&] {
              cagekit::compute_remesh_constraints(m, std::vector<uint32_t>(m.num_faces(), 0), 1, constraint_options);
            }),
            Status::invalid_mesh);
}

TEST(RemeshConstraints, FandiskThirtyRegions) { check_real_mesh_constraints("fandisk.obj", 30, 0.05); }
TEST(RemeshConstraints, RockerArmFortyOneRegions) { check_real_mesh_constraints("rocker-arm.obj", 41, 0.03); }

// ---------------------------------------------------------------------------------------------
// Joint sample counts (allocate_arc_segments) and re-sampling one arc

namespace {

// A g x g grid of square regions: region (i, j) has sides bottom h[i][j], right v[i][j + 1],
// top h[i + 1][j], left v[i][j] (one arc each; the outer arcs are mesh border).
struct GridProblem {
  std::vector<double> ideal;
  std::vector<cagekit::SegmentAllocationRegion> regions;
};

GridProblem grid_problem(int g) {
  GridProblem p;
  auto h = [g](int i, int j) { return uint32_t(i * g + j); };                    // (g + 1) x g
  auto v = [g](int i, int j) { return uint32_t((g + 1) * g + i * (g + 1) + j); };  // g x (g + 1)
  p.ideal.resize(size_t(2 * g * (g + 1)));
  // Rows of horizontal arcs alternate 2.9 / 3.2 (⌈⌉ 3 / 4): every region starts with top and
  // bottom unequal; vertical arcs 2.2 in every third column, else 1.5 (⌈⌉ 3 / 2), so some
  // regions start with an odd total.
  for (int i = 0; i <= g; ++i)
    for (int j = 0; j < g; ++j) p.ideal[h(i, j)] = (i % 2) ? 3.2 : 2.9;
  for (int i = 0; i < g; ++i)
    for (int j = 0; j <= g; ++j) p.ideal[v(i, j)] = (j % 3 == 0) ? 2.2 : 1.5;
  for (int i = 0; i < g; ++i)
    for (int j = 0; j < g; ++j) {
      cagekit::SegmentAllocationRegion r;
      r.sides = {{h(i, j)}, {v(i, j + 1)}, {h(i + 1, j)}, {v(i, j)}};
      r.quad_like = true;
      p.regions.push_back(r);
    }
  return p;
}

long side_total(const std::vector<uint32_t>& n, const std::vector<uint32_t>& side) {
  long t = 0;
  for (uint32_t a : side) t += long(n[a]);
  return t;
}

}  // namespace

TEST(SegmentAllocation, GridRegionsGetEvenCountsAndMatchingOppositeSides) {
  const GridProblem p = grid_problem(4);
  std::vector<uint32_t> base(p.ideal.size());
  for (size_t a = 0; a < base.size(); ++a) base[a] = uint32_t(std::ceil(p.ideal[a]));
  const std::vector<uint32_t> n = cagekit::allocate_arc_segments(p.ideal, p.regions);
  ASSERT_EQ(n.size(), p.ideal.size());
  for (size_t a = 0; a < n.size(); ++a) {
    EXPECT_GE(n[a] + 1, base[a]) << "arc " << a;  // within ±1 of ⌈ideal⌉
    EXPECT_LE(n[a], base[a] + 1) << "arc " << a;
  }
  size_t odd_before = 0;
  for (const auto& r : p.regions) {
    long total = 0, total_before = 0;
    for (const auto& side : r.sides) total += side_total(n, side), total_before += side_total(base, side);
    odd_before += total_before % 2 != 0;
    EXPECT_EQ(total % 2, 0);
    EXPECT_EQ(side_total(n, r.sides[0]), side_total(n, r.sides[2]));
    EXPECT_EQ(side_total(n, r.sides[1]), side_total(n, r.sides[3]));
  }
  EXPECT_GT(odd_before, 0u);  // the test starts from odd regions
  EXPECT_LT(cagekit::segment_allocation_cost(n, p.ideal, p.regions),
            cagekit::segment_allocation_cost(base, p.ideal, p.regions));
  EXPECT_EQ(cagekit::allocate_arc_segments(p.ideal, p.regions), n);  // deterministic
}

TEST(SegmentAllocation, RandomProblemsStayInBoundsAndNeverCostMoreThanCeil) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    const size_t arcs = 3 + rng() % 30;
    std::vector<double> ideal(arcs);
    for (double& x : ideal) x = double(rng() % 600) / 100.0;  // [0, 6), small and integer ones included
    std::vector<int> uses(arcs, 0);
    std::vector<cagekit::SegmentAllocationRegion> regions(1 + rng() % 8);
    for (auto& r : regions) {
      const size_t sides = 1 + rng() % 6;
      r.sides.resize(sides);
      for (auto& side : r.sides) {
        const uint32_t a = uint32_t(rng() % arcs);
        if (uses[a] < 2) ++uses[a], side.push_back(a);
      }
      r.quad_like = sides == 4;
    }
    cagekit::SegmentAllocationOptions o;
    o.anneal_steps = 2000;
    const std::vector<uint32_t> n = cagekit::allocate_arc_segments(ideal, regions, o);
    std::vector<uint32_t> base(arcs);
    for (size_t a = 0; a < arcs; ++a) {
      base[a] = std::max(1u, uint32_t(std::ceil(ideal[a] - 1e-9)));
      EXPECT_GE(n[a], 1u);
      EXPECT_GE(n[a] + 1, base[a]);
      EXPECT_LE(n[a], base[a] + 1);
    }
    EXPECT_LE(cagekit::segment_allocation_cost(n, ideal, regions, o),
              cagekit::segment_allocation_cost(base, ideal, regions, o) + 1e-12);
  }
  EXPECT_THROW(cagekit::allocate_arc_segments({1.0}, {cagekit::SegmentAllocationRegion{{{3}}, false}}), cagekit::Error);
  EXPECT_THROW(cagekit::allocate_arc_segments({-1.0}, {}), cagekit::Error);
  EXPECT_THROW(cagekit::segment_allocation_cost({1, 1}, {1.0}, {}), cagekit::Error);
}

TEST(RemeshConstraints, ResampleArcChangesBothNeighboursSamples) {
  const PolygonMesh m = box(4, 0.25);
  const VsaSegmentation seg = segment(m, 6);
  cagekit::ConstraintOptions constraint_options;
  constraint_options.spacing = 0.25;
  cagekit::RemeshConstraints c = cagekit::compute_remesh_constraints(m, seg.face_region, 6, constraint_options);
  ASSERT_EQ(c.arcs.size(), 12u);
  const cagekit::RegionArc& arc = c.boundaries.arcs[0];
  ASSERT_NE(arc.right_region, cagekit::kMeshBorder);
  const size_t left_before = c.loop_samples(arc.left_region, 0).size();
  const size_t right_before = c.loop_samples(arc.right_region, 0).size();
  const size_t segments = c.arcs[0].samples.t.size() - 1;
  EXPECT_EQ(c.arcs[0].base_segments, 4u);  // a unit edge at δ = 0.25
  cagekit::resample_arc(c, 0, uint32_t(segments + 1));
  EXPECT_EQ(c.arcs[0].samples.position.size(), segments + 2);
  EXPECT_EQ(c.loop_samples(arc.left_region, 0).size(), left_before + 1);
  EXPECT_EQ(c.loop_samples(arc.right_region, 0).size(), right_before + 1);
  EXPECT_EQ(c.loop_samples_uv(arc.left_region, 0).size(), left_before + 1);
  EXPECT_EQ(c.loop_samples_uv(arc.right_region, 0).size(), right_before + 1);
  // Equidistant on the straight edge: the middle sample of 5 segments at 0.4 / 0.6 of it.
  const Vec3 a = c.arcs[0].samples.position.front(), b = c.arcs[0].samples.position.back();
  EXPECT_NEAR(distance(c.arcs[0].samples.position[2], a), 0.4, 1e-9);
  EXPECT_NEAR(distance(c.arcs[0].samples.position[3], b), 0.4, 1e-9);
  EXPECT_THROW(cagekit::resample_arc(c, 0, 0), cagekit::Error);
  EXPECT_THROW(cagekit::resample_arc(c, 12, 2), cagekit::Error);
}
