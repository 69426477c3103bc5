// SPDX-License-Identifier: GPL-3.0-or-later
// cagekit pipeline SCAN OUTDIR ...: the whole journey through cagekit_scan_to_cage
// (conditioning -> simplify / quad / anisotropic -> fit -> judged report); writes OUTDIR/cage.obj
// (fitted, with crease tags), OUTDIR/limit.obj (its limit, L levels) and OUTDIR/report.json.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_context.h"
#include "pipeline.h"

namespace cli {

namespace {

const char* method_name(cagekit_scan_method m) {
  switch (m) {
    case CAGEKIT_SCAN_SIMPLIFY: return "simplify";
    case CAGEKIT_SCAN_QUAD: return "quad";
    case CAGEKIT_SCAN_ANISOTROPIC: return "anisotropic";
    default: return "unknown";
  }
}

nlohmann::ordered_json conditioning_json(const cagekit_scan_to_cage_report& r) {
  nlohmann::ordered_json j;
  j["input_vertices"] = uint64_t(r.input_vertices);
  j["input_faces"] = uint64_t(r.input_faces);
  j["vertices"] = uint64_t(r.conditioned_vertices);
  j["faces"] = uint64_t(r.conditioned_faces);
  j["welded_vertices"] = uint64_t(r.welded_vertices);
  j["dropped_degenerate_faces"] = uint64_t(r.dropped_degenerate_faces);
  j["dropped_duplicate_faces"] = uint64_t(r.dropped_duplicate_faces);
  j["split_vertices"] = uint64_t(r.split_vertices);
  j["flipped_faces"] = uint64_t(r.flipped_faces);
  j["non_orientable_components"] = uint64_t(r.non_orientable_components);
  j["removed_unreferenced_vertices"] = uint64_t(r.removed_unreferenced_vertices);
  j["components"] = uint64_t(r.components);
  j["dropped_components"] = uint64_t(r.dropped_components);
  j["dropped_component_faces"] = uint64_t(r.dropped_component_faces);
  return j;
}

double percent(uint64_t part, uint64_t whole) { return whole ? 100.0 * double(part) / double(whole) : 0.0; }

const FlagOption kJson{"--json", "print report.json on stdout"};
const FlagOption kNoRepair{"--no-repair", "no conditioning: an invalid scan is an error"};
const FlagOption kNoFallback{"--no-fallback", "quad, anisotropic: no fallback to simplify when the result is not good"};
const TextOption kMethod{"--method", "simplify", "simplify|anisotropic|quad",
                         "step 1: structure-preserving simplification to a creased cage (thesis ch. 3), or "
                         "remeshing as by `cagekit remesh` (ch. 5, ch. 6)"};
const RealOption kFitTolerance{"--fit-tolerance", 1e-4, 0.0, 1.0, "T",
                               "anisotropic, quad: the fit's tolerance (as --tolerance of `cagekit fit`)"};
const IntegerOption kFaces{"--faces", -1, 1, 2000000000, "N",
                           "simplify: the level with N polygons (this or --vertices); quad, anisotropic: the "
                           "fallback's target"};
const IntegerOption kVertices{"--vertices", -1, 1, 2000000000, "N",
                              "simplify: the level with N vertices (this or --faces)"};
const IntegerOption kLimitLevels{"--limit-levels", 3, 1, 5, "L", "limit.obj: the fitted cage refined L levels onto its limit"};
const TextOption kComponents{"--components", "all", "all|largest", "conditioning: keep all components or the largest"};
const RealOption kWeldTolerance{"--weld-tolerance", 1e-7, 0.0, 0.1, "REL",
                                "conditioning: weld vertices closer than REL x the bbox diagonal"};
const RealOption kTwoSidedRefit{"--two-sided-refit", 3.0, 0.0, 100.0, "FACTOR",
                                "last phase: the good cage fitted again by two-sided least squares (limit points "
                                "farther than FACTOR x the scan's RMS pulled to the scan), kept when it is better "
                                "(0: not tried)"};

int command_pipeline(const Options& args) {
  const bool quiet = args.quiet();
  const bool json = args.flag(kJson);
  const bool no_repair = args.flag(kNoRepair);
  const bool no_fallback = args.flag(kNoFallback);
  std::string method, components;
  int faces = -1, vertices = -1, limit_levels = 3;
  double fit_tolerance = -1.0, weld = 1e-7, two_sided_refit = 3.0;
  cagekit_cage_options cage = CAGEKIT_CAGE_OPTIONS_INIT;
  RemeshSettings remesh;
  const bool remeshing = args.text(kMethod) == "anisotropic" || args.text(kMethod) == "quad";
  try {
    method = args.text(kMethod);
    if (remeshing) {  // anisotropic: --tolerance is the remeshing tolerance; the fit's is --fit-tolerance
      remesh = parse_remesh_options(args, method);
      fit_tolerance = args.real(kFitTolerance);
    }
    faces = args.integer(kFaces);
    vertices = args.integer(kVertices);
    if (!remeshing) cage = parse_cage_options(args);  // the remeshers read --feature-angle themselves
    limit_levels = args.integer(kLimitLevels);
    components = args.text(kComponents);
    weld = args.real(kWeldTolerance);
    two_sided_refit = args.real(kTwoSidedRefit);
  } catch (const Failure& f) {  // option values are input of this command: exit code 2
    throw Failure(f.code == kExitUsage ? kExitBadInput : f.code, f.what());
  }
  if (method != "simplify" && method != "anisotropic" && method != "quad")
    throw Failure(kExitBadInput, "--method must be 'simplify', 'anisotropic' or 'quad', not '" + method + "'");
  if (components != "all" && components != "largest")
    throw Failure(kExitBadInput, "--components must be 'all' or 'largest', not '" + components + "'");
  cagekit_fit_options fit = parse_fit_options(args);
  if (fit_tolerance >= 0.0) fit.tolerance = fit_tolerance;
  // The options of the other methods, given, are usage errors.
  if (remeshing) {
    refuse_other_remesh_options(args, remesh);
    args.refuse({"--creases", "--crease-angle", "--input-crease-angle"}, "with --method " + method);
  } else {
    args.refuse({"--max-face-valence", "--curvature-radius", "--edge-length", "--regions", "--region-tolerance",
                 "--weights", "--refinement-passes", kFitTolerance.name},
                "with --method simplify");
  }
  const std::vector<std::string> files = {args.positional("SCAN"), args.positional("OUTDIR")};
  // simplify needs exactly one target; the remeshers take an optional --faces (the fallback's).
  if (method == "simplify" ? ((faces < 0) == (vertices < 0)) : vertices > 0)
    throw Failure(kExitUsage, method == "simplify" ? "pipeline --method simplify needs one of --faces N or --vertices N"
                                                   : "--vertices does not apply with --method " + method);

  cagekit_scan_to_cage_options options = CAGEKIT_SCAN_TO_CAGE_OPTIONS_INIT;
  options.method = method == "quad" ? CAGEKIT_SCAN_QUAD
                   : method == "anisotropic" ? CAGEKIT_SCAN_ANISOTROPIC
                                             : CAGEKIT_SCAN_SIMPLIFY;
  options.repair = no_repair ? 0 : 1;
  options.components = components == "largest" ? CAGEKIT_COMPONENTS_LARGEST : CAGEKIT_COMPONENTS_ALL;
  options.weld_tolerance_rel = weld;
  options.target_query = vertices > 0 ? CAGEKIT_LEVEL_BY_VERTICES : CAGEKIT_LEVEL_BY_FACES;
  if (faces > 0 || vertices > 0) options.target = faces > 0 ? faces : vertices;
  options.cage = &cage;
  options.quad = &remesh.quad_options;
  options.anisotropic = &remesh.anisotropic;
  options.fit = &fit;
  options.limit_levels = static_cast<uint32_t>(limit_levels);
  options.two_sided_refit_factor = two_sided_refit;
  options.fallback_to_simplify = no_fallback ? 0 : 1;

  Session session(quiet);
  const cagekit::Mesh scan = session.run(files[0], [&] { return session.context().read_mesh(files[0]); });
  make_directories(files[1]);
  cagekit::Cage::ScanToCage journey = session.run(files[0], [&] { return cagekit::scan_to_cage(scan, options); });
  const cagekit_scan_to_cage_report& r = journey.report;
  FitResult fit_result;
  fit_result.report = journey.fit_report;
  fit_result.passes = std::move(journey.fit_passes);
  const cagekit_write_options write = cagekit::defaults<cagekit_write_options>();
  const std::string cage_path = files[1] + "/cage.obj", limit_path = files[1] + "/limit.obj";
  session.run(cage_path, [&] { journey.cage.write_file(cage_path, write); });
  session.run(limit_path, [&] { journey.limit.write_file(limit_path, write); });
  session.finish_progress();

  // report.json: the method's section under its name ("simplify" or "remesh"), then fit, limit,
  // the conditioning and the quality figures the good-result rule used.
  const std::string used = method_name(r.used_method);
  cagekit_approximation_error method_error = {sizeof(cagekit_approximation_error), r.method_scan_to_cage_max_rel,
                                              std::max(r.method_scan_to_cage_max_rel, r.method_cage_to_scan_max_rel),
                                              r.method_mean_rel};
  nlohmann::ordered_json j;
  j["method"] = method;
  j["used_method"] = used;
  j["fallback"] = bool(r.fallback);
  j["fallback_reason"] = std::string(r.fallback_reason);
  j["input_is_cage"] = bool(r.input_is_cage);
  if (r.used_method == CAGEKIT_SCAN_SIMPLIFY) {
    nlohmann::ordered_json& s = j["simplify"];
    s["method"] = "simplify";
    s["level"] = r.level;
    s["levels"] = r.level_count;
    s["target"] = json_number(r.simplify_target_used);
    s["polygons"] = uint64_t(r.level_faces);
    s["faces_with_holes"] = uint64_t(r.level_faces_with_holes);
    s["cage_faces"] = uint64_t(r.cage_faces);
    s["quads"] = uint64_t(r.cage_quads);
    s["triangles"] = uint64_t(r.cage_triangles);
    s["creases"] = uint64_t(r.creases);
    s["error"] = {{"hausdorff_rel", json_number(method_error.hausdorff_rel)},
                  {"hausdorff_sym_rel", json_number(method_error.hausdorff_sym_rel)},
                  {"mean_rel", json_number(method_error.mean_rel)}};
    s["seconds"] = json_number(r.method_seconds);
  } else {
    RemeshFigures rr;
    rr.quality.faces = r.cage_faces;
    rr.quality.vertices = r.cage_vertices;
    rr.quality.quads = r.cage_quads;
    rr.quality.interior_vertices = r.interior_vertices;
    rr.quality.valence4_vertices = r.valence4_vertices;
    rr.quality.max_face_valence = r.max_face_valence;
    rr.quality.max_vertex_valence = r.max_vertex_valence;
    rr.quality.creases = r.creases;
    rr.regions = r.remesh_regions;
    if (r.used_method == CAGEKIT_SCAN_QUAD) rr.reseeded_regions = int64_t(r.remesh_reseeded_regions);
    rr.lines = r.remesh_lines;
    rr.holes = r.remesh_holes;
    rr.mean_alignment_deg = r.mean_alignment_deg;
    remesh.quad = r.used_method == CAGEKIT_SCAN_QUAD;
    nlohmann::ordered_json& m = j["remesh"];
    m = remesh_method_json(remesh);
    m.update(remesh_json_fields(rr, method_error));
    m["seconds"] = json_number(r.method_seconds);
  }
  j["conditioning"] = conditioning_json(r);
  j["fit"] = fit_json(fit_result, fit);
  nlohmann::ordered_json& limit_section = j["limit"];
  limit_section["levels"] = r.limit_levels;
  limit_section["faces"] = uint64_t(r.limit_faces);
  limit_section["error"] = {{"hausdorff_rel", json_number(r.scan_to_limit_max_rel)},
                            {"hausdorff_sym_rel", json_number(std::max(r.scan_to_limit_max_rel, r.limit_to_scan_max_rel))},
                            {"mean_rel", json_number(r.limit_mean_rel)}};
  nlohmann::ordered_json& q = j["quality"];
  q["good"] = true;
  q["scan_to_limit_max_rel"] = json_number(r.scan_to_limit_max_rel);
  q["limit_to_scan_max_rel"] = json_number(r.limit_to_scan_max_rel);
  q["limit_self_intersections"] = uint64_t(r.self_intersections);
  q["self_intersection_triangles"] = uint64_t(r.self_intersection_triangles);
  q["scan_self_intersections"] =
      r.scan_self_intersections_counted ? nlohmann::ordered_json(uint64_t(r.scan_self_intersections)) : nullptr;
  q["unfitted_self_intersections"] = uint64_t(r.unfitted_self_intersections);
  q["fit_fairing_used"] = json_number(r.fit_fairing_used);
  q["two_sided_refit"] = bool(r.two_sided_refit);
  if (r.two_sided_refit) q["one_sided_fit_max_rel"] = json_number(r.one_sided_fit_max_rel);
  if (r.input_is_cage) q["own_cage_crease_angle_deg"] = json_number(r.own_cage_crease_angle_deg);
  q["holes_added"] = uint64_t(r.holes_added);
  q["input_boundary_loops"] = uint64_t(r.input_boundary_loops);
  q["cage_boundary_loops"] = uint64_t(r.cage_boundary_loops);
  j["seconds"] = json_number(r.seconds);
  const std::string report = json_text(j, ",\n ") + "\n";  // one top-level member per line
  write_text_file(files[1] + "/report.json", report);

  if (json) {
    std::fputs(report.c_str(), stdout);
  } else if (!quiet) {
    std::printf("%s -> %s/\n", files[0].c_str(), files[1].c_str());
    std::printf("  condition %llu -> %llu faces, %llu component(s)\n", (unsigned long long)r.input_faces,
                (unsigned long long)r.conditioned_faces, (unsigned long long)r.components);
    if (r.fallback) std::printf("  fallback  %s -> simplify: %s\n", method.c_str(), r.fallback_reason);
    std::printf("  %-9s %s%llu faces (%.1f %% quads), %llu creases (%.2f s)\n", used.c_str(),
                r.input_is_cage ? "the input is its own cage: " : "", (unsigned long long)r.cage_faces,
                percent(r.cage_quads, r.cage_faces), (unsigned long long)r.creases, r.method_seconds);
    std::printf("  fit       %u states, best %u: max %.3g -> %.3g, rms %.3g -> %.3g of the diagonal (%.2f s)\n",
                r.fit_pass_count, r.fit_best_pass, r.fit_initial.max_rel, r.fit_final.max_rel, r.fit_initial.rms_rel,
                r.fit_final.rms_rel, r.fit_seconds);
    std::printf("  limit     level %u: scan -> limit %.3g, limit -> scan %.3g of the diagonal, %llu self-intersecting "
                "triangle pairs at level 2\n",
                r.limit_levels, r.scan_to_limit_max_rel, r.limit_to_scan_max_rel,
                (unsigned long long)r.self_intersections);
    std::printf("  wrote     cage.obj limit.obj report.json (%.2f s)\n", r.seconds);
  }
  return kExitOk;
}

}  // namespace

void add_pipeline_options(Options& options) {
  options.add(kMethod);
  options.add(kFaces);
  options.add(kVertices);
  add_cage_options(options);
  add_fit_options(options);  // before the remeshers': --tolerance shows the fit's default
  add_remesh_options(options);
  options.add(kFitTolerance);
  options.add(kLimitLevels);
  options.add(kNoRepair);
  options.add(kComponents);
  options.add(kWeldTolerance);
  options.add(kNoFallback);
  options.add(kTwoSidedRefit);
  // Shared by the methods with method-dependent meanings.
  options.app()
      ->get_option("--feature-angle")
      ->description("input edges sharper than DEG: sharp for simplify's sharp-input creases (0..180), feature lines "
                    "of the remeshers (-1: none)");
  options.app()
      ->get_option("--tolerance")
      ->description("simplify: the fit's tolerance (as in `cagekit fit`) [0, 1]; anisotropic: the remeshing tolerance "
                    "[1e-07, 1], default 0.002; quad: checked, no effect (the fit's is --fit-tolerance)");
}

Command add_pipeline(CLI::App& cagekit) {
  CLI::App* app = cagekit.add_subcommand(
      "pipeline", "conditioning -> simplify or remesh -> creased cage -> fit; writes OUTDIR/cage.obj, limit.obj, "
                  "report.json (a result that is not good: exit 2)");
  auto options = std::make_shared<Options>(app);
  options->add_positional("SCAN", "mesh file");
  options->add_positional("OUTDIR", "output folder (created with its parents)");
  add_pipeline_options(*options);
  options->add(kJson);
  options->add_quiet();
  return {app, [options] { return command_pipeline(*options); }};
}

}  // namespace cli
