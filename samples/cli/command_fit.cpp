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
      "[--keep-creases] [--threads N] [--json] [--quiet]";
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

int command_pipeline(Args& args) {
  const char* usage =
      "cagekit pipeline SCAN OUTDIR ([--method simplify] (--faces N | --vertices N) [--crease-angle DEG] [--input-crease-angle DEG] "
      "| --method anisotropic [--tolerance REL] [--feature-angle DEG] [--max-face-valence N] [--fit-tolerance T] "
      "| --method quad [--edge-length REL] [--regions N] [--weights TRI,PENT,TJOINT] [--refinement-passes N] [--feature-angle DEG] "
      "[--fit-tolerance T]) "
      "[--passes N] [--tolerance T] [--projection exact|linear] [--fairing F] [--keep-creases] [--threads N] "
      "[--limit-levels L] [--json] [--quiet]";
  const bool quiet = args.flag("--quiet");
  const bool json = args.flag("--json");
  PipelineSettings settings;
  std::string method;
  int faces = -1, vertices = -1, limit_levels = 3;
  double fit_tolerance = -1.0;
  try {
    method = args.option("--method", "simplify");
    const bool remesh = method == "anisotropic" || method == "quad";
    if (remesh) {  // anisotropic: --tolerance is the remeshing tolerance; the fit's is --fit-tolerance
      settings.remesh = parse_remesh_options(args, method);
      fit_tolerance = args.real("--fit-tolerance", 1e-4, 0.0, 1.0);
    }
    faces = args.integer("--faces", -1, 1, 2000000000);
    vertices = args.integer("--vertices", -1, 1, 2000000000);
    settings.crease_angle = args.real("--crease-angle", 30.0, -1.0, 180.0);
    settings.input_crease_angle = args.real("--input-crease-angle", -1.0, -1.0, 180.0);
    limit_levels = args.integer("--limit-levels", 3, 0, 5);
  } catch (const Failure& f) {  // option values are input of this command: exit code 2
    throw Failure(f.code == kExitUsage ? kExitBadInput : f.code, f.what());
  }
  if (method != "simplify" && method != "anisotropic" && method != "quad")
    throw Failure(kExitBadInput, "--method must be 'simplify', 'anisotropic' or 'quad', not '" + method + "'");
  settings.method = method;
  settings.fit = parse_fit_options(args);
  if (fit_tolerance >= 0.0) settings.fit.tolerance = fit_tolerance;
  const auto files = args.positional(2, 2, usage);
  if (method != "simplify" ? (faces > 0 || vertices > 0) : ((faces < 0) == (vertices < 0)))
    throw Failure(kExitUsage, std::string("usage: ") + usage);
  settings.query = faces > 0 ? CAGEKIT_LEVEL_BY_FACES : CAGEKIT_LEVEL_BY_VERTICES;  // (unused by remeshing)
  settings.target = faces > 0 ? faces : vertices;
  settings.limit_levels = static_cast<uint32_t>(limit_levels);

  Session session(quiet);
  Mesh scan;
  session.check(cagekit_mesh_read_file(session.context(), files[0].c_str(), CAGEKIT_FORMAT_AUTO, scan.out()), files[0]);
  PipelineResult result;
  run_pipeline(session, scan.get(), files[0], settings, files[1], &result);
  session.finish_progress();

  const cagekit_fit_report& r = result.fit.report;
  if (json) {
    std::fputs(result.json.c_str(), stdout);
  } else if (!quiet) {
    std::printf("%s -> %s/\n", files[0].c_str(), files[1].c_str());
    if (method == "quad") {
      const cagekit_remesh_report& m = result.remesh_report;
      std::printf("  remesh    quad, %llu regions, edge length %g: %llu faces (%llu quads), %llu creases, "
                  "Hausdorff %.3g of the diagonal (%.2f s)\n",
                  (unsigned long long)m.regions, settings.remesh.edge_length, (unsigned long long)m.faces,
                  (unsigned long long)m.quads, (unsigned long long)m.creases, result.level_error.hausdorff_sym_rel,
                  result.simplify_seconds);
    } else if (method == "anisotropic") {
      const cagekit_remesh_report& m = result.remesh_report;
      std::printf("  remesh    anisotropic, tolerance %g: %llu faces (%llu quads), %llu creases, mean alignment %.2f deg, "
                  "Hausdorff %.3g of the diagonal (%.2f s)\n",
                  settings.remesh.tolerance, (unsigned long long)m.faces, (unsigned long long)m.quads,
                  (unsigned long long)m.creases, m.mean_alignment_deg, result.level_error.hausdorff_sym_rel,
                  result.simplify_seconds);
    } else {
    std::printf("  simplify  level %u: %llu polygons -> cage of %llu quads, %llu triangles, %llu other, %llu creases "
                "(%.2f s)\n",
                result.level, (unsigned long long)result.level_info.faces,
                (unsigned long long)result.cage_report.quads, (unsigned long long)result.cage_report.triangles,
                (unsigned long long)(result.cage_report.pentagons + result.cage_report.other_polygons),
                (unsigned long long)result.cage_report.creases, result.simplify_seconds);
    }
    std::printf("  fit       %u passes: max %.3g -> %.3g, rms %.3g -> %.3g of the diagonal (%.2f s)\n", r.pass_count - 1,
                r.initial.max_rel, r.final.max_rel, r.initial.rms_rel, r.final.rms_rel, r.seconds);
    std::printf("  limit     level %u: %llu quads, Hausdorff %.3g of the diagonal from the scan\n",
                settings.limit_levels, (unsigned long long)result.limit_info.quads,
                result.limit_error.hausdorff_sym_rel);
    std::printf("  wrote     cage.obj limit.obj report.json (%.2f s)\n", result.seconds);
  }
  return kExitOk;
}

}  // namespace cli
