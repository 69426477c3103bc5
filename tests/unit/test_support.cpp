// SPDX-License-Identifier: GPL-3.0-or-later
#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <utility>

#include "core/io/mesh_io.h"

namespace cagekit_test {

using cagekit::PolygonMesh;
using cagekit::Vec3;

std::string shared_mesh_path(const std::string& name) {
  const std::string path = std::string(CAGEKIT_SHARED_MESHES) + "/" + name;
  std::ifstream probe(path);
  return probe.good() ? path : std::string();
}

PolygonMesh load_mesh(const std::string& path) { return cagekit::read_cage_from_file(path).mesh; }

PolygonMesh random_polygon_soup(std::mt19937& rng) {
  PolygonMesh mesh;
  const uint32_t nv = 4 + rng() % 10;
  for (uint32_t v = 0; v < nv; ++v) mesh.add_vertex(Vec3(rng() % 7, rng() % 5, rng() % 3));
  const int nf = 1 + static_cast<int>(rng() % 9);
  for (int f = 0; f < nf; ++f) {
    std::vector<uint32_t> face;
    const uint32_t size = 3 + rng() % std::min<uint32_t>(4, nv - 2);
    while (face.size() < size) {
      const uint32_t v = rng() % nv;
      if (std::find(face.begin(), face.end(), v) == face.end()) face.push_back(v);
    }
    mesh.add_face(face.data(), face.size());
  }
  return mesh;
}

PolygonMesh unit_cube_quads() {
  PolygonMesh m;
  for (int i = 0; i < 8; ++i) m.add_vertex(Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  // Outward-oriented (counter-clockwise seen from outside).
  m.add_face({0, 2, 3, 1});  // z = 0
  m.add_face({4, 5, 7, 6});  // z = 1
  m.add_face({0, 1, 5, 4});  // y = 0
  m.add_face({2, 6, 7, 3});  // y = 1
  m.add_face({0, 4, 6, 2});  // x = 0
  m.add_face({1, 3, 7, 5});  // x = 1
  return m;
}

cagekit::Cage creased_unit_cube() {
  cagekit::Cage cube;
  cube.mesh = unit_cube_quads();
  for (size_t f = 0; f < cube.mesh.num_faces(); ++f)
    for (uint32_t k = 0; k < 4; ++k) {
      const uint32_t a = cube.mesh.face_vertex(f, k), b = cube.mesh.face_vertex(f, (k + 1) % 4);
      if (a < b) cube.creases.push_back({a, b, cagekit::kSharpnessInfinite});
    }
  return cube;
}

PolygonMesh quad_grid(int nx, int ny, double (*height)(double, double)) {
  PolygonMesh m;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) m.add_vertex(Vec3(i, j, height ? height(i, j) : 0.0));
  auto id = [nx](int i, int j) { return static_cast<uint32_t>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) m.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return m;
}

PolygonMesh triangle_torus(double R, double r, int n_u, int n_v) {
  const double pi = 3.14159265358979323846;
  PolygonMesh m;
  for (int i = 0; i < n_u; ++i)
    for (int j = 0; j < n_v; ++j) {
      const double u = 2 * pi * i / n_u, v = 2 * pi * j / n_v;
      m.add_vertex({(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)});
    }
  auto id = [&](int i, int j) { return uint32_t((i % n_u) * n_v + (j % n_v)); };
  for (int i = 0; i < n_u; ++i)
    for (int j = 0; j < n_v; ++j) {
      const uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      m.add_face({a, b, c});
      m.add_face({a, c, d});
    }
  return m;
}

PolygonMesh triangle_sphere(int levels) {
  PolygonMesh m;
  const Vec3 v[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (const Vec3& p : v) m.add_vertex(p);
  const uint32_t f[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                            {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (const auto& t : f) m.add_face(t, 3);
  for (int l = 0; l < levels; ++l) {
    PolygonMesh next;
    next.positions = m.positions;
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      const uint32_t id = next.add_vertex(cagekit::normalized(0.5 * (next.positions[a] + next.positions[b])));
      mid.emplace(key, id);
      return id;
    };
    for (size_t t = 0; t < m.num_faces(); ++t) {
      const uint32_t a = m.face_vertex(t, 0), b = m.face_vertex(t, 1), c = m.face_vertex(t, 2);
      const uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      next.add_face({a, ab, ca});
      next.add_face({ab, b, bc});
      next.add_face({ca, bc, c});
      next.add_face({ab, bc, ca});
    }
    m = std::move(next);
  }
  return m;
}

OpenGrid open_grid_scan_and_cage() {
  double (*height)(double, double) = [](double x, double y) { return 0.05 * std::sin(0.3 * x) * y; };
  OpenGrid g;
  g.scan = quad_grid(20, 20, height);
  g.cage.mesh = quad_grid(4, 4);
  for (Vec3& p : g.cage.mesh.positions) p = {5 * p.x, 5 * p.y, height(5 * p.x, 5 * p.y)};
  return g;
}

cagekit::Status status_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const cagekit::Error& e) {
    return e.status();
  }
  return cagekit::Status::success;
}

cagekit::PolygonMesh triangle_cylinder(double radius, double height, int n_around, int n_along) {
  const double pi = 3.14159265358979323846;
  cagekit::PolygonMesh m;
  for (int j = 0; j <= n_along; ++j)
    for (int i = 0; i < n_around; ++i) {
      const double a = 2 * pi * i / n_around;
      m.add_vertex({radius * std::cos(a), radius * std::sin(a), height * j / n_along});
    }
  auto id = [&](int i, int j) { return uint32_t(j * n_around + (i % n_around)); };
  for (int j = 0; j < n_along; ++j)
    for (int i = 0; i < n_around; ++i) {
      const uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if ((i + j) % 2) {
        m.add_face({a, b, d});
        m.add_face({b, c, d});
      } else {
        m.add_face({a, b, c});
        m.add_face({a, c, d});
      }
    }
  return m;
}

ReadOutcome try_read_memory(const std::vector<uint8_t>& bytes, cagekit::FileFormat format, const std::string& name,
                            const cagekit::ReadOptions& options) {
  ReadOutcome out;
  try {
    out.cage = cagekit::read_cage_from_memory(bytes.data(), bytes.size(), format, name, options);
    out.ok = true;
  } catch (const cagekit::Error& e) {
    out.status = e.status();
    out.message = e.what();
  }
  return out;
}

std::vector<uint8_t> bytes_of(const std::string& text) { return std::vector<uint8_t>(text.begin(), text.end()); }

PolygonMesh quad_torus(int nu, int nv, bool split_first) {
  PolygonMesh m;
  const double pi = std::acos(-1.0);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double a = 2 * pi * i / nu, b = 2 * pi * j / nv;
      m.positions.push_back({(2.0 + 0.7 * std::cos(b)) * std::cos(a), (2.0 + 0.7 * std::cos(b)) * std::sin(a),
                             0.7 * std::sin(b)});
    }
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const uint32_t i1 = uint32_t((i + 1) % nu), j1 = uint32_t((j + 1) % nv);
      const uint32_t a = uint32_t(j * nu + i), b = uint32_t(j * nu) + i1, c = j1 * uint32_t(nu) + i1,
                     d = j1 * uint32_t(nu) + uint32_t(i);
      if (split_first && i == 0 && j == 0) {
        m.add_face({a, b, c});
        m.add_face({a, c, d});
      } else {
        m.add_face({a, b, c, d});
      }
    }
  return m;
}

cagekit::Cage cage_of(PolygonMesh mesh) {
  cagekit::Cage c;
  c.mesh = std::move(mesh);
  return c;
}

}  // namespace cagekit_test
