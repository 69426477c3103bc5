// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// CpuDeformer: positions and normals of a bound scan for moved control points (thesis §8.5, the
// CPU path; issue #5): P = S + D N_S (8.1) (or the local-frame offset) and approximate normals
// N = normalize(G_u x G_v), G_u = alpha_u S_u + beta_u S_v + gamma_u N_S (8.11)-(8.12).
//
// Fast path (binding.compact, patch_deformer_table.h): per frame, every cell's bicubic
// power-basis coefficients are gathered once from the control points (double), then S, S_s, S_t,
// the offset and the normal of each of the cell's vertices are evaluated in float32 from its
// cell-local (s, t), structure-of-arrays, in blocks the compiler vectorises (with a runtime
// AVX2+FMA clone next to the baseline x86-64 one, GCC function multiversioning); the few
// irregular vertices (near extraordinary vertices, where no cell is one polynomial) use float
// copies of their sparse rows. Full recompute on `threads` threads in one parallel region (each
// worker a range of cells, split by vertex count, and a share of the irregular vertices), or
// incremental: only the cells and irregular vertices in the support of the control
// points that moved since the last call are recomputed, with the same code as a full frame, so
// incremental results equal full ones bit for bit.
//
// Exact normals (8.4)-(8.7), and bindings made without the compact table, go through the
// double-precision SparseRowDeformer (sparse_row_deformer.h), which is also the reference the
// fast path is tested against (positions within ~1e-7 of the bbox diagonal).
//
// Outputs: Vec3 arrays, or flat xyz triples of double or float32 (hosts drawing float32 write
// half the bytes). Cells whose vertices are consecutive scan vertices (a scan renumbered by
// deformer_vertex_order) are written in runs with streaming stores (the output lines are not read
// first); the others with scattered stores, their lines prefetched for writing.
//
// Thread-safety: one deformer per thread (it keeps the last control points); the binding must
// outlive it and stay unchanged.
#include <cstdint>
#include <memory>
#include <vector>

#include "multires/scan_binding.h"
#include "multires/sparse_row_deformer.h"

CAGEKIT_NAMESPACE_BEGIN

// Bytes read + written per vertex in one full frame of positions + approximate normals: the
// compact table's figure (PatchDeformerTable::bytes_per_vertex), or the sparse rows' when the
// binding has no table.
double deform_bytes_per_vertex(const ScanBinding& binding);

class CpuDeformer {
 public:
  explicit CpuDeformer(const ScanBinding& binding, int threads = 0);
  ~CpuDeformer();

  // Full recompute. `control` has binding.num_control_vertices entries; positions and normals
  // (either may be null) receive binding.num_vertices() entries. Throws invalid_argument for a
  // wrong size, or exact normals without binding data for them.
  void deform(const std::vector<Vec3>& control, Vec3* positions, Vec3* normals,
              NormalMode mode = NormalMode::approximate);
  // The same into flat xyz triples (3 * binding.num_vertices() values each; either may be
  // null): double (the same values as the Vec3 overload), or float32 (the double values rounded
  // to float: the compact path evaluates in float32 anyway, positions are formed in double,
  // cell corner + offset, then rounded). Hosts that draw float32 save half the bytes written.
  void deform(const std::vector<Vec3>& control, double* positions, double* normals,
              NormalMode mode = NormalMode::approximate);
  void deform(const std::vector<Vec3>& control, float* positions, float* normals,
              NormalMode mode = NormalMode::approximate);
  // Incremental: `control` differs from the previous call's only at `moved` (after a first
  // deform()); recomputes and writes only the affected vertices (the rest of the output arrays is
  // left as the caller had it from earlier calls). Returns the number of vertices recomputed.
  size_t update(const std::vector<Vec3>& control, const std::vector<uint32_t>& moved, Vec3* positions,
                Vec3* normals, NormalMode mode = NormalMode::approximate);
  // The same into flat xyz triples of double or float32.
  size_t update(const std::vector<Vec3>& control, const std::vector<uint32_t>& moved, double* positions,
                double* normals, NormalMode mode = NormalMode::approximate);
  size_t update(const std::vector<Vec3>& control, const std::vector<uint32_t>& moved, float* positions,
                float* normals, NormalMode mode = NormalMode::approximate);
  // The vertices the last update() recomputed.
  const std::vector<uint32_t>& last_updated() const;

  // True when approximate normals use the compact table (else the sparse rows).
  bool compact() const { return !b_.compact.empty(); }
  // Bytes read + written per vertex in one full frame of positions + approximate normals (the
  // compact table's figure, or the sparse rows' when there is no table).
  double bytes_per_vertex() const;

 private:
  template <typename T>
  void deform_impl(const std::vector<Vec3>& control, T* positions, T* normals, NormalMode mode);
  template <typename T>
  size_t update_impl(const std::vector<Vec3>& control, const std::vector<uint32_t>& moved, T* positions, T* normals,
                     NormalMode mode);
  template <typename T>
  void scatter(const uint32_t* cells, size_t cell_count, const uint32_t* items, size_t item_count, T* positions,
               T* normals);
  template <typename T>
  void copy_out(const uint32_t* list, size_t count, T* positions, T* normals) const;
  void check_control(const std::vector<Vec3>& control) const;
  void check_mode(NormalMode mode) const;
  SparseRowDeformer& reference();

  const ScanBinding& b_;
  int threads_;
  std::vector<Vec3> control_;  // the control points of the last call
  std::unique_ptr<SparseRowDeformer> reference_;
  bool reference_synced_ = false;  // reference_ holds the frame of control_ (exact mode)
  bool last_from_reference_ = false;
  std::vector<uint32_t> cell_stamp_, irregular_stamp_, cells_, irregular_, touched_;
  std::vector<uint8_t> cell_contiguous_;  // per cell: its vertices are consecutive scan vertices
  uint32_t stamp_ = 0;
  std::vector<uint32_t> all_cells_, all_irregular_;  // 0, 1, 2, ... (full frames)
  std::vector<size_t> full_split_, split_;  // the workers' cell ranges: full frames, last update
  std::vector<double> irregular_data_;  // per irregular vertex: D, normal coefficients, a, b
  std::vector<Vec3> scratch_p_, scratch_n_;  // float outputs of the sparse-row path
};

CAGEKIT_NAMESPACE_END
