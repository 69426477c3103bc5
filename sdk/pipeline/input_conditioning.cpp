// SPDX-License-Identifier: GPL-3.0-or-later
#include "pipeline/input_conditioning.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "core/mesh_validation.h"
#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

uint32_t find_root(std::vector<uint32_t>& parent, uint32_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

// Face components by shared vertices; returns the component of each face and their count.
std::vector<uint32_t> face_components(const PolygonMesh& mesh, uint64_t* count) {
  std::vector<uint32_t> parent(mesh.num_vertices());
  std::iota(parent.begin(), parent.end(), 0u);
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t* v = mesh.face_begin(f);
    for (uint32_t k = 1; k < mesh.face_size(f); ++k) {
      const uint32_t a = find_root(parent, v[0]), b = find_root(parent, v[k]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  std::vector<uint32_t> label(mesh.num_vertices(), UINT32_MAX), component(mesh.num_faces());
  uint32_t next = 0;
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t r = find_root(parent, mesh.face_begin(f)[0]);
    if (label[r] == UINT32_MAX) label[r] = next++;
    component[f] = label[r];
  }
  *count = next;
  return component;
}

void append(std::string& s, uint64_t n, const char* what) {
  if (n == 0) return;
  if (!s.empty()) s += ", ";
  s += what;
  s += ' ';
  s += std::to_string(n);
}

}  // namespace

bool ConditioningReport::changed() const {
  const RepairReport& r = repair;
  return r.welded_vertices || r.dropped_degenerate_faces || r.dropped_duplicate_faces || r.split_vertices ||
         r.flipped_faces || r.removed_unreferenced_vertices || r.non_orientable_components || dropped_components;
}

std::string ConditioningReport::summary() const {
  std::string s;
  append(s, repair.welded_vertices, "welded vertices");
  append(s, repair.dropped_degenerate_faces, "dropped degenerate faces");
  append(s, repair.dropped_duplicate_faces, "dropped duplicate faces");
  append(s, repair.split_vertices, "vertices added to split non-manifold edges and vertices");
  append(s, repair.flipped_faces, "flipped faces");
  append(s, repair.non_orientable_components, "non-orientable components cut open");
  append(s, repair.removed_unreferenced_vertices, "removed unreferenced vertices");
  append(s, dropped_components, "dropped components");
  append(s, dropped_component_faces, "faces in dropped components");
  return s.empty() ? "nothing to change" : s;
}

PolygonMesh condition_input(const PolygonMesh& scan, const ConditioningOptions& options, ConditioningReport* report_out,
                            const TaskMonitor& monitor) {
  if (!(options.weld_tolerance_relative >= 0) || !std::isfinite(options.weld_tolerance_relative))
    fail(Status::invalid_argument, "conditioning: weld_tolerance_relative must be finite and >= 0");
  ConditioningReport report;
  report.input_vertices = scan.num_vertices();
  report.input_faces = scan.num_faces();
  if (scan.num_faces() == 0) fail(Status::invalid_mesh, "the scan has no faces (a point cloud?): nothing to remesh");
  // Corrupt input stays an error: conditioning does not guess what a bad index meant.
  monitor.report("conditioning: validation", 0.0);
  const ValidationReport before = validate_mesh(scan, 1, monitor, "conditioning: validation", 0.0);
  if (before.count(MeshIssue::index_out_of_range) > 0)
    fail(Status::invalid_mesh, "the scan has faces with out-of-range vertex indices (" +
                                   before.first_message[int(MeshIssue::index_out_of_range)] + ")");
  if (before.count(MeshIssue::non_finite_position) > 0)
    fail(Status::invalid_mesh, "the scan has non-finite vertex positions (" +
                                   before.first_message[int(MeshIssue::non_finite_position)] + ")");
  if (!options.repair) {
    if (!before.ok())
      fail(Status::invalid_mesh, "the scan is not a valid mesh and conditioning is off: " + before.summary());
    report.vertices = scan.num_vertices();
    report.faces = scan.num_faces();
    if (report_out) *report_out = report;
    return scan;
  }

  RepairOptions repair;
  repair.weld_tolerance = options.weld_tolerance_relative * scan.bounding_box().diagonal();
  repair.drop_invalid_faces = false;
  repair.remove_unreferenced_vertices = true;  // the fit samples every vertex: only surface points
  PolygonMesh mesh = repair_mesh(scan, repair, &report.repair, monitor);

  monitor.report("conditioning: components", 0.5);
  std::vector<uint32_t> component = face_components(mesh, &report.components);
  if (options.components == ComponentMode::largest && report.components > 1) {
    std::vector<uint64_t> faces(report.components, 0);
    for (uint32_t c : component) ++faces[c];
    const uint32_t keep = uint32_t(std::max_element(faces.begin(), faces.end()) - faces.begin());
    PolygonMesh kept;
    std::vector<uint32_t> index(mesh.num_vertices(), UINT32_MAX), corners;
    for (size_t f = 0; f < mesh.num_faces(); ++f) {
      if (component[f] != keep) {
        ++report.dropped_component_faces;
        continue;
      }
      corners.clear();
      for (uint32_t k = 0; k < mesh.face_size(f); ++k) {
        uint32_t& i = index[mesh.face_vertex(f, k)];
        if (i == UINT32_MAX) {
          i = uint32_t(kept.positions.size());
          kept.positions.push_back(mesh.positions[mesh.face_vertex(f, k)]);
        }
        corners.push_back(i);
      }
      kept.add_face(corners.data(), corners.size());
    }
    report.dropped_components = report.components - 1;
    report.components = 1;
    mesh = std::move(kept);
  }
  report.vertices = mesh.num_vertices();
  report.faces = mesh.num_faces();
  if (mesh.num_faces() == 0)
    fail(Status::invalid_mesh, "nothing left after conditioning (" + report.summary() +
                                   "): every face of the scan is degenerate or a duplicate");
  monitor.report("conditioning: validation", 0.75);
  const ValidationReport after = validate_mesh(mesh, 1, monitor, "conditioning: validation", 0.75);
  if (!after.ok()) fail(Status::internal_error, "conditioning left an invalid mesh: " + after.summary());
  monitor.log(LogLevel::info, "conditioning: " + std::to_string(report.input_faces) + " faces -> " +
                                  std::to_string(report.faces) + " faces, " + std::to_string(report.components) +
                                  " component(s); " + report.summary());
  if (report_out) *report_out = report;
  return mesh;
}

CAGEKIT_NAMESPACE_END
