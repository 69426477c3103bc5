// SPDX-License-Identifier: GPL-3.0-or-later
// cagekit demo: runs what the SDK can do today on a generated noisy scan of a CAD-like
// part and writes every result to OUTDIR (default ./cagekit-demo): exchange formats, the pipeline
// of `cagekit pipeline` (simplification -> creased cage -> fit, pipeline.h), subdivision, and
// overview.png (the render module; skipped with a note where it cannot draw).
// Multiresolution editing (thesis ch. 8) extends this when it lands.
#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli_context.h"
#include "demo_part.h"
#include "pipeline.h"

namespace cli {

namespace {

// scan | cage over its limit with creases | error map, one iso view, 960 x 400.
void write_overview(const cagekit::Context& context, const cagekit::Mesh& scan, const cagekit::Cage& cage,
                    const std::string& path) {
  cagekit::RenderScene scene = context.create_render_scene();
  cagekit_render_options options = cagekit::defaults<cagekit_render_options>();
  options.width = 960;
  options.height = 400;
  scene.set_options(options);
  cagekit_render_item_options item = cagekit::defaults<cagekit_render_item_options>();
  item.title = "scan";
  scene.add_mesh(scan, CAGEKIT_RENDER_ITEM_MESH, item);
  item.title = "cage over its limit";
  item.wireframe = 1;
  item.creases = 1;
  scene.add_cage(cage, item);
  item.title = "error map";
  item.wireframe = 0;
  item.creases = 0;
  const uint32_t error_map = scene.add_cage(cage, item);
  scene.set_distance_to_scan(error_map, scan);
  scene.write_png(path);
}

int command_demo(const Options& args) {
  const std::string dir = args.given("OUTDIR") ? args.positional("OUTDIR") : "cagekit-demo";
  make_directories(dir);
  Session session(args.quiet());
  const auto start = std::chrono::steady_clock::now();

  // 1. The input: a noisy scan of a 4 x 2.5 x 1.5 block, ~60 cells per unit.
  const double size[3] = {4.0, 2.5, 1.5};
  const double diagonal = std::sqrt(size[0] * size[0] + size[1] * size[1] + size[2] * size[2]);
  const DemoPart part = make_demo_part(size, 24, 2e-4 * diagonal, 20061113u);
  const cagekit::Context& context = session.context();
  const cagekit::Mesh scan = session.run("demo scan", [&] { return context.create_mesh(part.positions, part.triangles); });
  const cagekit_validation_report validation = session.run("demo scan", [&] {
    const cagekit_validation_report report = scan.validate();
    if (!report.valid) scan.require_valid();  // an invalid scan is an error (its problems named)
    return report;
  });

  // 2. Exchange: OBJ, binary PLY, Draco at 14 bits.
  const cagekit_write_options write = cagekit::defaults<cagekit_write_options>();
  const cagekit_write_report obj_report = session.run("scan.obj", [&] { return scan.write_file(dir + "/scan.obj", write); });
  session.run("scan.ply", [&] { scan.write_file(dir + "/scan.ply", write); });
  const cagekit_write_report drc_report = session.run("scan.drc", [&] { return scan.write_file(dir + "/scan.drc", write); });

  // 3. The pipeline (pipeline.h): structure-preserving simplification (thesis ch. 3) to the level
  //    of 6 polygons (the block's sides), partitioned into a quad-dominant cage whose edges on
  //    sharp cluster borders are tagged as creases; then the cage's limit surface fitted to the
  //    scan (ch. 7) and refined to level 3 on its limit.
  PipelineSettings settings;
  settings.query = CAGEKIT_LEVEL_BY_FACES;
  settings.target = 6;
  settings.fit.max_passes = 5;
  settings.cage_file = "cage_fitted.obj";
  settings.limit_file = "cage_fitted_limit.obj";
  settings.report_file = "pipeline.json";
  PipelineResult pipeline;
  run_pipeline(session, scan, "demo scan", settings, dir, &pipeline);
  const uint32_t level = pipeline.level, level_count = pipeline.level_count;
  const cagekit_cage_report& cage_report = pipeline.cage_report;
  const double simplify_seconds = pipeline.simplify_seconds;
  const cagekit_fit_report& fit = pipeline.fit.report;
  const cagekit::Cage& cage = pipeline.initial_cage;
  session.run("cage.obj", [&] { cage.write_file(dir + "/cage.obj", write); });
  session.run("cage.drc", [&] { cage.write_file(dir + "/cage.drc", write); });
  session.run("polygons.obj", [&] { pipeline.polygons.write_file(dir + "/polygons.obj", write); });

  // 4. Subdivision: the creased cage at level 3 (its limit surface is the block), compared with
  //    the scan; and the scan itself used as a cage, level 1 pushed to its limit surface.
  cagekit_subdivide_options subdivide = cagekit::defaults<cagekit_subdivide_options>();
  subdivide.levels = 3;
  subdivide.limit_positions = 1;
  const cagekit::Cage cage_level3 = session.run("cage", [&] { return cage.subdivide(subdivide); });
  session.run("cage_level3.obj", [&] { cage_level3.write_file(dir + "/cage_level3.obj", write); });
  const cagekit::Mesh level3_mesh = session.run("cage level 3", [&] { return cage_level3.mesh(); });
  const cagekit_approximation_error limit_error =
      session.run("cage level 3", [&] { return scan.measure_error(level3_mesh); });
  const cagekit::Cage scan_cage = session.run("demo scan", [&] { return scan.create_cage(); });
  subdivide.levels = 1;
  const auto subdivide_start = std::chrono::steady_clock::now();
  const cagekit::Cage scan_level1 = session.run("demo scan", [&] { return scan_cage.subdivide(subdivide); });
  const double subdivide_seconds = seconds_since(subdivide_start);
  session.run("scan_level1_limit.obj", [&] { scan_level1.write_file(dir + "/scan_level1_limit.obj", write); });

  // 5. The overview picture: scan | fitted cage over its limit surface, creases in magenta-red |
  //    the limit surface coloured by its two-sided distance to the scan. Drawn headless; where
  //    that cannot be done (no EGL, a build without the render module) one line says why and
  //    the demo goes on.
  const auto render_start = std::chrono::steady_clock::now();
  std::string overview_problem;
  try {
    write_overview(context, scan, pipeline.fitted_cage, dir + "/overview.png");
  } catch (const cagekit::Error& error) {
    overview_problem = error.message();
  }
  const double render_seconds = seconds_since(render_start);
  session.finish_progress();

  const cagekit_mesh_info scan_info = session.run("demo scan", [&] { return scan.info(); });
  const cagekit_mesh_info level3_info = session.run("cage_level3", [&] { return cage_level3.info(); });
  const cagekit_mesh_info level1_info = session.run("scan level 1", [&] { return scan_level1.info(); });

  const auto g9 = [](double x) { return json_rounded(x, "%.9g"); };
  const auto g3 = [](double x) { return json_rounded(x, "%.3g"); };
  const auto f3 = [](double x) { return json_rounded(x, "%.3f"); };
  nlohmann::ordered_json summary;
  summary["scan"] = {{"vertices", uint64_t(scan_info.vertices)},
                     {"triangles", uint64_t(scan_info.triangles)},
                     {"genus", int64_t(scan_info.genus)},
                     {"manifold", bool(scan_info.manifold)},
                     {"valid", bool(validation.valid)},
                     {"bbox_diagonal", g9(scan_info.bbox_diagonal)}};
  summary["exchange"] = {
      {"obj_bytes", uint64_t(obj_report.bytes)},
      {"drc_bytes", uint64_t(drc_report.bytes)},
      {"drc_ratio",
       json_rounded(drc_report.bytes ? double(obj_report.bytes) / double(drc_report.bytes) : 0.0, "%.2f")},
      {"drc_max_error_rel", g3(drc_report.max_position_error / scan_info.bbox_diagonal)}};
  summary["simplification"] = {{"levels", level_count}, {"level", level}, {"seconds", f3(simplify_seconds)}};
  summary["cage"] = {{"quads", uint64_t(cage_report.quads)},
                     {"triangles", uint64_t(cage_report.triangles)},
                     {"pentagons", uint64_t(cage_report.pentagons)},
                     {"creases", uint64_t(cage_report.creases)},
                     {"level3_quads", uint64_t(level3_info.quads)},
                     {"level3_creases", uint64_t(level3_info.creases)},
                     {"level3_limit_hausdorff_rel", g3(limit_error.hausdorff_sym_rel)}};
  summary["scan_as_cage_level1"] = {{"quads", uint64_t(level1_info.quads)}, {"seconds", f3(subdivide_seconds)}};
  summary["fit"] = fit_json(pipeline.fit, settings.fit);
  summary["fitted_limit"] = {{"levels", settings.limit_levels},
                             {"quads", uint64_t(pipeline.limit_info.quads)},
                             {"hausdorff_sym_rel", g3(pipeline.limit_error.hausdorff_sym_rel)}};
  summary["overview"] = overview_problem.empty() ? nlohmann::ordered_json("overview.png") : nlohmann::ordered_json();
  summary["render_seconds"] = f3(render_seconds);
  summary["seconds"] = f3(seconds_since(start));
  summary["not_yet"] = nlohmann::ordered_json::array({"multiresolution editing (ch. 8)"});
  write_text_file(dir + "/summary.json", json_text(summary, ",\n ") + "\n");

  std::printf("CageKit demo -> %s/\n", dir.c_str());
  std::printf("  scan.obj/.ply/.drc     noisy scan of a block: %llu vertices, %llu triangles, genus %lld, %s\n",
              (unsigned long long)scan_info.vertices, (unsigned long long)scan_info.triangles,
              (long long)scan_info.genus, validation.valid ? "valid" : "INVALID");
  std::printf("  Draco 14 bit           %llu bytes vs OBJ %llu bytes (%.1fx smaller), max error %.2g of the diagonal\n",
              (unsigned long long)drc_report.bytes, (unsigned long long)obj_report.bytes,
              drc_report.bytes ? double(obj_report.bytes) / double(drc_report.bytes) : 0.0,
              drc_report.max_position_error / scan_info.bbox_diagonal);
  std::printf("  polygons.obj           simplified to level %u of %u (6 polygons) in %.2f s\n", level, level_count,
              simplify_seconds);
  std::printf("  cage.obj/.drc          quad-dominant cage: %llu quads, %llu triangles, %llu pentagons, %llu creases\n",
              (unsigned long long)cage_report.quads, (unsigned long long)cage_report.triangles,
              (unsigned long long)cage_report.pentagons, (unsigned long long)cage_report.creases);
  std::printf("  cage_level3.obj        level 3 on the limit: %llu quads, %llu crease edges, %.2g of the diagonal "
              "from the scan\n",
              (unsigned long long)level3_info.quads, (unsigned long long)level3_info.creases,
              limit_error.hausdorff_sym_rel);
  std::printf("  cage_fitted.obj        limit surface fitted to the scan (thesis ch. 7), %u passes in %.2f s:\n"
              "                         max distance %.3g -> %.3g, rms %.3g -> %.3g of the diagonal%s\n",
              fit.pass_count - 1, fit.seconds, fit.initial.max_rel, fit.final.max_rel, fit.initial.rms_rel,
              fit.final.rms_rel, fit.stopped_by_tolerance ? " (converged)" : "");
  std::printf("  cage_fitted_limit.obj  fitted cage, level %u on the limit: %llu quads, %.2g of the diagonal from the "
              "scan\n",
              settings.limit_levels, (unsigned long long)pipeline.limit_info.quads,
              pipeline.limit_error.hausdorff_sym_rel);
  std::printf("  scan_level1_limit.obj  scan as cage, level 1 on the limit: %llu quads in %.3f s\n",
              (unsigned long long)level1_info.quads, subdivide_seconds);
  if (overview_problem.empty())
    std::printf("  overview.png           scan | fitted cage over its limit, creases | distance to the scan (%.2f s)\n",
                render_seconds);
  else
    std::printf("  overview.png           not written: %s\n", overview_problem.c_str());
  std::printf("  summary.json           these numbers (pipeline.json: the pipeline's report)\n");
  return kExitOk;
}

}  // namespace

Command add_demo(CLI::App& cagekit) {
  CLI::App* app = cagekit.add_subcommand(
      "demo", "run the pipeline on a generated noisy scan of a CAD-like part and write every result");
  auto options = std::make_shared<Options>(app);
  options->add_positional("OUTDIR", "output folder (default: ./cagekit-demo)", false);
  options->add_quiet();
  return {app, [options] { return command_demo(*options); }};
}

}  // namespace cli
