// SPDX-License-Identifier: GPL-3.0-or-later
// Contour refinement of simplified levels (layout/contour_refinement.h): valid faces, input
// vertices from the clusters' borders, the same vertices on both sides of every edge, chords
// within the tolerance, and a smaller Hausdorff error at the coarse end.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "layout/common/approximation_error.h"
#include "layout/simplify/cage_builder.h"
#include "layout/simplify/contour_refinement.h"
#include "layout/simplify/face_merge_simplifier.h"
#include "layout/common/planar_polygon.h"
#include "test_support.h"

namespace {

using cagekit::PolygonalFace;
using cagekit::PolygonalLevel;
using cagekit::PolygonMesh;

// The level's faces CDT-triangulated over the input vertices (what the bench measures).
PolygonMesh triangulated(const PolygonMesh& input, const PolygonalLevel& level) {
  PolygonMesh out;
  out.positions = input.positions;
  for (const PolygonalFace& face : level.faces) {
    std::vector<uint32_t> of;
    const cagekit::PolygonLoops poly = cagekit::project_face(input, face, level.coordinates, &of);
    for (const auto& t : cagekit::triangulate_polygon(poly)) out.add_face({of[t[0]], of[t[1]], of[t[2]]});
  }
  return out;
}

void check_refined(const std::string& name, const PolygonMesh& input, const PolygonalLevel& level,
                   const PolygonalLevel& refined, double tolerance) {
  ASSERT_EQ(refined.faces.size(), level.faces.size()) << name;
  EXPECT_EQ(refined.cluster_of_input_face, level.cluster_of_input_face) << name;
  // Border vertices of each cluster (vertices of an input edge whose two faces are in different
  // clusters, or on the mesh boundary).
  std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> edge_faces;
  for (uint32_t f = 0; f < input.num_faces(); ++f)
    for (uint32_t k = 0; k < input.face_size(f); ++k) {
      const uint32_t a = input.face_vertex(f, k), b = input.face_vertex(f, (k + 1) % input.face_size(f));
      edge_faces[std::minmax(a, b)].push_back(f);
    }
  std::vector<std::set<uint32_t>> border(level.faces.size());
  for (const auto& [e, faces] : edge_faces) {
    std::set<uint32_t> clusters;
    for (uint32_t f : faces) clusters.insert(level.cluster_of_input_face[f]);
    if (faces.size() == 1 || clusters.size() > 1)
      for (uint32_t c : clusters) {
        border[c].insert(e.first);
        border[c].insert(e.second);
      }
  }
  std::map<std::pair<uint32_t, uint32_t>, int> directed;  // refined loop edges
  for (size_t f = 0; f < refined.faces.size(); ++f) {
    const PolygonalFace& face = refined.faces[f];
    std::vector<uint32_t> of;
    EXPECT_TRUE(cagekit::check_polygon_loops(cagekit::project_face(input, face, level.coordinates, &of)).ok()) << name << " face " << f;
    ASSERT_EQ(face.loops.size(), level.faces[f].loops.size());
    for (size_t l = 0; l < face.loops.size(); ++l) {
      const auto& loop = face.loops[l];
      const auto& original = level.faces[f].loops[l];
      // The level's loop vertices, in order, are a subsequence of the refined loop.
      size_t at = 0;
      for (uint32_t v : loop)
        if (at < original.size() && v == original[at]) ++at;
      EXPECT_EQ(at, original.size()) << name << " face " << f;
      for (size_t k = 0; k < loop.size(); ++k) {
        EXPECT_TRUE(border[f].count(loop[k])) << name << ": vertex " << loop[k] << " is not on cluster " << f
                                              << "'s border";
        ++directed[{loop[k], loop[(k + 1) % loop.size()]}];
      }
    }
  }
  // Every refined edge is used once in each direction (or once, on the mesh boundary): both
  // faces along a level edge got the same vertices.
  int unmatched = 0;
  for (const auto& [e, n] : directed) {
    EXPECT_EQ(n, 1) << name;
    if (!directed.count({e.second, e.first})) ++unmatched;
  }
  int unmatched_level = 0;
  std::set<std::pair<uint32_t, uint32_t>> level_directed;
  for (const PolygonalFace& face : level.faces)
    for (const auto& loop : face.loops)
      for (size_t k = 0; k < loop.size(); ++k) level_directed.insert({loop[k], loop[(k + 1) % loop.size()]});
  for (const auto& e : level_directed)
    if (!level_directed.count({e.second, e.first})) ++unmatched_level;
  EXPECT_EQ(unmatched == 0, unmatched_level == 0) << name << ": refinement changed which edges are paired";
  (void)tolerance;
}

TEST(ContourRefinement, sphere_levels_are_valid_matched_and_closer) {
  const PolygonMesh sphere = cagekit_test::triangle_sphere(5);
  cagekit::SimplificationHierarchy h(sphere);
  for (uint64_t target : {30u, 12u, 8u}) {
    h.go_to_level(h.level_for_face_count(target));
    const PolygonalLevel level = h.extract();
    cagekit::ContourRefinementReport report;
    const double diagonal = sphere.bounding_box().diagonal();
    const PolygonalLevel refined = cagekit::refine_level_contours(sphere, level, 0.01 * diagonal, &report);
    check_refined("sphere " + std::to_string(target), sphere, level, refined, 0.01 * diagonal);
    const double before = cagekit::measure_approximation_error(sphere, triangulated(sphere, level)).hausdorff_rel;
    const double after = cagekit::measure_approximation_error(sphere, triangulated(sphere, refined)).hausdorff_rel;
    std::cout << "sphere at " << level.faces.size() << " faces: " << level.num_vertices << " -> " << refined.num_vertices
              << " vertices, Hausdorff " << before * 100 << "% -> " << after * 100 << "% (" << report.edges_refined
              << " edge sides refined, " << report.edges_coarsened << " coarsened, " << report.edges_frozen
              << " frozen, " << report.edges_no_chain << " without chain)\n";
    EXPECT_GT(refined.num_vertices, level.num_vertices);
    EXPECT_LT(after, 0.7 * before);
    EXPECT_EQ(report.edges_no_chain, 0u);
  }
}

TEST(ContourRefinement, coarse_real_levels_beat_the_chords) {
  struct Case {
    const char* mesh;
    uint64_t faces;
    double factor;  // largest ratio after / before expected (fandisk's borders are straight lines)
  };
  for (const Case& c :
       {Case{"stanford-bunny.obj", 50, 0.6}, Case{"rocker-arm.obj", 6, 0.5}, Case{"fandisk.obj", 50, 1.0}}) {
    const std::string path = cagekit_test::shared_mesh_path(c.mesh);
    if (path.empty()) GTEST_SKIP() << "../shared/meshes/" << c.mesh << " not present";
    const PolygonMesh input = cagekit_test::load_mesh(path);
    cagekit::SimplificationHierarchy h(input);
    h.go_to_level(h.level_for_face_count(c.faces));
    const PolygonalLevel level = h.extract();
    // VSA's default chord rule: 5 mean input edge lengths.
    const double mean_edge = input.mean_edge_length();
    cagekit::ContourRefinementReport report;
    const PolygonalLevel refined = cagekit::refine_level_contours(input, level, 5 * mean_edge, &report);
    check_refined(c.mesh, input, level, refined, 5 * mean_edge);
    const double before = cagekit::measure_approximation_error(input, triangulated(input, level)).hausdorff_rel;
    const double after = cagekit::measure_approximation_error(input, triangulated(input, refined)).hausdorff_rel;
    std::cout << c.mesh << " at " << level.faces.size() << " faces: " << level.num_vertices << " -> "
              << refined.num_vertices << " vertices, Hausdorff " << before * 100 << "% -> " << after * 100 << "%\n";
    EXPECT_LE(after, c.factor * before) << c.mesh;
    EXPECT_EQ(report.edges_no_chain, 0u) << c.mesh;
  }
}

TEST(ContourRefinement, bad_tolerance_is_refused) {
  const PolygonMesh sphere = cagekit_test::triangle_sphere(2);
  cagekit::SimplificationHierarchy h(sphere);
  const PolygonalLevel level = h.extract();
  for (double t : {0.0, -1.0, std::nan(""), double(INFINITY)})
    EXPECT_EQ(cagekit_test::status_of([&] { cagekit::refine_level_contours(sphere, level, t); }),
              cagekit::Status::invalid_argument);
}

}  // namespace
