// SPDX-License-Identifier: GPL-3.0-or-later
// Face-merge simplifier (thesis ch. 3): validity of every level with an independent brute-force
// verifier, clusters, proxies, hierarchy replay, greedy order, decimation, scale invariance,
// and the real models (timings printed, not asserted).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <fstream>
#include <ctime>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <unordered_map>

#include "core/mesh_validation.h"
#include "core/status.h"
#include "layout/simplify/cage_builder.h"
#include "layout/simplify/face_merge_simplifier.h"
#include "layout/simplify/merge_priority.h"
#include "test_support.h"

using namespace cagekit;

namespace {

using LD = long double;
struct P2 {
  LD x, y;
};

int orient(const P2& a, const P2& b, const P2& c) {
  const LD d = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  return d > 0 ? 1 : (d < 0 ? -1 : 0);
}
bool within(const P2& a, const P2& b, const P2& p) {
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y && p.y <= std::max(a.y, b.y);
}
bool segments_meet(const P2& a, const P2& b, const P2& c, const P2& d) {
  const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  return (o1 == 0 && within(a, b, c)) || (o2 == 0 && within(a, b, d)) || (o3 == 0 && within(c, d, a)) ||
         (o4 == 0 && within(c, d, b));
}
// Ray crossing (+x direction) point-in-polygon.
bool inside(const std::vector<P2>& poly, const P2& q) {
  bool in = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const P2 &a = poly[i], &b = poly[j];
    if ((a.y > q.y) != (b.y > q.y)) {
      const LD x = a.x + (q.y - a.y) * (b.x - a.x) / (b.y - a.y);
      if (q.x < x) in = !in;
    }
  }
  return in;
}
LD signed_area(const std::vector<P2>& poly) {
  LD a = 0;
  for (size_t i = 0; i < poly.size(); ++i) {
    const P2 &p = poly[i], &q = poly[(i + 1) % poly.size()];
    a += p.x * q.y - p.y * q.x;
  }
  return a / 2;
}

// Independent O(m^2) check of the injectivity criterion (a)-(d) + orientation; "" when valid.
std::string independent_check(const PolygonMesh& mesh, const std::vector<std::vector<uint32_t>>& loops,
                              const Vec3& normal, const Vec3& origin) {
  const Vec3 helper = std::fabs(normal.x) < 0.6 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  const Vec3 u = normalized(cross(helper, normal)), v = cross(normal, u);
  std::vector<std::vector<P2>> poly;
  std::set<uint32_t> seen;
  for (const auto& l : loops) {
    if (l.size() < 3) return "loop with < 3 vertices";
    poly.emplace_back();
    for (const uint32_t i : l) {
      if (!seen.insert(i).second) return "repeated vertex";
      const Vec3 d = mesh.positions[i] - origin;
      poly.back().push_back({static_cast<LD>(d.x) * u.x + static_cast<LD>(d.y) * u.y + static_cast<LD>(d.z) * u.z,
                             static_cast<LD>(d.x) * v.x + static_cast<LD>(d.y) * v.y + static_cast<LD>(d.z) * v.z});
    }
  }
  struct Seg {
    size_t loop, k;
  };
  std::vector<Seg> segs;
  for (size_t l = 0; l < poly.size(); ++l)
    for (size_t k = 0; k < poly[l].size(); ++k) segs.push_back({l, k});
  for (size_t i = 0; i < segs.size(); ++i)
    for (size_t j = i + 1; j < segs.size(); ++j) {
      const auto& L1 = poly[segs[i].loop];
      const auto& L2 = poly[segs[j].loop];
      const size_t n1 = L1.size(), n2 = L2.size(), a = segs[i].k, b = segs[j].k;
      const P2 &p0 = L1[a], &p1 = L1[(a + 1) % n1], &q0 = L2[b], &q1 = L2[(b + 1) % n2];
      if (segs[i].loop == segs[j].loop && ((a + 1) % n1 == b || (b + 1) % n1 == a)) {
        // Adjacent edges share exactly one endpoint; they must not fold back onto each other.
        const bool ab = (a + 1) % n1 == b;
        const P2 &s = ab ? p1 : p0, &x = ab ? p0 : p1, &y = ab ? q1 : q0;
        if (orient(x, s, y) == 0 && (x.x - s.x) * (y.x - s.x) + (x.y - s.y) * (y.y - s.y) > 0)
          return "adjacent edges overlap";
        if (n1 == 3 || !(ab && (b + 1) % n1 == a)) continue;
        continue;
      }
      if (segments_meet(p0, p1, q0, q1)) return "edges intersect";
    }
  if (!(signed_area(poly[0]) > 0)) return "outer loop not counter-clockwise";
  for (size_t h = 1; h < poly.size(); ++h) {
    if (!(signed_area(poly[h]) < 0)) return "hole not clockwise";
    if (!inside(poly[0], poly[h][0])) return "hole outside";
    for (size_t g = 1; g < poly.size(); ++g)
      if (g != h && inside(poly[g], poly[h][0])) return "holes nested";
  }
  return "";
}

double tri_area(const PolygonMesh& m, size_t f) {
  double a = 0;
  const uint32_t* v = m.face_begin(f);
  for (uint32_t i = 1; i + 1 < m.face_size(f); ++i)
    a += 0.5 * norm(cross(m.positions[v[i]] - m.positions[v[0]], m.positions[v[i + 1]] - m.positions[v[0]]));
  return a;
}

// All invariants of one extracted level (acceptance items 12-15).
void check_level(const PolygonMesh& mesh, const PolygonalLevel& level, const std::string& what) {
  SCOPED_TRACE(what);
  const size_t nf = mesh.num_faces();
  ASSERT_EQ(level.cluster_of_input_face.size(), nf);
  std::vector<double> area(level.faces.size(), 0);
  std::vector<size_t> members(level.faces.size(), 0);
  for (size_t t = 0; t < nf; ++t) {
    ASSERT_LT(level.cluster_of_input_face[t], level.faces.size());
    area[level.cluster_of_input_face[t]] += tri_area(mesh, t);
    ++members[level.cluster_of_input_face[t]];
  }
  std::set<std::pair<uint32_t, uint32_t>> directed;
  for (size_t f = 0; f < level.faces.size(); ++f) {
    const PolygonalFace& face = level.faces[f];
    EXPECT_GT(members[f], 0u) << "face " << f << " has an empty cluster";
    EXPECT_NEAR(face.area, area[f], 1e-9 * std::max(1.0, area[f])) << "face " << f;
    EXPECT_NEAR(norm(face.normal), 1.0, 1e-9);
    for (const auto& l : face.loops)
      for (size_t i = 0; i < l.size(); ++i) {
        ASSERT_LT(l[i], mesh.num_vertices());
        EXPECT_TRUE(directed.insert({l[i], l[(i + 1) % l.size()]}).second) << "duplicate half-edge";
      }
    const std::string err = independent_check(mesh, face.loops, face.normal, face.centroid);
    EXPECT_EQ(err, "") << "face " << f << " (" << face.loops.size() << " loops)";
  }
  // No two faces over the same vertices (a closed two-face "pillow" gives duplicate cage cells).
  std::map<std::vector<uint32_t>, size_t> vertex_sets;
  for (size_t f = 0; f < level.faces.size(); ++f) {
    std::vector<uint32_t> key;
    for (const auto& l : level.faces[f].loops) key.insert(key.end(), l.begin(), l.end());
    std::sort(key.begin(), key.end());
    const auto inserted = vertex_sets.emplace(key, f);
    EXPECT_TRUE(inserted.second) << "face " << f << " has the vertices of face " << inserted.first->second;
  }
  // No two faces joined by two distinct edges between the same vertex pair (no duplicate edges).
  std::map<std::pair<uint32_t, uint32_t>, int> undirected;
  for (const auto& e : directed) ++undirected[{std::min(e.first, e.second), std::max(e.first, e.second)}];
  for (const auto& e : undirected) EXPECT_LE(e.second, 2);
  // Clusters are edge-connected: union input faces across shared input edges of the same cluster.
  std::vector<uint32_t> parent(nf);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> edge_face;
  for (uint32_t t = 0; t < nf; ++t) {
    const uint32_t* v = mesh.face_begin(t);
    const uint32_t n = mesh.face_size(t);
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t a = v[i], b = v[(i + 1) % n];
      auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = edge_face.find(key);
      if (it == edge_face.end()) {
        edge_face[key] = t;
      } else if (level.cluster_of_input_face[it->second] == level.cluster_of_input_face[t]) {
        parent[find(t)] = find(it->second);
      }
    }
  }
  std::vector<int> components(level.faces.size(), 0);
  for (uint32_t t = 0; t < nf; ++t)
    if (find(t) == t) ++components[level.cluster_of_input_face[t]];
  for (size_t f = 0; f < level.faces.size(); ++f) EXPECT_EQ(components[f], 1) << "cluster " << f << " not connected";
}

bool same_level(const PolygonalLevel& a, const PolygonalLevel& b) {
  if (a.faces.size() != b.faces.size() || a.cluster_of_input_face != b.cluster_of_input_face) return false;
  for (size_t f = 0; f < a.faces.size(); ++f)
    if (a.faces[f].loops != b.faces[f].loops || a.faces[f].area != b.faces[f].area ||
        a.faces[f].normal != b.faces[f].normal || a.faces[f].centroid != b.faces[f].centroid)
      return false;
  return a.num_vertices == b.num_vertices;
}

// Box [0,1]^3 with each side an n x n grid of quads split into triangles.
PolygonMesh triangulated_box(int n, double sx = 1, double sy = 1, double sz = 1) {
  PolygonMesh m;
  std::map<std::tuple<int, int, int>, uint32_t> index;
  auto vertex = [&](int i, int j, int k) {
    auto key = std::make_tuple(i, j, k);
    auto it = index.find(key);
    if (it != index.end()) return it->second;
    const uint32_t id = m.add_vertex(Vec3(sx * i / n, sy * j / n, sz * k / n));
    index[key] = id;
    return id;
  };
  // For each of 6 sides: origin corner and two in-plane axes chosen so that a x b points outward.
  struct Side {
    int o[3], a[3], b[3];
  };
  const Side sides[6] = {{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}}, {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},
                         {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}}, {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},
                         {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}}, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  for (const Side& s : sides)
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        uint32_t q[4];
        const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
        for (int c = 0; c < 4; ++c) {
          int p[3];
          for (int d = 0; d < 3; ++d) p[d] = s.o[d] * n + s.a[d] * (i + di[c]) + s.b[d] * (j + dj[c]);
          q[c] = vertex(p[0], p[1], p[2]);
        }
        m.add_face({q[0], q[1], q[2]});
        m.add_face({q[0], q[2], q[3]});
      }
  return m;
}

double bump(double x, double y) { return 0.15 * std::sin(0.9 * x) * std::cos(0.7 * y); }

PolygonMesh triangulated_grid(int nx, int ny) {
  PolygonMesh q = cagekit_test::quad_grid(nx, ny, bump);
  PolygonMesh m;
  m.positions = q.positions;
  for (size_t f = 0; f < q.num_faces(); ++f) {
    const uint32_t* v = q.face_begin(f);
    m.add_face({v[0], v[1], v[2]});
    m.add_face({v[0], v[2], v[3]});
  }
  return m;
}

PolygonMesh scaled(PolygonMesh m, double s) {
  for (auto& p : m.positions) p = p * s;
  return m;
}

// Every level valid; replay in random order identical.
void check_all_levels(const PolygonMesh& mesh, const char* name, bool verify_greedy) {
  SimplifyOptions options;
  options.verify_greedy_order = verify_greedy;
  SimplificationHierarchy h(mesh, options);
  const size_t n = h.num_levels();
  std::printf("[%s] %zu input faces -> %zu levels, coarsest %llu faces / %llu vertices\n", name, mesh.num_faces(), n,
              static_cast<unsigned long long>(h.face_count(n - 1)), static_cast<unsigned long long>(h.vertex_count(n - 1)));
  std::vector<PolygonalLevel> levels;
  for (size_t l = 0; l < n; ++l) {
    h.go_to_level(l);
    levels.push_back(h.extract());
    EXPECT_EQ(levels.back().faces.size(), h.face_count(l));
    EXPECT_EQ(levels.back().num_vertices, h.vertex_count(l));
    check_level(mesh, levels.back(), std::string(name) + " level " + std::to_string(l));
    if (::testing::Test::HasFailure()) return;
  }
  std::mt19937 rng(7);
  for (int k = 0; k < 3 * static_cast<int>(n); ++k) {
    const size_t l = rng() % n;
    h.go_to_level(l);
    ASSERT_TRUE(same_level(h.extract(), levels[l])) << name << " replay of level " << l;
  }
}

// Closed mesh: no interior valence-2 vertex that could still be removed (item 18).
void expect_no_removable_valence2(const PolygonMesh& mesh, const PolygonalLevel& level) {
  std::map<uint32_t, std::vector<std::pair<uint32_t, size_t>>> star;  // vertex -> (face, loop)
  std::set<std::pair<uint32_t, uint32_t>> edges;
  for (uint32_t f = 0; f < level.faces.size(); ++f)
    for (size_t l = 0; l < level.faces[f].loops.size(); ++l) {
      const auto& loop = level.faces[f].loops[l];
      for (size_t i = 0; i < loop.size(); ++i) {
        star[loop[i]].push_back({f, l});
        const uint32_t a = loop[i], b = loop[(i + 1) % loop.size()];
        edges.insert({std::min(a, b), std::max(a, b)});
      }
    }
  for (const auto& [v, faces] : star) {
    if (faces.size() != 2) continue;
    uint32_t nb[2][2];
    std::vector<std::vector<uint32_t>> reduced[2];
    for (int k = 0; k < 2; ++k) {
      reduced[k] = level.faces[faces[k].first].loops;
      auto& loop = reduced[k][faces[k].second];
      const size_t i = static_cast<size_t>(std::find(loop.begin(), loop.end(), v) - loop.begin());
      nb[k][0] = loop[(i + loop.size() - 1) % loop.size()];
      nb[k][1] = loop[(i + 1) % loop.size()];
      loop.erase(loop.begin() + static_cast<std::ptrdiff_t>(i));
    }
    if (nb[0][0] != nb[1][1] || nb[0][1] != nb[1][0]) continue;  // not valence 2
    const bool duplicate = edges.count({std::min(nb[0][0], nb[0][1]), std::max(nb[0][0], nb[0][1])}) > 0;
    bool valid = !duplicate;
    for (int k = 0; k < 2 && valid; ++k) {
      const PolygonalFace& face = level.faces[faces[k].first];
      valid = independent_check(mesh, reduced[k], face.normal, face.centroid).empty();
    }
    EXPECT_FALSE(valid) << "valence-2 vertex " << v << " could still be removed";
  }
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

TEST(FaceMergeSimplifier, PriorityTermsMatchQuadrature) {
  // (3.2) against a dense midpoint quadrature of the squared signed distance.
  const Vec3 a(0.1, 0.2, 0.3), b(1.1, -0.2, 0.5), c(0.3, 0.9, -0.4), o(0.2, 0.1, 0.0);
  const Vec3 n = normalized(Vec3(0.3, -0.4, 0.85));
  const int k = 400;
  double sum = 0;
  const double area = 0.5 * norm(cross(b - a, c - a));
  for (int i = 0; i < k; ++i)
    for (int j = 0; i + j < k; ++j) {
      // Sub-triangle centroids of a uniform k x k split (upright and inverted).
      const double u = (i + 1.0 / 3) / k, v = (j + 1.0 / 3) / k;
      const double d = dot(a + (b - a) * u + (c - a) * v - o, n);
      sum += d * d;
      if (i + j + 1 < k) {
        const double u2 = (i + 2.0 / 3) / k, v2 = (j + 2.0 / 3) / k;
        const double d2 = dot(a + (b - a) * u2 + (c - a) * v2 - o, n);
        sum += d2 * d2;
      }
    }
  sum *= area / (static_cast<double>(k) * k);
  // Tetrahedron built from the triangle and its reflection must give the same exact value.
  PolygonMesh m;
  m.add_vertex(a);
  m.add_vertex(b);
  m.add_vertex(c);
  m.add_face({0, 1, 2});
  (void)m;
  const double d0 = dot(a - o, n), d1 = dot(b - o, n), d2 = dot(c - o, n);
  const double exact = (d0 * d0 + d1 * d1 + d2 * d2 + d0 * d1 + d0 * d2 + d1 * d2) * area / 6;
  EXPECT_NEAR(exact, sum, 1e-4 * exact);
}

TEST(FaceMergeSimplifier, QuantizePriorityMatchesFrexpRounding) {
  // The bit-manipulation fast path must equal round(m 2^40) 2^(e-40), m = frexp(x, &e).
  const auto reference = [](double x) {
    if (!std::isfinite(x) || x == 0) return x;
    int e = 0;
    const double m = std::frexp(x, &e);
    return std::ldexp(std::round(std::ldexp(m, 40)), e - 40);
  };
  std::mt19937_64 rng(7);
  std::vector<double> xs = {1.0, -1.0, 0.0, -0.0, 1e-310, -1e-310, INFINITY, -INFINITY, DBL_MAX, -DBL_MAX, DBL_MIN,
                            std::nextafter(1.0, 2.0), std::nextafter(1.0, 0.0), std::nextafter(2.0, 0.0)};
  for (int i = 0; i < 200000; ++i) {
    uint64_t u = rng();
    if (i % 4 == 1) u = (u & ~uint64_t(0x1fff)) | 0x1000;  // exact halves
    if (i % 4 == 2) u |= 0x1fff;                           // all dropped bits set (carry)
    if (i % 4 == 3) u = (u & 0x800fffffffffffffull) | (uint64_t(1023 + int(u % 64)) << 52);
    double x;
    std::memcpy(&x, &u, sizeof x);
    xs.push_back(x);
  }
  for (const double x : xs) {
    const double q = detail::quantize_priority(x), r = reference(x);
    if (std::isnan(x)) {
      EXPECT_TRUE(std::isnan(q));
      continue;
    }
    uint64_t a, b;
    std::memcpy(&a, &q, sizeof a);
    std::memcpy(&b, &r, sizeof b);
    ASSERT_EQ(a, b) << x;
  }
}

TEST(FaceMergeSimplifier, RejectsInvalidInput) {
  PolygonMesh m = cagekit_test::unit_cube_quads();
  m.add_face({0, 1, 2});  // non-manifold edge / duplicate-ish
  try {
    SimplificationHierarchy h(m);
    FAIL() << "expected Error(invalid_mesh)";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), Status::invalid_mesh);
  }
}

TEST(FaceMergeSimplifier, UnreferencedVerticesAreIgnored) {
  PolygonMesh m = triangulated_box(1);
  m.add_vertex(Vec3(100, 100, 100));
  SimplificationHierarchy h(m);
  h.go_to_level(h.num_levels() - 1);
  check_level(m, h.extract(), "box with unreferenced vertex");
}

TEST(FaceMergeSimplifier, TriangulatedBoxAllLevels) {
  const PolygonMesh box = triangulated_box(2);  // 48 triangles
  check_all_levels(box, "box 2x2", true);
  SimplificationHierarchy h(box);
  h.go_to_level(h.num_levels() - 1);
  const PolygonalLevel coarse = h.extract();
  std::printf("[box 2x2] coarsest: %zu faces\n", coarse.faces.size());
  EXPECT_GE(coarse.faces.size(), 3u) << "a closed component stops at three faces, never a two-face pillow";
  expect_no_removable_valence2(box, coarse);
  // The level with one face per side exists: 6 planar faces, zero L2 / L2,1 error.
  const size_t six = h.level_for_face_count(6);
  h.go_to_level(six);
  const PolygonalLevel sides = h.extract();
  std::printf("[box 2x2] level %zu: %zu faces, L2 %.3g, L2,1 %.3g\n", six, sides.faces.size(), sides.l2_error,
              sides.l21_error);
  if (sides.faces.size() == 6) {
    EXPECT_NEAR(sides.l21_error, 0.0, 1e-12);
    for (const auto& f : sides.faces) EXPECT_EQ(f.loops[0].size(), 4u) << "each side decimated to its 4 corners";
  }
}

TEST(FaceMergeSimplifier, TriangulatedGridAllLevels) {
  check_all_levels(triangulated_grid(6, 5), "grid 6x5", true);  // 60 triangles
  check_all_levels(triangulated_grid(12, 10), "grid 12x10", false);
}

TEST(FaceMergeSimplifier, SphereAllLevels) {
  const PolygonMesh s1 = cagekit_test::triangle_sphere(1);
  ASSERT_LE(s1.num_faces(), 60u);
  check_all_levels(s1, "sphere 1", true);
  const PolygonMesh s2 = cagekit_test::triangle_sphere(2);
  check_all_levels(s2, "sphere 2", false);
  SimplificationHierarchy h(s2);
  h.go_to_level(h.num_levels() - 1);
  expect_no_removable_valence2(s2, h.extract());
}

TEST(FaceMergeSimplifier, QuadInputPolygonPlanes) {
  const PolygonMesh cube = cagekit_test::unit_cube_quads();
  check_all_levels(cube, "quad cube", false);
  const PolygonMesh grid = cagekit_test::quad_grid(5, 4, bump);
  check_all_levels(grid, "quad grid", false);
}

TEST(FaceMergeSimplifier, UnitScaleInvariance) {
  const PolygonMesh meshes[3] = {triangulated_box(3), triangulated_grid(10, 8), cagekit_test::triangle_sphere(2)};
  for (const PolygonMesh& m : meshes) {
    SimplificationHierarchy a(m), b(scaled(m, 1000.0));
    ASSERT_EQ(a.num_levels(), b.num_levels());
    for (size_t l = 0; l < a.num_levels(); ++l) {
      ASSERT_EQ(a.face_count(l), b.face_count(l)) << "level " << l;
      ASSERT_EQ(a.vertex_count(l), b.vertex_count(l)) << "level " << l;
    }
    a.go_to_level(a.num_levels() - 1);
    b.go_to_level(b.num_levels() - 1);
    EXPECT_EQ(a.extract().cluster_of_input_face, b.extract().cluster_of_input_face);
  }
}

TEST(FaceMergeSimplifier, EpsilonIsATieBreak) {
  // On a curved surface the coarse structure barely depends on epsilon; report the counts.
  const PolygonMesh s = cagekit_test::triangle_sphere(3);
  for (const double eps : {0.0, 0.001, 0.01, 0.1}) {
    SimplifyOptions o;
    o.tie_break_epsilon = eps;
    SimplificationHierarchy h(s, o);
    h.go_to_level(h.num_levels() - 1);
    const PolygonalLevel c = h.extract();
    std::printf("[sphere 3, eps %.3g] %zu levels, coarsest %zu faces\n", eps, h.num_levels(), c.faces.size());
    check_level(s, c, "eps");
  }
}

TEST(FaceMergeSimplifier, LevelQueriesAndProgress) {
  const PolygonMesh s = cagekit_test::triangle_sphere(2);
  int calls = 0;
  TaskMonitor monitor([&](const char*, double f) { EXPECT_GE(f, 0.0); EXPECT_LE(f, 1.0); ++calls; return true; }, nullptr);
  SimplificationHierarchy h(s, {}, monitor);
  EXPECT_GE(calls, 1);
  for (size_t l = 1; l < h.num_levels(); ++l) {
    EXPECT_LE(h.face_count(l), h.face_count(l - 1));
    EXPECT_GE(h.error(l), 1.0);
  }
  const size_t l = h.level_for_face_count(20);
  EXPECT_LE(h.face_count(l), 20u);
  if (l > 0) {
    EXPECT_GT(h.face_count(l - 1), 20u);
  }
  EXPECT_EQ(h.level_for_face_count(0), h.num_levels() - 1);
  EXPECT_EQ(h.level_for_error(0.5), 0u);
  TaskMonitor cancel([](const char*, double) { return false; }, nullptr);
  try {
    SimplificationHierarchy c(cagekit_test::triangle_sphere(4), {}, cancel);
    FAIL() << "expected cancellation";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), Status::cancelled);
  }
}

namespace {
// FNV-1a digest of every level's face count, vertex count and error bits: identical digests
// before/after an optimisation mean identical hierarchies (level by level).
uint64_t level_digest(const SimplificationHierarchy& h) {
  uint64_t digest = 1469598103934665603ull;
  const auto mix = [&](uint64_t x) {
    for (int k = 0; k < 8; ++k) digest = (digest ^ ((x >> (8 * k)) & 0xff)) * 1099511628211ull;
  };
  for (size_t l = 0; l < h.num_levels(); ++l) {
    uint64_t bits;
    const double e = h.error(l);
    std::memcpy(&bits, &e, sizeof bits);
    mix(h.face_count(l));
    mix(h.vertex_count(l));
    mix(bits);
  }
  return digest;
}

void run_real(const char* file, size_t check_every) {
  const std::string path = cagekit_test::shared_mesh_path(file);
  if (path.empty()) GTEST_SKIP() << file << " not present";
  const PolygonMesh mesh = cagekit_test::load_mesh(path);
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  SimplificationHierarchy h(mesh);
  const double build = seconds_since(t0);
  const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  const size_t n = h.num_levels();
  h.go_to_level(n - 1);
  const PolygonalLevel c = h.extract();
  size_t holes = 0;
  for (const auto& f : c.faces) holes += f.loops.size() - 1;
  std::printf("[%s] %zu faces: simplified to the coarsest level in %.3f s wall, %.3f s CPU; %zu levels; coarsest %zu faces, %llu "
              "vertices, %zu holes\n",
              file, mesh.num_faces(), build, cpu, n, c.faces.size(), static_cast<unsigned long long>(c.num_vertices), holes);
  std::printf("   level digest (faces, vertices, error of all %zu levels): %016llx\n", n,
              static_cast<unsigned long long>(level_digest(h)));
  for (const uint64_t target : {270u, 50u, 32u, 17u, 14u}) {
    const size_t l = h.level_for_face_count(target);
    std::printf("   level for <= %llu faces: %zu (%llu faces, %llu vertices)\n", static_cast<unsigned long long>(target),
                l, static_cast<unsigned long long>(h.face_count(l)), static_cast<unsigned long long>(h.vertex_count(l)));
  }
  check_level(mesh, c, std::string(file) + " coarsest");
  for (size_t l = 0; l < n; l += check_every) {
    h.go_to_level(l);
    check_level(mesh, h.extract(), std::string(file) + " level " + std::to_string(l));
    if (::testing::Test::HasFailure()) break;
  }
  const auto t1 = std::chrono::steady_clock::now();
  h.go_to_level(0);
  h.go_to_level(n - 1);
  std::printf("   full replay down and up: %.3f s\n", seconds_since(t1));
  EXPECT_TRUE(same_level(h.extract(), c));
}
}  // namespace

TEST(FaceMergeSimplifier, Fandisk) { run_real("fandisk.obj", 97); }
TEST(FaceMergeSimplifier, RockerArm) { run_real("rocker-arm.obj", 2003); }
TEST(FaceMergeSimplifier, Bunny) { run_real("stanford-bunny.obj", 20011); }

namespace {
// One step of Loop subdivision (smooth; edges with != 2 faces use the boundary rules), so that
// the subdivided mesh has no flat patches that would make merges free.
PolygonMesh loop_subdivide(const PolygonMesh& m) {
  const size_t nv = m.num_vertices(), nf = m.num_faces();
  struct EdgeInfo {
    uint32_t id, count, opp[2];
  };
  std::unordered_map<uint64_t, EdgeInfo> edges;
  std::vector<uint64_t> order;  // edge keys in creation order (deterministic sums)
  edges.reserve(2 * nf);
  auto key = [](uint32_t a, uint32_t b) { return (uint64_t(std::min(a, b)) << 32) | std::max(a, b); };
  std::vector<uint32_t> face_edges(3 * nf);
  for (size_t t = 0; t < nf; ++t)
    for (uint32_t k = 0; k < 3; ++k) {
      const uint32_t a = m.face_vertex(t, k), b = m.face_vertex(t, (k + 1) % 3), c = m.face_vertex(t, (k + 2) % 3);
      const uint64_t kk = key(a, b);
      auto it = edges.find(kk);
      if (it == edges.end()) {
        it = edges.emplace(kk, EdgeInfo{static_cast<uint32_t>(nv + order.size()), 0, {0, 0}}).first;
        order.push_back(kk);
      }
      if (it->second.count < 2) it->second.opp[it->second.count] = c;
      ++it->second.count;
      face_edges[3 * t + k] = it->second.id;
    }
  PolygonMesh out;
  out.positions.resize(nv + order.size());
  std::vector<Vec3> sum(nv), bsum(nv);
  std::vector<uint32_t> valence(nv, 0), bcount(nv, 0);
  for (const uint64_t kk : order) {
    const EdgeInfo& e = edges[kk];
    const uint32_t a = static_cast<uint32_t>(kk >> 32), b = static_cast<uint32_t>(kk);
    const Vec3 &pa = m.positions[a], &pb = m.positions[b];
    sum[a] += pb;
    sum[b] += pa;
    ++valence[a];
    ++valence[b];
    if (e.count == 2) {
      out.positions[e.id] = (pa + pb) * 0.375 + (m.positions[e.opp[0]] + m.positions[e.opp[1]]) * 0.125;
    } else {
      out.positions[e.id] = (pa + pb) * 0.5;
      bsum[a] += pb;
      bsum[b] += pa;
      ++bcount[a];
      ++bcount[b];
    }
  }
  for (size_t v = 0; v < nv; ++v) {
    const Vec3& p = m.positions[v];
    if (bcount[v] == 2) {
      out.positions[v] = p * 0.75 + bsum[v] * 0.125;
    } else if (bcount[v] > 0 || valence[v] < 3) {
      out.positions[v] = p;
    } else {
      const double n = valence[v], c = 0.375 + 0.25 * std::cos(2 * M_PI / n);
      const double beta = (0.625 - c * c) / n;
      out.positions[v] = p * (1 - n * beta) + sum[v] * beta;
    }
  }
  for (size_t t = 0; t < nf; ++t) {
    const uint32_t a = m.face_vertex(t, 0), b = m.face_vertex(t, 1), c = m.face_vertex(t, 2);
    const uint32_t ab = face_edges[3 * t], bc = face_edges[3 * t + 1], ca = face_edges[3 * t + 2];
    out.add_face({a, ab, ca});
    out.add_face({ab, b, bc});
    out.add_face({ca, bc, c});
    out.add_face({ab, bc, ca});
  }
  return out;
}
}  // namespace

// 1.1M triangles: the bunny Loop-subdivided twice plus seeded Gaussian noise (sigma = 1e-4 of
// the bounding-box diagonal, per coordinate) to 100 faces. Set CAGEKIT_LARGE_TESTS=1.
TEST(FaceMergeSimplifier, MillionTrianglesTiming) {
  if (std::getenv("CAGEKIT_LARGE_TESTS") == nullptr) GTEST_SKIP() << "set CAGEKIT_LARGE_TESTS=1";
  const std::string path = cagekit_test::shared_mesh_path("stanford-bunny.obj");
  if (path.empty()) GTEST_SKIP() << "bunny not present";
  PolygonMesh m = cagekit_test::load_mesh(path);
  for (int level = 0; level < 2; ++level) m = loop_subdivide(m);
  {
    Vec3 lo = m.positions[0], hi = m.positions[0];
    for (const Vec3& p : m.positions) {
      lo = Vec3(std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z));
      hi = Vec3(std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z));
    }
    std::mt19937_64 rng(20240611);
    std::normal_distribution<double> noise(0.0, 1e-4 * norm(hi - lo));
    for (Vec3& p : m.positions) {
      const double x = noise(rng), y = noise(rng), z = noise(rng);
      p += Vec3(x, y, z);
    }
  }
  // Time to 100 faces: the first progress report at or past nf - 100 merges.
  const double target = static_cast<double>(m.num_faces() - 100) / static_cast<double>(m.num_faces() - 1);
  double wall100 = -1, cpu100 = -1;
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  TaskMonitor monitor(
      [&](const char*, double fraction) {
        if (wall100 < 0 && fraction >= target) {
          wall100 = seconds_since(t0);
          cpu100 = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
        }
        return true;
      },
      nullptr);
  SimplificationHierarchy h(m, {}, monitor);
  const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  const size_t l = h.level_for_face_count(100);
  std::printf("[bunny loop x2 + noise] level digest (faces, vertices, error of all %zu levels): %016llx\n",
              h.num_levels(), static_cast<unsigned long long>(level_digest(h)));
  std::printf("[bunny loop x2 + noise] %llu triangulations of %llu vertices, %llu in-place updates of large faces\n",
              static_cast<unsigned long long>(h.stats().triangulations),
              static_cast<unsigned long long>(h.stats().triangulated_vertices),
              static_cast<unsigned long long>(h.stats().incremental_updates));
  std::printf("[bunny loop x2 + noise] %zu triangles: 100 faces in %.2f s wall, %.2f s CPU; the coarsest level (%llu "
              "faces) in %.2f s wall, %.2f s CPU; 100 faces at level %zu\n",
              m.num_faces(), wall100, cpu100, static_cast<unsigned long long>(h.face_count(h.num_levels() - 1)),
              seconds_since(t0), cpu, l);
  h.go_to_level(l);
  check_level(m, h.extract(), "bunny x16 at 100 faces");
}

namespace {
// A finely tessellated, mostly flat plate: n x n grid cells of side 1, two triangles each, with
// a small smooth bump (height 1 over a radius of n/8) near one corner.
PolygonMesh flat_plate(int n) {
  PolygonMesh m;
  const double c = 0.3 * n, r = n / 8.0;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double d2 = ((i - c) * (i - c) + (j - c) * (j - c)) / (r * r);
      m.add_vertex(Vec3(i, j, d2 < 1 ? (1 - d2) * (1 - d2) : 0.0));
    }
  const auto id = [n](int i, int j) { return static_cast<uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.add_face({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}
}  // namespace

// The flat plate of 45K triangles simplifies to 60 faces. With epsilon = 0 (no valence penalty:
// every merge on the flat part has priority exactly 1, ties go by face id) one face grows by
// single triangles and its loops get long: re-triangulating it from scratch after every merge
// into it was quadratic (the 7,200-triangle plate: 1.26M CDT vertices, ~175 per input triangle,
// 7 s; ~50K triangles ran > 10 minutes). Faces above 64 loop vertices now keep their moments up
// to date in place, so the CDT work per input triangle stays bounded. Work counters, not timings.
TEST(FaceMergeSimplifier, FlatPlateTriangulationWorkIsLinear) {
  const PolygonMesh plate = flat_plate(150);
  SimplificationHierarchy h(plate);
  const SimplifyStats& st = h.stats();
  std::printf("[flat plate] %zu triangles: %llu triangulations of %llu vertices, %llu incremental updates\n",
              plate.num_faces(), (unsigned long long)st.triangulations, (unsigned long long)st.triangulated_vertices,
              (unsigned long long)st.incremental_updates);
  const size_t level = h.level_for_face_count(60);
  EXPECT_LE(h.face_count(level), 60u);
  h.go_to_level(level);
  check_level(plate, h.extract(), "flat plate at 60 faces");
  EXPECT_LE(static_cast<double>(st.triangulated_vertices), 16.0 * static_cast<double>(plate.num_faces()));
  SimplifyOptions ties;
  ties.tie_break_epsilon = 0;
  for (const int n : {50, 75}) {
    const PolygonMesh p = flat_plate(n);
    SimplificationHierarchy t(p, ties);
    const SimplifyStats& s = t.stats();
    std::printf("[flat plate, epsilon 0] %zu triangles: %llu triangulations of %llu vertices, %llu incremental updates\n",
                p.num_faces(), (unsigned long long)s.triangulations, (unsigned long long)s.triangulated_vertices,
                (unsigned long long)s.incremental_updates);
    EXPECT_LE(static_cast<double>(s.triangulated_vertices), 40.0 * static_cast<double>(p.num_faces())) << n;
    EXPECT_GT(s.incremental_updates, 0u);
    t.go_to_level(t.level_for_face_count(60));
    check_level(p, t.extract(), "flat plate, epsilon 0, at 60 faces");
  }
}

namespace {
// Every face of the level that the simplifier validated (all but unmerged input triangles) is
// valid in the level's coordinates, and the level becomes a valid cage and a polygon mesh
// without an error.
void expect_level_builds(const PolygonMesh& mesh, const PolygonalLevel& level, const std::string& what) {
  std::vector<uint32_t> of;
  for (size_t f = 0; f < level.faces.size(); ++f) {
    const auto& loops = level.faces[f].loops;
    if (loops.size() == 1 && loops[0].size() == 3) continue;
    const PolygonValidity v = check_polygon_loops(project_face(mesh, level.faces[f], level.coordinates, &of));
    EXPECT_TRUE(v.ok()) << what << ", face " << f << ": " << v.message;
  }
  try {
    CageBuildReport report;
    const Cage cage = build_quad_dominant_cage(mesh, level, {}, &report);
    EXPECT_GT(cage.mesh.num_faces(), 0u) << what;
    EXPECT_EQ(report.non_manifold_edges, 0u) << what;
    polygonal_level_mesh(mesh, level);
  } catch (const Error& e) {
    ADD_FAILURE() << what << ": " << e.what();
  }
}

// Quads of a grid with exactly vertical walls between terraces: merged across a wall, the wall's
// top and bottom vertices project onto the same points (coincident projected points), and
// nearly vertical walls (slope 1e-9) make edges that touch after projection.
PolygonMesh terraces(int steps, double wall_run) {
  PolygonMesh q;
  const int nx = 3 * steps, ny = 4;
  std::vector<std::vector<uint32_t>> id(nx + 1, std::vector<uint32_t>(ny + 1));
  for (int i = 0; i <= nx; ++i)
    for (int j = 0; j <= ny; ++j) {
      // Columns 3k+1 and 3k+2 share x (up to wall_run): the wall between terrace k and k+1.
      const int k = i / 3, r = i % 3;
      const double x = k * 2.0 + (r == 0 ? 0.0 : (r == 1 ? 1.0 : 1.0 + wall_run));
      const double z = k + (r == 2 ? 1.0 : 0.0);
      id[i][j] = q.add_vertex(Vec3(x, j, z));
    }
  PolygonMesh m;
  m.positions = q.positions;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      m.add_face({id[i][j], id[i + 1][j], id[i + 1][j + 1]});
      m.add_face({id[i][j], id[i + 1][j + 1], id[i][j + 1]});
    }
  return m;
}
}  // namespace

// Generated inputs for each class of polygon that must never reach the CDT: coincident projected
// points (exactly vertical walls, a box flattened to 1e-9 of its size), edges that touch after
// projection (walls of slope 1e-9), holes touching the outer loop (a plate with a square
// window, whose faces around the window merge into faces with holes). Every level the
// simplifier makes is valid and gives a cage without an error.
TEST(FaceMergeSimplifier, DegenerateProjectionsNeverReachTheTriangulation) {
  std::vector<std::pair<std::string, PolygonMesh>> meshes;
  meshes.push_back({"vertical terraces", terraces(4, 0.0)});
  meshes.push_back({"nearly vertical terraces", terraces(4, 1e-9)});
  meshes.push_back({"flattened box", triangulated_box(3, 1, 1, 1e-9)});
  {
    PolygonMesh window = flat_plate(12);  // drop the faces of a 4 x 4 window: a hole in the plate
    PolygonMesh m;
    m.positions = window.positions;
    for (size_t f = 0; f < window.num_faces(); ++f) {
      const size_t cell = f / 2, i = cell % 12, j = cell / 12;
      if (i >= 4 && i < 8 && j >= 4 && j < 8) continue;
      m.add_face(window.face_begin(f), window.face_size(f));
    }
    meshes.push_back({"plate with a window", m});
  }
  for (const auto& [name, mesh] : meshes) {
    ASSERT_TRUE(validate_mesh(mesh).ok()) << name << ": " << validate_mesh(mesh).summary();
    SimplificationHierarchy h(mesh);
    const size_t n = h.num_levels();
    for (size_t l = 0; l < n; l += std::max<size_t>(1, n / 40)) {
      h.go_to_level(l);
      expect_level_builds(mesh, h.extract(), name + " level " + std::to_string(l));
    }
    h.go_to_level(n - 1);
    expect_level_builds(mesh, h.extract(), name + " coarsest");
  }
}

// The corpus meshes that crashed the simplification (SIGSEGV in CGAL's constrained
// triangulation, polygons with holes), and others with holes: simplified, and their 60-face
// level becomes a cage. Skips when ../shared/corpus is absent.
TEST(FaceMergeSimplifier, CorpusMeshesWithHoles) {
  const std::string dir = std::string(CAGEKIT_SHARED_CORPUS) + "/cgal/";
  size_t ran = 0;
  for (const char* name : {"couplingdown.off", "elephant-with-holes.off", "boeing.off", "holes.off",
                           "mech-holes-shark.off", "corner_tris_with_hole.off"}) {
    const std::string path = dir + name;
    if (!std::ifstream(path).good()) continue;
    const PolygonMesh mesh = cagekit_test::load_mesh(path);
    SimplificationHierarchy h(mesh);
    for (const uint64_t faces : {200u, 60u, 20u}) {
      h.go_to_level(h.level_for_face_count(faces));
      expect_level_builds(mesh, h.extract(), std::string(name) + " at " + std::to_string(faces) + " faces");
    }
    ++ran;
  }
  if (ran == 0) GTEST_SKIP() << "corpus not present: " << dir;
  std::printf("[corpus] %zu meshes simplified and built at 200, 60 and 20 faces\n", ran);
}
