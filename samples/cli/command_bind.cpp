// SPDX-License-Identifier: GPL-3.0-or-later
// Binds the scan to the cage's limit surface (thesis §8.3) once and saves the binding with its
// cage (cagekit_binding_write_file); `cagekit deform SCAN OUT.ckb EDITED_CAGE OUT` then skips the
// binding step.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli_context.h"

namespace cli {

namespace {

const TextOption kSharpAngle{"--sharp-angle", "", "DEG",
                             "one vertex per smooth sector at edges sharper than DEG (0..180), each with its own "
                             "normal (default: off)"};
const FlagOption kJson{"--json", "print the binding's figures as one JSON object"};
const FlagOption kLocalFrame{"--local-frame", "keep the details' sideways offsets (local-frame displacements; "
                                              "default: along the normal)"};
const FlagOption kExactNormals{"--exact-normals", "exact limit normals (default: approximate)"};
const TextOption kThreads{"--threads", "0", "N", "worker threads (0..1024; 0: all cores)"};

}  // namespace

void add_sharp_angle(Options& options) { options.add(kSharpAngle); }

double parse_sharp_angle(const Options& args) {
  const std::string text = args.text(kSharpAngle);
  if (text.empty()) return -1.0;
  char* end = nullptr;
  const double angle = std::strtod(text.c_str(), &end);
  if (*end != '\0' || !(angle >= 0 && angle <= 180))
    throw Failure(kExitBadInput, "--sharp-angle must be a number of degrees in [0, 180], got '" + text + "'");
  return angle;
}

namespace {

int command_bind(const Options& args) {
  const bool quiet = args.quiet();
  const bool json = args.flag(kJson);
  const bool local_frame = args.flag(kLocalFrame);
  const bool exact = args.flag(kExactNormals);
  const double sharp_angle = parse_sharp_angle(args);
  const std::string threads_text = args.text(kThreads);
  const std::vector<std::string> files = {args.positional("SCAN"), args.positional("CAGE"),
                                          args.positional("OUT.ckb")};
  char* end = nullptr;
  const long threads = std::strtol(threads_text.c_str(), &end, 10);
  if (threads_text.empty() || *end != '\0' || threads < 0 || threads > 1024)
    throw Failure(kExitBadInput, "--threads must be an integer in [0, 1024], got '" + threads_text + "'");

  Session session(quiet);
  const cagekit::Mesh scan = session.run(files[0], [&] { return session.context().read_mesh(files[0]); });
  const cagekit::Cage cage = session.run(files[1], [&] { return session.context().read_cage(files[1]); });
  const auto t0 = std::chrono::steady_clock::now();
  cagekit_bind_options options = cagekit::defaults<cagekit_bind_options>();
  options.mode = local_frame ? CAGEKIT_DISPLACEMENT_LOCAL_FRAME : CAGEKIT_DISPLACEMENT_NORMAL;
  options.exact_normals = exact ? 1 : 0;
  options.threads = uint32_t(threads);
  options.sharp_angle_degrees = sharp_angle;
  const cagekit::Binding binding =
      session.run(files[0] + " bound to " + files[1], [&] { return cage.bind(scan, options); });
  const double bind_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  session.run(files[2], [&] { binding.write_file(files[2]); });
  session.finish_progress();
  const cagekit_binding_info info = session.run("binding", [&] { return binding.info(); });
  long long bytes = -1;
  if (FILE* f = std::fopen(files[2].c_str(), "rb")) {
    std::fseek(f, 0, SEEK_END);
    bytes = std::ftell(f);
    std::fclose(f);
  }
  if (json) {
    nlohmann::ordered_json j;
    j["vertices"] = info.vertex_count;
    j["scan_vertices"] = info.scan_vertex_count;
    j["control_points"] = info.control_count;
    j["mode"] = local_frame ? "local_frame" : "normal";
    j["exact_normals"] = exact;
    j["max_sideways_residual_rel"] = json_rounded(info.max_sideways_residual, "%.6g");
    j["bytes"] = int64_t(bytes);
    j["bind_seconds"] = json_rounded(bind_seconds, "%.4f");
    std::printf("%s\n", json_text(j).c_str());
  } else if (!quiet) {
    std::printf("%s bound to %s (%u vertices, %.2f s) -> %s (%lld bytes)\n", files[0].c_str(), files[1].c_str(),
                info.vertex_count, bind_seconds, files[2].c_str(), bytes);
  }
  return kExitOk;
}

}  // namespace

Command add_bind(CLI::App& cagekit) {
  CLI::App* app = cagekit.add_subcommand(
      "bind", "bind the scan to the cage's limit surface (thesis ch. 8) and save the binding");
  auto options = std::make_shared<Options>(app);
  options->add_positional("SCAN", "mesh file");
  options->add_positional("CAGE", "cage file");
  options->add_positional("OUT.ckb", "binding file (for `cagekit deform`)");
  options->add(kLocalFrame);
  options->add(kExactNormals);
  add_sharp_angle(*options);
  options->add(kThreads);
  options->add(kJson);
  options->add_quiet();
  return {app, [options] { return command_bind(*options); }};
}

}  // namespace cli
