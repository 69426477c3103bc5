// SPDX-License-Identifier: GPL-3.0-or-later
// bench_deform: multiresolution deformation (thesis ch. 8, issue #5). A ~667K-triangle scan
// (the Stanford bunny, every triangle split 1-to-9 and displaced by seeded noise: the size of
// the thesis's "Male" model) is bound to a ~500-face cage (CageKit's simplifier on the bunny,
// fitted 3 passes); then per frame:
//   - CPU full: every control point moves, positions + approximate normals of all vertices
//     (CpuDeformer::deform, compact per-cell table), 2 threads and 1 thread;
//   - CPU incremental: 10 control points move (CpuDeformer::update);
//   - the sparse-row reference deformer (SparseRowDeformer), 2 threads, for scale;
//   - the peer: OpenSubdiv's Far::LimitStencilTable (float) at the same foot points, built by
//     LimitStencilTableFactory after RefineAdaptive(3) with Gregory end caps; a frame is
//     UpdateValues + UpdateDerivs (position, du, dv; no displacement, no normals) over the
//     stencil range split in two halves on 2 std::threads (as peer-measurements §4);
//   - GPU: not measured here (tests/gpu, samples/egl_host).
// Median frame time over the frames after 3 warm-up frames; load average printed. Never fails
// on timing; prints markdown.
#include <opensubdiv/far/ptexIndices.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/far/topologyRefiner.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <string>
#include <thread>

#include "bench_support.h"
#include "core/io/file_io.h"
#include "core/io/mesh_io.h"
#include "fit/surface_fitter.h"
#include "layout/simplify/cage_builder.h"
#include "layout/simplify/face_merge_simplifier.h"
#include "multires/binding_file.h"
#include "multires/cpu_deformer.h"
#include "core/vertex_renumbering.h"
#include "multires/deformer_vertex_order.h"
#include "multires/scan_binding.h"
#include "multires/sparse_row_deformer.h"
#include "subdiv/subdivision_surface.h"
#include "subdiv/topology_refiner_factory.h"

using namespace cagekit;
namespace Far = OpenSubdiv::Far;

namespace {

std::string shared(const char* name) { return std::string(CAGEKIT_SHARED_MESHES) + "/" + name; }

// Every triangle split 1-to-9 (edges in thirds, one centre point), then each vertex moved along
// its normal by uniform noise of +-amplitude (seeded).
PolygonMesh split_1_to_9(const PolygonMesh& mesh, double amplitude) {
  PolygonMesh out;
  out.positions = mesh.positions;
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> edge_first;  // (a < b) -> point at 1/3 from a
  auto edge_points = [&](uint32_t a, uint32_t b, uint32_t* p_near_a, uint32_t* p_near_b) {
    const auto key = std::make_pair(std::min(a, b), std::max(a, b));
    auto it = edge_first.find(key);
    if (it == edge_first.end()) {
      const Vec3 &pa = mesh.positions[key.first], &pb = mesh.positions[key.second];
      const uint32_t first = out.add_vertex(pa + (pb - pa) * (1.0 / 3.0));
      out.add_vertex(pa + (pb - pa) * (2.0 / 3.0));
      it = edge_first.emplace(key, first).first;
    }
    const uint32_t near_min = it->second, near_max = it->second + 1;
    *p_near_a = a == key.first ? near_min : near_max;
    *p_near_b = a == key.first ? near_max : near_min;
  };
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    if (mesh.face_size(f) != 3) continue;
    const uint32_t a = mesh.face_vertex(f, 0), b = mesh.face_vertex(f, 1), c = mesh.face_vertex(f, 2);
    uint32_t ab, ba, bc, cb, ca, ac;
    edge_points(a, b, &ab, &ba);
    edge_points(b, c, &bc, &cb);
    edge_points(c, a, &ca, &ac);
    const uint32_t m = out.add_vertex((mesh.positions[a] + mesh.positions[b] + mesh.positions[c]) * (1.0 / 3.0));
    const uint32_t tris[9][3] = {{a, ab, ac}, {ab, m, ac}, {ab, ba, m}, {ba, bc, m}, {ba, b, bc},
                                 {ac, m, ca}, {m, cb, ca}, {m, bc, cb}, {ca, cb, c}};
    for (const auto& t : tris) out.add_face(t, 3);
  }
  const std::vector<Vec3> normals = vertex_normals(out);
  std::mt19937 rng(20261124);
  std::uniform_real_distribution<double> noise(-amplitude, amplitude);
  for (size_t i = 0; i < out.num_vertices(); ++i) out.positions[i] += normals[i] * noise(rng);
  return out;
}

Cage cage_near(const PolygonMesh& scan, size_t target_faces) {
  SimplificationHierarchy hierarchy(scan);
  Cage best;
  size_t best_gap = SIZE_MAX;
  for (size_t faces = target_faces * 8 / 10; faces <= target_faces * 12 / 10; faces += 4) {
    hierarchy.go_to_level(hierarchy.level_for_face_count(faces));
    Cage cage = build_quad_dominant_cage(scan, hierarchy.extract());
    const size_t gap = cage.mesh.num_faces() > target_faces ? cage.mesh.num_faces() - target_faces
                                                            : target_faces - cage.mesh.num_faces();
    if (gap < best_gap) best_gap = gap, best = std::move(cage);
  }
  return best;
}

// Median seconds of `frames` calls of f(frame) after 3 warm-up calls; *cpu receives the median
// process CPU seconds per frame (all threads), which other processes on the machine disturb less.
double g_cpu = 0;
template <typename F>
double median_frame(int frames, F&& f) {
  for (int i = 0; i < 3; ++i) f(i);
  std::vector<double> t, c;
  for (int i = 0; i < frames; ++i) {
    const double c0 = bench::cpu_seconds();
    const auto t0 = bench::Clock::now();
    f(i + 3);
    t.push_back(bench::seconds_since(t0));
    c.push_back(bench::cpu_seconds() - c0);
  }
  std::sort(t.begin(), t.end());
  std::sort(c.begin(), c.end());
  g_cpu = c[c.size() / 2];
  return t[t.size() / 2];
}

struct Point3f {
  float x = 0, y = 0, z = 0;
  void Clear() { x = y = z = 0; }
  void AddWithWeight(const Point3f& s, float w) {
    x += w * s.x;
    y += w * s.y;
    z += w * s.z;
  }
};

}  // namespace

// bench_deform [FRAMES] [--table-only] [--cpu-only] [--cache FILE.ckb] [--cell-order]
//   --cell-order: the scan renumbered in the deformer's write order (deformer_vertex_order.h,
//   what a host that may renumber its scan does once) and bound again before the frames;
//   --cpu-only: only the CpuDeformer rows (no sparse-row reference, no OpenSubdiv);
//   --cache: read the cage + binding from FILE.ckb if it exists, else make them and write it there
//   (the binding file rebuilds the same binding bit for bit; for repeated runs while tuning).
//   (with --cell-order the renumbered binding is written to FILE.ckb.cell as well).
int main(int argc, char** argv) {
  int frames = 60;
  bool table_only = false, cpu_only = false, cell_order = false;
  std::string cache;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--table-only") table_only = true;
    else if (arg == "--cpu-only") cpu_only = true;
    else if (arg == "--cell-order") cell_order = true;
    else if (arg == "--cache" && a + 1 < argc) cache = argv[++a];
    else frames = std::max(5, std::atoi(arg.c_str()));
  }
  PolygonMesh bunny;
  try {
    bunny = read_cage_from_file(shared("stanford-bunny.obj")).mesh;
  } catch (const Error&) {
    std::printf("stanford-bunny.obj not present: bench_deform skipped\n");
    return 0;
  }
  BoundingBox box;
  for (const Vec3& p : bunny.positions) box.extend(p);
  auto t0 = bench::Clock::now();
  PolygonMesh scan = split_1_to_9(bunny, 5e-4 * box.diagonal());
  const double split_s = bench::seconds_since(t0);
  Cage cage;
  ScanBinding binding;
  double cage_s = 0, bind_s = 0;
  bool cached = false;
  if (!cache.empty()) {
    try {
      const std::vector<uint8_t> bytes = read_whole_file(cache);
      t0 = bench::Clock::now();
      SavedBinding saved = read_binding(bytes.data(), bytes.size(), cache);
      bind_s = bench::seconds_since(t0);
      cage = std::move(saved.cage);
      binding = std::move(saved.binding);
      cached = binding.num_vertices() == scan.num_vertices();
    } catch (const Error&) {
    }
  }
  if (!cached) {
    t0 = bench::Clock::now();
    cage = cage_near(bunny, 500);
    FitOptions fit;
    fit.max_passes = 3;
    cage = fit_cage_to_mesh(cage, bunny, fit);
    cage_s = bench::seconds_since(t0);
    t0 = bench::Clock::now();
    binding = bind_scan_to_cage(cage, scan);
    bind_s = bench::seconds_since(t0);
    if (!cache.empty()) {
      const std::vector<uint8_t> bytes = write_binding(binding, cage, BindOptions());
      std::FILE* f = std::fopen(cache.c_str(), "wb");
      if (f) std::fwrite(bytes.data(), 1, bytes.size(), f), std::fclose(f);
    }
  }
  if (cell_order) {  // the scan renumbered in the deformer's write order, bound again
    scan = renumber_vertices(scan, deformer_vertex_order(binding));
    t0 = bench::Clock::now();
    binding = bind_scan_to_cage(cage, scan);
    std::printf("--cell-order: the scan renumbered by deformer_vertex_order and bound again (%.1f s)\n\n",
                bench::seconds_since(t0));
    if (!cache.empty()) {  // the renumbered binding too (FILE.cell), for tools that time it alone
      const std::vector<uint8_t> bytes = write_binding(binding, cage, BindOptions());
      std::FILE* f = std::fopen((cache + ".cell").c_str(), "wb");
      if (f) std::fwrite(bytes.data(), 1, bytes.size(), f), std::fclose(f);
    }
  }
  const size_t n = binding.num_vertices(), m = binding.num_control_vertices;
  const PatchDeformerTable& table = binding.compact;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  std::printf("## bench_deform: %zu-vertex / %zu-triangle scan (bunny split 1-to-9 + noise, %.1f s), %zu-vertex / "
              "%zu-face cage (simplified + 3 fit passes, %.1f s), bind %.1f s%s\n\n",
              n, scan.num_faces(), split_s, m, cage.mesh.num_faces(), cage_s, bind_s,
              cached ? " (read from the --cache file)" : "");
  std::printf("Compact table: %zu cells (%.0f vertices per cell, %zu terms), %zu irregular vertices (%.2f%%, %.1f row "
              "entries each); sparse rows %.1f entries per vertex. %u cores, load average before: %s\n\n",
              table.num_cells(), double(table.num_cell_vertices()) / std::max<size_t>(1, table.num_cells()),
              table.term_control.size(), table.num_irregular_vertices(),
              100.0 * double(table.num_irregular_vertices()) / double(n),
              double(table.irregular_control.size()) / std::max<size_t>(1, table.num_irregular_vertices()),
              double(binding.num_entries()) / double(n), cores, bench::load_average().c_str());
  {
    size_t cells_at[32] = {}, vertices_at[32] = {};
    for (size_t c = 0; c < table.num_cells(); ++c) {
      cells_at[table.cell_depth[c]] += 1;
      vertices_at[table.cell_depth[c]] += table.cell_vertex_offsets[c + 1] - table.cell_vertex_offsets[c];
    }
    std::printf("Cells by depth (cells / vertices):");
    for (int d = 0; d < 32; ++d)
      if (cells_at[d]) std::printf(" %d: %zu / %zu;", d, cells_at[d], vertices_at[d]);
    std::printf(" ptex faces %u\n\n", SubdivisionSurface(cage).num_ptex_faces());
  }
  std::fflush(stdout);
  if (table_only) return 0;

  std::vector<Vec3> positions(n), normals(n), control = cage.mesh.positions;
  const double step = 1e-4 * binding.bbox_diagonal;
  auto move_all = [&](int frame) {
    for (Vec3& c : control) c.x += frame % 2 ? -step : step;
  };
  struct Row {
    std::string name;
    double seconds;
    double cpu;
    double vertices;
    double bytes;
  };
  std::vector<Row> rows;
  for (int threads : {2, 1}) {
    CpuDeformer deformer(binding, threads);
    const double s = median_frame(frames, [&](int f) {
      move_all(f);
      deformer.deform(control, positions.data(), normals.data());
    });
    rows.push_back({"CpuDeformer full (compact), " + std::to_string(threads) + " thread" + (threads > 1 ? "s" : ""), s,
                    g_cpu, double(n), deformer.bytes_per_vertex()});
  }
  // The same into float32 xyz arrays (CpuDeformer::deform(float*), cagekit_cpu_deformer_deform_f32):
  // 24 bytes written per vertex instead of 48.
  std::vector<float> positions_f32(3 * n), normals_f32(3 * n);
  for (int threads : {2, 1}) {
    CpuDeformer deformer(binding, threads);
    const double s = median_frame(frames, [&](int f) {
      move_all(f);
      deformer.deform(control, positions_f32.data(), normals_f32.data());
    });
    rows.push_back({"CpuDeformer full (compact), float32 outputs, " + std::to_string(threads) + " thread" +
                        (threads > 1 ? "s" : ""),
                    s, g_cpu, double(n), deformer.bytes_per_vertex() - 24});
  }
  // Incremental: 10 control points spread over the cage move every frame.
  double incremental_vertices = 0;
  {
    CpuDeformer deformer(binding, 2);
    deformer.deform(control, positions.data(), normals.data());
    std::vector<uint32_t> moved;
    for (uint32_t k = 0; k < 10; ++k) moved.push_back(uint32_t((uint64_t(k) * 2654435761u) % m));
    std::sort(moved.begin(), moved.end());
    moved.erase(std::unique(moved.begin(), moved.end()), moved.end());
    size_t total = 0;
    int calls = 0;
    const double s = median_frame(frames, [&](int f) {
      for (uint32_t j : moved) control[j].y += f % 2 ? -step : step;
      total += deformer.update(control, moved, positions.data(), normals.data());
      ++calls;
    });
    incremental_vertices = double(total) / calls;
    rows.push_back({"CpuDeformer incremental, " + std::to_string(moved.size()) + " moved, 2 threads", s,
                    g_cpu, incremental_vertices, deformer.bytes_per_vertex()});
  }
  if (!cpu_only) {
    SparseRowDeformer reference(binding, 2);
    const double s = median_frame(std::max(5, frames / 4), [&](int f) {
      move_all(f);
      reference.deform(control, positions.data(), normals.data());
    });
    const double bytes = 4 + 8 * 7 + 3 * 24 + 2 * 24 + double(binding.num_entries()) * 28 / double(n);
    rows.push_back({"SparseRowDeformer full (double rows, reference), 2 threads", s, g_cpu, double(n), bytes});
  }

  // The peer: OpenSubdiv limit stencils at the same foot points, grouped by ptex face.
  double peer_s = 0, peer_s1 = 0, peer_cpu = 0, peer_cpu1 = 0, peer_bytes = 0, peer_max_diff = 0;
  size_t peer_weights = 0;
  if (!cpu_only) {
    auto refiner = subdiv_detail::create_topology_refiner(cage);
    Far::TopologyRefiner::AdaptiveOptions adaptive(3);
    adaptive.useInfSharpPatch = true;
    refiner->RefineAdaptive(adaptive);
    const int num_ptex = Far::PtexIndices(*refiner).GetNumFaces();
    std::vector<std::vector<uint32_t>> by_ptex(static_cast<size_t>(num_ptex));
    for (size_t i = 0; i < n; ++i) by_ptex[binding.foot_points[i].ptex_face].push_back(uint32_t(i));
    std::vector<float> s, t;
    std::vector<uint32_t> order;
    for (const auto& list : by_ptex)
      for (uint32_t i : list) {
        order.push_back(i);
        s.push_back(float(binding.foot_points[i].u));
        t.push_back(float(binding.foot_points[i].v));
      }
    Far::LimitStencilTableFactory::LocationArrayVec arrays;
    size_t at = 0;
    for (int f = 0; f < num_ptex; ++f) {
      if (by_ptex[size_t(f)].empty()) continue;
      Far::LimitStencilTableFactory::LocationArray a;
      a.ptexIdx = f;
      a.numLocations = int(by_ptex[size_t(f)].size());
      a.s = s.data() + at;
      a.t = t.data() + at;
      arrays.push_back(a);
      at += by_ptex[size_t(f)].size();
    }
    t0 = bench::Clock::now();
    std::unique_ptr<const Far::LimitStencilTable> stencils(Far::LimitStencilTableFactory::Create(*refiner, arrays));
    const double create_s = bench::seconds_since(t0);
    if (!stencils || size_t(stencils->GetNumStencils()) != n) {
      std::printf("OpenSubdiv made %d stencils for %zu points: peer skipped\n", stencils ? stencils->GetNumStencils() : -1, n);
    } else {
      peer_weights = stencils->GetWeights().size();
      std::vector<Point3f> cv(m), p(n), du(n), dv(n);
      for (size_t j = 0; j < m; ++j) cv[j] = {float(control[j].x), float(control[j].y), float(control[j].z)};
      auto half = [&](int begin, int end) {
        stencils->UpdateValues(cv.data(), p.data(), begin, end);
        stencils->UpdateDerivs(cv.data(), du.data(), dv.data(), begin, end);
      };
      const int ns = stencils->GetNumStencils();
      peer_s = median_frame(frames, [&](int f) {
        for (Point3f& c : cv) c.x += float(f % 2 ? -step : step);
        std::thread other(half, ns / 2, ns);
        half(0, ns / 2);
        other.join();
      });
      peer_cpu = g_cpu;
      peer_s1 = median_frame(std::max(5, frames / 2), [&](int f) {
        for (Point3f& c : cv) c.x += float(f % 2 ? -step : step);
        half(0, ns);
      });
      peer_cpu1 = g_cpu;
      // Read per stencil: size + offset + weights (index + 3 floats each); written: 3 float3.
      peer_bytes = double(peer_weights) * 16.0 / double(n) + 8 + 36;
      // Sanity: OpenSubdiv's limit points against the binding's foot points on the undeformed
      // cage (they differ only on end caps, Gregory vs CageKit's Stam).
      for (size_t j = 0; j < m; ++j) cv[j] = {float(cage.mesh.positions[j].x), float(cage.mesh.positions[j].y), float(cage.mesh.positions[j].z)};
      stencils->UpdateValues(cv.data(), p.data());
      std::vector<double> diffs;
      for (size_t k = 0; k < n; ++k) {
        const Vec3 q{p[k].x, p[k].y, p[k].z};
        diffs.push_back(distance(q, binding.foot_points[order[k]].position) / binding.bbox_diagonal);
      }
      std::sort(diffs.begin(), diffs.end());
      peer_max_diff = diffs[diffs.size() / 2];
      std::printf("OpenSubdiv: LimitStencilTableFactory %.2f s, %zu weights (%.2f per stencil); median |P_OSD - S| "
                  "%.2g of the diagonal (max %.2g, end caps)\n\n",
                  create_s, peer_weights, double(peer_weights) / double(n), peer_max_diff, diffs.back());
    }
  }
  if (peer_s > 0) {
    rows.push_back({"OpenSubdiv Far::LimitStencilTable UpdateValues + UpdateDerivs (P, du, dv only), 2 threads", peer_s,
                    peer_cpu, double(n), peer_bytes});
    rows.push_back({"OpenSubdiv Far::LimitStencilTable UpdateValues + UpdateDerivs, 1 thread", peer_s1, peer_cpu1,
                    double(n), peer_bytes});
  }
  std::printf("| run | frame ms (median) | frames/s | CPU ms per frame (all threads) | vertices per frame | M vertices/s | "
              "bytes/vertex (read + written) | GB/s | fps / OpenSubdiv 2 threads | CPU time OpenSubdiv / this |\n"
              "|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    char ratio[32] = "n/a", cpu_ratio[32] = "n/a";
    if (peer_s > 0) {
      std::snprintf(ratio, sizeof ratio, "%.2fx", peer_s / r.seconds);
      std::snprintf(cpu_ratio, sizeof cpu_ratio, "%.2fx", peer_cpu / r.cpu);
    }
    std::printf("| %s | %.3f | %.1f | %.3f | %.0f | %.1f | %.1f | %.2f | %s | %s |\n", r.name.c_str(), 1e3 * r.seconds,
                1.0 / r.seconds, 1e3 * r.cpu, r.vertices, r.vertices / r.seconds * 1e-6, r.bytes,
                r.vertices * r.bytes / r.seconds * 1e-9, ratio, cpu_ratio);
  }
  std::printf("| GPU deformer (GL) | not measured here (tests/gpu) | | | | | | | | |\n\n");
  std::printf("%d frames per run (reference: %d, 1-thread OpenSubdiv: %d) after 3 warm-up frames.\n", frames,
              std::max(5, frames / 4), std::max(5, frames / 2));
  std::printf("Load average after: %s\n", bench::load_average().c_str());
  return 0;
}
