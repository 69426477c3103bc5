// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Summary statistics of a mesh or cage (what `cagekit info` prints).
#include <cstdint>

#include "core/cage.h"
#include "core/task_monitor.h"

CAGEKIT_NAMESPACE_BEGIN

struct MeshStatistics {
  uint64_t vertices = 0, faces = 0, edges = 0;
  uint64_t triangles = 0, quads = 0, other_polygons = 0;
  uint64_t boundary_edges = 0, boundary_loops = 0, components = 0;
  uint64_t unreferenced_vertices = 0;
  // Faces left out of the topology (edges, chi, genus): an index >= vertices, fewer than 3
  // vertices, or a repeated vertex. Any such face makes the mesh non-manifold.
  uint64_t invalid_faces = 0;
  int64_t euler_characteristic = 0;  // V - E + F over referenced vertices
  // Genus of the surface from chi = sum over components (2 - 2g - b); -1 when not manifold
  // (or manifold but not orientable: a Moebius strip, a Klein bottle).
  int64_t genus = -1;
  bool manifold = false;  // edge- and vertex-manifold, valid indices, no face repeating a vertex
  BoundingBox bbox;  // of every finite position (unreferenced vertices included, NaN/Inf left out)
  double bbox_diagonal = 0;
  uint64_t creases = 0, corners = 0, holes = 0;
};

MeshStatistics compute_mesh_statistics(const Cage& cage);
// The same without tags (creases/corners/holes are 0); avoids copying a mesh into a cage.
// `monitor` gets "statistics" reports between the passes (cancel points on a large mesh).
MeshStatistics compute_mesh_statistics(const PolygonMesh& mesh, const TaskMonitor& monitor = {});

CAGEKIT_NAMESPACE_END
