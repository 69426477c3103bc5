// SPDX-License-Identifier: GPL-3.0-or-later
// cagekit fit SCAN CAGE OUT [--passes N] [--tolerance T] [--projection exact|linear] [--fairing F]
//             [--keep-creases] [--threads N] [--json] [--quiet]
// cagekit pipeline SCAN OUTDIR [--method simplify] (--faces N | --vertices N) [--passes N] ...
// cagekit pipeline SCAN OUTDIR --method anisotropic [--tolerance REL] [--fit-tolerance T] [--passes N] ...
// cagekit pipeline SCAN OUTDIR --method quad [--edge-length REL] [--regions N] [--weights TRI,PENT,TJOINT] [--refinement-passes N]
//                  [--fit-tolerance T] [--passes N] ...
#include <cstdio>
#include <string>

#include "cli_context.h"
#include "pipeline.h"

namespace cli {

int command_fit(Args& args) {
  const char* usage =
      "cagekit fit SCAN CAGE OUT [--passes N] [--tolerance T] [--projection exact|linear] [--fairing F] "
      "[--crease-feature-reach REL] [--keep-creases] [--threads N] [--json] [--quiet]";
  const bool quiet = args.flag("--quiet");
  const bool json = args.flag("--json");
  const cagekit_fit_options options = parse_fit_options(args);
  const auto files = args.positional(3, 3, usage);
  const cagekit_file_format out_format = format_from_extension(files[2]);

  Session session(quiet);
  Mesh scan;
  session.check(cagekit_mesh_read_file(session.context(), files[0].c_str(), CAGEKIT_FORMAT_AUTO, scan.out()), files[0]);
  Cage cage;
  session.check(cagekit_cage_read_file(session.context(), files[1].c_str(), CAGEKIT_FORMAT_AUTO, cage.out()), files[1]);
  Cage fitted;
  FitResult fit;
  run_fit(session, cage.get(), scan.get(), options, files[1] + " fitted to " + files[0], &fitted, &fit);
  cagekit_write_options write = CAGEKIT_WRITE_OPTIONS_INIT;
  write.format = out_format;
  session.check(cagekit_cage_write_file(fitted.get(), files[2].c_str(), &write, nullptr), files[2]);
  session.finish_progress();

  const cagekit_fit_report& r = fit.report;
  if (json) {
    std::printf("%s\n", fit_json(fit, options).c_str());
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

}  // namespace cli
