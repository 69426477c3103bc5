// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The demo's pipeline, step by step through the individual SDK calls (`cagekit demo` shows
// them; `cagekit pipeline` makes the whole journey with one cagekit_scan_to_cage call):
// structure-preserving simplification (thesis ch. 3) -> quad-dominant cage with creases ->
// fit of the cage's limit surface to the scan (ch. 7) -> the fitted cage refined to its limit.
// Also the fit options and JSON of `cagekit fit` and `cagekit pipeline`.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_context.h"

namespace cli {

// The fit's options (fit, pipeline): --passes N --tolerance T --projection exact|linear --fairing F
// --keep-creases --threads N --crease-feature-reach REL (cagekit_fit_options.crease_feature_reach;
// 0: crease curves free).
void add_fit_options(Options& options);
// Values out of range are bad input (Failure with kExitBadInput naming the option).
cagekit_fit_options parse_fit_options(const Options& options);

// Simplify's crease options (simplify, pipeline --method simplify): --creases
// sharp-input|cluster-angle (default sharp-input: creases only where the scan is sharp),
// --feature-angle DEG (sharp-input, default 40), --crease-angle DEG and --input-crease-angle DEG
// (cluster-angle, defaults 30 and -1).
void add_cage_options(Options& options);
// Values out of range are bad input (Failure with kExitBadInput naming the option).
cagekit_cage_options parse_cage_options(const Options& options);

// Runs cagekit::Cage::fit (a pass array of max_passes + 1 entries: all of them) and returns the
// fitted cage; errors are Failure naming `what`.
struct FitResult {
  cagekit_fit_report report{};
  std::vector<cagekit_fit_pass> passes;  // pass_count entries, 0 = the initial cage
};
cagekit::Cage run_fit(const Session& session, const cagekit::Cage& cage, const cagekit::Mesh& scan,
                      const cagekit_fit_options& options, const std::string& what, FitResult* result);

// {"passes": steps, final figures, "seconds": whole fit, "stopped_by_tolerance", ..., "per_pass": [...]}.
nlohmann::ordered_json fit_json(const FitResult& fit, const cagekit_fit_options& options);

struct PipelineSettings {
  cagekit_level_query query = CAGEKIT_LEVEL_BY_FACES;  // BY_FACES or BY_VERTICES
  double target = 0;
  double crease_angle = 30.0;
  double input_crease_angle = -1.0;  // also require the scan to be sharp there (< 0: off)
  cagekit_fit_options fit = CAGEKIT_FIT_OPTIONS_INIT;
  uint32_t limit_levels = 3;
  // Output file names inside the output folder ("" = not written).
  std::string cage_file = "cage.obj", limit_file = "limit.obj", report_file = "report.json";
};

struct PipelineResult {
  // simplification
  uint32_t level = 0, level_count = 0;
  cagekit_polygonal_level_info level_info{};
  cagekit_cage_report cage_report{};
  cagekit_approximation_error level_error{};  // scan vs the level's polygons (or the remeshed mesh)
  double simplify_seconds = 0;
  cagekit::Mesh polygons;       // the level as a polygon mesh
  cagekit::Cage initial_cage;   // quad-dominant cage with creases, before the fit
  // fit
  FitResult fit;
  cagekit::Cage fitted_cage;
  // the fitted cage refined limit_levels times, on its limit surface
  cagekit::Cage limit;
  cagekit_mesh_info limit_info{};
  cagekit_approximation_error limit_error{};  // scan vs the refined limit mesh
  double seconds = 0;
  std::string json;   // what report.json holds (json_text)
};

// Runs the pipeline on `scan` (a valid mesh) and writes the outputs named in `settings` into
// `dir` (created with its parents when missing).
void run_pipeline(const Session& session, const cagekit::Mesh& scan, const std::string& scan_name,
                  const PipelineSettings& settings, const std::string& dir, PipelineResult* result);

// x as a JSON number rounded to 9 significant digits (null for NaN/Inf).
nlohmann::ordered_json json_number(double x);
// Writes `text` to path.tmp and renames it over `path` (Failure(kExitBadInput) on error).
void write_text_file(const std::string& path, const std::string& text);

// mkdir -p; throws Failure(kExitBadInput) when a component cannot be created.
void make_directories(const std::string& path);

}  // namespace cli
