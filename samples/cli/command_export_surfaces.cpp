// SPDX-License-Identifier: GPL-3.0-or-later
// cagekit export-surfaces: the cage's limit surface as B-spline surfaces (one per ptex face,
// cagekit_limit_surfaces_*) written as a STEP file through OpenCASCADE (samples/step_export):
// faces sewn into a shell, a solid when the shell is closed, checked by BRepCheck. Prints a JSON
// summary on stdout. Built only with CAGEKIT_WITH_OCCT; without it the command says so.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli_context.h"
#ifdef CAGEKIT_CLI_HAS_OCCT
#include "step_export.h"
#endif

namespace cli {

namespace {

const RealOption kTolerance{"--tolerance", 1e-4, 1e-9, 1.0, "REL",
                            "largest distance of an approximated surface to the limit surface, relative to the "
                            "bounding-box diagonal of the cage"};
const IntegerOption kMaxLevel{"--max-level", 5, 1, 7, "L", "largest knot level (2^L spans per quad side)"};
const TextOption kPer{"--per", "face", "face", "one B-spline surface per ptex face (the only mode so far)"};
const RealOption kSewing{"--sewing-tolerance", 1e-7, 1e-12, 1e-2, "REL",
                         "sewing tolerance relative to the bounding-box diagonal"};
const RealOption kKnotRemoval{"--knot-removal", -1.0, -1.0, 1.0, "REL",
                              "remove knots where a surface moves by at most REL of the diagonal and by no more "
                              "than --tolerance leaves it (fewer control points, a smaller file; the move is "
                              "measured and reported; 0: off, -1: a tenth of --tolerance)"};
const TextOption kSchema{"--schema", "AP214", "NAME", "STEP schema: AP214 or AP203"};
const IntegerOption kThreads{"--threads", 0, 0, 1024, "N", "worker threads for the surface fits (0: all cores)"};
const FlagOption kCheck{"--check",
                        "read the file back and measure it against the limit surface (5 x 5 points per surface)"};

#ifdef CAGEKIT_CLI_HAS_OCCT

// The C API's surfaces (cagekit_limit_surfaces_*, through cagekit::LimitSurfaces) as plain data.
std::vector<cagekit_step::BSplineSurface> plain_surfaces(const cagekit::LimitSurfaces& surfaces, uint32_t count,
                                                         std::vector<cagekit_limit_surface>& descriptors) {
  std::vector<cagekit_step::BSplineSurface> out(count);
  descriptors.resize(count);
  for (uint32_t i = 0; i < count; ++i) {
    const cagekit_limit_surface d = descriptors[i] = surfaces.surface(i);
    cagekit_step::BSplineSurface& s = out[i];
    s.degree_u = int(d.degree_u);
    s.degree_v = int(d.degree_v);
    s.num_u = d.num_u;
    s.num_v = d.num_v;
    s.knots_u = surfaces.knots(i, CAGEKIT_SURFACE_DIRECTION_U);
    s.knots_v = surfaces.knots(i, CAGEKIT_SURFACE_DIRECTION_V);
    s.points = surfaces.control_points(i);
  }
  return out;
}

int command_export_surfaces(const Options& args) {
  const bool quiet = args.quiet();
  const std::string per = args.text(kPer);
  if (per != "face")
    throw Failure(kExitUsage, "--per " + per + ": only 'face' (one surface per ptex face) is available");
  const std::string schema = args.text(kSchema);
  if (schema != "AP214" && schema != "AP203") throw Failure(kExitUsage, "--schema " + schema + ": AP214 or AP203");
  cagekit_limit_surface_options options = cagekit::defaults<cagekit_limit_surface_options>();
  options.tolerance = args.real(kTolerance);
  options.max_level = uint32_t(args.integer(kMaxLevel));
  options.threads = uint32_t(args.integer(kThreads));
  const double sewing_rel = args.real(kSewing);
  const bool read_back = args.flag(kCheck);
  const std::vector<std::string> files = {args.positional("CAGE"), args.positional("OUT")};

  const auto start = std::chrono::steady_clock::now();
  Session session(quiet);
  const cagekit::Cage cage = session.run(files[0], [&] { return session.context().read_cage(files[0]); });
  cagekit_limit_surface_info info = cagekit::defaults<cagekit_limit_surface_info>();
  std::vector<cagekit_limit_surface> descriptors;
  std::vector<cagekit_step::BSplineSurface> data;
  session.run(files[0], [&] {
    const cagekit::LimitSurfaces surfaces = cage.create_limit_surfaces(options);
    info = surfaces.info();
    data = plain_surfaces(surfaces, info.surface_count, descriptors);
  });
  const double surface_seconds = seconds_since(start);
  session.finish_progress();
  if (data.empty()) throw Failure(kExitBadInput, files[0] + ": the cage has no surface to export");

  cagekit_step::WriteOptions write;
  write.sewing_tolerance = sewing_rel * info.bbox_diagonal;
  const double removal_rel = args.real(kKnotRemoval) < 0 ? 0.1 * options.tolerance : args.real(kKnotRemoval);
  write.knot_removal_tolerance = removal_rel * info.bbox_diagonal;
  // Each surface moves by at most what the tolerance leaves it: its two-sided distance to the limit
  // surface grows by at most the move (triangle inequality), so it stays within the tolerance; a
  // surface already over it keeps its knots.
  for (size_t i = 0; i < data.size(); ++i)
    data[i].knot_removal_budget = std::max(0.0, options.tolerance * info.bbox_diagonal - descriptors[i].error);
  write.schema = schema;
  const cagekit_step::WriteReport w = cagekit_step::write_step(data, files[1], write);
  if (!w.ok) throw Failure(kExitBadInput, files[1] + ": " + w.error);

  nlohmann::ordered_json j;
  j["cage"] = files[0];
  j["step"] = files[1];
  j["per"] = per;
  j["tolerance"] = options.tolerance;
  j["surfaces"] = info.surface_count;
  j["ptex_faces"] = info.ptex_face_count;
  j["exact"] = info.exact_count;
  j["approximated"] = info.approximated_count;
  j["over_tolerance"] = info.over_tolerance_count;
  j["level"] = info.level;
  j["faces"] = w.faces;
  j["shells"] = w.shells;
  j["free_edges"] = w.free_edges;
  j["closed"] = w.closed;
  j["solid"] = w.solid;
  j["valid"] = w.valid;
  j["bytes"] = w.bytes;
  j["control_points"] = w.control_points;
  j["control_points_before"] = w.control_points_before;
  j["knot_removal_rel"] = removal_rel;
  j["max_knot_removal_deviation_rel"] = json_rounded(w.max_knot_removal_deviation / info.bbox_diagonal, "%.4g");
  j["max_error_rel"] = json_rounded(info.max_error_rel, "%.4g");
  j["max_normal_jump_deg"] = json_rounded(info.max_normal_jump_deg, "%.4g");
  j["max_crease_angle_deg"] = json_rounded(info.max_crease_angle_deg, "%.4g");
  j["seconds_surfaces"] = json_rounded(surface_seconds, "%.3f");
  j["seconds_sewing"] = json_rounded(w.sewing_seconds, "%.3f");
  j["seconds_solid_check"] = json_rounded(w.solid_seconds + w.check_seconds, "%.3f");
  j["seconds_write"] = json_rounded(w.write_seconds, "%.3f");
  j["seconds"] = json_rounded(seconds_since(start), "%.3f");

  if (read_back) {
    // 5 x 5 limit-surface points per surface (cagekit_surface_evaluate at the surfaces' ptex faces);
    // each is projected onto the faces near it (about 3 ms per point on a 53 MB fandisk file).
    std::vector<cagekit_surface_location> locations;
    for (const cagekit_limit_surface& d : descriptors)
      for (int b = 0; b < 5; ++b)
        for (int a = 0; a < 5; ++a) locations.push_back({d.ptex_face, a / 4.0, b / 4.0});
    std::vector<std::array<double, 3>> points;
    session.run(files[0], [&] {
      const cagekit::Surface limit = cage.create_surface();
      for (const cagekit_surface_point& p : limit.evaluate(locations))
        points.push_back({p.position[0], p.position[1], p.position[2]});
    });
    const cagekit_step::ReadReport r = cagekit_step::read_step(files[1], points);
    if (!r.ok) throw Failure(kExitBadInput, files[1] + ": reading back: " + r.error);
    nlohmann::ordered_json c;
    c["faces"] = r.faces;
    c["shells"] = r.shells;
    c["solids"] = r.solids;
    c["valid"] = r.valid;
    c["points"] = r.points_checked;
    c["max_distance_rel"] = json_rounded(r.max_distance / info.bbox_diagonal, "%.4g");
    c["seconds"] = json_rounded(r.read_seconds + r.distance_seconds, "%.3f");
    j["read_back"] = c;
  }
  std::printf("%s\n", json_text(j).c_str());
  if (!quiet && info.over_tolerance_count > 0)
    std::fprintf(stderr, "cagekit: warning: %u surfaces above the tolerance at --max-level %u\n",
                 info.over_tolerance_count, options.max_level);
  return kExitOk;
}

#else

int command_export_surfaces(const Options&) {
  throw Failure(kExitUsage, "export-surfaces: this cagekit was built without OpenCASCADE (CAGEKIT_WITH_OCCT off)");
}

#endif

}  // namespace

Command add_export_surfaces(CLI::App& cagekit) {
#ifdef CAGEKIT_CLI_HAS_OCCT
  const char* what = "the limit surface as B-spline surfaces in a STEP file (OpenCASCADE; sewn, a solid when closed)";
#else
  const char* what = "(not available: built without OpenCASCADE) the limit surface as B-spline surfaces in STEP";
#endif
  CLI::App* app = cagekit.add_subcommand("export-surfaces", what);
  auto options = std::make_shared<Options>(app);
  options->add_positional("CAGE", "cage file");
  options->add_positional("OUT", "STEP file (.step / .stp)");
  options->add(kTolerance);
  options->add(kMaxLevel);
  options->add(kPer);
  options->add(kSewing);
  options->add(kKnotRemoval);
  options->add(kSchema);
  options->add(kThreads);
  options->add(kCheck);
  options->add_quiet();
  return {app, [options] { return command_export_surfaces(*options); }};
}

}  // namespace cli
