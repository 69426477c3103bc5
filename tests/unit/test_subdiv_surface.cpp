// SPDX-License-Identifier: GPL-3.0-or-later
// SubdivisionSurface: evaluation, derivatives and basis functions of the Catmull-Clark limit
// surface (thesis §2.3-2.4, spec acceptance criteria 6, 7, 9, 10, 11).
#include <gtest/gtest.h>

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyRefiner.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iostream>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/status.h"
#include "subdiv/primvar_point.h"
#include "subdiv/subdivision_surface.h"
#include "subdiv/topology_refiner_factory.h"
#include "subdiv/uniform_refinement.h"
#include "test_support.h"

namespace {

namespace Far = OpenSubdiv::Far;
using cagekit_test::status_of;
using cagekit::BasisWeights;
using cagekit::BoundaryRule;
using cagekit::Cage;
using cagekit::Error;
using cagekit::PolygonMesh;
using cagekit::Status;
using cagekit::SubdivisionSurface;
using cagekit::SurfaceOptions;
using cagekit::SurfacePoint;
using cagekit::Vec3;

// ---------------------------------------------------------------------------------------------
// Cages

Cage cage_of(PolygonMesh mesh) {
  Cage cage;
  cage.mesh = std::move(mesh);
  return cage;
}

// Two pentagons and five quads: valence-5 extraordinary points at the pentagon centres.
PolygonMesh pentagonal_prism() {
  PolygonMesh m;
  for (int z = 0; z < 2; ++z)
    for (int i = 0; i < 5; ++i) {
      const double a = 2.0 * M_PI * i / 5.0;
      m.add_vertex(Vec3(std::cos(a), std::sin(a), 1.2 * z));
    }
  m.add_face({4, 3, 2, 1, 0});
  m.add_face({5, 6, 7, 8, 9});
  for (uint32_t i = 0; i < 5; ++i) {
    const uint32_t j = (i + 1) % 5;
    m.add_face({i, j, j + 5, i + 5});
  }
  return m;
}

// A cube whose top face outline is an infinitely sharp crease loop: its corners are crease
// vertices of valence 3 (extraordinary, with sectors of one and two faces).
Cage cube_with_crease_loop() {
  Cage cage = cage_of(cagekit_test::unit_cube_quads());
  cage.creases = {{4, 5}, {5, 7}, {7, 6}, {6, 4}};
  return cage;
}

Cage fully_creased_cube() {
  Cage cage = cage_of(cagekit_test::unit_cube_quads());
  const uint32_t edges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                 {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  for (const auto& e : edges) cage.creases.push_back({e[0], e[1], cagekit::kSharpnessInfinite});
  return cage;
}

double wavy(double x, double y) { return 0.4 * std::sin(0.7 * x) * std::cos(0.5 * y) + 0.05 * x * y; }

struct NamedCage {
  std::string name;
  Cage cage;
};

std::vector<NamedCage> test_cages() {
  std::vector<NamedCage> cages;
  cages.push_back({"cube", cage_of(cagekit_test::unit_cube_quads())});
  cages.push_back({"triangle_sphere", cage_of(cagekit_test::triangle_sphere(1))});
  cages.push_back({"pentagonal_prism", cage_of(pentagonal_prism())});
  cages.push_back({"cube_crease_loop", cube_with_crease_loop()});
  Cage semi = cage_of(cagekit_test::unit_cube_quads());
  semi.creases = {{0, 1, 1.5f}, {1, 3, 2.0f}};
  semi.corners = {{6, 2.5f}};
  cages.push_back({"cube_semi_sharp", semi});
  Cage grid = cage_of(cagekit_test::quad_grid(3, 3, wavy));
  cages.push_back({"grid_edges_only", grid});
  grid.boundary = BoundaryRule::edges_and_corners;
  grid.corners = {{5, cagekit::kSharpnessInfinite}};
  cages.push_back({"grid_edges_and_corners", grid});
  Cage holed = cage_of(cagekit_test::triangle_sphere(1));
  holed.holes = {0, 5};
  cages.push_back({"sphere_with_holes", holed});
  return cages;
}

// ---------------------------------------------------------------------------------------------
// Sampling

struct Sample {
  uint32_t ptex;
  double u, v;
};

bool is_hole(const SubdivisionSurface& s, const Cage& cage, uint32_t ptex) {
  const uint32_t face = s.base_face_of_ptex(ptex);
  return std::find(cage.holes.begin(), cage.holes.end(), face) != cage.holes.end();
}

// Random samples, half of them uniform, half within [0, 0.05]^2 of a ptex corner (where
// extraordinary vertices sit), never exactly on one.
std::vector<Sample> random_samples(const SubdivisionSurface& s, const Cage& cage, int count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0), near(1e-4, 0.05);
  std::vector<Sample> samples;
  while (static_cast<int>(samples.size()) < count) {
    const uint32_t ptex = static_cast<uint32_t>(rng() % s.num_ptex_faces());
    if (is_hole(s, cage, ptex)) continue;
    double u = unit(rng), v = unit(rng);
    if (samples.size() % 2) {
      const int corner = static_cast<int>(rng() % 4);
      u = near(rng), v = near(rng);
      if (corner & 1) u = 1.0 - u;
      if (corner & 2) v = 1.0 - v;
    }
    samples.push_back({ptex, u, v});
  }
  return samples;
}

double sum(const std::vector<double>& values) {
  double total = 0;
  for (double x : values) total += x;
  return total;
}

double abs_sum(const std::vector<double>& values) {
  double total = 0;
  for (double x : values) total += std::abs(x);
  return total;
}

// ---------------------------------------------------------------------------------------------
// Basis functions

TEST(SubdivisionSurface, basis_functions_are_a_partition_of_unity_everywhere) {
  for (const NamedCage& c : test_cages()) {
    const SubdivisionSurface surface(c.cage);
    for (const Sample& p : random_samples(surface, c.cage, 400, 7)) {
      const BasisWeights b = surface.basis(p.ptex, p.u, p.v);
      ASSERT_FALSE(b.indices.empty());
      EXPECT_NEAR(sum(b.w), 1.0, 1e-12) << c.name << " ptex " << p.ptex << " at " << p.u << ", " << p.v;
      const std::vector<double>* derivatives[5] = {&b.wu, &b.wv, &b.wuu, &b.wuv, &b.wvv};
      for (const auto* d : derivatives)
        EXPECT_NEAR(sum(*d), 0.0, 1e-11 * (1.0 + abs_sum(*d))) << c.name << " ptex " << p.ptex << " at " << p.u
                                                                 << ", " << p.v;
    }
  }
}

TEST(SubdivisionSurface, basis_functions_reproduce_evaluation_and_are_linear_in_the_control_points) {
  for (const NamedCage& c : test_cages()) {
    const SubdivisionSurface surface(c.cage);
    std::vector<Vec3> moved = c.cage.mesh.positions;
    for (size_t i = 0; i < moved.size(); ++i) moved[i] += Vec3(0.01 * i, -0.02 * (i % 3), 0.5);
    for (const Sample& p : random_samples(surface, c.cage, 50, 11)) {
      const BasisWeights b = surface.basis(p.ptex, p.u, p.v);
      const SurfacePoint e = surface.evaluate(p.ptex, p.u, p.v, moved);
      const Vec3 expected[6] = {e.position, e.du, e.dv, e.duu, e.duv, e.dvv};
      const std::vector<double>* weights[6] = {&b.w, &b.wu, &b.wv, &b.wuu, &b.wuv, &b.wvv};
      for (int k = 0; k < 6; ++k) {
        Vec3 from_basis;
        double magnitude = 0;  // rounding scale (end-cap stencils cancel, hence the margin)
        for (size_t i = 0; i < b.indices.size(); ++i) {
          from_basis += moved[b.indices[i]] * (*weights[k])[i];
          magnitude += std::abs((*weights[k])[i]) * cagekit::norm(moved[b.indices[i]]);
        }
        EXPECT_NEAR(cagekit::distance(from_basis, expected[k]), 0.0, 1e-10 * (1.0 + magnitude))
            << c.name << " k=" << k;
      }
      // Affine invariance: translating the cage translates the surface, derivatives unchanged.
      const SurfacePoint original = surface.evaluate(p.ptex, p.u, p.v);
      std::vector<Vec3> shifted = c.cage.mesh.positions;
      for (Vec3& q : shifted) q += Vec3(3, -2, 1);
      const SurfacePoint translated = surface.evaluate(p.ptex, p.u, p.v, shifted);
      EXPECT_NEAR(cagekit::distance(translated.position, original.position + Vec3(3, -2, 1)), 0.0, 1e-12);
      EXPECT_NEAR(cagekit::distance(translated.du, original.du), 0.0, 1e-10 * (1.0 + cagekit::norm(original.du)));
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Regular patches are the bicubic uniform B-spline (criterion 7)

std::array<double, 4> bspline(double t, int derivative) {
  const double s = 1.0 - t;
  switch (derivative) {
    case 0: return {s * s * s / 6, (3 * t * t * t - 6 * t * t + 4) / 6, (-3 * t * t * t + 3 * t * t + 3 * t + 1) / 6, t * t * t / 6};
    case 1: return {-s * s / 2, (3 * t * t - 4 * t) / 2, (-3 * t * t + 2 * t + 1) / 2, t * t / 2};
    default: return {s, 3 * t - 2, -3 * t + 1, t};
  }
}

TEST(SubdivisionSurface, regular_patches_equal_the_bicubic_bspline) {
  const int n = 8;
  const Cage cage = cage_of(cagekit_test::quad_grid(n, n, wavy));
  const SubdivisionSurface surface(cage);
  auto vertex = [&](int i, int j) { return static_cast<uint32_t>(j * (n + 1) + i); };
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int j = 1; j + 1 < n; ++j)
    for (int i = 1; i + 1 < n; ++i) {
      const uint32_t face = static_cast<uint32_t>(j * n + i);
      const uint32_t ptex = surface.ptex_face(face);
      for (int trial = 0; trial < 6; ++trial) {
        const double u = trial == 0 ? 0.0 : unit(rng), v = trial == 0 ? 1.0 : unit(rng);
        Vec3 expected[6];
        std::map<uint32_t, std::array<double, 6>> weights;
        const int orders[6][2] = {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2}};
        for (int k = 0; k < 6; ++k) {
          const auto bu = bspline(u, orders[k][0]), bv = bspline(v, orders[k][1]);
          for (int b = 0; b < 4; ++b)
            for (int a = 0; a < 4; ++a) {
              const uint32_t id = vertex(i - 1 + a, j - 1 + b);
              expected[k] += cage.mesh.positions[id] * (bu[a] * bv[b]);
              weights[id][k] += bu[a] * bv[b];
            }
        }
        const SurfacePoint p = surface.evaluate(ptex, u, v);
        const Vec3 got[6] = {p.position, p.du, p.dv, p.duu, p.duv, p.dvv};
        for (int k = 0; k < 6; ++k)
          EXPECT_NEAR(cagekit::distance(got[k], expected[k]), 0.0, 1e-12 * (1.0 + cagekit::norm(expected[k])))
              << "face " << face << " k=" << k;
        const BasisWeights b = surface.basis(ptex, u, v);
        for (size_t m = 0; m < b.indices.size(); ++m) {
          const auto it = weights.find(b.indices[m]);
          const std::array<double, 6> want = it == weights.end() ? std::array<double, 6>{} : it->second;
          const double got_w[6] = {b.w[m], b.wu[m], b.wv[m], b.wuu[m], b.wuv[m], b.wvv[m]};
          for (int k = 0; k < 6; ++k) EXPECT_NEAR(got_w[k], want[k], 1e-13);
        }
      }
    }
}

// The limit curve of a crease through regular vertices is the uniform cubic B-spline of the
// crease's control points (criterion 8), and infinitely sharp patches make it exact.
TEST(SubdivisionSurface, crease_curves_are_exact_cubic_bsplines) {
  const int n = 6;
  Cage cage = cage_of(cagekit_test::quad_grid(n, n, wavy));
  auto vertex = [&](int i, int j) { return static_cast<uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j) cage.creases.push_back({vertex(3, j), vertex(3, j + 1), cagekit::kSharpnessInfinite});
  const SubdivisionSurface surface(cage);
  for (int j = 1; j + 1 < n; ++j) {
    const uint32_t left = surface.ptex_face(static_cast<uint32_t>(j * n + 2));  // crease at its u = 1
    const uint32_t right = surface.ptex_face(static_cast<uint32_t>(j * n + 3));  // crease at its u = 0
    for (double t : {0.0, 0.125, 0.3, 0.5, 0.77, 1.0}) {
      Vec3 expected, expected_dt;
      const auto b = bspline(t, 0), db = bspline(t, 1);
      for (int a = 0; a < 4; ++a) {
        expected += cage.mesh.positions[vertex(3, j - 1 + a)] * b[a];
        expected_dt += cage.mesh.positions[vertex(3, j - 1 + a)] * db[a];
      }
      const SurfacePoint l = surface.evaluate(left, 1.0, t), r = surface.evaluate(right, 0.0, t);
      EXPECT_NEAR(cagekit::distance(l.position, expected), 0.0, 1e-12);
      EXPECT_NEAR(cagekit::distance(r.position, expected), 0.0, 1e-12);
      EXPECT_NEAR(cagekit::distance(l.dv, expected_dt), 0.0, 1e-12);
      EXPECT_NEAR(cagekit::distance(r.dv, expected_dt), 0.0, 1e-12);
    }
  }
  // The fully creased cube: its patch boundaries are the straight cube edges.
  const Cage cube = fully_creased_cube();
  const SubdivisionSurface cube_surface(cube);
  for (uint32_t ptex = 0; ptex < 6; ++ptex)
    for (double t : {0.0, 0.1, 0.25, 0.5, 0.9, 1.0})
      for (const auto& uv : {std::array<double, 2>{t, 0.0}, {1.0, t}, {t, 1.0}, {0.0, t}}) {
        const Vec3 p = cube_surface.evaluate(ptex, uv[0], uv[1]).position;
        int on_faces = 0;
        for (int k = 0; k < 3; ++k) on_faces += std::abs(p[k]) < 1e-12 || std::abs(p[k] - 1.0) < 1e-12;
        EXPECT_GE(on_faces, 2) << "ptex " << ptex << " (" << uv[0] << ", " << uv[1] << ")";
      }
}

// ---------------------------------------------------------------------------------------------
// Derivatives against central differences (criterion 10)

bool straddles_dyadic_line(double t, double h, int level) {
  const double scale = std::ldexp(1.0, level + 1);  // ptex sub-faces sit one level deeper
  return std::floor((t - h) * scale) != std::floor((t + h) * scale);
}

TEST(SubdivisionSurface, derivatives_match_central_differences) {
  for (const NamedCage& c : test_cages()) {
    const SubdivisionSurface surface(c.cage);
    int checked = 0;
    for (const Sample& p : random_samples(surface, c.cage, 300, 5)) {
      // A step small against the distance to the patch corners, so that near extraordinary
      // vertices the differences stay inside one patch of the adaptive hierarchy.
      const double margin = std::min({p.u, p.v, 1.0 - p.u, 1.0 - p.v});
      if (margin < 2e-3) continue;
      const double h = 1e-4 * margin;
      if (straddles_dyadic_line(p.u, h, 6) || straddles_dyadic_line(p.v, h, 6)) continue;
      const SurfacePoint at = surface.evaluate(p.ptex, p.u, p.v);
      const SurfacePoint up = surface.evaluate(p.ptex, p.u + h, p.v), um = surface.evaluate(p.ptex, p.u - h, p.v);
      const SurfacePoint vp = surface.evaluate(p.ptex, p.u, p.v + h), vm = surface.evaluate(p.ptex, p.u, p.v - h);
      const double scale = 1.0 + cagekit::norm(at.du) + cagekit::norm(at.dv);
      const double scale2 = scale + cagekit::norm(at.duu) + cagekit::norm(at.duv) + cagekit::norm(at.dvv);
      auto check = [&](const Vec3& fd, const Vec3& exact, double s, const char* what) {
        EXPECT_LT(cagekit::distance(fd, exact), 1e-6 * s)
            << c.name << " " << what << " ptex " << p.ptex << " at " << p.u << ", " << p.v;
      };
      check((up.position - um.position) * (0.5 / h), at.du, scale, "du");
      check((vp.position - vm.position) * (0.5 / h), at.dv, scale, "dv");
      check((up.du - um.du) * (0.5 / h), at.duu, scale2, "duu");
      check((vp.du - vm.du) * (0.5 / h), at.duv, scale2, "duv (from du)");
      check((up.dv - um.dv) * (0.5 / h), at.duv, scale2, "duv (from dv)");
      check((vp.dv - vm.dv) * (0.5 / h), at.dvv, scale2, "dvv");
      ++checked;
    }
    EXPECT_GT(checked, 200) << c.name;
  }
}

// ---------------------------------------------------------------------------------------------
// Reference: uniform refinement to level K with Far, pushed to the limit. Every vertex of level
// K is an exact point of the limit surface and sits at a dyadic (u, v) of a ptex face.

struct LimitReference {
  std::vector<Vec3> limit;          // limit positions of the level-K vertices
  std::vector<Sample> samples;      // (ptex, u, v) of level-K vertices, one per occurrence
  std::vector<int> sample_vertex;   // the level-K vertex of each sample
  std::vector<double> ev_distance;  // per sample: ptex-parameter distance to an extraordinary corner
};

struct Cell {
  int face;           // at the current level
  double uv[4][2];    // ptex coordinates of the face's vertices, in the face's order
};

std::vector<Cell> child_cells(const Far::TopologyRefiner& r, int level, const Cell& cell) {
  const Far::TopologyLevel& parent = r.GetLevel(level);
  const Far::TopologyLevel& child = r.GetLevel(level + 1);
  const auto fv = parent.GetFaceVertices(cell.face);
  const auto fe = parent.GetFaceEdges(cell.face);
  std::vector<std::pair<int, std::array<double, 2>>> known;
  std::array<double, 2> centre{0, 0};
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    known.push_back({parent.GetVertexChildVertex(fv[i]), {cell.uv[i][0], cell.uv[i][1]}});
    known.push_back({parent.GetEdgeChildVertex(fe[i]),
                     {0.5 * (cell.uv[i][0] + cell.uv[j][0]), 0.5 * (cell.uv[i][1] + cell.uv[j][1])}});
    centre[0] += 0.25 * cell.uv[i][0];
    centre[1] += 0.25 * cell.uv[i][1];
  }
  known.push_back({parent.GetFaceChildVertex(cell.face), centre});
  std::vector<Cell> cells;
  for (int c : parent.GetFaceChildFaces(cell.face)) {
    Cell out{c, {}};
    const auto cv = child.GetFaceVertices(c);
    for (int i = 0; i < 4; ++i) {
      const auto it = std::find_if(known.begin(), known.end(), [&](const auto& k) { return k.first == cv[i]; });
      EXPECT_NE(it, known.end());
      out.uv[i][0] = it->second[0];
      out.uv[i][1] = it->second[1];
    }
    cells.push_back(out);
  }
  return cells;
}

// With corner_square > 0 only the cells within that ptex-parameter distance of an
// extraordinary corner are refined (and their vertices sampled).
LimitReference limit_reference(const Cage& cage, const SubdivisionSurface& surface, int levels,
                               double corner_square = 0) {
  auto refiner = cagekit::subdiv_detail::create_topology_refiner(cage);
  Far::TopologyRefiner::UniformOptions options(levels);
  options.fullTopologyInLastLevel = true;
  refiner->RefineUniform(options);
  const Far::TopologyRefiner& r = *refiner;

  using cagekit::subdiv_detail::PrimvarPoint;
  std::vector<PrimvarPoint> coarse = cagekit::subdiv_detail::to_primvar(cage.mesh.positions), fine;
  Far::PrimvarRefinerReal<double> primvar(r);
  for (int level = 1; level <= levels; ++level) {
    fine.assign(r.GetLevel(level).GetNumVertices(), PrimvarPoint());
    primvar.Interpolate(level, coarse, fine);
    coarse.swap(fine);
  }
  fine.assign(coarse.size(), PrimvarPoint());
  primvar.Limit(coarse, fine);
  LimitReference ref;
  for (const PrimvarPoint& p : fine) ref.limit.push_back(p.p);

  const Far::TopologyLevel& base = r.GetLevel(0);
  const Far::TopologyLevel& level1 = r.GetLevel(1);
  auto extraordinary = [&](int v) { return !base.IsVertexValenceRegular(v); };
  for (uint32_t f = 0; f < cage.mesh.num_faces(); ++f) {
    if (std::find(cage.holes.begin(), cage.holes.end(), f) != cage.holes.end()) continue;
    const auto fv = base.GetFaceVertices(static_cast<int>(f));
    const auto fe = base.GetFaceEdges(static_cast<int>(f));
    const int n = fv.size();
    // Per ptex face: its level-0 or level-1 cell, and which of its corners are extraordinary.
    std::vector<std::pair<int, Cell>> roots;  // (start level, cell)
    std::vector<std::array<bool, 4>> ev_corner;
    if (n == 4) {
      roots.push_back({0, Cell{static_cast<int>(f), {{0, 0}, {1, 0}, {1, 1}, {0, 1}}}});
      ev_corner.push_back({extraordinary(fv[0]), extraordinary(fv[1]), extraordinary(fv[2]), extraordinary(fv[3])});
    } else {
      for (int k = 0; k < n; ++k) {
        const int corner = base.GetVertexChildVertex(fv[k]);
        const int next_edge = base.GetEdgeChildVertex(fe[k]);
        const int prev_edge = base.GetEdgeChildVertex(fe[(k + n - 1) % n]);
        const int centre = base.GetFaceChildVertex(static_cast<int>(f));
        for (int c : base.GetFaceChildFaces(static_cast<int>(f))) {
          const auto cv = level1.GetFaceVertices(c);
          if (std::find(cv.begin(), cv.end(), corner) == cv.end()) continue;
          Cell cell{c, {}};
          for (int i = 0; i < 4; ++i) {
            const double u = (cv[i] == next_edge || cv[i] == centre) ? 1.0 : 0.0;
            const double v = (cv[i] == prev_edge || cv[i] == centre) ? 1.0 : 0.0;
            cell.uv[i][0] = u;
            cell.uv[i][1] = v;
          }
          roots.push_back({1, cell});
          // (0,0) is the cage vertex, (1,1) the face centre (valence n != 4).
          ev_corner.push_back({extraordinary(fv[k]), false, true, false});
        }
      }
    }
    for (size_t k = 0; k < roots.size(); ++k) {
      const uint32_t ptex = surface.ptex_face(f, static_cast<uint32_t>(n == 4 ? 0 : k));
      std::vector<Cell> cells{roots[k].second};
      for (int level = roots[k].first; level < levels; ++level) {
        std::vector<Cell> next;
        for (const Cell& c : cells)
          for (const Cell& child : child_cells(r, level, c)) {
            if (corner_square > 0) {
              const double corners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
              bool near = false;
              for (int i = 0; i < 4; ++i) {
                if (!ev_corner[k][i]) continue;
                double d = 1e300;  // distance of the cell's nearest vertex from the corner
                for (int j = 0; j < 4; ++j)
                  d = std::min(d, std::max(std::abs(child.uv[j][0] - corners[i][0]),
                                           std::abs(child.uv[j][1] - corners[i][1])));
                near = near || d < corner_square;
              }
              if (!near) continue;
            }
            next.push_back(child);
          }
        cells.swap(next);
      }
      std::map<int, std::array<double, 2>> seen;
      const Far::TopologyLevel& last = r.GetLevel(levels);
      for (const Cell& c : cells) {
        const auto cv = last.GetFaceVertices(c.face);
        for (int i = 0; i < 4; ++i) seen[cv[i]] = {c.uv[i][0], c.uv[i][1]};
      }
      const double corners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
      for (const auto& [vertex, uv] : seen) {
        double d = 1e300;
        for (int i = 0; i < 4; ++i)
          if (ev_corner[k][i])
            d = std::min(d, std::max(std::abs(uv[0] - corners[i][0]), std::abs(uv[1] - corners[i][1])));
        if (corner_square > 0 && d > corner_square) continue;
        ref.samples.push_back({ptex, uv[0], uv[1]});
        ref.sample_vertex.push_back(vertex);
        ref.ev_distance.push_back(d);
      }
    }
  }
  return ref;
}

struct Deviation {
  double all = 0, near_ev = 0, at_ev = 0;
  size_t count = 0, near_count = 0;
};

Deviation deviation_from_limit(const Cage& cage, const SurfaceOptions& options, int levels,
                               double corner_square = 0) {
  const SubdivisionSurface surface(cage, options);
  const LimitReference ref = limit_reference(cage, surface, levels, corner_square);
  Deviation d;
  for (size_t i = 0; i < ref.samples.size(); ++i) {
    const Sample& s = ref.samples[i];
    const double e = cagekit::distance(surface.evaluate(s.ptex, s.u, s.v).position, ref.limit[ref.sample_vertex[i]]);
    d.all = std::max(d.all, e);
    ++d.count;
    if (ref.ev_distance[i] == 0) d.at_ev = std::max(d.at_ev, e);
    if (ref.ev_distance[i] > 0 && ref.ev_distance[i] <= 0.125) {
      d.near_ev = std::max(d.near_ev, e);
      ++d.near_count;
    }
  }
  const double diagonal = cage.mesh.bounding_box().diagonal();
  d.all /= diagonal;
  d.near_ev /= diagonal;
  d.at_ev /= diagonal;
  return d;
}

std::vector<NamedCage> extraordinary_cages() {
  std::vector<NamedCage> cages;
  cages.push_back({"cube (valence 3)", cage_of(cagekit_test::unit_cube_quads())});
  cages.push_back({"pentagonal prism (valence 3, 5)", cage_of(pentagonal_prism())});
  cages.push_back({"triangle sphere (valence 3, 4, 6)", cage_of(cagekit_test::triangle_sphere(1))});
  cages.push_back({"cube with crease loop (crease valence 3)", cube_with_crease_loop()});
  Cage grid = cage_of(cagekit_test::quad_grid(3, 3, wavy));
  grid.holes = {4};
  cages.push_back({"grid with boundary and hole", grid});
  return cages;
}

// With refinement depth <= isolation level, every level-K vertex is a corner or an edge point
// of a regular (B-spline) patch or a corner of an end cap: evaluation must be exact there.
// Smooth extraordinary vertices are exact at any depth (Stam patches, default isolation);
// crease/boundary ones are exact at these points with isolation 6 (Gregory end caps below).
TEST(SubdivisionSurface, agrees_with_deep_refinement_limit_points_near_extraordinary_vertices) {
  for (const NamedCage& c : extraordinary_cages()) {
    SurfaceOptions options;
    if (!c.cage.creases.empty() || !c.cage.holes.empty()) options.isolation_level = 6;
    const int levels = c.cage.mesh.all_faces_have_size(4) ? 6 : 5;
    const Deviation d = deviation_from_limit(c.cage, options, levels);
    std::cout << c.name << ": level " << levels << ", " << d.count << " points, max deviation / bbox diagonal "
              << d.all << " (near EVs " << d.near_ev << ", " << d.near_count << " points; at EVs " << d.at_ev
              << ")\n";
    if (c.name.find("valence") != std::string::npos) {
      EXPECT_GT(d.near_count, 0u) << c.name;
    }
    EXPECT_LT(d.all, 1e-6) << c.name;
    EXPECT_LT(d.near_ev, 1e-6) << c.name;
    EXPECT_LT(d.at_ev, 1e-12) << c.name;
  }
}

// Inside the Stam patches of smooth interior extraordinary vertices (valence 3, 5, 6): exact
// limit points of deep refinement levels at dyadic points within the end-cap squares, and
// derivatives against central differences and the partition of unity there.
TEST(SubdivisionSurface, stam_patches_are_exact_near_smooth_extraordinary_vertices) {
  struct Case {
    NamedCage cage;
    int levels;
  };
  std::vector<Case> cases;
  cases.push_back({{"cube (valence 3)", cage_of(cagekit_test::unit_cube_quads())}, 7});
  cases.push_back({{"pentagonal prism (valence 3, 5)", cage_of(pentagonal_prism())}, 6});
  cases.push_back({{"triangle sphere (valence 3, 4, 6)", cage_of(cagekit_test::triangle_sphere(1))}, 6});
  for (const Case& k : cases) {
    const Cage& cage = k.cage.cage;
    // The Stam squares: 2^-2 of a quad's ptex face, 2^-1 of an n-gon's sub-face.
    const double square = cage.mesh.all_faces_have_size(4) ? 0.25 : 0.5;
    const Deviation d = deviation_from_limit(cage, SurfaceOptions(), k.levels, square);
    std::cout << k.cage.name << ": level " << k.levels << ", " << d.count << " points in the Stam squares, max "
              << "deviation / bbox diagonal " << d.all << " (not at EVs " << d.near_ev << ", at EVs " << d.at_ev
              << ")\n";
    EXPECT_GT(d.near_count, 500u) << k.cage.name;
    EXPECT_LT(d.all, 1e-6) << k.cage.name;

    const SubdivisionSurface surface(cage);
    std::mt19937 rng(21);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    double worst_fd = 0;
    for (int trial = 0; trial < 300; ++trial) {
      const uint32_t ptex = static_cast<uint32_t>(rng() % surface.num_ptex_faces());
      // Near corner (0,0) (a cage vertex), at distances down to 2^-20 of the square.
      const double scale = square * std::ldexp(1.0, -static_cast<int>(rng() % 20));
      const double u = scale * (0.05 + 0.9 * unit(rng)), v = scale * (0.05 + 0.9 * unit(rng));
      const BasisWeights b = surface.basis(ptex, u, v);
      EXPECT_NEAR(sum(b.w), 1.0, 1e-12);
      for (const auto* w : {&b.wu, &b.wv, &b.wuu, &b.wuv, &b.wvv})
        EXPECT_NEAR(sum(*w), 0.0, 1e-11 * (1.0 + abs_sum(*w)));
      // Central differences lose digits to rounding close to the EV (positions ~1, steps tiny):
      // they are checked down to 2^-10 of the square, the partition of unity down to 2^-20.
      if (scale < square * std::ldexp(1.0, -10)) continue;
      const double h = 2e-4 * std::min(u, v);
      const SurfacePoint at = surface.evaluate(ptex, u, v);
      const SurfacePoint up = surface.evaluate(ptex, u + h, v), um = surface.evaluate(ptex, u - h, v);
      const SurfacePoint vp = surface.evaluate(ptex, u, v + h), vm = surface.evaluate(ptex, u, v - h);
      const double s1 = cagekit::norm(at.du) + cagekit::norm(at.dv);
      const double s2 = cagekit::norm(at.duu) + cagekit::norm(at.duv) + cagekit::norm(at.dvv);
      // A dyadic line between u - h and u + h changes the subdivision level: still C2 there.
      const double e1 = std::max(cagekit::distance((up.position - um.position) * (0.5 / h), at.du),
                                 cagekit::distance((vp.position - vm.position) * (0.5 / h), at.dv)) / s1;
      const double e2 = std::max({cagekit::distance((up.du - um.du) * (0.5 / h), at.duu),
                                  cagekit::distance((vp.du - vm.du) * (0.5 / h), at.duv),
                                  cagekit::distance((vp.dv - vm.dv) * (0.5 / h), at.dvv)}) / (s1 / scale + s2);
      worst_fd = std::max({worst_fd, e1, e2});
      EXPECT_LT(e1, 1e-6) << k.cage.name << " ptex " << ptex << " at " << u << ", " << v;
      EXPECT_LT(e2, 1e-5) << k.cage.name << " ptex " << ptex << " at " << u << ", " << v;
    }
    std::cout << k.cage.name << ": worst relative central-difference error of the derivatives " << worst_fd << "\n";
  }
}

// Crease and boundary extraordinary vertices keep OpenSubdiv's Gregory end caps: the deviation
// inside them is measured (for the README) at the default isolation level, one and two levels
// below it.
TEST(SubdivisionSurface, gregory_end_caps_at_crease_and_boundary_extraordinary_vertices_are_measured) {
  std::vector<NamedCage> cages;
  cages.push_back({"cube with crease loop (crease valence 3)", cube_with_crease_loop()});
  Cage grid = cage_of(cagekit_test::quad_grid(3, 3, wavy));
  grid.holes = {4};
  cages.push_back({"grid with boundary and hole", grid});
  Cage open_box = cage_of(cagekit_test::unit_cube_quads());
  open_box.holes = {0};
  cages.push_back({"cube with a hole (boundary valence 3)", open_box});
  for (const NamedCage& c : cages) {
    // The deviation inside the Gregory end caps at low isolation levels of the region around
    // the crease/boundary extraordinary vertices (measured at the dyadic points of level 5):
    // it shrinks by a roughly constant factor per level.
    double previous = 0;
    for (int region_level : {2, 3, 4}) {
      SurfaceOptions options;
      options.sharp_extraordinary_isolation_level = region_level;
      const Deviation d = deviation_from_limit(c.cage, options, 5);
      std::cout << c.name << ": region isolation " << region_level << ", level-5 points, max deviation / bbox diagonal "
                << d.all;
      if (previous > 0) std::cout << " (x" << d.all / previous << " per level)";
      std::cout << "\n";
      EXPECT_LT(d.all, 1e-2) << c.name;  // a sanity bound only
      previous = d.all;
    }
    // The default isolates the region to level 10: every point of dyadic level <= 10 near such
    // a vertex is on an exact patch, so the level-5 points agree with the limit to rounding.
    const Deviation d = deviation_from_limit(c.cage, SurfaceOptions(), 5);
    std::cout << c.name << ": default (region isolation 10), level-5 points: " << d.all << "\n";
    EXPECT_LT(d.all, 1e-6) << c.name;
  }
}

// Positions agree with OpenSubdiv's own Bfr evaluation (an independent code path through the
// same B-spline patches and Gregory end caps, at the same approximation levels), which checks
// CageKit's patch bases against OpenSubdiv's. Inside the Stam patches of smooth interior
// extraordinary vertices CageKit is exact and Bfr is a Gregory approximation, so samples there
// (the corner squares of side 2^-L of a quad's ptex face, 2^-(L-1) of an n-gon's sub-face, at
// such vertices; semi-sharp vertices count as smooth) are left out.
bool in_smooth_ev_corner(const SubdivisionSurface& s, const Cage& cage, const Sample& p, int isolation) {
  const uint32_t face = s.base_face_of_ptex(p.ptex);
  const uint32_t n = cage.mesh.face_size(face);
  auto smooth_ev = [&](uint32_t vertex) {
    uint32_t valence = 0;
    for (size_t f = 0; f < cage.mesh.num_faces(); ++f)
      for (uint32_t k = 0; k < cage.mesh.face_size(f); ++k) valence += cage.mesh.face_vertex(f, k) == vertex;
    for (const auto& c : cage.creases)
      if ((c.v0 == vertex || c.v1 == vertex) && c.sharpness >= cagekit::kSharpnessInfinite) return false;
    for (const auto& c : cage.corners)
      if (c.vertex == vertex && c.sharpness >= cagekit::kSharpnessInfinite) return false;
    // Boundary vertices: some edge of theirs is used by one face only.
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (size_t f = 0; f < cage.mesh.num_faces(); ++f)
      for (uint32_t k = 0, m = cage.mesh.face_size(f); k < m; ++k) {
        const uint32_t a = cage.mesh.face_vertex(f, k), b = cage.mesh.face_vertex(f, (k + 1) % m);
        if (a == vertex || b == vertex) ++edges[{std::min(a, b), std::max(a, b)}];
      }
    for (const auto& [edge, count] : edges)
      if (count != 2) return false;
    return valence != 4;
  };
  const double side = std::ldexp(1.0, n == 4 ? -isolation : 1 - isolation);
  const double corners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int i = 0; i < 4; ++i) {
    if (std::max(std::abs(p.u - corners[i][0]), std::abs(p.v - corners[i][1])) >= side) continue;
    if (n != 4) {
      if (i == 2) return true;  // the face centre
      if (i == 0 && smooth_ev(cage.mesh.face_vertex(face, p.ptex - s.ptex_face(face)))) return true;
      continue;
    }
    if (smooth_ev(cage.mesh.face_vertex(face, i))) return true;
  }
  return false;
}

// OpenSubdiv Bfr's position at CageKit's sample p (ptex face, u, v) of `cage` (a face's
// sub-face parameters converted to Bfr's), or false when Bfr has no surface there.
bool bfr_position(const OpenSubdiv::Bfr::RefinerSurfaceFactory<>& factory, const SubdivisionSurface& surface,
                  const Cage& cage, const Sample& p, Vec3* out) {
  const uint32_t face = surface.base_face_of_ptex(p.ptex);
  OpenSubdiv::Bfr::Surface<double> bfr;
  if (!factory.InitVertexSurface(static_cast<int>(face), &bfr)) return false;
  double uv[2] = {p.u, p.v};
  const auto param = bfr.GetParameterization();
  if (param.HasSubFaces()) {
    const double sub[2] = {p.u, p.v};
    param.ConvertNormalizedSubFaceToCoord<double>(static_cast<int>(p.ptex - surface.ptex_face(face)), sub, uv);
  }
  std::vector<double> points(3 * static_cast<size_t>(bfr.GetNumPatchPoints()));
  bfr.PreparePatchPoints(&cage.mesh.positions[0].x, 3, points.data(), 3);
  double position[3];
  bfr.Evaluate(uv, points.data(), 3, position);
  *out = Vec3(position[0], position[1], position[2]);
  return true;
}

TEST(SubdivisionSurface, positions_agree_with_opensubdiv_bfr) {
  for (const NamedCage& c : test_cages()) {
    // Bfr approximates every irregular feature at one level: compare with the crease/boundary
    // region isolated to the same level (the default isolates it deeper, see above).
    SurfaceOptions defaults;
    defaults.sharp_extraordinary_isolation_level = defaults.isolation_level;
    const SubdivisionSurface surface(c.cage, defaults);
    auto refiner = cagekit::subdiv_detail::create_topology_refiner(c.cage);
    float finite_max = 0;  // CageKit isolates semi-sharp features to ceil(sharpness) levels
    for (const auto& e : c.cage.creases)
      if (e.sharpness < cagekit::kSharpnessInfinite) finite_max = std::max(finite_max, e.sharpness);
    for (const auto& e : c.cage.corners)
      if (e.sharpness < cagekit::kSharpnessInfinite) finite_max = std::max(finite_max, e.sharpness);
    OpenSubdiv::Bfr::RefinerSurfaceFactory<>::Options options;
    options.SetApproxLevelSmooth(defaults.isolation_level)
        .SetApproxLevelSharp(std::max(defaults.isolation_level, static_cast<int>(std::ceil(finite_max))));
    const OpenSubdiv::Bfr::RefinerSurfaceFactory<> factory(*refiner, options);
    double max_gap = 0;
    int compared = 0;
    for (const Sample& p : random_samples(surface, c.cage, 300, 13)) {
      if (in_smooth_ev_corner(surface, c.cage, p, defaults.isolation_level)) continue;
      ++compared;
      Vec3 reference;
      ASSERT_TRUE(bfr_position(factory, surface, c.cage, p, &reference));
      max_gap = std::max(max_gap, cagekit::distance(surface.evaluate(p.ptex, p.u, p.v).position, reference));
    }
    EXPECT_LT(max_gap, 1e-12) << c.name;
    EXPECT_GT(compared, 100) << c.name;
  }
}

// Many end-cap faces (a triangle sphere with a third of its edges creased): the Gregory region
// is built as two sub-cages (on two threads when asked). Same positions as OpenSubdiv's Bfr at
// the same approximation level, and the same bits with 1 or 2 build threads.
TEST(SubdivisionSurface, split_gregory_region_agrees_with_bfr_and_ignores_threads) {
  Cage cage = cage_of(cagekit_test::triangle_sphere(2));
  for (size_t f = 0; f < cage.mesh.num_faces(); ++f)
    for (uint32_t k = 0; k < 3; ++k) {
      const uint32_t a = cage.mesh.face_vertex(f, k), b = cage.mesh.face_vertex(f, (k + 1) % 3);
      if (a < b && (a + b) % 3 == 0) cage.creases.push_back({a, b, cagekit::kSharpnessInfinite});
    }
  SurfaceOptions one, two;
  one.sharp_extraordinary_isolation_level = two.sharp_extraordinary_isolation_level = one.isolation_level;
  two.threads = 2;
  const SubdivisionSurface s1(cage, one), s2(cage, two);
  auto refiner = cagekit::subdiv_detail::create_topology_refiner(cage);
  OpenSubdiv::Bfr::RefinerSurfaceFactory<>::Options options;
  options.SetApproxLevelSmooth(one.isolation_level).SetApproxLevelSharp(one.isolation_level);
  const OpenSubdiv::Bfr::RefinerSurfaceFactory<> factory(*refiner, options);
  double max_gap = 0;
  int compared = 0;
  for (const Sample& p : random_samples(s1, cage, 400, 17)) {
    const SurfacePoint a = s1.evaluate(p.ptex, p.u, p.v), b = s2.evaluate(p.ptex, p.u, p.v);
    ASSERT_TRUE(a.position.x == b.position.x && a.position.y == b.position.y && a.position.z == b.position.z &&
                a.du.x == b.du.x && a.dv.z == b.dv.z);
    if (in_smooth_ev_corner(s1, cage, p, one.isolation_level)) continue;
    Vec3 reference;
    ASSERT_TRUE(bfr_position(factory, s1, cage, p, &reference));
    max_gap = std::max(max_gap, cagekit::distance(a.position, reference));
    ++compared;
  }
  std::cout << cage.creases.size() << " creases: " << compared << " samples, max gap to Bfr " << max_gap << "\n";
  EXPECT_LT(max_gap, 1e-12);
  EXPECT_GT(compared, 100);
}

// ---------------------------------------------------------------------------------------------
// Continuity across ptex edges (criterion 10), from the shared level-K vertices

// With isolation 6 all level-4 points lie on regular patch edges (normals must agree too); with
// isolation 2 many lie on Gregory end caps, which are watertight with matching edge curves but
// only approximately G1: their normal gap is measured.
TEST(SubdivisionSurface, continuous_across_ptex_edges_with_matching_edge_tangents) {
  for (int isolation : {6, 2})
  for (const NamedCage& c : extraordinary_cages()) {
    SurfaceOptions options;
    options.isolation_level = isolation;
    const SubdivisionSurface surface(c.cage, options);
    const int levels = 4;
    const LimitReference ref = limit_reference(c.cage, surface, levels);
    std::map<int, std::vector<size_t>> occurrences;  // level-K vertex -> its samples
    for (size_t i = 0; i < ref.samples.size(); ++i) occurrences[ref.sample_vertex[i]].push_back(i);
    double max_gap = 0, max_tangent_gap = 0, max_normal_gap = 0;
    size_t pairs = 0;
    for (const auto& [vertex, list] : occurrences)
      for (size_t a = 0; a < list.size(); ++a)
        for (size_t b = a + 1; b < list.size(); ++b) {
          const Sample& p = ref.samples[list[a]];
          const Sample& q = ref.samples[list[b]];
          const SurfacePoint sp = surface.evaluate(p.ptex, p.u, p.v), sq = surface.evaluate(q.ptex, q.u, q.v);
          max_gap = std::max(max_gap, cagekit::distance(sp.position, sq.position));
          ++pairs;
          if (c.cage.creases.empty())  // creases have a normal per side
            max_normal_gap = std::max(max_normal_gap, cagekit::distance(cagekit::normalized(cagekit::cross(sp.du, sp.dv)),
                                                                        cagekit::normalized(cagekit::cross(sq.du, sq.dv))));
          // The tangent along the shared ptex edge: step to the next shared point on that edge.
          const bool p_on_u_edge = p.v == 0.0 || p.v == 1.0, p_on_v_edge = p.u == 0.0 || p.u == 1.0;
          if (p_on_u_edge == p_on_v_edge) continue;  // a ptex corner: no single shared edge
          const double step = 1.0 / 1024;
          // Midpoint between this vertex and the next along p's edge, evaluated from both sides
          // through the affine map of the shared edge (found by evaluation of positions).
          const double pu2 = p_on_u_edge ? std::min(1.0, p.u + step) : p.u;
          const double pv2 = p_on_v_edge ? std::min(1.0, p.v + step) : p.v;
          if (pu2 == p.u && pv2 == p.v) continue;
          const Vec3 target = surface.evaluate(p.ptex, pu2, pv2).position;
          const bool q_on_u_edge = q.v == 0.0 || q.v == 1.0;
          double best = 1e300, best_t = 0;
          for (double dir : {-1.0, 1.0})
            for (double scale : {0.5, 1.0, 2.0}) {
              const double t = (q_on_u_edge ? q.u : q.v) + dir * scale * step;
              if (t < 0 || t > 1) continue;
              const Vec3 x = surface.evaluate(q.ptex, q_on_u_edge ? t : q.u, q_on_u_edge ? q.v : t).position;
              if (cagekit::distance(x, target) < best) {
                best = cagekit::distance(x, target);
                best_t = dir * scale * step;
              }
            }
          max_gap = std::max(max_gap, best);
          const Vec3 tp = (p_on_u_edge ? sp.du : sp.dv) * step;
          const Vec3 tq = (q_on_u_edge ? sq.du : sq.dv) * best_t;
          max_tangent_gap = std::max(max_tangent_gap, cagekit::distance(tp, tq) / step);
        }
    std::cout << c.name << ", isolation " << isolation << ": " << pairs << " shared points, max position gap "
              << max_gap << ", max edge-tangent gap " << max_tangent_gap << ", max normal gap " << max_normal_gap
              << "\n";
    EXPECT_GT(pairs, 100u);
    EXPECT_LT(max_gap, 1e-9) << c.name;
    EXPECT_LT(max_tangent_gap, 1e-9) << c.name;
    EXPECT_LT(max_normal_gap, isolation == 6 ? 1e-9 : 0.1) << c.name;
  }
}

// ---------------------------------------------------------------------------------------------
// Parameterisation, errors, thread safety

TEST(SubdivisionSurface, ptex_faces_split_non_quads_per_corner) {
  const Cage prism = cage_of(pentagonal_prism());
  const SubdivisionSurface surface(prism);
  EXPECT_EQ(surface.num_control_vertices(), 10u);
  EXPECT_EQ(surface.num_ptex_faces(), 5u + 5u + 5u);
  std::vector<int> seen(surface.num_ptex_faces(), 0);
  for (uint32_t f = 0; f < 7; ++f) {
    const uint32_t corners = prism.mesh.face_size(f) == 4 ? 1 : prism.mesh.face_size(f);
    for (uint32_t k = 0; k < corners; ++k) {
      const uint32_t ptex = surface.ptex_face(f, k);
      EXPECT_EQ(surface.base_face_of_ptex(ptex), f);
      ++seen[ptex];
    }
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), 15);
  // Sub-face k of an n-gon has (0,0) at corner k (the limit point of that vertex), (1,0) at the
  // midpoint of edge k, (0,1) at the midpoint of edge k-1, and (1,1) at the face centre.
  std::vector<Vec3> limit;
  cagekit::limit_positions_and_normals(prism, &limit, nullptr);
  const Vec3 centre = surface.evaluate(surface.ptex_face(0, 0), 1, 1).position;
  for (uint32_t k = 0; k < 5; ++k) {
    const uint32_t ptex = surface.ptex_face(0, k), next = surface.ptex_face(0, (k + 1) % 5);
    EXPECT_NEAR(cagekit::distance(surface.evaluate(ptex, 0, 0).position, limit[prism.mesh.face_vertex(0, k)]), 0, 1e-14);
    EXPECT_NEAR(cagekit::distance(surface.evaluate(ptex, 1, 1).position, centre), 0, 1e-14);
    for (double t : {0.0, 0.3, 1.0})
      EXPECT_NEAR(cagekit::distance(surface.evaluate(ptex, 1, t).position, surface.evaluate(next, t, 1).position), 0,
                  1e-14);
  }
}

TEST(SubdivisionSurface, invalid_queries_and_cages_throw) {
  Cage cage = cage_of(cagekit_test::unit_cube_quads());
  cage.holes = {2};
  const SubdivisionSurface surface(cage);
  EXPECT_EQ(status_of([&] { surface.evaluate(6, 0.5, 0.5); }), Status::invalid_argument);
  EXPECT_EQ(status_of([&] { surface.evaluate(0, -0.1, 0.5); }), Status::invalid_argument);
  EXPECT_EQ(status_of([&] { surface.evaluate(0, 0.5, std::nan("")); }), Status::invalid_argument);
  EXPECT_EQ(status_of([&] { surface.evaluate(2, 0.5, 0.5); }), Status::invalid_argument);  // the hole
  EXPECT_EQ(status_of([&] { surface.basis(2, 0.5, 0.5); }), Status::invalid_argument);
  EXPECT_EQ(status_of([&] { surface.evaluate(1, 0.5, 0.5, std::vector<Vec3>(3)); }), Status::invalid_argument);
  EXPECT_EQ(status_of([&] { surface.ptex_face(6); }), Status::invalid_argument);
  EXPECT_EQ(status_of([&] { surface.ptex_face(0, 1); }), Status::invalid_argument);
  EXPECT_EQ(status_of([&] { surface.base_face_of_ptex(6); }), Status::invalid_argument);
  EXPECT_EQ(status_of([&] { surface.evaluate(3, 0.5, 0.5); }), Status::success);

  SurfaceOptions bad;
  bad.isolation_level = 11;
  EXPECT_EQ(status_of([&] { SubdivisionSurface s(cage, bad); }), Status::invalid_argument);
  Cage broken = cage;
  broken.mesh.face_vertices[0] = 99;
  EXPECT_EQ(status_of([&] { SubdivisionSurface s(broken); }), Status::invalid_mesh);
  EXPECT_EQ(status_of([&] { SubdivisionSurface s(cage_of(PolygonMesh())); }), Status::invalid_mesh);
}

TEST(SubdivisionSurface, non_manifold_cages_evaluate_without_crashing) {
  PolygonMesh fin;  // three quads around one edge
  for (int i = 0; i < 8; ++i) fin.add_vertex(Vec3(i % 2, (i / 2) % 2, i / 4));
  fin.add_face({0, 1, 3, 2});
  fin.add_face({0, 1, 5, 4});
  fin.add_face({1, 0, 6, 7});
  const Cage cage = cage_of(fin);
  const SubdivisionSurface surface(cage);
  for (const Sample& p : random_samples(surface, cage, 50, 1)) {
    const BasisWeights b = surface.basis(p.ptex, p.u, p.v);
    EXPECT_NEAR(sum(b.w), 1.0, 1e-12);
    EXPECT_TRUE(cagekit::is_finite(surface.evaluate(p.ptex, p.u, p.v).position));
  }
}

// Random polygon soups (non-manifold, inconsistently oriented, randomly tagged): construction
// and evaluation either succeed with finite results and a partition of unity, or throw an Error.
TEST(SubdivisionSurface, random_soups_never_crash) {
  std::mt19937 rng(77);
  int succeeded = 0;
  for (int trial = 0; trial < 60; ++trial) {
    Cage cage;
    cage.mesh = cagekit_test::random_polygon_soup(rng);
    const uint32_t nv = static_cast<uint32_t>(cage.mesh.num_vertices());
    const int nf = static_cast<int>(cage.mesh.num_faces());
    for (size_t f = 0; f < cage.mesh.num_faces(); ++f)
      if (rng() % 5 == 0) cage.creases.push_back({cage.mesh.face_vertex(f, 0), cage.mesh.face_vertex(f, 1),
                                                  static_cast<float>(rng() % 12)});
    if (rng() % 3 == 0) cage.corners.push_back({static_cast<uint32_t>(rng() % nv), 3.0f});
    if (rng() % 4 == 0) cage.holes.push_back(static_cast<uint32_t>(rng() % nf));
    SurfaceOptions options;
    options.isolation_level = 1 + static_cast<int>(rng() % 4);
    try {
      const SubdivisionSurface surface(cage, options);
      for (int k = 0; k < 20; ++k) {
        const uint32_t ptex = static_cast<uint32_t>(rng() % surface.num_ptex_faces());
        if (is_hole(surface, cage, ptex)) continue;
        const double u = (rng() % 1001) / 1000.0, v = (rng() % 1001) / 1000.0;
        const SurfacePoint p = surface.evaluate(ptex, u, v);
        ASSERT_TRUE(cagekit::is_finite(p.position) && cagekit::is_finite(p.dvv)) << "trial " << trial;
        EXPECT_NEAR(sum(surface.basis(ptex, u, v).w), 1.0, 1e-9) << "trial " << trial;
      }
      ++succeeded;
    } catch (const Error& e) {
      EXPECT_NE(e.status(), Status::internal_error) << "trial " << trial << ": " << e.what();
      std::cout << "trial " << trial << " rejected: " << e.what() << "\n";
    }
  }
  std::cout << succeeded << " of 60 random soups accepted\n";
  EXPECT_GT(succeeded, 40);
}

TEST(SubdivisionSurface, degenerate_but_valid_cages) {
  Cage all_holes = cage_of(cagekit_test::unit_cube_quads());
  all_holes.holes = {0, 1, 2, 3, 4, 5};
  const SubdivisionSurface empty(all_holes);
  EXPECT_EQ(status_of([&] { empty.evaluate(0, 0.5, 0.5); }), Status::invalid_argument);

  PolygonMesh triangle;
  triangle.add_vertex(Vec3(0, 0, 0));
  triangle.add_vertex(Vec3(1, 0, 0));
  triangle.add_vertex(Vec3(0, 1, 0));
  triangle.add_face({0, 1, 2});
  PolygonMesh bowtie = triangle;  // two triangles sharing only vertex 0
  bowtie.add_vertex(Vec3(-1, 0, 0.5));
  bowtie.add_vertex(Vec3(0, -1, 0.5));
  bowtie.add_face({0, 3, 4});
  for (const PolygonMesh& m : {triangle, bowtie, cagekit_test::quad_grid(1, 1)})
    for (BoundaryRule rule : {BoundaryRule::edges_only, BoundaryRule::edges_and_corners}) {
      Cage cage = cage_of(m);
      cage.boundary = rule;
      const SubdivisionSurface surface(cage);
      for (uint32_t ptex = 0; ptex < surface.num_ptex_faces(); ++ptex)
        for (double t : {0.0, 0.5, 1.0}) {
          const SurfacePoint p = surface.evaluate(ptex, t, 1.0 - t);
          EXPECT_TRUE(cagekit::is_finite(p.position) && cagekit::is_finite(p.duu));
          EXPECT_NEAR(sum(surface.basis(ptex, t, t).w), 1.0, 1e-12);
        }
    }
}

// A dense cage (8,192 triangles, 24,576 ptex faces, every vertex extraordinary after one
// step; triangle_sphere(6), 32,768 triangles, takes ~4x longer): builds (time printed; timing itself belongs in benchmarks) and agrees with the limit
// positions of its vertices and with a coarse-isolation build.
TEST(SubdivisionSurface, dense_cage_builds_and_agrees_with_vertex_limits) {
  const Cage cage = cage_of(cagekit_test::triangle_sphere(5));
  const auto start = std::chrono::steady_clock::now();
  const SubdivisionSurface surface(cage);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "triangle sphere, " << cage.mesh.num_faces() << " triangles: SubdivisionSurface built in " << seconds
            << " s (this build type)\n";
  ASSERT_EQ(surface.num_ptex_faces(), 3u * cage.mesh.num_faces());
  EXPECT_EQ(surface.num_control_vertices(), cage.mesh.num_vertices());
  std::vector<Vec3> limit;
  cagekit::limit_positions_and_normals(cage, &limit, nullptr);
  double max_gap = 0, max_centre_gap = 0;
  for (uint32_t f = 0; f < cage.mesh.num_faces(); f += 7)
    for (uint32_t k = 0; k < 3; ++k) {
      const uint32_t ptex = surface.ptex_face(f, k);
      max_gap = std::max(max_gap, cagekit::distance(surface.evaluate(ptex, 0, 0).position,
                                                    limit[cage.mesh.face_vertex(f, k)]));
      // The face centre from all three sub-faces.
      max_centre_gap = std::max(max_centre_gap, cagekit::distance(surface.evaluate(ptex, 1, 1).position,
                                                                  surface.evaluate(surface.ptex_face(f, 0), 1, 1).position));
      const BasisWeights b = surface.basis(ptex, 0.1, 0.3);
      EXPECT_NEAR(sum(b.w), 1.0, 1e-12);
    }
  EXPECT_LT(max_gap, 1e-13);
  EXPECT_LT(max_centre_gap, 1e-13);
}

TEST(SubdivisionSurface, const_evaluation_is_thread_safe_and_movable) {
  const Cage cage = cage_of(cagekit_test::triangle_sphere(1));
  SubdivisionSurface surface(cage);
  const std::vector<Sample> samples = random_samples(surface, cage, 500, 9);
  std::vector<Vec3> serial;
  for (const Sample& p : samples) serial.push_back(surface.evaluate(p.ptex, p.u, p.v).du);
  std::vector<Vec3> a(samples.size()), b(samples.size());
  std::thread ta([&] { for (size_t i = 0; i < samples.size(); ++i) a[i] = surface.evaluate(samples[i].ptex, samples[i].u, samples[i].v).du; });
  std::thread tb([&] { for (size_t i = samples.size(); i-- > 0;) b[i] = surface.evaluate(samples[i].ptex, samples[i].u, samples[i].v).du; });
  ta.join();
  tb.join();
  EXPECT_EQ(a, serial);
  EXPECT_EQ(b, serial);
  SubdivisionSurface moved(std::move(surface));
  EXPECT_EQ(moved.evaluate(samples[0].ptex, samples[0].u, samples[0].v).du, serial[0]);
}

}  // namespace
