// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// PatchDeformerTable: the compact representation of a ScanBinding that the fast CpuDeformer
// streams every frame (issue #5; thesis §8.5, §8.6.1). Instead of a sparse row of ~16 basis
// weights (and their two derivatives) per scan vertex, the scan vertices are grouped into
// *cells*: dyadic squares [ix, ix+1] x [iy, iy+1] * 2^-depth of a ptex face on which the limit
// surface is one bicubic polynomial (a regular B-spline patch, or one piece of a Stam patch's
// ring, or a crease/boundary patch). Per cell the table keeps the power-basis coefficients of
// that polynomial as fixed linear combinations of the cage's control vertices
//   S(s, t) = sum_{a,b <= 3} C_ab s^a t^b,   C_ab = sum_k M_k,ab c_{j_k}
// (s, t the cell-local parameters in [0,1]^2), found from basis() at 16 nodes and *verified*
// against the binding's stored rows at every vertex of the cell (values and both derivatives to
// 1e-9): a square where the surface is not one polynomial (the corner square of a Stam patch,
// a Gregory end cap, a semi-sharp crease's pieces) is split into its four children, down to
// `max_depth` or until it holds fewer than `min_split_vertices` vertices; the vertices left over
// are *irregular* and keep copies of their sparse rows (double), as do the vertices of a cell
// where float32 would lose the surface frame (S_s or S_t below 1% of the cell's extent, or
// nearly parallel: boundary corners of the limit surface).
//
// Per frame the deformer gathers each cell's control points once (~16 multiply-adds per
// coefficient, float32, relative to the cell's first control point: the coefficients of
// s^a t^b, (a, b) != (0, 0), sum to 0 over the terms and those of 1 to 1) and then evaluates S, S_s, S_t of every vertex of the cell from its
// float32 (s, t) with the coefficients broadcast: the per-vertex data is 36 bytes (40 with the
// vertex index; 48 in local-frame mode) of float32 structure-of-arrays, sorted by cell.
//
// Precision: coefficients are computed relative to the cell's first control point (kept in
// double) and the vertices relative to the cell's corner S(0, 0) (double), so float rounding is
// relative to the size of the cell's neighbourhood, not to the coordinates' magnitude: positions agree with the double sparse-row reference to ~1e-7 of the
// bounding-box diagonal (tested <= 2e-6), normals to ~1e-5 rad.
#include <cstdint>
#include <vector>

#include "core/namespace.h"
#include "core/task_monitor.h"

CAGEKIT_NAMESPACE_BEGIN

struct ScanBinding;
class SubdivisionSurface;

struct PatchTableOptions {
  int max_depth = 12;               // deepest cell: 2^-12 of a ptex face
  uint32_t min_split_vertices = 8;  // a non-polynomial square with fewer vertices is not split
  double tolerance = 1e-9;          // |weight difference| allowed (derivatives: times 2^depth)
};

struct PatchDeformerTable {
  // Cells: cell c covers the sorted vertices [cell_vertex_offsets[c], cell_vertex_offsets[c+1])
  // and has the terms [cell_term_offsets[c], cell_term_offsets[c+1]): term k contributes
  // term_coefficients[16 k + a + 4 b] * control[term_control[k]] to C_ab.
  std::vector<uint32_t> cell_vertex_offsets{0};
  std::vector<uint32_t> cell_term_offsets{0};
  std::vector<uint32_t> term_control;
  std::vector<float> term_coefficients;  // applied to control[j] - control[first term's j]
  std::vector<uint8_t> cell_depth;
  // Sorted cell vertices (structure of arrays, float32): the scan vertex index, the cell-local
  // (s, t), the displacement D (or c), the normal coefficients (8.11)-(8.12) with the
  // derivative ones scaled to the cell's parameters (k0, k1, k3, k4 times 2^depth), and in
  // local-frame mode the tangent offsets (a, b). The float arrays have 7 entries of padding at
  // the end (the deformer evaluates groups of 8).
  std::vector<uint32_t> vertex;
  std::vector<float> s, t, displacement;
  std::vector<float> k[6];
  std::vector<float> tangent_a, tangent_b;
  // Irregular vertices: copies of their sparse rows (phi, phi_u, phi_v in ptex units, double);
  // the displacement and coefficients are read from the binding (double).
  std::vector<uint32_t> irregular_vertex;
  std::vector<uint32_t> irregular_offsets{0};
  std::vector<uint32_t> irregular_control;
  std::vector<double> irregular_w, irregular_wu, irregular_wv;
  // Per control vertex: the cells whose terms use it, and the irregular vertices (positions in
  // irregular_vertex) whose rows use it (the support for incremental updates).
  std::vector<uint32_t> control_cell_offsets, control_cells;
  std::vector<uint32_t> control_irregular_offsets, control_irregular;
  bool local_frame = false;

  bool empty() const { return cell_vertex_offsets.size() <= 1 && irregular_vertex.empty(); }
  size_t num_cells() const { return cell_vertex_offsets.size() - 1; }
  size_t num_cell_vertices() const { return vertex.size(); }
  size_t num_irregular_vertices() const { return irregular_vertex.size(); }
  // Bytes read from the table and binding plus bytes written to the caller's position and
  // normal arrays, per scan vertex, in one full frame of positions + approximate normals (the
  // control points and the per-cell float coefficients, which stay in cache, are counted too).
  double bytes_per_vertex(size_t num_control_vertices) const;
};

// Builds the table of `binding` (its foot points, rows and coefficients) on `surface` (the
// limit surface the binding was made on). Throws Error(invalid_argument) when the binding does
// not belong to the surface; cancellable (stage "bind").
PatchDeformerTable build_patch_deformer_table(const ScanBinding& binding, const SubdivisionSurface& surface,
                                              const PatchTableOptions& options = {}, int threads = 0,
                                              const TaskMonitor& monitor = {});

CAGEKIT_NAMESPACE_END
