// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Validation of a polygon mesh before it enters the pipeline: every problem is found, counted
// and described precisely (which face/vertex/edge), never asserted on.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/cage.h"
#include "core/polygon_mesh.h"
#include "core/task_monitor.h"

CAGEKIT_NAMESPACE_BEGIN

// Values match the C header's cagekit_mesh_issue (bit positions of cagekit_mesh_issue_flags).
enum class MeshIssue : int {
  index_out_of_range = 0,       // a face refers to a vertex >= num_vertices
  non_finite_position = 1,      // NaN or Inf coordinate
  degenerate_face = 2,          // fewer than 3 vertices, a repeated vertex, or zero area
  duplicate_face = 3,           // same vertex cycle as another face (either orientation)
  non_manifold_edge = 4,        // an edge used by more than two faces
  non_manifold_vertex = 5,      // faces around a vertex form more than one fan
  inconsistent_orientation = 6, // two faces traverse a shared edge in the same direction
  unreferenced_vertex = 7,      // vertex used by no face (a warning: not an error)
  count_ = 8
};

const char* mesh_issue_name(MeshIssue issue);

struct MeshIssueRecord {
  MeshIssue issue;
  uint64_t element;     // face index, vertex index, or for edges the first face found
  std::string message;  // e.g. "face 12 refers to vertex 9000 but the mesh has 6475 vertices"
};

struct ValidationReport {
  uint64_t counts[static_cast<int>(MeshIssue::count_)] = {};
  std::vector<MeshIssueRecord> records;  // the first `max_records` problems found, in order
  // Message of the first problem of each kind, kept even when `records` is full ("" if none).
  std::string first_message[static_cast<int>(MeshIssue::count_)];
  uint64_t count(MeshIssue i) const { return counts[static_cast<int>(i)]; }
  // Bit i set when counts[i] > 0.
  uint32_t flags() const;
  // True when no error-level issue was found (unreferenced vertices alone are fine).
  bool ok() const;
  // One line per issue kind with count and the first example, "" when clean.
  std::string summary() const;
};

// Faces with out-of-range indices, fewer than 3 vertices or a repeated vertex, and the later
// copies of duplicate faces, are reported and then left out of the edge/vertex checks (so each
// defect is reported once, under its own kind). Throws Error(Status::invalid_mesh) only when
// face_offsets itself is malformed.
ValidationReport validate_mesh(const PolygonMesh& mesh, size_t max_records = 16);
// The same with a progress report (`stage`, `fraction`) between its passes over the mesh (each
// takes a fraction of a second on a million faces), where a cancel takes effect: throws
// Error(Status::cancelled) when the monitor's callback asks to stop.
ValidationReport validate_mesh(const PolygonMesh& mesh, size_t max_records, const TaskMonitor& monitor,
                               const char* stage, double fraction);
// Also checks the cage's tags: crease edges that are not mesh edges, corner/hole indices out
// of range, negative or NaN sharpness (reported as index_out_of_range / non_finite_position).
ValidationReport validate_cage(const Cage& cage, size_t max_records = 16);

CAGEKIT_NAMESPACE_END
