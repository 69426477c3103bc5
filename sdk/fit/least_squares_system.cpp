// SPDX-License-Identifier: GPL-3.0-or-later
#include "fit/least_squares_system.h"

// eigen_config.h must come before any Eigen header.
#include "core/eigen_config.h"

#include <Eigen/Sparse>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>

#include "core/memory_budget.h"
#include "core/parallel_for.h"
#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {
using SparseMatrix = Eigen::SparseMatrix<double>;
// Largest number of free control vertices for the dense per-thread normal-equation
// accumulators (8 MB each at the limit).
constexpr size_t kDenseNormalEquationsLimit = 1024;
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
// The Laplacian rows' targets. Row j weighs lambda_j |(L c)_j|^2 (fairing, towards the
// neighbours' average) + lambda_w,j |(L c)_j - t0_j|^2 (weak support), together
// w_j |(L c)_j - t_j|^2 + const with w_j = lambda_j + lambda_w,j and t_j = lambda_w,j / w_j t0_j.
// A weakly supported vertex is pulled towards its neighbours' average (t0 = 0) when its cluster
// of weakly supported vertices (connected by cage edges) touches a supported or fixed vertex:
// the neighbours anchor it, and the average smooths folds the data cannot see. A cluster
// without any anchor (a speck of a component with a sample or two) would collapse to one point
// that way: its vertices keep the initial cage's Laplacian coordinates instead (t0 = (L c0)_j,
// c0 the initial cage), so it keeps its shape and moves as a whole.
Eigen::MatrixXd weak_row_targets(const SparseMatrix& L, const Cage& cage, const Eigen::VectorXd& row_weight,
                                 const Eigen::VectorXd& weak_weight) {
  const Eigen::Index n = row_weight.size();
  Eigen::MatrixXd target = Eigen::MatrixXd::Zero(n, 3);
  // Adjacency from L's off-diagonal entries (column-major: column k lists the rows of k).
  std::vector<std::vector<uint32_t>> adjacent(static_cast<size_t>(n));
  for (int k = 0; k < L.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(L, k); it; ++it)
      if (it.row() != it.col()) adjacent[size_t(it.col())].push_back(uint32_t(it.row()));
  std::vector<int8_t> seen(size_t(n), 0);
  std::vector<uint32_t> cluster, stack;
  Eigen::MatrixXd initial_laplacian;  // L c0, computed on the first unanchored cluster
  for (Eigen::Index start = 0; start < n; ++start) {
    if (!(weak_weight(start) > 0) || seen[size_t(start)]) continue;
    cluster.clear();
    stack.assign(1, uint32_t(start));
    seen[size_t(start)] = 1;
    bool anchored = false;
    while (!stack.empty()) {
      const uint32_t v = stack.back();
      stack.pop_back();
      cluster.push_back(v);
      for (const uint32_t u : adjacent[v]) {
        if (!(weak_weight(u) > 0)) {
          anchored = true;
        } else if (!seen[u]) {
          seen[u] = 1;
          stack.push_back(u);
        }
      }
    }
    if (anchored) continue;
    if (initial_laplacian.size() == 0) {
      Eigen::MatrixXd c0(n, 3);
      for (Eigen::Index j = 0; j < n; ++j) {
        const Vec3& p = cage.mesh.positions[size_t(j)];
        c0.row(j) << p.x, p.y, p.z;
      }
      initial_laplacian = L * c0;
    }
    for (const uint32_t v : cluster)
      target.row(Eigen::Index(v)) = initial_laplacian.row(Eigen::Index(v)) * (weak_weight(v) / row_weight(v));
  }
  return target;
}

// couple: 3 rows per sample (W_i^(1/2) = n n^T + sqrt(w) (I - n n^T)), 3n unknowns.
std::vector<Vec3> solve_control_points_coupled(const SubdivisionSurface& surface, const Cage& cage,
                                               const std::vector<Vec3>& current_control,
                                               const std::vector<Vec3>& samples,
                                               const std::vector<FootPoint>& foot_points, double smoothness,
                                               const std::vector<bool>& fixed, double w,
                                               const LeastSquaresOptions& options, LeastSquaresReport& report) {
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
  // Laplacian row weights per vertex: the fairing term for all, plus the weak-support rows
  // (the support of vertex j: its three diagonal entries of B^T B, against their mean).
  Eigen::VectorXd row_weight = Eigen::VectorXd::Constant(n, smoothness * scale / 3);
  Eigen::VectorXd weak_weight = Eigen::VectorXd::Zero(n);
  if (options.weak_support_fraction > 0 && options.weak_fairing > 0) {
    for (int j = 0; j < n; ++j) {
      if (fixed[size_t(j)]) continue;
      const double support = M.coeff(3 * j, 3 * j) + M.coeff(3 * j + 1, 3 * j + 1) + M.coeff(3 * j + 2, 3 * j + 2);
      if (support < options.weak_support_fraction * scale) {
        weak_weight(j) = options.weak_fairing * scale / 3;
        row_weight(j) += weak_weight(j);
        ++report.weakly_supported_control_vertices;
      }
      if (support <= 1e-14 * scale) ++report.unsupported_control_vertices;
    }
  }
  if (row_weight.maxCoeff() > 0) {
    const SparseMatrix L = umbrella_laplacian(cage.mesh);
    std::vector<Triplet> lt;
    for (int k = 0; k < L.outerSize(); ++k)
      for (SparseMatrix::InnerIterator it(L, k); it; ++it)
        for (int c = 0; c < 3; ++c) lt.emplace_back(int(3 * it.row()) + c, int(3 * it.col()) + c, it.value());
    SparseMatrix L3(unknowns, unknowns);
    L3.setFromTriplets(lt.begin(), lt.end());
    Eigen::VectorXd w3(unknowns);
    for (int j = 0; j < unknowns; ++j) w3(j) = row_weight(j / 3);
    M += SparseMatrix(L3.transpose() * w3.asDiagonal() * L3);
    // The weak rows' targets (weak_row_targets).
    const Eigen::MatrixXd target = weak_row_targets(L, cage, row_weight, weak_weight);
    Eigen::VectorXd t3(unknowns);
    for (int j = 0; j < unknowns; ++j) t3(j) = target(j / 3, j % 3);
    b += L3.transpose() * (w3.asDiagonal() * t3);
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

// The data rows' inputs: samples p_i at foot points t_i, and the current control points (the
// fixed ones go to the right-hand side, the free ones warm-start CGLS).
struct SampleRows {
  const SubdivisionSurface& surface;
  const std::vector<Vec3>& current_control;
  const std::vector<Vec3>& samples;
  const std::vector<FootPoint>& foot_points;
};

// Progress and cancel points of one solve: point() between steps; in a parallel loop the calling
// thread's range (worker 0) calls loop_point() every 4096 samples, and when that throws (a cancel)
// the other workers see `stop` and leave their ranges at the next sample.
struct CancelPoints {
  const TaskMonitor* monitor = nullptr;
  const char* stage = "fit";
  double fraction = 0.0;
  mutable std::atomic<bool> stop{false};

  void point() const {
    if (monitor) monitor->report(stage, fraction);
  }
  // True when worker w should leave its range now.
  bool loop_point(size_t w, size_t done) const {
    if (monitor == nullptr) return false;
    if (w != 0) return stop.load(std::memory_order_relaxed);
    if ((done & 4095u) == 0) {
      try {
        point();
      } catch (...) {
        stop.store(true);
        throw;
      }
    }
    return false;
  }
};

// The point-distance system over the free control vertices, as the steps of
// solve_point_distance fill it in.
struct PointDistanceSystem {
  int n = 0;                    // control vertices
  std::vector<int> free_index;  // per control vertex: its column, or -1 when fixed
  int free_count = 0;
  // Dense normal equations: M (lower triangle) = A_F^T A_F and AtP = A_F^T P at once; otherwise
  // the rows A (= A_F) and P (= P - A_X c_X), multiplied out by the direct solve.
  bool dense_normal_equations = false;
  SparseMatrix A, M;
  Eigen::MatrixXd P, AtP;
  Eigen::VectorXd column_norm2;  // per free column: its squared norm in A (the diagonal of A^T A)
  double mu = 0;
  Eigen::VectorXd row_weight, weak_weight;  // per vertex: w_j and lambda_w,j of its Laplacian row
  bool laplacian_rows = false;
  Eigen::MatrixXd C;  // the free vertices' current positions
  SparseMatrix LF;    // the Laplacian rows' free columns
  Eigen::MatrixXd LX_c;  // L_X c_X - t (weak_row_targets)
};

void index_free_vertices(const std::vector<bool>& fixed, PointDistanceSystem& s) {
  s.free_index.assign(size_t(s.n), -1);
  for (int j = 0; j < s.n; ++j)
    if (!fixed[size_t(j)]) s.free_index[size_t(j)] = s.free_count++;
}

// One thread's share [begin, end) of the samples summed into dense A^T A (G, F x F) and A^T P
// (R, F x 3) over the F free columns.
void accumulate_normal_equations(const SampleRows& data, const std::vector<int>& free_index, size_t F, size_t begin,
                                 size_t end, std::vector<double>& G, std::vector<double>& R, size_t w,
                                 const CancelPoints& cancel) {
  G.assign(F * F, 0.0);
  R.assign(3 * F, 0.0);
  std::vector<uint32_t> indices, cols;
  std::vector<double> weights, vals;
  for (size_t i = begin; i < end; ++i) {
    if (cancel.loop_point(w, i - begin)) return;
    const FootPoint& t = data.foot_points[i];
    data.surface.basis_values(t.ptex_face, t.u, t.v, indices, weights);
    Vec3 r = data.samples[i];
    cols.clear();
    vals.clear();
    for (size_t k = 0; k < indices.size(); ++k) {
      const double wk = weights[k];
      if (wk == 0) continue;
      const int col = free_index[indices[k]];
      if (col >= 0)
        cols.push_back(uint32_t(col)), vals.push_back(wk);
      else
        r -= data.current_control[indices[k]] * wk;
    }
    for (size_t x = 0; x < cols.size(); ++x) {
      double* row = &G[size_t(cols[x]) * F];
      const double wx = vals[x];
      for (size_t y = 0; y < cols.size(); ++y) row[cols[y]] += wx * vals[y];
      for (int c = 0; c < 3; ++c) R[3 * size_t(cols[x]) + size_t(c)] += wx * r[c];
    }
  }
}

// The normal equations at once, per thread into dense accumulators (k^2 updates per sample with
// k basis functions; no N-row matrix, no sparse product), summed in thread order.
void assemble_normal_equations(const SampleRows& data, size_t workers, PointDistanceSystem& s,
                               const CancelPoints& cancel) {
  const size_t N = data.samples.size();
  const size_t F = size_t(s.free_count);
  check_memory_estimate(estimate_sum(estimate_product(workers, F * F * sizeof(double)),
                                     estimate_product(F * F, 2 * sizeof(Triplet))),
                        "least squares");
  std::vector<std::vector<double>> gram(workers), rhs(workers);
  run_ranges(N, workers, [&](size_t begin, size_t end, size_t w) {
    accumulate_normal_equations(data, s.free_index, F, begin, end, gram[w], rhs[w], w, cancel);
  });
  for (size_t w = 1; w < workers; ++w) {
    for (size_t k = 0; k < F * F; ++k) gram[0][k] += gram[w][k];
    for (size_t k = 0; k < 3 * F; ++k) rhs[0][k] += rhs[w][k];
    gram[w] = {}, rhs[w] = {};
  }
  // The lower triangle is all SimplicialLDLT reads.
  std::vector<Triplet> triplets;
  for (size_t j = 0; j < F; ++j)
    for (size_t i = j; i < F; ++i)
      if (gram[0][i * F + j] != 0) triplets.emplace_back(int(i), int(j), gram[0][i * F + j]);
  s.M = SparseMatrix(s.free_count, s.free_count);
  s.M.setFromTriplets(triplets.begin(), triplets.end());
  s.AtP.resize(s.free_count, 3);
  for (size_t k = 0; k < F; ++k) {
    s.column_norm2(Eigen::Index(k)) = gram[0][k * F + k];
    s.AtP.row(Eigen::Index(k)) << rhs[0][3 * k], rhs[0][3 * k + 1], rhs[0][3 * k + 2];
  }
}

// The column-major A straight from the per-thread row lists: a count per column, then a scatter,
// with a cancel point every 2^20 entries. setFromTriplets did the same in one Eigen call (about
// 0.7 s for the 18M entries of a million-sample fit) that a cancel could not interrupt, after a
// copy of all lists into one. The parts cover ascending row ranges in order, so each column's rows
// come out ascending, as setFromTriplets sorts them; a row's columns are distinct (basis_values
// sums per control vertex, free_index is one-to-one), so there is nothing to add up.
void fill_columns(const std::vector<std::vector<Triplet>>& parts, Eigen::Index rows, Eigen::Index cols, SparseMatrix& A,
                  const CancelPoints& cancel) {
  using Index = SparseMatrix::StorageIndex;
  size_t total = 0;
  for (const auto& part : parts) total += part.size();
  if (total > size_t(std::numeric_limits<Index>::max()))
    fail(Status::out_of_memory, "least squares: more sample-row entries than a sparse matrix can index");
  auto every_2_20 = [&](size_t k) {
    if ((k & 0xfffff) == 0) cancel.point();
  };
  std::vector<Index> next(size_t(cols) + 1, 0);
  size_t k = 0;
  for (const auto& part : parts)
    for (const Triplet& t : part) every_2_20(++k), ++next[size_t(t.col()) + 1];
  for (size_t j = 0; j < size_t(cols); ++j) next[j + 1] += next[j];
  A = SparseMatrix(rows, cols);
  A.resizeNonZeros(Eigen::Index(total));
  std::copy(next.begin(), next.end(), A.outerIndexPtr());
  Index* inner = A.innerIndexPtr();
  double* value = A.valuePtr();
  for (const auto& part : parts)
    for (const Triplet& t : part) {
      every_2_20(++k);
      const Index at = next[size_t(t.col())]++;
      inner[at] = Index(t.row());
      value[at] = t.value();
    }
}

// The rows of A and P, assembled in parallel (one triplet list per thread, in row order;
// fill_columns makes A of them).
void assemble_rows(const SampleRows& data, size_t workers, PointDistanceSystem& s, const CancelPoints& cancel) {
  const size_t N = data.samples.size();
  std::vector<std::vector<Triplet>> parts(workers);
  s.P.resize(Eigen::Index(N), 3);
  run_ranges(N, workers, [&](size_t begin, size_t end, size_t w) {
    auto& triplets = parts[w];
    triplets.reserve((end - begin) * 18);
    std::vector<uint32_t> indices;
    std::vector<double> weights;
    for (size_t i = begin; i < end; ++i) {
      if (cancel.loop_point(w, i - begin)) return;
      const FootPoint& t = data.foot_points[i];
      data.surface.basis_values(t.ptex_face, t.u, t.v, indices, weights);
      Vec3 rhs = data.samples[i];
      for (size_t k = 0; k < indices.size(); ++k) {
        const double wk = weights[k];
        if (wk == 0) continue;
        const int col = s.free_index[indices[k]];
        if (col >= 0)
          triplets.emplace_back(int(i), col, wk);
        else
          rhs -= data.current_control[indices[k]] * wk;
      }
      s.P.row(Eigen::Index(i)) << rhs.x, rhs.y, rhs.z;
    }
  });
  cancel.point();
  fill_columns(parts, Eigen::Index(N), s.free_count, s.A, cancel);
  parts = {};
  cancel.point();
  for (int k = 0; k < s.A.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(s.A, k); it; ++it) s.column_norm2(it.col()) += it.value() * it.value();
}

// The scale of the system (the mean diagonal of A^T A), mu, and the per-vertex weight of its
// Laplacian row: lambda for all (fairing), plus lambda_w for the weakly supported free vertices.
void weigh_rows(const LeastSquaresOptions& options, PointDistanceSystem& s, LeastSquaresReport& report) {
  const double scale = std::max(s.column_norm2.sum() / s.free_count, 1e-300);
  for (int k = 0; k < s.free_count; ++k)
    if (s.column_norm2(k) <= 1e-14 * scale) ++report.unsupported_control_vertices;
  const double mu = 1e-12 * scale, lambda = options.fairing * scale;
  s.mu = mu;
  s.row_weight = Eigen::VectorXd::Constant(s.n, lambda);
  s.weak_weight = Eigen::VectorXd::Zero(s.n);
  if (options.weak_support_fraction > 0 && options.weak_fairing > 0) {
    const double threshold = options.weak_support_fraction * scale;
    for (int j = 0; j < s.n; ++j) {
      const int k = s.free_index[size_t(j)];
      if (k >= 0 && s.column_norm2(k) < threshold) {
        s.weak_weight(j) = options.weak_fairing * scale;
        s.row_weight(j) += s.weak_weight(j);
        ++report.weakly_supported_control_vertices;
      }
    }
  }
  s.laplacian_rows = s.row_weight.maxCoeff() > 0;
}

void gather_free_positions(const std::vector<Vec3>& current_control, PointDistanceSystem& s) {
  s.C.resize(s.free_count, 3);
  for (int j = 0; j < s.n; ++j)
    if (s.free_index[size_t(j)] >= 0) {
      const Vec3& c = current_control[size_t(j)];
      s.C.row(s.free_index[size_t(j)]) << c.x, c.y, c.z;
    }
}

// Laplacian rows: sqrt(w_j) (L_F c_F + L_X c_X)_j.
void add_laplacian_rows(const Cage& cage, const std::vector<Vec3>& current_control, PointDistanceSystem& s) {
  const SparseMatrix L = umbrella_laplacian(cage.mesh);
  std::vector<Triplet> lt;
  s.LX_c = Eigen::MatrixXd::Zero(s.n, 3);
  for (int k = 0; k < L.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(L, k); it; ++it) {
      const int col = s.free_index[size_t(it.col())];
      if (col >= 0) {
        lt.emplace_back(int(it.row()), col, it.value());
      } else {
        const Vec3& c = current_control[size_t(it.col())];
        s.LX_c.row(it.row()) += it.value() * Eigen::RowVector3d(c.x, c.y, c.z);
      }
    }
  s.LF = SparseMatrix(s.n, s.free_count);
  s.LF.setFromTriplets(lt.begin(), lt.end());
  // Rows sqrt(w_j) ((L c)_j - t_j), t from weak_row_targets.
  s.LX_c -= weak_row_targets(L, cage, s.row_weight, s.weak_weight);
}

// A^T A, a block of columns at a time with a cancel point after each block: in one product it
// took ~0.35 s on the 18M entries of a million-sample fit without one. Each column of the product
// is summed the same way either way (over the column's entries of A in order), so the matrix is
// the same as At * A's.
SparseMatrix gram_in_column_blocks(const SparseMatrix& At, const SparseMatrix& A, const CancelPoints& cancel) {
  using Index = SparseMatrix::StorageIndex;
  const Eigen::Index cols = A.cols();
  // About 2^20 entries of A per block (~0.02 s).
  const Eigen::Index per_block =
      std::max<Eigen::Index>(1, Eigen::Index(double(cols) * double(1 << 20) / double(std::max<Eigen::Index>(1, A.nonZeros()))));
  if (per_block >= cols) return At * A;
  std::vector<SparseMatrix> blocks;
  Eigen::Index nonzeros = 0;
  for (Eigen::Index j = 0; j < cols; j += per_block) {
    blocks.push_back(At * A.middleCols(j, std::min(per_block, cols - j)));
    nonzeros += blocks.back().nonZeros();
    cancel.point();
  }
  SparseMatrix M(At.rows(), cols);
  M.resizeNonZeros(nonzeros);
  Index* outer = M.outerIndexPtr();
  Index at = 0;
  Eigen::Index column = 0;
  for (SparseMatrix& block : blocks) {
    block.makeCompressed();
    for (Eigen::Index k = 0; k < block.cols(); ++k) outer[column + k] = at + block.outerIndexPtr()[k];
    std::copy(block.innerIndexPtr(), block.innerIndexPtr() + block.nonZeros(), M.innerIndexPtr() + at);
    std::copy(block.valuePtr(), block.valuePtr() + block.nonZeros(), M.valuePtr() + at);
    at += Index(block.nonZeros());
    column += block.cols();
    block = SparseMatrix();
  }
  outer[cols] = at;
  return M;
}

// The direct solver: SimplicialLDLT of the normal equations (x, y, z share the factorisation).
Eigen::MatrixXd solve_normal_equations(PointDistanceSystem& s, const CancelPoints& cancel) {
  if (!s.dense_normal_equations) {
    const SparseMatrix At = s.A.transpose();
    cancel.point();
    s.M = gram_in_column_blocks(At, s.A, cancel);
    cancel.point();
    s.AtP = At * s.P;
    cancel.point();
  }
  Eigen::MatrixXd b = s.AtP + s.mu * s.C;
  if (s.laplacian_rows) {
    const SparseMatrix LFt_W = s.LF.transpose() * s.row_weight.asDiagonal();
    s.M += SparseMatrix(LFt_W * s.LF);
    b -= LFt_W * s.LX_c;
  }
  SparseMatrix I(s.free_count, s.free_count);
  I.setIdentity();
  s.M += s.mu * I;
  Eigen::SimplicialLDLT<SparseMatrix> solver(s.M);
  if (solver.info() != Eigen::Success)
    fail(Status::internal_error, "least squares: the normal equations could not be factorised");
  Eigen::MatrixXd x = solver.solve(b);
  if (solver.info() != Eigen::Success) fail(Status::internal_error, "least squares: the solve failed");
  return x;
}

// CGLS on the stacked system, warm-started from the current control points.
Eigen::MatrixXd solve_stacked_cgls(const PointDistanceSystem& s, LeastSquaresReport& report) {
  const int n = s.n, free_count = s.free_count;
  const SparseMatrix &A = s.A, &LF = s.LF;
  const bool laplacian_rows = s.laplacian_rows;
  const Eigen::Index rows = A.rows() + (laplacian_rows ? n : 0) + free_count;
  std::vector<Triplet> bt;
  bt.reserve(size_t(A.nonZeros() + (laplacian_rows ? LF.nonZeros() : 0) + free_count));
  for (int k = 0; k < A.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(A, k); it; ++it) bt.emplace_back(int(it.row()), int(it.col()), it.value());
  Eigen::Index row = A.rows();
  Eigen::MatrixXd d(rows, 3);
  d.topRows(A.rows()) = s.P;
  if (laplacian_rows) {
    const Eigen::VectorXd sl = s.row_weight.cwiseSqrt();
    for (int k = 0; k < LF.outerSize(); ++k)
      for (SparseMatrix::InnerIterator it(LF, k); it; ++it)
        bt.emplace_back(int(row + it.row()), int(it.col()), sl(it.row()) * it.value());
    d.middleRows(row, n) = -(sl.asDiagonal() * s.LX_c);
    row += n;
  }
  const double sm = std::sqrt(s.mu);
  for (int k = 0; k < free_count; ++k) bt.emplace_back(int(row + k), k, sm);
  d.bottomRows(free_count) = sm * s.C;
  SparseMatrix B(rows, free_count);
  B.setFromTriplets(bt.begin(), bt.end());
  Eigen::LeastSquaresConjugateGradient<SparseMatrix> cg;
  cg.setTolerance(1e-10);
  cg.setMaxIterations(std::max<Eigen::Index>(100, 4 * free_count));
  cg.compute(B);
  Eigen::MatrixXd x(free_count, 3);
  for (int c = 0; c < 3; ++c) {
    x.col(c) = cg.solveWithGuess(d.col(c), s.C.col(c));
    report.cgls_iterations = std::max(report.cgls_iterations, int(cg.iterations()));
  }
  return x;
}

// The point-distance system (w = 1) as one augmented least-squares problem over the free
// control vertices: B x = d with B = [A_F; sqrt(lambda) L_F; sqrt(mu) I],
// d = [P - A_X c_X; -sqrt(lambda) L_X c_X; sqrt(mu) c_F] (X = fixed vertices).
std::vector<Vec3> solve_point_distance(const SubdivisionSurface& surface, const Cage& cage,
                                       const std::vector<Vec3>& current_control, const std::vector<Vec3>& samples,
                                       const std::vector<FootPoint>& foot_points, const std::vector<bool>& fixed,
                                       const LeastSquaresOptions& options, LeastSquaresReport& report,
                                       const CancelPoints& cancel) {
  PointDistanceSystem s;
  s.n = int(surface.num_control_vertices());
  index_free_vertices(fixed, s);
  std::vector<Vec3> result = current_control;
  if (s.free_count == 0) return result;

  // The direct solver with a small cage assembles the normal equations A^T A and A^T P at once;
  // otherwise the rows of A are assembled (in parallel) and multiplied out. Fixed columns go to
  // the right-hand side either way.
  const SampleRows data{surface, current_control, samples, foot_points};
  const size_t N = samples.size();
  const size_t workers = size_t(std::max(1, std::min(options.threads, int((N + 4095) / 4096))));
  s.dense_normal_equations =
      options.solver == LeastSquaresSolver::direct && size_t(s.free_count) <= kDenseNormalEquationsLimit;
  s.column_norm2 = Eigen::VectorXd::Zero(s.free_count);
  cancel.point();
  if (s.dense_normal_equations)
    assemble_normal_equations(data, workers, s, cancel);
  else
    assemble_rows(data, workers, s, cancel);
  weigh_rows(options, s, report);
  gather_free_positions(current_control, s);
  if (s.laplacian_rows) add_laplacian_rows(cage, current_control, s);
  cancel.point();

  const Eigen::MatrixXd x =
      options.solver == LeastSquaresSolver::direct ? solve_normal_equations(s, cancel) : solve_stacked_cgls(s, report);
  if (!x.allFinite()) fail(Status::internal_error, "least squares: the solve gave non-finite positions");
  for (int j = 0; j < s.n; ++j) {
    const int k = s.free_index[size_t(j)];
    if (k >= 0) result[size_t(j)] = {x(k, 0), x(k, 1), x(k, 2)};
  }
  return result;
}
}  // namespace

std::vector<Vec3> solve_control_points(const SubdivisionSurface& surface, const Cage& cage,
                                       const std::vector<Vec3>& current_control, const std::vector<Vec3>& samples,
                                       const std::vector<FootPoint>& foot_points, const std::vector<bool>& fixed,
                                       const LeastSquaresOptions& options, LeastSquaresReport* report,
                                       const TaskMonitor* monitor, const char* stage, double fraction) {
  const int n = int(surface.num_control_vertices());
  if (samples.size() != foot_points.size() || current_control.size() != size_t(n) ||
      fixed.size() != size_t(n) || cage.mesh.num_vertices() != size_t(n))
    fail(Status::invalid_argument, "least squares: inconsistent sizes");
  if (!(options.fairing >= 0) || !std::isfinite(options.fairing))
    fail(Status::invalid_argument, "least squares: fairing must be finite and >= 0");
  if (!(options.tangential_weight >= 0 && options.tangential_weight <= 1))
    fail(Status::invalid_argument, "least squares: tangential_weight must be in [0, 1]");
  if (!(options.weak_support_fraction >= 0) || !std::isfinite(options.weak_support_fraction) ||
      !(options.weak_fairing >= 0) || !std::isfinite(options.weak_fairing))
    fail(Status::invalid_argument, "least squares: weak_support_fraction and weak_fairing must be finite and >= 0");
  LeastSquaresReport local;
  LeastSquaresReport& r = report ? *report : local;
  r = {};
  if (options.tangential_weight < 1)
    return solve_control_points_coupled(surface, cage, current_control, samples, foot_points, options.fairing,
                                         fixed, options.tangential_weight, options, r);
  CancelPoints cancel;
  cancel.monitor = monitor, cancel.stage = stage, cancel.fraction = fraction;
  return solve_point_distance(surface, cage, current_control, samples, foot_points, fixed, options, r, cancel);
}

CAGEKIT_NAMESPACE_END
