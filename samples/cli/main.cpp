// SPDX-License-Identifier: GPL-3.0-or-later
// cagekit — command-line front end of the CageKit SDK. The commands and their options are
// declared in CLI11 (add_* in command_*.cpp), which parses the command line and writes the usage
// (`cagekit --help`, `cagekit COMMAND --help`) from them.
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_context.h"

namespace {

const char* kExitCodes =
    "Exit codes: 0 ok; 2 bad input (one line on stderr names the file and the problem; for fit, pipeline,\n"
    "remesh, bench-deform, bind, deform --sharp-angle and simplify's crease options also option values out\n"
    "of range or unknown); 64 usage (one line and a hint to --help).\n";

void print_help(FILE* out, const std::string& help) {
  std::fputs(help.c_str(), out);
  if (!help.empty() && help.back() != '\n') std::fputc('\n', out);
}

// "cagekit" or "cagekit COMMAND", for the hint after a usage error.
std::string parsed_command(const CLI::App& app) {
  const std::vector<CLI::App*> selected = app.get_subcommands();
  return selected.empty() ? std::string("cagekit") : "cagekit " + selected.front()->get_name();
}

int usage_error(const CLI::App& app, const std::string& message) {
  std::fprintf(stderr, "cagekit: %s\nRun '%s --help' for the usage.\n", message.c_str(), parsed_command(app).c_str());
  return cli::kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("cagekit: Catmull-Clark cages with creases from triangle meshes (CageKit SDK)", "cagekit");
  app.footer(kExitCodes);  // copied into every subcommand's help (set before they are added)
  app.get_formatter()->column_width(36);
  app.require_subcommand(1);
  std::vector<cli::Command> commands = {
      cli::add_info(app),   cli::add_convert(app),  cli::add_subdivide(app), cli::add_simplify(app),
      cli::add_remesh(app), cli::add_fit(app),      cli::add_pipeline(app),  cli::add_batch(app), cli::add_bind(app),
      cli::add_deform(app), cli::add_bench_deform(app), cli::add_render(app), cli::add_demo(app),
      cli::add_export_surfaces(app)};
  CLI::App* version = app.add_subcommand("version", "print the library version");
  commands.push_back({version, [] {
                        std::printf("cagekit %s (ABI %u)\n", cagekit::version_string(), cagekit::abi_version());
                        return cli::kExitOk;
                      }});

  if (argc < 2) {
    print_help(stderr, app.help());
    return cli::kExitUsage;
  }
  if (argv[1][0] != '-') {
    try {
      app.get_subcommand(argv[1]);
    } catch (const CLI::OptionNotFound&) {
      return usage_error(app, std::string("unknown command '") + argv[1] + "'");
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    print_help(stdout, app.help());
    return cli::kExitOk;
  } catch (const CLI::CallForAllHelp&) {
    print_help(stdout, app.help("", CLI::AppFormatMode::All));
    return cli::kExitOk;
  } catch (const CLI::ParseError& e) {
    return usage_error(app, e.what());
  }

  try {
    for (const cli::Command& command : commands)
      if (command.app->parsed()) return command.run();
    return usage_error(app, "no command");
  } catch (const cli::Failure& f) {
    if (f.code == cli::kExitUsage) return usage_error(app, f.what());
    std::fprintf(stderr, "cagekit: %s\n", f.what());
    return f.code;
  } catch (const std::bad_alloc&) {
    // Allocation failures outside the C API (which reports them as OUT_OF_MEMORY itself).
    std::fprintf(stderr, "cagekit: out of memory\n");
    return cli::kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cagekit: %s\n", e.what());
    return 1;
  }
}
