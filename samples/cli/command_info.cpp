// SPDX-License-Identifier: GPL-3.0-or-later
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

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

  cagekit_mesh_info info = {};
  info.struct_size = sizeof(info);
  cagekit_validation_report report = {};
  report.struct_size = sizeof(report);
  bool valid = true;
  if (input.cage.get()) {
    session.check(cagekit_cage_get_info(input.cage.get(), &info), files[0]);
  } else {
    session.check(cagekit_mesh_get_info(input.mesh.get(), &info), files[0]);
    valid = false;
  }
  session.finish_progress();

  if (json) {
    std::printf(
        "{\"file\": %s, \"vertices\": %llu, \"faces\": %llu, \"edges\": %llu, \"quads\": %llu, "
        "\"triangles\": %llu, \"other_polygons\": %llu, \"boundary_edges\": %llu, \"boundary_loops\": %llu, "
        "\"components\": %llu, \"unreferenced_vertices\": %llu, \"genus\": %lld, \"manifold\": %s, "
        "\"valid\": %s, \"problem\": %s, \"bbox_min\": [%.9g, %.9g, %.9g], \"bbox_max\": [%.9g, %.9g, %.9g], "
        "\"bbox_diagonal\": %.9g, \"creases\": %llu, \"corners\": %llu, \"holes\": %llu}\n",
        json_string(files[0]).c_str(), (unsigned long long)info.vertices, (unsigned long long)info.faces,
        (unsigned long long)info.edges, (unsigned long long)info.quads, (unsigned long long)info.triangles,
        (unsigned long long)info.other_polygons, (unsigned long long)info.boundary_edges,
        (unsigned long long)info.boundary_loops, (unsigned long long)info.components,
        (unsigned long long)info.unreferenced_vertices, (long long)info.genus, info.manifold ? "true" : "false",
        valid ? "true" : "false", json_string(input.problem).c_str(), info.bbox_min[0], info.bbox_min[1],
        info.bbox_min[2], info.bbox_max[0], info.bbox_max[1], info.bbox_max[2], info.bbox_diagonal,
        (unsigned long long)info.creases, (unsigned long long)info.corners, (unsigned long long)info.holes);
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
