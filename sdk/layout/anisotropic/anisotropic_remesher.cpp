// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/anisotropic/anisotropic_remesher.h"
#include "core/angles.h"
#include "layout/common/sharp_input_features.h"

#include <chrono>
#include <cmath>
#include <string>
#include <unordered_set>

#include "core/edge_map.h"
#include "core/memory_budget.h"
#include "core/status.h"
#include "layout/anisotropic/convex_face_partition.h"
#include "layout/anisotropic/curvature_line_mesher.h"
#include "layout/anisotropic/curvature_line_sampling.h"
#include "layout/anisotropic/curvature_tensor_field.h"
#include "layout/common/feature_edges.h"
#include "layout/anisotropic/principal_alignment.h"
#include "layout/common/remesh_quality.h"
#include "layout/common/triangle_mesh_input.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Connected regions of confident faces (edge-adjacent).
uint64_t confident_regions(const PolygonMesh& tri, const CurvatureField& field, const TriangleAdjacency& adj) {
  const double lambda_min = std::cos(kPi / 6.0);
  std::vector<uint8_t> seen(tri.num_faces(), 0);
  std::vector<uint32_t> stack;
  uint64_t regions = 0;
  for (uint32_t f = 0; f < tri.num_faces(); ++f) {
    if (seen[f] || field.face_confidence[f] < lambda_min) continue;
    ++regions;
    seen[f] = 1;
    stack.push_back(f);
    while (!stack.empty()) {
      const uint32_t g = stack.back();
      stack.pop_back();
      for (uint32_t k = 0; k < 3; ++k) {
        const uint32_t t = adj.twin[3 * g + k];
        if (t == detail::kNone || seen[t / 3] || field.face_confidence[t / 3] < lambda_min) continue;
        seen[t / 3] = 1;
        stack.push_back(t / 3);
      }
    }
  }
  return regions;
}

void measure(const CurvatureField& field, const LineMesh& lm, AnisotropicRemeshResult& r) {
  const PolygonMesh& m = lm.mesh;
  const PolygonMeshFigures figures = polygon_mesh_figures(m);
  static_cast<RemeshQuality&>(r) = measure_remesh_quality(m, lm.vertex_normals, &figures);
  // Alignment of the edges along curvature lines (feature lines and partition diagonals are not
  // meant to follow the field), scored against the faces their two ends lie on: the chord of a
  // curved edge is parallel to the tangent at its middle, approximated by the sign-aligned mean
  // of the nearer principal directions at the two ends.
  std::unordered_set<uint64_t> face_edges;
  for (const auto& [a, b] : figures.edges) face_edges.insert(edge_key(a, b));
  std::vector<AlignmentSample> samples;
  for (const LineMesh::Edge& e : lm.edges) {
    if (!is_curvature_line(e.type) || !face_edges.count(edge_key(e.a, e.b))) continue;
    samples.push_back({m.positions[e.b] - m.positions[e.a], lm.vertex_face[e.a], lm.vertex_face[e.b]});
  }
  r.mean_alignment_deg = measure_principal_alignment(field, samples).mean_deg;
}

}  // namespace

CurvatureOptions anisotropic_curvature_options(const PolygonMesh& triangles, const AnisotropicRemeshOptions& o) {
  CurvatureOptions co;
  // The thesis's radius (a fraction of the diagonal), capped at 6 mean edge lengths [J]: on dense
  // meshes 1% of the diagonal spans tens of edges and the disk traversal dominates the run time
  // (1M-triangle torus: 32 s at 1% = 15 edges, 8.5 s at 3 edges).
  co.disk_radius_bbox = 0.0;
  if (o.disk_radius_bbox > 0.0) {
    const double mean_edge = triangles.mean_edge_length();
    const double diagonal = triangles.bounding_box().diagonal();
    co.disk_radius_bbox = diagonal > 0.0 ? std::min(o.disk_radius_bbox, 6.0 * mean_edge / diagonal) : o.disk_radius_bbox;
  }
  co.threads = o.threads;
  co.feature_angle_degrees = -1.0;  // the features are detected once and passed as host flags
  return co;
}

AnisotropicRemeshResult remesh_anisotropic(const PolygonMesh& input, const AnisotropicRemeshOptions& o,
                                           const TaskMonitor& monitor) {
  const auto start = std::chrono::steady_clock::now();
  if (!(o.tolerance > 0.0) || !std::isfinite(o.tolerance) || o.tolerance > 1.0)
    fail(Status::invalid_argument, "anisotropic remeshing: tolerance must be in (0, 1] (relative to the bbox diagonal)");
  if (!(o.feature_angle_degrees <= 180.0) || std::isnan(o.feature_angle_degrees))
    fail(Status::invalid_argument, "anisotropic remeshing: feature angle must be <= 180 degrees (< 0: none)");
  if (o.max_face_valence < 3) fail(Status::invalid_argument, "anisotropic remeshing: max face valence must be >= 3");
  if (!std::isfinite(o.disk_radius_bbox) || o.disk_radius_bbox > 1.0 || o.threads < 0)
    fail(Status::invalid_argument, "anisotropic remeshing: disk radius must be <= 1 and threads >= 0");
  const PolygonMesh tri = fan_triangulated(input, "anisotropic remeshing");
  // Dominant arrays: field (~300 B per triangle), adjacency and database (~150 B), meshing; the
  // 1M-triangle torus peaked at 532 MB of resident memory.
  check_memory_estimate(estimate_sum(estimate_product(tri.num_faces(), 560), estimate_product(tri.num_vertices(), 64)),
                        "anisotropic remeshing");
  std::vector<uint8_t> features;
  if (o.feature_angle_degrees >= 0.0 || !o.sharp_edges.empty()) {  // the sharp input features every
    SharpFeatureOptions fo;                                           // method's creases follow
    fo.angle_degrees = std::clamp(o.feature_angle_degrees, 0.0, 180.0);
    fo.detect = o.feature_angle_degrees >= 0.0;
    fo.host_edges = o.sharp_edges;
    features = detect_sharp_features(tri, fo).corner_flags;
  }

  AnisotropicRemeshResult r;
  const CurvatureOptions co = anisotropic_curvature_options(tri, o);
  const CurvatureField field = estimate_curvature_field(tri, co, features.empty() ? nullptr : &features, monitor);
  r.field_seconds = seconds_since(start);

  LineSamplingOptions lo;
  lo.tolerance = o.tolerance;
  const LineSampling lines = sample_curvature_lines(tri, field, lo, features.empty() ? nullptr : &features, monitor);
  r.sampling_seconds = lines.seconds;
  r.lines = lines.lines.size();

  LineMeshOptions mo;
  mo.max_face_valence = o.max_face_valence;
  const LineMesh lm = mesh_curvature_lines(tri, field, lines, mo, monitor);
  r.meshing_seconds = lm.seconds;
  r.holes = lm.unclosed_half_edges;
  r.regions = confident_regions(tri, field, *lines.adjacency);
  measure(field, lm, r);

  r.cage.mesh = lm.mesh;
  std::unordered_set<uint64_t> face_edges;
  for (size_t f = 0; f < lm.mesh.num_faces(); ++f)
    for (uint32_t k = 0, n = lm.mesh.face_size(f); k < n; ++k)
      face_edges.insert(edge_key(lm.mesh.face_vertex(f, k), lm.mesh.face_vertex(f, (k + 1) % n)));
  for (const LineMesh::Edge& e : lm.edges)
    if (e.type == LineType::feature && face_edges.count(edge_key(e.a, e.b)))
      r.cage.creases.push_back({e.a, e.b, kSharpnessInfinite});
  r.creases = r.cage.creases.size();
  r.seconds = seconds_since(start);
  return r;
}

CAGEKIT_NAMESPACE_END
