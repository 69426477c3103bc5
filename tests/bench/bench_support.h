// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Measurement helpers shared by the benchmarks: wall and process-CPU clocks, load average,
// /proc/self/status fields (VmHWM, VmRSS); OpenMesh conversions and the generated
// bunny-1.1M input (bench_io, bench_simplify, bench_remesh). The OpenMesh functions are inline
// templates' users only: benchmarks that do not call them need no OpenMesh library.
#include <malloc.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "core/polygon_mesh.h"

namespace bench {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Process CPU time: robust to other processes competing for the cores (everything timed here is
// single-threaded, so on an idle machine it equals the wall time).
inline double cpu_seconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

inline std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  in >> one >> five >> fifteen;
  return one + " " + five + " " + fifteen;
}

// A "Field:   1234 kB" line of /proc/self/status, in KiB; -1 if absent.
inline long status_kib(const char* field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::string key = std::string(field) + ":";
  while (std::getline(in, line))
    if (line.compare(0, key.size(), key) == 0) return std::atol(line.c_str() + key.size());
  return -1;
}

// Brackets the timed library call in a child: RSS before (after malloc_trim + VmHWM reset), wall
// and CPU time, VmHWM right after.
struct Meter {
  long before_kib = 0, peak_kib = 0;
  Clock::time_point start;
  double cpu0 = 0, wall = 0, cpu = 0;
  void begin() {
    malloc_trim(0);
    std::ofstream("/proc/self/clear_refs") << "5";
    before_kib = status_kib("VmRSS");
    cpu0 = cpu_seconds();
    start = Clock::now();
  }
  void end() {
    wall = seconds_since(start);
    cpu = cpu_seconds() - cpu0;
    peak_kib = status_kib("VmHWM");
  }
};

// Runs `f` in a forked child; the child fills `n` Results that come back through a pipe. Result:
// trivially copyable, with `bool ok` and `char error[...]` (set from an exception, or "child
// died" when the child ends without writing them back, e.g. killed by the 600 s alarm).
template <class Result>
std::vector<Result> in_child(size_t n, const std::function<void(std::vector<Result>&)>& f) {
  std::vector<Result> results(n);
  int fd[2];
  if (pipe(fd) != 0) std::abort();
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    alarm(600);  // a hung tool ends as 'child died', not as a hung benchmark
    try {
      f(results);
    } catch (const std::exception& e) {
      for (Result& r : results) {
        r.ok = false;
        std::snprintf(r.error, sizeof r.error, "%s", e.what());
      }
    }
    const char* p = reinterpret_cast<const char*>(results.data());
    size_t left = n * sizeof(Result);
    while (left > 0) {
      const ssize_t w = write(fd[1], p, left);
      if (w <= 0) break;
      p += w;
      left -= size_t(w);
    }
    close(fd[1]);
    std::fflush(stdout);
    _exit(0);
  }
  close(fd[1]);
  char* p = reinterpret_cast<char*>(results.data());
  size_t got = 0;
  while (got < n * sizeof(Result)) {
    const ssize_t r = read(fd[0], p + got, n * sizeof(Result) - got);
    if (r <= 0) break;
    got += size_t(r);
  }
  close(fd[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (got != n * sizeof(Result)) {
    results.assign(n, Result{});
    for (Result& r : results) std::snprintf(r.error, sizeof r.error, "child died (status %d)", status);
  }
  return results;
}

// --- OpenMesh (double precision) and the generated dense input ---

struct OmTraits : OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
using OmMesh = OpenMesh::TriMesh_ArrayKernelT<OmTraits>;

// Faces OpenMesh refuses (non-manifold additions) are skipped and counted in *rejected_faces.
inline OmMesh to_openmesh(const cagekit::PolygonMesh& mesh, size_t* rejected_faces = nullptr) {
  OmMesh om;
  std::vector<OmMesh::VertexHandle> vh;
  vh.reserve(mesh.num_vertices());
  for (const cagekit::Vec3& p : mesh.positions) vh.push_back(om.add_vertex(OmMesh::Point(p.x, p.y, p.z)));
  size_t rejected = 0;
  std::vector<OmMesh::VertexHandle> face;
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    face.clear();
    for (uint32_t k = 0; k < mesh.face_size(f); ++k) face.push_back(vh[mesh.face_vertex(f, k)]);
    if (!om.add_face(face).is_valid()) ++rejected;
  }
  if (rejected_faces) *rejected_faces = rejected;
  return om;
}

inline cagekit::PolygonMesh from_openmesh(const OmMesh& om) {
  cagekit::PolygonMesh mesh;
  mesh.reserve(om.n_vertices(), om.n_faces(), 3 * om.n_faces());
  for (const auto v : om.vertices()) {
    const OmMesh::Point& p = om.point(v);
    mesh.add_vertex({p[0], p[1], p[2]});
  }
  uint32_t tri[3];
  for (const auto f : om.faces()) {
    int k = 0;
    for (const auto v : om.fv_range(f)) tri[k++] = static_cast<uint32_t>(v.idx());
    mesh.add_face(tri, 3);
  }
  return mesh;
}

// bunny-1.1M: the bunny (without its unreferenced vertices) Loop-subdivided twice with OpenMesh's
// LoopT, each vertex moved along its normal by seeded Gaussian noise of sigma = 1e-4 of the
// bounding-box diagonal (556,051 vertices, 1,111,216 triangles from the shared bunny).
inline cagekit::PolygonMesh dense_bunny(const cagekit::PolygonMesh& bunny) {
  size_t rejected = 0;
  OmMesh om = to_openmesh(bunny, &rejected);
  if (rejected) std::printf("  (OpenMesh rejected %zu bunny faces while building the dense mesh)\n", rejected);
  OpenMesh::Subdivider::Uniform::LoopT<OmMesh, double> loop;
  loop.attach(om);
  loop(2);
  loop.detach();
  om.request_face_normals();
  om.request_vertex_normals();
  om.update_normals();
  const double sigma = 1e-4 * bunny.bounding_box().diagonal();
  std::mt19937_64 rng(20261123);
  std::normal_distribution<double> noise(0.0, sigma);
  for (const auto v : om.vertices()) om.set_point(v, om.point(v) + om.normal(v) * noise(rng));
  return from_openmesh(om);
}

}  // namespace bench
