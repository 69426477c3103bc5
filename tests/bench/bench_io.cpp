// SPDX-License-Identifier: GPL-3.0-or-later
// bench_io: mesh file I/O, CageKit against the peers, in one process on the same meshes:
//   * OBJ read   cagekit::read_cage_from_file        vs OpenMesh::IO::read_mesh (TriMesh, double points)
//   * OBJ write  cagekit::write_cage_to_file (9 digits) vs OpenMesh::IO::write_mesh (precision 9)
//   * Draco      cagekit::write_cage_to_memory / read_cage_from_memory (14 bits, speed 5)
//                vs plain draco::Encoder::EncodeMeshToBuffer / Decoder::DecodeMeshFromBuffer on the
//                same triangles (positions only, 14 bits, SetSpeedOptions(5, 5))
// Meshes: fandisk, the Stanford bunny, and a ~1.1M-triangle mesh generated here: the bunny
// (unreferenced vertices removed) Loop-subdivided twice with OpenMesh's LoopT, each vertex moved
// along its normal by seeded Gaussian noise of sigma = 1e-4 of the bounding-box diagonal (as in
// ../shared/README.md); it is written to a temporary OBJ with CageKit for the read benchmark.
// Method (as in ../shared/spec/peer-measurements.md §5): steady_clock around the library call
// only (the input already in each library's structure; files in the page cache), 1 warm-up run
// of each variant (its peak RSS above the RSS before it is reported; VmHWM reset through
// /proc/self/clear_refs), then 5 rounds (3 for the 1.1M mesh) running CageKit and the peer in
// turn, median of each. Never fails on timing.
#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/core/draco_version.h>
#include <draco/mesh/mesh.h>
#include <malloc.h>
#include <unistd.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "core/cage.h"
#include "core/io/mesh_io.h"
#include "core/mesh_repair.h"
#include "core/status.h"

#include "bench_support.h"

namespace {

using bench::cpu_seconds;
using bench::load_average;
using bench::seconds_since;
using bench::status_kib;

using Clock = std::chrono::steady_clock;

using bench::dense_bunny;
using bench::OmMesh;
using bench::to_openmesh;

// --- measurement helpers (each benchmark is self-contained) ---





struct Timing {
  double median_s = 0;    // wall
  double median_cpu = 0;  // process CPU time
  double peak_mib = 0;
};

// "wall ratio (CPU-time ratio)"
std::string ratio(const Timing& a, const Timing& b) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.2f (%.2f)", a.median_s / b.median_s, a.median_cpu / b.median_cpu);
  return buf;
}

// Each variant once as a warm-up (its peak RSS above the RSS before it, after malloc_trim and a
// VmHWM reset), then `runs` rounds that run every variant once in turn; the median per variant.
std::vector<Timing> measure_interleaved(int runs, const std::vector<std::function<void()>>& variants) {
  std::vector<Timing> t(variants.size());
  for (size_t i = 0; i < variants.size(); ++i) {
    malloc_trim(0);
    std::ofstream("/proc/self/clear_refs") << "5";
    const long start_kib = status_kib("VmRSS");
    variants[i]();
    t[i].peak_mib = (status_kib("VmHWM") - start_kib) / 1024.0;
  }
  std::vector<std::vector<double>> times(variants.size()), cpu(variants.size());
  for (int round = 0; round < runs; ++round)
    for (size_t i = 0; i < variants.size(); ++i) {
      const auto start = Clock::now();
      const double cpu0 = cpu_seconds();
      variants[i]();
      times[i].push_back(seconds_since(start));
      cpu[i].push_back(cpu_seconds() - cpu0);
    }
  for (size_t i = 0; i < variants.size(); ++i) {
    std::sort(times[i].begin(), times[i].end());
    std::sort(cpu[i].begin(), cpu[i].end());
    t[i].median_s = times[i][times[i].size() / 2];
    t[i].median_cpu = cpu[i][cpu[i].size() / 2];
  }
  return t;
}

std::string shared_mesh(const char* name) {
  const std::string path = std::string(CAGEKIT_SHARED_MESHES) + "/" + name;
  return std::ifstream(path).good() ? path : std::string();
}

[[noreturn]] void die(const std::string& message) {
  std::fprintf(stderr, "bench_io: %s\n", message.c_str());
  std::exit(2);
}

// --- conversions (outside the timed regions) ---

// Positions only (float32), identity point mapping, the same triangles in the same order.
std::unique_ptr<draco::Mesh> to_draco(const cagekit::PolygonMesh& mesh) {
  auto d = std::make_unique<draco::Mesh>();
  d->set_num_points(static_cast<uint32_t>(mesh.num_vertices()));
  draco::GeometryAttribute position;
  position.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, 12, 0);
  draco::PointAttribute* pos = d->attribute(d->AddAttribute(position, true, static_cast<uint32_t>(mesh.num_vertices())));
  for (size_t v = 0; v < mesh.num_vertices(); ++v) {
    const float xyz[3] = {float(mesh.positions[v].x), float(mesh.positions[v].y), float(mesh.positions[v].z)};
    pos->SetAttributeValue(draco::AttributeValueIndex(static_cast<uint32_t>(v)), xyz);
  }
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    if (mesh.face_size(f) != 3) die("the Draco peer takes triangles only");
    d->AddFace({draco::PointIndex(mesh.face_vertex(f, 0)), draco::PointIndex(mesh.face_vertex(f, 1)),
                draco::PointIndex(mesh.face_vertex(f, 2))});
  }
  return d;
}

// --- the benchmark ---

struct Input {
  std::string label;
  std::string obj_path;          // file for the OBJ read benchmark
  cagekit::Cage cage;            // what the writers get (and the Draco peer, as triangles)
  std::string note;
  int runs = 5;
};

struct Rows {
  std::string label;
  size_t v = 0, f = 0, obj_bytes = 0;
  size_t ck_read_v = 0, ck_read_f = 0, om_read_v = 0, om_read_f = 0;
  Timing ck_read, om_read, ck_write, om_write;
  size_t ck_obj_out = 0, om_obj_out = 0;
  Timing ck_drc_write, drc_encode, ck_drc_read, drc_decode;
  size_t ck_drc_bytes = 0, drc_bytes = 0;
  double ck_drc_error = 0, diag = 0;
  int runs = 0;
};

Rows run(const Input& in, const std::string& tmp) {
  Rows r;
  r.label = in.label;
  r.runs = in.runs;
  r.v = in.cage.mesh.num_vertices();
  r.f = in.cage.mesh.num_faces();
  r.diag = in.cage.mesh.bounding_box().diagonal();
  r.obj_bytes = std::filesystem::file_size(in.obj_path);
  std::printf("%s: OBJ %s (%.1f MB); writers get %zu vertices, %zu faces\n", in.label.c_str(), in.obj_path.c_str(),
              r.obj_bytes / 1e6, r.v, r.f);
  std::fflush(stdout);

  // OBJ read.
  std::vector<Timing> t = measure_interleaved(in.runs, {
      [&] {
        const cagekit::Cage c = cagekit::read_cage_from_file(in.obj_path, cagekit::FileFormat::obj);
        r.ck_read_v = c.mesh.num_vertices();
        r.ck_read_f = c.mesh.num_faces();
      },
      [&] {
        OmMesh m;
        OpenMesh::IO::Options options;
        if (!OpenMesh::IO::read_mesh(m, in.obj_path, options)) die("OpenMesh could not read " + in.obj_path);
        r.om_read_v = m.n_vertices();
        r.om_read_f = m.n_faces();
      },
  });
  r.ck_read = t[0];
  r.om_read = t[1];

  // OBJ write (same mesh, 9 significant digits for both).
  const std::string ck_obj = tmp + "/cagekit.obj", om_obj = tmp + "/openmesh.obj";
  cagekit::WriteOptions obj_options;
  obj_options.format = cagekit::FileFormat::obj;
  obj_options.obj_precision = 9;
  const OmMesh om = to_openmesh(in.cage.mesh);
  t = measure_interleaved(in.runs, {
      [&] { cagekit::write_cage_to_file(ck_obj, in.cage, obj_options); },
      [&] {
        if (!OpenMesh::IO::write_mesh(om, om_obj, OpenMesh::IO::Options::Default, 9)) die("OpenMesh could not write");
      },
  });
  r.ck_write = t[0];
  r.om_write = t[1];
  r.ck_obj_out = std::filesystem::file_size(ck_obj);
  r.om_obj_out = std::filesystem::file_size(om_obj);
  std::filesystem::remove(ck_obj);
  std::filesystem::remove(om_obj);
  std::printf("  OBJ done\n");
  std::fflush(stdout);

  // Draco write / read.
  cagekit::WriteOptions drc_options;
  drc_options.format = cagekit::FileFormat::draco;
  drc_options.draco_position_bits = 14;
  drc_options.draco_speed = 5;
  std::vector<uint8_t> ck_bytes;
  cagekit::WriteReport report;
  const std::unique_ptr<draco::Mesh> dmesh = to_draco(in.cage.mesh);
  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
  encoder.SetSpeedOptions(5, 5);
  draco::EncoderBuffer encoded;
  t = measure_interleaved(in.runs, {
      [&] { ck_bytes = cagekit::write_cage_to_memory(in.cage, drc_options, &report); },
      [&] {
        encoded.Clear();
        const draco::Status s = encoder.EncodeMeshToBuffer(*dmesh, &encoded);
        if (!s.ok()) die("draco encode: " + s.error_msg_string());
      },
  });
  r.ck_drc_write = t[0];
  r.drc_encode = t[1];
  r.ck_drc_bytes = ck_bytes.size();
  r.ck_drc_error = report.max_position_error;
  r.drc_bytes = encoded.size();

  size_t back_f = 0, decoded_f = 0;
  t = measure_interleaved(in.runs, {
      [&] {
        const cagekit::Cage c = cagekit::read_cage_from_memory(ck_bytes.data(), ck_bytes.size(),
                                                               cagekit::FileFormat::draco, "<memory>");
        back_f = c.mesh.num_faces();
      },
      [&] {
        draco::DecoderBuffer buffer;
        buffer.Init(encoded.data(), encoded.size());
        draco::Decoder decoder;
        auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
        if (!decoded.ok()) die("draco decode: " + decoded.status().error_msg_string());
        decoded_f = decoded.value()->num_faces();
      },
  });
  r.ck_drc_read = t[0];
  r.drc_decode = t[1];
  if (back_f != r.f) die(in.label + ": CageKit's Draco stream came back with another face count");
  if (decoded_f != r.f) die(in.label + ": plain Draco came back with another face count");
  std::printf("  Draco done\n");
  std::fflush(stdout);
  return r;
}

std::string ms(double seconds) {
  char b[32];
  std::snprintf(b, sizeof b, seconds < 0.01 ? "%.2f" : seconds < 1 ? "%.1f" : "%.0f", seconds * 1e3);
  return b;
}

}  // namespace

int main() {
  omlog().disable();  // OpenMesh's OBJ writer logs every file it writes
  std::printf("## bench_io: OBJ and Draco I/O, CageKit vs OpenMesh %d.%d and Draco %s\n\n", OM_GET_VER, OM_GET_MAJ,
              draco::kDracoVersion);
  std::printf("load average at start: %s\n", load_average().c_str());
  const std::filesystem::path tmp =
      std::filesystem::temp_directory_path() / ("cagekit-bench-io-" + std::to_string(::getpid()));
  std::filesystem::create_directories(tmp);

  std::vector<Input> inputs;
  std::vector<std::string> notes;
  const std::string fandisk = shared_mesh("fandisk.obj");
  if (fandisk.empty())
    std::printf("skipped fandisk: %s/fandisk.obj not found\n", CAGEKIT_SHARED_MESHES);
  else
    inputs.push_back({"fandisk", fandisk, cagekit::read_cage_from_file(fandisk), "", 5});

  const std::string bunny_path = shared_mesh("stanford-bunny.obj");
  if (bunny_path.empty()) {
    std::printf("skipped bunny and bunny-1.1M: %s/stanford-bunny.obj not found\n", CAGEKIT_SHARED_MESHES);
  } else {
    cagekit::Cage bunny = cagekit::read_cage_from_file(bunny_path);
    cagekit::RepairOptions repair;
    repair.weld_tolerance = -1;
    repair.drop_invalid_faces = repair.drop_degenerate_faces = repair.drop_duplicate_faces = false;
    repair.split_non_manifold = repair.orient_consistently = false;
    repair.remove_unreferenced_vertices = true;
    cagekit::RepairReport report;
    const size_t file_vertices = bunny.mesh.num_vertices();
    bunny.mesh = cagekit::repair_mesh(bunny.mesh, repair, &report);
    notes.push_back("bunny: the OBJ read rows read the file as it is (" + std::to_string(file_vertices) +
                    " vertices); the write and Draco rows use it without its " +
                    std::to_string(report.removed_unreferenced_vertices) +
                    " unreferenced vertices (the same triangles for every library)");

    std::printf("generating bunny-1.1M (Loop x2 + noise) ...\n");
    std::fflush(stdout);
    const auto start = Clock::now();
    cagekit::Cage dense;
    dense.mesh = dense_bunny(bunny.mesh);
    const std::string dense_path = (tmp / "bunny-1.1M.obj").string();
    cagekit::WriteOptions obj_options;
    obj_options.format = cagekit::FileFormat::obj;
    obj_options.obj_precision = 9;
    cagekit::write_cage_to_file(dense_path, dense, obj_options);
    std::printf("  %zu vertices, %zu triangles, generated and written in %.1f s (not part of any table)\n",
                dense.mesh.num_vertices(), dense.mesh.num_faces(), seconds_since(start));
    inputs.push_back({"bunny", bunny_path, std::move(bunny), "", 5});
    inputs.push_back({"bunny-1.1M", dense_path, std::move(dense), "", 3});
  }

  std::vector<Rows> rows;
  for (const Input& in : inputs) rows.push_back(run(in, tmp.string()));
  std::filesystem::remove_all(tmp);

  std::printf("\nOBJ read (from the page cache into each library's own structure):\n\n");
  std::printf("| mesh | OBJ MB | V / F read: CageKit | V / F read: OpenMesh | CageKit ms | OpenMesh ms | ratio CageKit / "
              "OpenMesh (by CPU time) | CageKit MB/s | peak RSS MiB CageKit / OpenMesh |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  for (const Rows& r : rows)
    std::printf("| %s | %.1f | %zu / %zu | %zu / %zu | %s | %s | %s | %.0f | %.0f / %.0f |\n", r.label.c_str(),
                r.obj_bytes / 1e6, r.ck_read_v, r.ck_read_f, r.om_read_v, r.om_read_f, ms(r.ck_read.median_s).c_str(),
                ms(r.om_read.median_s).c_str(), ratio(r.ck_read, r.om_read).c_str(),
                r.obj_bytes / 1e6 / r.ck_read.median_s, r.ck_read.peak_mib, r.om_read.peak_mib);

  std::printf("\nOBJ write (9 significant digits, to a file):\n\n");
  std::printf("| mesh | V / F | CageKit ms | OpenMesh ms | ratio CageKit / OpenMesh (by CPU time) | bytes CageKit / OpenMesh |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (const Rows& r : rows)
    std::printf("| %s | %zu / %zu | %s | %s | %s | %zu / %zu |\n", r.label.c_str(), r.v, r.f,
                ms(r.ck_write.median_s).c_str(), ms(r.om_write.median_s).c_str(), ratio(r.ck_write, r.om_write).c_str(),
                r.ck_obj_out, r.om_obj_out);

  std::printf("\nDraco, 14 bits, speed 5 (in memory):\n\n");
  std::printf("| mesh | V / F | CageKit write ms | Draco encode ms | ratio (by CPU time) | CageKit read ms | Draco decode ms | ratio (by "
              "CPU time) | "
              "CageKit bytes | Draco bytes | CageKit / Draco size | CageKit max position error / diag | peak RSS "
              "MiB write CageKit / Draco |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Rows& r : rows)
    std::printf("| %s | %zu / %zu | %s | %s | %s | %s | %s | %s | %zu | %zu | %.2f (+%.0f%%) | %.1e | %.0f / %.0f |\n",
                r.label.c_str(), r.v, r.f, ms(r.ck_drc_write.median_s).c_str(), ms(r.drc_encode.median_s).c_str(),
                ratio(r.ck_drc_write, r.drc_encode).c_str(), ms(r.ck_drc_read.median_s).c_str(),
                ms(r.drc_decode.median_s).c_str(), ratio(r.ck_drc_read, r.drc_decode).c_str(), r.ck_drc_bytes,
                r.drc_bytes, double(r.ck_drc_bytes) / r.drc_bytes, 100.0 * (double(r.ck_drc_bytes) / r.drc_bytes - 1),
                r.ck_drc_error / r.diag, r.ck_drc_write.peak_mib, r.drc_encode.peak_mib);

  std::printf("\nTimes: median of %d interleaved rounds (%d for bunny-1.1M) after 1 warm-up run of each; peak RSS: the warm-up run, above the "
              "RSS before it. CageKit's Draco stream also restores the exact vertex order, face order, polygons and "
              "first corners (plain Draco reorders vertices and triangles).\n",
              5, 3);
  std::printf("Ratios: wall-time ratio, in parentheses the ratio of process CPU times (the same on an idle machine; "
              "closer to the truth under load). Load average at the end: %s.\n",
              load_average().c_str());
  for (const std::string& note : notes) std::printf("Note: %s.\n", note.c_str());
  std::printf("\n");
  return 0;
}
