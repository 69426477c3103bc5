// SPDX-License-Identifier: GPL-3.0-or-later
// bench_evaluate: limit-surface evaluation at N random (ptex face, u, v) points of a cage, in one
// process on the same points:
//   * CageKit  cagekit::SubdivisionSurface (sdk/subdiv/subdivision_surface.h) with its default
//              options (exact Stam evaluation around smooth extraordinary vertices): construction,
//              then evaluate(face, u, v) per point (position, du, dv and 2nd derivatives),
//              evaluate(face, u, v, control) (any control array: the deformation case), and
//              basis() rows applied to the control points by a plain loop
//   * peer     OpenSubdiv 3.5 Far at isolation levels 3 and 6 (Gregory end caps): setup =
//              TopologyRefinerFactory<TopologyDescriptor> + RefineAdaptive (useInfSharpPatch) +
//              PatchTableFactory (ENDCAP_GREGORY_BASIS, double) + StencilTableFactoryReal<double> +
//              AppendLocalPointStencilTable; per point set = LimitStencilTableFactoryReal<double>::
//              Create for the N locations (1st derivatives); per frame = LimitStencilTable::
//              UpdateValues + UpdateDerivs (position, du, dv) over all N
// Cages: fandisk as a cage (12,946 triangles, no tags) and a quad-only cage, fandisk refined once
// by CageKit (38,838 quads). Both are closed and untagged: every extraordinary vertex is smooth
// and interior, so CageKit is exact everywhere and OpenSubdiv approximates inside its Gregory end
// caps ([0, 2^-L]^2 at each extraordinary corner). The position difference is therefore
// OpenSubdiv's end-cap error; it shrinks as the peer's isolation level L grows.
// Usage: bench_evaluate [N=100000] [CageKit isolation=default] [peer isolation levels=3,6].
// Method (as in ../shared/spec/peer-measurements.md §4): steady_clock (and process CPU time)
// around the library calls only; setups timed once (they take seconds); per-point times: median
// of 5 passes over all N points; peak RSS of each setup above the RSS before it (VmHWM reset by
// /proc/self/clear_refs). Never fails on timing.
#include <malloc.h>
#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/patchMap.h>
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

#include "bench_support.h"

namespace {

using bench::cpu_seconds;
using bench::load_average;
using bench::seconds_since;
using bench::status_kib;

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;
using Clock = std::chrono::steady_clock;

constexpr int kPasses = 5;

// --- measurement helpers (each benchmark is self-contained) ---



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


// "wall ratio (CPU-time ratio)"
std::string ratio(const Seconds& a, const Seconds& b) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.2f (%.2f)", a.wall / b.wall, a.cpu / b.cpu);
  return buf;
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

std::vector<Location> random_locations(size_t n, uint32_t ptex_faces) {
  std::mt19937_64 rng(20261123);
  std::uniform_int_distribution<uint32_t> face(0, ptex_faces - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Location> where(n);
  for (Location& l : where) {
    l.face = face(rng);
    l.u = unit(rng);
    l.v = unit(rng);
  }
  return where;
}

// Points for the derivative referee: (u - h, u, u + h) at the first points, u kept inside.
constexpr double kStep = 1e-5;
constexpr size_t kRefereePoints = 2000;

std::vector<Location> referee_locations(const std::vector<Location>& where) {
  std::vector<Location> out;
  for (size_t i = 0; i < where.size() && i < kRefereePoints; ++i) {
    const double u = std::min(std::max(where[i].u, 2 * kStep), 1 - 2 * kStep);
    for (double d : {-kStep, 0.0, kStep}) out.push_back({where[i].face, u + d, where[i].v});
  }
  return out;
}

// Median of |du - central difference of the positions| / |central difference| over the triples.
template <typename P, typename D>
double referee_median(const std::vector<P>& position, const std::vector<D>& du) {
  std::vector<double> err;
  for (size_t i = 0; i + 2 < position.size(); i += 3) {
    const cagekit::Vec3 fd = (position[i + 2] - position[i]) * (1 / (2 * kStep));
    err.push_back(cagekit::norm(du[i + 1] - fd) / std::max(cagekit::norm(fd), 1e-300));
  }
  std::sort(err.begin(), err.end());
  return err.empty() ? 0 : err[err.size() / 2];
}

cagekit::Vec3 vec(const Point3& p) { return {p.x, p.y, p.z}; }

struct CageKitResult {
  Seconds setup, eval, eval_control, basis, basis_apply;
  double setup_mib = 0;
  uint32_t ptex = 0;
  size_t basis_weights = 0;
  double referee = 0, basis_max_diff = 0;
  std::vector<cagekit::SurfacePoint> points;
};

struct PeerResult {
  int isolation = 0;
  Seconds setup, stencils, eval;
  double setup_mib = 0;
  size_t weights = 0;
  double max_pos_diff = 0, max_deriv_rel = 0, deriv_scale_median = 0, deriv_differing = 0, referee = 0;
  double max_pos_diff_bspline = 0, max_pos_diff_end_caps = 0;
  size_t end_cap_points = 0;
};

struct CageRun {
  std::string cage;
  size_t faces = 0;
  double diag = 0;
  CageKitResult ck;
  std::vector<PeerResult> peers;
};

CageKitResult run_cagekit(const cagekit::Cage& cage, const cagekit::SurfaceOptions& options,
                          std::vector<Location>* where, size_t n) {
  CageKitResult r;
  PeakRss rss;
  rss.begin();
  Stopwatch sw;
  auto surface = std::make_unique<cagekit::SubdivisionSurface>(cage, options);
  r.setup = sw.elapsed();
  r.setup_mib = rss.mib_above_start();
  r.ptex = surface->num_ptex_faces();
  std::printf("  CageKit SubdivisionSurface (isolation %d, sharp EV isolation %d): %.2f s, %.0f MiB\n",
              options.isolation_level, options.sharp_extraordinary_isolation_level, r.setup.wall, r.setup_mib);
  std::fflush(stdout);
  *where = random_locations(n, r.ptex);

  r.points.resize(n);
  r.eval = median_seconds(kPasses, [&] {
             for (size_t i = 0; i < n; ++i) r.points[i] = surface->evaluate((*where)[i].face, (*where)[i].u, (*where)[i].v);
           }) / double(n);
  std::vector<cagekit::SurfacePoint> with_control(n);
  const std::vector<cagekit::Vec3>& control = cage.mesh.positions;
  r.eval_control = median_seconds(kPasses, [&] {
                     for (size_t i = 0; i < n; ++i)
                       with_control[i] = surface->evaluate((*where)[i].face, (*where)[i].u, (*where)[i].v, control);
                   }) / double(n);
  for (size_t i = 0; i < n; ++i)
    r.basis_max_diff = std::max(r.basis_max_diff, cagekit::norm(with_control[i].position - r.points[i].position));

  // The stencil path: basis() per point (phi_j, phi_j,u, phi_j,v over the cage vertices) kept as
  // a CSR table, then applied to the control points by a plain loop (this file's code).
  std::vector<uint32_t> offsets{0}, indices;
  std::vector<double> w, wu, wv;
  sw = Stopwatch();
  for (const Location& l : *where) {
    const cagekit::BasisWeights b = surface->basis(l.face, l.u, l.v);
    indices.insert(indices.end(), b.indices.begin(), b.indices.end());
    w.insert(w.end(), b.w.begin(), b.w.end());
    wu.insert(wu.end(), b.wu.begin(), b.wu.end());
    wv.insert(wv.end(), b.wv.begin(), b.wv.end());
    offsets.push_back(static_cast<uint32_t>(indices.size()));
  }
  r.basis = sw.elapsed() / double(n);
  r.basis_weights = indices.size();
  std::vector<cagekit::Vec3> p(n), pu(n), pv(n);
  r.basis_apply = median_seconds(kPasses, [&] {
                    for (size_t i = 0; i < n; ++i) {
                      cagekit::Vec3 a, au, av;
                      for (uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
                        const cagekit::Vec3& c = control[indices[k]];
                        a += c * w[k];
                        au += c * wu[k];
                        av += c * wv[k];
                      }
                      p[i] = a;
                      pu[i] = au;
                      pv[i] = av;
                    }
                  }) / double(n);
  for (size_t i = 0; i < n; ++i)
    r.basis_max_diff = std::max({r.basis_max_diff, cagekit::norm(p[i] - r.points[i].position),
                                 cagekit::norm(pu[i] - r.points[i].du), cagekit::norm(pv[i] - r.points[i].dv)});

  const std::vector<Location> ref = referee_locations(*where);
  std::vector<cagekit::Vec3> ref_p, ref_du;
  for (const Location& l : ref) {
    const cagekit::SurfacePoint sp = surface->evaluate(l.face, l.u, l.v);
    ref_p.push_back(sp.position);
    ref_du.push_back(sp.du);
  }
  r.referee = referee_median(ref_p, ref_du);
  return r;
}

double rel(const cagekit::Vec3& a, const cagekit::Vec3& b) {
  const double d = std::max({std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - b.z)});
  const double m = std::max({std::abs(a.x), std::abs(a.y), std::abs(a.z), 1e-300});
  return d / m;
}

using LocationArrays = Far::LimitStencilTableFactoryReal<double>::LocationArrayVec;

// One LocationArray per point (each point has its own ptex face); s, t must outlive the arrays.
LocationArrays location_arrays(const std::vector<Location>& where, std::vector<double>* s, std::vector<double>* t) {
  s->resize(where.size());
  t->resize(where.size());
  LocationArrays arrays(where.size());
  for (size_t i = 0; i < where.size(); ++i) {
    (*s)[i] = where[i].u;
    (*t)[i] = where[i].v;
    arrays[i].ptexIdx = static_cast<int>(where[i].face);
    arrays[i].numLocations = 1;
    arrays[i].s = &(*s)[i];
    arrays[i].t = &(*t)[i];
  }
  return arrays;
}

PeerResult run_peer(const cagekit::Cage& cage, int isolation, const std::vector<Location>& where,
                    const CageKitResult& ck) {
  PeerResult r;
  r.isolation = isolation;
  const size_t n = where.size();
  const PeerInput in = peer_input(cage.mesh);
  std::vector<double> s, t;
  const LocationArrays arrays = location_arrays(where, &s, &t);

  // Fixed part (independent of the points).
  PeakRss rss;
  rss.begin();
  Stopwatch sw;
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
  r.setup = sw.elapsed();
  // Per point set: the limit stencils of the N locations.
  sw = Stopwatch();
  std::unique_ptr<const Far::LimitStencilTableReal<double>> table(
      Far::LimitStencilTableFactoryReal<double>::Create(*refiner, arrays, refined.get(), patches.get()));
  r.stencils = sw.elapsed() / double(n);
  r.setup_mib = rss.mib_above_start();
  if (!table || static_cast<size_t>(table->GetNumStencils()) != n) {
    std::fprintf(stderr, "bench_evaluate: OpenSubdiv made %d stencils for %zu locations\n",
                 table ? table->GetNumStencils() : -1, n);
    std::exit(2);
  }
  r.weights = table->GetWeights().size();
  const int peer_ptex = Far::PtexIndices(*refiner).GetNumFaces();
  if (static_cast<uint32_t>(peer_ptex) != ck.ptex) {
    std::fprintf(stderr, "bench_evaluate: ptex face counts differ: CageKit %u, OpenSubdiv %d\n", ck.ptex, peer_ptex);
    std::exit(2);
  }
  std::printf("  OpenSubdiv isolation %d: refiner + patch table + stencils %.2f s; limit stencils %.2f s; %.0f MiB\n",
              isolation, r.setup.wall, r.stencils.wall * double(n), r.setup_mib);
  std::fflush(stdout);

  // The derivative referee's points (outside the timings).
  {
    const std::vector<Location> ref = referee_locations(where);
    std::vector<double> rs, rt;
    const LocationArrays ref_arrays = location_arrays(ref, &rs, &rt);
    std::unique_ptr<const Far::LimitStencilTableReal<double>> ref_table(
        Far::LimitStencilTableFactoryReal<double>::Create(*refiner, ref_arrays, refined.get(), patches.get()));
    std::vector<Point3> p(ref.size()), du(ref.size()), dv(ref.size());
    ref_table->UpdateValues(in.control.data(), p.data());
    ref_table->UpdateDerivs(in.control.data(), du.data(), dv.data());
    std::vector<cagekit::Vec3> pv, duv;
    for (size_t i = 0; i < ref.size(); ++i) {
      pv.push_back(vec(p[i]));
      duv.push_back(vec(du[i]));
    }
    r.referee = referee_median(pv, duv);
  }
  // Which points lie on OpenSubdiv's Gregory end caps (the rest are on its B-spline patches).
  std::vector<char> in_end_cap(n, 0);
  {
    const Far::PatchMap map(*patches);
    for (size_t i = 0; i < n; ++i) {
      const Far::PatchMap::Handle* h = map.FindPatch(static_cast<int>(where[i].face), where[i].u, where[i].v);
      in_end_cap[i] = h && patches->GetPatchDescriptor(*h).GetType() == Far::PatchDescriptor::GREGORY_BASIS;
    }
  }
  refined.reset();
  patches.reset();
  refiner.reset();

  std::vector<Point3> pos(n), du(n), dv(n);
  r.eval = median_seconds(kPasses, [&] {
             table->UpdateValues(in.control.data(), pos.data());
             table->UpdateDerivs(in.control.data(), du.data(), dv.data());
           }) / double(n);

  std::vector<double> scale;  // |du_OSD| / |du_CageKit|
  size_t differing = 0;
  for (size_t i = 0; i < n; ++i) {
    const cagekit::SurfacePoint& c = ck.points[i];
    const double pd = cagekit::norm(c.position - vec(pos[i]));
    r.max_pos_diff = std::max(r.max_pos_diff, pd);
    if (in_end_cap[i]) {
      r.end_cap_points += 1;
      r.max_pos_diff_end_caps = std::max(r.max_pos_diff_end_caps, pd);
    } else {
      r.max_pos_diff_bspline = std::max(r.max_pos_diff_bspline, pd);
    }
    const double d = std::max(rel(c.du, vec(du[i])), rel(c.dv, vec(dv[i])));
    r.max_deriv_rel = std::max(r.max_deriv_rel, d);
    if (d > 1e-6) ++differing;
    if (cagekit::norm(c.du) > 0) scale.push_back(cagekit::norm(vec(du[i])) / cagekit::norm(c.du));
  }
  std::sort(scale.begin(), scale.end());
  r.deriv_scale_median = scale.empty() ? 0 : scale[scale.size() / 2];
  r.deriv_differing = double(differing) / double(n);
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

std::vector<int> parse_levels(const char* text) {
  std::vector<int> levels;
  std::string item;
  for (const char* c = text;; ++c) {
    if (*c == ',' || *c == 0) {
      if (!item.empty()) levels.push_back(std::atoi(item.c_str()));
      item.clear();
      if (*c == 0) break;
    } else {
      item += *c;
    }
  }
  return levels;
}

}  // namespace

int main(int argc, char** argv) {
  const long n_arg = argc > 1 ? std::atol(argv[1]) : 100000;
  cagekit::SurfaceOptions ck_options;
  if (argc > 2) ck_options.isolation_level = std::atoi(argv[2]);
  const std::vector<int> peer_levels = parse_levels(argc > 3 ? argv[3] : "3,6");
  bool ok = n_arg >= 1 && ck_options.isolation_level >= 1 && ck_options.isolation_level <= cagekit::kMaxIsolationLevel &&
            !peer_levels.empty();
  for (int level : peer_levels) ok = ok && level >= 1 && level <= 10;
  if (!ok) {
    std::fprintf(stderr, "usage: bench_evaluate [points >= 1] [CageKit isolation 1..%d] [peer levels, e.g. 3,6]\n",
                 cagekit::kMaxIsolationLevel);
    return 2;
  }
  const size_t n = static_cast<size_t>(n_arg);
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

  std::vector<CageRun> runs;
  const std::pair<const char*, const cagekit::Cage*> cages[] = {{"fandisk (triangles)", &fandisk},
                                                                 {"fandisk refined once (quads)", &quads}};
  for (const auto& [label, cage] : cages) {
    CageRun run;
    run.cage = label;
    run.faces = cage->mesh.num_faces();
    run.diag = cage->mesh.bounding_box().diagonal();
    std::printf("%s: %zu vertices, %zu faces, %zu points\n", label, cage->mesh.num_vertices(), run.faces, n);
    std::fflush(stdout);
    std::vector<Location> where;
    run.ck = run_cagekit(*cage, ck_options, &where, n);
    for (int level : peer_levels) run.peers.push_back(run_peer(*cage, level, where, run.ck));
    runs.push_back(std::move(run));
  }

  std::printf("\nSetup (once per cage; OSD's limit stencils for the N points are in the per-point table):\n\n");
  std::printf("| cage | faces | ptex faces | CageKit `SubdivisionSurface` (isolation %d) | OSD isolation | OSD refiner + "
              "`RefineAdaptive` + patch table + stencil table (+ end-cap points) | ratio CageKit / OSD (by CPU time) | "
              "peak RSS MiB CageKit / OSD (incl. the N limit stencils) |\n",
              ck_options.isolation_level);
  std::printf("|---|---|---|---|---|---|---|---|\n");
  for (const CageRun& c : runs)
    for (const PeerResult& p : c.peers)
      std::printf("| %s | %zu | %u | %s | %d | %s | %s | %.0f / %.0f |\n", c.cage.c_str(), c.faces, c.ck.ptex,
                  si_time(c.ck.setup).c_str(), p.isolation, si_time(p.setup).c_str(), ratio(c.ck.setup, p.setup).c_str(),
                  c.ck.setup_mib, p.setup_mib);

  std::printf("\nPer point, new points each time (N = %zu), and agreement of the positions:\n\n", n);
  std::printf("| cage | CageKit `evaluate` (P, 1st + 2nd derivs) | OSD isolation | OSD limit stencil creation + "
              "`UpdateValues` + `UpdateDerivs` (P, 1st derivs) | ratio CageKit / OSD (by CPU time) | CageKit `basis()` "
              "(weights, to build stencils) | points on OSD end caps | max abs position diff CageKit vs OSD: on OSD's "
              "B-spline patches; on its Gregory end caps (/ bbox diagonal) |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  for (const CageRun& c : runs)
    for (const PeerResult& p : c.peers) {
      const Seconds osd_new = p.stencils + p.eval;
      std::printf("| %s | %s | %d | %s | %s | %s | %.1f%% | %.1e; %.1e (%.1e) |\n", c.cage.c_str(),
                  si_time(c.ck.eval).c_str(), p.isolation, si_time(osd_new).c_str(), ratio(c.ck.eval, osd_new).c_str(),
                  si_time(c.ck.basis).c_str(), 100.0 * double(p.end_cap_points) / double(n), p.max_pos_diff_bspline,
                  p.max_pos_diff_end_caps, p.max_pos_diff_end_caps / c.diag);
    }

  std::printf("\nPer point, fixed points, moved control points (a deformation frame; N = %zu):\n\n", n);
  std::printf("| cage | CageKit `evaluate(control)` | CageKit `basis()` weights applied (plain loop, P + 1st derivs) | "
              "OSD isolation | OSD `UpdateValues` + `UpdateDerivs` (P, 1st derivs) | ratio evaluate(control) / OSD (by "
              "CPU time) | ratio basis loop / OSD (by CPU time) | weights / point CageKit basis / OSD stencil |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  for (const CageRun& c : runs)
    for (const PeerResult& p : c.peers)
      std::printf("| %s | %s | %s | %d | %s | %s | %s | %.1f / %.1f |\n", c.cage.c_str(),
                  si_time(c.ck.eval_control).c_str(), si_time(c.ck.basis_apply).c_str(), p.isolation,
                  si_time(p.eval).c_str(), ratio(c.ck.eval_control, p.eval).c_str(),
                  ratio(c.ck.basis_apply, p.eval).c_str(), double(c.ck.basis_weights) / double(n),
                  double(p.weights) / double(n));

  std::printf("\nFirst derivatives:\n\n");
  std::printf("| cage | OSD isolation | max rel du/dv diff CageKit vs OSD | points with rel diff > 1e-6 | median "
              "abs(du_OSD) / abs(du_CageKit) | median rel error of du vs central differences of the library's own "
              "positions: CageKit / OSD | max diff of CageKit's basis loop and evaluate(control) vs evaluate |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  for (const CageRun& c : runs)
    for (const PeerResult& p : c.peers)
      std::printf("| %s | %d | %.1e | %.1f%% | %.3f | %.1e / %.1e | %.1e |\n", c.cage.c_str(), p.isolation,
                  p.max_deriv_rel, 100.0 * p.deriv_differing, p.deriv_scale_median, c.ck.referee, p.referee,
                  c.ck.basis_max_diff);

  std::printf("\nN random points (uniform ptex face, uniform u, v; seeded); double precision for both. CageKit: "
              "SurfaceOptions isolation %d, sharp-EV isolation %d. Setups timed once; per-point times: median of %d "
              "passes over all N points / N (OSD's limit stencil creation for the N points timed once / N). CageKit's "
              "`evaluate` always computes the 2nd derivatives too. Ratios: wall-time ratio, in parentheses the ratio of "
              "process CPU times (the same on an idle machine; closer to the truth under load). Load average at the "
              "end: %s.\n\n",
              ck_options.isolation_level, ck_options.sharp_extraordinary_isolation_level, kPasses,
              load_average().c_str());
  return 0;
}
