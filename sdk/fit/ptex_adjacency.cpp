// SPDX-License-Identifier: GPL-3.0-or-later
#include "fit/ptex_adjacency.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/edge_key.h"
#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

// Side running from vertex x (parameter 0) towards vertex y over `fraction` of the edge.
void along_edge(uint32_t x, uint32_t y, double fraction, uint64_t& line, double& offset, double& scale) {
  line = edge_key(x, y);
  if (x < y) {
    offset = 0;
    scale = fraction;
  } else {
    offset = 1;
    scale = -fraction;
  }
}

}  // namespace

PtexAdjacency::PtexAdjacency(const PolygonMesh& cage, const SubdivisionSurface& surface) {
  const uint32_t num_ptex = surface.num_ptex_faces();
  sides_.resize(size_t(num_ptex) * 4);
  hole_.resize(num_ptex);
  base_face_.resize(num_ptex);
  for (uint32_t p = 0; p < num_ptex; ++p) {
    hole_[p] = !surface.has_limit_surface(p);
    base_face_[p] = surface.base_face_of_ptex(p);
  }
  for (size_t f = 0; f < cage.num_faces(); ++f) {
    const uint32_t n = cage.face_size(f);
    if (n == 4) {
      const uint32_t p = surface.ptex_face(uint32_t(f), 0);
      const uint32_t* v = cage.face_begin(f);
      Side* s = &sides_[size_t(p) * 4];
      along_edge(v[0], v[1], 1.0, s[0].line, s[0].offset, s[0].scale);
      along_edge(v[1], v[2], 1.0, s[1].line, s[1].offset, s[1].scale);
      along_edge(v[3], v[2], 1.0, s[2].line, s[2].offset, s[2].scale);
      along_edge(v[0], v[3], 1.0, s[3].line, s[3].offset, s[3].scale);
      continue;
    }
    for (uint32_t k = 0; k < n; ++k) {
      const uint32_t p = surface.ptex_face(uint32_t(f), k);
      const uint32_t vk = cage.face_vertex(f, k), vn = cage.face_vertex(f, (k + 1) % n),
                     vp = cage.face_vertex(f, (k + n - 1) % n);
      Side* s = &sides_[size_t(p) * 4];
      along_edge(vk, vn, 0.5, s[0].line, s[0].offset, s[0].scale);
      along_edge(vk, vp, 0.5, s[3].line, s[3].offset, s[3].scale);
      // Spokes from the midpoint of edge k (side 1) / edge k-1 (side 2) to the centre.
      s[1].line = (uint64_t(1) << 63) | (uint64_t(cage.face_offsets[f]) + k);
      s[2].line = (uint64_t(1) << 63) | (uint64_t(cage.face_offsets[f]) + (k + n - 1) % n);
      s[1].offset = s[2].offset = 0;
      s[1].scale = s[2].scale = 1;
    }
  }
  sorted_sides_.resize(sides_.size());
  std::iota(sorted_sides_.begin(), sorted_sides_.end(), 0u);
  std::sort(sorted_sides_.begin(), sorted_sides_.end(),
            [&](uint32_t a, uint32_t b) { return sides_[a].line < sides_[b].line || (sides_[a].line == sides_[b].line && a < b); });
  sorted_lines_.resize(sides_.size());
  for (size_t i = 0; i < sorted_sides_.size(); ++i) sorted_lines_[i] = sides_[sorted_sides_[i]].line;
}

uint64_t PtexAdjacency::cage_edge(uint32_t face, int side) const {
  if (face >= hole_.size() || side < 0 || side > 3) return kNoEdge;
  const uint64_t line = sides_[size_t(face) * 4 + size_t(side)].line;
  return (line >> 63) != 0 ? kNoEdge : line;
}

int PtexAdjacency::transfer(uint32_t& face, double& u, double& v, int side) const {
  if (face >= hole_.size() || side < 0 || side > 3) fail(Status::invalid_argument, "ptex transfer: bad face or side");
  const uint32_t id = face * 4 + uint32_t(side);
  const Side& from = sides_[id];
  const double sigma = (side == 0 || side == 2) ? u : v;
  const double s = from.offset + from.scale * sigma;
  const auto range = std::equal_range(sorted_lines_.begin(), sorted_lines_.end(), from.line);
  // The sides on this line from other base faces (a cage edge: the neighbouring face, with a
  // whole side or two n-gon half sides) or, on an n-gon's spoke, the next ptex face.
  const bool spoke = (from.line >> 63) != 0;
  uint32_t other_base = ~0u;
  bool non_manifold = false;
  uint32_t best = ~0u;
  double best_gap = HUGE_VAL;
  for (auto it = range.first; it != range.second; ++it) {
    const uint32_t other = sorted_sides_[size_t(it - sorted_lines_.begin())];
    if (other / 4 == face || (!spoke && base_face_[other / 4] == base_face_[face])) continue;
    if (other_base != ~0u && base_face_[other / 4] != other_base) non_manifold = true;
    other_base = base_face_[other / 4];
    const Side& to = sides_[other];
    const double lo = std::min(to.offset, to.offset + to.scale), hi = std::max(to.offset, to.offset + to.scale);
    const double gap = s < lo ? lo - s : s > hi ? s - hi : 0.0;
    if (gap < best_gap) best_gap = gap, best = other;
  }
  if (best == ~0u || best_gap > 1e-9 || non_manifold || hole_[best / 4]) return -1;
  const Side& to = sides_[best];
  const double t = std::clamp((s - to.offset) / to.scale, 0.0, 1.0);
  const int to_side = int(best % 4);
  face = best / 4;
  switch (to_side) {
    case 0: u = t, v = 0; break;
    case 1: u = 1, v = t; break;
    case 2: u = t, v = 1; break;
    default: u = 0, v = t; break;
  }
  return to_side;
}

CAGEKIT_NAMESPACE_END
