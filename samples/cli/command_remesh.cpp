// SPDX-License-Identifier: GPL-3.0-or-later
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli_context.h"

namespace cli {

namespace {

double percent(uint64_t part, uint64_t whole) { return whole ? 100.0 * double(part) / double(whole) : 0.0; }

}  // namespace

namespace {

// "--weights TRI,PENT,TJOINT": three positive finite numbers.
void parse_weights(const std::string& text, cagekit_quad_remesh_options& o) {
  double w[3];
  const char* p = text.c_str();
  for (int i = 0; i < 3; ++i) {
    char* end = nullptr;
    w[i] = std::strtod(p, &end);
    if (end == p || !std::isfinite(w[i]) || !(w[i] > 0.0) || (i < 2 ? *end != ',' : *end != '\0'))
      throw Failure(kExitBadInput, "--weights must be three positive numbers TRI,PENT,TJOINT, not '" + text + "'");
    p = end + 1;
  }
  o.triangle_weight = w[0];
  o.pentagon_weight = w[1];
  o.t_joint_weight = w[2];
}

// anisotropic
const RealOption kTolerance{"--tolerance", 0.002, 1e-7, 1.0, "REL",
                            "anisotropic: approximation tolerance relative to the bbox diagonal (sets the line spacing)"};
const IntegerOption kMaxFaceValence{"--max-face-valence", 5, 3, 1000, "N", "anisotropic: faces with more corners are split"};
const RealOption kCurvatureRadius{"--curvature-radius", 0.01, 0.0, 1.0, "REL",
                                  "anisotropic: curvature averaging radius relative to the bbox diagonal"};
// quad
const RealOption kEdgeLength{"--edge-length", 0.05, 1e-4, 1.0, "REL",
                             "quad: region-boundary samples REL of the bbox diagonal apart"};
const IntegerOption kRegions{"--regions", 30, 0, 1000000, "N",
                             "quad: region count (0: the first count whose L2,1 error / area <= --region-tolerance)"};
const RealOption kRegionTolerance{"--region-tolerance", 0.01, 0.0, 4.0, "T", "quad: the error bound of --regions 0"};
const TextOption kWeights{"--weights", "40,40,100", "TRI,PENT,TJOINT",
                          "quad: element energy weights of triangles, pentagons and T-joints (Table 6.1)"};
const IntegerOption kRefinementPasses{"--refinement-passes", 1, 0, 16, "N",
                                      "quad: sample-count refinement passes (0: none, 3-10x faster)"};
// both
const RealOption kFeatureAngle{"--feature-angle", 40.0, -1.0, 180.0, "DEG",
                               "input edges sharper than DEG are feature lines, kept as creases (-1: none)"};
const IntegerOption kThreads{"--threads", 0, 0, 1024, "N", "worker threads (0: all cores)"};

}  // namespace

void add_remesh_options(Options& options) {
  options.add(kTolerance);
  options.add(kMaxFaceValence);
  options.add(kCurvatureRadius);
  options.add(kEdgeLength);
  options.add(kRegions);
  options.add(kRegionTolerance);
  options.add(kWeights);
  options.add(kRefinementPasses);
  options.add(kFeatureAngle);
  options.add(kThreads);
}

RemeshSettings parse_remesh_options(const Options& args, const std::string& method) {
  RemeshSettings settings;
  if (method != "anisotropic" && method != "quad")
    throw Failure(kExitBadInput, "--method must be 'anisotropic' or 'quad', not '" + method + "'");
  try {
    if (method == "quad") {
      cagekit_quad_remesh_options& o = settings.quad_options;
      settings.quad = true;
      o.edge_length = args.real(kEdgeLength);
      o.regions = static_cast<uint32_t>(args.integer(kRegions));
      o.region_tolerance = args.real(kRegionTolerance);
      const std::string weights = args.given(kWeights.name) ? args.text(kWeights) : std::string();
      if (!weights.empty()) parse_weights(weights, o);  // else the library's (kWeights' shown default)
      o.refinement_passes = static_cast<uint32_t>(args.integer(kRefinementPasses));
      o.crease_angle_degrees = args.real(kFeatureAngle);
      o.threads = static_cast<uint32_t>(args.integer(kThreads));
    } else {
      cagekit_anisotropic_options& o = settings.anisotropic;
      o.tolerance = args.real(kTolerance);
      o.max_face_valence = static_cast<uint32_t>(args.integer(kMaxFaceValence));
      o.curvature_radius = args.real(kCurvatureRadius);
      o.feature_angle_degrees = args.real(kFeatureAngle);
      o.threads = static_cast<uint32_t>(args.integer(kThreads));
    }
  } catch (const Failure& f) {  // option values are input: exit code 2
    throw Failure(f.code == kExitUsage ? kExitBadInput : f.code, f.what());
  }
  return settings;
}

void refuse_other_remesh_options(const Options& args, const RemeshSettings& settings) {
  if (settings.quad)
    args.refuse({kMaxFaceValence.name, kCurvatureRadius.name}, "with --method quad");
  else
    args.refuse({kEdgeLength.name, kRegions.name, kRegionTolerance.name, kWeights.name, kRefinementPasses.name},
                "with --method anisotropic");
}

nlohmann::ordered_json remesh_method_json(const RemeshSettings& settings) {
  const auto g = [](double x) { return json_rounded(x, "%.9g"); };
  const cagekit_quad_remesh_options& q = settings.quad_options;
  nlohmann::ordered_json j;
  if (settings.quad) {
    j["method"] = "quad";
    j["edge_length"] = g(q.edge_length);
    j["weights"] = {g(q.triangle_weight), g(q.pentagon_weight), g(q.t_joint_weight)};
    j["refinement_passes"] = q.refinement_passes;
  } else {
    j["method"] = "anisotropic";
    j["tolerance"] = g(settings.anisotropic.tolerance);
  }
  return j;
}

nlohmann::ordered_json remesh_json_fields(const RemeshFigures& f, const cagekit_approximation_error& e) {
  const cagekit_remesh_quality& q = f.quality;
  nlohmann::ordered_json j;
  j["faces"] = uint64_t(q.faces);
  j["vertices"] = uint64_t(q.vertices);
  j["quads_pct"] = json_rounded(percent(q.quads, q.faces), "%.3f");
  j["valence4_vertices_pct"] = json_rounded(percent(q.valence4_vertices, q.interior_vertices), "%.3f");
  j["max_face_valence"] = q.max_face_valence;
  j["max_vertex_valence"] = q.max_vertex_valence;
  j["creases"] = uint64_t(q.creases);
  j["hausdorff_rel"] = json_rounded(e.hausdorff_rel, "%.9g");
  j["hausdorff_sym_rel"] = json_rounded(e.hausdorff_sym_rel, "%.9g");
  j["min_scaled_jacobian"] = json_rounded(q.min_scaled_jacobian, "%.6f");
  j["regions"] = uint64_t(f.regions);
  if (f.reseeded_regions >= 0) j["reseeded_regions"] = f.reseeded_regions;
  j["mean_alignment_deg"] = json_rounded(f.mean_alignment_deg, "%.4f");
  j["lines"] = uint64_t(f.lines);
  j["holes"] = uint64_t(f.holes);
  return j;
}

namespace {

const FlagOption kJson{"--json", "print the report as one JSON object"};
const TextOption kMethod{"--method", "", "anisotropic|quad",
                         "anisotropic: curvature-line remeshing (thesis ch. 5); quad: two-step quad-dominant "
                         "remeshing (thesis ch. 6) (required)"};

int command_remesh(const Options& args) {
  const bool quiet = args.quiet();
  const bool json = args.flag(kJson);
  const std::string method = args.text(kMethod);
  if (method.empty()) throw Failure(kExitUsage, "--method is required");
  const RemeshSettings settings = parse_remesh_options(args, method);
  if (settings.quad) args.refuse({kTolerance.name}, "with --method quad");
  refuse_other_remesh_options(args, settings);
  const std::vector<std::string> files = {args.positional("IN"), args.positional("OUT")};
  const cagekit_file_format out_format = format_from_extension(files[1]);
  const auto start = std::chrono::steady_clock::now();

  Session session(quiet);
  const cagekit::Mesh input = session.run(files[0], [&] { return session.context().read_mesh(files[0]); });
  RemeshFigures figures;
  cagekit::Cage output;
  if (settings.quad) {
    cagekit_quad_remesh_report report = cagekit::defaults<cagekit_quad_remesh_report>();
    output = session.run(files[0], [&] { return input.remesh_quad(settings.quad_options, &report); });
    figures.quality = report.quality;
    figures.regions = report.regions;
    figures.reseeded_regions = int64_t(report.reseeded_regions);
    figures.lines = report.arcs;
  } else {
    cagekit_anisotropic_report report = cagekit::defaults<cagekit_anisotropic_report>();
    output = session.run(files[0], [&] { return input.remesh_anisotropic(settings.anisotropic, &report); });
    figures.quality = report.quality;
    figures.regions = report.regions;
    figures.lines = report.lines;
    figures.holes = report.holes;
    figures.mean_alignment_deg = report.mean_alignment_deg;
  }
  const cagekit_remesh_quality& quality = figures.quality;
  cagekit_write_options write = cagekit::defaults<cagekit_write_options>();
  write.format = out_format;
  session.run(files[1], [&] { output.write_file(files[1], write); });
  const cagekit::Mesh output_mesh = session.run(files[1], [&] { return output.mesh(); });
  const cagekit_approximation_error error = session.run(files[0], [&] { return input.measure_error(output_mesh); });
  session.finish_progress();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  if (json) {
    nlohmann::ordered_json j = remesh_method_json(settings);
    j.update(remesh_json_fields(figures, error));
    j["remesh_seconds"] = json_rounded(quality.seconds, "%.3f");
    j["seconds"] = json_rounded(seconds, "%.3f");
    std::printf("%s\n", json_text(j).c_str());
  } else if (!quiet) {
    char described[128];
    if (settings.quad)
      std::snprintf(described, sizeof(described), "%llu regions, edge length %g", (unsigned long long)figures.regions,
                    settings.quad_options.edge_length);
    else
      std::snprintf(described, sizeof(described), "tolerance %g", settings.anisotropic.tolerance);
    std::printf("%s -> %s (%s, %s): %llu faces (%.1f%% quads), %llu vertices (%.1f%% interior valence 4), "
                "%llu creases, ",
                files[0].c_str(), files[1].c_str(), method.c_str(), described, (unsigned long long)quality.faces,
                percent(quality.quads, quality.faces), (unsigned long long)quality.vertices,
                percent(quality.valence4_vertices, quality.interior_vertices), (unsigned long long)quality.creases);
    if (!settings.quad) std::printf("mean alignment %.2f deg, ", figures.mean_alignment_deg);
    std::printf("Hausdorff %.3g of the diagonal, %.2f s\n", error.hausdorff_sym_rel, seconds);
  }
  return kExitOk;
}

}  // namespace

Command add_remesh(CLI::App& cagekit) {
  CLI::App* app = cagekit.add_subcommand(
      "remesh", "remeshing to a quad-dominant cage with creases (anisotropic: thesis ch. 5, quad: ch. 6)");
  auto options = std::make_shared<Options>(app);
  options->add_positional("IN", "mesh file");
  options->add_positional("OUT", "output cage file (.obj .ply .off .drc)");
  options->add(kMethod);
  add_remesh_options(*options);
  options->add(kJson);
  options->add_quiet();
  return {app, [options] { return command_remesh(*options); }};
}

}  // namespace cli
