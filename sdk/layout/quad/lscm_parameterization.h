// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Free-boundary conformal parameterisation of one region by Least Squares Conformal Maps
// [LPRM02] (thesis §6.4.3, spec thesis-ch4-6.md §2.5): the domain Ω_i in which chapter 6
// builds and selects its curve network.
//
// Per triangle t (area A, vertices in a local orthonormal frame of its plane), LSCM penalises the
// Cauchy-Riemann residual of the piecewise-linear map (u, v): A ((u_x − v_y)² + (u_y + v_x)²).
// The two boundary vertices farthest apart (double sweep) are pinned at (0, 0) and (d, 0), d
// their 3D distance, which removes the similarity null space; the rest is a sparse linear least
// squares problem solved through its normal equations with Eigen's SimplicialLDLT. Holes need no
// cutting. A vanishing Laplacian term (weight 1e-10 per edge against O(1) LSCM rows) keeps
// vertices that touch only zero-area triangles determined; a part joined to the rest only through
// a vertex or through zero-area triangles is placed by that term alone (any similarity of it
// has zero LSCM energy). Why not CGAL's LSCM_parameterizer_3: it
// documents disk-topology input only, and each CGAL translation unit costs ~25 s / 1.4 GB.
//
// The map preserves orientation (Cauchy-Riemann, not the anti-conformal equations): triangles
// that run counter-clockwise about their normal run counter-clockwise in (u, v). LSCM does not
// guarantee injectivity; `flipped_triangles` reports the count.
//
// Thread-safety: a pure function. Errors: invalid_mesh for an invalid triangle mesh (as
// require_triangle_mesh), a region whose faces are not edge-connected, have an edge of more than
// two faces or inconsistent orientation, have no boundary, or have a handle (genus > 0: LSCM
// needs a disk, possibly with holes); invalid_argument for an empty, repeated or out-of-range
// face list; internal_error if the factorisation fails; cancelled from the monitor.
#include <array>
#include <cstdint>
#include <vector>

#include "core/polygon_mesh.h"
#include "core/task_monitor.h"
#include "core/vec2.h"

CAGEKIT_NAMESPACE_BEGIN

struct RegionParameterization {
  std::vector<uint32_t> faces;                 // the region's input faces, increasing
  std::vector<uint32_t> vertices;              // its input vertices, increasing
  std::vector<Vec2> uv;       // per entry of `vertices`
  std::array<uint32_t, 2> pinned_vertices{};   // input ids, at (0, 0) and (d, 0)
  // Quality over triangles of non-zero area: signed (u, v) area <= 0 counts as flipped; the
  // conformal distortion of a triangle is σ_max / σ_min of its Jacobian (1 for a similarity).
  size_t flipped_triangles = 0;
  double max_conformal_distortion = 1.0;
  double mean_conformal_distortion = 1.0;      // area-weighted

  // Index of input vertex v in `vertices`, or 0xffffffff when v is not in the region.
  uint32_t local_index(uint32_t vertex) const;
  const Vec2& uv_of(uint32_t vertex) const { return uv[local_index(vertex)]; }
};

RegionParameterization parameterize_region_lscm(const PolygonMesh& triangles, const std::vector<uint32_t>& faces,
                                                const TaskMonitor& monitor = {});

// Signed area of a closed polygon of input vertices in the domain (> 0: counter-clockwise). The
// outer loop of a region is counter-clockwise, its holes clockwise.
double signed_domain_area(const RegionParameterization& parameterization, const std::vector<uint32_t>& loop);

CAGEKIT_NAMESPACE_END
