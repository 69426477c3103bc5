// SPDX-License-Identifier: GPL-3.0-or-later
// bench_fit: fitting a cage's Catmull-Clark limit surface to a scan (thesis ch. 7).
//  1. Bunny (raw scan with holes) with a ~612-vertex cage from CageKit's simplifier, 5 passes:
//     the thesis's experiment (0.81% max deviation, 29 s on a 3.2 GHz Pentium IV), all-vertex and
//     interior figures, 1 thread and all threads, exact vs piecewise-linear projection.
//  2. Rocker arm, exact projection vs the piecewise-linear projection of [HDD+94] (the peer
//     method; thesis Fig. 7.5: 9.3% lower L2 after 30 passes, 61.5% less time to the same L2) at
//     equal passes and at equal time.
// Distances relative to the scan's bbox diagonal. Never fails on timing; prints markdown.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>

#include "bench_support.h"
#include "core/io/mesh_io.h"
#include "fit/surface_fitter.h"
#include "layout/simplify/cage_builder.h"
#include "layout/simplify/face_merge_simplifier.h"

using namespace cagekit;

namespace {

std::string shared(const char* name) { return std::string(CAGEKIT_SHARED_MESHES) + "/" + name; }

// The simplifier level whose quad-dominant cage has the number of vertices (or faces) closest to
// the target.
Cage cage_near(const PolygonMesh& scan, SimplificationHierarchy& hierarchy, size_t target, bool by_vertices) {
  Cage best;
  size_t best_gap = SIZE_MAX;
  const size_t start = by_vertices ? target / 2 : target / 2;
  for (size_t faces = std::max<size_t>(4, start * 8 / 10); faces <= start * 13 / 10; faces += 2) {
    hierarchy.go_to_level(hierarchy.level_for_face_count(faces));
    Cage cage = build_quad_dominant_cage(scan, hierarchy.extract());
    const size_t value = by_vertices ? cage.mesh.num_vertices() : cage.mesh.num_faces();
    const size_t gap = value > target ? value - target : target - value;
    if (gap < best_gap) best_gap = gap, best = std::move(cage);
  }
  return best;
}

struct Run {
  FitReport report;
  double wall = 0, cpu = 0;
};

Run run(const Cage& cage, const PolygonMesh& scan, const FitOptions& options) {
  Run r;
  const double c0 = bench::cpu_seconds();
  const auto t0 = bench::Clock::now();
  fit_cage_to_mesh(cage, scan, options, &r.report);
  r.wall = bench::seconds_since(t0);
  r.cpu = bench::cpu_seconds() - c0;
  return r;
}

void bunny() {
  PolygonMesh scan;
  try {
    scan = read_cage_from_file(shared("stanford-bunny.obj")).mesh;
  } catch (const Error&) {
    std::printf("stanford-bunny.obj not present: bunny benchmark skipped\n\n");
    return;
  }
  SimplificationHierarchy hierarchy(scan);
  const Cage cage = cage_near(scan, hierarchy, 612, true);
  std::printf("## Bunny, %zu-vertex / %zu-face cage (thesis: 612 vertices), %zu samples, 5 passes\n\n",
              cage.mesh.num_vertices(), cage.mesh.num_faces(), scan.num_vertices());
  std::printf("| run | max_rel | max_rel_interior | rms_rel | mean_rel | L2 (7.1) | unconverged | steps/search | "
              "wall s | CPU s |\n|---|---|---|---|---|---|---|---|---|---|\n");
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  struct Case {
    const char* name;
    ProjectionMode mode;
    int threads;
  } cases[] = {{"initial cage", ProjectionMode::exact, 1},
               {"exact, 1 thread", ProjectionMode::exact, 1},
               {"exact, all threads", ProjectionMode::exact, int(cores)},
               {"piecewise linear, all threads", ProjectionMode::piecewise_linear, int(cores)}};
  for (const Case& c : cases) {
    FitOptions options;
    options.max_passes = c.mode == ProjectionMode::exact && std::string(c.name) == "initial cage" ? 0 : 5;
    options.tolerance = 0;
    options.projection = c.mode;
    options.threads = c.threads;
    const Run r = run(cage, scan, options);
    const FitPassStatistics& s = r.report.passes.back();
    std::printf("| %s | %.3f%% | %.3f%% | %.4f%% | %.4f%% | %.4g | %zu | %.2f | %.2f | %.2f |\n", c.name,
                100 * s.max_relative, 100 * s.max_relative_interior, 100 * s.rms_relative, 100 * s.mean_relative, s.l2,
                s.unconverged_projections, s.mean_projection_steps, r.wall, r.cpu);
  }
  std::printf("| thesis (own bunny scan, 612 vertices, 3.2 GHz Pentium IV) | 0.81%% | | | | 46.2 | | | 29 | |\n\n");
}

void rocker_arm() {
  PolygonMesh scan;
  try {
    scan = read_cage_from_file(shared("rocker-arm.obj")).mesh;
  } catch (const Error&) {
    std::printf("rocker-arm.obj not present: rocker-arm benchmark skipped\n\n");
    return;
  }
  SimplificationHierarchy hierarchy(scan);
  const Cage cage = cage_near(scan, hierarchy, 431, false);
  std::printf("## Rocker arm, %zu-face cage (thesis: a 431- or 1096-face ch. 6 cage), %zu samples: exact vs "
              "piecewise-linear projection ([HDD+94])\n\n",
              cage.mesh.num_faces(), scan.num_vertices());
  FitOptions exact, linear;
  exact.tolerance = linear.tolerance = 0;
  exact.max_passes = 30;
  linear.max_passes = 100;
  linear.projection = ProjectionMode::piecewise_linear;
  const Run e = run(cage, scan, exact), l = run(cage, scan, linear);
  auto cumulative = [](const FitReport& r, size_t pass) {
    double t = 0;
    for (size_t k = 0; k <= pass && k < r.passes.size(); ++k) t += r.passes[k].seconds;
    return t;
  };
  std::printf("| passes | exact L2 | exact max_rel | exact s | linear L2 | linear max_rel | linear s | exact/linear L2 |\n"
              "|---|---|---|---|---|---|---|---|\n");
  for (size_t k : {0, 1, 2, 5, 10, 20, 30}) {
    if (k >= e.report.passes.size() || k >= l.report.passes.size()) break;
    const FitPassStatistics &a = e.report.passes[k], &b = l.report.passes[k];
    std::printf("| %zu | %.5g | %.3f%% | %.2f | %.5g | %.3f%% | %.2f | %.3f |\n", k, a.l2, 100 * a.max_relative,
                cumulative(e.report, k), b.l2, 100 * b.max_relative, cumulative(l.report, k), a.l2 / b.l2);
  }
  const FitPassStatistics& l100 = l.report.passes.back();
  const double linear_time = cumulative(l.report, l.report.passes.size() - 1);
  size_t reach = 0;
  while (reach < e.report.passes.size() && e.report.passes[reach].l2 > l100.l2) ++reach;
  std::printf("\nPiecewise linear after %zu passes: L2 %.5g, max %.3f%%, %.2f s.\n", l.report.passes.size() - 1,
              l100.l2, 100 * l100.max_relative, linear_time);
  if (reach < e.report.passes.size())
    std::printf("Exact reaches that L2 after %zu passes in %.2f s: %.1f%% less time (thesis: 25 vs 100 passes, "
                "61.5%% less time).\n",
                reach, cumulative(e.report, reach), 100 * (1 - cumulative(e.report, reach) / linear_time));
  else
    std::printf("Exact does not reach that L2 within %zu passes.\n", e.report.passes.size() - 1);
  // Equal time: the exact fit's L2 at the last pass finished within the linear fit's time for
  // min(30, its passes) passes.
  const size_t l30 = std::min<size_t>(30, l.report.passes.size() - 1);
  const double t30 = cumulative(l.report, l30);
  size_t k = 0;
  while (k + 1 < e.report.passes.size() && cumulative(e.report, k + 1) <= t30) ++k;
  std::printf("Equal time (%.2f s = %zu linear passes): exact L2 %.5g after %zu passes vs linear %.5g (%.1f%% lower).\n",
              t30, l30, e.report.passes[k].l2, k, l.report.passes[l30].l2,
              100 * (1 - e.report.passes[k].l2 / l.report.passes[l30].l2));
  if (l.report.rejected_last_step)
    std::printf("The piecewise-linear fit stopped after %zu passes: its next step would have increased its own "
                "objective (the distance to the piecewise-linear mesh).\n",
                l.report.passes.size() - 1);
  std::printf("After 30 passes (linear: its last): exact L2 %.1f%% lower than linear (thesis: 9.3%%).\n\n",
              100 * (1 - e.report.passes[std::min<size_t>(30, e.report.passes.size() - 1)].l2 /
                             l.report.passes[std::min<size_t>(30, l.report.passes.size() - 1)].l2));
}

}  // namespace

int main() {
  std::printf("# bench_fit (load average at start: %s, %u hardware threads)\n\n", bench::load_average().c_str(),
              std::thread::hardware_concurrency());
  bunny();
  rocker_arm();
  std::printf("load average at end: %s\n", bench::load_average().c_str());
  return 0;
}
