// SPDX-License-Identifier: GPL-3.0-or-later
// bench_subdivide: uniform Catmull-Clark refinement of real meshes used as cages (no tags) to
// levels 1, 2, 3, in one process on the same input:
//   * CageKit C++   cagekit::refine_uniform (sdk/subdiv/uniform_refinement.h)
//   * CageKit C API cagekit_cage_subdivide (<cagekit/cagekit.h>, libcagekit.so)
//   * peer          raw OpenSubdiv 3.5: Far::TopologyRefinerFactory<TopologyDescriptor>::Create +
//                   RefineUniform + PrimvarRefinerReal<double>::Interpolate level by level into
//                   a caller-owned double xyz vertex buffer (the OpenSubdiv tutorial pattern)
//   * the peer again with UniformOptions::fullTopologyInLastLevel, which CageKit sets (it reads the
//     last level's edges for the crease tags): the same work as CageKit inside OpenSubdiv
// Method (as in ../shared/spec/peer-measurements.md): in-process steady_clock around the library
// call only (the input is already in each library's own structure; the result is freed inside
// the timed call for every variant), 1 warm-up run of each variant, then 5 rounds that run every
// variant once in turn, median per variant; peak RSS of the warm-up run above the RSS just before
// it (VmHWM after resetting it through /proc/self/clear_refs). Output face counts must be equal
// (exit 1 otherwise); positions of CageKit and OpenSubdiv are compared (same vertex order).
// Never fails on timing.
#include <cagekit/cagekit.h>
#include <malloc.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <opensubdiv/version.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/cage.h"
#include "core/io/mesh_io.h"
#include "core/mesh_repair.h"
#include "core/mesh_validation.h"
#include "core/status.h"
#include "subdiv/uniform_refinement.h"

#include "bench_support.h"

namespace {

using bench::cpu_seconds;
using bench::load_average;
using bench::seconds_since;
using bench::status_kib;

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;
using Clock = std::chrono::steady_clock;

constexpr int kRuns = 5;

// --- measurement helpers (each benchmark is self-contained) ---





// Peak RSS of a region above the RSS at its start, in MiB: malloc_trim, reset VmHWM to the
// current RSS (writing "5" to /proc/self/clear_refs, Linux >= 4.0), run, read VmHWM.
struct PeakRss {
  long start_kib = 0;
  bool reset_ok = false;
  void begin() {
    malloc_trim(0);
    std::ofstream clear("/proc/self/clear_refs");
    clear << "5";
    clear.close();
    reset_ok = static_cast<bool>(clear);
    start_kib = status_kib("VmRSS");
  }
  double mib_above_start() const { return (status_kib("VmHWM") - start_kib) / 1024.0; }
};

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

// Each variant once as a warm-up (its peak RSS measured alone), then kRuns rounds that run every
// variant once in turn (so machine load and heap state drift hit all of them alike); the
// median per variant. Each run's result is destroyed inside its own run.
std::vector<Timing> measure_interleaved(const std::vector<std::function<void()>>& variants) {
  std::vector<Timing> t(variants.size());
  for (size_t i = 0; i < variants.size(); ++i) {
    PeakRss rss;
    rss.begin();
    variants[i]();
    t[i].peak_mib = rss.mib_above_start();
  }
  std::vector<std::vector<double>> times(variants.size()), cpu(variants.size());
  for (int round = 0; round < kRuns; ++round)
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

// --- the peer: raw OpenSubdiv ---

struct OsdVertex {
  double x = 0, y = 0, z = 0;
  void Clear() { x = y = z = 0; }
  void AddWithWeight(const OsdVertex& s, double w) {
    x += w * s.x;
    y += w * s.y;
    z += w * s.z;
  }
};

// The peer's own input arrays (made once, outside the timed region).
struct OsdInput {
  std::vector<int> sizes, indices;
  std::vector<OsdVertex> points;
};

OsdInput osd_input(const cagekit::PolygonMesh& mesh) {
  OsdInput in;
  for (size_t f = 0; f < mesh.num_faces(); ++f) in.sizes.push_back(static_cast<int>(mesh.face_size(f)));
  in.indices.assign(mesh.face_vertices.begin(), mesh.face_vertices.end());
  for (const cagekit::Vec3& p : mesh.positions) in.points.push_back({p.x, p.y, p.z});
  return in;
}

struct OsdResult {
  std::unique_ptr<Far::TopologyRefiner> refiner;
  std::vector<OsdVertex> vertices;  // all levels, level 0 first
  size_t last_level_offset = 0;
};

OsdResult osd_refine(const OsdInput& in, int levels, bool full_topology_in_last_level = false) {
  Far::TopologyDescriptor desc;
  desc.numVertices = static_cast<int>(in.points.size());
  desc.numFaces = static_cast<int>(in.sizes.size());
  desc.numVertsPerFace = in.sizes.data();
  desc.vertIndicesPerFace = in.indices.data();
  Sdc::Options sdc;  // the same scheme options as CageKit's default cage
  sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  sdc.SetCreasingMethod(Sdc::Options::CREASE_UNIFORM);
  sdc.SetTriangleSubdivision(Sdc::Options::TRI_SUB_CATMARK);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  OsdResult r;
  r.refiner.reset(Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdc)));
  Far::TopologyRefiner::UniformOptions uniform(levels);
  uniform.fullTopologyInLastLevel = full_topology_in_last_level;
  r.refiner->RefineUniform(uniform);
  r.vertices.resize(static_cast<size_t>(r.refiner->GetNumVerticesTotal()));
  std::copy(in.points.begin(), in.points.end(), r.vertices.begin());
  Far::PrimvarRefinerReal<double> primvar(*r.refiner);
  OsdVertex* src = r.vertices.data();
  for (int level = 1; level <= levels; ++level) {
    OsdVertex* dst = src + r.refiner->GetLevel(level - 1).GetNumVertices();
    primvar.Interpolate(level, src, dst);
    src = dst;
  }
  r.last_level_offset = static_cast<size_t>(src - r.vertices.data());
  return r;
}

// --- CageKit through the C API ---

[[noreturn]] void capi_fail(cagekit_context ctx, const char* what, cagekit_status s) {
  std::fprintf(stderr, "bench_subdivide: %s failed: %s: %s\n", what, cagekit_status_string(s),
               cagekit_last_error_message(ctx));
  std::exit(2);
}

cagekit_cage capi_cage(cagekit_context ctx, const cagekit::PolygonMesh& mesh) {
  std::vector<uint32_t> sizes(mesh.num_faces());
  for (size_t f = 0; f < mesh.num_faces(); ++f) sizes[f] = mesh.face_size(f);
  cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
  desc.vertex_count = static_cast<uint32_t>(mesh.num_vertices());
  desc.positions = mesh.positions.data();
  desc.position_type = CAGEKIT_SCALAR_FLOAT64;
  desc.position_stride = sizeof(cagekit::Vec3);
  desc.face_count = static_cast<uint32_t>(mesh.num_faces());
  desc.face_sizes = sizes.data();
  desc.face_indices = mesh.face_vertices.data();
  cagekit_mesh m = nullptr;
  cagekit_status s = cagekit_mesh_create(ctx, &desc, &m);
  if (CAGEKIT_FAILED(s)) capi_fail(ctx, "cagekit_mesh_create", s);
  cagekit_cage cage = nullptr;
  s = cagekit_cage_create(m, &cage);
  cagekit_mesh_release(m);
  if (CAGEKIT_FAILED(s)) capi_fail(ctx, "cagekit_cage_create", s);
  return cage;
}

uint32_t capi_face_count(cagekit_context ctx, cagekit_cage cage) {
  cagekit_mesh m = nullptr;
  cagekit_status s = cagekit_cage_get_mesh(cage, &m);
  if (CAGEKIT_FAILED(s)) capi_fail(ctx, "cagekit_cage_get_mesh", s);
  uint32_t faces = 0;
  s = cagekit_mesh_get_counts(m, nullptr, &faces, nullptr);
  cagekit_mesh_release(m);
  if (CAGEKIT_FAILED(s)) capi_fail(ctx, "cagekit_mesh_get_counts", s);
  return faces;
}

struct Row {
  std::string mesh;
  int level = 0;
  size_t faces = 0;
  Timing ck, capi, osd, osd_full;
  double max_diff = 0, diag = 0;
};

std::string ms(double seconds) {
  char b[32];
  std::snprintf(b, sizeof b, seconds < 0.01 ? "%.2f" : seconds < 1 ? "%.1f" : "%.0f", seconds * 1e3);
  return b;
}

}  // namespace

int main() {
  std::printf("## bench_subdivide: uniform Catmull-Clark refinement, CageKit %s vs raw OpenSubdiv %d.%d.%d\n\n",
              cagekit_version_string(), OPENSUBDIV_VERSION_MAJOR, OPENSUBDIV_VERSION_MINOR, OPENSUBDIV_VERSION_PATCH);
  std::printf("load average at start: %s\n", load_average().c_str());
  cagekit_context ctx = nullptr;
  if (CAGEKIT_FAILED(cagekit_context_create(nullptr, &ctx))) return 2;

  struct Input {
    const char* label;
    const char* file;
  };
  const Input inputs[] = {{"fandisk", "fandisk.obj"}, {"rocker-arm", "rocker-arm.obj"}, {"bunny", "stanford-bunny.obj"}};
  std::vector<Row> rows;
  std::vector<std::string> notes;
  bool counts_ok = true;

  for (const Input& input : inputs) {
    const std::string path = shared_mesh(input.file);
    if (path.empty()) {
      std::printf("skipped %s: %s/%s not found\n", input.label, CAGEKIT_SHARED_MESHES, input.file);
      continue;
    }
    cagekit::Cage cage = cagekit::read_cage_from_file(path);
    cage.clear_tags();
    // Used as given when CageKit accepts it; repaired (unreferenced vertices removed, nothing
    // else) only if refine_uniform refuses it.
    try {
      cagekit::RefineOptions one;
      cagekit::refine_uniform(cage, one);
    } catch (const cagekit::Error& e) {
      cagekit::RepairOptions repair;
      repair.weld_tolerance = -1;
      repair.drop_invalid_faces = repair.drop_degenerate_faces = repair.drop_duplicate_faces = false;
      repair.split_non_manifold = repair.orient_consistently = false;
      repair.remove_unreferenced_vertices = true;
      cagekit::RepairReport report;
      cage.mesh = cagekit::repair_mesh(cage.mesh, repair, &report);
      notes.push_back(std::string(input.label) + ": refine_uniform refused the file as read (" + e.what() +
                      "); repaired with remove_unreferenced_vertices (" +
                      std::to_string(report.removed_unreferenced_vertices) + " vertices removed) first");
    }
    const size_t unreferenced = cagekit::validate_mesh(cage.mesh).count(cagekit::MeshIssue::unreferenced_vertex);
    if (unreferenced > 0)
      notes.push_back(std::string(input.label) + ": used as read, with its " + std::to_string(unreferenced) +
                      " unreferenced vertices (CageKit and OpenSubdiv both accept them)");
    std::printf("%s: %zu vertices, %zu faces\n", input.label, cage.mesh.num_vertices(), cage.mesh.num_faces());
    std::fflush(stdout);

    const OsdInput osd_in = osd_input(cage.mesh);
    cagekit_cage handle = capi_cage(ctx, cage.mesh);
    for (int level = 1; level <= 3; ++level) {
      Row row;
      row.mesh = input.label;
      row.level = level;
      cagekit::RefineOptions options;
      options.levels = level;
      cagekit_subdivide_options capi_options = CAGEKIT_SUBDIVIDE_OPTIONS_INIT;
      capi_options.levels = static_cast<uint32_t>(level);
      const std::vector<Timing> t = measure_interleaved({
          [&] { cagekit::refine_uniform(cage, options); },
          [&] {
            cagekit_cage out = nullptr;
            const cagekit_status s = cagekit_cage_subdivide(handle, &capi_options, &out);
            if (CAGEKIT_FAILED(s)) capi_fail(ctx, "cagekit_cage_subdivide", s);
            cagekit_cage_release(out);
          },
          [&] { osd_refine(osd_in, level); },
          [&] { osd_refine(osd_in, level, true); },
      });
      row.ck = t[0];
      row.capi = t[1];
      row.osd = t[2];
      row.osd_full = t[3];

      // Correctness, outside the timed runs: one more run of each, compared.
      uint32_t capi_faces = 0;
      {
        cagekit_cage out = nullptr;
        const cagekit_status s = cagekit_cage_subdivide(handle, &capi_options, &out);
        if (CAGEKIT_FAILED(s)) capi_fail(ctx, "cagekit_cage_subdivide", s);
        capi_faces = capi_face_count(ctx, out);
        cagekit_cage_release(out);
      }
      const cagekit::Cage ck_out = cagekit::refine_uniform(cage, options);
      const OsdResult osd_out = osd_refine(osd_in, level);
      const size_t osd_faces = static_cast<size_t>(osd_out.refiner->GetLevel(level).GetNumFaces());
      row.faces = ck_out.mesh.num_faces();
      if (row.faces != osd_faces || row.faces != capi_faces) {
        std::fprintf(stderr, "bench_subdivide: %s level %d: face counts differ: CageKit %zu, C API %u, OpenSubdiv %zu\n",
                     input.label, level, row.faces, capi_faces, osd_faces);
        counts_ok = false;
      }
      const size_t n = std::min(ck_out.mesh.num_vertices(), osd_out.vertices.size() - osd_out.last_level_offset);
      for (size_t i = 0; i < n; ++i) {
        const cagekit::Vec3& a = ck_out.mesh.positions[i];
        const OsdVertex& b = osd_out.vertices[osd_out.last_level_offset + i];
        row.max_diff = std::max({row.max_diff, std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - b.z)});
      }
      row.diag = cage.mesh.bounding_box().diagonal();
      std::printf("  level %d: %zu faces (CageKit %zu, C API %u, OpenSubdiv %zu)\n", level, row.faces, row.faces,
                  capi_faces, osd_faces);
      std::fflush(stdout);
      rows.push_back(row);
    }
    cagekit_cage_release(handle);
  }
  cagekit_context_release(ctx);

  std::printf("\n| mesh | level | output quads (all equal) | CageKit C++ `refine_uniform` ms | C API "
              "`cagekit_cage_subdivide` ms | OpenSubdiv ms | C++ / OSD (by CPU time) | C API / OSD (by CPU time) | OSD "
              "with `fullTopologyInLastLevel` ms | C++ / that (by CPU time) | peak RSS MiB C++ / C API / OSD / OSD full | max abs position "
              "diff vs OSD |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows)
    std::printf("| %s | %d | %zu | %s | %s | %s | %s | %s | %s | %s | %.0f / %.0f / %.0f / %.0f | %.1e |\n",
                r.mesh.c_str(), r.level, r.faces, ms(r.ck.median_s).c_str(), ms(r.capi.median_s).c_str(),
                ms(r.osd.median_s).c_str(), ratio(r.ck, r.osd).c_str(), ratio(r.capi, r.osd).c_str(),
                ms(r.osd_full.median_s).c_str(), ratio(r.ck, r.osd_full).c_str(), r.ck.peak_mib, r.capi.peak_mib,
                r.osd.peak_mib, r.osd_full.peak_mib, r.max_diff);
  std::printf("\nTimes: median of %d interleaved rounds (every variant once per round) after 1 warm-up run of each; "
              "peak RSS: the warm-up run, above the RSS before it. OSD = TopologyRefinerFactory + RefineUniform + "
              "PrimvarRefiner::Interpolate (double); \"OSD with fullTopologyInLastLevel\" is the same with the "
              "UniformOptions flag that CageKit sets (it needs the last level's edges for crease tags).\n",
              kRuns);
  std::printf("Ratios: wall-time ratio, in parentheses the ratio of process CPU times (the same on an idle machine; "
              "closer to the truth under load). Load average at the end: %s.\n",
              load_average().c_str());
  for (const std::string& note : notes) std::printf("Note: %s.\n", note.c_str());
  std::printf("\n");
  if (!counts_ok) {
    std::fprintf(stderr, "bench_subdivide: output face counts differ (see above)\n");
    return 1;
  }
  return 0;
}
