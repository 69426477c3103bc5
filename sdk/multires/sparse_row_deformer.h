// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// SparseRowDeformer: positions and normals of a bound scan for moved control points (thesis §8.5, the
// CPU reference path): S, S_u, S_v from the stored basis rows (8.3), P = S + D N_S (8.1) (or the
// local-frame offset), approximate normals N = normalize(G_u x G_v) with
// G_u = alpha_u S_u + beta_u S_v + gamma_u N_S (8.11)-(8.12), or exact normals (8.4)-(8.7) when
// the binding has them. Full recompute on `threads` threads, or incremental: only the vertices
// in the support of the control points that moved since the last call are recomputed (their
// S, S_u, S_v are updated by the moved points' deltas).
//
// This is the straightforward sparse-row representation (an index and 3 doubles per non-zero
// basis function, ~13-16 per vertex, double precision throughout): the reference the compact
// CpuDeformer (cpu_deformer.h) is tested against, and the path of exact normals.
//
// Thread-safety: one deformer per thread (it keeps the last control points and per-vertex
// S, S_u, S_v); the binding must outlive it and stay unchanged.
#include <cstdint>
#include <vector>

#include "multires/scan_binding.h"

CAGEKIT_NAMESPACE_BEGIN

enum class NormalMode { approximate, exact };

// The control points an update() is given against the ones of the last deform(): throws
// invalid_operation before a first deform() (`last_count` differs from the binding's
// `bound_count`) and invalid_argument when `given_count` differs from it.
void check_update_control(size_t last_count, size_t bound_count, size_t given_count);
// Throws invalid_argument when a moved control vertex is out of range.
void check_moved_control(const std::vector<uint32_t>& moved, size_t control_count);

class SparseRowDeformer {
 public:
  explicit SparseRowDeformer(const ScanBinding& binding, int threads = 0);

  // Full recompute. `control` has binding.num_control_vertices entries; positions and normals
  // (either may be null) receive binding.num_vertices() entries. Throws invalid_argument for a
  // wrong size, or exact normals without binding data for them.
  void deform(const std::vector<Vec3>& control, Vec3* positions, Vec3* normals,
              NormalMode mode = NormalMode::approximate);
  // Incremental: `control` differs from the previous call's only at `moved` (after a first
  // deform()); recomputes and writes only the affected vertices (the rest of the output arrays is
  // left as the caller had it from earlier calls). Returns the number of vertices recomputed.
  size_t update(const std::vector<Vec3>& control, const std::vector<uint32_t>& moved, Vec3* positions,
                Vec3* normals, NormalMode mode = NormalMode::approximate);
  // The vertices the last update() recomputed.
  const std::vector<uint32_t>& last_updated() const { return touched_; }

 private:
  void finish_vertex(size_t i, Vec3* positions, Vec3* normals, NormalMode mode) const;
  const ScanBinding& b_;
  int threads_;
  std::vector<Vec3> control_;       // the control points of the last call
  std::vector<Vec3> s_, su_, sv_;   // per vertex, for the last control points
  std::vector<Vec3> suu_, suv_, svv_;  // exact normals only
  bool have_second_ = false;
  // Inverse rows: the entries of each control vertex (vertex index and entry index).
  std::vector<uint32_t> support_offsets_, support_vertex_, support_entry_;
  std::vector<uint32_t> touched_stamp_, touched_;
  uint32_t stamp_ = 0;
};

CAGEKIT_NAMESPACE_END
