// SPDX-License-Identifier: GPL-3.0-or-later
// Timings of the subdivision layer (not part of the CMake build; see the build line below).
//   g++ -O3 -DNDEBUG -std=c++17 -Isdk -Itests/unit tests/bench/bench_subdivide.cpp
//       tests/unit/test_support.cpp -DCAGEKIT_SHARED_MESHES='"../shared/meshes"'
//       build-rel/sdk/subdiv/libcagekit_subdiv.a build-rel/sdk/core/libcagekit_core.a -losdCPU -o bench_subdivide
// Prints: fandisk uniform refinement to levels 1-3 (median of 5), SubdivisionSurface
// construction on generated cages, evaluate()/basis() cost per call.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "subdiv/subdivision_surface.h"
#include "subdiv/uniform_refinement.h"
#include "test_support.h"

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

cagekit::PolygonMesh read_obj(const std::string& path) {
  cagekit::PolygonMesh m;
  std::ifstream in(path);
  std::string line;
  std::vector<uint32_t> face;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v") {
      cagekit::Vec3 p;
      s >> p.x >> p.y >> p.z;
      m.add_vertex(p);
    } else if (tag == "f") {
      face.clear();
      std::string token;
      while (s >> token) face.push_back(static_cast<uint32_t>(std::stol(token.substr(0, token.find('/'))) - 1));
      m.add_face(face.data(), face.size());
    }
  }
  return m;
}

template <typename F>
double median_seconds(int runs, F&& f) {
  std::vector<double> t;
  for (int i = 0; i < runs; ++i) {
    const auto start = Clock::now();
    f();
    t.push_back(seconds_since(start));
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

void bench_surface(const char* name, const cagekit::Cage& cage, int isolation) {
  cagekit::SurfaceOptions options;
  options.isolation_level = isolation;
  const auto start = Clock::now();
  const cagekit::SubdivisionSurface surface(cage, options);
  const double build = seconds_since(start);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> unit(0, 1);
  const int n = 200000;
  std::vector<std::array<double, 3>> q(n);
  for (auto& x : q) x = {double(rng() % surface.num_ptex_faces()), unit(rng), unit(rng)};
  auto t0 = Clock::now();
  double sink = 0;
  for (const auto& x : q) sink += surface.evaluate(uint32_t(x[0]), x[1], x[2]).position.x;
  const double eval = seconds_since(t0) / n;
  t0 = Clock::now();
  for (const auto& x : q) sink += surface.evaluate(uint32_t(x[0]), x[1], x[2], cage.mesh.positions).du.x;
  const double eval_control = seconds_since(t0) / n;
  t0 = Clock::now();
  for (int i = 0; i < n / 4; ++i) sink += surface.basis(uint32_t(q[i][0]), q[i][1], q[i][2]).w.size();
  const double basis = seconds_since(t0) / (n / 4);
  std::printf("%-28s isolation %d: %zu faces, build %.1f ms, evaluate %.0f ns, evaluate(control) %.0f ns, "
              "basis %.0f ns (sink %g)\n",
              name, isolation, cage.mesh.num_faces(), build * 1e3, eval * 1e9, eval_control * 1e9, basis * 1e9, sink);
}

}  // namespace

int main() {
  const std::string path = cagekit_test::shared_mesh_path("fandisk.obj");
  if (!path.empty()) {
    cagekit::Cage fandisk;
    fandisk.mesh = read_obj(path);
    for (int levels = 1; levels <= 3; ++levels) {
      cagekit::RefineOptions options;
      options.levels = levels;
      const double t = median_seconds(5, [&] { cagekit::refine_uniform(fandisk, options); });
      options.limit_positions = true;
      const double tl = median_seconds(5, [&] { cagekit::refine_uniform(fandisk, options); });
      std::printf("fandisk refine_uniform level %d: %.1f ms (with limit positions %.1f ms)\n", levels, t * 1e3, tl * 1e3);
    }
    bench_surface("fandisk (12946 triangles)", fandisk, 6);
  }
  cagekit::Cage sphere;
  sphere.mesh = cagekit_test::triangle_sphere(3);
  for (int isolation : {2, 4, 6, 8, 10}) bench_surface("triangle sphere (512 tris)", sphere, isolation);
  cagekit::Cage grid;
  grid.mesh = cagekit_test::quad_grid(24, 24, [](double x, double y) { return 0.1 * x * y; });
  bench_surface("quad grid 24x24", grid, 6);
  return 0;
}
