// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Generated scans for the C++ layer's tests (no files: the tests must not depend on ../shared).
#include <cmath>
#include <cstdint>
#include <vector>

namespace {

// A UV sphere of radius 0.75 around (0.5, 0.5, 0.5): kRings - 1 rings of kSegments vertices and
// two poles, triangles only, outward-facing.
constexpr uint32_t kRings = 12, kSegments = 16;
constexpr uint32_t kSphereVertices = 2 + (kRings - 1) * kSegments;
constexpr uint32_t kSphereTriangles = 2 * kSegments + 2 * kSegments * (kRings - 2);

struct Geometry {
  std::vector<double> positions;
  std::vector<uint32_t> triangles;
};

inline Geometry sphere_geometry() {
  const double pi = 3.14159265358979323846;
  Geometry g;
  auto add = [&](double x, double y, double z) {
    g.positions.insert(g.positions.end(), {0.5 + 0.75 * x, 0.5 + 0.75 * y, 0.5 + 0.75 * z});
  };
  add(0, 0, 1);
  for (uint32_t r = 1; r < kRings; ++r)
    for (uint32_t k = 0; k < kSegments; ++k) {
      const double theta = pi * r / kRings, phi = 2 * pi * k / kSegments;
      add(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    }
  add(0, 0, -1);
  const uint32_t south = kSphereVertices - 1;
  for (uint32_t k = 0; k < kSegments; ++k) g.triangles.insert(g.triangles.end(), {0, 1 + k, 1 + (k + 1) % kSegments});
  for (uint32_t r = 1; r + 1 < kRings; ++r)
    for (uint32_t k = 0; k < kSegments; ++k) {
      const uint32_t k1 = (k + 1) % kSegments;
      const uint32_t a = 1 + (r - 1) * kSegments + k, b = 1 + (r - 1) * kSegments + k1;
      const uint32_t c = a + kSegments, d = b + kSegments;
      g.triangles.insert(g.triangles.end(), {a, c, d, a, d, b});
    }
  const uint32_t base = 1 + (kRings - 2) * kSegments;
  for (uint32_t k = 0; k < kSegments; ++k)
    g.triangles.insert(g.triangles.end(), {south, base + (k + 1) % kSegments, base + k});
  return g;
}

// The unit cube as six quads.
const std::vector<double> kCube = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 0, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1};
const std::vector<uint32_t> kCubeQuads = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};

}  // namespace
