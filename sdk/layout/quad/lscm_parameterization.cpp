// SPDX-License-Identifier: GPL-3.0-or-later
// Eigen's assertions throw instead of aborting: before any Eigen header.
#include "core/eigen_config.h"
#include "layout/quad/lscm_parameterization.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <string>

#include "core/edge_map.h"
#include "core/status.h"
#include "layout/common/triangle_mesh_input.h"

CAGEKIT_NAMESPACE_BEGIN
namespace {

using detail::kNone;

// Weight of the regularising edge Laplacian relative to the (dimensionless) LSCM rows.
constexpr double kLaplacianWeight = 1e-10;

// The region as its own mesh with local vertex ids, and its topology checks.
struct RegionMesh {
  PolygonMesh mesh;
  detail::EdgeMap edges;
  std::vector<uint32_t> boundary_vertices;
};

void build_region_mesh(const PolygonMesh& triangles, RegionParameterization& out, RegionMesh& region) {
  for (uint32_t f : out.faces)
    for (uint32_t i = 0; i < 3; ++i) out.vertices.push_back(triangles.face_vertex(f, i));
  std::sort(out.vertices.begin(), out.vertices.end());
  out.vertices.erase(std::unique(out.vertices.begin(), out.vertices.end()), out.vertices.end());
  for (uint32_t v : out.vertices) region.mesh.add_vertex(triangles.positions[v]);
  for (uint32_t f : out.faces)
    region.mesh.add_face({out.local_index(triangles.face_vertex(f, 0)), out.local_index(triangles.face_vertex(f, 1)),
                          out.local_index(triangles.face_vertex(f, 2))});
  FaceAdjacency adjacency;
  build_face_adjacency(adjacency, region.mesh);
  require_oriented_manifold_edges(adjacency.edges, "lscm parameterization");
  // Edge-connected?
  const size_t nf = region.mesh.num_faces();
  std::vector<uint8_t> seen(nf, 0);
  std::vector<uint32_t> stack{0};
  seen[0] = 1;
  size_t reached = 1;
  while (!stack.empty()) {
    const uint32_t f = stack.back();
    stack.pop_back();
    for (uint32_t k = adjacency.offsets[f]; k < adjacency.offsets[f + 1]; ++k)
      if (!seen[adjacency.neighbours[k]]) seen[adjacency.neighbours[k]] = 1, ++reached, stack.push_back(adjacency.neighbours[k]);
  }
  if (reached != nf) fail(Status::invalid_mesh, "lscm parameterization: the region is not edge-connected");
  region.edges = std::move(adjacency.edges);
  const detail::EdgeMap& edges = region.edges;
  // Boundary loops: components of the boundary-edge graph.
  detail::UnionFind loops(out.vertices.size());
  std::vector<uint8_t> on_boundary(out.vertices.size(), 0);
  size_t boundary_edges = 0;
  for (size_t e = 0; e < edges.num_edges(); ++e) {
    if (edges.valence(e) != 1) continue;
    ++boundary_edges;
    loops.unite(edges.edge_lo[e], edges.edge_hi[e]);
    on_boundary[edges.edge_lo[e]] = on_boundary[edges.edge_hi[e]] = 1;
  }
  if (boundary_edges == 0) fail(Status::invalid_mesh, "lscm parameterization: the region is closed (no boundary)");
  size_t num_loops = 0;
  for (uint32_t v = 0; v < out.vertices.size(); ++v)
    if (on_boundary[v]) {
      region.boundary_vertices.push_back(v);
      if (loops.find(v) == v) ++num_loops;
    }
  const long euler = long(out.vertices.size()) - long(edges.num_edges()) + long(nf);
  const long genus = (2 - euler - long(num_loops)) / 2;
  if (genus != 0)
    fail(Status::invalid_mesh, "lscm parameterization: the region has genus " + std::to_string(genus) +
                                   " (a disk with holes is required; split regions with handles)");
}

// Local orthonormal frame of triangle (p0, p1, p2): p0 at the origin, p1 on the +x axis.
void triangle_frame(const Vec3& p0, const Vec3& p1, const Vec3& p2, double x[3], double y[3]) {
  const Vec3 e1 = p1 - p0, e2 = p2 - p0;
  const Vec3 ex = normalized(e1);
  const Vec3 n = normalized(cross(e1, e2));
  const Vec3 ey = cross(n, ex);
  x[0] = y[0] = 0.0;
  x[1] = norm(e1), y[1] = 0.0;
  x[2] = dot(e2, ex), y[2] = dot(e2, ey);
}

// σ_max / σ_min of the 2x2 Jacobian and its determinant sign, from the two edge vectors in the
// triangle's plane (dx, dy) and in the domain (du, dv).
void jacobian_quality(const double x[3], const double y[3], const double u[3], const double v[3], double& ratio,
                      double& det) {
  const double a11 = x[1] - x[0], a12 = x[2] - x[0], a21 = y[1] - y[0], a22 = y[2] - y[0];
  const double b11 = u[1] - u[0], b12 = u[2] - u[0], b21 = v[1] - v[0], b22 = v[2] - v[0];
  const double inv = 1.0 / (a11 * a22 - a12 * a21);
  // J = B A^{-1}
  const double j11 = (b11 * a22 - b12 * a21) * inv, j12 = (-b11 * a12 + b12 * a11) * inv;
  const double j21 = (b21 * a22 - b22 * a21) * inv, j22 = (-b21 * a12 + b22 * a11) * inv;
  const double E = 0.5 * (j11 + j22), F = 0.5 * (j11 - j22), G = 0.5 * (j21 + j12), H = 0.5 * (j21 - j12);
  const double Q = std::hypot(E, H), R = std::hypot(F, G);
  det = j11 * j22 - j12 * j21;
  ratio = (Q - R) != 0.0 ? (Q + R) / std::abs(Q - R) : HUGE_VAL;
}

}  // namespace

uint32_t RegionParameterization::local_index(uint32_t vertex) const {
  const auto it = std::lower_bound(vertices.begin(), vertices.end(), vertex);
  return it != vertices.end() && *it == vertex ? uint32_t(it - vertices.begin()) : kNone;
}

double signed_domain_area(const RegionParameterization& parameterization, const std::vector<uint32_t>& loop) {
  double area = 0.0;
  for (size_t i = 0; i < loop.size(); ++i) {
    const uint32_t a = parameterization.local_index(loop[i]), b = parameterization.local_index(loop[(i + 1) % loop.size()]);
    if (a == kNone || b == kNone) fail(Status::invalid_argument, "signed domain area: a loop vertex is not in the region");
    const auto& p = parameterization.uv[a];
    const auto& q = parameterization.uv[b];
    area += p.x * q.y - p.y * q.x;
  }
  return 0.5 * area;
}

RegionParameterization parameterize_region_lscm(const PolygonMesh& triangles, const std::vector<uint32_t>& faces,
                                                const TaskMonitor& monitor) {
  require_triangle_mesh(triangles, "lscm parameterization");
  if (faces.empty()) fail(Status::invalid_argument, "lscm parameterization: the region has no faces");
  RegionParameterization out;
  out.faces = faces;
  std::sort(out.faces.begin(), out.faces.end());
  if (out.faces.back() >= triangles.num_faces())
    fail(Status::invalid_argument, "lscm parameterization: face " + std::to_string(out.faces.back()) + " is out of range");
  if (std::adjacent_find(out.faces.begin(), out.faces.end()) != out.faces.end())
    fail(Status::invalid_argument, "lscm parameterization: a face is listed twice");
  RegionMesh region;
  build_region_mesh(triangles, out, region);
  const PolygonMesh& mesh = region.mesh;
  const size_t n = out.vertices.size();
  monitor.report("lscm parameterization", 0.1);

  // Pins: the farthest pair of boundary vertices by a double sweep.
  auto farthest_from = [&](uint32_t a) {
    uint32_t best = a;
    for (uint32_t v : region.boundary_vertices)
      if (distance(mesh.positions[v], mesh.positions[a]) > distance(mesh.positions[best], mesh.positions[a])) best = v;
    return best;
  };
  const uint32_t pin0 = farthest_from(region.boundary_vertices.front());
  const uint32_t pin1 = farthest_from(pin0);
  const double d = distance(mesh.positions[pin0], mesh.positions[pin1]);
  if (!(d > 0.0)) fail(Status::invalid_mesh, "lscm parameterization: all boundary vertices coincide");
  out.pinned_vertices = {out.vertices[pin0], out.vertices[pin1]};

  // Unknowns: u of free vertices, then v of free vertices. Variable k of vertex i: u -> i, v -> n + i.
  std::vector<int> column(2 * n, -1);
  int free_count = 0;
  for (uint32_t i = 0; i < n; ++i)
    if (i != pin0 && i != pin1) column[i] = free_count++;
  for (uint32_t i = 0; i < n; ++i)
    if (i != pin0 && i != pin1) column[n + i] = free_count++;
  std::vector<double> pinned_value(2 * n, 0.0);
  pinned_value[pin1] = d;  // u(pin1) = d; all other pinned coordinates are 0

  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(mesh.num_faces() * 2 * 36 + region.edges.num_edges() * 8);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(free_count);
  // One least-squares row Σ coefficient[k] * variable[k] = 0, with `count` entries.
  auto add_row = [&](const size_t* var, const double* coefficient, int count) {
    double pinned_part = 0.0;
    for (int k = 0; k < count; ++k)
      if (column[var[k]] < 0) pinned_part += coefficient[k] * pinned_value[var[k]];
    for (int a = 0; a < count; ++a) {
      const int ca = column[var[a]];
      if (ca < 0) continue;
      rhs[ca] -= coefficient[a] * pinned_part;
      for (int b = 0; b < count; ++b)
        if (column[var[b]] >= 0) triplets.emplace_back(ca, column[var[b]], coefficient[a] * coefficient[b]);
    }
  };
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t* vi = mesh.face_begin(f);
    double x[3], y[3];
    triangle_frame(mesh.positions[vi[0]], mesh.positions[vi[1]], mesh.positions[vi[2]], x, y);
    const double twice_area = x[1] * y[2];
    const double longest = std::max({x[1], std::hypot(x[2], y[2]), std::hypot(x[2] - x[1], y[2])});
    if (!(twice_area > 1e-12 * longest * longest)) continue;  // zero-area: no conformal constraint
    const double scale = std::sqrt(0.5 * twice_area) / twice_area;
    size_t var[6];
    double row1[6], row2[6];
    for (int j = 0; j < 3; ++j) {
      // e_j: edge opposite corner j (from corner j+1 to corner j+2); ∇φ_j = rot90(e_j) / (2A).
      const double ex = x[(j + 2) % 3] - x[(j + 1) % 3], ey = y[(j + 2) % 3] - y[(j + 1) % 3];
      var[j] = vi[j], var[3 + j] = n + vi[j];
      row1[j] = -ey * scale, row1[3 + j] = -ex * scale;  // u_x − v_y
      row2[j] = ex * scale, row2[3 + j] = -ey * scale;   // u_y + v_x
    }
    add_row(var, row1, 6);
    add_row(var, row2, 6);
  }
  const double lap = std::sqrt(kLaplacianWeight);
  for (size_t e = 0; e < region.edges.num_edges(); ++e) {
    const uint32_t a = region.edges.edge_lo[e], b = region.edges.edge_hi[e];
    const double coefficient[2] = {lap, -lap};
    const size_t vu[2] = {a, b}, vv[2] = {n + a, n + b};
    add_row(vu, coefficient, 2);
    add_row(vv, coefficient, 2);
  }
  monitor.report("lscm parameterization", 0.3);
  Eigen::SparseMatrix<double> normal(free_count, free_count);
  normal.setFromTriplets(triplets.begin(), triplets.end());
  triplets = {};
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(normal);
  if (solver.info() != Eigen::Success)
    fail(Status::internal_error, "lscm parameterization: the normal equations could not be factorised");
  const Eigen::VectorXd solution = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !solution.allFinite())
    fail(Status::internal_error, "lscm parameterization: the normal equations could not be solved");
  monitor.report("lscm parameterization", 0.9);

  out.uv.assign(n, {0.0, 0.0});
  for (uint32_t i = 0; i < n; ++i) {
    out.uv[i].x = column[i] >= 0 ? solution[column[i]] : pinned_value[i];
    out.uv[i].y = column[n + i] >= 0 ? solution[column[n + i]] : pinned_value[n + i];
  }
  double weighted = 0.0, total_area = 0.0;
  out.max_conformal_distortion = 1.0;
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t* vi = mesh.face_begin(f);
    double x[3], y[3], u[3], v[3];
    triangle_frame(mesh.positions[vi[0]], mesh.positions[vi[1]], mesh.positions[vi[2]], x, y);
    const double area = 0.5 * x[1] * y[2];
    const double longest = std::max({x[1], std::hypot(x[2], y[2]), std::hypot(x[2] - x[1], y[2])});
    if (!(2.0 * area > 1e-12 * longest * longest)) continue;
    for (int j = 0; j < 3; ++j) u[j] = out.uv[vi[j]].x, v[j] = out.uv[vi[j]].y;
    double ratio, det;
    jacobian_quality(x, y, u, v, ratio, det);
    if (!(det > 0.0)) ++out.flipped_triangles;
    out.max_conformal_distortion = std::max(out.max_conformal_distortion, ratio);
    weighted += area * ratio;
    total_area += area;
  }
  out.mean_conformal_distortion = total_area > 0.0 ? weighted / total_area : 1.0;
  return out;
}

CAGEKIT_NAMESPACE_END
