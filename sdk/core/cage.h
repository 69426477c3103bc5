// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Cage: a Catmull-Clark control mesh = polygon mesh + crease tags (thesis §2.2.1, with
// OpenSubdiv's semi-sharp extension), corner tags, hole faces and a boundary rule.
#include <cstdint>
#include <vector>

#include "core/polygon_mesh.h"

CAGEKIT_NAMESPACE_BEGIN

// Sharpness at or above this value is infinitely sharp (OpenSubdiv's SHARPNESS_INFINITE).
constexpr float kSharpnessInfinite = 10.0f;

struct EdgeCrease {
  uint32_t v0 = 0, v1 = 0;  // an edge of the mesh, either orientation
  float sharpness = kSharpnessInfinite;
};

struct VertexCorner {
  uint32_t vertex = 0;
  float sharpness = kSharpnessInfinite;
};

// Values match the C header's cagekit_boundary_rule.
enum class BoundaryRule : int {
  // Boundary edges are infinitely sharp creases, boundary corners are NOT pinned: the thesis's rule.
  edges_only = 0,
  // Boundary edges are creases and boundary vertices of valence 2 are pinned corners.
  edges_and_corners = 1,
};

struct Cage {
  PolygonMesh mesh;
  std::vector<EdgeCrease> creases;
  std::vector<VertexCorner> corners;
  std::vector<uint32_t> holes;  // face indices of faces that are holes (not part of the surface)
  BoundaryRule boundary = BoundaryRule::edges_only;

  bool has_tags() const { return !creases.empty() || !corners.empty() || !holes.empty(); }
  void clear_tags() {
    creases.clear();
    corners.clear();
    holes.clear();
  }
};

CAGEKIT_NAMESPACE_END
