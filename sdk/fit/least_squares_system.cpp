// SPDX-License-Identifier: GPL-3.0-or-later
#include "fit/least_squares_system.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <string>

#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {
using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplet = Eigen::Triplet<double>;

// Umbrella Laplacian over the cage's edges (duplicates from the two faces of an edge removed).
SparseMatrix umbrella_laplacian(const PolygonMesh& mesh) {
  const size_t n = mesh.num_vertices();
  std::vector<std::vector<uint32_t>> neighbours(n);
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t k = mesh.face_size(f);
    for (uint32_t c = 0; c < k; ++c) {
      const uint32_t a = mesh.face_vertex(f, c), b = mesh.face_vertex(f, (c + 1) % k);
      neighbours[a].push_back(b);
      neighbours[b].push_back(a);
    }
  }
  std::vector<Triplet> triplets;
  for (size_t i = 0; i < n; ++i) {
    auto& nb = neighbours[i];
    std::sort(nb.begin(), nb.end());
    nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
    if (nb.empty()) continue;
    triplets.emplace_back(int(i), int(i), 1.0);
    for (uint32_t j : nb) triplets.emplace_back(int(i), int(j), -1.0 / double(nb.size()));
  }
  SparseMatrix L(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  L.setFromTriplets(triplets.begin(), triplets.end());
  return L;
}

// The squared-distance-like variant: residual r_i = A_i c - p_i weighted by
// W_i = n n^T + w (I - n n^T) (n = unit normal of the current surface at t_i). The coordinates
// couple: 3 rows per sample (W_i^(1/2) = n n^T + sqrt(w) (I - n n^T)), 3n unknowns.
std::vector<Vec3> solve_control_points_coupled(const SubdivisionSurface& surface, const Cage& cage,
                                               const std::vector<Vec3>& current_control,
                                               const std::vector<Vec3>& samples,
                                               const std::vector<FootPoint>& foot_points, double smoothness,
                                               const std::vector<bool>& fixed, double w) {
  const int n = int(surface.num_control_vertices());
  const int unknowns = 3 * n;
  const double sw = std::sqrt(w);
  std::vector<Triplet> triplets;
  triplets.reserve(samples.size() * 9 * 20);
  Eigen::VectorXd rhs(Eigen::Index(3 * samples.size()));
  for (size_t i = 0; i < samples.size(); ++i) {
    const FootPoint& t = foot_points[i];
    const BasisWeights basis = surface.basis(t.ptex_face, t.u, t.v);
    Vec3 du, dv;
    for (size_t k = 0; k < basis.indices.size(); ++k) {
      du += basis.wu[k] * current_control[basis.indices[k]];
      dv += basis.wv[k] * current_control[basis.indices[k]];
    }
    const Vec3 normal = normalized(cross(du, dv));
    double W[3][3];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) W[r][c] = normal[r] * normal[c] * (1 - sw) + (r == c ? sw : 0.0);
    for (int r = 0; r < 3; ++r) {
      const int row = int(3 * i) + r;
      rhs(row) = W[r][0] * samples[i].x + W[r][1] * samples[i].y + W[r][2] * samples[i].z;
      for (size_t k = 0; k < basis.indices.size(); ++k) {
        if (basis.w[k] == 0) continue;
        for (int c = 0; c < 3; ++c)
          if (W[r][c] != 0) triplets.emplace_back(row, int(3 * basis.indices[k]) + c, basis.w[k] * W[r][c]);
      }
    }
  }
  SparseMatrix B(Eigen::Index(3 * samples.size()), unknowns);
  B.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::VectorXd C(unknowns);
  for (int j = 0; j < n; ++j)
    for (int c = 0; c < 3; ++c) C(3 * j + c) = current_control[j][c];
  const SparseMatrix Bt = B.transpose();
  SparseMatrix M = Bt * B;
  double trace = 0;
  for (int j = 0; j < unknowns; ++j) trace += M.coeff(j, j);
  const double scale = unknowns > 0 ? std::max(trace / n, 1e-300) : 1.0;  // per vertex, as in the split path
  const double mu = 1e-12 * scale;
  Eigen::VectorXd b = Bt * rhs + mu * C;
  if (smoothness > 0) {
    const SparseMatrix L = umbrella_laplacian(cage.mesh);
    std::vector<Triplet> lt;
    for (int k = 0; k < L.outerSize(); ++k)
      for (SparseMatrix::InnerIterator it(L, k); it; ++it)
        for (int c = 0; c < 3; ++c) lt.emplace_back(int(3 * it.row()) + c, int(3 * it.col()) + c, it.value());
    SparseMatrix L3(unknowns, unknowns);
    L3.setFromTriplets(lt.begin(), lt.end());
    M += (smoothness * scale / 3) * SparseMatrix(L3.transpose() * L3);
  }
  SparseMatrix I(unknowns, unknowns);
  I.setIdentity();
  M += mu * I;

  std::vector<int> free_index(unknowns, -1);
  int free_count = 0;
  for (int j = 0; j < unknowns; ++j)
    if (!fixed[j / 3]) free_index[j] = free_count++;
  std::vector<Vec3> result = current_control;
  if (free_count == 0) return result;
  Eigen::VectorXd C_fixed = C;
  for (int j = 0; j < unknowns; ++j)
    if (!fixed[j / 3]) C_fixed(j) = 0;
  b -= M * C_fixed;
  std::vector<Triplet> selection;
  for (int j = 0; j < unknowns; ++j)
    if (!fixed[j / 3]) selection.emplace_back(j, free_index[j], 1.0);
  SparseMatrix S(unknowns, free_count);
  S.setFromTriplets(selection.begin(), selection.end());
  const SparseMatrix M_ff = SparseMatrix(S.transpose() * M * S);
  const Eigen::VectorXd b_f = S.transpose() * b;
  Eigen::SimplicialLDLT<SparseMatrix> solver(M_ff);
  if (solver.info() != Eigen::Success)
    fail(Status::internal_error, "least squares: the normal equations could not be factorised");
  const Eigen::VectorXd x = solver.solve(b_f);
  if (solver.info() != Eigen::Success || !x.allFinite())
    fail(Status::internal_error, "least squares: the solve failed");
  for (int j = 0; j < unknowns; ++j)
    if (!fixed[j / 3]) result[j / 3][j % 3] = x(free_index[j]);
  return result;
}
}  // namespace

std::vector<Vec3> solve_control_points(const SubdivisionSurface& surface, const Cage& cage,
                                       const std::vector<Vec3>& current_control,
                                       const std::vector<Vec3>& samples,
                                       const std::vector<FootPoint>& foot_points, double smoothness,
                                       const std::vector<bool>& fixed, double tangential_weight) {
  const int n = int(surface.num_control_vertices());
  if (samples.size() != foot_points.size() || current_control.size() != size_t(n) ||
      fixed.size() != size_t(n) || cage.mesh.num_vertices() != size_t(n))
    fail(Status::invalid_argument, "least squares: inconsistent sizes");
  if (!(smoothness >= 0)) fail(Status::invalid_argument, "least squares: smoothness must be >= 0");
  if (!(tangential_weight >= 0 && tangential_weight <= 1))
    fail(Status::invalid_argument, "least squares: tangential_weight must be in [0, 1]");
  if (tangential_weight < 1)
    return solve_control_points_coupled(surface, cage, current_control, samples, foot_points, smoothness, fixed,
                                         tangential_weight);

  // A (N x n), ~16 non-zeros per row.
  std::vector<Triplet> triplets;
  triplets.reserve(samples.size() * 20);
  for (size_t i = 0; i < samples.size(); ++i) {
    const FootPoint& t = foot_points[i];
    const BasisWeights basis = surface.basis(t.ptex_face, t.u, t.v);
    for (size_t k = 0; k < basis.indices.size(); ++k)
      if (basis.w[k] != 0) triplets.emplace_back(int(i), int(basis.indices[k]), basis.w[k]);
  }
  SparseMatrix A(int(samples.size()), n);
  A.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::MatrixXd P(samples.size(), 3), C(n, 3);
  for (size_t i = 0; i < samples.size(); ++i) P.row(Eigen::Index(i)) << samples[i].x, samples[i].y, samples[i].z;
  for (int j = 0; j < n; ++j) C.row(j) << current_control[j].x, current_control[j].y, current_control[j].z;

  const SparseMatrix At = A.transpose();
  SparseMatrix M = At * A;
  double trace = 0;
  for (int j = 0; j < n; ++j) trace += M.coeff(j, j);
  const double scale = n > 0 ? std::max(trace / n, 1e-300) : 1.0;
  const double mu = 1e-12 * scale;
  Eigen::MatrixXd b = At * P + mu * C;
  if (smoothness > 0) {
    const SparseMatrix L = umbrella_laplacian(cage.mesh);
    M += (smoothness * scale) * SparseMatrix(L.transpose() * L);
  }
  SparseMatrix I(n, n);
  I.setIdentity();
  M += mu * I;

  // Eliminate the fixed vertices: M_FF c_F = b_F - M_FX c_X.
  std::vector<int> free_index(n, -1);
  int free_count = 0;
  for (int j = 0; j < n; ++j)
    if (!fixed[j]) free_index[j] = free_count++;
  std::vector<Vec3> result = current_control;
  if (free_count == 0) return result;
  Eigen::MatrixXd C_fixed = C;
  for (int j = 0; j < n; ++j)
    if (!fixed[j]) C_fixed.row(j).setZero();
  b -= M * C_fixed;
  std::vector<Triplet> selection;
  for (int j = 0; j < n; ++j)
    if (!fixed[j]) selection.emplace_back(j, free_index[j], 1.0);
  SparseMatrix S(n, free_count);
  S.setFromTriplets(selection.begin(), selection.end());
  const SparseMatrix M_ff = SparseMatrix(S.transpose() * M * S);
  const Eigen::MatrixXd b_f = S.transpose() * b;

  Eigen::SimplicialLDLT<SparseMatrix> solver(M_ff);
  if (solver.info() != Eigen::Success)
    fail(Status::internal_error, "least squares: the normal equations could not be factorised");
  const Eigen::MatrixXd x = solver.solve(b_f);
  if (solver.info() != Eigen::Success || !x.allFinite())
    fail(Status::internal_error, "least squares: the solve failed");
  for (int j = 0; j < n; ++j)
    if (!fixed[j]) {
      const int k = free_index[j];
      result[j] = {x(k, 0), x(k, 1), x(k, 2)};
    }
  return result;
}

CAGEKIT_NAMESPACE_END
