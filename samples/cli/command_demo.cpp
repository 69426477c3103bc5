// SPDX-License-Identifier: GPL-3.0-or-later
// cagekit demo [OUTDIR]: runs what the SDK can do today on a generated noisy scan of a CAD-like
// part and writes every result to OUTDIR (default ./cagekit-demo). Later stages of the pipeline
// (simplification, fitting, editing) extend this as they land.
#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>

#include "cli_context.h"
#include "demo_part.h"

namespace cli {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void make_directory(const std::string& path) {
  if (mkdir(path.c_str(), 0755) != 0 && errno != EEXIST)
    throw Failure(kExitBadInput, path + ": cannot create directory: " + std::strerror(errno));
}

// The structure of the part as a Catmull-Clark cage: the block's 8 corners, 6 quads, and its
// 12 feature edges tagged infinitely sharp, so the limit surface is the block itself.
void make_block_cage(const Session& session, const double size[3], Cage* cage) {
  double p[8 * 3];
  for (int i = 0; i < 8; ++i)
    for (int k = 0; k < 3; ++k) p[3 * i + k] = ((i >> k) & 1) ? size[k] : 0.0;
  const uint32_t quads[24] = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};
  cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
  desc.vertex_count = 8;
  desc.positions = p;
  desc.face_count = 6;
  desc.uniform_face_size = 4;
  desc.face_indices = quads;
  Mesh mesh;
  session.check(cagekit_mesh_create(session.context(), &desc, mesh.out()), "block cage");
  session.check(cagekit_cage_create(mesh.get(), cage->out()), "block cage");
  const uint32_t edges[24] = {0, 1, 2, 3, 4, 5, 6, 7, 0, 2, 1, 3, 4, 6, 5, 7, 0, 4, 1, 5, 2, 6, 3, 7};
  session.check(cagekit_cage_set_creases(cage->get(), 12, edges, nullptr), "block cage");
}

}  // namespace

int command_demo(Args& args) {
  const bool quiet = args.flag("--quiet");
  const auto rest = args.positional(0, 1, "cagekit demo [OUTDIR] [--quiet]");
  const std::string dir = rest.empty() ? "cagekit-demo" : rest[0];
  make_directory(dir);
  Session session(quiet);
  const auto start = std::chrono::steady_clock::now();

  // 1. The input: a noisy scan of a 4 x 2.5 x 1.5 block, ~60 cells per unit.
  const double size[3] = {4.0, 2.5, 1.5};
  const double diagonal = std::sqrt(size[0] * size[0] + size[1] * size[1] + size[2] * size[2]);
  const DemoPart part = make_demo_part(size, 24, 2e-4 * diagonal, 20061113u);
  cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
  desc.vertex_count = static_cast<uint32_t>(part.positions.size() / 3);
  desc.positions = part.positions.data();
  desc.face_count = static_cast<uint32_t>(part.triangles.size() / 3);
  desc.uniform_face_size = 3;
  desc.face_indices = part.triangles.data();
  Mesh scan;
  session.check(cagekit_mesh_create(session.context(), &desc, scan.out()), "demo scan");
  cagekit_validation_report validation = {};
  validation.struct_size = sizeof(validation);
  session.check(cagekit_mesh_validate(scan.get(), &validation), "demo scan");

  // 2. Exchange: OBJ, binary PLY, Draco at 14 bits.
  cagekit_write_options write = CAGEKIT_WRITE_OPTIONS_INIT;
  cagekit_write_report obj_report = {sizeof(cagekit_write_report), 0, 0.0};
  cagekit_write_report drc_report = obj_report;
  session.check(cagekit_mesh_write_file(scan.get(), (dir + "/scan.obj").c_str(), &write, &obj_report), "scan.obj");
  session.check(cagekit_mesh_write_file(scan.get(), (dir + "/scan.ply").c_str(), &write, nullptr), "scan.ply");
  session.check(cagekit_mesh_write_file(scan.get(), (dir + "/scan.drc").c_str(), &write, &drc_report), "scan.drc");

  // 3. The cage. Until simplification lands (thesis ch. 3), the demo uses the part's known
  //    structure: the block with its 12 feature edges tagged as creases.
  Cage cage;
  make_block_cage(session, size, &cage);
  session.check(cagekit_cage_write_file(cage.get(), (dir + "/cage.obj").c_str(), &write, nullptr), "cage.obj");
  session.check(cagekit_cage_write_file(cage.get(), (dir + "/cage.drc").c_str(), &write, nullptr), "cage.drc");

  // 4. Subdivision: the creased cage at level 3 (its limit is the block), and the scan used
  //    directly as a cage at level 1 pushed to its limit surface.
  cagekit_subdivide_options subdivide = CAGEKIT_SUBDIVIDE_OPTIONS_INIT;
  subdivide.levels = 3;
  Cage cage_level3;
  session.check(cagekit_cage_subdivide(cage.get(), &subdivide, cage_level3.out()), "cage");
  session.check(cagekit_cage_write_file(cage_level3.get(), (dir + "/cage_level3.obj").c_str(), &write, nullptr),
                "cage_level3.obj");
  Cage scan_cage, scan_level1;
  session.check(cagekit_cage_create(scan.get(), scan_cage.out()), "demo scan");
  subdivide.levels = 1;
  subdivide.limit_positions = 1;
  const auto subdivide_start = std::chrono::steady_clock::now();
  session.check(cagekit_cage_subdivide(scan_cage.get(), &subdivide, scan_level1.out()), "demo scan");
  const double subdivide_seconds = seconds_since(subdivide_start);
  session.check(cagekit_cage_write_file(scan_level1.get(), (dir + "/scan_level1_limit.obj").c_str(), &write, nullptr),
                "scan_level1_limit.obj");
  session.finish_progress();

  cagekit_mesh_info scan_info = {}, level3_info = {}, level1_info = {};
  scan_info.struct_size = level3_info.struct_size = level1_info.struct_size = sizeof(cagekit_mesh_info);
  session.check(cagekit_mesh_get_info(scan.get(), &scan_info), "demo scan");
  session.check(cagekit_cage_get_info(cage_level3.get(), &level3_info), "cage_level3");
  session.check(cagekit_cage_get_info(scan_level1.get(), &level1_info), "scan level 1");

  const std::string summary_path = dir + "/summary.json";
  FILE* summary = std::fopen(summary_path.c_str(), "w");
  if (!summary) throw Failure(kExitBadInput, summary_path + ": cannot write: " + std::strerror(errno));
  std::fprintf(summary,
               "{\n  \"scan\": {\"vertices\": %llu, \"triangles\": %llu, \"genus\": %lld, \"manifold\": %s, "
               "\"valid\": %s, \"bbox_diagonal\": %.9g},\n"
               "  \"exchange\": {\"obj_bytes\": %llu, \"drc_bytes\": %llu, \"drc_ratio\": %.2f, "
               "\"drc_max_error_rel\": %.3g},\n"
               "  \"cage\": {\"faces\": 6, \"creases\": 12, \"level3_quads\": %llu, \"level3_creases\": %llu},\n"
               "  \"scan_as_cage_level1\": {\"quads\": %llu, \"seconds\": %.3f},\n"
               "  \"seconds\": %.3f,\n"
               "  \"not_yet\": [\"simplification (ch. 3)\", \"fitting (ch. 7)\", \"multiresolution editing (ch. 8)\"]\n}\n",
               (unsigned long long)scan_info.vertices, (unsigned long long)scan_info.triangles,
               (long long)scan_info.genus, scan_info.manifold ? "true" : "false", validation.valid ? "true" : "false",
               scan_info.bbox_diagonal, (unsigned long long)obj_report.bytes, (unsigned long long)drc_report.bytes,
               drc_report.bytes ? double(obj_report.bytes) / double(drc_report.bytes) : 0.0,
               drc_report.max_position_error / scan_info.bbox_diagonal, (unsigned long long)level3_info.quads,
               (unsigned long long)level3_info.creases, (unsigned long long)level1_info.quads, subdivide_seconds,
               seconds_since(start));
  std::fclose(summary);

  std::printf("CageKit demo -> %s/\n", dir.c_str());
  std::printf("  scan.obj/.ply/.drc     noisy scan of a block: %llu vertices, %llu triangles, genus %lld, %s\n",
              (unsigned long long)scan_info.vertices, (unsigned long long)scan_info.triangles,
              (long long)scan_info.genus, validation.valid ? "valid" : "INVALID");
  std::printf("  Draco 14 bit           %llu bytes vs OBJ %llu bytes (%.1fx smaller), max error %.2g of the diagonal\n",
              (unsigned long long)drc_report.bytes, (unsigned long long)obj_report.bytes,
              drc_report.bytes ? double(obj_report.bytes) / double(drc_report.bytes) : 0.0,
              drc_report.max_position_error / scan_info.bbox_diagonal);
  std::printf("  cage.obj/.drc          block cage: 6 quads, 12 crease edges\n");
  std::printf("  cage_level3.obj        level 3: %llu quads, %llu crease edges\n",
              (unsigned long long)level3_info.quads, (unsigned long long)level3_info.creases);
  std::printf("  scan_level1_limit.obj  scan as cage, level 1 on the limit: %llu quads in %.3f s\n",
              (unsigned long long)level1_info.quads, subdivide_seconds);
  std::printf("  summary.json           these numbers\n");
  return kExitOk;
}

}  // namespace cli
