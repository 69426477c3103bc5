// SPDX-License-Identifier: GPL-3.0-or-later
// bench_evaluate: limit-surface evaluation at N random (ptex face, u, v) points of a cage, in one
// process on the same points:
//   * CageKit  cagekit::SubdivisionSurface (sdk/subdiv/subdivision_surface.h): construction, then
//              evaluate(face, u, v) per point (position, du, dv and 2nd derivatives, with the
//              cage's own control points), and evaluate(face, u, v, control) (any control array,
//              the deformation case)
//   * peer     OpenSubdiv 3.5 Far: TopologyRefinerFactory<TopologyDescriptor> + RefineAdaptive
//              (same isolation level, useInfSharpPatch as CageKit) + LimitStencilTableFactoryReal
//              <double>::Create for the N locations (1st derivatives on), then per frame
//              LimitStencilTable::UpdateValues + UpdateDerivs (position, du, dv) over all N
// Cages: fandisk as a cage (12,946 triangles, no tags) and a quad-only cage, fandisk refined once
// by CageKit (38,838 quads). Usage: bench_evaluate [N=100000] [isolation=6].
// Method (as in ../shared/spec/peer-measurements.md §4): steady_clock around the library calls
// only; setup timed once (it takes seconds); per-point times: median of 5 passes over all N
// points; peak RSS of each setup above the RSS before it (VmHWM reset by /proc/self/clear_refs).
// Agreement: max |CageKit - OpenSubdiv| of the positions, and of du/dv relative to their size.
// Never fails on timing.
#include <malloc.h>
#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/ptexIndices.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "core/cage.h"
#include "core/io/mesh_io.h"
#include "core/status.h"
#include "subdiv/subdivision_surface.h"
#include "subdiv/uniform_refinement.h"

namespace {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;
using Clock = std::chrono::steady_clock;

constexpr int kPasses = 5;

// --- measurement helpers (each benchmark is self-contained) ---

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Process CPU time: robust to other processes competing for the cores (everything timed here is
// single-threaded, so on an idle machine it equals the wall time).
double cpu_seconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

struct Seconds {
  double wall = 0, cpu = 0;
  Seconds operator/(double d) const { return {wall / d, cpu / d}; }
  Seconds operator+(const Seconds& o) const { return {wall + o.wall, cpu + o.cpu}; }
};

struct Stopwatch {
  Clock::time_point wall0 = Clock::now();
  double cpu0 = cpu_seconds();
  Seconds elapsed() const { return {seconds_since(wall0), cpu_seconds() - cpu0}; }
};

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  in >> one >> five >> fifteen;
  return one + " " + five + " " + fifteen;
}

// "wall ratio (CPU-time ratio)"
std::string ratio(const Seconds& a, const Seconds& b) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.2f (%.2f)", a.wall / b.wall, a.cpu / b.cpu);
  return buf;
}

long status_kib(const char* field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::string key = std::string(field) + ":";
  while (std::getline(in, line))
    if (line.compare(0, key.size(), key) == 0) return std::atol(line.c_str() + key.size());
  return -1;
}

// Peak RSS of a region above the RSS at its start, in MiB (VmHWM reset through clear_refs).
struct PeakRss {
  long start_kib = 0;
  void begin() {
    malloc_trim(0);
    std::ofstream("/proc/self/clear_refs") << "5";
    start_kib = status_kib("VmRSS");
  }
  double mib_above_start() const { return (status_kib("VmHWM") - start_kib) / 1024.0; }
};

// Median of the wall times and median of the CPU times of `runs` runs.
template <typename F>
Seconds median_seconds(int runs, F&& f) {
  std::vector<double> wall, cpu;
  for (int i = 0; i < runs; ++i) {
    const Stopwatch sw;
    f();
    const Seconds e = sw.elapsed();
    wall.push_back(e.wall);
    cpu.push_back(e.cpu);
  }
  std::sort(wall.begin(), wall.end());
  std::sort(cpu.begin(), cpu.end());
  return {wall[wall.size() / 2], cpu[cpu.size() / 2]};
}

std::string shared_mesh(const char* name) {
  const std::string path = std::string(CAGEKIT_SHARED_MESHES) + "/" + name;
  return std::ifstream(path).good() ? path : std::string();
}

// --- the peer: OpenSubdiv limit stencils ---

struct Point3 {
  double x = 0, y = 0, z = 0;
  void Clear() { x = y = z = 0; }
  void AddWithWeight(const Point3& s, double w) {
    x += w * s.x;
    y += w * s.y;
    z += w * s.z;
  }
};

struct PeerInput {
  std::vector<int> sizes, indices;
  std::vector<Point3> control;
};

PeerInput peer_input(const cagekit::PolygonMesh& mesh) {
  PeerInput in;
  for (size_t f = 0; f < mesh.num_faces(); ++f) in.sizes.push_back(static_cast<int>(mesh.face_size(f)));
  in.indices.assign(mesh.face_vertices.begin(), mesh.face_vertices.end());
  for (const cagekit::Vec3& p : mesh.positions) in.control.push_back({p.x, p.y, p.z});
  return in;
}

std::unique_ptr<Far::TopologyRefiner> peer_refiner(const PeerInput& in, int isolation) {
  Far::TopologyDescriptor desc;
  desc.numVertices = static_cast<int>(in.control.size());
  desc.numFaces = static_cast<int>(in.sizes.size());
  desc.numVertsPerFace = in.sizes.data();
  desc.vertIndicesPerFace = in.indices.data();
  Sdc::Options sdc;  // CageKit's defaults for an untagged cage
  sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  sdc.SetCreasingMethod(Sdc::Options::CREASE_UNIFORM);
  sdc.SetTriangleSubdivision(Sdc::Options::TRI_SUB_CATMARK);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> refiner(Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdc)));
  Far::TopologyRefiner::AdaptiveOptions adaptive(isolation);
  adaptive.useInfSharpPatch = true;
  refiner->RefineAdaptive(adaptive);
  return refiner;
}

struct Location {
  uint32_t face;
  double u, v;
};

struct Result {
  std::string cage;
  size_t faces = 0, ptex = 0;
  Seconds ck_setup, ck_eval, ck_eval_control, ck_basis, ck_basis_apply, peer_setup, peer_stencils, peer_eval;
  double ck_setup_mib = 0, peer_setup_mib = 0;
  size_t peer_weights = 0;
  double fd_ck_median = 0, fd_osd_median = 0, basis_max_diff = 0;
  size_t ck_basis_weights = 0;
  double max_pos_diff = 0, diag = 0, max_deriv_rel = 0, deriv_scale_median = 0, deriv_differing = 0;
  bool ran = false;
};

double rel(const cagekit::Vec3& a, const Point3& b) {
  const double d = std::max({std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - b.z)});
  const double m = std::max({std::abs(a.x), std::abs(a.y), std::abs(a.z), 1e-300});
  return d / m;
}

Result run(const std::string& label, const cagekit::Cage& cage, int n, int isolation) {
  Result r;
  r.cage = label;
  r.faces = cage.mesh.num_faces();
  r.diag = cage.mesh.bounding_box().diagonal();
  std::printf("%s: %zu vertices, %zu faces, isolation %d, %d points\n", label.c_str(), cage.mesh.num_vertices(),
              cage.mesh.num_faces(), isolation, n);
  std::fflush(stdout);

  // CageKit setup.
  cagekit::SurfaceOptions options;
  options.isolation_level = isolation;
  PeakRss rss;
  rss.begin();
  Stopwatch sw;
  auto surface = std::make_unique<cagekit::SubdivisionSurface>(cage, options);
  r.ck_setup = sw.elapsed();
  r.ck_setup_mib = rss.mib_above_start();
  r.ptex = surface->num_ptex_faces();
  std::printf("  CageKit SubdivisionSurface: %.2f s, %.0f MiB\n", r.ck_setup.wall, r.ck_setup_mib);
  std::fflush(stdout);

  // The same random points for both.
  std::mt19937_64 rng(20261123);
  std::uniform_int_distribution<uint32_t> face(0, static_cast<uint32_t>(r.ptex - 1));
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Location> where(static_cast<size_t>(n));
  for (Location& l : where) {
    l.face = face(rng);
    l.u = unit(rng);
    l.v = unit(rng);
  }

  std::vector<cagekit::Vec3> fd_du;  // central differences of the positions
  std::vector<Location> fd_where;
  std::vector<cagekit::SurfacePoint> ck(where.size());
  r.ck_eval = median_seconds(kPasses, [&] {
                for (size_t i = 0; i < where.size(); ++i) ck[i] = surface->evaluate(where[i].face, where[i].u, where[i].v);
              }) / n;
  std::vector<cagekit::SurfacePoint> ck_control(where.size());
  const std::vector<cagekit::Vec3>& control = cage.mesh.positions;
  r.ck_eval_control = median_seconds(kPasses, [&] {
                        for (size_t i = 0; i < where.size(); ++i)
                          ck_control[i] = surface->evaluate(where[i].face, where[i].u, where[i].v, control);
                      }) / n;

  // CageKit's stencil path: basis() per point (phi_j, phi_j,u, phi_j,v over the cage vertices),
  // kept as a CSR table, then applied to the control points by a plain loop (this file's code).
  std::vector<uint32_t> offsets{0}, indices;
  std::vector<double> w, wu, wv;
  sw = Stopwatch();
  for (const Location& l : where) {
    const cagekit::BasisWeights b = surface->basis(l.face, l.u, l.v);
    indices.insert(indices.end(), b.indices.begin(), b.indices.end());
    w.insert(w.end(), b.w.begin(), b.w.end());
    wu.insert(wu.end(), b.wu.begin(), b.wu.end());
    wv.insert(wv.end(), b.wv.begin(), b.wv.end());
    offsets.push_back(static_cast<uint32_t>(indices.size()));
  }
  r.ck_basis = sw.elapsed() / n;
  r.ck_basis_weights = indices.size();
  std::vector<cagekit::Vec3> basis_p(where.size()), basis_du(where.size()), basis_dv(where.size());
  r.ck_basis_apply = median_seconds(kPasses, [&] {
                       for (size_t i = 0; i < where.size(); ++i) {
                         cagekit::Vec3 p, pu, pv;
                         for (uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
                           const cagekit::Vec3& c = control[indices[k]];
                           p += c * w[k];
                           pu += c * wu[k];
                           pv += c * wv[k];
                         }
                         basis_p[i] = p;
                         basis_du[i] = pu;
                         basis_dv[i] = pv;
                       }
                     }) / n;

  // A neutral referee for the first derivatives: central differences of the positions (CageKit's
  // and OpenSubdiv's positions agree to rounding, see below), step 1e-5 in u.
  {
    const double h = 1e-5;
    std::vector<double> err_ck;
    for (size_t i = 0; i < where.size() && i < 2000; ++i) {
      const double u = std::min(std::max(where[i].u, 2 * h), 1 - 2 * h);
      const cagekit::Vec3 a = surface->evaluate(where[i].face, u + h, where[i].v).position;
      const cagekit::Vec3 b = surface->evaluate(where[i].face, u - h, where[i].v).position;
      const cagekit::Vec3 fd = (a - b) * (1 / (2 * h));
      const cagekit::Vec3 du_ck = surface->evaluate(where[i].face, u, where[i].v).du;
      fd_du.push_back(fd);
      fd_where.push_back({where[i].face, u, where[i].v});
      err_ck.push_back(cagekit::norm(du_ck - fd) / std::max(cagekit::norm(fd), 1e-300));
    }
    std::sort(err_ck.begin(), err_ck.end());
    r.fd_ck_median = err_ck.empty() ? 0 : err_ck[err_ck.size() / 2];
  }
  surface.reset();

  // Peer setup: refiner + adaptive refinement + limit stencil table for the N locations.
  const PeerInput in = peer_input(cage.mesh);
  std::vector<double> s(where.size()), t(where.size());
  Far::LimitStencilTableFactoryReal<double>::LocationArrayVec arrays(where.size());
  for (size_t i = 0; i < where.size(); ++i) {
    s[i] = where[i].u;
    t[i] = where[i].v;
    arrays[i].ptexIdx = static_cast<int>(where[i].face);
    arrays[i].numLocations = 1;
    arrays[i].s = &s[i];
    arrays[i].t = &t[i];
  }
  // Fixed part (independent of the points): refiner, adaptive refinement, patch table (Gregory
  // end caps, double), stencils of the refined vertices over the control vertices.
  rss.begin();
  sw = Stopwatch();
  auto refiner = peer_refiner(in, isolation);
  Far::PatchTableFactory::Options patch_options(isolation);
  patch_options.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
  patch_options.useInfSharpPatch = true;
  patch_options.generateVaryingTables = false;
  patch_options.SetPatchPrecision<double>();
  std::unique_ptr<const Far::PatchTable> patches(Far::PatchTableFactory::Create(*refiner, patch_options));
  Far::StencilTableFactoryReal<double>::Options stencil_options;
  stencil_options.generateIntermediateLevels = true;
  stencil_options.generateControlVerts = true;
  stencil_options.generateOffsets = true;
  std::unique_ptr<const Far::StencilTableReal<double>> refined(
      Far::StencilTableFactoryReal<double>::Create(*refiner, stencil_options));
  if (const Far::StencilTableReal<double>* local = patches->GetLocalPointStencilTable<double>())
    refined.reset(Far::StencilTableFactoryReal<double>::AppendLocalPointStencilTable(*refiner, refined.get(), local));
  r.peer_setup = sw.elapsed();
  // Per point set: the limit stencils of the N locations.
  sw = Stopwatch();
  std::unique_ptr<const Far::LimitStencilTableReal<double>> table(
      Far::LimitStencilTableFactoryReal<double>::Create(*refiner, arrays, refined.get(), patches.get()));
  r.peer_stencils = sw.elapsed() / n;
  r.peer_setup_mib = rss.mib_above_start();
  if (!table || table->GetNumStencils() != n) {
    std::fprintf(stderr, "bench_evaluate: OpenSubdiv made %d stencils for %d locations\n",
                 table ? table->GetNumStencils() : -1, n);
    std::exit(2);
  }
  r.peer_weights = table->GetWeights().size();
  const int peer_ptex = Far::PtexIndices(*refiner).GetNumFaces();
  if (static_cast<size_t>(peer_ptex) != r.ptex) {
    std::fprintf(stderr, "bench_evaluate: ptex face counts differ: CageKit %zu, OpenSubdiv %d\n", r.ptex, peer_ptex);
    std::exit(2);
  }
  std::printf("  OpenSubdiv refiner + patch table + stencils: %.2f s; limit stencils: %.2f s; %.0f MiB, %zu weights\n",
              r.peer_setup.wall, r.peer_stencils.wall * n, r.peer_setup_mib, r.peer_weights);
  std::fflush(stdout);
  {  // OpenSubdiv's du at the central-difference points (outside the timings)
    std::vector<double> fs(fd_where.size()), ft(fd_where.size());
    Far::LimitStencilTableFactoryReal<double>::LocationArrayVec fd_arrays(fd_where.size());
    for (size_t i = 0; i < fd_where.size(); ++i) {
      fs[i] = fd_where[i].u;
      ft[i] = fd_where[i].v;
      fd_arrays[i].ptexIdx = static_cast<int>(fd_where[i].face);
      fd_arrays[i].numLocations = 1;
      fd_arrays[i].s = &fs[i];
      fd_arrays[i].t = &ft[i];
    }
    std::unique_ptr<const Far::LimitStencilTableReal<double>> fd_table(
        Far::LimitStencilTableFactoryReal<double>::Create(*refiner, fd_arrays, refined.get(), patches.get()));
    std::vector<Point3> fp(fd_where.size()), fdu(fd_where.size()), fdv(fd_where.size());
    fd_table->UpdateDerivs(in.control.data(), fdu.data(), fdv.data());
    std::vector<double> err;
    for (size_t i = 0; i < fd_where.size(); ++i) {
      const cagekit::Vec3 du_osd(fdu[i].x, fdu[i].y, fdu[i].z);
      err.push_back(cagekit::norm(du_osd - fd_du[i]) / std::max(cagekit::norm(fd_du[i]), 1e-300));
    }
    std::sort(err.begin(), err.end());
    r.fd_osd_median = err.empty() ? 0 : err[err.size() / 2];
  }
  refined.reset();
  patches.reset();
  refiner.reset();

  std::vector<Point3> pos(where.size()), du(where.size()), dv(where.size());
  r.peer_eval = median_seconds(kPasses, [&] {
                  table->UpdateValues(in.control.data(), pos.data());
                  table->UpdateDerivs(in.control.data(), du.data(), dv.data());
                }) / n;

  std::vector<double> scale;  // |du_OSD| / |du_CageKit|
  size_t differing = 0;
  for (size_t i = 0; i < where.size(); ++i) {
    const cagekit::Vec3& a = ck[i].position;
    r.max_pos_diff = std::max({r.max_pos_diff, std::abs(a.x - pos[i].x), std::abs(a.y - pos[i].y), std::abs(a.z - pos[i].z)});
    const cagekit::Vec3& b = ck_control[i].position;
    r.max_pos_diff = std::max({r.max_pos_diff, std::abs(b.x - pos[i].x), std::abs(b.y - pos[i].y), std::abs(b.z - pos[i].z)});
    const double d = std::max(rel(ck[i].du, du[i]), rel(ck[i].dv, dv[i]));
    r.max_deriv_rel = std::max(r.max_deriv_rel, d);
    if (d > 1e-6) ++differing;
    const double n_ck = std::sqrt(ck[i].du.x * ck[i].du.x + ck[i].du.y * ck[i].du.y + ck[i].du.z * ck[i].du.z);
    const double n_osd = std::sqrt(du[i].x * du[i].x + du[i].y * du[i].y + du[i].z * du[i].z);
    if (n_ck > 0) scale.push_back(n_osd / n_ck);
  }
  std::sort(scale.begin(), scale.end());
  r.deriv_scale_median = scale.empty() ? 0 : scale[scale.size() / 2];
  r.deriv_differing = double(differing) / n;
  for (size_t i = 0; i < where.size(); ++i)
    r.basis_max_diff = std::max({r.basis_max_diff, cagekit::norm(basis_p[i] - ck[i].position),
                                 cagekit::norm(basis_du[i] - ck[i].du), cagekit::norm(basis_dv[i] - ck[i].dv)});
  r.ran = true;
  return r;
}

std::string si_time(const Seconds& t) {
  const double seconds = t.wall;
  char b[32];
  if (seconds < 1e-6)
    std::snprintf(b, sizeof b, "%.0f ns", seconds * 1e9);
  else if (seconds < 1e-3)
    std::snprintf(b, sizeof b, "%.2f µs", seconds * 1e6);
  else if (seconds < 1)
    std::snprintf(b, sizeof b, "%.0f ms", seconds * 1e3);
  else
    std::snprintf(b, sizeof b, "%.2f s", seconds);
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 100000;
  const int isolation = argc > 2 ? std::atoi(argv[2]) : 6;
  if (n < 1 || isolation < 1 || isolation > cagekit::kMaxIsolationLevel) {
    std::fprintf(stderr, "usage: bench_evaluate [points >= 1] [isolation 1..%d]\n", cagekit::kMaxIsolationLevel);
    return 2;
  }
  std::printf("## bench_evaluate: limit-surface evaluation, CageKit SubdivisionSurface vs OpenSubdiv %d.%d.%d "
              "LimitStencilTable\n\n",
              OPENSUBDIV_VERSION_MAJOR, OPENSUBDIV_VERSION_MINOR, OPENSUBDIV_VERSION_PATCH);
  std::printf("load average at start: %s\n", load_average().c_str());
  const std::string path = shared_mesh("fandisk.obj");
  if (path.empty()) {
    std::printf("skipped: %s/fandisk.obj not found\n", CAGEKIT_SHARED_MESHES);
    return 0;
  }
  cagekit::Cage fandisk = cagekit::read_cage_from_file(path);
  fandisk.clear_tags();
  cagekit::RefineOptions once;
  once.levels = 1;
  const cagekit::Cage quads = cagekit::refine_uniform(fandisk, once);

  std::vector<Result> results;
  results.push_back(run("fandisk (triangles)", fandisk, n, isolation));
  results.push_back(run("fandisk refined once (quads)", quads, n, isolation));

  std::printf("\nSetup (once per cage):\n\n");
  std::printf("| cage | faces | ptex faces | CageKit `SubdivisionSurface` | OSD refiner + `RefineAdaptive` + patch table + "
              "stencil table (+ end-cap points) | ratio CageKit / OSD (by CPU time) | peak RSS MiB CageKit / OSD (incl. the N limit stencils) |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  for (const Result& r : results)
    std::printf("| %s | %zu | %zu | %s | %s | %s | %.0f / %.0f |\n", r.cage.c_str(), r.faces, r.ptex,
                si_time(r.ck_setup).c_str(), si_time(r.peer_setup).c_str(), ratio(r.ck_setup, r.peer_setup).c_str(),
                r.ck_setup_mib,
                r.peer_setup_mib);
  std::printf("\nPer point, new points each time (N = %d):\n\n", n);
  std::printf("| cage | CageKit `evaluate` (P, 1st + 2nd derivs) | OSD: limit stencil creation + `UpdateValues` + "
              "`UpdateDerivs` (P, 1st derivs) | ratio CageKit / OSD (by CPU time) | CageKit `basis()` (weights, to build stencils) | "
              "max abs position diff CageKit vs OSD (/ bbox diagonal) |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (const Result& r : results) {
    const Seconds osd_new = r.peer_stencils + r.peer_eval;
    std::printf("| %s | %s | %s | %s | %s | %.1e (%.1e) |\n", r.cage.c_str(), si_time(r.ck_eval).c_str(),
                si_time(osd_new).c_str(), ratio(r.ck_eval, osd_new).c_str(), si_time(r.ck_basis).c_str(), r.max_pos_diff,
                r.max_pos_diff / r.diag);
  }
  std::printf("\nPer point, fixed points, moved control points (a deformation frame; N = %d):\n\n", n);
  std::printf("| cage | CageKit `evaluate(control)` | CageKit `basis()` weights applied (plain loop, P + 1st derivs) | "
              "OSD `UpdateValues` + `UpdateDerivs` (P, 1st derivs) | ratio evaluate(control) / OSD (by CPU time) | ratio "
              "basis loop / OSD (by CPU time) | weights / point CageKit basis / OSD stencil |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  for (const Result& r : results)
    std::printf("| %s | %s | %s | %s | %s | %s | %.1f / %.1f |\n", r.cage.c_str(),
                si_time(r.ck_eval_control).c_str(), si_time(r.ck_basis_apply).c_str(), si_time(r.peer_eval).c_str(),
                ratio(r.ck_eval_control, r.peer_eval).c_str(), ratio(r.ck_basis_apply, r.peer_eval).c_str(),
                double(r.ck_basis_weights) / n,
                double(r.peer_weights) / n);
  std::printf("\nFirst derivatives (agreement):\n\n");
  std::printf("| cage | max rel du/dv diff CageKit vs OSD | points with rel diff > 1e-6 | median abs(du_OSD) / "
              "abs(du_CageKit) | median rel error of du vs central difference of the positions: CageKit / OSD | "
              "max diff of CageKit basis-loop P/du/dv vs `evaluate` |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (const Result& r : results)
    std::printf("| %s | %.1e | %.1f%% | %.3f | %.1e / %.1e | %.1e |\n", r.cage.c_str(), r.max_deriv_rel,
                100.0 * r.deriv_differing, r.deriv_scale_median, r.fd_ck_median, r.fd_osd_median, r.basis_max_diff);
  std::printf("\nN random points (uniform ptex face, uniform u, v; seeded), isolation level %d for both, double precision "
              "for both. Setup timed once; per-point times: median of %d passes over all N points / N (the OSD limit "
              "stencil creation for the N points is timed once / N). CageKit's `evaluate` always computes the 2nd "
              "derivatives too. Ratios: wall-time ratio, in parentheses the ratio of process CPU times (the same on an "
              "idle machine; closer to the truth under load). Load average at the end: %s.\n\n",
              isolation, kPasses, load_average().c_str());
  return 0;
}
