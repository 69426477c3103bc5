// SPDX-License-Identifier: GPL-3.0-or-later
// Multiresolution editing (thesis ch. 8) through the C API: bind the scan to the cage's limit
// surface, then move the cage's control points and rebuild the scan with its details.
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

namespace cli {

namespace {

const FlagOption kJson{"--json", "print the deformation's figures as one JSON object"};
const FlagOption kLocalFrame{"--local-frame", "keep the details' sideways offsets (local-frame displacements; "
                                              "default: along the normal)"};

int command_deform(const Options& args) {
  const bool quiet = args.quiet();
  const bool json = args.flag(kJson);
  const bool local_frame = args.flag(kLocalFrame);
  const double sharp_angle = parse_sharp_angle(args);
  const std::vector<std::string> files = {args.positional("SCAN"), args.positional("CAGE"),
                                          args.positional("EDITED_CAGE"), args.positional("OUT")};
  const cagekit_file_format out_format = format_from_extension(files[3]);

  Session session(quiet);
  const cagekit::Context& context = session.context();
  const cagekit::Mesh scan = session.run(files[0], [&] { return context.read_mesh(files[0]); });
  // CAGE is a cage file, or a binding saved by `cagekit bind` (.ckb: the cage is in it).
  const bool saved = files[1].size() > 4 && files[1].compare(files[1].size() - 4, 4, ".ckb") == 0;
  cagekit::Binding binding;
  cagekit::Cage cage;
  if (saved) {
    session.run(files[1], [&] {
      binding = context.read_binding(files[1], 0);
      cage = binding.cage();
    });
  } else {
    cage = session.run(files[1], [&] { return context.read_cage(files[1]); });
  }
  const cagekit::Cage edited = session.run(files[2], [&] { return context.read_cage(files[2]); });
  const std::vector<double> before = cage_positions(session, cage, files[1]);
  const std::vector<double> after = cage_positions(session, edited, files[2]);
  if (before.size() != after.size())
    throw Failure(kExitBadInput, files[2] + ": has " + std::to_string(after.size() / 3) + " vertices but " + files[1] +
                                     " has " + std::to_string(before.size() / 3) + " (the edited cage must be the same cage)");

  const auto t0 = std::chrono::steady_clock::now();
  cagekit_bind_options options = cagekit::defaults<cagekit_bind_options>();
  options.mode = local_frame ? CAGEKIT_DISPLACEMENT_LOCAL_FRAME : CAGEKIT_DISPLACEMENT_NORMAL;
  options.sharp_angle_degrees = sharp_angle;
  if (!saved) binding = session.run(files[0] + " bound to " + files[1], [&] { return cage.bind(scan, options); });
  const double bind_seconds = seconds_since(t0);
  const cagekit_binding_info info = session.run("binding", [&] { return binding.info(); });
  const uint32_t scan_vertices = session.run(files[0], [&] { return scan.counts().vertices; });
  if (scan_vertices != info.scan_vertex_count)
    throw Failure(kExitBadInput, files[1] + ": binds " + std::to_string(info.vertex_count) + " vertices but " + files[0] +
                                     " has " + std::to_string(scan_vertices) + " (not the scan it was made from)");
  cagekit::CpuDeformer deformer = session.run("deformer", [&] { return binding.create_cpu_deformer(0); });
  std::vector<double> positions(3 * size_t(info.vertex_count));
  const auto t1 = std::chrono::steady_clock::now();
  session.run("deform", [&] { deformer.deform(after, CAGEKIT_NORMALS_APPROXIMATE, positions, nullptr); });
  const double deform_seconds = seconds_since(t1);

  // The scan's connectivity with the deformed positions (with a sector split: the faces over
  // the bound vertices, one copy per smooth sector at sharp features).
  const cagekit::Faces faces = info.has_sector_split ? session.run("binding", [&] { return binding.faces(); })
                                                     : session.run(files[0], [&] { return scan.faces(); });
  const cagekit::Mesh out = session.run(
      "deformed scan", [&] { return context.create_mesh(positions, faces.face_sizes, faces.face_indices); });
  cagekit_write_options write = cagekit::defaults<cagekit_write_options>();
  write.format = out_format;
  session.run(files[3], [&] { out.write_file(files[3], write); });
  session.finish_progress();

  double moved = 0;
  for (size_t k = 0; k + 2 < before.size(); k += 3)
    moved = std::max(moved, std::hypot(after[k] - before[k], after[k + 1] - before[k + 1], after[k + 2] - before[k + 2]));
  if (json) {
    nlohmann::ordered_json j;
    j["vertices"] = info.vertex_count;
    j["scan_vertices"] = info.scan_vertex_count;
    j["control_points"] = info.control_count;
    j["basis_entries"] = uint64_t(info.basis_entries);
    j["max_control_move_rel"] = json_rounded(info.bbox_diagonal > 0 ? moved / info.bbox_diagonal : 0.0, "%.6g");
    j["max_sideways_residual_rel"] = json_rounded(info.max_sideways_residual, "%.6g");
    j["mode"] = saved ? "saved" : local_frame ? "local_frame" : "normal";
    j["bind_seconds"] = json_rounded(bind_seconds, "%.4f");
    j["deform_seconds"] = json_rounded(deform_seconds, "%.5f");
    std::printf("%s\n", json_text(j).c_str());
  } else if (!quiet) {
    std::printf("%s bound to %s (%u vertices, %.1f basis entries each, %.2f s); deformed by %s -> %s (%.3f s)\n",
                files[0].c_str(), files[1].c_str(), info.vertex_count, double(info.basis_entries) / info.vertex_count,
                bind_seconds, files[2].c_str(), files[3].c_str(), deform_seconds);
    if (!local_frame && info.vertices_with_sideways_residual > 0)
      std::printf("  normal mode dropped sideways offsets of up to %.3g of the diagonal at %llu vertices "
                  "(--local-frame keeps them)\n",
                  info.max_sideways_residual, (unsigned long long)info.vertices_with_sideways_residual);
  }
  return kExitOk;
}

}  // namespace

Command add_deform(CLI::App& cagekit) {
  CLI::App* app = cagekit.add_subcommand(
      "deform", "rebuild the scan over the edited cage (details kept), bound anew or by a saved binding");
  auto options = std::make_shared<Options>(app);
  options->add_positional("SCAN", "mesh file");
  options->add_positional("CAGE", "cage file, or a binding saved by `cagekit bind` (BINDING.ckb)");
  options->add_positional("EDITED_CAGE", "the cage with moved vertices (same vertices and faces)");
  options->add_positional("OUT", "deformed scan file (.obj .ply .off .drc)");
  options->add(kLocalFrame);
  add_sharp_angle(*options);
  options->add(kJson);
  options->add_quiet();
  return {app, [options] { return command_deform(*options); }};
}

}  // namespace cli
