// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The demo's built-in input: a synthetic "scan" of a CAD-like part (a rectangular block),
// densely triangulated, watertight, with seeded noise along the surface normal.
#include <cstdint>
#include <vector>

namespace cli {

struct DemoPart {
  std::vector<double> positions;     // xyz per vertex
  std::vector<uint32_t> triangles;   // 3 indices per triangle, outward-oriented
  double size[3];                    // block extents
};

// A block of extents size[] with about `cells_per_unit` grid cells per unit length on every face,
// each cell split into two triangles, vertices displaced along the face normal by uniform noise
// of amplitude `noise` (absolute), from a fixed seed.
DemoPart make_demo_part(const double size[3], int cells_per_unit, double noise, uint32_t seed);

}  // namespace cli
