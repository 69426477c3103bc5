// SPDX-License-Identifier: GPL-3.0-or-later
// Sharp input features (issue 20): the one definition every method's creases follow.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <optional>
#include <cmath>
#include <random>

#include "layout/common/sharp_input_features.h"
#include "pipeline/scan_to_cage.h"
#include "test_support.h"

namespace {

using cagekit::PolygonMesh;
using cagekit::Vec3;

constexpr double kPi = 3.14159265358979323846;

// A box 2 x 2 x 2 whose four vertical edges are rounded (radius 0.4, `arc` segments per quarter
// turn: 90 / arc degrees between neighbouring facets) and whose top and bottom rims are sharp
// (90 degrees): the outline in xy extruded along z in `rows` rows, caps fanned from their
// centres. The sharp edges are exactly the outline's edges at z = -1 and z = +1.
struct RoundedBox {
  PolygonMesh mesh;
  size_t outline = 0;  // vertices per ring
  int rows = 0;
};

RoundedBox rounded_box(int arc, int side, int rows) {
  RoundedBox box;
  box.rows = rows;
  std::vector<std::array<double, 2>> ring;
  const double r = 0.4, h = 1.0 - r;
  const double centres[4][2] = {{h, h}, {-h, h}, {-h, -h}, {h, -h}};
  for (int q = 0; q < 4; ++q) {
    for (int k = 0; k < arc; ++k) {  // quarter circle from angle q·90° to (q+1)·90°
      const double a = (q + double(k) / arc) * kPi / 2;
      ring.push_back({centres[q][0] + r * std::cos(a), centres[q][1] + r * std::sin(a)});
    }
    // The straight side to the next corner's arc, in `side` pieces.
    const double a = (q + 1) * kPi / 2;
    const std::array<double, 2> from{centres[q][0] + r * std::cos(a), centres[q][1] + r * std::sin(a)};
    const double* c = centres[(q + 1) % 4];
    const std::array<double, 2> to{c[0] + r * std::cos(a), c[1] + r * std::sin(a)};
    for (int k = 0; k < side; ++k) {
      const double t = double(k) / side;
      ring.push_back({from[0] + t * (to[0] - from[0]), from[1] + t * (to[1] - from[1])});
    }
  }
  box.outline = ring.size();
  const uint32_t n = uint32_t(ring.size());
  for (int row = 0; row <= rows; ++row)
    for (const auto& p : ring) box.mesh.add_vertex(Vec3(p[0], p[1], -1.0 + 2.0 * row / rows));
  for (int row = 0; row < rows; ++row)
    for (uint32_t k = 0; k < n; ++k) {
      const uint32_t a = row * n + k, b = row * n + (k + 1) % n, c = a + n, d = b + n;
      box.mesh.add_face({a, b, d});
      box.mesh.add_face({a, d, c});
    }
  const uint32_t bottom = box.mesh.add_vertex(Vec3(0, 0, -1)), top = box.mesh.add_vertex(Vec3(0, 0, 1));
  for (uint32_t k = 0; k < n; ++k) {
    box.mesh.add_face({bottom, (k + 1) % n, k});
    box.mesh.add_face({top, rows * n + k, rows * n + (k + 1) % n});
  }
  return box;
}

TEST(SharpInputFeatures, rounded_box_is_sharp_exactly_along_its_rims) {
  const RoundedBox box = rounded_box(6, 8, 10);
  const cagekit::SharpFeatures f = cagekit::detect_sharp_features(box.mesh);
  ASSERT_EQ(f.edges.size(), 2 * box.outline);
  const uint32_t n = uint32_t(box.outline), last = uint32_t(box.rows) * n;
  for (uint32_t k = 0; k < n; ++k) {
    EXPECT_TRUE(f.contains(k, (k + 1) % n)) << "bottom rim edge " << k;
    EXPECT_TRUE(f.contains(last + k, last + (k + 1) % n)) << "top rim edge " << k;
  }
  EXPECT_EQ(f.noise_edges, 0u);
  EXPECT_EQ(f.short_edges, 0u);
  // Corner flags agree with the edge list.
  size_t flagged = 0;
  for (uint8_t c : f.corner_flags) flagged += c;
  EXPECT_EQ(flagged, 2 * f.edges.size());
}

TEST(SharpInputFeatures, noisy_sphere_keeps_few_of_its_sharp_raw_dihedrals) {
  PolygonMesh sphere = cagekit_test::triangle_sphere(5);  // 8192 triangles, edges ~0.03
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-0.012, 0.012);
  for (Vec3& p : sphere.positions) p = p * (1.0 + noise(rng));
  const cagekit::SharpFeatures f = cagekit::detect_sharp_features(sphere);
  EXPECT_GT(f.raw_edges, 20u) << "the noise must make some raw dihedral angles exceed 40 degrees";
  // Heavy noise (a third of an edge length): the side normals and the line rule drop most; the
  // few short lines left are not creases of a cage (the cage tests below).
  EXPECT_LE(f.edges.size(), f.raw_edges / 4) << f.raw_edges << " raw, " << f.noise_edges << " noise, " << f.short_edges << " short";
  // Without the filters and the length rule the same edges would be sharp.
  cagekit::SharpFeatureOptions raw;
  raw.side_rings = 0;
  raw.min_length_rel = 0.0;
  raw.min_edges = 0;
  raw.max_side_bend_fraction = 1.0;
  EXPECT_EQ(cagekit::detect_sharp_features(sphere, raw).edges.size(), f.raw_edges);
}

// A surface of revolution about z: the profile (radius, height) turned in `segments` facets, each
// band of quads split into two triangles, the ends closed by fans from the axis at the end rings'
// heights (flat caps) or at the given pole heights.
PolygonMesh revolved(const std::vector<std::array<double, 2>>& profile, uint32_t segments,
                     std::optional<std::array<double, 2>> poles = std::nullopt) {
  PolygonMesh m;
  const uint32_t rings = uint32_t(profile.size());
  for (const auto& [r, z] : profile)
    for (uint32_t k = 0; k < segments; ++k) {
      const double a = 2 * kPi * k / segments;
      m.add_vertex(Vec3(r * std::cos(a), r * std::sin(a), z));
    }
  for (uint32_t i = 0; i + 1 < rings; ++i)
    for (uint32_t k = 0; k < segments; ++k) {
      const uint32_t a = i * segments + k, b = i * segments + (k + 1) % segments, c = a + segments, d = b + segments;
      m.add_face({a, b, d});
      m.add_face({a, d, c});
    }
  const uint32_t bottom = m.add_vertex(Vec3(0, 0, poles ? (*poles)[0] : profile.front()[1]));
  const uint32_t top = m.add_vertex(Vec3(0, 0, poles ? (*poles)[1] : profile.back()[1])), last = (rings - 1) * segments;
  for (uint32_t k = 0; k < segments; ++k) {
    m.add_face({bottom, (k + 1) % segments, k});
    m.add_face({top, last + k, last + (k + 1) % segments});
  }
  return m;
}

// Test 4 keeps a CAD feature whose both sides are coarse: a shaft (32 facets, 11.25 degrees
// between neighbours) stepped down by a 45-degree chamfer, as couplingdown.off's bores are. Its
// four rims (two caps at 90 degrees, the chamfer's two at 45) stay sharp.
TEST(SharpInputFeatures, chamfer_between_coarse_cylinders_stays_sharp) {
  const uint32_t n = 32;
  const PolygonMesh shaft = revolved({{1.0, 0.0}, {1.0, 1.0}, {0.8, 1.2}, {0.8, 2.0}}, n);
  const cagekit::SharpFeatures f = cagekit::detect_sharp_features(shaft);
  EXPECT_EQ(f.faceted_edges, 0u);
  ASSERT_EQ(f.edges.size(), 4 * n);
  for (uint32_t ring = 0; ring < 4; ++ring)
    for (uint32_t k = 0; k < n; ++k)
      EXPECT_TRUE(f.contains(ring * n + k, ring * n + (k + 1) % n)) << "ring " << ring << " edge " << k;
}

// A low-poly smooth body: an ellipsoid 6 x 2 x 1 as 128 triangles (an octahedron split twice,
// stretched). 20 of its edges bend by more than 40 degrees and join into lines long enough for
// test 3 (without test 4 all 20 are sharp), yet the facets beside them bend nearly as much: test 4
// drops them all, as it does the faceting of the corpus's low-poly animals.
TEST(SharpInputFeatures, coarsely_faceted_ellipsoid_has_no_sharp_features) {
  PolygonMesh body = cagekit_test::triangle_sphere(2);
  for (Vec3& p : body.positions) p = Vec3(3.0 * p.x, p.y, 0.5 * p.z);
  cagekit::SharpFeatureOptions without;
  without.max_side_bend_fraction = 1.0;
  const cagekit::SharpFeatures g = cagekit::detect_sharp_features(body, without);
  EXPECT_EQ(g.raw_edges, 20u);
  EXPECT_EQ(g.edges.size(), 20u) << "without test 4, lines of the faceting are sharp";
  const cagekit::SharpFeatures f = cagekit::detect_sharp_features(body);
  EXPECT_EQ(f.edges.size(), 0u);
  EXPECT_EQ(f.faceted_edges, 20u);
}

TEST(SharpInputFeatures, fandisk_keeps_every_edge_sharper_than_40_degrees) {
  const std::string path = cagekit_test::shared_mesh_path("fandisk.obj");
  if (path.empty()) GTEST_SKIP() << "../shared/meshes/fandisk.obj not present";
  const PolygonMesh mesh = cagekit_test::load_mesh(path);
  const cagekit::SharpFeatures f = cagekit::detect_sharp_features(mesh);
  EXPECT_GT(f.edges.size(), 300u);
  // A clean CAD mesh: the noise filter and the length rule drop (almost) nothing.
  EXPECT_LE(double(f.noise_edges + f.short_edges), 0.02 * double(f.raw_edges))
      << f.raw_edges << " raw, " << f.noise_edges << " noise, " << f.short_edges << " short";
}

// A border edge runs along the features when it is a rim edge, a rim chord, or zigzags beside a
// rim; the axial edges of a one-row box (a coarse CAD tessellation: each facet one quad from the
// bottom rim to the top rim) join the two rims but do not run along either.
TEST(SharpInputFeatures, edges_along_features_follow_a_line_and_do_not_join_two) {
  const RoundedBox box = rounded_box(6, 8, 1);
  const cagekit::SharpFeatures f = cagekit::detect_sharp_features(box.mesh);
  ASSERT_EQ(f.edges.size(), 2 * box.outline);
  const uint32_t n = uint32_t(box.outline);
  std::vector<std::pair<uint32_t, uint32_t>> rim, chords, axial, diagonal;
  for (uint32_t k = 0; k < n; ++k) {
    rim.push_back({k, (k + 1) % n});
    chords.push_back({k, (k + 2) % n});  // skips one rim vertex
    axial.push_back({k, n + k});          // bottom rim to top rim, straight up a facet
    diagonal.push_back({k, n + (k + 1) % n});
  }
  auto count = [&](const std::vector<std::pair<uint32_t, uint32_t>>& edges) {
    const std::vector<uint8_t> along = cagekit::edges_along_features(box.mesh, f, edges, 40.0);
    return size_t(std::count(along.begin(), along.end(), uint8_t(1)));
  };
  EXPECT_EQ(count(rim), n);
  EXPECT_EQ(count(chords), n);
  EXPECT_EQ(count(axial), 0u) << "an axial edge joins the two rims, it does not follow one";
  EXPECT_EQ(count(diagonal), 0u);
  // The old rule (both ends on or next to a feature) took every one of them: both ends are on a rim.
  for (const auto& [a, b] : axial)
    EXPECT_TRUE(f.contains(a, (a + 1) % n) && f.contains(b, n + (b + 1 - n) % n));
  // Beside a line: on the ten-row box a border that zigzags one triangle above the bottom rim.
  const RoundedBox tall = rounded_box(6, 8, 10);
  const cagekit::SharpFeatures g = cagekit::detect_sharp_features(tall.mesh);
  std::vector<std::pair<uint32_t, uint32_t>> zigzag;
  for (uint32_t k = 0; k < n; ++k) {
    zigzag.push_back({k, n + (k + 1) % n});      // the triangle's diagonal, up from the rim
    zigzag.push_back({n + (k + 1) % n, (k + 1) % n});  // and back down to it
  }
  const std::vector<uint8_t> along = cagekit::edges_along_features(tall.mesh, g, zigzag, 40.0);
  EXPECT_EQ(size_t(std::count(along.begin(), along.end(), uint8_t(1))), zigzag.size());
  // The second ring's edges are two rings from the rim: not along it.
  std::vector<std::pair<uint32_t, uint32_t>> second;
  for (uint32_t k = 0; k < n; ++k) second.push_back({2 * n + k, 2 * n + (k + 1) % n});
  const std::vector<uint8_t> far = cagekit::edges_along_features(tall.mesh, g, second, 40.0);
  EXPECT_EQ(std::count(far.begin(), far.end(), uint8_t(1)), 0);
}

// Distance from p to the segment a-b.
double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp(dot(p - a, ab) / std::max(dot(ab, ab), 1e-300), 0.0, 1.0);
  return cagekit::distance(p, a + ab * t);
}

// The simplify journey's cage (scan_to_cage, defaults: 60 faces, creases by the sharp-input
// rule) before its fit: its vertices are input vertices at their input positions.
cagekit::Cage simplify_cage(const PolygonMesh& scan, uint64_t target = 60) {
  cagekit::ScanToCageOptions options;
  options.target = target;
  return cagekit::scan_to_cage(scan, options).initial_cage;
}

TEST(SharpInputCreases, rounded_box_cage_is_creased_along_its_rims_only) {
  const RoundedBox box = rounded_box(6, 8, 10);
  const cagekit::Cage cage = simplify_cage(box.mesh);
  ASSERT_GT(cage.creases.size(), 4u);
  // Every crease runs along a rim: both ends at z = ±1 on the outline, its middle too (a chord of
  // a rounded corner's arc at most), never down a rounded vertical edge or across a cap.
  for (const cagekit::EdgeCrease& c : cage.creases) {
    const Vec3 a = cage.mesh.positions[c.v0], b = cage.mesh.positions[c.v1], m = (a + b) * 0.5;
    EXPECT_TRUE(std::fabs(a.z) == 1.0 && std::fabs(b.z) == 1.0 && a.z == b.z)
        << "crease (" << a.x << " " << a.y << " " << a.z << ") - (" << b.x << " " << b.y << " " << b.z << ")";
    EXPECT_GE(std::max(std::fabs(m.x), std::fabs(m.y)), 0.75) << "a crease across a cap";
  }
  // ... and the rims are covered: every rim edge's middle lies near a crease (4 % of the diagonal:
  // a chord cuts a rounded corner's arc by up to 0.12).
  const uint32_t n = uint32_t(box.outline), last = uint32_t(box.rows) * n;
  for (uint32_t ring : {0u, last})
    for (uint32_t k = 0; k < n; ++k) {
      const Vec3 m = (box.mesh.positions[ring + k] + box.mesh.positions[ring + (k + 1) % n]) * 0.5;
      double nearest = 1e9;
      for (const cagekit::EdgeCrease& c : cage.creases)
        nearest = std::min(nearest, segment_distance(m, cage.mesh.positions[c.v0], cage.mesh.positions[c.v1]));
      EXPECT_LE(nearest, 0.15) << "rim edge " << ring + k << " has no crease";
    }
}

// A puck as a CAD exporter writes it: a cylinder (radius 1, height `height`, `segments` facets)
// whose side is one row of quads (each split into two triangles) from the bottom rim to the top
// rim, caps fanned from their centres. Sharp: the two rims; the facets meet at 360/segments.
PolygonMesh coarse_puck(uint32_t segments, double height) {
  PolygonMesh m;
  for (int z = 0; z < 2; ++z)
    for (uint32_t k = 0; k < segments; ++k) {
      const double a = 2 * kPi * k / segments;
      m.add_vertex(Vec3(std::cos(a), std::sin(a), (z - 0.5) * height));
    }
  for (uint32_t k = 0; k < segments; ++k) {
    const uint32_t a = k, b = (k + 1) % segments, c = a + segments, d = b + segments;
    m.add_face({a, b, d});
    m.add_face({a, d, c});
  }
  const uint32_t bottom = m.add_vertex(Vec3(0, 0, -0.5 * height)), top = m.add_vertex(Vec3(0, 0, 0.5 * height));
  for (uint32_t k = 0; k < segments; ++k) {
    m.add_face({bottom, (k + 1) % segments, k});
    m.add_face({top, segments + k, segments + (k + 1) % segments});
  }
  return m;
}

// The cluster borders down the side of a coarse puck run over single axial edges whose ends are
// both on a rim. They must not become creases: before edges_along_features they did, and the
// puck's side (like the bores of pinion.off and anchor.off) came out a faceted prism.
TEST(SharpInputCreases, coarse_puck_cage_has_no_crease_down_its_side) {
  const PolygonMesh puck = coarse_puck(24, 1.0);
  for (uint64_t target : {12u, 20u}) {  // 16 and 25 cage faces: the side in a few clusters
    const cagekit::Cage cage = simplify_cage(puck, target);
    EXPECT_GE(cage.creases.size(), 8u) << "the rims are creased";
    for (const cagekit::EdgeCrease& c : cage.creases) {
      const Vec3 a = cage.mesh.positions[c.v0], b = cage.mesh.positions[c.v1];
      EXPECT_EQ(a.z, b.z) << "target " << target << ": crease down the side (" << a.x << " " << a.y << " " << a.z
                          << ") - (" << b.x << " " << b.y << " " << b.z << ")";
    }
  }
}

TEST(SharpInputCreases, noisy_sphere_cage_has_no_creases) {
  PolygonMesh sphere = cagekit_test::triangle_sphere(5);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-0.012, 0.012);
  for (Vec3& p : sphere.positions) p = p * (1.0 + noise(rng));
  // At the default 60 faces and at 120. (At 200 faces two cage edges of this sphere are creased:
  // there two clusters meet at 41 degrees over a surviving 4-edge noise line; issue 20's note.)
  EXPECT_EQ(simplify_cage(sphere).creases.size(), 0u);
  EXPECT_EQ(simplify_cage(sphere, 120).creases.size(), 0u);
}

// The cage of the low-poly ellipsoid above: no creases (with test 4 off: 22 creases at 16
// faces, 36 at 30).
TEST(SharpInputCreases, coarsely_faceted_ellipsoid_cage_has_no_creases) {
  PolygonMesh body = cagekit_test::triangle_sphere(2);
  for (Vec3& p : body.positions) p = Vec3(3.0 * p.x, p.y, 0.5 * p.z);
  EXPECT_EQ(simplify_cage(body, 16).creases.size(), 0u);
  EXPECT_EQ(simplify_cage(body, 30).creases.size(), 0u);
}

TEST(SharpInputCreases, fandisk_cage_has_every_sharp_feature_line_on_crease_edges) {
  const std::string path = cagekit_test::shared_mesh_path("fandisk.obj");
  if (path.empty()) GTEST_SKIP() << "../shared/meshes/fandisk.obj not present";
  const PolygonMesh mesh = cagekit_test::load_mesh(path);
  const cagekit::SharpFeatures features = cagekit::detect_sharp_features(mesh);
  const cagekit::Cage cage = simplify_cage(mesh);
  const double tolerance = 0.01 * mesh.bounding_box().diagonal();
  // Recall: the share of the feature lines' length within 1 % of the diagonal of a crease edge.
  double near = 0.0, total = 0.0;
  for (uint64_t e : features.edges) {
    const Vec3 a = mesh.positions[uint32_t(e >> 32)], b = mesh.positions[uint32_t(e)];
    const double l = cagekit::distance(a, b);
    double nearest = 1e300;
    for (const cagekit::EdgeCrease& c : cage.creases)
      nearest = std::min(nearest, segment_distance((a + b) * 0.5, cage.mesh.positions[c.v0], cage.mesh.positions[c.v1]));
    total += l;
    near += nearest <= tolerance ? l : 0.0;
  }
  EXPECT_GE(near, 0.95 * total) << "recall " << near / total;
  // Precision: every crease edge's middle lies on a feature line (within 1 %).
  for (const cagekit::EdgeCrease& c : cage.creases) {
    const Vec3 m = (cage.mesh.positions[c.v0] + cage.mesh.positions[c.v1]) * 0.5;
    double nearest = 1e300;
    for (uint64_t e : features.edges)
      nearest = std::min(nearest, segment_distance(m, mesh.positions[uint32_t(e >> 32)], mesh.positions[uint32_t(e)]));
    EXPECT_LE(nearest, tolerance) << "a crease away from every feature line";
  }
}

TEST(SharpInputFeatures, bad_options_and_meshes_are_errors) {
  const RoundedBox box = rounded_box(2, 2, 2);
  for (auto set : {+[](cagekit::SharpFeatureOptions& o) { o.angle_degrees = 181; },
                   +[](cagekit::SharpFeatureOptions& o) { o.angle_degrees = std::nan(""); },
                   +[](cagekit::SharpFeatureOptions& o) { o.side_rings = -1; },
                   +[](cagekit::SharpFeatureOptions& o) { o.confirm_fraction = 1.5; },
                   +[](cagekit::SharpFeatureOptions& o) { o.min_length_rel = -1; }}) {
    cagekit::SharpFeatureOptions o;
    set(o);
    EXPECT_EQ(cagekit_test::status_of([&] { cagekit::detect_sharp_features(box.mesh, o); }),
              cagekit::Status::invalid_argument);
  }
  PolygonMesh broken = box.mesh;
  broken.face_vertices[0] = 100000;
  EXPECT_EQ(cagekit_test::status_of([&] { cagekit::detect_sharp_features(broken); }), cagekit::Status::invalid_mesh);
  EXPECT_EQ(cagekit::detect_sharp_features(PolygonMesh{}).edges.size(), 0u);
}

}  // namespace
