// SPDX-License-Identifier: GPL-3.0-or-later
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_context.h"
#include "pipeline.h"

namespace cli {

namespace {

const FlagOption kJson{"--json", "print the fit's figures (per pass too) as one JSON object"};

int command_fit(const Options& args) {
  const bool quiet = args.quiet();
  const bool json = args.flag(kJson);
  const cagekit_fit_options options = parse_fit_options(args);
  const std::vector<std::string> files = {args.positional("SCAN"), args.positional("CAGE"), args.positional("OUT")};
  const cagekit_file_format out_format = format_from_extension(files[2]);

  Session session(quiet);
  const cagekit::Mesh scan = session.run(files[0], [&] { return session.context().read_mesh(files[0]); });
  const cagekit::Cage cage = session.run(files[1], [&] { return session.context().read_cage(files[1]); });
  FitResult fit;
  const cagekit::Cage fitted = run_fit(session, cage, scan, options, files[1] + " fitted to " + files[0], &fit);
  cagekit_write_options write = cagekit::defaults<cagekit_write_options>();
  write.format = out_format;
  session.run(files[2], [&] { fitted.write_file(files[2], write); });
  session.finish_progress();

  const cagekit_fit_report& r = fit.report;
  if (json) {
    std::printf("%s\n", json_text(fit_json(fit, options)).c_str());
  } else if (!quiet) {
    std::printf("%s fitted to %s -> %s: %u passes%s, %.2f s\n", files[1].c_str(), files[0].c_str(), files[2].c_str(),
                r.pass_count - 1,
                r.stopped_by_tolerance ? " (converged)" : r.rejected_last_step ? " (stopped: no further decrease)" : "",
                r.seconds);
    std::printf("  pass  rms/diag    max/diag    mean/diag   unconverged\n");
    for (size_t i = 0; i < fit.passes.size(); ++i)
      std::printf("  %4zu  %.4e  %.4e  %.4e  %llu\n", i, fit.passes[i].rms_rel, fit.passes[i].max_rel,
                  fit.passes[i].mean_rel, (unsigned long long)fit.passes[i].unconverged_projections);
  }
  return kExitOk;
}

}  // namespace

Command add_fit(CLI::App& cagekit) {
  CLI::App* app = cagekit.add_subcommand(
      "fit", "fit the cage's limit surface to the scan's vertices (thesis ch. 7)");
  auto options = std::make_shared<Options>(app);
  options->add_positional("SCAN", "mesh file");
  options->add_positional("CAGE", "cage file");
  options->add_positional("OUT", "fitted cage file (.obj .ply .off .drc)");
  add_fit_options(*options);
  options->add(kJson);
  options->add_quiet();
  return {app, [options] { return command_fit(*options); }};
}

}  // namespace cli
