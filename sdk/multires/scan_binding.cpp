// SPDX-License-Identifier: GPL-3.0-or-later
#include "multires/scan_binding.h"

#include <algorithm>
#include <cmath>

#include "core/memory_budget.h"
#include "core/parallel_for.h"
#include "core/sector_split.h"
#include "core/status.h"
#include "fit/ptex_adjacency.h"
#include "multires/basis_rows.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

// A unit vector orthogonal to unit n.
Vec3 any_orthogonal(const Vec3& n) {
  const Vec3 axis = std::abs(n.x) <= std::abs(n.y) && std::abs(n.x) <= std::abs(n.z) ? Vec3{1, 0, 0}
                    : std::abs(n.y) <= std::abs(n.z)                                 ? Vec3{0, 1, 0}
                                                                                     : Vec3{0, 0, 1};
  return normalized(cross(n, axis));
}

// (alpha, beta, gamma) with q = alpha S_u + beta S_v + gamma N (N unit, orthogonal to S_u, S_v).
void frame_coefficients(const Vec3& su, const Vec3& sv, const Vec3& n, const Vec3& q, double out[3]) {
  const double e = dot(su, su), f = dot(su, sv), g = dot(sv, sv), det = e * g - f * f;
  const double a = dot(q, su), b = dot(q, sv);
  out[0] = det != 0 ? (a * g - b * f) / det : 0.0;
  out[1] = det != 0 ? (b * e - a * f) / det : 0.0;
  out[2] = dot(q, n);
}

}  // namespace

std::vector<Vec3> vertex_normals(const PolygonMesh& mesh) {
  std::vector<Vec3> normals(mesh.num_vertices());
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t k = mesh.face_size(f);
    if (k < 3) continue;
    bool in_range = true;
    for (uint32_t c = 0; c < k; ++c) in_range = in_range && mesh.face_vertex(f, c) < mesh.num_vertices();
    if (!in_range) continue;
    const Vec3 area = mesh.face_vector_area(f);
    for (uint32_t c = 0; c < k; ++c) {
      const uint32_t a = mesh.face_vertex(f, c);
      normals[a] += area;
    }
  }
  for (Vec3& n : normals) {
    const double l = norm(n);
    n = l > 0 ? n * (1.0 / l) : Vec3();
  }
  return normals;
}

ScanBinding bind_scan_to_cage(const Cage& cage, const PolygonMesh& input_scan, const BindOptions& options,
                              const TaskMonitor& monitor) {
  if (options.mode != DisplacementMode::normal && options.mode != DisplacementMode::local_frame)
    fail(Status::invalid_argument, "bind: unknown displacement mode");
  if (options.threads < 0) fail(Status::invalid_argument, "bind: threads must be >= 0");
  if (!(options.sharp_angle_degrees < 0) && !(options.sharp_angle_degrees <= 180))
    fail(Status::invalid_argument, "bind: sharp_angle_degrees must be < 0 (off) or in [0, 180]");
  // Sharp features: the scan's vertices duplicated per smooth sector, each copy bound on its own
  // (same position, so the same foot point; its own sector's normal).
  const bool split_sectors = options.sharp_angle_degrees >= 0;
  SectorSplit split;
  if (split_sectors) split = split_vertices_by_sector(input_scan, options.sharp_angle_degrees);
  const PolygonMesh& scan = split_sectors ? split.mesh : input_scan;
  if (scan.num_vertices() == 0) fail(Status::invalid_argument, "bind: the scan has no vertices");
  BoundingBox box;
  for (const Vec3& p : scan.positions) {
    if (!is_finite(p)) fail(Status::invalid_argument, "bind: non-finite scan position");
    box.extend(p);
  }
  const int threads = resolve_threads(options.threads);
  const size_t n = scan.num_vertices();
  // Foot points, rows of ~20-40 entries of 3 (6) doubles + index, coefficients.
  check_memory_estimate(estimate_product(n, options.exact_normals ? 2200 : 1200), "binding the scan");

  SurfaceOptions surface_options = options.surface;
  surface_options.threads = threads;
  const SubdivisionSurface surface(cage, surface_options);
  const PtexAdjacency adjacency(cage.mesh, surface);
  const LimitSurfaceProjector projector(surface, &adjacency, cage.mesh.positions, options.closest_point, true,
                                        threads);
  ScanBinding b;
  b.num_control_vertices = surface.num_control_vertices();
  b.mode = options.mode;
  b.bbox_diagonal = box.diagonal();
  b.foot_points.resize(n);
  parallel_for(n, threads, monitor, "bind", 0.0, 0.6, [&](size_t i) { b.foot_points[i] = projector.project(scan.positions[i]); });

  const std::vector<Vec3> scan_normals = vertex_normals(scan);
  std::vector<BasisWeights> rows(n);
  b.displacement.resize(n);
  if (options.mode == DisplacementMode::local_frame) b.tangent_offset.resize(2 * n);
  b.normal_coefficients.resize(6 * n);
  if (options.exact_normals) b.displacement_gradient.resize(2 * n);
  std::vector<double> sideways(n, 0.0);
  const std::vector<Vec3>& control = cage.mesh.positions;
  parallel_for(n, threads, monitor, "bind", 0.6, 0.95, [&](size_t i) {
    const FootPoint& t = b.foot_points[i];
    BasisWeights& w = rows[i];
    w = surface.basis(t.ptex_face, t.u, t.v);
    Vec3 s, su, sv, suu, suv, svv;
    for (size_t k = 0; k < w.indices.size(); ++k) {
      const Vec3& c = control[w.indices[k]];
      s += w.w[k] * c, su += w.wu[k] * c, sv += w.wv[k] * c;
      suu += w.wuu[k] * c, suv += w.wuv[k] * c, svv += w.wvv[k] * c;
    }
    const Vec3 cr = cross(su, sv);
    const double cl = norm(cr);
    const Vec3 ns = cl > 0 ? cr * (1.0 / cl) : Vec3{0, 0, 1};
    const Vec3 offset = scan.positions[i] - s;
    if (options.mode == DisplacementMode::normal) {
      b.displacement[i] = dot(offset, ns);
      sideways[i] = norm(offset - b.displacement[i] * ns);
    } else {
      // Orthonormal frame (T1 = S_u / |S_u|, T2 = N x T1, N): well conditioned where the
      // derivatives nearly vanish (e.g. at a boundary corner of the limit surface).
      const Vec3 t1 = normalized(su), t2 = cross(ns, t1);
      b.tangent_offset[2 * i] = dot(offset, t1), b.tangent_offset[2 * i + 1] = dot(offset, t2);
      b.displacement[i] = dot(offset, ns);
    }
    // Approximate normals (8.11)-(8.12): G_u = q0, G_v = q1 with q0, q1 an orthonormal tangent
    // frame of the scan's normal N_G (q0 x q1 = N_G).
    const Vec3 ng = norm(scan_normals[i]) > 0 ? scan_normals[i] : ns;
    const Vec3 q0 = any_orthogonal(ng), q1 = cross(ng, q0);
    frame_coefficients(su, sv, ns, q0, &b.normal_coefficients[6 * i]);
    frame_coefficients(su, sv, ns, q1, &b.normal_coefficients[6 * i + 3]);
    if (options.exact_normals && cl > 0) {
      // D_u, D_v from N_G . G_u = N_G . G_v = 0 with G = S + D N_S (8.4)-(8.6).
      auto dn = [&](const Vec3& d) {  // (I - N N^T) d / |S_u x S_v|
        return (d - dot(d, ns) * ns) * (1.0 / cl);
      };
      const Vec3 nu = dn(cross(suu, sv) + cross(su, suv)), nv = dn(cross(suv, sv) + cross(su, svv));
      const double D = dot(offset, ns), denom = dot(ng, ns);
      b.displacement_gradient[2 * i] = denom != 0 ? -(dot(ng, su) + D * dot(ng, nu)) / denom : 0.0;
      b.displacement_gradient[2 * i + 1] = denom != 0 ? -(dot(ng, sv) + D * dot(ng, nv)) / denom : 0.0;
    }
  });
  monitor.report("bind", 0.95);
  store_basis_rows(b, rows, options.exact_normals);
  if (split_sectors) {
    b.source_vertex = std::move(split.source_vertex);
    b.face_offsets = scan.face_offsets;
    b.face_vertices = scan.face_vertices;
    b.scan_vertex_count = split.num_input_vertices;
  }
  const double d = b.bbox_diagonal > 0 ? b.bbox_diagonal : 1.0;
  for (double r : sideways) {
    b.max_sideways_residual = std::max(b.max_sideways_residual, r / d);
    if (r > 1e-6 * d) ++b.vertices_with_sideways_residual;
  }
  if (options.compact_table) b.compact = build_patch_deformer_table(b, surface, options.patch_table, threads, monitor);
  monitor.report("bind", 1.0);
  return b;
}

CAGEKIT_NAMESPACE_END
