// SPDX-License-Identifier: GPL-3.0-or-later
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli_context.h"
#include "pipeline.h"

namespace cli {

namespace {

// The input coloured by cluster, as an ascii PLY with per-face colours (written atomically).
void write_clusters_ply(const Session& session, const cagekit::Mesh& input, const std::vector<uint32_t>& clusters,
                        const std::string& path) {
  const std::vector<double> positions = session.run(path, [&] { return input.positions(); });
  const cagekit::Faces faces_of_input = session.run(path, [&] { return input.faces(); });
  const std::vector<uint32_t>& sizes = faces_of_input.face_sizes;
  const std::vector<uint32_t>& face_indices = faces_of_input.face_indices;
  const uint32_t vertices = static_cast<uint32_t>(positions.size() / 3);
  const uint32_t faces = static_cast<uint32_t>(sizes.size());
  const std::string temporary = path + ".tmp";
  FILE* out = std::fopen(temporary.c_str(), "w");
  if (!out) throw Failure(kExitBadInput, path + ": cannot write");
  std::fprintf(out,
               "ply\nformat ascii 1.0\ncomment CageKit clusters: faces coloured by simplification cluster\n"
               "element vertex %u\nproperty double x\nproperty double y\nproperty double z\n"
               "element face %u\nproperty list uchar int vertex_indices\nproperty uchar red\n"
               "property uchar green\nproperty uchar blue\nproperty int cluster\nend_header\n",
               vertices, faces);
  for (uint32_t v = 0; v < vertices; ++v)
    std::fprintf(out, "%.17g %.17g %.17g\n", positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
  size_t at = 0;
  for (uint32_t f = 0; f < faces; ++f) {
    std::fprintf(out, "%u", sizes[f]);
    for (uint32_t k = 0; k < sizes[f]; ++k) std::fprintf(out, " %u", face_indices[at + k]);
    at += sizes[f];
    // Golden-ratio hue steps give neighbouring cluster ids well separated colours.
    const uint32_t c = clusters[f];
    const double hue = c * 0.6180339887498949 - static_cast<long>(c * 0.6180339887498949);
    const double r = 0.5 + 0.5 * std::sin(6.283185307179586 * (hue + 0.0 / 3));
    const double g = 0.5 + 0.5 * std::sin(6.283185307179586 * (hue + 1.0 / 3));
    const double b = 0.5 + 0.5 * std::sin(6.283185307179586 * (hue + 2.0 / 3));
    std::fprintf(out, " %d %d %d %u\n", int(r * 255), int(g * 255), int(b * 255), c);
  }
  const bool ok = std::fclose(out) == 0;
  if (!ok || std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    throw Failure(kExitBadInput, path + ": cannot write");
  }
}

const FlagOption kJson{"--json", "print the report as one JSON object"};
const FlagOption kCage{"--cage", "write the quad-dominant cage with creases instead of the polygons"};
const IntegerOption kFaces{"--faces", -1, 1, 2000000000, "N", "the level with N polygons (this or --vertices)"};
const IntegerOption kVertices{"--vertices", -1, 1, 2000000000, "N", "the level with N vertices (this or --faces)"};
const TextOption kClusters{"--clusters", "", "FILE.ply", "also write the input coloured by cluster"};
const RealOption kEpsilon{"--epsilon", 0.01, 0.0, 1e6, "E", "weight of the valence/angle tie-break (thesis (3.8))"};
// Polygonal output only: border vertices put back where the border strays more than REL x the
// input's bbox diagonal from a level edge (cagekit_hierarchy_get_refined_polygon_mesh).
const RealOption kContourTolerance{"--contour-tolerance", 0.0, 0.0, 1.0, "REL",
                                   "polygonal output: border vertices put back where the border strays more than "
                                   "REL x the bbox diagonal from a level edge (0: off; not with --cage)"};

int command_simplify(const Options& args) {
  const bool quiet = args.quiet();
  const bool json = args.flag(kJson);
  const bool want_cage = args.flag(kCage);
  const int faces_target = args.integer(kFaces);
  const int vertices_target = args.integer(kVertices);
  const std::string clusters_path = args.text(kClusters);
  const cagekit_cage_options cage_options = parse_cage_options(args);
  const double epsilon = args.real(kEpsilon);
  const double contour_tolerance = args.real(kContourTolerance);
  const std::vector<std::string> files = {args.positional("IN"), args.positional("OUT")};
  if ((faces_target < 0) == (vertices_target < 0)) throw Failure(kExitUsage, "simplify needs one of --faces N or --vertices N");
  if (contour_tolerance > 0 && want_cage)
    throw Failure(kExitUsage, "--contour-tolerance refines the polygonal level; it does not apply with --cage");
  const cagekit_file_format out_format = format_from_extension(files[1]);
  const auto start = std::chrono::steady_clock::now();

  Session session(quiet);
  const cagekit::Mesh input = session.run(files[0], [&] { return session.context().read_mesh(files[0]); });
  cagekit_simplify_options options = cagekit::defaults<cagekit_simplify_options>();
  options.tie_break_epsilon = epsilon;
  cagekit::Hierarchy hierarchy = session.run(files[0], [&] { return input.create_hierarchy(options); });
  const uint32_t level = session.run(files[0], [&] {
    const uint32_t found = faces_target > 0 ? hierarchy.find_level(CAGEKIT_LEVEL_BY_FACES, faces_target)
                                            : hierarchy.find_level(CAGEKIT_LEVEL_BY_VERTICES, vertices_target);
    hierarchy.set_level(found);
    return found;
  });
  const double simplify_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const cagekit_polygonal_level_info info = session.run(files[0], [&] { return hierarchy.current_info(); });

  cagekit_cage_report cage_report = cagekit::defaults<cagekit_cage_report>();
  cagekit::Mesh output_mesh;
  cagekit_write_options write = cagekit::defaults<cagekit_write_options>();
  write.format = out_format;
  if (want_cage) {
    const cagekit::Cage cage =
        session.run(files[0], [&] { return hierarchy.build_cage(cage_options, &cage_report); });
    session.run(files[1], [&] { cage.write_file(files[1], write); });
    output_mesh = session.run(files[1], [&] { return cage.mesh(); });
  } else {
    output_mesh = session.run(files[0], [&] {
      return contour_tolerance > 0 ? hierarchy.refined_polygon_mesh(contour_tolerance) : hierarchy.polygon_mesh();
    });
    session.run(files[1], [&] { output_mesh.write_file(files[1], write); });
  }
  if (!clusters_path.empty()) {
    const std::vector<uint32_t> clusters = session.run(files[0], [&] { return hierarchy.clusters(); });
    write_clusters_ply(session, input, clusters, clusters_path);
  }
  const cagekit_approximation_error error = session.run(files[0], [&] { return input.measure_error(output_mesh); });
  const cagekit_mesh_info out_info = session.run(files[1], [&] { return output_mesh.info(); });
  session.finish_progress();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const unsigned long long quads = want_cage ? cage_report.quads : out_info.quads;
  const unsigned long long triangles = want_cage ? cage_report.triangles : out_info.triangles;
  const unsigned long long pentagons = want_cage ? cage_report.pentagons : 0ull;
  if (json) {
    nlohmann::ordered_json j;
    j["level"] = level;
    j["polygons"] = uint64_t(info.faces);
    j["faces"] = uint64_t(out_info.faces);
    j["vertices"] = uint64_t(out_info.vertices);
    j["quads"] = quads;
    j["triangles"] = triangles;
    j["pentagons"] = pentagons;
    j["other_polygons"] = uint64_t(want_cage ? cage_report.other_polygons : out_info.other_polygons);
    j["faces_with_holes"] = uint64_t(info.faces_with_holes);
    j["invalid_faces"] = uint64_t(info.invalid_faces + (want_cage ? cage_report.other_polygons : 0));
    j["non_manifold_edges"] = uint64_t(want_cage ? cage_report.non_manifold_edges : 0);
    j["creases"] = uint64_t(want_cage ? cage_report.creases : 0);
    j["l2_error"] = json_rounded(info.l2_error, "%.9g");
    j["l21_error"] = json_rounded(info.l21_error, "%.9g");
    j["hausdorff_rel"] = json_rounded(error.hausdorff_rel, "%.9g");
    j["hausdorff_sym_rel"] = json_rounded(error.hausdorff_sym_rel, "%.9g");
    j["mean_rel"] = json_rounded(error.mean_rel, "%.9g");
    j["simplify_seconds"] = json_rounded(simplify_seconds, "%.3f");
    j["seconds"] = json_rounded(seconds, "%.3f");
    std::printf("%s\n", json_text(j).c_str());
  } else if (!quiet) {
    std::printf("%s -> %s: level %u, %llu polygons (%llu with holes) -> %llu faces (%llu quads, %llu triangles, "
                "%llu pentagons), %llu creases, Hausdorff %.3g of the diagonal, %.2f s\n",
                files[0].c_str(), files[1].c_str(), level, (unsigned long long)info.faces,
                (unsigned long long)info.faces_with_holes, (unsigned long long)out_info.faces, quads, triangles,
                pentagons, (unsigned long long)(want_cage ? cage_report.creases : 0), error.hausdorff_rel, seconds);
  }
  return kExitOk;
}

}  // namespace

Command add_simplify(CLI::App& cagekit) {
  CLI::App* app = cagekit.add_subcommand(
      "simplify", "structure-preserving simplification (thesis ch. 3) to polygons or a quad-dominant cage");
  auto options = std::make_shared<Options>(app);
  options->add_positional("IN", "mesh file");
  options->add_positional("OUT", "output file (.obj .ply .off .drc)");
  options->add(kFaces);
  options->add(kVertices);
  options->add(kCage);
  options->add(kClusters);
  add_cage_options(*options);
  options->add(kEpsilon);
  options->add(kContourTolerance);
  options->add(kJson);
  options->add_quiet();
  return {app, [options] { return command_simplify(*options); }};
}

}  // namespace cli
