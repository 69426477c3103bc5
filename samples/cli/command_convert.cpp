// SPDX-License-Identifier: GPL-3.0-or-later
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_context.h"

namespace cli {

namespace {

const FlagOption kAscii{"--ascii", "write .ply as ascii (default: binary)"};
const IntegerOption kBits{"--bits", 14, 1, 30, "N", "Draco position quantization bits (.drc)"};
const IntegerOption kSpeed{"--speed", 5, 0, 10, "S", "Draco encoder speed (0: smallest, 10: fastest; .drc)"};

int command_convert(const Options& args) {
  const bool quiet = args.quiet();
  const bool ascii = args.flag(kAscii);
  const int bits = args.integer(kBits);
  const int speed = args.integer(kSpeed);
  const std::vector<std::string> files = {args.positional("IN"), args.positional("OUT")};
  Session session(quiet);
  cagekit_write_options options = cagekit::defaults<cagekit_write_options>();
  options.format = format_from_extension(files[1]);
  options.ply_binary = ascii ? 0 : 1;
  options.draco_position_bits = bits;
  options.draco_speed = speed;

  LoadedInput input;
  load_input(session, files[0], &input);
  cagekit_write_report report;
  cagekit_mesh_info info;
  if (input.cage) {
    report = session.run(files[1], [&] { return input.cage.write_file(files[1], options); });
    info = session.run(files[0], [&] { return input.cage.info(); });
  } else {
    report = session.run(files[1], [&] { return input.mesh.write_file(files[1], options); });
    info = session.run(files[0], [&] { return input.mesh.info(); });
  }
  session.finish_progress();
  if (!quiet) {
    const double relative = info.bbox_diagonal > 0 ? report.max_position_error / info.bbox_diagonal : 0.0;
    std::fprintf(stderr, "cagekit: wrote %s (%llu bytes; max position error %.3g = %.3g of the bbox diagonal)\n",
                 files[1].c_str(), (unsigned long long)report.bytes, report.max_position_error, relative);
  }
  return kExitOk;
}

}  // namespace

Command add_convert(CLI::App& cagekit) {
  CLI::App* app = cagekit.add_subcommand(
      "convert", "convert between .obj .ply .off .drc, also from .stl; cage tags kept in .obj and .drc");
  auto options = std::make_shared<Options>(app);
  options->add_positional("IN", "mesh or cage file (.obj .ply .off .drc .stl)");
  options->add_positional("OUT", "output file (.obj .ply .off .drc)");
  options->add(kBits);
  options->add(kSpeed);
  options->add(kAscii);
  options->add_quiet();
  return {app, [options] { return command_convert(*options); }};
}

}  // namespace cli
