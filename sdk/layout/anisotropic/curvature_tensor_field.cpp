// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/anisotropic/curvature_tensor_field.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/edge_map.h"
#include "core/parallel_for.h"
#include "core/status.h"
#include "layout/common/feature_edges.h"
#include "layout/anisotropic/morton_order.h"

CAGEKIT_NAMESPACE_BEGIN
namespace {

using Tensor = CurvatureField::Tensor;
using detail::kNone;

// ---- small symmetric-tensor helpers (xx, yy, zz, xy, xz, yz) --------------------------------

void add_outer(Tensor& t, const Vec3& a, double w) {
  t[0] += w * a.x * a.x;
  t[1] += w * a.y * a.y;
  t[2] += w * a.z * a.z;
  t[3] += w * a.x * a.y;
  t[4] += w * a.x * a.z;
  t[5] += w * a.y * a.z;
}

void add_scaled(Tensor& t, const Tensor& s, double w) {
  for (int i = 0; i < 6; ++i) t[i] += w * s[i];
}

Vec3 tensor_times(const Tensor& t, const Vec3& a) {
  return {t[0] * a.x + t[3] * a.y + t[4] * a.z, t[3] * a.x + t[1] * a.y + t[5] * a.z,
          t[4] * a.x + t[5] * a.y + t[2] * a.z};
}

// A unit tangent basis (b1, b2) of unit n, b2 = n x b1, built from the world axis least aligned
// with n (deterministic).
void tangent_basis(const Vec3& n, Vec3& b1, Vec3& b2) {
  const double ax = std::fabs(n.x), ay = std::fabs(n.y), az = std::fabs(n.z);
  const Vec3 axis = ax <= ay && ax <= az ? Vec3{1, 0, 0} : (ay <= az ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
  b1 = normalized(cross(n, axis));
  b2 = cross(n, b1);
}

struct Frame {
  Vec3 t_min, t_max;
  double k_min = 0, k_max = 0;
};

// Eigen-decomposition (5.4)-(5.6) with the re-alignment of §5.4.1.1: the tensor is restricted to
// the tangent plane of the averaged normal n (P T P, P = I - n nᵀ) and that 2x2 symmetric matrix
// is decomposed in closed form. k_max is the eigenvalue of larger magnitude (|k_min| <= |k_max|,
// ties: the larger signed value) and t_min its eigenvector (the swapped pairing of (5.6));
// t_max = n x t_min carries k_min. At an umbilic (equal eigenvalues) t_min is b1 of
// tangent_basis(n): arbitrary but deterministic; the confidence (5.8) is what marks such places.
Frame decompose(const Tensor& t, const Vec3& n) {
  Frame fr;
  if (dot(n, n) == 0.0) return fr;  // isolated or all-degenerate vertex: no frame
  Vec3 b1, b2;
  tangent_basis(n, b1, b2);
  const Vec3 tb1 = tensor_times(t, b1);
  const double a = dot(b1, tb1), b = dot(b2, tb1), c = dot(b2, tensor_times(t, b2));
  const double m = 0.5 * (a + c), h = 0.5 * (a - c);
  const double d = std::sqrt(h * h + b * b);
  const double phi = 0.5 * std::atan2(2.0 * b, a - c);  // eigenvector of m + d
  const Vec3 e_plus = std::cos(phi) * b1 + std::sin(phi) * b2;
  const Vec3 e_minus = cross(n, e_plus);
  if (m >= 0.0) {
    fr.k_max = m + d;
    fr.k_min = m - d;
    fr.t_min = e_plus;
  } else {
    fr.k_max = m - d;
    fr.k_min = m + d;
    fr.t_min = e_minus;
  }
  fr.t_max = cross(n, fr.t_min);
  return fr;
}

// Area of triangle (p0, p1, p2) (unit normal n) inside the ball of radius r about c: the ball
// meets the triangle's plane in a disk (centre q, radius rho); the area is the sum over the
// triangle's edges of the signed area of (q, edge) inside that disk: straight pieces inside,
// circular sectors outside.
double triangle_ball_area(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& n, const Vec3& c, double r) {
  const double dist = dot(c - p0, n);
  const double rho2 = r * r - dist * dist;
  if (rho2 <= 0.0) return 0.0;
  const Vec3 q = c - dist * n;
  const Vec3 p[3] = {p0 - q, p1 - q, p2 - q};
  double area = 0.0;
  auto piece = [&](const Vec3& a, const Vec3& b) {
    const Vec3 mid = 0.5 * (a + b);
    const double cr = dot(cross(a, b), n);
    if (dot(mid, mid) <= rho2) return 0.5 * cr;
    return 0.5 * rho2 * std::atan2(cr, dot(a, b));
  };
  for (int i = 0; i < 3; ++i) {
    const Vec3& a = p[i];
    const Vec3& b = p[(i + 1) % 3];
    const Vec3 d = b - a;
    const double A = dot(d, d), B = dot(a, d), C = dot(a, a) - rho2;
    double ts[2];
    int nt = 0;
    const double disc = B * B - A * C;
    if (A > 0.0 && disc > 0.0) {
      const double s = std::sqrt(disc);
      const double t0 = (-B - s) / A, t1 = (-B + s) / A;
      if (t0 > 0.0 && t0 < 1.0) ts[nt++] = t0;
      if (t1 > 0.0 && t1 < 1.0) ts[nt++] = t1;
    }
    Vec3 prev = a;
    for (int k = 0; k < nt; ++k) {
      const Vec3 x = a + ts[k] * d;
      area += piece(prev, x);
      prev = x;
    }
    area += piece(prev, b);
  }
  return std::max(0.0, area);
}

// Length of segment (a, b) inside the ball of radius r about c: |e ∩ Γ| of (5.2).
double segment_ball_length(const Vec3& a, const Vec3& b, const Vec3& c, double r) {
  const Vec3 d = b - a, ac = a - c;
  const double A = dot(d, d);
  if (A == 0.0) return 0.0;
  const double B = dot(ac, d), C = dot(ac, ac) - r * r;
  const double disc = B * B - A * C;
  if (disc <= 0.0) return 0.0;
  const double s = std::sqrt(disc);
  const double t0 = std::max(0.0, (-B - s) / A), t1 = std::min(1.0, (-B + s) / A);
  return t1 > t0 ? (t1 - t0) * std::sqrt(A) : 0.0;
}

void check_input(const PolygonMesh& mesh, const CurvatureOptions& o, const std::vector<uint8_t>* host) {
  auto bad_option = [](const char* what) { fail(Status::invalid_argument, std::string("curvature field: ") + what); };
  if (o.disk_radius_bbox > 0.0 ? !std::isfinite(o.disk_radius_bbox)
                               : !(std::isfinite(o.disk_radius) && o.disk_radius > 0.0))
    bad_option("disk_radius must be finite and > 0 (or disk_radius_bbox > 0 and finite)");
  if (std::isnan(o.disk_radius_bbox)) bad_option("disk_radius_bbox is NaN");
  if (!(o.feature_angle_degrees <= 180.0)) bad_option("feature_angle_degrees must be <= 180 (< 0: off)");
  if (o.smoothing_iterations < 0 || o.smoothing_iterations > 100000)
    bad_option("smoothing_iterations must be in [0, 100000]");
  if (o.threads < 0) bad_option("threads must be >= 0");
  detail::check_mesh_arrays(mesh);
  if (mesh.num_faces() == 0) fail(Status::invalid_mesh, "curvature field: the mesh has no faces");
  if (host && host->size() != mesh.num_face_vertices())
    fail(Status::invalid_argument, "curvature field: host feature flags must have one entry per face corner (" +
                                       std::to_string(mesh.num_face_vertices()) + "), got " +
                                       std::to_string(host->size()));
  for (size_t v = 0; v < mesh.num_vertices(); ++v)
    if (!is_finite(mesh.positions[v]))
      fail(Status::invalid_mesh, "curvature field: vertex " + std::to_string(v) + " has a non-finite position");
  const size_t nv = mesh.num_vertices();
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    if (mesh.face_size(f) != 3)
      fail(Status::invalid_mesh, "curvature field: face " + std::to_string(f) + " has " +
                                     std::to_string(mesh.face_size(f)) + " vertices; triangles are required");
    for (int i = 0; i < 3; ++i)
      if (mesh.face_vertex(f, i) >= nv)
        fail(Status::invalid_mesh, "curvature field: face " + std::to_string(f) + " has an out-of-range vertex index");
    if (detail::find_repeated_vertex(mesh.face_begin(f), 3) != kNone)
      fail(Status::invalid_mesh, "curvature field: face " + std::to_string(f) + " repeats a vertex");
  }
}

// Everything the passes share.
struct Context {
  const PolygonMesh& mesh;
  detail::EdgeMap map;
  std::vector<Vec3> face_normal;       // unit (zero for zero-area faces)
  std::vector<Vec3> vertex_normal;     // unit area-weighted mean of the face normals
  std::vector<uint8_t> barrier;        // per edge
  std::vector<double> edge_theta;      // signed dihedral angle (5.1), 0 on barriers (freed once packed)
  std::vector<Vec3> edge_dir;          // unit direction lo -> hi (freed once packed)
  std::vector<uint32_t> vf_offsets, vf;  // vertex -> incident faces
  std::vector<uint32_t> vv_offsets, vv;  // vertex -> neighbour vertices (one ring)
  std::vector<uint8_t> on_feature;     // vertex incident to a barrier edge
  // What the disk traversal reads per edge and per face, packed (one or two cache lines each).
  struct DiskEdge {
    uint32_t lo, hi;
    uint32_t face[2];  // the two faces in the edge map's corner order (non-barrier edges only)
    double theta;      // edge_theta
    double length;     // |hi - lo|, as segment_ball_length computes it for a whole edge
    Vec3 dir;          // edge_dir
    uint8_t barrier;
  };
  struct DiskFace {
    Vec3 normal;     // face_normal
    double area;     // 0.5 |(q1 - q0) x (q2 - q0)|
    uint32_t v[3];   // corners
    uint32_t e[3];   // edges of the corners' half-edges
  };
  std::vector<DiskEdge> disk_edge;     // freed after the vertex tensors
  std::vector<DiskFace> disk_face;
  int threads = 1;                     // workers of the per-vertex / per-face loops

  explicit Context(const PolygonMesh& m) : mesh(m) {}
};

void build_context(Context& cx, const CurvatureOptions& o, const std::vector<uint8_t>* host) {
  const PolygonMesh& mesh = cx.mesh;
  const size_t nf = mesh.num_faces(), nv = mesh.num_vertices();
  detail::build_edge_map(cx.map, mesh, std::vector<uint8_t>(nf, 1));
  const detail::EdgeMap& map = cx.map;
  const size_t ne = map.num_edges();

  cx.face_normal.resize(nf);
  cx.vertex_normal.assign(nv, Vec3{});
  for (size_t f = 0; f < nf; ++f) {
    const Vec3 va = mesh.face_vector_area(f);
    // Zero-area faces (relative to their size) get no normal: they carry no bending.
    cx.face_normal[f] = detail::face_has_zero_area(mesh, f) ? Vec3{} : normalized(va);
    if (dot(cx.face_normal[f], cx.face_normal[f]) == 0.0) continue;
    for (int i = 0; i < 3; ++i) cx.vertex_normal[mesh.face_vertex(f, i)] += va;  // area weights
  }
  for (Vec3& n : cx.vertex_normal) n = normalized(n);

  // Barriers: host flags, detected features, boundary / non-manifold / inconsistently oriented.
  cx.barrier.assign(ne, 0);
  if (host)
    for (size_t c = 0; c < host->size(); ++c)
      if ((*host)[c]) cx.barrier[map.corner_edge[c]] = 1;
  if (o.feature_angle_degrees >= 0.0) {
    const std::vector<uint8_t> det = dihedral_feature_edges(map, cx.face_normal, o.feature_angle_degrees);
    for (size_t e = 0; e < ne; ++e) cx.barrier[e] |= det[e];
  }
  cx.edge_theta.assign(ne, 0.0);
  cx.edge_dir.resize(ne);
  for (size_t e = 0; e < ne; ++e) {
    const Vec3 a = mesh.positions[map.edge_lo[e]], b = mesh.positions[map.edge_hi[e]];
    cx.edge_dir[e] = normalized(b - a);
    if (map.valence(e) != 2) {
      cx.barrier[e] = 1;
      continue;
    }
    const uint32_t c0 = map.corners_begin(e)[0], c1 = map.corners_begin(e)[1];
    if (map.forward(c0) == map.forward(c1)) {  // both faces run the edge the same way
      cx.barrier[e] = 1;
      continue;
    }
    if (cx.barrier[e]) continue;
    const Vec3& n0 = cx.face_normal[map.corner_face[c0]];
    const Vec3& n1 = cx.face_normal[map.corner_face[c1]];
    if (dot(n0, n0) == 0.0 || dot(n1, n1) == 0.0) continue;
    // (5.1): signed dihedral angle; with e the direction of face 0's half-edge,
    // theta = atan2((n0 x n1)·e, n0·n1) > 0 on convex edges (outward normals), < 0 on concave.
    const Vec3 e0 = map.forward(c0) ? cx.edge_dir[e] : -cx.edge_dir[e];
    cx.edge_theta[e] = std::atan2(dot(cross(n0, n1), e0), dot(n0, n1));
  }

  cx.disk_edge.resize(ne);
  for (size_t e = 0; e < ne; ++e) {
    Context::DiskEdge& de = cx.disk_edge[e];
    de.lo = map.edge_lo[e];
    de.hi = map.edge_hi[e];
    const Vec3 d = mesh.positions[de.hi] - mesh.positions[de.lo];
    de.length = std::sqrt(dot(d, d));
    de.theta = cx.edge_theta[e];
    de.dir = cx.edge_dir[e];
    de.barrier = cx.barrier[e];
    de.face[0] = de.face[1] = kNone;
    if (!de.barrier) {  // valence 2 (other valences are barriers)
      de.face[0] = map.corner_face[map.corners_begin(e)[0]];
      de.face[1] = map.corner_face[map.corners_begin(e)[1]];
    }
  }
  // Only the packed copies are read from here on (memory: 1.6M edges on a 1M-triangle mesh).
  std::vector<double>().swap(cx.edge_theta);
  std::vector<Vec3>().swap(cx.edge_dir);
  cx.disk_face.resize(nf);
  for (size_t f = 0; f < nf; ++f) {
    Context::DiskFace& df = cx.disk_face[f];
    const uint32_t c0 = mesh.face_offsets[f];
    for (int k = 0; k < 3; ++k) {
      df.v[k] = mesh.face_vertices[c0 + k];
      df.e[k] = map.corner_edge[c0 + k];
    }
    const Vec3& q0 = mesh.positions[df.v[0]];
    const Vec3& q1 = mesh.positions[df.v[1]];
    const Vec3& q2 = mesh.positions[df.v[2]];
    df.normal = cx.face_normal[f];
    df.area = 0.5 * norm(cross(q1 - q0, q2 - q0));
  }

  // Vertex -> faces and vertex -> vertices (CSR).
  cx.vf_offsets.assign(nv + 1, 0);
  for (uint32_t v : mesh.face_vertices) ++cx.vf_offsets[v + 1];
  for (size_t v = 0; v < nv; ++v) cx.vf_offsets[v + 1] += cx.vf_offsets[v];
  cx.vf.resize(mesh.face_vertices.size());
  {
    std::vector<uint32_t> fill(cx.vf_offsets.begin(), cx.vf_offsets.end() - 1);
    for (size_t f = 0; f < nf; ++f)
      for (int i = 0; i < 3; ++i) cx.vf[fill[mesh.face_vertex(f, i)]++] = uint32_t(f);
  }
  cx.vv_offsets.assign(nv + 1, 0);
  cx.on_feature.assign(nv, 0);
  for (size_t e = 0; e < ne; ++e) {
    ++cx.vv_offsets[map.edge_lo[e] + 1];
    ++cx.vv_offsets[map.edge_hi[e] + 1];
    if (cx.barrier[e]) cx.on_feature[map.edge_lo[e]] = cx.on_feature[map.edge_hi[e]] = 1;
  }
  for (size_t v = 0; v < nv; ++v) cx.vv_offsets[v + 1] += cx.vv_offsets[v];
  cx.vv.resize(2 * ne);
  {
    std::vector<uint32_t> fill(cx.vv_offsets.begin(), cx.vv_offsets.end() - 1);
    for (size_t e = 0; e < ne; ++e) {
      cx.vv[fill[map.edge_lo[e]]++] = map.edge_hi[e];
      cx.vv[fill[map.edge_hi[e]]++] = map.edge_lo[e];
    }
  }
}

// Per-worker scratch of the disk traversal: stamps per face, edge and vertex, the face queue,
// and per vertex its squared distance to the disk's centre (valid where vertex_stamp matches).
struct DiskScratch {
  struct VertexDistance {
    uint32_t stamp;
    double d2;
  };
  std::vector<uint32_t> face_stamp, edge_stamp, queue;
  std::vector<VertexDistance> vertex;
  uint32_t stamp = 0;
};

// Squared distance of vertex u to c, computed once per disk: dot(q - c, q - c) as every test of
// the traversal spells it.
inline double disk_d2(const PolygonMesh& mesh, DiskScratch& s, uint32_t u, const Vec3& c, uint32_t st) {
  DiskScratch::VertexDistance& vd = s.vertex[u];
  if (vd.stamp != st) {
    vd.stamp = st;
    const Vec3 q = mesh.positions[u];
    vd.d2 = dot(q - c, q - c);
  }
  return vd.d2;
}

// (5.2) at vertex v: Γ is the connected part of M ∩ Ball(p_v, r) that contains v, where
// "connected" means reachable from v's incident faces by crossing non-barrier edges through the
// ball (so Γ never reaches across a feature curve: the trimming of Fig. 5.4b). Distances are
// Euclidean within that connected region [J]: for r of a few edge lengths on a surface whose
// curvature radius is much larger than r they equal the geodesic ones to O(r³κ²), and the
// clipping of edges (|e ∩ Γ|) and faces (|Γ|) to a ball is exact.
Tensor vertex_tensor(const Context& cx, uint32_t v, double r, DiskScratch& s) {
  const PolygonMesh& mesh = cx.mesh;
  if (++s.stamp == 0) {  // wrapped: clear
    std::fill(s.face_stamp.begin(), s.face_stamp.end(), 0);
    std::fill(s.edge_stamp.begin(), s.edge_stamp.end(), 0);
    for (DiskScratch::VertexDistance& vd : s.vertex) vd.stamp = 0;
    s.stamp = 1;
  }
  const uint32_t st = s.stamp;
  const Vec3 c = mesh.positions[v];
  s.queue.clear();
  for (uint32_t i = cx.vf_offsets[v]; i < cx.vf_offsets[v + 1]; ++i) {
    const uint32_t f = cx.vf[i];
    if (s.face_stamp[f] != st) {
      s.face_stamp[f] = st;
      s.queue.push_back(f);
    }
  }
  Tensor t{};
  double area = 0.0;
  const double r2 = r * r;
  // An edge whose two ends lie inside the ball by this relative margin is inside whole: there
  // segment_ball_length's clamped roots are exactly 0 and 1 (their rounding error is ~1e-16 of
  // the margin's effect), so its value is the edge length, bit for bit.
  const double r2_inner = r2 * (1.0 - 1e-6);
  for (size_t qi = 0; qi < s.queue.size(); ++qi) {
    const uint32_t f = s.queue[qi];
    const Context::DiskFace& df = cx.disk_face[f];
    const Vec3& n = df.normal;
    const uint32_t v0 = df.v[0], v1 = df.v[1], v2 = df.v[2];
    if (dot(n, n) > 0.0) {  // zero-area faces add no area
      if (disk_d2(mesh, s, v0, c, st) <= r2 && disk_d2(mesh, s, v1, c, st) <= r2 && disk_d2(mesh, s, v2, c, st) <= r2)
        area += df.area;  // the ball is convex: the whole face is inside
      else
        area += triangle_ball_area(mesh.positions[v0], mesh.positions[v1], mesh.positions[v2], n, c, r);
    }
    for (uint32_t k = 0; k < 3; ++k) {
      const uint32_t e = df.e[k];
      if (s.edge_stamp[e] == st) continue;
      s.edge_stamp[e] = st;
      const Context::DiskEdge& de = cx.disk_edge[e];
      const double len = disk_d2(mesh, s, de.lo, c, st) <= r2_inner && disk_d2(mesh, s, de.hi, c, st) <= r2_inner
                             ? de.length
                             : segment_ball_length(mesh.positions[de.lo], mesh.positions[de.hi], c, r);
      if (len <= 0.0) continue;
      if (de.theta != 0.0) add_outer(t, de.dir, len * de.theta);
      if (de.barrier) continue;
      for (const uint32_t g : de.face) {
        if (s.face_stamp[g] != st) {
          s.face_stamp[g] = st;
          s.queue.push_back(g);
        }
      }
    }
  }
  if (area > 0.0)
    for (double& x : t) x /= area;
  else
    t = Tensor{};
  return t;
}

// Flattening (5.7) of the frame of vertex v into the unfolding of face f, where v is corner k
// and P[0..2] are the face's unfolded corners: pick the face edge at v that makes the smallest
// angle with v's tangent plane, ξ = signed angle (about n) from its projection to t_min, and
// rotate the edge's 2D image by ξ. The unfolding has the face's orientation; when v's normal
// points against the face normal the rotation sense flips.
std::array<double, 2> flatten_t_min(const PolygonMesh& mesh, const Vec3& fn, const Vec3& n, const Vec3& t_min,
                                    uint32_t f, int k, const std::array<std::array<double, 2>, 3>& P) {
  if (dot(n, n) == 0.0 || dot(t_min, t_min) == 0.0) return {0.0, 0.0};
  const Vec3 pv = mesh.positions[mesh.face_vertex(f, k)];
  int best = -1;
  double best_sin = 2.0;
  for (int j : {(k + 1) % 3, (k + 2) % 3}) {
    const Vec3 e = normalized(mesh.positions[mesh.face_vertex(f, j)] - pv);
    const double sn = std::fabs(dot(e, n));
    if (sn < best_sin) {
      best_sin = sn;
      best = j;
    }
  }
  const Vec3 e3 = mesh.positions[mesh.face_vertex(f, best)] - pv;
  const Vec3 proj = e3 - dot(e3, n) * n;
  double xi = std::atan2(dot(cross(proj, t_min), n), dot(proj, t_min));
  if (dot(fn, n) < 0.0) xi = -xi;
  double ex = P[best][0] - P[k][0], ey = P[best][1] - P[k][1];
  const double len = std::sqrt(ex * ex + ey * ey);
  if (len == 0.0) return {0.0, 0.0};
  ex /= len;
  ey /= len;
  const double cs = std::cos(xi), sn = std::sin(xi);
  return {cs * ex - sn * ey, sn * ex + cs * ey};
}

std::array<std::array<double, 2>, 3> unfold(const PolygonMesh& mesh, uint32_t f) {
  const Vec3 a = mesh.positions[mesh.face_vertex(f, 0)], b = mesh.positions[mesh.face_vertex(f, 1)],
             c = mesh.positions[mesh.face_vertex(f, 2)];
  const double lab = distance(a, b);
  const Vec3 u = lab > 0 ? (b - a) * (1.0 / lab) : Vec3{};
  const double cu = dot(c - a, u);
  const double cv = norm((c - a) - cu * u);
  return {{{0.0, 0.0}, {lab, 0.0}, {cu, cv}}};
}

// Λ(f) of (5.8): unfold f on its own, flatten the t_min of its three vertices, and take the
// smallest |cos| of the angles between the three direction lines. 0 when a vertex has no frame.
double face_confidence(const PolygonMesh& mesh, const std::vector<Vec3>& fnormal, const std::vector<Vec3>& vnormal,
                       const std::vector<Vec3>& t_min, uint32_t f) {
  const auto P = unfold(mesh, f);
  std::array<double, 2> d[3];
  for (int k = 0; k < 3; ++k) {
    const uint32_t v = mesh.face_vertex(f, k);
    d[k] = flatten_t_min(mesh, fnormal[f], vnormal[v], t_min[v], f, k, P);
    if (d[k][0] == 0.0 && d[k][1] == 0.0) return 0.0;
  }
  double lam = 1.0;
  for (int j = 0; j < 3; ++j) {
    const auto& p = d[j];
    const auto& q = d[(j + 1) % 3];
    lam = std::min(lam, std::fabs(p[0] * q[0] + p[1] * q[1]));
  }
  return std::min(1.0, lam);
}

// Directions of every vertex from `tensors`, then Λ(f) and Λ(v) (mean over adjacent faces).
void directions_and_confidence(const Context& cx, const std::vector<Tensor>& tensors, std::vector<Frame>& frames,
                               std::vector<Vec3>& t_min, std::vector<double>& face_conf,
                               std::vector<double>& vertex_conf) {
  const PolygonMesh& mesh = cx.mesh;
  const size_t nv = mesh.num_vertices(), nf = mesh.num_faces();
  frames.resize(nv);
  t_min.resize(nv);
  // Every entry depends on its own index only: contiguous ranges per worker, any thread count.
  parallel_ranges(nv, cx.threads, [&](size_t begin, size_t end) {
    for (size_t v = begin; v < end; ++v) {
      frames[v] = decompose(tensors[v], cx.vertex_normal[v]);
      t_min[v] = frames[v].t_min;
    }
  });
  face_conf.resize(nf);
  parallel_ranges(nf, cx.threads, [&](size_t begin, size_t end) {
    for (size_t f = begin; f < end; ++f)
      face_conf[f] = face_confidence(mesh, cx.face_normal, cx.vertex_normal, t_min, uint32_t(f));
  });
  vertex_conf.assign(nv, 0.0);
  parallel_ranges(nv, cx.threads, [&](size_t begin, size_t end) {
    for (size_t v = begin; v < end; ++v) {
      const uint32_t b = cx.vf_offsets[v], e = cx.vf_offsets[v + 1];
      if (b == e) continue;
      double sum = 0.0;
      for (uint32_t i = b; i < e; ++i) sum += face_conf[cx.vf[i]];
      vertex_conf[v] = sum / double(e - b);
    }
  });
}

}  // namespace

CurvatureField estimate_curvature_field(const PolygonMesh& mesh, const CurvatureOptions& options,
                                        const std::vector<uint8_t>* host_feature_edges, const TaskMonitor& monitor) {
  check_input(mesh, options, host_feature_edges);
  monitor.report("curvature field", 0.0);
  Context cx(mesh);
  cx.threads = resolve_threads(options.threads);
  build_context(cx, options, host_feature_edges);
  const detail::EdgeMap& map = cx.map;
  const size_t nv = mesh.num_vertices(), nf = mesh.num_faces(), ne = map.num_edges();

  CurvatureField out;
  double r = 0.0;
  if (options.disk_radius_bbox > 0.0) {
    r = options.disk_radius_bbox * mesh.bounding_box().diagonal();
  } else {
    double total = 0.0;
    for (size_t e = 0; e < ne; ++e) total += distance(mesh.positions[map.edge_lo[e]], mesh.positions[map.edge_hi[e]]);
    r = options.disk_radius * (ne ? total / double(ne) : 0.0);
  }
  if (!(r > 0.0) || !std::isfinite(r))
    fail(Status::invalid_mesh, "curvature field: the disk radius is zero or not finite (degenerate mesh?)");
  out.disk_radius = r;

  // (5.2) per vertex: chunks with progress/cancel between them, contiguous ranges per worker.
  // Vertices are visited in Morton (Z-curve) order of their positions: consecutive disks then
  // touch mostly the same faces, edges and stamps (cache-resident), whatever the input's vertex
  // order; each tensor depends on its own vertex only, so the order changes no result.
  const std::vector<uint32_t> order = detail::morton_order(mesh.positions, mesh.bounding_box());
  std::vector<Tensor> tensors(nv);
  const int threads = resolve_threads(options.threads);
  const size_t workers = size_t(std::max(1, threads));
  std::vector<DiskScratch> scratch(workers);
  const size_t chunk = 4096;
  for (size_t begin = 0; begin < nv; begin += chunk) {
    monitor.report("curvature field: vertex tensors", 0.8 * double(begin) / double(nv));
    const size_t end = std::min(nv, begin + chunk);
    const size_t w = std::min(workers, (end - begin + 63) / 64);
    run_ranges(end - begin, w, [&](size_t b, size_t e, size_t worker) {
      DiskScratch& s = scratch[worker];
      if (s.face_stamp.size() != nf) {
        s.face_stamp.assign(nf, 0);
        s.edge_stamp.assign(ne, 0);
        s.vertex.assign(nv, DiskScratch::VertexDistance{0, 0.0});
      }
      for (size_t i = begin + b; i < begin + e; ++i) tensors[order[i]] = vertex_tensor(cx, order[i], r, s);
    });
  }
  scratch.clear();
  std::vector<Context::DiskEdge>().swap(cx.disk_edge);  // not needed after (5.2)
  std::vector<Context::DiskFace>().swap(cx.disk_face);
  out.raw_vertex_tensor = tensors;

  std::vector<Frame> frames;
  std::vector<Vec3> t_min;
  std::vector<double> face_conf, vertex_conf;
  directions_and_confidence(cx, tensors, frames, t_min, face_conf, vertex_conf);
  out.raw_vertex_t_min = t_min;
  out.raw_face_confidence = face_conf;

  // (5.9) confidence-weighted Laplacian on the full 3x3 tensors, Λ recomputed after every
  // iteration [J] (so directions keep propagating into isotropic regions as they become
  // coherent). Σ Λ(v_ij) = 0: the plain mean of the neighbours [J]. A vertex off the feature
  // curves takes no tensor from vertices on them (their disks span both sides) [J].
  std::vector<Tensor> next(nv);
  for (int it = 0; it < options.smoothing_iterations; ++it) {
    monitor.report("curvature field: smoothing", 0.8 + 0.15 * double(it) / double(options.smoothing_iterations));
    parallel_ranges(nv, cx.threads, [&](size_t vbegin, size_t vend) {
      for (size_t v = vbegin; v < vend; ++v) {
        Tensor sum{}, plain{};
        double wsum = 0.0;
        int count = 0;
        for (uint32_t i = cx.vv_offsets[v]; i < cx.vv_offsets[v + 1]; ++i) {
          const uint32_t u = cx.vv[i];
          if (!cx.on_feature[v] && cx.on_feature[u]) continue;
          add_scaled(sum, tensors[u], vertex_conf[u]);
          add_scaled(plain, tensors[u], 1.0);
          wsum += vertex_conf[u];
          ++count;
        }
        if (count == 0) {
          next[v] = tensors[v];
          continue;
        }
        Tensor mean = plain;
        if (wsum > 0.0)
          for (int k = 0; k < 6; ++k) mean[k] = sum[k] / wsum;
        else
          for (int k = 0; k < 6; ++k) mean[k] = plain[k] / double(count);
        const double self = 0.5 * vertex_conf[v];
        for (int k = 0; k < 6; ++k) next[v][k] = self * tensors[v][k] + (1.0 - self) * mean[k];
      }
    });
    tensors.swap(next);
    directions_and_confidence(cx, tensors, frames, t_min, face_conf, vertex_conf);
  }
  monitor.report("curvature field: frames", 0.95);

  // Re-aligned per-vertex frames (§5.4.1.1) and tensors κ_min t_max t_maxᵀ + κ_max t_min t_minᵀ.
  out.vertex_normal = cx.vertex_normal;
  out.vertex_tensor.assign(nv, Tensor{});
  out.vertex_t_min.resize(nv);
  out.vertex_t_max.resize(nv);
  out.vertex_k_min.resize(nv);
  out.vertex_k_max.resize(nv);
  for (size_t v = 0; v < nv; ++v) {
    const Frame& fr = frames[v];
    out.vertex_t_min[v] = fr.t_min;
    out.vertex_t_max[v] = fr.t_max;
    out.vertex_k_min[v] = fr.k_min;
    out.vertex_k_max[v] = fr.k_max;
    add_outer(out.vertex_tensor[v], fr.t_max, fr.k_min);
    add_outer(out.vertex_tensor[v], fr.t_min, fr.k_max);
  }
  out.vertex_confidence = vertex_conf;
  out.face_confidence = face_conf;

  // Per face: (5.3) at the centroid, decomposed against the face normal.
  out.face_tensor.resize(nf);
  out.face_t_min.resize(nf);
  out.face_t_max.resize(nf);
  out.face_k_min.resize(nf);
  out.face_k_max.resize(nf);
  parallel_ranges(nf, cx.threads, [&](size_t fbegin, size_t fend) {
    for (size_t f = fbegin; f < fend; ++f) {
      Tensor t{};
      for (int i = 0; i < 3; ++i) add_scaled(t, out.vertex_tensor[mesh.face_vertex(f, i)], 1.0 / 3.0);
      out.face_tensor[f] = t;
      const Frame fr = decompose(t, cx.face_normal[f]);
      out.face_t_min[f] = fr.t_min;
      out.face_t_max[f] = fr.t_max;
      out.face_k_min[f] = fr.k_min;
      out.face_k_max[f] = fr.k_max;
    }
  });

  out.barrier_edges.resize(mesh.num_face_vertices());
  for (size_t c = 0; c < out.barrier_edges.size(); ++c) out.barrier_edges[c] = cx.barrier[map.corner_edge[c]];
  monitor.report("curvature field", 1.0);
  return out;
}

CurvatureField::Tensor interpolate_tensor(const PolygonMesh& mesh, const CurvatureField& field, uint32_t face,
                                          double u, double v, double w) {
  if (face >= mesh.num_faces() || mesh.face_size(face) != 3 || field.vertex_tensor.size() != mesh.num_vertices())
    fail(Status::invalid_argument, "interpolate_tensor: face out of range, not a triangle, or field of another mesh");
  const double bw[3] = {u, v, w};
  CurvatureField::Tensor t{};
  for (int i = 0; i < 3; ++i) {
    const uint32_t vi = mesh.face_vertex(face, i);
    if (vi >= field.vertex_tensor.size()) fail(Status::invalid_argument, "interpolate_tensor: vertex out of range");
    add_scaled(t, field.vertex_tensor[vi], bw[i]);
  }
  return t;
}

FlattenedFace flatten_face(const PolygonMesh& mesh, const CurvatureField& field, uint32_t face) {
  if (face >= mesh.num_faces() || mesh.face_size(face) != 3 || field.vertex_t_min.size() != mesh.num_vertices() ||
      field.vertex_normal.size() != mesh.num_vertices() || field.vertex_k_min.size() != mesh.num_vertices() ||
      field.vertex_k_max.size() != mesh.num_vertices())
    fail(Status::invalid_argument, "flatten_face: face out of range, not a triangle, or field of another mesh");
  for (int i = 0; i < 3; ++i)
    if (mesh.face_vertex(face, i) >= mesh.num_vertices())
      fail(Status::invalid_argument, "flatten_face: vertex out of range");
  FlattenedFace out;
  out.corner = unfold(mesh, face);
  const Vec3 fn = normalized(mesh.face_vector_area(face));
  for (int k = 0; k < 3; ++k) {
    const uint32_t v = mesh.face_vertex(face, k);
    const auto d = flatten_t_min(mesh, fn, field.vertex_normal[v], field.vertex_t_min[v], face, k, out.corner);
    out.t_min[k] = d;
    // T̄ = Q̄ diag(k_min, k_max) Q̄ᵀ, Q̄ = [t̄_max | t̄_min], t̄_max = rot(t̄_min, π/2)   (5.7)
    const double mx = -d[1], my = d[0];
    const double kmin = field.vertex_k_min[v], kmax = field.vertex_k_max[v];
    out.tensor[k] = {kmin * mx * mx + kmax * d[0] * d[0], kmin * my * my + kmax * d[1] * d[1],
                     kmin * mx * my + kmax * d[0] * d[1]};
  }
  return out;
}

CAGEKIT_NAMESPACE_END
