// SPDX-License-Identifier: GPL-3.0-or-later
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_context.h"

namespace cli {

namespace {

const FlagOption kLimit{"--limit", "put the refined vertices on the limit surface"};
const IntegerOption kLevels{"--levels", -1, 0, CAGEKIT_MAX_SUBDIVISION_LEVELS, "N", "refinement levels (required)"};

int command_subdivide(const Options& args) {
  const bool quiet = args.quiet();
  const bool limit = args.flag(kLimit);
  const int levels = args.integer(kLevels);
  const std::vector<std::string> files = {args.positional("IN"), args.positional("OUT")};
  if (levels < 0) throw Failure(kExitUsage, "subdivide needs --levels N");

  Session session(quiet);
  const cagekit_file_format out_format = format_from_extension(files[1]);
  Cage cage;
  session.check(cagekit_cage_read_file(session.context(), files[0].c_str(), CAGEKIT_FORMAT_AUTO, cage.out()), files[0]);
  cagekit_subdivide_options options = CAGEKIT_SUBDIVIDE_OPTIONS_INIT;
  options.levels = static_cast<uint32_t>(levels);
  options.limit_positions = limit ? 1 : 0;
  Cage refined;
  session.check(cagekit_cage_subdivide(cage.get(), &options, refined.out()), files[0]);
  cagekit_write_options write = CAGEKIT_WRITE_OPTIONS_INIT;
  write.format = out_format;
  session.check(cagekit_cage_write_file(refined.get(), files[1].c_str(), &write, nullptr), files[1]);
  session.finish_progress();
  if (!quiet) {
    uint32_t vertices = 0, faces = 0;
    cagekit_mesh m = nullptr;
    if (cagekit_cage_get_mesh(refined.get(), &m) == CAGEKIT_SUCCESS) {
      cagekit_mesh_get_counts(m, &vertices, &faces, nullptr);
      cagekit_mesh_release(m);
    }
    std::fprintf(stderr, "cagekit: wrote %s (level %d: %u vertices, %u faces)\n", files[1].c_str(), levels, vertices,
                 faces);
  }
  return kExitOk;
}

}  // namespace

Command add_subdivide(CLI::App& cagekit) {
  CLI::App* app = cagekit.add_subcommand("subdivide", "uniform Catmull-Clark refinement with creases");
  auto options = std::make_shared<Options>(app);
  options->add_positional("IN", "cage file");
  options->add_positional("OUT", "output file (.obj .ply .off .drc)");
  options->add(kLevels);
  options->add(kLimit);
  options->add_quiet();
  return {app, [options] { return command_subdivide(*options); }};
}

}  // namespace cli
