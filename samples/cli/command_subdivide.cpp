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
  const cagekit::Cage cage = session.run(files[0], [&] { return session.context().read_cage(files[0]); });
  cagekit_subdivide_options options = cagekit::defaults<cagekit_subdivide_options>();
  options.levels = static_cast<uint32_t>(levels);
  options.limit_positions = limit ? 1 : 0;
  const cagekit::Cage refined = session.run(files[0], [&] { return cage.subdivide(options); });
  cagekit_write_options write = cagekit::defaults<cagekit_write_options>();
  write.format = out_format;
  session.run(files[1], [&] { refined.write_file(files[1], write); });
  session.finish_progress();
  if (!quiet) {
    uint32_t vertices = 0, faces = 0;
    try {  // only for the summary line: a failure here leaves it at 0
      const cagekit::MeshCounts counts = refined.mesh().counts();
      vertices = counts.vertices;
      faces = counts.faces;
    } catch (const cagekit::Error&) {
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
