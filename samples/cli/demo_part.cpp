// SPDX-License-Identifier: GPL-3.0-or-later
#include "demo_part.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>

namespace cli {

DemoPart make_demo_part(const double size[3], int cells_per_unit, double noise, uint32_t seed) {
  DemoPart part;
  int n[3];
  for (int k = 0; k < 3; ++k) {
    part.size[k] = size[k];
    n[k] = std::max(1, static_cast<int>(std::lround(size[k] * cells_per_unit)));
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-noise, noise);
  // Lattice points on the block's surface are shared between faces, so the mesh is watertight.
  std::map<std::array<int, 3>, uint32_t> lattice;
  auto vertex = [&](std::array<int, 3> g, int axis, int side) {
    auto it = lattice.find(g);
    if (it != lattice.end()) return it->second;
    const uint32_t id = static_cast<uint32_t>(part.positions.size() / 3);
    for (int k = 0; k < 3; ++k) {
      double p = size[k] * g[k] / n[k];
      if (k == axis) p += side ? jitter(rng) : -jitter(rng);
      part.positions.push_back(p);
    }
    lattice.emplace(g, id);
    return id;
  };
  for (int axis = 0; axis < 3; ++axis) {
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      for (int i = 0; i < n[a]; ++i)
        for (int j = 0; j < n[b]; ++j) {
          uint32_t q[4];
          const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
          for (int c = 0; c < 4; ++c) {
            std::array<int, 3> g{};
            g[axis] = side ? n[axis] : 0;
            g[a] = i + di[c];
            g[b] = j + dj[c];
            q[c] = vertex(g, axis, side);
          }
          // (a, b, axis) is right-handed: counter-clockwise in (a, b) faces +axis.
          if (side) {
            part.triangles.insert(part.triangles.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
          } else {
            part.triangles.insert(part.triangles.end(), {q[0], q[2], q[1], q[0], q[3], q[2]});
          }
        }
    }
  }
  return part;
}

}  // namespace cli
