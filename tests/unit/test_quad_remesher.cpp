// SPDX-License-Identifier: GPL-3.0-or-later
// The two-step quad-dominant remesher end to end (issue #7 deliverables 5 and 7): the glued cage
// is a valid oriented 2-manifold with the input's genus, no face is flipped against the input
// surface, every region boundary is a chain of cage edges, the selection is never worse than its
// Phase I, fandisk's sharp feature lines lie on crease-tagged cage edges; bad options and input
// are errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

#include "core/mesh_statistics.h"
#include "core/mesh_validation.h"
#include "core/mesh_validation.h"
#include "layout/common/feature_edges.h"
#include "layout/quad/quad_remesher.h"
#include "layout/quad/remesh_constraints.h"
#include "layout/quad/vsa_segmentation.h"
#include "test_support.h"
#include "../sanitizer/sanitized_build.h"

using cagekit::Error;
using cagekit::PolygonMesh;
using cagekit::QuadRemeshOptions;
using cagekit::QuadRemeshResult;
using cagekit::Status;
using cagekit::Vec3;

namespace {

using PositionKey = std::array<double, 3>;
PositionKey key_of(const Vec3& p) { return {p.x, p.y, p.z}; }
uint64_t undirected(uint32_t a, uint32_t b) { return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a; }

// Distance from p to segment [a, b].
double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double len2 = cagekit::dot(d, d);
  const double t = len2 > 0.0 ? std::clamp(cagekit::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
  return cagekit::distance(p, a + t * d);
}

struct Checked {
  QuadRemeshResult result;
  double seconds = 0.0;
};

// Runs the remesher and checks what holds for every input: validity, genus, orientation against
// the input, region boundaries reproduced (by recomputing the deterministic segmentation and
// constraints), energy not above Phase I.
Checked run_and_check(const PolygonMesh& mesh, const QuadRemeshOptions& options, const char* name) {
  Checked out;
  const auto start = std::chrono::steady_clock::now();
  out.result = cagekit::remesh_quad_dominant(mesh, options);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const QuadRemeshResult& r = out.result;
  const PolygonMesh& cage = r.cage.mesh;

  const cagekit::ValidationReport check = cagekit::validate_cage(r.cage);
  EXPECT_TRUE(check.ok()) << name << ": " << check.summary();
  EXPECT_EQ(check.count(cagekit::MeshIssue::unreferenced_vertex), 0u) << name;
  const cagekit::MeshStatistics in = cagekit::compute_mesh_statistics(mesh);
  const cagekit::MeshStatistics outs = cagekit::compute_mesh_statistics(cage);
  EXPECT_TRUE(outs.manifold) << name;
  EXPECT_EQ(outs.genus, in.genus) << name;
  EXPECT_EQ(outs.boundary_loops, in.boundary_loops) << name;
  EXPECT_EQ(outs.components, in.components) << name;
  EXPECT_EQ(r.flipped_faces, 0u) << name;
  EXPECT_GT(r.faces, 0u) << name;
  EXPECT_EQ(r.faces, cage.num_faces()) << name;
  // The selection keeps the best configuration seen, Phase I's included.
  EXPECT_LE(r.energy, r.phase1_energy + 1e-9 * (1.0 + r.phase1_energy)) << name;

  // Every region boundary (every arc's chain of samples) is a chain of cage edges.
  // The segmentation is deterministic: without host pins or seeds it is recomputed here and
  // must equal the one the result reports.
  // (Only when no region was split or merged for disk regions or a failed layout: then the
  // regions are VSA's at the count used, the request raised to the component count.)
  if (options.pinned_regions.empty() && options.seed_faces.empty() && r.split_regions == 0 && r.merged_regions == 0) {
    cagekit::VsaOptions vo;
    vo.region_count = int(r.regions);
    const cagekit::VsaSegmentation seg = cagekit::segment_vsa(mesh, vo);
    EXPECT_EQ(r.regions, seg.num_regions()) << name;
    EXPECT_EQ(r.face_region, seg.face_region) << name;
  }
  cagekit::ConstraintOptions co;
  co.spacing = cagekit::spacing_from_bbox_fraction(mesh, options.edge_length);
  cagekit::RemeshConstraints c = cagekit::compute_remesh_constraints(mesh, r.face_region, uint32_t(r.regions), co);
  EXPECT_EQ(r.arcs, c.arcs.size()) << name;
  // The refinement changed some sample counts, by at most one from ⌈len/δ⌉ each; with them the
  // constraints give the cage's samples.
  EXPECT_EQ(r.arc_segments.size(), c.arcs.size()) << name;
  size_t refined = 0;
  for (uint32_t a = 0; a < c.arcs.size() && a < r.arc_segments.size(); ++a) {
    EXPECT_LE(r.arc_segments[a], c.arcs[a].base_segments + 1) << name << " arc " << a;
    EXPECT_GE(r.arc_segments[a] + 1, c.arcs[a].base_segments) << name << " arc " << a;
    EXPECT_GE(r.arc_segments[a], 1u) << name << " arc " << a;
    if (r.arc_segments[a] + 1 != c.arcs[a].samples.t.size()) {
      ++refined;
      cagekit::resample_arc(c, a, r.arc_segments[a]);
    }
  }
  std::printf("%s: %zu arcs re-sampled by the refinement\n", name, refined);
  std::map<PositionKey, uint32_t> vertex_at;
  for (uint32_t v = 0; v < cage.num_vertices(); ++v) vertex_at.emplace(key_of(cage.positions[v]), v);
  std::set<uint64_t> edges;
  for (size_t f = 0; f < cage.num_faces(); ++f)
    for (uint32_t k = 0, n = cage.face_size(f); k < n; ++k)
      edges.insert(undirected(cage.face_vertex(f, k), cage.face_vertex(f, (k + 1) % n)));
  size_t missing_samples = 0, missing_edges = 0;
  for (const cagekit::ArcConstraint& arc : c.arcs) {
    const std::vector<Vec3>& p = arc.samples.position;
    for (size_t k = 0; k + 1 < p.size(); ++k) {
      const auto a = vertex_at.find(key_of(p[k])), b = vertex_at.find(key_of(p[k + 1]));
      if (a == vertex_at.end() || b == vertex_at.end()) {
        ++missing_samples;
        continue;
      }
      missing_edges += !edges.count(undirected(a->second, b->second));
    }
  }
  EXPECT_EQ(missing_samples, 0u) << name;
  EXPECT_EQ(missing_edges, 0u) << name;

  const cagekit::RemeshQuality& q = r;
  std::printf("%s |S| = %d, δ = %.0f%%, w = %g/%g/%g: %llu faces (%.1f%% quads), %llu vertices (%.1f%% of %llu interior "
              "valence 4), max valence F/V %u/%u, %llu creases on %llu arcs, min scaled Jacobian %.3f, %llu inner "
              "vertices outside Ω; E %.1f (Phase I %.1f); %.2f s (VSA %.2f, constraints %.2f, selection %.2f, post %.3f)\n",
              name, options.regions, 100.0 * options.edge_length, options.triangle_weight, options.pentagon_weight,
              options.t_joint_weight, (unsigned long long)q.faces, 100.0 * double(q.quads) / double(q.faces),
              (unsigned long long)q.vertices,
              q.interior_vertices ? 100.0 * double(q.valence4_vertices) / double(q.interior_vertices) : 0.0,
              (unsigned long long)q.interior_vertices, q.max_face_valence, q.max_vertex_valence,
              (unsigned long long)r.creases, (unsigned long long)r.crease_arcs, q.min_scaled_jacobian,
              (unsigned long long)r.outside_domain_vertices, r.energy, r.phase1_energy, out.seconds,
              r.segmentation_seconds, r.constraint_seconds, r.selection_seconds, r.postprocess_seconds);
  return out;
}

QuadRemeshOptions table_six_one(int regions, double delta, double w_tri, double w_pent, double w_t) {
  QuadRemeshOptions o;
  o.regions = regions;
  o.edge_length = delta;
  o.triangle_weight = w_tri;
  o.pentagon_weight = w_pent;
  o.t_joint_weight = w_t;
  return o;
}

}  // namespace

// Sharp input edges (dihedral above `angle`) farther than `tolerance` from every crease edge.
size_t sharp_edges_off_creases(const PolygonMesh& mesh, const cagekit::Cage& cage, double angle, double tolerance,
                               size_t* sharp_edges) {
  const std::vector<uint8_t> sharp = cagekit::detect_feature_edges(mesh, angle);
  size_t off = 0;
  *sharp_edges = 0;
  for (size_t f = 0; f < mesh.num_faces(); ++f)
    for (uint32_t k = 0; k < 3; ++k) {
      const uint32_t a = mesh.face_vertex(f, k), b = mesh.face_vertex(f, (k + 1) % 3);
      if (!sharp[3 * f + k] || a > b) continue;
      ++*sharp_edges;
      const Vec3 mid = 0.5 * (mesh.positions[a] + mesh.positions[b]);
      double d = HUGE_VAL;
      for (const cagekit::EdgeCrease& e : cage.creases)
        d = std::min(d, segment_distance(mid, cage.mesh.positions[e.v0], cage.mesh.positions[e.v1]));
      off += d > tolerance;
    }
  return off;
}

TEST(QuadRemesher, FandiskTableSixOneValidCageWithCreasesOnFeatures) {
  const std::string path = cagekit_test::shared_mesh_path("fandisk.obj");
  if (path.empty()) GTEST_SKIP() << "../shared/meshes/fandisk.obj not present";
  const PolygonMesh mesh = cagekit_test::load_mesh(path);
  const QuadRemeshOptions options = table_six_one(30, 0.10, 500, 500, 500);
  const Checked run = run_and_check(mesh, options, "fandisk");
  const QuadRemeshResult& r = run.result;
  EXPECT_GT(r.creases, 0u);
  // Table 6.1's regularity (94 % quads, 76 % valence-4 vertices), with the face count within ±30 %
  // of its 185.
  EXPECT_GE(double(r.quads), 0.94 * double(r.faces));
  EXPECT_GE(double(r.valence4_vertices), 0.76 * double(r.interior_vertices));
  EXPECT_NEAR(double(r.faces), 185.0, 0.3 * 185.0);

  // Every sharp input edge (dihedral above the crease angle) lies within δ/4 of a crease-tagged
  // cage edge (the arc cubics follow the boundary within the (6.1) fit, max RMS δ/4).
  const double delta = cagekit::spacing_from_bbox_fraction(mesh, options.edge_length);
  size_t sharp_edges = 0;
  const size_t off = sharp_edges_off_creases(mesh, r.cage, options.crease_angle_degrees, 0.25 * delta, &sharp_edges);
  std::printf("fandisk: %zu sharp input edges, %zu farther than δ/4 from a crease edge\n", sharp_edges, off);
  EXPECT_GT(sharp_edges, 0u);
  EXPECT_EQ(off, 0u);
}

TEST(QuadRemesher, RockerArmTableSixOneValidCage) {
  const std::string path = cagekit_test::shared_mesh_path("rocker-arm.obj");
  if (path.empty()) GTEST_SKIP() << "../shared/meshes/rocker-arm.obj not present";
  const PolygonMesh mesh = cagekit_test::load_mesh(path);
  // Without the sample-count refinement (about 6 s here, too much for the test budget; the
  // fandisk test covers it): the allocated sample counts as they are.
  QuadRemeshOptions o = table_six_one(41, 0.06, 20, 70, 70);
  o.sample_refinement_passes = 0;
  const QuadRemeshResult r = run_and_check(mesh, o, "rocker-arm").result;
  EXPECT_NEAR(double(r.faces), 431.0, 0.3 * 431.0);
}

// Issue "quad on any mesh": a region that is closed or has a handle is split until every region
// is a disk (possibly with holes), instead of the LSCM refusing it.
TEST(QuadRemesher, ClosedRegionsAndHandlesAreSplitIntoDisks) {
  QuadRemeshOptions o;
  o.regions = 1;
  o.edge_length = 0.1;
  o.sample_refinement_passes = 0;
  const Checked sphere = run_and_check(cagekit_test::triangle_sphere(3), o, "sphere, 1 region");
  EXPECT_GE(sphere.result.split_regions, 1u);
  EXPECT_EQ(sphere.result.regions, 1u + sphere.result.split_regions - sphere.result.merged_regions);
  const Checked torus = run_and_check(cagekit_test::triangle_torus(1.0, 0.35, 36, 12), o, "torus, 1 region");
  EXPECT_GE(torus.result.split_regions, 1u);
  EXPECT_GE(torus.result.regions, 2u);
}

// A thin part: a flat disc (a sphere squashed to 2 % of its width) whose thickness is far
// below the sample spacing. Its top and bottom regions share the rim, and the layout of each
// spans the disc from rim sample to rim sample, so the two glue into faces over the same vertices
// or an edge of four faces (turbine.off's blades, bull.off's legs). They are mended in place (a
// vertex inside one face of each pair) or the region is split between the conflict's ends and
// laid out again: a valid cage either way.
TEST(QuadRemesher, ThinPartsWhoseRegionsSpanTheSameSamples) {
  PolygonMesh disc = cagekit_test::triangle_sphere(3);
  for (Vec3& p : disc.positions) p.z *= 0.02;
  QuadRemeshOptions o;
  o.regions = 2;
  o.edge_length = 0.5;
  const Checked run = run_and_check(disc, o, "thin disc");
  std::printf("thin disc: %llu regions, %llu split, %llu layout retries, %llu faces mended, %llu faces\n",
              (unsigned long long)run.result.regions, (unsigned long long)run.result.split_regions,
              (unsigned long long)run.result.layout_retries, (unsigned long long)run.result.mended_faces,
              (unsigned long long)run.result.faces);
  EXPECT_GT(run.result.mended_faces + run.result.layout_retries, 0u) << "the thin disc did not make the class";
}

// Many components, fewer regions requested than components: the count is raised (every
// component needs its own regions, a closed one at least two), reported, not refused.
TEST(QuadRemesher, ManyComponentsGetTheirOwnRegions) {
  PolygonMesh spheres;
  const PolygonMesh one = cagekit_test::triangle_sphere(2);
  for (int k = 0; k < 50; ++k) {
    const uint32_t offset = uint32_t(spheres.num_vertices());
    for (const Vec3& p : one.positions) spheres.add_vertex(p * 0.3 + Vec3{double(k % 10), double(k / 10), 0.0});
    for (size_t f = 0; f < one.num_faces(); ++f)
      spheres.add_face({one.face_vertex(f, 0) + offset, one.face_vertex(f, 1) + offset, one.face_vertex(f, 2) + offset});
  }
  QuadRemeshOptions o;
  o.regions = 30;
  o.edge_length = 0.02;
  o.sample_refinement_passes = 0;
  const Checked run = run_and_check(spheres, o, "50 spheres, 30 regions");
  EXPECT_EQ(run.result.requested_regions, 30u);
  EXPECT_GE(run.result.regions, 100u) << "two or more per closed component";
}

// A gear blank as a CAD exporter writes it: a star outline (`teeth` teeth, tips at radius 1, roots
// at 0.75) extruded to height 0.5 in `rows` rows, caps fanned from the axis. Every flank is a flat
// patch between sharp vertical edges, so it has 2 * teeth + 2 feature patches.
PolygonMesh gear_blank(uint32_t teeth, uint32_t rows) {
  PolygonMesh m;
  const uint32_t n = 2 * teeth;
  const double pi = 3.14159265358979323846;
  for (uint32_t row = 0; row <= rows; ++row)
    for (uint32_t k = 0; k < n; ++k) {
      const double a = 2 * pi * k / n, r = k % 2 ? 0.75 : 1.0;
      m.add_vertex(Vec3(r * std::cos(a), r * std::sin(a), 0.5 * row / rows));
    }
  for (uint32_t row = 0; row < rows; ++row)
    for (uint32_t k = 0; k < n; ++k) {
      const uint32_t a = row * n + k, b = row * n + (k + 1) % n, c = a + n, d = b + n;
      m.add_face({a, b, d});
      m.add_face({a, d, c});
    }
  const uint32_t bottom = m.add_vertex(Vec3(0, 0, 0)), top = m.add_vertex(Vec3(0, 0, 0.5));
  for (uint32_t k = 0; k < n; ++k) {
    m.add_face({bottom, (k + 1) % n, k});
    m.add_face({top, rows * n + k, rows * n + (k + 1) % n});
  }
  return m;
}

// 30 regions cannot separate a 16-tooth gear's 34 flat faces: some flank edges end up inside
// regions, uncreased. The count is raised to 1.5 regions per feature patch (51) and then every
// sharp edge lies within δ/4 of a crease edge.
TEST(QuadRemesher, RegionCountIsRaisedToTheFeaturePatches) {
  const PolygonMesh gear = gear_blank(16, 4);
  QuadRemeshOptions o;
  o.sample_refinement_passes = 0;
  const Checked run = run_and_check(gear, o, "gear blank");
  EXPECT_EQ(run.result.requested_regions, 30u);
  EXPECT_GE(run.result.regions, 51u);
  const double tolerance = 0.25 * cagekit::spacing_from_bbox_fraction(gear, o.edge_length);
  size_t sharp = 0;
  const size_t off = sharp_edges_off_creases(gear, run.result.cage, o.crease_angle_degrees, tolerance, &sharp);
  EXPECT_EQ(sharp, 32u * 4 + 2 * 32u);  // the flanks' vertical edges in 4 rows, the two rims
  EXPECT_EQ(off, 0u) << "of " << sharp << " sharp edges";
  // The thesis's fixed count leaves some flank edges uncreased.
  o.regions_per_feature_patch = 0.0;
  const Checked fixed = run_and_check(gear, o, "gear blank, 30 regions");
  EXPECT_LT(fixed.result.regions, 51u);
  size_t sharp_fixed = 0;
  const size_t off_fixed =
      sharp_edges_off_creases(gear, fixed.result.cage, o.crease_angle_degrees, tolerance, &sharp_fixed);
  std::printf("gear blank: %llu regions: %zu of %zu sharp edges off the creases; %llu regions: %zu\n",
              (unsigned long long)run.result.regions, off, sharp, (unsigned long long)fixed.result.regions, off_fixed);
  EXPECT_GT(off_fixed, 0u);
}

// Corpus meshes of each failure class the remesher had (issue "quad on any mesh"), with the
// pipeline's default options: regions with a handle (patch-01, patch-30), a sliver region whose
// sample loop had no area (plane), a folded or non-counter-clockwise sample loop
// (cylinder_locally_refined) and, outside the sanitizer builds, glued faces of two regions that
// coincided (dino), and small holes closed by their two samples (lion, elephant-with-holes).
// Each must now give a valid cage of the same topology.
TEST(QuadRemesher, CorpusMeshesOfEachFailureClass) {
  const std::string dir = std::string(CAGEKIT_SHARED_CORPUS) + "/cgal/";
  std::vector<const char*> names = {"patch-01.off", "patch-30.off", "plane.off", "cylinder_locally_refined.off"};
#if !CAGEKIT_SANITIZED_BUILD
  names.push_back("dino.off");
  // Thin parts whose regions' layouts glued into coinciding faces (mended or split).
  names.push_back("bull.off");
  // A 4-edge hole split between two regions' one-segment arcs closed in the glued mesh, and
  // 6- to 10-edge holes whose arcs the sample-count refinement lowered to one segment each.
  names.push_back("lion.off");
  names.push_back("elephant-with-holes.off");
#endif
  size_t ran = 0;
  for (const char* name : names) {
    const std::string path = dir + name;
    if (!std::ifstream(path).good()) continue;
    const Checked run = run_and_check(cagekit_test::load_mesh(path), QuadRemeshOptions{}, name);
    std::printf("%s: %llu regions (%llu requested, %llu split, %llu merged, %llu layout retries), %llu faces mended, "
                "%llu faces\n",
                name, (unsigned long long)run.result.regions, (unsigned long long)run.result.requested_regions,
                (unsigned long long)run.result.split_regions, (unsigned long long)run.result.merged_regions,
                (unsigned long long)run.result.layout_retries, (unsigned long long)run.result.mended_faces,
                (unsigned long long)run.result.faces);
    if (std::string(name) == "bull.off") {
      EXPECT_GT(run.result.mended_faces + run.result.layout_retries, 0u) << "bull's legs no longer make the class";
    }
    ++ran;
  }
  if (ran == 0) GTEST_SKIP() << "corpus not found at " << dir;
}

// refined_elephant.off: a glue conflict that no split or merge resolves within the retries of
// before 2026-12-06 (4 layouts, a retry only when the failing count drops; the pipeline fell back
// to simplify; with today's retries, 8 layouts and a retry while few regions fail, it lays out
// after 2 retries). The last resort lays the failing regions out by the quad-dominant partition
// of their polygons of samples: a valid cage of the input's topology (run_and_check), with those
// regions reported.
TEST(QuadRemesher, RegionsWhoseLayoutStillFailsArePartitioned) {
#if CAGEKIT_SANITIZED_BUILD
  GTEST_SKIP() << "Release only (a 25k-triangle mesh laid out 4 times)";
#endif
  const std::string path = std::string(CAGEKIT_SHARED_CORPUS) + "/cgal/refined_elephant.off";
  if (!std::ifstream(path).good()) GTEST_SKIP() << "corpus not found at " << path;
  QuadRemeshOptions old_retries;
  old_retries.layout_attempts = 4;
  old_retries.retry_few_failing_share = 0.0;
  const Checked run = run_and_check(cagekit_test::load_mesh(path), old_retries, "refined_elephant.off");
  std::printf("refined_elephant.off: %llu regions, %llu layout retries, %llu partitioned, %llu faces, %.1f%% quads\n",
              (unsigned long long)run.result.regions, (unsigned long long)run.result.layout_retries,
              (unsigned long long)run.result.partitioned_regions, (unsigned long long)run.result.faces,
              100.0 * double(run.result.quads) / double(std::max<uint64_t>(1, run.result.faces)));
  EXPECT_GT(run.result.partitioned_regions, 0u) << "refined_elephant no longer makes the class";
  EXPECT_GT(run.result.layout_retries, 0u);
}

// couplingdown.off: a CAD part with bolt holes and thin walls. No layout of its first
// segmentation comes out valid (faces folded against the input remain after every retry and the
// partition), so it is re-seeded with more regions (QuadRemeshOptions::reseed_factors): the
// result is a valid cage of the input's topology (run_and_check) made from the new segmentation,
// reported in reseeded_regions. Without re-seeding it is the error it was.
TEST(QuadRemesher, ALayoutThatFailsIsReseededWithMoreRegions) {
#if CAGEKIT_SANITIZED_BUILD
  GTEST_SKIP() << "Release only (a 7k-triangle mesh laid out up to 12 times)";
#endif
  const std::string path = std::string(CAGEKIT_SHARED_CORPUS) + "/cgal/couplingdown.off";
  if (!std::ifstream(path).good()) GTEST_SKIP() << "corpus not found at " << path;
  const PolygonMesh mesh = cagekit_test::load_mesh(path);
  QuadRemeshOptions once;
  once.reseed_factors.clear();
  try {
    remesh_quad_dominant(mesh, once);
    ADD_FAILURE() << "couplingdown.off's first segmentation now lays out: the test no longer makes the class";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), Status::internal_error) << e.what();
  }
  const Checked run = run_and_check(mesh, QuadRemeshOptions{}, "couplingdown.off");
  std::printf("couplingdown.off: re-seeded with %llu regions, %llu regions used, %llu faces, %.1f%% quads\n",
              (unsigned long long)run.result.reseeded_regions, (unsigned long long)run.result.regions,
              (unsigned long long)run.result.faces,
              100.0 * double(run.result.quads) / double(std::max<uint64_t>(1, run.result.faces)));
  EXPECT_GT(run.result.reseeded_regions, run.result.requested_regions);
  EXPECT_GE(run.result.regions, run.result.reseeded_regions);
  EXPECT_EQ(run.result.flipped_faces, 0u);
}

// turbine.off: a thin disc with bolt holes whose walls are thinner than the sample spacing. Its
// top and bottom regions' layouts filled the holes apart from the rest (the glued mesh had 7
// components and genus 3 for the input's 1 and 11) and were returned. The remesher checks the
// glued mesh's components and Euler characteristic against the input's: the result keeps the
// input's topology (run_and_check asserts it) or is a clean error (the pipeline then falls back).
TEST(QuadRemesher, AResultKeepsTheInputsTopologyOrIsAnError) {
#if CAGEKIT_SANITIZED_BUILD
  GTEST_SKIP() << "Release only (a 18k-triangle mesh laid out up to 4 times)";
#endif
  const std::string path = std::string(CAGEKIT_SHARED_CORPUS) + "/cgal/turbine.off";
  if (!std::ifstream(path).good()) GTEST_SKIP() << "corpus not found at " << path;
  const PolygonMesh mesh = cagekit_test::load_mesh(path);
  try {
    const Checked run = run_and_check(mesh, QuadRemeshOptions{}, "turbine.off");
    std::printf("turbine.off: %llu faces, topology kept\n", (unsigned long long)run.result.faces);
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), Status::internal_error) << e.what();
    std::printf("turbine.off: %s\n", e.what());
  }
}

// femur.off (a crumpled scan, 497 edges sharper than 90 degrees; b9_mesh.off, walls thinner than
// the sample spacing, is the same class, left to the corpus run for time): each retry split the
// few failing regions, and parts of them or their neighbours failed next (folds, a boundary
// touching itself), so the count of failing regions did not drop and the retries ended after 4
// layouts at every re-seeded count: it fell back to simplify. A glued layout whose failing
// regions are at most 10 % of its regions is retried whatever their count (up to 8 layouts,
// until a layout with folded faces only is kept): it now gives the quad method's own valid cage
// of the input's topology, after more layouts than the 4 of before.
TEST(QuadRemesher, AFewFailingRegionsAreRetriedUntilTheLayoutHolds) {
#if CAGEKIT_SANITIZED_BUILD
  GTEST_SKIP() << "Release only (an 8k-triangle mesh laid out 8 times)";
#endif
  const std::string dir = std::string(CAGEKIT_SHARED_CORPUS) + "/cgal/";
  size_t ran = 0;
  for (const char* name : {"femur.off"}) {
    const std::string path = dir + name;
    if (!std::ifstream(path).good()) continue;
    const PolygonMesh mesh = cagekit_test::load_mesh(path);
    const QuadRemeshResult r = cagekit::remesh_quad_dominant(mesh, QuadRemeshOptions{});
    const cagekit::ValidationReport check = cagekit::validate_cage(r.cage);
    EXPECT_TRUE(check.ok()) << name << ": " << check.summary();
    const cagekit::MeshStatistics in = cagekit::compute_mesh_statistics(mesh);
    const cagekit::MeshStatistics out = cagekit::compute_mesh_statistics(r.cage.mesh);
    EXPECT_TRUE(out.manifold) << name;
    EXPECT_EQ(out.genus, in.genus) << name;
    EXPECT_EQ(out.components, in.components) << name;
    EXPECT_EQ(out.boundary_loops, in.boundary_loops) << name;
    std::printf("%s: %llu regions (re-seeded %llu), %llu layout retries, %llu partitioned, %llu flipped, %llu faces, "
                "%.1f%% quads\n",
                name, (unsigned long long)r.regions, (unsigned long long)r.reseeded_regions,
                (unsigned long long)r.layout_retries, (unsigned long long)r.partitioned_regions,
                (unsigned long long)r.flipped_faces, (unsigned long long)r.faces,
                100.0 * double(r.quads) / double(std::max<uint64_t>(1, r.faces)));
    EXPECT_GE(r.layout_retries, 4u) << name << " no longer needs more than the 4 layouts of before";
    ++ran;
  }
  if (ran == 0) GTEST_SKIP() << "corpus not found at " << dir;
}

// A small hole of the input whose border two regions share: each region's arc along it is
// shorter than the spacing and got one segment, so the hole had 2 samples and the glued faces on
// either side shared the chord between them: the hole was closed (lion.off: a 4-edge hole, the
// glued mesh's Euler characteristic -2 for the input's -3). A loop of mesh-border arcs keeps at
// least 3 samples, and a sample inside each arc where it has two (as a region's loop does).
TEST(QuadRemesher, SmallHolesKeepThreeSamples) {
  // A 5 x 5 grid of the unit square in triangles, its centre cell left out (a 4-edge hole);
  // region 0: the triangles whose centroid has x < 0.5, region 1 the others (the hole's
  // border is split between them).
  cagekit::PolygonMesh mesh;
  const int n = 5;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) mesh.add_vertex({double(i) / n, double(j) / n, 0.0});
  std::vector<uint32_t> region;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (i == 2 && j == 2) continue;
      const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n + 1) + 1, d = a + uint32_t(n + 1);
      for (const std::array<uint32_t, 3>& t : {std::array<uint32_t, 3>{a, b, c}, std::array<uint32_t, 3>{a, c, d}}) {
        mesh.add_face({t[0], t[1], t[2]});
        const double x = (mesh.positions[t[0]].x + mesh.positions[t[1]].x + mesh.positions[t[2]].x) / 3.0;
        region.push_back(x < 0.5 ? 0u : 1u);
      }
    }
  cagekit::ConstraintOptions co;
  co.spacing = 0.6;  // longer than the hole's arcs (0.2 - 0.4)
  const cagekit::RemeshConstraints constraints = cagekit::compute_remesh_constraints(mesh, region, 2, co);
  auto on_hole = [](const Vec3& p) { return p.x > 0.39 && p.x < 0.61 && p.y > 0.39 && p.y < 0.61; };
  uint64_t hole_points = 0;
  std::vector<uint64_t> hole_arc_segments;
  for (uint32_t a = 0; a < constraints.arcs.size(); ++a) {
    const cagekit::RegionArc& ra = constraints.boundaries.arcs[a];
    if (ra.right_region != cagekit::kMeshBorder || !on_hole(mesh.positions[ra.vertices.front()])) continue;
    hole_arc_segments.push_back(constraints.arcs[a].samples.t.size() - 1);
    hole_points += hole_arc_segments.back();
  }
  ASSERT_GE(hole_arc_segments.size(), 2u) << "the regions do not share the hole's border";
  EXPECT_GE(hole_points, 3u);
  if (hole_arc_segments.size() == 2) {
    for (const uint64_t segments : hole_arc_segments) EXPECT_GE(segments, 2u);
  }
  // The outer border keeps its samples too: every region loop is a polygon.
  for (uint32_t r = 0; r < 2; ++r) EXPECT_TRUE(cagekit::loops_are_polygons(constraints, r));
  // The sample-count refinement asks border_loop_is_polygon before it keeps a count: one segment
  // on a hole arc (2 samples on the hole) is refused, on an interior arc it is not asked.
  cagekit::RemeshConstraints fewer = constraints;
  for (uint32_t a = 0; a < fewer.arcs.size(); ++a) {
    const bool hole = fewer.boundaries.arcs[a].right_region == cagekit::kMeshBorder &&
                      on_hole(mesh.positions[fewer.boundaries.arcs[a].vertices.front()]);
    EXPECT_TRUE(cagekit::border_loop_is_polygon(fewer, a));
    if (!hole) continue;
    cagekit::resample_arc(fewer, a, 1);
    EXPECT_FALSE(cagekit::border_loop_is_polygon(fewer, a)) << "arc " << a;
    break;
  }
  EXPECT_THROW(cagekit::border_loop_is_polygon(fewer, uint32_t(fewer.arcs.size())), std::out_of_range);
}

// An open surface (mesh border arcs) with a few regions.
TEST(QuadRemesher, OpenCylinderValidCage) {
  const PolygonMesh mesh = cagekit_test::triangle_cylinder(1.0, 3.0, 32, 24);
  QuadRemeshOptions o;
  o.regions = 6;
  o.edge_length = 0.08;
  const Checked run = run_and_check(mesh, o, "cylinder");
  // A smooth surface: no region boundary is sharp.
  EXPECT_EQ(run.result.creases, 0u);
}

TEST(QuadRemesher, PinnedRegionsStayAndSeedsStartRegions) {
  const PolygonMesh mesh = cagekit_test::triangle_cylinder(1.0, 3.0, 32, 24);
  // An edge-connected set of 60 triangles grown from triangle 0 (breadth first).
  std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> edge_faces;
  for (uint32_t f = 0; f < mesh.num_faces(); ++f)
    for (uint32_t k = 0; k < 3; ++k) {
      const uint32_t a = mesh.face_vertex(f, k), b = mesh.face_vertex(f, (k + 1) % 3);
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back(f);
    }
  std::vector<uint32_t> pinned{0};
  std::set<uint32_t> in{0};
  for (size_t i = 0; i < pinned.size() && pinned.size() < 60; ++i)
    for (uint32_t k = 0; k < 3 && pinned.size() < 60; ++k) {
      const uint32_t a = mesh.face_vertex(pinned[i], k), b = mesh.face_vertex(pinned[i], (k + 1) % 3);
      for (uint32_t g : edge_faces[{std::min(a, b), std::max(a, b)}])
        if (pinned.size() < 60 && in.insert(g).second) pinned.push_back(g);
    }
  QuadRemeshOptions o;
  o.regions = 7;
  o.edge_length = 0.08;
  o.pinned_regions = {pinned};
  o.seed_faces = {700, 1200};
  const Checked run = run_and_check(mesh, o, "cylinder, pinned");
  const std::vector<uint32_t>& region = run.result.face_region;
  ASSERT_EQ(region.size(), mesh.num_faces());
  EXPECT_EQ(run.result.regions, 7u);
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) EXPECT_EQ(region[f] == 0, in.count(f) == 1) << f;
  // Bad host input: a face out of range, a seed inside the pinned set, a disconnected set.
  auto status_of = [&](const QuadRemeshOptions& bad) {
    try {
      cagekit::remesh_quad_dominant(mesh, bad);
    } catch (const Error& e) {
      return e.status();
    }
    return Status::success;
  };
  QuadRemeshOptions bad = o;
  bad.seed_faces = {uint32_t(mesh.num_faces())};
  EXPECT_EQ(status_of(bad), Status::invalid_argument);
  bad = o;
  bad.seed_faces = {pinned[3]};
  EXPECT_EQ(status_of(bad), Status::invalid_argument);
  bad = o;
  bad.pinned_regions = {{0, 1200}};
  EXPECT_EQ(status_of(bad), Status::invalid_argument);
}

TEST(QuadRemesher, BadOptionsAndInputAreErrors) {
  const PolygonMesh cylinder = cagekit_test::triangle_cylinder(1.0, 3.0, 16, 8);
  auto status_of = [](const PolygonMesh& m, const QuadRemeshOptions& o) {
    try {
      cagekit::remesh_quad_dominant(m, o);
    } catch (const Error& e) {
      return e.status();
    }
    return Status::success;
  };
  QuadRemeshOptions o;
  o.regions = 4;
  o.edge_length = 0.0;
  EXPECT_EQ(status_of(cylinder, o), Status::invalid_argument);
  o.edge_length = 0.1;
  o.triangle_weight = -1.0;
  EXPECT_EQ(status_of(cylinder, o), Status::invalid_argument);
  o.triangle_weight = 40.0;
  o.regions = -1;
  EXPECT_EQ(status_of(cylinder, o), Status::invalid_argument);
  o.regions = 30;
  o.regions_per_feature_patch = -0.5;
  EXPECT_EQ(status_of(cylinder, o), Status::invalid_argument);
  o.regions_per_feature_patch = std::nan("");
  EXPECT_EQ(status_of(cylinder, o), Status::invalid_argument);
  o.regions_per_feature_patch = 1.5;
  o.regions = 100000;  // more regions than triangles: capped at the triangle count, not refused
  {
    const PolygonMesh small = cagekit_test::triangle_cylinder(1.0, 3.0, 6, 2);  // 24 triangles
    QuadRemeshOptions capped;
    capped.regions = int(small.num_faces()) + 7;
    capped.edge_length = 0.1;
    capped.sample_refinement_passes = 0;
    const QuadRemeshResult r = remesh_quad_dominant(small, capped);
    EXPECT_EQ(r.requested_regions, small.num_faces() + 7);
    EXPECT_LE(r.regions, small.num_faces());
    EXPECT_TRUE(validate_cage(r.cage).ok());
  }
  o.regions = 4;
  o.layout_attempts = 0;
  EXPECT_EQ(status_of(cylinder, o), Status::invalid_argument);
  o.layout_attempts = 8;
  o.retry_few_failing_share = std::nan("");
  EXPECT_EQ(status_of(cylinder, o), Status::invalid_argument);
  o.retry_few_failing_share = 1.5;
  EXPECT_EQ(status_of(cylinder, o), Status::invalid_argument);
  o.retry_few_failing_share = 0.1;
  o.sample_refinement_passes = -1;
  EXPECT_EQ(status_of(cylinder, o), Status::invalid_argument);
  o.sample_refinement_passes = 1;
  PolygonMesh broken = cylinder;
  broken.face_vertices[5] = 100000;  // out of range
  EXPECT_EQ(status_of(broken, o), Status::invalid_mesh);
  PolygonMesh flipped = cylinder;
  std::swap(flipped.face_vertices[0], flipped.face_vertices[1]);  // inconsistent orientation
  EXPECT_EQ(status_of(flipped, o), Status::invalid_mesh);
  PolygonMesh nan = cylinder;
  nan.positions[3].x = std::nan("");
  EXPECT_EQ(status_of(nan, o), Status::invalid_mesh);
  EXPECT_EQ(status_of(PolygonMesh{}, o), Status::invalid_mesh);
}

// Progress runs through the four stages in order and a cancel in any of them is Status::cancelled.
TEST(QuadRemesher, ProgressStagesAndCancellation) {
  const PolygonMesh cylinder = cagekit_test::triangle_cylinder(1.0, 3.0, 16, 12);
  QuadRemeshOptions o;
  o.regions = 4;
  o.edge_length = 0.1;
  std::vector<std::string> stages;
  const cagekit::TaskMonitor record(
      [&](const char* stage, double) {
        if (stages.empty() || stages.back() != stage) stages.push_back(stage);
        return true;
      },
      nullptr);
  cagekit::remesh_quad_dominant(cylinder, o, record);
  const std::vector<std::string> expected{"vsa segmentation", "remesh constraints", "quad region selection",
                                          "post-processing"};
  std::vector<std::string> distinct;
  for (const std::string& s : stages)
    if (std::find(distinct.begin(), distinct.end(), s) == distinct.end()) distinct.push_back(s);
  for (const std::string& want : expected)
    EXPECT_NE(std::find(distinct.begin(), distinct.end(), want), distinct.end()) << want;
  for (const std::string& stop : expected) {
    const cagekit::TaskMonitor cancel([&](const char* stage, double) { return stop != stage; }, nullptr);
    Status status = Status::success;
    try {
      cagekit::remesh_quad_dominant(cylinder, o, cancel);
    } catch (const Error& e) {
      status = e.status();
    }
    EXPECT_EQ(status, Status::cancelled) << stop;
  }
}
