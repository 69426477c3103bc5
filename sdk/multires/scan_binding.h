// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// ScanBinding: the two-scale representation of a scan over a cage's limit surface (thesis §8.3):
// every scan vertex v_i = S(t_i) + D_i N_S(t_i) (8.1)-(8.2), with t_i its foot point (exact
// closest point, §7.4) and D_i its normal displacement; plus what the deformer needs to
// evaluate S, S_u, S_v at t_i for moved control points (the basis functions phi_j of (8.3),
// stored sparsely per vertex) and the coefficients of the approximate normal reconstruction
// (8.11)-(8.12). Binding the same scan to a finer cage works the same way (Fig. 8.3).
//
// Departures, documented: `DisplacementMode::local_frame` keeps the whole offset
// v_i - S(t_i) = a T1 + b T2 + c N_S in the surface's orthonormal local frame
// (T1 = S_u / |S_u|, T2 = N_S x T1), so vertices whose foot
// point lies on a patch border, a crease or the scan boundary (where the offset is not along
// the normal) are reproduced exactly too; the thesis's normal mode loses that sideways part and
// the binding reports the largest such residual.
//
// The compact per-cell representation the fast CPU deformer streams is built with the binding
// (`compact`, patch_deformer_table.h); the sparse rows stay (reference, exact normals, GPU).
// Sharp features: optionally one bound vertex (and normal) per smooth sector
// (BindOptions::sharp_angle_degrees). Saved to and read from files by binding_file.h.
#include <cstdint>
#include <vector>

#include "core/cage.h"
#include "core/polygon_mesh.h"
#include "core/task_monitor.h"
#include "fit/closest_point_on_limit_surface.h"
#include "multires/patch_deformer_table.h"
#include "subdiv/subdivision_surface.h"

CAGEKIT_NAMESPACE_BEGIN

enum class DisplacementMode {
  normal,       // the thesis: D_i along N_S (8.1)
  local_frame,  // a T1 + b T2 + c N_S, T1 = S_u/|S_u|, T2 = N_S x T1 (keeps sideways offsets)
};

struct BindOptions {
  DisplacementMode mode = DisplacementMode::normal;
  // Also store the second-derivative weights and the displacement gradient (D_u, D_v) of the
  // exact normal (8.4)-(8.7), for comparison with the approximate normals.
  bool exact_normals = false;
  ClosestPointOptions closest_point;
  SurfaceOptions surface;
  int threads = 0;  // 0 = all cores
  // Sharp features (thesis §8.5.2, AC-8.8): >= 0 duplicates every scan vertex once per smooth
  // sector (sectors separated by edges whose faces' normals differ by more than this many
  // degrees, and by boundary / non-manifold edges; core/sector_split.h), so each copy keeps its
  // own sector's normal. The bound vertices are then the copies (ScanBinding::source_vertex,
  // face_offsets, face_vertices). -1 (default): one bound vertex per scan vertex.
  double sharp_angle_degrees = -1;
  // Also build the compact per-cell table the fast CpuDeformer streams (patch_deformer_table.h).
  bool compact_table = true;
  PatchTableOptions patch_table;
};

struct ScanBinding {
  uint32_t num_control_vertices = 0;
  // Per scan vertex.
  std::vector<FootPoint> foot_points;
  std::vector<double> displacement;    // D_i (normal mode) or c (local-frame mode)
  std::vector<double> tangent_offset;  // local-frame mode: (a, b) per vertex (T1, T2 components)
  std::vector<double> normal_coefficients;  // (alpha_u, beta_u, gamma_u, alpha_v, beta_v, gamma_v)
  std::vector<double> displacement_gradient;  // exact normals: (D_u, D_v) per vertex
  // Sparse basis rows (8.3): vertex i uses entries [row_offsets[i], row_offsets[i+1]).
  std::vector<uint32_t> row_offsets;
  std::vector<uint32_t> control_index;
  std::vector<double> phi, phi_u, phi_v;           // per entry
  std::vector<double> phi_uu, phi_uv, phi_vv;      // per entry, exact normals only
  DisplacementMode mode = DisplacementMode::normal;
  // Normal mode: the largest |(v_i - S) - D_i N_S| (the sideways residual the thesis drops),
  // relative to the scan's bbox diagonal, and how many vertices exceed 1e-6 of it.
  double max_sideways_residual = 0;
  size_t vertices_with_sideways_residual = 0;
  double bbox_diagonal = 0;
  // The compact representation for the CPU deformer (empty when BindOptions::compact_table is
  // off; the deformer then uses the sparse rows above).
  PatchDeformerTable compact;

  // Sector split (BindOptions::sharp_angle_degrees >= 0; all three empty otherwise): bound
  // vertex i copies scan vertex source_vertex[i] (the first scan_vertex_count bound vertices are
  // the scan's own, the copies follow), and the scan's faces over the bound vertices are
  // face_offsets / face_vertices (same faces, same order).
  std::vector<uint32_t> source_vertex, face_offsets, face_vertices;
  size_t scan_vertex_count = 0;  // with a sector split; 0 otherwise

  size_t num_vertices() const { return foot_points.size(); }
  size_t num_entries() const { return control_index.size(); }
};

// Throws Error(invalid_argument) for bad options or non-finite scan positions,
// Error(invalid_mesh) for a cage without a limit surface; cancellable (stage "bind").
ScanBinding bind_scan_to_cage(const Cage& cage, const PolygonMesh& scan, const BindOptions& options = {},
                              const TaskMonitor& monitor = {});

// Area-weighted vertex normals of a mesh (unit; zero for vertices on no non-degenerate face).
std::vector<Vec3> vertex_normals(const PolygonMesh& mesh);

CAGEKIT_NAMESPACE_END
