// SPDX-License-Identifier: GPL-3.0-or-later
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli_context.h"

namespace cli {

namespace {

const FlagOption kJson{"--json", "print the statistics as one JSON object"};

int command_info(const Options& args) {
  const bool json = args.flag(kJson);
  const std::vector<std::string> files = {args.positional("IN")};
  Session session(args.quiet());
  LoadedInput input;
  load_input(session, files[0], &input);

  const bool valid = static_cast<bool>(input.cage);
  const cagekit_mesh_info info =
      session.run(files[0], [&] { return valid ? input.cage.info() : input.mesh.info(); });
  session.finish_progress();

  if (json) {
    const auto g = [](double x) { return json_rounded(x, "%.9g"); };
    nlohmann::ordered_json j;
    j["file"] = files[0];
    j["vertices"] = uint64_t(info.vertices);
    j["faces"] = uint64_t(info.faces);
    j["edges"] = uint64_t(info.edges);
    j["quads"] = uint64_t(info.quads);
    j["triangles"] = uint64_t(info.triangles);
    j["other_polygons"] = uint64_t(info.other_polygons);
    j["boundary_edges"] = uint64_t(info.boundary_edges);
    j["boundary_loops"] = uint64_t(info.boundary_loops);
    j["components"] = uint64_t(info.components);
    j["unreferenced_vertices"] = uint64_t(info.unreferenced_vertices);
    j["genus"] = int64_t(info.genus);
    j["manifold"] = bool(info.manifold);
    j["valid"] = valid;
    j["problem"] = input.problem;
    j["bbox_min"] = {g(info.bbox_min[0]), g(info.bbox_min[1]), g(info.bbox_min[2])};
    j["bbox_max"] = {g(info.bbox_max[0]), g(info.bbox_max[1]), g(info.bbox_max[2])};
    j["bbox_diagonal"] = g(info.bbox_diagonal);
    j["creases"] = uint64_t(info.creases);
    j["corners"] = uint64_t(info.corners);
    j["holes"] = uint64_t(info.holes);
    std::printf("%s\n", json_text(j).c_str());
    return kExitOk;
  }
  std::printf("%s\n", files[0].c_str());
  std::printf("  vertices        %llu (%llu unreferenced)\n", (unsigned long long)info.vertices,
              (unsigned long long)info.unreferenced_vertices);
  std::printf("  faces           %llu (%llu triangles, %llu quads, %llu other)\n", (unsigned long long)info.faces,
              (unsigned long long)info.triangles, (unsigned long long)info.quads,
              (unsigned long long)info.other_polygons);
  std::printf("  edges           %llu (%llu boundary, %llu boundary loops)\n", (unsigned long long)info.edges,
              (unsigned long long)info.boundary_edges, (unsigned long long)info.boundary_loops);
  std::printf("  components      %llu\n", (unsigned long long)info.components);
  std::printf("  manifold        %s, genus %lld\n", info.manifold ? "yes" : "no", (long long)info.genus);
  std::printf("  bbox diagonal   %.9g\n", info.bbox_diagonal);
  std::printf("  tags            %llu creases, %llu corners, %llu holes\n", (unsigned long long)info.creases,
              (unsigned long long)info.corners, (unsigned long long)info.holes);
  if (!valid) std::printf("  not a valid cage: %s\n", input.problem.c_str());
  return kExitOk;
}

}  // namespace

Command add_info(CLI::App& cagekit) {
  CLI::App* app = cagekit.add_subcommand("info", "statistics of a mesh or cage file (vertices, faces, genus, creases, ...)");
  auto options = std::make_shared<Options>(app);
  options->add_positional("IN", "mesh or cage file (.obj .ply .off .drc .stl)");
  options->add(kJson);
  options->add_quiet();
  return {app, [options] { return command_info(*options); }};
}

}  // namespace cli
