// SPDX-License-Identifier: GPL-3.0-or-later
// Curvature tensor field (thesis ch. 5 Stage I, spec thesis-ch4-6.md §1.2, AC5-1..AC5-3).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>

#include "layout/anisotropic/curvature_tensor_field.h"
#include "layout/common/feature_edges.h"
#include "test_support.h"

using cagekit::CurvatureField;
using cagekit::CurvatureOptions;
using cagekit::PolygonMesh;
using cagekit::Status;
using cagekit::Vec3;
using cagekit_test::status_of;

namespace {

const double kPi = 3.14159265358979323846;

double deg(double radians) { return radians * 180.0 / kPi; }

// Angle in degrees between two direction lines (sign ignored).
double line_angle(const Vec3& a, const Vec3& b) {
  const double c = std::fabs(cagekit::dot(cagekit::normalized(a), cagekit::normalized(b)));
  return deg(std::acos(std::min(1.0, c)));
}

void add_quad(PolygonMesh& m, uint32_t a, uint32_t b, uint32_t c, uint32_t d, bool flip_diagonal) {
  if (flip_diagonal) {
    m.add_face({a, b, d});
    m.add_face({b, c, d});
  } else {
    m.add_face({a, b, c});
    m.add_face({a, c, d});
  }
}

// Torus: ring radius R, tube radius r; u around the ring (n_u), v around the tube (n_v).
PolygonMesh torus(double R, double r, int n_u, int n_v) {
  PolygonMesh m;
  for (int i = 0; i < n_u; ++i)
    for (int j = 0; j < n_v; ++j) {
      const double u = 2 * kPi * i / n_u, v = 2 * kPi * j / n_v;
      m.add_vertex({(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)});
    }
  auto id = [&](int i, int j) { return uint32_t((i % n_u) * n_v + (j % n_v)); };
  for (int i = 0; i < n_u; ++i)
    for (int j = 0; j < n_v; ++j) add_quad(m, id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1), (i + j) % 2);
  return m;
}

// Closed box [0, n]^3 scaled by s, every side an n x n grid of triangulated quads, outward.
PolygonMesh box(int n, double s) {
  PolygonMesh m;
  std::map<long, uint32_t> ids;
  auto vid = [&](int x, int y, int z) {
    const long key = (long(x) * (n + 1) + y) * (n + 1) + z;
    auto it = ids.find(key);
    if (it != ids.end()) return it->second;
    const uint32_t v = m.add_vertex({s * x, s * y, s * z});
    ids.emplace(key, v);
    return v;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side <= 1; ++side)
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
          uint32_t q[4];
          const int da[4] = {0, 1, 1, 0}, db[4] = {0, 0, 1, 1};
          for (int k = 0; k < 4; ++k) {
            int c[3];
            c[axis] = side * n;
            c[(axis + 1) % 3] = a + da[k];
            c[(axis + 2) % 3] = b + db[k];
            q[k] = vid(c[0], c[1], c[2]);
          }
          // (axis+1) x (axis+2) = +axis: this order faces +axis; reverse it on the low side.
          if (side == 1)
            add_quad(m, q[0], q[1], q[2], q[3], (a + b) % 2);
          else
            add_quad(m, q[3], q[2], q[1], q[0], (a + b) % 2);
        }
  return m;
}

template <class T>
double mean(const std::vector<T>& v) {
  double s = 0;
  for (const T& x : v) s += double(x);
  return v.empty() ? 0.0 : s / double(v.size());
}

}  // namespace

// AC5-1: cylinder of radius R: k_max ≈ 1/R, k_min ≈ 0, t_min (the eigenvector paired with k_max:
// the swapped pairing of (5.6)) along the axis; AC5-3: Λ ≥ cos(π/6) on ≥ 95% of the faces.
TEST(CurvatureTensorField, CylinderPrincipalCurvaturesAndAxis) {
  const double R = 2.0, H = 6.0;
  const PolygonMesh m = cagekit_test::triangle_cylinder(R, H, 96, 46);
  CurvatureOptions o;
  o.smoothing_iterations = 0;
  const CurvatureField f = cagekit::estimate_curvature_field(m, o);
  ASSERT_EQ(f.vertex_k_max.size(), m.num_vertices());
  int interior = 0, axis_ok = 0;
  std::vector<double> kmax, kmin;
  for (size_t v = 0; v < m.num_vertices(); ++v) {
    const double z = m.positions[v].z;
    if (z < f.disk_radius * 1.5 || z > H - f.disk_radius * 1.5) continue;
    ++interior;
    kmax.push_back(f.vertex_k_max[v]);
    kmin.push_back(std::fabs(f.vertex_k_min[v]));
    if (line_angle(f.vertex_t_min[v], {0, 0, 1}) < 5.0) ++axis_ok;
    // The swapped pairing (5.6) on the raw estimate (5.2): the axis (the minimum-curvature
    // direction) is the eigenvector of T(v) whose eigenvalue is k_max ≈ 1/R.
    const CurvatureField::Tensor& T = f.raw_vertex_tensor[v];
    EXPECT_NEAR(T[2], f.vertex_k_max[v], 1e-9);  // zᵀ T z
    EXPECT_NEAR(T[4], 0.0, 1e-9);                // (T z)·x
    EXPECT_NEAR(T[5], 0.0, 1e-9);                // (T z)·y
    // frame: unit, tangent, orthogonal
    EXPECT_NEAR(cagekit::norm(f.vertex_t_min[v]), 1.0, 1e-12);
    EXPECT_NEAR(cagekit::dot(f.vertex_t_min[v], f.vertex_normal[v]), 0.0, 1e-12);
    EXPECT_NEAR(cagekit::dot(f.vertex_t_min[v], f.vertex_t_max[v]), 0.0, 1e-12);
  }
  ASSERT_GT(interior, 1000);
  std::printf("cylinder R=%g: r=%.4f, mean k_max %.5f (1/R %.5f), mean |k_min| %.2e, axis within 5 deg %d/%d\n", R,
              f.disk_radius, mean(kmax), 1 / R, mean(kmin), axis_ok, interior);
  EXPECT_NEAR(mean(kmax) * R, 1.0, 0.05);
  for (double k : kmax) EXPECT_NEAR(k * R, 1.0, 0.1);
  EXPECT_LT(mean(kmin) * R, 0.02);
  EXPECT_GE(axis_ok, int(0.95 * interior));
  int confident = 0;
  for (double c : f.face_confidence) confident += c >= std::cos(kPi / 6);
  std::printf("cylinder: faces with confidence >= cos(pi/6): %d / %zu\n", confident, f.face_confidence.size());
  EXPECT_GE(confident, int(0.95 * double(m.num_faces())));
}

// AC5-1 on a sphere of radius R (>= 20K triangles): umbilic, k_min ≈ k_max ≈ 1/R, and the
// directions are noise: low anisotropy and a lower confidence than on the cylinder.
TEST(CurvatureTensorField, SphereIsUmbilic) {
  const double R = 3.0;
  PolygonMesh m = cagekit_test::triangle_sphere(6);  // 32768 triangles
  for (Vec3& p : m.positions) p *= R;
  CurvatureOptions o;
  o.smoothing_iterations = 0;
  const CurvatureField f = cagekit::estimate_curvature_field(m, o);
  std::vector<double> kmax, kmin, aniso;
  for (size_t v = 0; v < m.num_vertices(); ++v) {
    kmax.push_back(f.vertex_k_max[v]);
    kmin.push_back(f.vertex_k_min[v]);
    aniso.push_back((f.vertex_k_max[v] - f.vertex_k_min[v]) / f.vertex_k_max[v]);
    EXPECT_NEAR(f.vertex_k_max[v] * R, 1.0, 0.15);
    EXPECT_NEAR(f.vertex_k_min[v] * R, 1.0, 0.15);
    // the normal is the radial direction
    EXPECT_GT(cagekit::dot(f.vertex_normal[v], cagekit::normalized(m.positions[v])), 0.999);
  }
  std::printf("sphere R=%g: mean k_max %.5f, mean k_min %.5f (1/R %.5f), mean (k_max-k_min)/k_max %.4f, "
              "mean face confidence %.3f\n",
              R, mean(kmax), mean(kmin), 1 / R, mean(aniso), mean(f.face_confidence));
  EXPECT_NEAR(mean(kmax) * R, 1.0, 0.05);
  EXPECT_NEAR(mean(kmin) * R, 1.0, 0.05);
  EXPECT_LT(mean(aniso), 0.1);
  // Λ (5.8) measures direction coherence, not anisotropy: on this very regular mesh the
  // (meaningless) umbilic directions follow the mesh structure and stay locally coherent (printed
  // above). Jitter the vertices along the sphere (AC5-3, "noisy sphere"): curvatures stay ≈ 1/R,
  // the directions become incoherent and a large share of faces falls below Λ_min = cos(π/6).
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-0.02, 0.02);  // ~20% of an edge length
  for (Vec3& p : m.positions) p = R * cagekit::normalized(p + Vec3{jitter(rng), jitter(rng), jitter(rng)});
  const CurvatureField j = cagekit::estimate_curvature_field(m, o);
  int low = 0;
  for (double c : j.face_confidence) low += c < std::cos(kPi / 6);
  std::printf("jittered sphere: mean k_max %.5f, mean k_min %.5f, faces below cos(pi/6): %d / %zu\n",
              mean(j.vertex_k_max), mean(j.vertex_k_min), low, m.num_faces());
  EXPECT_NEAR(mean(j.vertex_k_max) * R, 1.0, 0.1);
  EXPECT_NEAR(mean(j.vertex_k_min) * R, 1.0, 0.1);
  EXPECT_GT(low, int(0.3 * double(m.num_faces())));
}

// Torus (ring radius 3, tube radius 1): t_min along the ring circles, t_max along the tube
// circles; k_max ≈ 1 (tube), k_min ≈ cos v / (3 + cos v), negative on the inner side (saddles).
TEST(CurvatureTensorField, TorusDirectionsFollowRingAndTube) {
  const double R = 3.0, r = 1.0;
  const int nu = 120, nv = 40;
  const PolygonMesh m = torus(R, r, nu, nv);
  CurvatureOptions o;
  o.smoothing_iterations = 0;
  const CurvatureField f = cagekit::estimate_curvature_field(m, o);
  int ring_ok = 0, tube_ok = 0, kmax_ok = 0, kmin_ok = 0;
  double worst_kmin = 0;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const size_t id = size_t(i) * nv + j;
      const double u = 2 * kPi * i / nu, v = 2 * kPi * j / nv;
      const Vec3 ring{-std::sin(u), std::cos(u), 0};
      const Vec3 tube{-std::sin(v) * std::cos(u), -std::sin(v) * std::sin(u), std::cos(v)};
      ring_ok += line_angle(f.vertex_t_min[id], ring) < 5.0;
      tube_ok += line_angle(f.vertex_t_max[id], tube) < 5.0;
      kmax_ok += std::fabs(f.vertex_k_max[id] * r - 1.0) < 0.1;
      const double kmin_exact = std::cos(v) / (R + r * std::cos(v));
      worst_kmin = std::max(worst_kmin, std::fabs(f.vertex_k_min[id] - kmin_exact));
      // The disk (r ≈ 0.5 tube radii) averages k_min, which varies with v across it: 0.1 k_max.
      kmin_ok += std::fabs(f.vertex_k_min[id] - kmin_exact) < 0.1;
    }
  const int n = nu * nv;
  std::printf("torus: t_min along ring %d/%d, t_max along tube %d/%d, |k_max-1|<0.1 %d/%d, |k_min-exact|<0.1 %d/%d "
              "(worst %.3f)\n",
              ring_ok, n, tube_ok, n, kmax_ok, n, kmin_ok, n, worst_kmin);
  EXPECT_GE(ring_ok, int(0.95 * n));
  EXPECT_GE(tube_ok, int(0.95 * n));
  EXPECT_GE(kmax_ok, int(0.95 * n));
  EXPECT_GE(kmin_ok, int(0.95 * n));
}

// AC5-2: a box with sharp edges. Without features the disks of vertices near an edge take its
// 90-degree bend; with feature detection on (or the same edges given by the host) the disks
// stop at the edges and every flat face keeps k ≈ 0.
TEST(CurvatureTensorField, BoxFeatureEdgesTrimTheDisks) {
  const PolygonMesh m = box(12, 0.5);
  CurvatureOptions o;
  o.smoothing_iterations = 3;
  const CurvatureField plain = cagekit::estimate_curvature_field(m, o);
  double plain_max = 0;
  for (size_t f = 0; f < m.num_faces(); ++f) plain_max = std::max(plain_max, std::fabs(plain.face_k_max[f]));
  EXPECT_GT(plain_max, 0.5);  // the bend leaks into the sides when nothing trims the disks

  o.feature_angle_degrees = 30.0;
  const CurvatureField trimmed = cagekit::estimate_curvature_field(m, o);
  double trimmed_max = 0;
  for (size_t f = 0; f < m.num_faces(); ++f)
    trimmed_max = std::max({trimmed_max, std::fabs(trimmed.face_k_max[f]), std::fabs(trimmed.face_k_min[f])});
  for (size_t v = 0; v < m.num_vertices(); ++v)
    trimmed_max = std::max(trimmed_max, std::fabs(trimmed.vertex_k_max[v]));
  std::printf("box: max |k| on faces without features %.3f, with feature detection %.3e\n", plain_max, trimmed_max);
  EXPECT_LT(trimmed_max, 1e-9);
  size_t flagged = 0;
  for (uint8_t b : trimmed.barrier_edges) flagged += b;
  EXPECT_EQ(flagged, size_t(12 * 12 * 2));  // 12 box edges x 12 segments x 2 half-edges

  // The same edges given by the host (one side tagged is enough).
  std::vector<uint8_t> host = cagekit::detect_feature_edges(m, 30.0);
  ASSERT_EQ(host.size(), m.num_face_vertices());
  o.feature_angle_degrees = -1.0;
  const CurvatureField hosted = cagekit::estimate_curvature_field(m, o, &host);
  EXPECT_EQ(hosted.vertex_tensor, trimmed.vertex_tensor);
}

// (5.9): on a cylinder with a noisy patch, smoothing raises the share of the patch's
// low-confidence faces whose vertex directions agree with the confident neighbourhood (the
// axis), and leaves the directions of confident faces away from the patch unchanged.
TEST(CurvatureTensorField, SmoothingPropagatesConfidentDirections) {
  const double R = 2.0, H = 6.0;
  PolygonMesh m = cagekit_test::triangle_cylinder(R, H, 96, 46);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.02);  // ~15% of an edge length, radial
  std::vector<uint8_t> noisy(m.num_vertices(), 0);
  for (size_t v = 0; v < m.num_vertices(); ++v) {
    Vec3& p = m.positions[v];
    if (p.z > 2.0 && p.z < 4.0 && p.x > 0.5) {
      const Vec3 radial = cagekit::normalized({p.x, p.y, 0});
      p += radial * noise(rng);
      noisy[v] = 1;
    }
  }
  CurvatureOptions o;
  o.smoothing_iterations = 10;
  const CurvatureField f = cagekit::estimate_curvature_field(m, o);
  const double lam_min = std::cos(kPi / 6);
  int low = 0, low_aligned_before = 0, low_aligned_after = 0, confident = 0, confident_kept = 0;
  double worst_confident = 0;
  for (size_t t = 0; t < m.num_faces(); ++t) {
    bool before = true, after = true, near_noise = false, in_range = true;
    double change = 0;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = m.face_vertex(t, k);
      before &= line_angle(f.raw_vertex_t_min[v], {0, 0, 1}) < 10.0;
      after &= line_angle(f.vertex_t_min[v], {0, 0, 1}) < 10.0;
      change = std::max(change, line_angle(f.raw_vertex_t_min[v], f.vertex_t_min[v]));
      const Vec3& p = m.positions[v];
      near_noise |= p.z > 1.0 && p.z < 5.0 && p.x > -0.5;
      in_range &= p.z > 1.0 && p.z < 5.0;
    }
    if (f.raw_face_confidence[t] < lam_min && in_range) {
      ++low;
      low_aligned_before += before;
      low_aligned_after += after;
    }
    if (f.raw_face_confidence[t] >= 0.99 && !near_noise && in_range) {
      ++confident;
      confident_kept += change < 1.0;
      worst_confident = std::max(worst_confident, change);
    }
  }
  std::printf("smoothing: low-confidence faces %d, aligned with the axis before %d, after %d; confident faces %d, "
              "direction kept within 1 deg %d (worst %.3f deg)\n",
              low, low_aligned_before, low_aligned_after, confident, confident_kept, worst_confident);
  ASSERT_GT(low, 20);
  ASSERT_GT(confident, 1000);
  EXPECT_GT(low_aligned_after, low_aligned_before + low / 4);
  EXPECT_EQ(confident_kept, confident);
  int low_after = 0, low_before = 0;
  for (size_t t = 0; t < m.num_faces(); ++t) {
    low_before += f.raw_face_confidence[t] < lam_min;
    low_after += f.face_confidence[t] < lam_min;
  }
  EXPECT_LT(low_after, low_before);
}

// Flattening (5.7) and interpolation (5.3) on the cylinder: the flattened t_min, mapped back
// through the face's unfolding, is the axis; T̄ has eigenvalue k_max along t̄_min.
TEST(CurvatureTensorField, FlatteningAndInterpolation) {
  const PolygonMesh m = cagekit_test::triangle_cylinder(2.0, 6.0, 96, 46);
  CurvatureOptions o;
  const CurvatureField f = cagekit::estimate_curvature_field(m, o);
  int checked = 0;
  for (uint32_t t = 0; t < m.num_faces(); t += 7) {
    const double z = m.positions[m.face_vertex(t, 0)].z;
    if (z < 1.5 || z > 4.5) continue;
    const cagekit::FlattenedFace ff = cagekit::flatten_face(m, f, t);
    const Vec3 a = m.positions[m.face_vertex(t, 0)], b = m.positions[m.face_vertex(t, 1)],
               c = m.positions[m.face_vertex(t, 2)];
    const Vec3 eu = cagekit::normalized(b - a);
    const Vec3 ev = cagekit::normalized((c - a) - cagekit::dot(c - a, eu) * eu);
    // the unfolding is isometric
    EXPECT_NEAR(ff.corner[2][0], cagekit::dot(c - a, eu), 1e-12);
    EXPECT_NEAR(ff.corner[2][1], cagekit::dot(c - a, ev), 1e-12);
    for (int k = 0; k < 3; ++k) {
      const Vec3 d3 = ff.t_min[k][0] * eu + ff.t_min[k][1] * ev;
      EXPECT_LT(line_angle(d3, {0, 0, 1}), 5.0);
      const uint32_t v = m.face_vertex(t, k);
      const auto& T = ff.tensor[k];
      const double tx = T[0] * ff.t_min[k][0] + T[2] * ff.t_min[k][1];
      const double ty = T[2] * ff.t_min[k][0] + T[1] * ff.t_min[k][1];
      EXPECT_NEAR(tx, f.vertex_k_max[v] * ff.t_min[k][0], 1e-12);
      EXPECT_NEAR(ty, f.vertex_k_max[v] * ff.t_min[k][1], 1e-12);
    }
    const CurvatureField::Tensor t0 = cagekit::interpolate_tensor(m, f, t, 1, 0, 0);
    EXPECT_EQ(t0, f.vertex_tensor[m.face_vertex(t, 0)]);
    const CurvatureField::Tensor tc = cagekit::interpolate_tensor(m, f, t, 1.0 / 3, 1.0 / 3, 1.0 / 3);
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(tc[i], f.face_tensor[t][i], 1e-12);
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

TEST(CurvatureTensorField, ThreadCountDoesNotChangeResults) {
  const PolygonMesh m = torus(3.0, 1.0, 60, 24);
  CurvatureOptions o;
  o.threads = 1;
  const CurvatureField a = cagekit::estimate_curvature_field(m, o);
  o.threads = 3;
  const CurvatureField b = cagekit::estimate_curvature_field(m, o);
  EXPECT_EQ(a.vertex_tensor, b.vertex_tensor);
  EXPECT_EQ(a.face_confidence, b.face_confidence);
}

TEST(CurvatureTensorField, BadInputIsAnErrorNotACrash) {
  const PolygonMesh good = cagekit_test::triangle_cylinder(1.0, 2.0, 16, 4);
  const CurvatureOptions o;
  auto run = [&](const PolygonMesh& m, const CurvatureOptions& opt, const std::vector<uint8_t>* host = nullptr) {
    return status_of([&] { cagekit::estimate_curvature_field(m, opt, host); });
  };
  EXPECT_EQ(run(good, o), Status::success);

  PolygonMesh nan_mesh = good;
  nan_mesh.positions[3].y = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(run(nan_mesh, o), Status::invalid_mesh);
  PolygonMesh inf_mesh = good;
  inf_mesh.positions[0].x = std::numeric_limits<double>::infinity();
  EXPECT_EQ(run(inf_mesh, o), Status::invalid_mesh);
  PolygonMesh out_of_range = good;
  out_of_range.face_vertices[5] = 100000;
  EXPECT_EQ(run(out_of_range, o), Status::invalid_mesh);
  PolygonMesh repeated = good;
  repeated.face_vertices[1] = repeated.face_vertices[0];
  EXPECT_EQ(run(repeated, o), Status::invalid_mesh);
  PolygonMesh quads = cagekit_test::unit_cube_quads();
  EXPECT_EQ(run(quads, o), Status::invalid_mesh);
  PolygonMesh broken_offsets = good;
  broken_offsets.face_offsets.back() += 1;
  EXPECT_EQ(run(broken_offsets, o), Status::invalid_mesh);
  EXPECT_EQ(run(PolygonMesh{}, o), Status::invalid_mesh);

  CurvatureOptions bad = o;
  bad.disk_radius = 0;
  EXPECT_EQ(run(good, bad), Status::invalid_argument);
  bad = o;
  bad.disk_radius = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(run(good, bad), Status::invalid_argument);
  bad = o;
  bad.disk_radius_bbox = std::numeric_limits<double>::infinity();
  EXPECT_EQ(run(good, bad), Status::invalid_argument);
  bad = o;
  bad.feature_angle_degrees = 200;
  EXPECT_EQ(run(good, bad), Status::invalid_argument);
  bad = o;
  bad.smoothing_iterations = -1;
  EXPECT_EQ(run(good, bad), Status::invalid_argument);
  bad = o;
  bad.threads = -2;
  EXPECT_EQ(run(good, bad), Status::invalid_argument);
  const std::vector<uint8_t> short_flags(3, 1);
  EXPECT_EQ(run(good, o, &short_flags), Status::invalid_argument);
  EXPECT_EQ(status_of([] { cagekit::detect_feature_edges(cagekit_test::unit_cube_quads(), 181); }),
            Status::invalid_argument);

  // Degenerate but valid-index input: non-manifold fins, a zero-area face, coincident points,
  // inconsistent orientation: a result, finite everywhere.
  PolygonMesh odd;
  for (const Vec3& p : {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, -1, 0}, Vec3{0, 0, 1}, Vec3{2, 0, 0},
                        Vec3{0, 0, 0}})
    odd.add_vertex(p);
  odd.add_face({0, 1, 2});
  odd.add_face({1, 0, 3});
  odd.add_face({0, 1, 4});  // third face on edge 0-1, same direction as the first
  odd.add_face({0, 1, 5});  // collinear: zero area
  odd.add_face({6, 2, 4});  // vertex 6 coincides with vertex 0
  CurvatureField f;
  ASSERT_EQ(status_of([&] { f = cagekit::estimate_curvature_field(odd, o); }), Status::success);
  for (size_t v = 0; v < odd.num_vertices(); ++v) {
    EXPECT_TRUE(std::isfinite(f.vertex_k_max[v]) && std::isfinite(f.vertex_k_min[v]));
    EXPECT_TRUE(f.vertex_confidence[v] >= 0 && f.vertex_confidence[v] <= 1);
  }
  for (double c : f.face_confidence) EXPECT_TRUE(c >= 0 && c <= 1);

  // Cancellation from the progress callback.
  cagekit::TaskMonitor cancel([](const char*, double) { return false; }, nullptr);
  EXPECT_EQ(status_of([&] { cagekit::estimate_curvature_field(good, o, nullptr, cancel); }), Status::cancelled);
  // Accessors check their arguments.
  const CurvatureField gf = cagekit::estimate_curvature_field(good, o);
  EXPECT_EQ(status_of([&] { cagekit::flatten_face(good, gf, uint32_t(good.num_faces())); }), Status::invalid_argument);
  EXPECT_EQ(status_of([&] { cagekit::interpolate_tensor(odd, gf, 0, 1, 0, 0); }), Status::invalid_argument);
}

// Real CAD mesh (when present): fandisk with feature detection; sane, finite, tangent frames.
TEST(CurvatureTensorField, FandiskWithFeatures) {
  const std::string path = cagekit_test::shared_mesh_path("fandisk.obj");
  if (path.empty()) GTEST_SKIP() << "shared mesh fandisk.obj not present";
  const PolygonMesh m = cagekit_test::load_mesh(path);
  if (!m.all_faces_have_size(3)) GTEST_SKIP() << "fandisk.obj is not all triangles";
  CurvatureOptions o;
  o.feature_angle_degrees = 30.0;
  o.threads = 2;
  const CurvatureField f = cagekit::estimate_curvature_field(m, o);
  size_t barriers = 0, confident = 0;
  for (uint8_t b : f.barrier_edges) barriers += b;
  for (size_t v = 0; v < m.num_vertices(); ++v) {
    ASSERT_TRUE(std::isfinite(f.vertex_k_max[v]) && std::isfinite(f.vertex_k_min[v]));
    EXPECT_LE(std::fabs(f.vertex_k_min[v]), std::fabs(f.vertex_k_max[v]) + 1e-12);
    if (cagekit::dot(f.vertex_normal[v], f.vertex_normal[v]) > 0) {
      EXPECT_NEAR(cagekit::dot(f.vertex_t_min[v], f.vertex_normal[v]), 0.0, 1e-9);
    }
  }
  for (double c : f.face_confidence) confident += c >= std::cos(kPi / 6);
  std::printf("fandisk: %zu triangles, r=%.4f, %zu barrier half-edges, confident faces %zu (%.1f%%)\n", m.num_faces(),
              f.disk_radius, barriers, confident, 100.0 * double(confident) / double(m.num_faces()));
  EXPECT_GT(barriers, 0u);
  EXPECT_GT(confident, m.num_faces() / 2);
}

// AC5-1 with the thesis's own radius (r = 1% of the bbox diagonal) on a finer sphere.
TEST(CurvatureTensorField, SphereWithThesisRadius) {
  const double R = 3.0;
  PolygonMesh m = cagekit_test::triangle_sphere(7);  // 131072 triangles
  for (Vec3& p : m.positions) p *= R;
  CurvatureOptions o;
  o.disk_radius_bbox = 0.01;
  o.smoothing_iterations = 0;
  o.threads = 2;
  const auto t0 = std::chrono::steady_clock::now();
  const CurvatureField f = cagekit::estimate_curvature_field(m, o);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("sphere (131K triangles), r = 1%% of the diagonal = %.4f: mean k_max %.5f, mean k_min %.5f (1/R %.5f), "
              "%.2f s on 2 threads\n",
              f.disk_radius, mean(f.vertex_k_max), mean(f.vertex_k_min), 1 / R, seconds);
  EXPECT_NEAR(f.disk_radius, 0.01 * m.bounding_box().diagonal(), 1e-12);
  EXPECT_NEAR(mean(f.vertex_k_max) * R, 1.0, 0.05);
  EXPECT_NEAR(mean(f.vertex_k_min) * R, 1.0, 0.05);
}

// Real scan (when present): run time on the bunny, default options.
TEST(CurvatureTensorField, BunnyRunTime) {
  const std::string path = cagekit_test::shared_mesh_path("stanford-bunny.obj");
  if (path.empty()) GTEST_SKIP() << "shared mesh stanford-bunny.obj not present";
  const PolygonMesh m = cagekit_test::load_mesh(path);
  if (!m.all_faces_have_size(3)) GTEST_SKIP() << "stanford-bunny.obj is not all triangles";
  CurvatureOptions o;
  const auto t0 = std::chrono::steady_clock::now();
  const CurvatureField f = cagekit::estimate_curvature_field(m, o);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  size_t confident = 0;
  for (double c : f.face_confidence) confident += c >= std::cos(kPi / 6);
  std::printf("bunny: %zu triangles, r=%.5f, %.2f s (1 thread, 5 smoothing iterations), confident faces %.1f%%\n",
              m.num_faces(), f.disk_radius, seconds, 100.0 * double(confident) / double(m.num_faces()));
  for (size_t v = 0; v < m.num_vertices(); ++v)
    ASSERT_TRUE(std::isfinite(f.vertex_k_max[v]) && std::isfinite(f.vertex_k_min[v]));
}
