// SPDX-License-Identifier: GPL-3.0-or-later
// cagekit convert IN OUT [--bits N] [--speed S] [--ascii]
#include <cstdio>
#include <string>

#include "cli_context.h"

namespace cli {

int command_convert(Args& args) {
  const bool quiet = args.flag("--quiet");
  const bool ascii = args.flag("--ascii");
  const int bits = args.integer("--bits", 14, 1, 30);
  const int speed = args.integer("--speed", 5, 0, 10);
  const auto files = args.positional(2, 2, "cagekit convert IN OUT [--bits N] [--speed S] [--ascii] [--quiet]");
  Session session(quiet);
  cagekit_write_options options = CAGEKIT_WRITE_OPTIONS_INIT;
  options.format = format_from_extension(files[1]);
  options.ply_binary = ascii ? 0 : 1;
  options.draco_position_bits = bits;
  options.draco_speed = speed;

  LoadedInput input;
  load_input(session, files[0], &input);
  cagekit_write_report report = {};
  report.struct_size = sizeof(report);
  cagekit_mesh_info info = {};
  info.struct_size = sizeof(info);
  if (input.cage.get()) {
    session.check(cagekit_cage_write_file(input.cage.get(), files[1].c_str(), &options, &report), files[1]);
    session.check(cagekit_cage_get_info(input.cage.get(), &info), files[0]);
  } else {
    session.check(cagekit_mesh_write_file(input.mesh.get(), files[1].c_str(), &options, &report), files[1]);
    session.check(cagekit_mesh_get_info(input.mesh.get(), &info), files[0]);
  }
  session.finish_progress();
  if (!quiet) {
    const double relative = info.bbox_diagonal > 0 ? report.max_position_error / info.bbox_diagonal : 0.0;
    std::fprintf(stderr, "cagekit: wrote %s (%llu bytes; max position error %.3g = %.3g of the bbox diagonal)\n",
                 files[1].c_str(), (unsigned long long)report.bytes, report.max_position_error, relative);
  }
  return kExitOk;
}

}  // namespace cli
