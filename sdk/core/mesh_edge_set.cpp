// SPDX-License-Identifier: GPL-3.0-or-later
#include "core/mesh_edge_set.h"

#include <algorithm>

#include "core/edge_key.h"

CAGEKIT_NAMESPACE_BEGIN

MeshEdgeSet::MeshEdgeSet(const PolygonMesh& mesh) {
  keys_.reserve(mesh.num_face_vertices());
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t size = mesh.face_size(f);
    const uint32_t* face = mesh.face_begin(f);
    for (uint32_t i = 0; i < size; ++i) keys_.push_back(edge_key(face[i], face[(i + 1) % size]));
  }
  std::sort(keys_.begin(), keys_.end());
  keys_.erase(std::unique(keys_.begin(), keys_.end()), keys_.end());
}

bool MeshEdgeSet::contains(uint32_t a, uint32_t b) const {
  return a != b && std::binary_search(keys_.begin(), keys_.end(), edge_key(a, b));
}

CAGEKIT_NAMESPACE_END
