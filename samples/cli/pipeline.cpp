// SPDX-License-Identifier: GPL-3.0-or-later
#include "pipeline.h"

#include <sys/stat.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace cli {

namespace {

// Option values of fit/pipeline are input: out of range is exit code 2, not a usage error.
template <class F>
auto bad_value_is_bad_input(F&& parse) {
  try {
    return parse();
  } catch (const Failure& f) {
    if (f.code == kExitUsage) throw Failure(kExitBadInput, f.what());
    throw;
  }
}

}  // namespace

nlohmann::ordered_json json_number(double x) { return json_rounded(x, "%.9g"); }

namespace {

nlohmann::ordered_json number(double x) { return json_number(x); }

// The figures of one fit state, added to `j`.
void add_pass_fields(nlohmann::ordered_json& j, const cagekit_fit_pass& p, double seconds) {
  j["l2"] = number(p.l2);
  j["rms_rel"] = number(p.rms_rel);
  j["max_rel"] = number(p.max_rel);
  j["mean_rel"] = number(p.mean_rel);
  j["max_rel_interior"] = number(p.max_rel_interior);
  j["seconds"] = number(seconds);
  j["unconverged_projections"] = uint64_t(p.unconverged_projections);
  j["mean_projection_steps"] = number(p.mean_projection_steps);
}

nlohmann::ordered_json error_json(const cagekit_approximation_error& e) {
  nlohmann::ordered_json j;
  j["hausdorff_rel"] = number(e.hausdorff_rel);
  j["hausdorff_sym_rel"] = number(e.hausdorff_sym_rel);
  j["mean_rel"] = number(e.mean_rel);
  return j;
}

}  // namespace

void write_text_file(const std::string& path, const std::string& text) {
  const std::string temporary = path + ".tmp";
  FILE* out = std::fopen(temporary.c_str(), "w");
  if (!out) throw Failure(kExitBadInput, path + ": cannot write: " + std::strerror(errno));
  const bool written = std::fwrite(text.data(), 1, text.size(), out) == text.size();
  if (std::fclose(out) != 0 || !written || std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    throw Failure(kExitBadInput, path + ": cannot write");
  }
}

namespace {

// Steps 2 and 3 of the pipeline, shared by both methods: fit of the initial cage's limit surface
// to the scan, then the fitted cage refined to (nearly) its limit surface and compared with it.
void fit_and_limit(const Session& session, const cagekit::Mesh& scan, const std::string& scan_name,
                   const PipelineSettings& settings, const std::string& dir, PipelineResult* result) {
  const cagekit_write_options write = cagekit::defaults<cagekit_write_options>();
  // 2. Fit of the cage's limit surface to the scan.
  result->fitted_cage = run_fit(session, result->initial_cage, scan, settings.fit, scan_name, &result->fit);
  if (!settings.cage_file.empty()) {
    const std::string path = dir + "/" + settings.cage_file;
    session.run(path, [&] { result->fitted_cage.write_file(path, write); });
  }

  // 3. The fitted cage refined to (nearly) its limit surface, compared with the scan.
  cagekit_subdivide_options subdivide = cagekit::defaults<cagekit_subdivide_options>();
  subdivide.levels = settings.limit_levels;
  subdivide.limit_positions = 1;
  result->limit = session.run("fitted cage", [&] { return result->fitted_cage.subdivide(subdivide); });
  if (!settings.limit_file.empty()) {
    const std::string path = dir + "/" + settings.limit_file;
    session.run(path, [&] { result->limit.write_file(path, write); });
  }
  result->limit_info = session.run("fitted limit", [&] { return result->limit.info(); });
  const cagekit::Mesh limit_mesh = session.run("fitted limit", [&] { return result->limit.mesh(); });
  result->limit_error = session.run(scan_name, [&] { return scan.measure_error(limit_mesh); });
}

nlohmann::ordered_json limit_json(const PipelineSettings& settings, const PipelineResult& result) {
  nlohmann::ordered_json j;
  j["levels"] = settings.limit_levels;
  j["vertices"] = uint64_t(result.limit_info.vertices);
  j["faces"] = uint64_t(result.limit_info.faces);
  j["error"] = error_json(result.limit_error);
  return j;
}

}  // namespace

void make_directories(const std::string& path) {
  if (path.empty()) throw Failure(kExitBadInput, "output folder name is empty");
  for (size_t at = path.find('/', 1);; at = path.find('/', at + 1)) {
    const std::string prefix = at == std::string::npos ? path : path.substr(0, at);
    struct stat info {};
    if (stat(prefix.c_str(), &info) == 0) {
      if (!S_ISDIR(info.st_mode)) throw Failure(kExitBadInput, prefix + ": exists and is not a folder");
    } else if (mkdir(prefix.c_str(), 0755) != 0 && errno != EEXIST) {
      throw Failure(kExitBadInput, prefix + ": cannot create folder: " + std::strerror(errno));
    }
    if (at == std::string::npos) break;
  }
}

namespace {

const TextOption kCreases{"--creases", "sharp-input", "sharp-input|cluster-angle",
                          "where the cage gets creases: where the scan is sharp (input edges above --feature-angle, "
                          "noise filtered), or by the clusters' normals (thesis rule, --crease-angle)"};
const RealOption kFeatureAngle{"--feature-angle", 40.0, 0.0, 180.0, "DEG",
                               "sharp-input: input edges sharper than DEG are sharp"};
const RealOption kCreaseAngle{"--crease-angle", 30.0, -1.0, 180.0, "DEG",
                              "cluster-angle: clusters whose normals differ by more than DEG meet at a crease"};
const RealOption kInputCreaseAngle{"--input-crease-angle", -1.0, -1.0, 180.0, "DEG",
                                   "cluster-angle: also require the input to be sharper than DEG there (-1: off)"};

const IntegerOption kPasses{"--passes", 5, 0, 100000, "N", "fit passes (control-vertex steps) at most"};
const RealOption kFitTolerance{"--tolerance", 1e-4, 0.0, 1.0, "T",
                               "stop when a pass lowers the L2 error by less than T x L2 (0: run all --passes)"};
const RealOption kFairing{"--fairing", 0.0, 0.0, 1e6, "F", "weight of an umbrella-Laplacian fairing term (0: none, as in the thesis)"};
const IntegerOption kThreads{"--threads", 0, 0, 1024, "N", "worker threads (0: all cores)"};
const FlagOption kKeepCreases{"--keep-creases", "vertices on sharp creases and corners keep their positions"};
const RealOption kCreaseFeatureReach{"--crease-feature-reach", 0.02, 0.0, 1.0, "REL",
                                     "the limit's crease curves are pulled onto the scan's sharp edges within "
                                     "REL x the bbox diagonal (0: crease curves free)"};
const TextOption kProjection{"--projection", "exact", "exact|linear",
                             "closest points on the exact limit surface or on its piecewise-linear refinement"};

}  // namespace

void add_cage_options(Options& options) {
  options.add(kCreases);
  options.add(kFeatureAngle);
  options.add(kCreaseAngle);
  options.add(kInputCreaseAngle);
}

cagekit_cage_options parse_cage_options(const Options& args) {
  cagekit_cage_options o = CAGEKIT_CAGE_OPTIONS_INIT;
  const std::string rule = bad_value_is_bad_input([&] { return args.text(kCreases); });
  if (rule == "sharp-input")
    o.crease_rule = CAGEKIT_CREASES_SHARP_INPUT;
  else if (rule == "cluster-angle")
    o.crease_rule = CAGEKIT_CREASES_CLUSTER_ANGLE;
  else
    throw Failure(kExitBadInput, "--creases must be 'sharp-input' or 'cluster-angle', not '" + rule + "'");
  o.feature_angle_degrees = bad_value_is_bad_input([&] { return args.real(kFeatureAngle); });
  o.crease_angle_degrees = bad_value_is_bad_input([&] { return args.real(kCreaseAngle); });
  o.input_crease_angle_degrees = bad_value_is_bad_input([&] { return args.real(kInputCreaseAngle); });
  return o;
}

void add_fit_options(Options& options) {
  options.add(kPasses);
  options.add(kFitTolerance);
  options.add(kProjection);
  options.add(kFairing);
  options.add(kCreaseFeatureReach);
  options.add(kKeepCreases);
  options.add(kThreads);
}

cagekit_fit_options parse_fit_options(const Options& args) {
  cagekit_fit_options o = CAGEKIT_FIT_OPTIONS_INIT;
  o.max_passes = static_cast<uint32_t>(bad_value_is_bad_input([&] { return args.integer(kPasses); }));
  o.tolerance = bad_value_is_bad_input([&] { return args.real(kFitTolerance); });
  o.fairing = bad_value_is_bad_input([&] { return args.real(kFairing); });
  o.threads = static_cast<uint32_t>(bad_value_is_bad_input([&] { return args.integer(kThreads); }));
  o.keep_crease_vertices = args.flag(kKeepCreases) ? 1 : 0;
  o.crease_feature_reach = bad_value_is_bad_input([&] { return args.real(kCreaseFeatureReach); });
  const std::string projection = bad_value_is_bad_input([&] { return args.text(kProjection); });
  if (projection == "exact")
    o.projection = CAGEKIT_PROJECTION_EXACT;
  else if (projection == "linear")
    o.projection = CAGEKIT_PROJECTION_PIECEWISE_LINEAR;
  else
    throw Failure(kExitBadInput, "--projection must be 'exact' or 'linear', not '" + projection + "'");
  return o;
}

cagekit::Cage run_fit(const Session& session, const cagekit::Cage& cage, const cagekit::Mesh& scan,
                      const cagekit_fit_options& options, const std::string& what, FitResult* result) {
  cagekit::Cage::Fit fit = session.run(what, [&] { return cage.fit(scan, options); });
  result->report = fit.report;
  result->passes = std::move(fit.passes);
  return std::move(fit.cage);
}

nlohmann::ordered_json fit_json(const FitResult& fit, const cagekit_fit_options& options) {
  const cagekit_fit_report& r = fit.report;
  nlohmann::ordered_json j;
  j["passes"] = r.pass_count > 0 ? r.pass_count - 1 : 0;
  add_pass_fields(j, r.final, r.seconds);
  j["stopped_by_tolerance"] = bool(r.stopped_by_tolerance);
  j["rejected_last_step"] = bool(r.rejected_last_step);
  j["unsupported_control_vertices"] = uint64_t(r.unsupported_control_vertices);
  j["weakly_supported_control_vertices"] = uint64_t(r.weakly_supported_control_vertices);
  j["best_pass"] = r.best_pass;
  j["surface_to_scan_max_rel"] = number(r.final_two_sided.surface_to_scan_max_rel);
  j["surface_to_scan_rms_rel"] = number(r.final_two_sided.surface_to_scan_rms_rel);
  j["two_sided_rms_rel"] = number(r.final_two_sided.two_sided_rms_rel);
  j["initial_surface_to_scan_max_rel"] = number(r.initial_two_sided.surface_to_scan_max_rel);
  j["bbox_diagonal"] = number(r.bbox_diagonal);
  j["max_passes"] = options.max_passes;
  j["tolerance"] = number(options.tolerance);
  j["fairing"] = number(options.fairing);
  j["crease_feature_reach"] = number(options.crease_feature_reach);
  j["projection"] = options.projection == CAGEKIT_PROJECTION_EXACT ? "exact" : "linear";
  j["per_pass"] = nlohmann::ordered_json::array();
  for (size_t i = 0; i < fit.passes.size(); ++i) {
    nlohmann::ordered_json pass;
    pass["pass"] = i;
    add_pass_fields(pass, fit.passes[i], fit.passes[i].seconds);
    j["per_pass"].push_back(pass);
  }
  return j;
}

void run_pipeline(const Session& session, const cagekit::Mesh& scan, const std::string& scan_name,
                  const PipelineSettings& settings, const std::string& dir, PipelineResult* result) {
  const auto start = std::chrono::steady_clock::now();
  make_directories(dir);

  // 1. Simplification to the requested level and the quad-dominant cage with creases.
  cagekit::Hierarchy hierarchy = session.run(scan_name, [&] { return scan.create_hierarchy(); });
  session.run(scan_name, [&] {
    result->level_count = hierarchy.level_count();
    result->level = hierarchy.find_level(settings.query, settings.target);
    hierarchy.set_level(result->level);
    result->level_info = hierarchy.current_info();
  });
  cagekit_cage_options cage_options = cagekit::defaults<cagekit_cage_options>();
  cage_options.crease_angle_degrees = settings.crease_angle;
  cage_options.input_crease_angle_degrees = settings.input_crease_angle;
  result->initial_cage =
      session.run(scan_name, [&] { return hierarchy.build_cage(cage_options, &result->cage_report); });
  result->simplify_seconds = seconds_since(start);
  result->polygons = session.run(scan_name, [&] { return hierarchy.polygon_mesh(); });
  result->level_error = session.run(scan_name, [&] { return scan.measure_error(result->polygons); });

  fit_and_limit(session, scan, scan_name, settings, dir, result);
  result->seconds = seconds_since(start);

  const cagekit_cage_report& c = result->cage_report;
  nlohmann::ordered_json simplify;
  simplify["method"] = "simplify";
  simplify["level"] = result->level;
  simplify["levels"] = result->level_count;
  simplify["polygons"] = uint64_t(result->level_info.faces);
  simplify["faces_with_holes"] = uint64_t(result->level_info.faces_with_holes);
  simplify["cage_faces"] = uint64_t(c.quads + c.triangles + c.pentagons + c.other_polygons);
  simplify["quads"] = uint64_t(c.quads);
  simplify["triangles"] = uint64_t(c.triangles);
  simplify["pentagons"] = uint64_t(c.pentagons);
  simplify["other_polygons"] = uint64_t(c.other_polygons);
  simplify["creases"] = uint64_t(c.creases);
  simplify["non_manifold_edges"] = uint64_t(c.non_manifold_edges);
  simplify["error"] = error_json(result->level_error);
  simplify["seconds"] = number(result->simplify_seconds);
  nlohmann::ordered_json report;
  report["simplify"] = simplify;
  report["fit"] = fit_json(result->fit, settings.fit);
  report["limit"] = limit_json(settings, *result);
  report["seconds"] = number(result->seconds);
  result->json = json_text(report, ",\n ") + "\n";
  if (!settings.report_file.empty()) write_text_file(dir + "/" + settings.report_file, result->json);
}

}  // namespace cli
