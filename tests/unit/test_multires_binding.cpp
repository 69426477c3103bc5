// SPDX-License-Identifier: GPL-3.0-or-later
// Multiresolution layer (thesis ch. 8): binding a scan to a cage's limit surface (§8.3) and the
// CPU deformer (§8.5): reproduction of the undeformed scan, approximate vs exact normals,
// incremental vs full recompute.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "core/vertex_renumbering.h"
#include "fit/surface_fitter.h"
#include "multires/cpu_deformer.h"
#include "multires/deformer_vertex_order.h"
#include "multires/scan_binding.h"
#include "multires/sparse_row_deformer.h"
#include "subdiv/uniform_refinement.h"
#include "test_support.h"

using namespace cagekit;

namespace {

constexpr double kDegree = 3.141592653589793 / 180.0;

// A bumpy sphere scan (radial noise) and a cube cage fitted to it.
struct BoundSphere {
  PolygonMesh scan;
  Cage cage;
};

const BoundSphere& sphere_setup() {
  static const BoundSphere setup = [] {
    BoundSphere s;
    s.scan = cagekit_test::triangle_sphere(5);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> bump(-0.01, 0.01);
    for (Vec3& p : s.scan.positions) p = p * (1.0 + bump(rng) + 0.05 * p.x * p.y);
    Cage cube;
    cube.mesh = cagekit_test::unit_cube_quads();
    for (Vec3& p : cube.mesh.positions) p = (p - Vec3{0.5, 0.5, 0.5}) * 1.2;
    // The cube refined twice (98 vertices: regular and valence-3 extraordinary ones), fitted.
    RefineOptions twice;
    twice.levels = 2;
    FitOptions options;
    options.max_passes = 3;
    s.cage = fit_cage_to_mesh(refine_uniform(cube, twice), s.scan, options);
    return s;
  }();
  return setup;
}

double angle_between(const Vec3& a, const Vec3& b) {
  return std::atan2(norm(cross(a, b)), dot(a, b));
}

}  // namespace

TEST(MultiresBinding, undeformed_cage_reproduces_the_scan) {
  const BoundSphere& s = sphere_setup();
  for (DisplacementMode mode : {DisplacementMode::normal, DisplacementMode::local_frame}) {
    BindOptions options;
    options.mode = mode;
    const ScanBinding binding = bind_scan_to_cage(s.cage, s.scan, options);
    ASSERT_EQ(binding.num_vertices(), s.scan.num_vertices());
    const std::vector<Vec3> scan_normals = vertex_normals(s.scan);
    // The double sparse-row reference reproduces to rounding; the compact float32 deformer to
    // float rounding relative to each cell's size (issue #5's bar: 1e-5 of the diagonal).
    for (bool compact : {false, true}) {
      std::vector<Vec3> positions(binding.num_vertices()), normals(binding.num_vertices());
      if (compact) {
        CpuDeformer deformer(binding);
        ASSERT_TRUE(deformer.compact());
        deformer.deform(s.cage.mesh.positions, positions.data(), normals.data());
      } else {
        SparseRowDeformer(binding).deform(s.cage.mesh.positions, positions.data(), normals.data());
      }
      double worst = 0, worst_normal = 0;
      for (size_t i = 0; i < positions.size(); ++i) {
        worst = std::max(worst, distance(positions[i], s.scan.positions[i]) / binding.bbox_diagonal);
        worst_normal = std::max(worst_normal, angle_between(normals[i], scan_normals[i]));
      }
      std::printf("%s mode, %s: %zu vertices, %zu basis entries (%.1f per vertex), worst reproduction %.3g of the "
                  "diagonal, normals %.3g deg off the scan's, max sideways residual %.3g\n",
                  mode == DisplacementMode::normal ? "normal" : "local-frame", compact ? "compact" : "sparse rows",
                  binding.num_vertices(), binding.num_entries(), double(binding.num_entries()) / binding.num_vertices(),
                  worst, worst_normal / kDegree, binding.max_sideways_residual);
      EXPECT_LT(worst, mode == DisplacementMode::normal ? 1e-5 : compact ? 1e-6 : 1e-12);
      // Undeformed, the approximate normals are the scan's normals by construction (8.11)-(8.12).
      EXPECT_LT(worst_normal, compact ? 2e-6 : 1e-7);
    }
  }
}

// An open scan: the limit surface of an open cage stops short of the scan's border, so border
// vertices have foot points on the surface's border and a sideways offset; normal mode reports
// it, local-frame mode keeps it.
TEST(MultiresBinding, sideways_residual_is_reported_and_kept_in_local_frame_mode) {
  const cagekit_test::OpenGrid open = cagekit_test::open_grid_scan_and_cage();
  const PolygonMesh& scan = open.scan;
  const Cage& cage = open.cage;
  BindOptions normal_mode, frame_mode;
  frame_mode.mode = DisplacementMode::local_frame;
  const ScanBinding a = bind_scan_to_cage(cage, scan, normal_mode), b = bind_scan_to_cage(cage, scan, frame_mode);
  std::printf("open grid: normal mode loses up to %.3g of the diagonal sideways at %zu vertices\n",
              a.max_sideways_residual, a.vertices_with_sideways_residual);
  EXPECT_GT(a.max_sideways_residual, 1e-3);
  EXPECT_GT(a.vertices_with_sideways_residual, 0u);
  for (bool compact : {false, true}) {
    std::vector<Vec3> pa(scan.num_vertices()), pb(scan.num_vertices());
    if (compact) {
      CpuDeformer(a).deform(cage.mesh.positions, pa.data(), nullptr);
      CpuDeformer(b).deform(cage.mesh.positions, pb.data(), nullptr);
    } else {
      SparseRowDeformer(a).deform(cage.mesh.positions, pa.data(), nullptr);
      SparseRowDeformer(b).deform(cage.mesh.positions, pb.data(), nullptr);
    }
    double worst_a = 0, worst_b = 0;
    for (size_t i = 0; i < pa.size(); ++i) {
      worst_a = std::max(worst_a, distance(pa[i], scan.positions[i]) / a.bbox_diagonal);
      worst_b = std::max(worst_b, distance(pb[i], scan.positions[i]) / b.bbox_diagonal);
    }
    std::printf("open grid, %s: local frame reproduces to %.3g of the diagonal (%zu irregular vertices)\n",
                compact ? "compact" : "sparse rows", worst_b, b.compact.num_irregular_vertices());
    EXPECT_NEAR(worst_a, a.max_sideways_residual, compact ? 1e-6 : 1e-9);
    EXPECT_LT(worst_b, compact ? 1e-6 : 1e-12);
  }
}

// Issue #5 test: approximate vs exact normals after pulling 4 control vertices by 10% of the
// bbox diagonal: mean <= 2 degrees, max <= 30 degrees over the moved vertices (thesis Fig. 8.5:
// mean 1, max 23).
TEST(MultiresBinding, approximate_normals_stay_close_to_exact_normals) {
  const BoundSphere& s = sphere_setup();
  BindOptions options;
  options.exact_normals = true;
  const ScanBinding binding = bind_scan_to_cage(s.cage, s.scan, options);
  CpuDeformer deformer(binding);
  std::vector<Vec3> control = s.cage.mesh.positions;
  for (uint32_t j : {0u, 1u, 2u, 3u}) control[j] += normalized(control[j]) * (0.1 * binding.bbox_diagonal);
  const size_t n = binding.num_vertices();
  std::vector<Vec3> p0(n), approx(n), exact(n);
  deformer.deform(s.cage.mesh.positions, p0.data(), nullptr);
  deformer.deform(control, nullptr, approx.data(), NormalMode::approximate);
  std::vector<Vec3> p1(n);
  deformer.deform(control, p1.data(), exact.data(), NormalMode::exact);
  double sum = 0, worst = 0;
  size_t moved = 0;
  for (size_t i = 0; i < n; ++i) {
    if (distance(p0[i], p1[i]) < 1e-9 * binding.bbox_diagonal) continue;
    const double a = angle_between(approx[i], exact[i]) / kDegree;
    sum += a;
    worst = std::max(worst, a);
    ++moved;
  }
  std::printf("approximate vs exact normals over %zu moved vertices: mean %.3f deg, max %.3f deg\n", moved,
              sum / moved, worst);
  ASSERT_GT(moved, n / 4);
  EXPECT_LE(sum / moved, 2.0);
  EXPECT_LE(worst, 30.0);
  // Undeformed, exact normals also match the scan's normals.
  std::vector<Vec3> n0(n);
  deformer.deform(s.cage.mesh.positions, nullptr, n0.data(), NormalMode::exact);
  const std::vector<Vec3> scan_normals = vertex_normals(s.scan);
  double worst0 = 0;
  for (size_t i = 0; i < n; ++i) worst0 = std::max(worst0, angle_between(n0[i], scan_normals[i]) / kDegree);
  EXPECT_LT(worst0, 1e-6);
}

TEST(MultiresBinding, incremental_update_equals_full_recompute) {
  const BoundSphere& s = sphere_setup();
  const ScanBinding binding = bind_scan_to_cage(s.cage, s.scan);
  const size_t n = binding.num_vertices();
  CpuDeformer incremental(binding, 1), full(binding, 3);
  std::vector<Vec3> pi(n), ni(n), pf(n), nf(n);
  std::vector<Vec3> control = s.cage.mesh.positions;
  incremental.deform(control, pi.data(), ni.data());
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> step(-0.05, 0.05);
  size_t recomputed = 0;
  for (int frame = 0; frame < 5; ++frame) {
    const std::vector<uint32_t> moved = {uint32_t(frame * 7 % 98), uint32_t((frame * 13 + 1) % 98)};
    for (uint32_t j : moved) control[j] += Vec3{step(rng), step(rng), step(rng)};
    recomputed += incremental.update(control, moved, pi.data(), ni.data());
  }
  full.deform(control, pf.data(), nf.data());
  double dp = 0, dn = 0;
  for (size_t i = 0; i < n; ++i) {
    dp = std::max(dp, distance(pi[i], pf[i]));
    dn = std::max(dn, angle_between(ni[i], nf[i]));
  }
  std::printf("incremental vs full after 5 frames: %zu vertices recomputed, max position difference %.3g, "
              "normal %.3g rad\n", recomputed, dp, dn);
  EXPECT_LT(dp, 1e-12 * binding.bbox_diagonal);
  EXPECT_LT(dn, 1e-10);
  EXPECT_GT(recomputed, 0u);
}

TEST(MultiresBinding, bad_input_is_rejected) {
  const BoundSphere& s = sphere_setup();
  PolygonMesh bad = s.scan;
  bad.positions[3].x = std::nan("");
  EXPECT_THROW(bind_scan_to_cage(s.cage, bad), Error);
  EXPECT_THROW(bind_scan_to_cage(s.cage, PolygonMesh()), Error);
  const ScanBinding binding = bind_scan_to_cage(s.cage, s.scan);
  CpuDeformer deformer(binding);
  std::vector<Vec3> out(binding.num_vertices());
  EXPECT_THROW(deformer.deform(std::vector<Vec3>(3), out.data(), nullptr), Error);
  EXPECT_THROW(deformer.deform(s.cage.mesh.positions, nullptr, out.data(), NormalMode::exact), Error);
  EXPECT_THROW(deformer.update(s.cage.mesh.positions, {0}, out.data(), nullptr), Error);  // before deform()
  deformer.deform(s.cage.mesh.positions, out.data(), nullptr);
  EXPECT_THROW(deformer.update(s.cage.mesh.positions, {999}, out.data(), nullptr), Error);
}


// The compact per-cell table (patch_deformer_table.h) against the double sparse rows it
// replaces, after a deformation: every cell's polynomial was verified at its vertices, so the
// two differ by float32 rounding only; most vertices are in cells.
TEST(MultiresBinding, compact_table_matches_the_sparse_rows) {
  const BoundSphere& s = sphere_setup();
  for (DisplacementMode mode : {DisplacementMode::normal, DisplacementMode::local_frame}) {
    BindOptions options;
    options.mode = mode;
    const ScanBinding binding = bind_scan_to_cage(s.cage, s.scan, options);
    const PatchDeformerTable& table = binding.compact;
    const size_t n = binding.num_vertices();
    ASSERT_EQ(table.num_cell_vertices() + table.num_irregular_vertices(), n);
    std::vector<char> seen(n, 0);
    for (uint32_t i : table.vertex) seen[i] += 1;
    for (uint32_t i : table.irregular_vertex) seen[i] += 1;
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), std::ptrdiff_t(n));
    EXPECT_GT(table.num_irregular_vertices(), 0u);  // the valence-3 corners: the row path is tested too
    EXPECT_LT(table.num_irregular_vertices(), n / 10);
    std::vector<Vec3> control = s.cage.mesh.positions;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> step(-0.05, 0.05);
    for (Vec3& c : control) c += Vec3{step(rng), step(rng), step(rng)} * binding.bbox_diagonal;
    std::vector<Vec3> pc(n), nc(n), pr(n), nr(n);
    CpuDeformer fast(binding, 2);
    fast.deform(control, pc.data(), nc.data());
    SparseRowDeformer(binding, 2).deform(control, pr.data(), nr.data());
    double dp = 0, dn = 0;
    for (size_t i = 0; i < n; ++i) {
      dp = std::max(dp, distance(pc[i], pr[i]) / binding.bbox_diagonal);
      dn = std::max(dn, angle_between(nc[i], nr[i]));
    }
    std::printf("%s mode: %zu cells, %zu irregular vertices, %.1f bytes per vertex; compact vs sparse rows: "
                "positions %.3g of the diagonal, normals %.3g rad\n",
                mode == DisplacementMode::normal ? "normal" : "local-frame", table.num_cells(),
                table.num_irregular_vertices(), fast.bytes_per_vertex(), dp, dn);
    EXPECT_LT(dp, 2e-6);
    EXPECT_LT(dn, 1e-4);
    // Exact normals and bindings without the table go through the sparse rows.
    options.compact_table = false;
    const ScanBinding plain = bind_scan_to_cage(s.cage, s.scan, options);
    EXPECT_TRUE(plain.compact.empty());
    CpuDeformer slow(plain);
    EXPECT_FALSE(slow.compact());
    // Per-cell coefficients dominate on this small scan (28 vertices per cell); still < 1/2.
    EXPECT_LT(fast.bytes_per_vertex(), 0.5 * slow.bytes_per_vertex());
    std::vector<Vec3> ps(n);
    slow.deform(control, ps.data(), nullptr);
    for (size_t i = 0; i < n; ++i) ASSERT_EQ(ps[i], pr[i]);
  }
}

// Incremental updates after exact-normal frames and back: the deformer keeps both paths on the
// same control points.
TEST(MultiresBinding, incremental_update_across_normal_modes) {
  const BoundSphere& s = sphere_setup();
  BindOptions options;
  options.exact_normals = true;
  const ScanBinding binding = bind_scan_to_cage(s.cage, s.scan, options);
  const size_t n = binding.num_vertices();
  CpuDeformer deformer(binding), full(binding);
  std::vector<Vec3> control = s.cage.mesh.positions, p(n), nn(n), pf(n), nf(n);
  deformer.deform(control, p.data(), nn.data(), NormalMode::exact);
  control[5] += Vec3{0.01, 0.02, -0.01};
  deformer.update(control, {5}, p.data(), nn.data(), NormalMode::approximate);
  control[40] += Vec3{-0.02, 0.01, 0.01};
  deformer.update(control, {40}, p.data(), nn.data(), NormalMode::exact);
  full.deform(control, pf.data(), nf.data(), NormalMode::exact);
  // Vertices recomputed by the exact update match a full exact frame; all positions agree to
  // float rounding (the approximate update wrote the compact path's).
  for (uint32_t i : deformer.last_updated()) {
    ASSERT_LT(distance(p[i], pf[i]), 1e-12 * binding.bbox_diagonal);
    ASSERT_LT(angle_between(nn[i], nf[i]), 1e-10);
  }
  for (size_t i = 0; i < n; ++i) ASSERT_LT(distance(p[i], pf[i]), 2e-6 * binding.bbox_diagonal);
}

// Flat outputs (CpuDeformer::deform / update into double or float32 xyz triples): the double
// triples equal the Vec3 overload's values, the float32 ones are those values rounded; full
// frames do not depend on the thread count (each worker stages its cells, then writes its
// vertex range); incremental updates into float32 arrays match a full float32 frame.
TEST(MultiresBinding, flat_and_float32_outputs_match_the_vec3_outputs) {
  const BoundSphere& s = sphere_setup();
  for (DisplacementMode mode : {DisplacementMode::normal, DisplacementMode::local_frame}) {
    BindOptions options;
    options.mode = mode;
    options.exact_normals = mode == DisplacementMode::normal;
    const ScanBinding binding = bind_scan_to_cage(s.cage, s.scan, options);
    const size_t n = binding.num_vertices();
    ASSERT_GT(binding.compact.num_irregular_vertices(), 0u);
    std::vector<Vec3> control = s.cage.mesh.positions;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> step(-0.03, 0.03);
    for (Vec3& c : control) c += Vec3{step(rng), step(rng), step(rng)};
    std::vector<NormalMode> normal_modes = {NormalMode::approximate};
    if (options.exact_normals) normal_modes.push_back(NormalMode::exact);
    for (NormalMode normal_mode : normal_modes) {
      std::vector<Vec3> p(n), nn(n);
      CpuDeformer reference(binding, 1);
      reference.deform(control, p.data(), nn.data(), normal_mode);
      for (int threads : {1, 2, 3}) {
        CpuDeformer deformer(binding, threads);
        std::vector<Vec3> p3(n), n3(n);
        deformer.deform(control, p3.data(), n3.data(), normal_mode);
        std::vector<double> pd(3 * n), nd(3 * n);
        deformer.deform(control, pd.data(), nd.data(), normal_mode);
        std::vector<float> pf(3 * n), nf(3 * n);
        deformer.deform(control, pf.data(), nf.data(), normal_mode);
        size_t mismatches = 0;
        for (size_t i = 0; i < n; ++i)
          for (int a = 0; a < 3; ++a) {
            mismatches += p3[i][a] != p[i][a] || n3[i][a] != nn[i][a];
            mismatches += pd[3 * i + a] != p[i][a] || nd[3 * i + a] != nn[i][a];
            mismatches += pf[3 * i + a] != float(p[i][a]) || nf[3 * i + a] != float(nn[i][a]);
          }
        EXPECT_EQ(mismatches, 0u) << "threads " << threads;
      }
      // Incremental float32 updates against a full float32 frame at the end.
      CpuDeformer incremental(binding, 2), full(binding, 2);
      std::vector<Vec3> moving = control;
      std::vector<float> pi(3 * n), ni(3 * n), pf(3 * n), nf(3 * n);
      incremental.deform(moving, pi.data(), ni.data(), normal_mode);
      size_t recomputed = 0;
      for (int frame = 0; frame < 3; ++frame) {
        const std::vector<uint32_t> moved = {uint32_t(frame * 11 % 98), uint32_t((frame * 17 + 3) % 98)};
        for (uint32_t j : moved) moving[j] += Vec3{step(rng), step(rng), step(rng)};
        recomputed += incremental.update(moving, moved, pi.data(), ni.data(), normal_mode);
      }
      full.deform(moving, pf.data(), nf.data(), normal_mode);
      EXPECT_GT(recomputed, 0u);
      EXPECT_EQ(pi, pf);
      EXPECT_EQ(ni, nf);
      // Positions only / normals only.
      std::vector<float> only(3 * n);
      full.deform(moving, only.data(), static_cast<float*>(nullptr), normal_mode);
      EXPECT_EQ(only, pf);
      full.deform(moving, static_cast<float*>(nullptr), only.data(), normal_mode);
      EXPECT_EQ(only, nf);
    }
  }
}

TEST(MultiresBinding, scan_renumbered_in_the_deformer_order_deforms_the_same_with_sequential_writes) {
  const BoundSphere& s = sphere_setup();
  const ScanBinding binding = bind_scan_to_cage(s.cage, s.scan);
  const std::vector<uint32_t> order = deformer_vertex_order(binding);
  const size_t n = s.scan.num_vertices();
  ASSERT_EQ(order.size(), n);
  std::vector<uint32_t> new_id(n, 0xffffffffu);
  for (uint32_t k = 0; k < n; ++k) {
    ASSERT_LT(order[k], n);
    ASSERT_EQ(new_id[order[k]], 0xffffffffu) << "vertex " << order[k] << " twice";
    new_id[order[k]] = k;
  }
  // The order starts with the first cell's vertices, as the deformer writes them.
  const PatchDeformerTable& t = binding.compact;
  ASSERT_FALSE(t.empty());
  EXPECT_EQ(order[0], t.vertex[0]);
  // Renumber the scan, bind again.
  const PolygonMesh renumbered = renumber_vertices(s.scan, order);
  for (size_t e = 0; e < renumbered.face_vertices.size(); ++e)
    ASSERT_EQ(renumbered.face_vertices[e], new_id[s.scan.face_vertices[e]]);
  const ScanBinding again = bind_scan_to_cage(s.cage, renumbered);
  // The deformer now writes (nearly) sequentially: consecutive cell vertices are consecutive ids.
  const PatchDeformerTable& u = again.compact;
  size_t sequential = 0;
  for (size_t k = 1; k < u.vertex.size(); ++k) sequential += u.vertex[k] == u.vertex[k - 1] + 1;
  size_t before = 0;
  for (size_t k = 1; k < t.vertex.size(); ++k) before += t.vertex[k] == t.vertex[k - 1] + 1;
  std::printf("consecutive cell vertices with consecutive ids: %zu of %zu before, %zu after\n", before,
              t.vertex.size(), sequential);
  EXPECT_GT(sequential, (u.vertex.size() * 9) / 10);
  EXPECT_GT(sequential, before);
  // The same shape after moving control points: vertex order[k] of the scan is vertex k now.
  std::vector<Vec3> control = s.cage.mesh.positions;
  for (size_t j = 0; j < control.size(); j += 5) control[j] += Vec3{0.03, -0.02, 0.04};
  std::vector<Vec3> p0(n), n0(n), p1(n), n1(n);
  CpuDeformer(binding, 2).deform(control, p0.data(), n0.data());
  CpuDeformer(again, 2).deform(control, p1.data(), n1.data());
  double dp = 0, dn = 0;
  for (uint32_t k = 0; k < n; ++k) {
    dp = std::max(dp, distance(p1[k], p0[order[k]]));
    dn = std::max(dn, angle_between(n1[k], n0[order[k]]));
  }
  EXPECT_LT(dp, 1e-9 * binding.bbox_diagonal);
  EXPECT_LT(dn, 1e-7);
  // Cells of consecutive vertices are staged and written with streaming stores: every vertex is
  // written (NaN-filled arrays before), the flat double / float32 outputs equal the Vec3 ones,
  // and incremental updates equal full frames, on 1 and 2 threads.
  size_t contiguous_cells = 0;
  for (size_t c = 0; c < u.num_cells(); ++c) {
    bool consecutive = true;
    for (uint32_t k = u.cell_vertex_offsets[c] + 1; k < u.cell_vertex_offsets[c + 1]; ++k)
      consecutive = consecutive && u.vertex[k] == u.vertex[k - 1] + 1;
    contiguous_cells += consecutive;
  }
  EXPECT_GT(contiguous_cells, (u.num_cells() * 9) / 10);
  const double nan = std::nan("");
  for (int threads : {1, 2}) {
    CpuDeformer d(again, threads);
    std::vector<Vec3> pv(n, Vec3{nan, nan, nan}), nv(n, Vec3{nan, nan, nan});
    std::vector<double> pd(3 * n, nan), nd(3 * n, nan);
    std::vector<float> pf(3 * n, std::nanf("")), nf(3 * n, std::nanf(""));
    d.deform(control, pv.data(), nv.data());
    d.deform(control, pd.data(), nd.data());
    d.deform(control, pf.data(), nf.data());
    for (size_t k = 0; k < n; ++k) {
      ASSERT_TRUE(std::isfinite(pv[k].x) && std::isfinite(nv[k].z)) << "vertex " << k << " not written";
      for (int a = 0; a < 3; ++a) {
        ASSERT_EQ(pd[3 * k + size_t(a)], (&pv[k].x)[a]) << "vertex " << k;
        ASSERT_EQ(nd[3 * k + size_t(a)], (&nv[k].x)[a]) << "vertex " << k;
        ASSERT_EQ(pf[3 * k + size_t(a)], float((&pv[k].x)[a])) << "vertex " << k;
        ASSERT_EQ(nf[3 * k + size_t(a)], float((&nv[k].x)[a])) << "vertex " << k;
      }
    }
    // Incremental: two control points moved; the full frame of the same control points agrees.
    std::vector<Vec3> moved = control;
    moved[1] += Vec3{-0.05, 0.02, 0.01}, moved[7] += Vec3{0.02, 0.04, -0.03};
    const size_t updated = d.update(moved, {1, 7}, pf.data(), nf.data());
    EXPECT_GT(updated, 0u);
    EXPECT_LT(updated, n);
    std::vector<float> qf(3 * n), mf(3 * n);
    CpuDeformer(again, threads).deform(moved, qf.data(), mf.data());
    EXPECT_EQ(pf, qf);
    EXPECT_EQ(nf, mf);
  }
}
