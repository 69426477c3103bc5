// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Shared helpers for the C++ unit tests: locating the shared meshes, small generated meshes.
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "core/cage.h"
#include "core/io/mesh_io.h"
#include "core/polygon_mesh.h"
#include "core/status.h"

namespace cagekit_test {

// Full path of ../shared/meshes/NAME, or "" when it is not present (tests then GTEST_SKIP).
std::string shared_mesh_path(const std::string& name);

// Reads a mesh file with the library's reader (tags dropped).
cagekit::PolygonMesh load_mesh(const std::string& path);

// An axis-aligned unit cube of 6 quads, outward-oriented, vertices at {0,1}^3.
cagekit::PolygonMesh unit_cube_quads();
// The same cube as a cage with all 12 edges tagged infinitely sharp (refined: a box with flat
// sides and sharp edges).
cagekit::Cage creased_unit_cube();

// A regular grid of nx * ny quads over [0,nx]x[0,ny] at z = height(x, y); open boundary.
cagekit::PolygonMesh quad_grid(int nx, int ny, double (*height)(double x, double y) = nullptr);

// A small random polygon soup: 4-13 vertices on an integer grid, 1-9 faces of 3-6 distinct
// vertices (non-manifold edges and vertices, inconsistent orientation: for crash tests).
cagekit::PolygonMesh random_polygon_soup(std::mt19937& rng);

// An open cylinder of radius r about the z axis, z in [0, height]: n_around x n_along quads, each
// split into two triangles with diagonals alternating like a checkerboard, outward-oriented.
cagekit::PolygonMesh triangle_cylinder(double radius, double height, int n_around, int n_along);

// A UV-sphere-like closed mesh of triangles (an octahedron subdivided `levels` times, projected).
cagekit::PolygonMesh triangle_sphere(int levels);

// Torus about the z axis: ring radius R, tube radius r, n_u x n_v quads each split along its
// diagonal (a, c), outward-oriented triangles.
cagekit::PolygonMesh triangle_torus(double R, double r, int n_u, int n_v);

// A closed torus of nu x nv quads about the z axis (ring radius 2, tube radius 0.7): every vertex
// has valence 4, so the limit surface is one bicubic B-spline patch per face. With `split_first`
// the first quad is split into two triangles (two valence-5 vertices, triangles next to quads).
cagekit::PolygonMesh quad_torus(int nu, int nv, bool split_first = false);

// `mesh` as a cage without tags.
cagekit::Cage cage_of(cagekit::PolygonMesh mesh);

// An open, gently curved 20x20 quad grid (the scan) and a 4x4 quad cage over the same square
// with its vertices on the same height field (z = 0.05 sin(0.3 x) y).
struct OpenGrid {
  cagekit::PolygonMesh scan;
  cagekit::Cage cage;
};
OpenGrid open_grid_scan_and_cage();

// What reading bytes with the library's reader gave: the cage, or the error's status and message.
struct ReadOutcome {
  bool ok = false;
  cagekit::Status status = cagekit::Status::success;
  std::string message;
  cagekit::Cage cage;
};
ReadOutcome try_read_memory(const std::vector<uint8_t>& bytes, cagekit::FileFormat format, const std::string& name,
                            const cagekit::ReadOptions& options = {});
std::vector<uint8_t> bytes_of(const std::string& text);

// The status f() throws as cagekit::Error, or success.
cagekit::Status status_of(const std::function<void()>& f);

}  // namespace cagekit_test
