// SPDX-License-Identifier: GPL-3.0-or-later
// Frames per second of the multiresolution deformer (thesis ch. 8): the CPU deformer over the
// whole cage and over K moved control points, and the GPU deformer where EGL gives a context.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli_context.h"
#include "gpu_bench.h"

namespace cli {

namespace {

const FlagOption kJson{"--json", "print the frame rates as one JSON object"};
const TextOption kVertexOrder{"--vertex-order", "scan", "scan|deformer",
                              "deformer: the scan renumbered first in the deformer's write order, as a host that "
                              "may renumber does"};
const IntegerOption kFrames{"--frames", 100, 1, 1000000, "N", "frames timed per measurement"};
const IntegerOption kMoved{"--moved", 10, 1, 1000000, "K", "control points moved per frame in the incremental run"};
const IntegerOption kThreads{"--threads", 0, 0, 1024, "N", "deformer threads (0: all cores)"};

int command_bench_deform(const Options& args) {
  const bool quiet = args.quiet();
  const bool json = args.flag(kJson);
  const std::string vertex_order = args.text(kVertexOrder);
  if (vertex_order != "scan" && vertex_order != "deformer")
    throw Failure(kExitBadInput, "--vertex-order must be scan or deformer, not '" + vertex_order + "'");
  int frames = 100, moved_count = 10, threads = 0;
  try {
    frames = args.integer(kFrames);
    moved_count = args.integer(kMoved);
    threads = args.integer(kThreads);
  } catch (const Failure& f) {
    throw Failure(f.code == kExitUsage ? kExitBadInput : f.code, f.what());
  }
  const std::vector<std::string> files = {args.positional("SCAN"), args.positional("CAGE")};
  Session session(quiet);
  const cagekit::Context& context = session.context();
  cagekit::Mesh scan = session.run(files[0], [&] { return context.read_mesh(files[0]); });
  const cagekit::Cage cage = session.run(files[1], [&] { return context.read_cage(files[1]); });
  std::vector<double> control = cage_positions(session, cage, files[1]);
  const uint32_t m = uint32_t(control.size() / 3);
  const auto bind = [&cage](const cagekit::Mesh& mesh) { return cage.bind(mesh); };  // default options
  cagekit::Binding binding = session.run(files[0] + " bound to " + files[1], [&] { return bind(scan); });
  if (vertex_order == "deformer") {
    // What a host that may renumber its scan does once: the scan renumbered in the deformer's
    // write order (cagekit::Binding::deformer_vertex_order), bound again.
    const std::vector<uint32_t> order = session.run("vertex order", [&] { return binding.deformer_vertex_order(); });
    const uint32_t count = uint32_t(order.size());
    const std::vector<double> positions = session.run(files[0], [&] { return scan.positions(); });
    cagekit::Faces faces = session.run(files[0], [&] { return scan.faces(); });
    const uint32_t vertices = uint32_t(positions.size() / 3);
    std::vector<double> renumbered(positions.size());
    std::vector<uint32_t> new_id(vertices);
    if (count != vertices) throw Failure(kExitBadInput, "vertex order: " + std::to_string(count) + " entries");
    for (uint32_t k = 0; k < count; ++k) {
      new_id[order[k]] = k;
      for (int a = 0; a < 3; ++a) renumbered[3 * size_t(k) + size_t(a)] = positions[3 * size_t(order[k]) + size_t(a)];
    }
    for (uint32_t& v : faces.face_indices) v = new_id[v];
    scan = session.run("renumbered scan",
                       [&] { return context.create_mesh(renumbered, faces.face_sizes, faces.face_indices); });
    binding = session.run("renumbered scan bound to " + files[1], [&] { return bind(scan); });
  }
  const cagekit_binding_info info = session.run("binding", [&] { return binding.info(); });
  cagekit::CpuDeformer deformer =
      session.run("deformer", [&] { return binding.create_cpu_deformer(uint32_t(threads)); });
  const cagekit::MeshCounts counts = session.run(files[0], [&] { return scan.counts(); });
  const uint32_t faces = counts.faces;
  const uint64_t indices = counts.face_indices;
  std::vector<double> positions(3 * size_t(info.vertex_count)), normals(positions.size());
  const uint32_t n = info.vertex_count;
  const double step = 1e-4 * info.bbox_diagonal;
  const auto deform = [&] {
    session.run("deform", [&] { deformer.deform(control, CAGEKIT_NORMALS_APPROXIMATE, positions, normals); });
  };
  // Full recompute: every control point moves every frame.
  deform();
  auto t0 = std::chrono::steady_clock::now();
  for (int f = 0; f < frames; ++f) {
    for (double& c : control) c += (f % 2 ? -step : step);
    deform();
  }
  const double full_fps = frames / seconds_since(t0);
  // The same into float32 arrays (CpuDeformer::deform_f32: what GL / Blender hosts draw).
  std::vector<float> positions_f32(positions.size()), normals_f32(normals.size());
  const auto deform_f32 = [&] {
    session.run("deform_f32",
                [&] { deformer.deform_f32(control, CAGEKIT_NORMALS_APPROXIMATE, positions_f32, normals_f32); });
  };
  deform_f32();
  t0 = std::chrono::steady_clock::now();
  for (int f = 0; f < frames; ++f) {
    for (double& c : control) c += (f % 2 ? -step : step);
    deform_f32();
  }
  const double full_fps_f32 = frames / seconds_since(t0);
  // Back to the double arrays (the incremental run below updates them).
  deform();
  // Incremental: K control points move per frame.
  std::vector<uint32_t> moved;
  for (int k = 0; k < moved_count && k < int(m); ++k) moved.push_back(uint32_t((uint64_t(k) * 2654435761u) % m));
  std::sort(moved.begin(), moved.end());
  moved.erase(std::unique(moved.begin(), moved.end()), moved.end());
  uint64_t updated_total = 0;
  t0 = std::chrono::steady_clock::now();
  for (int f = 0; f < frames; ++f) {
    for (uint32_t j : moved) control[3 * size_t(j)] += (f % 2 ? -step : step);
    updated_total += session.run(
        "update", [&] { return deformer.update(control, moved, CAGEKIT_NORMALS_APPROXIMATE, positions, normals); });
  }
  const double incremental_fps = frames / seconds_since(t0);
  session.finish_progress();
  // GPU: full recompute in a headless EGL context (llvmpipe where there is no GPU).
  const GpuBench gpu = bench_gpu_deformer(context, binding, scan, control, frames, step);
  if (!gpu.ran && !quiet) std::fprintf(stderr, "cagekit: bench-deform: gpu_fps is null: %s\n", gpu.why.c_str());
  // Bytes read + written per vertex in one full CPU frame (the library's own count for the table
  // the deformer streams; sdk/multires/patch_deformer_table.h).
  const double bytes_per_vertex = info.deform_bytes_per_vertex;
  if (json) {
    nlohmann::ordered_json j;
    j["vertices"] = n;
    j["triangles"] = uint64_t(indices - 2ull * faces);
    j["control_points"] = m;
    j["moved"] = moved.size();
    j["frames"] = frames;
    j["cpu_fps"] = json_rounded(full_fps, "%.2f");
    j["cpu_fps_f32"] = json_rounded(full_fps_f32, "%.2f");
    j["cpu_incremental_fps"] = json_rounded(incremental_fps, "%.2f");
    j["incremental_vertices_per_frame"] = json_rounded(double(updated_total) / frames, "%.1f");
    j["gpu_fps"] = gpu.ran ? json_rounded(gpu.fps, "%.2f") : nullptr;
    j["gpu_renderer"] = gpu.ran ? nlohmann::ordered_json(gpu.renderer) : nullptr;
    j["gpu_gl_version"] = gpu.ran ? nlohmann::ordered_json(gpu.version) : nullptr;
    j["bytes_per_vertex"] = json_rounded(bytes_per_vertex, "%.1f");
    j["basis_entries_per_vertex"] = json_rounded(double(info.basis_entries) / n, "%.2f");
    j["vertex_order"] = vertex_order;
    std::printf("%s\n", json_text(j).c_str());
  } else if (!quiet) {
    std::printf("%u vertices, %u control points: full recompute %.1f frames/s (float32 outputs %.1f), %zu moved "
                "points %.1f frames/s (%.0f vertices recomputed per frame), %.0f bytes per vertex\n",
                n, m, full_fps, full_fps_f32, moved.size(), incremental_fps, double(updated_total) / frames, bytes_per_vertex);
    if (gpu.ran)
      std::printf("GPU deformer (full recompute, %s, %s): %.1f frames/s\n", gpu.renderer.c_str(), gpu.version.c_str(),
                  gpu.fps);
  }
  return kExitOk;
}

}  // namespace

Command add_bench_deform(CLI::App& cagekit) {
  CLI::App* app = cagekit.add_subcommand(
      "bench-deform", "frames per second of the CPU deformer (full and K moved points) and the GPU one (EGL)");
  auto options = std::make_shared<Options>(app);
  options->add_positional("SCAN", "mesh file");
  options->add_positional("CAGE", "cage file");
  options->add(kFrames);
  options->add(kMoved);
  options->add(kThreads);
  options->add(kVertexOrder);
  options->add(kJson);
  options->add_quiet();
  return {app, [options] { return command_bench_deform(*options); }};
}

}  // namespace cli
