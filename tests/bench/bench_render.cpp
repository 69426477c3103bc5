// SPDX-License-Identifier: GPL-3.0-or-later
// bench_render (issue 24): `cagekit render OUT.png --mesh IN --views front,side,top,iso --size 1024x1024`
// against Blender 3.4's Workbench engine drawing the same mesh from the same four views into the same
// 2 x 2 picture (tests/bench/render_blender.py), on fandisk, the Stanford bunny and bunny-1.1M (generated as
// in bench_io: the bunny Loop-subdivided twice with seeded noise). Rounds alternate CageKit and Blender;
// medians of 3 rounds. Reported: the whole command's wall time (process start to exit, file read and PNG
// write included), the read and draw times each tool reports of itself, and the PNG size. Timing only:
// never fails on it. Usage: bench_render [CAGEKIT_CLI]  (default: the CLI of this build tree)
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_support.h"
#include "core/io/mesh_io.h"
#include "core/mesh_repair.h"

#ifndef CAGEKIT_BENCH_DIR
#error "CAGEKIT_BENCH_DIR must name tests/bench"
#endif

namespace {

struct Run {
  double wall = 0, read = -1, draw = -1;
  std::string output;
};

Run run_command(const std::string& command) {
  Run r;
  const auto start = bench::Clock::now();
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) r.output += buffer;
  const int status = pclose(pipe);
  r.wall = bench::seconds_since(start);
  if (status != 0) r.wall = -1;
  return r;
}

double number_after(const std::string& text, const std::string& key) {
  const size_t at = text.rfind(key);
  return at == std::string::npos ? -1.0 : std::atof(text.c_str() + at + key.size());
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? -1.0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const std::string cli = argc > 1 ? argv[1] : CAGEKIT_CLI;
  const std::string meshes = CAGEKIT_SHARED_MESHES;
  const std::filesystem::path tmp = std::filesystem::temp_directory_path() / "cagekit_bench_render";
  std::filesystem::create_directories(tmp);
  const bool blender = std::system("blender --version >/dev/null 2>&1") == 0;
  std::vector<std::pair<std::string, std::string>> inputs;
  if (std::filesystem::exists(meshes + "/fandisk.obj")) inputs.push_back({"fandisk", meshes + "/fandisk.obj"});
  if (std::filesystem::exists(meshes + "/stanford-bunny.obj")) {
    inputs.push_back({"bunny", meshes + "/stanford-bunny.obj"});
    std::printf("generating bunny-1.1M (Loop x2 + noise) ...\n");
    std::fflush(stdout);
    cagekit::Cage bunny = cagekit::read_cage_from_file(meshes + "/stanford-bunny.obj");
    cagekit::RepairOptions repair;  // as bench_io: only the unreferenced vertices dropped
    repair.weld_tolerance = -1;
    repair.drop_invalid_faces = repair.drop_degenerate_faces = repair.drop_duplicate_faces = false;
    repair.split_non_manifold = repair.orient_consistently = false;
    repair.remove_unreferenced_vertices = true;
    cagekit::RepairReport report;
    bunny.mesh = cagekit::repair_mesh(bunny.mesh, repair, &report);
    cagekit::Cage dense;
    dense.mesh = bench::dense_bunny(bunny.mesh);
    cagekit::WriteOptions obj;
    obj.format = cagekit::FileFormat::obj;
    obj.obj_precision = 9;
    const std::string path = (tmp / "bunny-1.1M.obj").string();
    cagekit::write_cage_to_file(path, dense, obj);
    std::printf("  %zu triangles\n", dense.mesh.num_faces());
    inputs.push_back({"bunny-1.1M", path});
  }
  if (inputs.empty()) {
    std::printf("skipped: no meshes in %s\n", meshes.c_str());
    return 0;
  }
  std::printf("load average before: %s\n\n", bench::load_average().c_str());
  std::printf("| mesh | tool | whole command s | read s | draw s | PNG KB | CageKit / Blender (whole) |\n");
  std::printf("|---|---|--:|--:|--:|--:|--:|\n");
  for (const auto& [name, path] : inputs) {
    const std::string ours_png = (tmp / (name + "-cagekit.png")).string();
    const std::string peer_png = (tmp / (name + "-blender.png")).string();
    std::vector<double> ow, orr, od, bw, br, bd;
    for (int round = 0; round < 3; ++round) {
      const Run o = run_command("'" + cli + "' render '" + ours_png + "' --mesh '" + path +
                                "' --views front,side,top,iso --size 1024x1024");
      if (o.wall >= 0) {
        ow.push_back(o.wall);
        orr.push_back(number_after(o.output, "read "));
        od.push_back(number_after(o.output, "render "));
      } else {
        std::printf("cagekit render failed:\n%s\n", o.output.c_str());
      }
      if (!blender) continue;
      const Run b = run_command("blender -b --factory-startup -noaudio --python '" CAGEKIT_BENCH_DIR
                                "/render_blender.py' -- '" + path + "' '" + peer_png + "' 1024");
      if (b.wall >= 0) {
        bw.push_back(b.wall);
        br.push_back(number_after(b.output, "\"import_seconds\": "));
        bd.push_back(number_after(b.output, "\"render_seconds\": "));
      }
    }
    auto kb = [](const std::string& p) {
      return std::filesystem::exists(p) ? double(std::filesystem::file_size(p)) / 1024.0 : -1.0;
    };
    const double ours = median(ow), peer = median(bw);
    std::printf("| %s | CageKit | %.2f | %.2f | %.2f | %.0f | %s |\n", name.c_str(), ours, median(orr), median(od),
                kb(ours_png), peer > 0 && ours > 0 ? (std::to_string(ours / peer).substr(0, 5) + "x").c_str() : "n/a");
    if (blender)
      std::printf("| %s | Blender Workbench | %.2f | %.2f | %.2f | %.0f | |\n", name.c_str(), peer, median(br),
                  median(bd), kb(peer_png));
    std::fflush(stdout);
  }
  std::printf("\nload average after: %s\n", bench::load_average().c_str());
  return 0;
}
