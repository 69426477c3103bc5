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
  Mesh scan;
  session.check(cagekit_mesh_read_file(session.context().get(), files[0].c_str(), CAGEKIT_FORMAT_AUTO, scan.out()), files[0]);
  Cage cage;
  session.check(cagekit_cage_read_file(session.context().get(), files[1].c_str(), CAGEKIT_FORMAT_AUTO, cage.out()), files[1]);
  std::vector<double> control = cage_positions(session, cage.get(), files[1]);
  const uint32_t m = uint32_t(control.size() / 3);
  Binding binding;
  session.check(cagekit_multires_bind(cage.get(), scan.get(), nullptr, binding.out()), files[0] + " bound to " + files[1]);
  if (vertex_order == "deformer") {
    // What a host that may renumber its scan does once: the scan renumbered in the deformer's
    // write order (cagekit_binding_get_deformer_vertex_order), bound again.
    uint32_t count = 0, vertices = 0, face_count = 0;
    uint64_t index_count = 0;
    session.check(cagekit_binding_get_deformer_vertex_order(binding.get(), 0, &count, nullptr), "vertex order");
    std::vector<uint32_t> order(count);
    session.check(cagekit_binding_get_deformer_vertex_order(binding.get(), count, &count, order.data()), "vertex order");
    session.check(cagekit_mesh_get_positions(scan.get(), CAGEKIT_SCALAR_FLOAT64, 0, &vertices, nullptr), files[0]);
    std::vector<double> positions(3 * size_t(vertices)), renumbered(positions.size());
    session.check(cagekit_mesh_get_positions(scan.get(), CAGEKIT_SCALAR_FLOAT64, vertices, &vertices, positions.data()),
                  files[0]);
    session.check(cagekit_mesh_get_faces(scan.get(), 0, &face_count, nullptr, 0, &index_count, nullptr), files[0]);
    std::vector<uint32_t> sizes(face_count), indices(index_count), new_id(vertices);
    session.check(cagekit_mesh_get_faces(scan.get(), face_count, &face_count, sizes.data(), index_count, &index_count,
                                         indices.data()),
                  files[0]);
    if (count != vertices) throw Failure(kExitBadInput, "vertex order: " + std::to_string(count) + " entries");
    for (uint32_t k = 0; k < count; ++k) {
      new_id[order[k]] = k;
      for (int a = 0; a < 3; ++a) renumbered[3 * size_t(k) + size_t(a)] = positions[3 * size_t(order[k]) + size_t(a)];
    }
    for (uint32_t& v : indices) v = new_id[v];
    cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
    desc.vertex_count = vertices;
    desc.positions = renumbered.data();
    desc.face_count = face_count;
    desc.face_sizes = sizes.data();
    desc.face_indices = indices.data();
    session.check(cagekit_mesh_create(session.context().get(), &desc, scan.out()), "renumbered scan");
    session.check(cagekit_multires_bind(cage.get(), scan.get(), nullptr, binding.out()),
                  "renumbered scan bound to " + files[1]);
  }
  cagekit_binding_info info;
  info.struct_size = sizeof(info);
  session.check(cagekit_binding_get_info(binding.get(), &info), "binding");
  Deformer deformer;
  session.check(cagekit_cpu_deformer_create(binding.get(), uint32_t(threads), deformer.out()), "deformer");
  uint32_t faces = 0;
  uint64_t indices = 0;
  session.check(cagekit_mesh_get_faces(scan.get(), 0, &faces, nullptr, 0, &indices, nullptr), files[0]);
  std::vector<double> positions(3 * size_t(info.vertex_count)), normals(positions.size());
  const uint32_t n = info.vertex_count;
  uint32_t written = 0;  // the deform calls' vertex count output (n)
  const double step = 1e-4 * info.bbox_diagonal;
  // Full recompute: every control point moves every frame.
  session.check(cagekit_cpu_deformer_deform(deformer.get(), control.data(), m, CAGEKIT_NORMALS_APPROXIMATE, n,
                                            &written, positions.data(), normals.data()), "deform");
  auto t0 = std::chrono::steady_clock::now();
  for (int f = 0; f < frames; ++f) {
    for (double& c : control) c += (f % 2 ? -step : step);
    session.check(cagekit_cpu_deformer_deform(deformer.get(), control.data(), m, CAGEKIT_NORMALS_APPROXIMATE, n,
                                              &written, positions.data(), normals.data()), "deform");
  }
  const double full_fps = frames / seconds_since(t0);
  // The same into float32 arrays (cagekit_cpu_deformer_deform_f32: what GL / Blender hosts draw).
  std::vector<float> positions_f32(positions.size()), normals_f32(normals.size());
  session.check(cagekit_cpu_deformer_deform_f32(deformer.get(), control.data(), m, CAGEKIT_NORMALS_APPROXIMATE, n,
                                                &written, positions_f32.data(), normals_f32.data()), "deform_f32");
  t0 = std::chrono::steady_clock::now();
  for (int f = 0; f < frames; ++f) {
    for (double& c : control) c += (f % 2 ? -step : step);
    session.check(cagekit_cpu_deformer_deform_f32(deformer.get(), control.data(), m, CAGEKIT_NORMALS_APPROXIMATE, n,
                                                  &written, positions_f32.data(), normals_f32.data()), "deform_f32");
  }
  const double full_fps_f32 = frames / seconds_since(t0);
  // Back to the double arrays (the incremental run below updates them).
  session.check(cagekit_cpu_deformer_deform(deformer.get(), control.data(), m, CAGEKIT_NORMALS_APPROXIMATE, n,
                                            &written, positions.data(), normals.data()), "deform");
  // Incremental: K control points move per frame.
  std::vector<uint32_t> moved;
  for (int k = 0; k < moved_count && k < int(m); ++k) moved.push_back(uint32_t((uint64_t(k) * 2654435761u) % m));
  std::sort(moved.begin(), moved.end());
  moved.erase(std::unique(moved.begin(), moved.end()), moved.end());
  uint64_t updated_total = 0;
  t0 = std::chrono::steady_clock::now();
  for (int f = 0; f < frames; ++f) {
    for (uint32_t j : moved) control[3 * size_t(j)] += (f % 2 ? -step : step);
    uint32_t updated = 0;
    session.check(cagekit_cpu_deformer_update(deformer.get(), control.data(), m, moved.data(), uint32_t(moved.size()),
                                              CAGEKIT_NORMALS_APPROXIMATE, n, &written, positions.data(),
                                              normals.data(), &updated),
                  "update");
    updated_total += updated;
  }
  const double incremental_fps = frames / seconds_since(t0);
  session.finish_progress();
  // GPU: full recompute in a headless EGL context (llvmpipe where there is no GPU).
  const GpuBench gpu = bench_gpu_deformer(session.context().get(), binding.get(), scan.get(), control, frames, step);
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
