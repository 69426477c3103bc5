// SPDX-License-Identifier: GPL-3.0-or-later
// Mesh and cage validation: every check is a linear pass over faces, vertices or the edge map
// (built once by a counting sort, see edge_map.h), so the whole validation is O(n log n) at
// worst and never asserts: any input, including out-of-range indices and NaN positions, only
// produces counts and messages.
#include "core/mesh_validation.h"

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "core/edge_map.h"
#include "core/mesh_edge_set.h"

CAGEKIT_NAMESPACE_BEGIN

const char* mesh_issue_name(MeshIssue issue) {
  switch (issue) {
    case MeshIssue::index_out_of_range: return "index out of range";
    case MeshIssue::non_finite_position: return "non-finite position";
    case MeshIssue::degenerate_face: return "degenerate face";
    case MeshIssue::duplicate_face: return "duplicate face";
    case MeshIssue::non_manifold_edge: return "non-manifold edge";
    case MeshIssue::non_manifold_vertex: return "non-manifold vertex";
    case MeshIssue::inconsistent_orientation: return "inconsistent orientation";
    case MeshIssue::unreferenced_vertex: return "unreferenced vertex";
    case MeshIssue::count_: break;
  }
  return "unknown issue";
}

uint32_t ValidationReport::flags() const {
  uint32_t bits = 0;
  for (int i = 0; i < static_cast<int>(MeshIssue::count_); ++i)
    if (counts[i] > 0) bits |= 1u << i;
  return bits;
}

bool ValidationReport::ok() const {
  for (int i = 0; i < static_cast<int>(MeshIssue::count_); ++i)
    if (i != static_cast<int>(MeshIssue::unreferenced_vertex) && counts[i] > 0) return false;
  return true;
}

std::string ValidationReport::summary() const {
  std::string out;
  for (int i = 0; i < static_cast<int>(MeshIssue::count_); ++i) {
    if (counts[i] == 0) continue;
    out += mesh_issue_name(static_cast<MeshIssue>(i));
    out += ": " + std::to_string(counts[i]);
    if (i == static_cast<int>(MeshIssue::unreferenced_vertex)) out += " (warning)";
    if (!first_message[i].empty()) out += " (first: " + first_message[i] + ")";
    out += "\n";
  }
  return out;
}

namespace {

using detail::kNone;

// Counts every problem; builds a message only for the first `max_records` problems and for
// the first problem of each kind (messages are the expensive part on million-face meshes).
class Recorder {
 public:
  Recorder(ValidationReport& report, size_t max_records) : report_(report), max_(max_records) {}
  template <class MakeMessage>
  void add(MeshIssue issue, uint64_t element, MakeMessage make_message) {
    const int k = static_cast<int>(issue);
    ++report_.counts[k];
    const bool want_record = report_.records.size() < max_;
    const bool want_first = report_.first_message[k].empty();
    if (!want_record && !want_first) return;
    std::string message = make_message();
    if (want_first) report_.first_message[k] = message;
    if (want_record) report_.records.push_back({issue, element, std::move(message)});
  }

 private:
  ValidationReport& report_;
  size_t max_;
};

std::string fmt_double(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

std::string fmt_edge(uint32_t a, uint32_t b) { return "(" + std::to_string(a) + "," + std::to_string(b) + ")"; }

struct MeshCheck {
  std::vector<uint8_t> topo;  // faces taking part in the topology checks
  detail::EdgeMap edges;
  // Where a caller's monitor reports between the passes (none: no reports).
  const TaskMonitor* monitor = nullptr;
  const char* stage = "";
  double fraction = 0.0;
  void checkpoint() const {
    if (monitor != nullptr) monitor->report(stage, fraction);
  }
};

void check_mesh(const PolygonMesh& mesh, Recorder& rec, MeshCheck& out) {
  detail::check_mesh_arrays(mesh);
  const size_t nf = mesh.num_faces(), nv = mesh.num_vertices();
  out.topo.assign(nf, 0);
  std::vector<uint8_t> finite(nv);
  for (size_t v = 0; v < nv; ++v) finite[v] = is_finite(mesh.positions[v]);

  // Per face: indices, size, repeated vertices, zero area.
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t n = mesh.face_size(f);
    const uint32_t* fv = mesh.face_begin(f);
    bool in_range = true, all_finite = true;
    for (uint32_t i = 0; i < n; ++i) {
      if (fv[i] >= nv) {
        if (in_range) {
          const uint32_t bad = fv[i];
          rec.add(MeshIssue::index_out_of_range, f, [&] {
            return "face " + std::to_string(f) + " refers to vertex " + std::to_string(bad) +
                   " but the mesh has " + std::to_string(nv) + " vertices";
          });
        }
        in_range = false;
      } else if (!finite[fv[i]]) {
        all_finite = false;
      }
    }
    if (n < 3) {
      rec.add(MeshIssue::degenerate_face, f, [&] {
        return "face " + std::to_string(f) + " is degenerate: it has " +
               (n == 0 ? std::string("no vertices") : "only " + std::to_string(n) + (n == 1 ? " vertex" : " vertices"));
      });
      continue;
    }
    const uint32_t repeated = detail::find_repeated_vertex(fv, n);
    if (repeated != kNone) {
      rec.add(MeshIssue::degenerate_face, f, [&] {
        return "face " + std::to_string(f) + " is degenerate: vertex " + std::to_string(repeated) + " repeats";
      });
      continue;
    }
    if (!in_range) continue;
    out.topo[f] = 1;
    if (all_finite && detail::face_has_zero_area(mesh, f))
      rec.add(MeshIssue::degenerate_face, f, [&] { return "face " + std::to_string(f) + " has zero area"; });
  }

  for (size_t v = 0; v < nv; ++v) {
    if (finite[v]) continue;
    rec.add(MeshIssue::non_finite_position, v, [&] {
      const Vec3& p = mesh.positions[v];
      return "vertex " + std::to_string(v) + " has a non-finite position (" + fmt_double(p.x) + ", " +
             fmt_double(p.y) + ", " + fmt_double(p.z) + ")";
    });
  }

  out.checkpoint();
  // Duplicates: reported, then left out of the topology checks (what is left is exactly what
  // repair_mesh still has to fix after dropping them).
  {
    std::vector<uint32_t> dup_of;
    std::vector<uint8_t> dup_reversed;
    detail::find_duplicate_faces(mesh, out.topo, dup_of, dup_reversed);
    for (size_t f = 0; f < nf; ++f) {
      if (dup_of[f] == kNone) continue;
      out.topo[f] = 0;
      rec.add(MeshIssue::duplicate_face, f, [&] {
        return "face " + std::to_string(f) + " duplicates face " + std::to_string(dup_of[f]) +
               (dup_reversed[f] ? " (opposite orientation)" : "");
      });
    }
  }

  out.checkpoint();
  // Edges: more than two faces, or two faces running the same way.
  detail::EdgeMap& map = out.edges;
  detail::build_edge_map(map, mesh, out.topo);
  out.checkpoint();
  for (size_t e = 0; e < map.num_edges(); ++e) {
    const uint32_t k = map.valence(e);
    const uint32_t* h = map.corners_begin(e);
    if (k > 2) {
      rec.add(MeshIssue::non_manifold_edge, map.corner_face[h[0]], [&] {
        std::string m = "edge " + fmt_edge(map.edge_lo[e], map.edge_hi[e]) + " is used by " + std::to_string(k) +
                        " faces: ";
        for (uint32_t i = 0; i < k && i < 10; ++i) m += (i ? ", " : "") + std::to_string(map.corner_face[h[i]]);
        if (k > 10) m += ", ...";
        return m;
      });
    } else if (k == 2 && map.forward(h[0]) == map.forward(h[1])) {
      rec.add(MeshIssue::inconsistent_orientation, map.corner_face[h[0]], [&] {
        return "faces " + std::to_string(map.corner_face[h[0]]) + " and " + std::to_string(map.corner_face[h[1]]) +
               " traverse edge " + fmt_edge(map.from(h[0]), map.to(h[0])) +
               " in the same direction (inconsistent orientation)";
      });
    }
  }

  // Vertices: fans of faces (corners joined across every shared edge), references.
  const size_t nc = mesh.face_vertices.size();
  detail::UnionFind corners(nc);
  detail::glue_fans(map, corners, [](size_t) { return true; });
  out.checkpoint();
  std::vector<uint32_t> fans(nv, 0);
  std::vector<uint8_t> referenced(nv, 0);
  for (size_t c = 0; c < nc; ++c) {
    const uint32_t v = mesh.face_vertices[c];
    if (v >= nv) continue;
    referenced[v] = 1;
    if (out.topo[map.corner_face[c]] && corners.find(static_cast<uint32_t>(c)) == c) ++fans[v];
  }
  for (size_t v = 0; v < nv; ++v) {
    if (fans[v] > 1)
      rec.add(MeshIssue::non_manifold_vertex, v, [&] {
        return "vertex " + std::to_string(v) + " joins " + std::to_string(fans[v]) +
               " separate fans of faces (non-manifold vertex)";
      });
    if (!referenced[v])
      rec.add(MeshIssue::unreferenced_vertex, v, [&] { return "vertex " + std::to_string(v) + " is not used by any face"; });
  }
}

}  // namespace

ValidationReport validate_mesh(const PolygonMesh& mesh, size_t max_records, const TaskMonitor& monitor,
                               const char* stage, double fraction) {
  ValidationReport report;
  Recorder rec(report, max_records);
  MeshCheck check;
  check.monitor = &monitor, check.stage = stage, check.fraction = fraction;
  check_mesh(mesh, rec, check);
  return report;
}

ValidationReport validate_mesh(const PolygonMesh& mesh, size_t max_records) {
  return validate_mesh(mesh, max_records, TaskMonitor(), "", 0.0);  // a default monitor reports nothing
}

ValidationReport validate_cage(const Cage& cage, size_t max_records) {
  ValidationReport report;
  Recorder rec(report, max_records);
  MeshCheck check;
  check_mesh(cage.mesh, rec, check);
  const size_t nv = cage.mesh.num_vertices(), nf = cage.mesh.num_faces();
  auto bad_sharpness = [](float s) { return std::isnan(s) || s < 0; };
  const MeshEdgeSet edges(cage.mesh);
  for (size_t i = 0; i < cage.creases.size(); ++i) {
    const EdgeCrease& c = cage.creases[i];
    if (c.v0 >= nv || c.v1 >= nv) {
      rec.add(MeshIssue::index_out_of_range, i, [&] {
        return "crease " + std::to_string(i) + " refers to vertex " + std::to_string(c.v0 >= nv ? c.v0 : c.v1) +
               " but the mesh has " + std::to_string(nv) + " vertices";
      });
    } else if (!edges.contains(c.v0, c.v1)) {
      rec.add(MeshIssue::index_out_of_range, i, [&] {
        return "crease " + std::to_string(i) + " " + fmt_edge(c.v0, c.v1) + " is not an edge of the mesh";
      });
    }
    if (bad_sharpness(c.sharpness))
      rec.add(MeshIssue::non_finite_position, i, [&] {
        return "crease " + std::to_string(i) + " " + fmt_edge(c.v0, c.v1) + " has sharpness " +
               fmt_double(c.sharpness) + " (must be >= 0)";
      });
  }
  for (size_t i = 0; i < cage.corners.size(); ++i) {
    const VertexCorner& c = cage.corners[i];
    if (c.vertex >= nv)
      rec.add(MeshIssue::index_out_of_range, i, [&] {
        return "corner " + std::to_string(i) + " refers to vertex " + std::to_string(c.vertex) + " but the mesh has " +
               std::to_string(nv) + " vertices";
      });
    if (bad_sharpness(c.sharpness))
      rec.add(MeshIssue::non_finite_position, i, [&] {
        return "corner " + std::to_string(i) + " (vertex " + std::to_string(c.vertex) + ") has sharpness " +
               fmt_double(c.sharpness) + " (must be >= 0)";
      });
  }
  for (size_t i = 0; i < cage.holes.size(); ++i) {
    if (cage.holes[i] >= nf)
      rec.add(MeshIssue::index_out_of_range, i, [&] {
        return "hole " + std::to_string(i) + " refers to face " + std::to_string(cage.holes[i]) + " but the mesh has " +
               std::to_string(nf) + " faces";
      });
  }
  return report;
}

CAGEKIT_NAMESPACE_END
