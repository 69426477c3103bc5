// SPDX-License-Identifier: GPL-3.0-or-later
// The C++ layer <cagekit/cagekit.hpp> on a generated sphere scan: the simplify path (hierarchy ->
// cage), the fit, the binding and the CPU deformer with real numbers; errors as exceptions with
// their status and message; callbacks whose exceptions come back to the caller; RAII ownership
// (share, adopt, borrow, release, moves). Sees only the public headers and links only libcagekit
// (run it in the CAGEKIT_SANITIZE build for LeakSanitizer's check of every release).
#include <cagekit/cagekit.hpp>

#include "cpp_check.h"
#include "test_geometry.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace {

// Runs `body`, which must throw cagekit::Error with `status`; returns the error's message.
template <class Body>
std::string expect_error(cagekit_status status, Body&& body, int line) {
  try {
    body();
  } catch (const cagekit::Error& e) {
    if (e.status() != status) {
      std::fprintf(stderr, "line %d: expected status %d, got %d (%s)\n", line, static_cast<int>(status),
                   static_cast<int>(e.status()), e.what());
      ++g_failures;
    }
    return e.message();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "line %d: expected cagekit::Error, got %s\n", line, e.what());
    ++g_failures;
    return "";
  }
  std::fprintf(stderr, "line %d: expected cagekit::Error %d, nothing thrown\n", line, static_cast<int>(status));
  ++g_failures;
  return "";
}
#define EXPECT_ERROR(status, ...) expect_error(status, [&] { __VA_ARGS__; }, __LINE__)

double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return INFINITY;
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::fabs(a[i] - b[i]));
  return worst;
}

// Handles are movable, not copyable; share() is the copy.
template <class T>
constexpr bool is_move_only() {
  return !std::is_copy_constructible<T>::value && !std::is_copy_assignable<T>::value &&
         std::is_nothrow_move_constructible<T>::value && std::is_nothrow_move_assignable<T>::value;
}
static_assert(is_move_only<cagekit::Context>() && is_move_only<cagekit::Mesh>() && is_move_only<cagekit::Cage>() &&
                  is_move_only<cagekit::Surface>() && is_move_only<cagekit::Hierarchy>() &&
                  is_move_only<cagekit::Binding>() && is_move_only<cagekit::CpuDeformer>() &&
                  is_move_only<cagekit::LimitPatches>() && is_move_only<cagekit::LimitSurfaces>() && is_move_only<cagekit::Blob>(),
              "every handle is move-only");
static_assert(std::is_base_of<std::runtime_error, cagekit::Error>::value, "Error is a std::runtime_error");

struct ProgressStop {};  // thrown by a progress callback

void the_simplify_fit_bind_deform_path() {
  int log_lines = 0, progress_calls = 0;
  bool throw_from_progress = false;
  cagekit::ContextOptions options;
  options.log = [&](cagekit_log_level, const char* message) {
    ++log_lines;
    CHECK(message != nullptr);
    throw std::runtime_error("a log callback's exception is swallowed");
  };
  options.log_level = CAGEKIT_LOG_DEBUG;
  options.progress = [&](const char* stage, double fraction) {
    ++progress_calls;
    CHECK(stage != nullptr && fraction >= 0 && fraction <= 1);
    if (throw_from_progress) throw ProgressStop();
    return true;
  };
  cagekit::Context context = cagekit::Context::create(options);
  CHECK(context);

  // --- the scan ---
  const Geometry g = sphere_geometry();
  CHECK(g.positions.size() == 3 * kSphereVertices && g.triangles.size() == 3 * kSphereTriangles);
  cagekit::Mesh scan = context.create_mesh(g.positions, g.triangles);
  const cagekit::MeshCounts counts = scan.counts();
  CHECK(counts.vertices == kSphereVertices && counts.faces == kSphereTriangles &&
        counts.face_indices == 3 * kSphereTriangles);
  CHECK(scan.validate().valid == CAGEKIT_TRUE);
  scan.require_valid();
  CHECK(scan.positions() == g.positions);
  std::vector<double> into(g.positions.size());
  CHECK(scan.positions(cagekit::View<double>(into)) == kSphereVertices && into == g.positions);
  const std::vector<float> positions32 = scan.positions_f32();
  CHECK(positions32.size() == g.positions.size() && positions32[5] == static_cast<float>(g.positions[5]));
  const cagekit::Faces faces = scan.faces();
  CHECK(faces.face_indices == g.triangles && faces.face_sizes == std::vector<uint32_t>(kSphereTriangles, 3));
  const cagekit_mesh_info info = scan.info();
  CHECK(info.vertices == kSphereVertices && info.faces == kSphereTriangles && info.manifold == CAGEKIT_TRUE &&
        info.genus == 0 && info.boundary_edges == 0);
  CHECK(std::fabs(info.bbox_diagonal - std::sqrt(3.0) * 1.5) < 0.2);

  // --- the simplify path: hierarchy, a coarse level, its cage ---
  cagekit::Hierarchy hierarchy = scan.create_hierarchy();
  const uint32_t levels = hierarchy.level_count();
  CHECK(levels > 2);
  CHECK(hierarchy.level_info(0).faces == kSphereTriangles && hierarchy.level_info(0).vertices == kSphereVertices);
  CHECK(hierarchy.current_level() == levels - 1);
  const uint32_t level = hierarchy.find_level(CAGEKIT_LEVEL_BY_FACES, 40);
  hierarchy.set_level(level);
  CHECK(hierarchy.current_level() == level);
  const cagekit_polygonal_level_info current = hierarchy.current_info();
  CHECK(current.level == level && current.faces <= 40 && current.faces >= 4 && current.invalid_faces == 0);
  const cagekit::LevelFaces level_faces = hierarchy.faces();
  CHECK(level_faces.loops_per_face.size() == current.faces);
  CHECK(std::accumulate(level_faces.loops_per_face.begin(), level_faces.loops_per_face.end(), size_t{0}) ==
        level_faces.loop_sizes.size());
  CHECK(std::accumulate(level_faces.loop_sizes.begin(), level_faces.loop_sizes.end(), size_t{0}) ==
        level_faces.loop_vertices.size());
  const std::vector<uint32_t> clusters = hierarchy.clusters();
  CHECK(clusters.size() == kSphereTriangles &&
        *std::max_element(clusters.begin(), clusters.end()) + 1 == current.faces);
  cagekit::Mesh level_mesh = hierarchy.polygon_mesh();
  CHECK(level_mesh.counts().vertices <= kSphereVertices && level_mesh.counts().faces >= current.faces);
  cagekit::Mesh refined = hierarchy.refined_polygon_mesh(0.01);
  CHECK(refined.counts().vertices >= level_mesh.counts().vertices);
  const cagekit_approximation_error level_error = scan.measure_error(level_mesh);
  CHECK(level_error.hausdorff_rel > 0 && level_error.hausdorff_rel < 0.2 && level_error.mean_rel > 0);

  cagekit_cage_report cage_report{};
  cagekit::Cage cage = hierarchy.build_cage(cagekit::defaults<cagekit_cage_options>(), &cage_report);
  const cagekit_mesh_info cage_info = cage.info();
  CHECK(cage_info.faces == cage_report.quads + cage_report.triangles + cage_report.pentagons +
                               cage_report.other_polygons);
  CHECK(cage_info.faces >= current.faces && cage_info.manifold == CAGEKIT_TRUE && cage_report.non_manifold_edges == 0);

  // --- the fit ---
  cagekit_fit_options fit_options = cagekit::defaults<cagekit_fit_options>();
  fit_options.max_passes = 4;
  fit_options.threads = 2;
  const int progress_before_fit = progress_calls;
  cagekit::Cage::Fit fit = cage.fit(scan, fit_options);
  CHECK(progress_calls > progress_before_fit);
  CHECK(fit.cage && fit.passes.size() == fit.report.pass_count && fit.passes.size() >= 2 &&
        fit.passes.size() <= 5);
  CHECK(fit.report.best_pass < fit.passes.size());
  CHECK(fit.passes[0].l2 == fit.report.initial.l2 && fit.passes[fit.report.best_pass].l2 == fit.report.final.l2);
  CHECK(fit.report.final.rms_rel < fit.report.initial.rms_rel && fit.report.final.rms_rel < 0.02);
  CHECK(fit.cage.info().vertices == cage_info.vertices);

  // --- the binding (local-frame displacements: the rest pose gives the scan back exactly) ---
  cagekit_bind_options bind_options = cagekit::defaults<cagekit_bind_options>();
  bind_options.mode = CAGEKIT_DISPLACEMENT_LOCAL_FRAME;
  bind_options.threads = 2;
  cagekit::Binding binding = fit.cage.bind(scan, bind_options);
  const cagekit_binding_info binding_info = binding.info();
  CHECK(binding_info.vertex_count == kSphereVertices && binding_info.scan_vertex_count == kSphereVertices);
  CHECK(binding_info.control_count == cage_info.vertices && binding_info.has_sector_split == CAGEKIT_FALSE);
  std::vector<uint32_t> identity(kSphereVertices);
  std::iota(identity.begin(), identity.end(), 0u);
  CHECK(binding.vertex_sources() == identity);
  CHECK(binding.faces().face_sizes.empty());
  std::vector<uint32_t> order = binding.deformer_vertex_order();
  std::sort(order.begin(), order.end());
  CHECK(order == identity);

  // --- the CPU deformer ---
  const std::vector<double> rest = binding.cage().mesh().positions();
  CHECK(rest == fit.cage.mesh().positions() && rest.size() == 3 * binding_info.control_count);
  cagekit::CpuDeformer deformer = binding.create_cpu_deformer(2);
  CHECK(deformer.vertex_count() == kSphereVertices);
  const cagekit::Deformed<double> at_rest = deformer.deform(rest);
  CHECK(at_rest.vertex_count == kSphereVertices && at_rest.positions.size() == 3 * kSphereVertices);
  // The deformer's compact table evaluates in float32: the rest pose is the scan to float precision
  // (relative to the scan's size, about 2).
  CHECK(max_difference(at_rest.positions, g.positions) < 1e-6);
  for (uint32_t v = 0; v < kSphereVertices; ++v) {
    const double* n = &at_rest.normals[3 * v];
    const double* p = &g.positions[3 * v];
    CHECK(std::fabs(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] - 1) < 1e-6);
    // Outward on a sphere: the normal agrees with the direction from the centre.
    CHECK(n[0] * (p[0] - 0.5) + n[1] * (p[1] - 0.5) + n[2] * (p[2] - 0.5) > 0.5 * 0.75);
  }
  // A translated cage translates the scan.
  std::vector<double> moved = rest;
  for (size_t i = 0; i < moved.size(); ++i) moved[i] += (i % 3 == 0 ? 1.0 : i % 3 == 1 ? -2.0 : 0.5);
  std::vector<double> positions(3 * kSphereVertices), normals(3 * kSphereVertices);
  CHECK(deformer.deform(moved, CAGEKIT_NORMALS_APPROXIMATE, positions, normals) == kSphereVertices);
  std::vector<double> expected = g.positions;
  for (size_t i = 0; i < expected.size(); ++i) expected[i] += (i % 3 == 0 ? 1.0 : i % 3 == 1 ? -2.0 : 0.5);
  CHECK(max_difference(positions, expected) < 1e-6);
  CHECK(max_difference(normals, at_rest.normals) < 1e-6);
  // Incremental: one control point moved, the same as a full recompute of a fresh deformer.
  moved[0] += 0.1;
  const uint32_t updated = deformer.update(moved, {0u}, CAGEKIT_NORMALS_APPROXIMATE, positions, normals);
  CHECK(updated > 0 && updated < kSphereVertices);
  cagekit::CpuDeformer fresh = binding.create_cpu_deformer(1);
  const cagekit::Deformed<double> full = fresh.deform(moved, CAGEKIT_NORMALS_APPROXIMATE);
  CHECK(max_difference(positions, full.positions) < 1e-12 && max_difference(normals, full.normals) < 1e-12);
  CHECK(max_difference(positions, expected) > 1e-3);  // the moved point's support did move
  // float32 outputs: the double values rounded.
  const cagekit::Deformed<float> full32 = fresh.deform_f32(moved);
  CHECK(full32.vertex_count == kSphereVertices);
  bool rounded = true;
  for (size_t i = 0; i < full32.positions.size(); ++i)
    rounded = rounded && full32.positions[i] == static_cast<float>(full.positions[i]);
  CHECK(rounded);
  std::vector<float> positions32b(3 * kSphereVertices);
  fresh.deform_f32(rest, CAGEKIT_NORMALS_APPROXIMATE, positions32b, nullptr);
  moved = rest;
  moved[3] -= 0.2;
  CHECK(fresh.update_f32(moved, {1u}, CAGEKIT_NORMALS_APPROXIMATE, positions32b, nullptr) > 0);

  // --- a saved binding in memory gives the same deformation ---
  cagekit::Blob saved = binding.write_memory();
  CHECK(saved.size() > 100 * kSphereVertices && saved.data() != nullptr && saved.bytes().size() == saved.size());
  cagekit::Binding reread = context.read_binding(saved.data(), saved.size(), 2);
  CHECK(reread.info().vertex_count == kSphereVertices);
  CHECK(max_difference(reread.create_cpu_deformer(1).deform(moved).positions, fresh.deform(moved).positions) == 0);

  // --- a progress callback's exception cancels the operation and comes back as thrown ---
  throw_from_progress = true;
  bool caught = false;
  try {
    (void)scan.create_hierarchy();
  } catch (const ProgressStop&) {
    caught = true;
  }
  CHECK(caught);
  throw_from_progress = false;
  // ... and cancel() is CANCELLED.
  context.cancel();
  CHECK(!EXPECT_ERROR(CAGEKIT_ERROR_CANCELLED, cage.fit(scan, fit_options)).empty());
  context.reset_cancel();
  CHECK(cage.fit(scan, fit_options).cage);
  // The log callback threw on every line; nothing escaped.
  std::printf("log lines: %d, progress calls: %d\n", log_lines, progress_calls);
}

// cagekit_scan_to_cage and both remeshers on the sphere, through the C++ layer.
void scan_to_cage_and_remeshers() {
  cagekit::Context context = cagekit::Context::create();
  const Geometry g = sphere_geometry();
  cagekit::Mesh scan = context.create_mesh(g.positions, g.triangles);
  cagekit_fit_options fit = cagekit::defaults<cagekit_fit_options>();
  fit.threads = 2;
  fit.max_passes = 3;
  cagekit_scan_to_cage_options options = cagekit::defaults<cagekit_scan_to_cage_options>();
  options.target = 30;
  options.fit = &fit;
  const cagekit::Cage::ScanToCage result = cagekit::scan_to_cage(scan, options);
  CHECK(result.cage && result.limit);
  CHECK(result.report.input_vertices == kSphereVertices && result.report.used_method == CAGEKIT_SCAN_SIMPLIFY);
  CHECK(result.fit_passes.size() == result.fit_report.pass_count && !result.fit_passes.empty() &&
        result.fit_passes.size() <= fit.max_passes + 1);
  CHECK(result.cage.info().faces == result.report.cage_faces && result.report.scan_to_limit_max_rel < 0.05);
  const cagekit::Cage::ScanToCage without_limit = cagekit::scan_to_cage(scan, options, false);
  CHECK(without_limit.cage && !without_limit.limit);

  cagekit_quad_remesh_options quad = cagekit::defaults<cagekit_quad_remesh_options>();
  quad.threads = 2;
  quad.regions = 8;
  cagekit_quad_remesh_report quad_report{};
  cagekit::Cage quads = scan.remesh_quad(quad, &quad_report);
  CHECK(quads.info().faces == quad_report.quality.faces && quad_report.quality.quads > 0);
  cagekit_anisotropic_options anisotropic = cagekit::defaults<cagekit_anisotropic_options>();
  anisotropic.threads = 2;
  anisotropic.tolerance = 0.01;
  cagekit_anisotropic_report anisotropic_report{};
  try {
    cagekit::Cage lines = scan.remesh_anisotropic(anisotropic, &anisotropic_report);
    CHECK(lines.info().faces == anisotropic_report.quality.faces);
    std::printf("anisotropic remesh: %llu faces\n", static_cast<unsigned long long>(anisotropic_report.quality.faces));
  } catch (const cagekit::Error& e) {
    // A sphere has no principal directions (umbilic everywhere): an INVALID_MESH that says why
    // is a correct answer too.
    CHECK(e.status() == CAGEKIT_ERROR_INVALID_MESH && e.message()[0] != '\0');
    std::printf("anisotropic remesh: %s\n", e.what());
  }
}

void errors_are_exceptions_with_status_and_message() {
  cagekit::Context context = cagekit::Context::create();
  cagekit::Mesh cube = context.create_mesh(kCube, kCubeQuads, 4);
  cagekit::Hierarchy hierarchy = cube.create_hierarchy();
  const uint32_t levels = hierarchy.level_count();
  std::string message = EXPECT_ERROR(CAGEKIT_ERROR_INVALID_ARGUMENT, hierarchy.set_level(levels));
  CHECK(!message.empty() && message == context.last_error_message());
  try {
    hierarchy.level_info(levels);
    CHECK(false);
  } catch (const cagekit::Error& e) {
    CHECK(std::string(e.function()) == "cagekit_hierarchy_get_level_info");
    CHECK(std::string(e.what()) == "cagekit_hierarchy_get_level_info: " + std::string(e.message()));
  }
  message = EXPECT_ERROR(CAGEKIT_ERROR_IO, context.read_mesh("/nonexistent/cagekit/scan.obj"));
  CHECK(message.find("scan.obj") != std::string::npos);
  message = EXPECT_ERROR(CAGEKIT_ERROR_PARSE, context.read_mesh("v 1 2\nf 1 2 x\n", 13, CAGEKIT_FORMAT_OBJ));
  CHECK(!message.empty());
  // An invalid mesh: validate() reports, require_valid() and create_cage() throw INVALID_MESH.
  cagekit::Mesh broken = context.create_mesh(kCube, {0u, 1u, 9u});
  const cagekit_validation_report report = broken.validate();
  CHECK(report.valid == CAGEKIT_FALSE && (report.issue_flags & (1u << CAGEKIT_ISSUE_INDEX_OUT_OF_RANGE)) != 0);
  message = EXPECT_ERROR(CAGEKIT_ERROR_INVALID_MESH, broken.require_valid());
  CHECK(message.find('9') != std::string::npos);
  CHECK(!EXPECT_ERROR(CAGEKIT_ERROR_INVALID_MESH, broken.create_cage()).empty());
  cagekit_repair_report repair_report{};
  cagekit::Mesh repaired = broken.repair(cagekit::defaults<cagekit_repair_options>(), &repair_report);
  CHECK(repair_report.dropped_invalid_faces == 1 && repaired.counts().faces == 0);
  // Errors found before the C call: arrays that are no xyz triples, odd crease pairs.
  message = EXPECT_ERROR(CAGEKIT_ERROR_INVALID_ARGUMENT, context.create_mesh({0.0, 1.0}, {0u, 0u, 0u}));
  CHECK(message.find("xyz") != std::string::npos);
  cagekit::Cage cage = cube.create_cage();
  EXPECT_ERROR(CAGEKIT_ERROR_INVALID_ARGUMENT, cage.set_creases({0u, 1u, 2u}));
  // A bad option: the SDK names it.
  cagekit_subdivide_options subdivide = cagekit::defaults<cagekit_subdivide_options>();
  subdivide.levels = CAGEKIT_MAX_SUBDIVISION_LEVELS + 1;
  message = EXPECT_ERROR(CAGEKIT_ERROR_INVALID_ARGUMENT, cage.subdivide(subdivide));
  CHECK(message.find("levels") != std::string::npos);
  // Control points of the wrong count (the C call has no count to check them by).
  cagekit::Surface surface = cage.create_surface();
  EXPECT_ERROR(CAGEKIT_ERROR_INVALID_ARGUMENT, surface.evaluate({cagekit_surface_location{0, 0.5, 0.5}}, {0.0, 0.0, 0.0}));
  // Empty wrappers: INVALID_HANDLE with a message, never a crash.
  cagekit::Context empty;
  CHECK(!EXPECT_ERROR(CAGEKIT_ERROR_INVALID_HANDLE, empty.create_mesh(kCube, kCubeQuads, 4)).empty());
  EXPECT_ERROR(CAGEKIT_ERROR_INVALID_HANDLE, empty.set_progress(nullptr));
  CHECK(!EXPECT_ERROR(CAGEKIT_ERROR_INVALID_HANDLE, cagekit::Mesh().counts()).empty());
  // A context for another ABI: the message comes from the context-less slot.
  cagekit_context_desc desc = cagekit::defaults<cagekit_context_desc>();
  desc.abi_version = CAGEKIT_ABI_VERSION + 1;
  CHECK(!EXPECT_ERROR(CAGEKIT_ERROR_VERSION_MISMATCH, cagekit::Context::create(desc)).empty());
  CHECK(std::string(cagekit::status_string(CAGEKIT_ERROR_IO)).size() > 0);
  CHECK(cagekit::abi_version() == CAGEKIT_ABI_VERSION && cagekit::version() == CAGEKIT_VERSION &&
        std::string(cagekit::version_string()).size() >= 5);
}

void cage_tags_surfaces_patches_and_files() {
  cagekit::Context context = cagekit::Context::create();
  cagekit::Mesh cube = context.create_mesh(kCube, kCubeQuads, 4);
  cagekit::Cage cage = cube.create_cage();
  cage.set_creases({0u, 1u, 2u, 3u}, {CAGEKIT_SHARP, 2.5f});
  const cagekit::Creases creases = cage.creases();
  CHECK(creases.vertex_pairs.size() == 4 && creases.sharpness.size() == 2);
  CHECK(std::count(creases.sharpness.begin(), creases.sharpness.end(), 2.5f) == 1);
  cage.set_corners({5u});
  CHECK(cage.corners().vertices == std::vector<uint32_t>{5u} && cage.corners().sharpness[0] == CAGEKIT_SHARP);
  cage.set_boundary_rule(CAGEKIT_BOUNDARY_EDGES_AND_CORNERS);
  CHECK(cage.boundary_rule() == CAGEKIT_BOUNDARY_EDGES_AND_CORNERS);
  CHECK(cage.info().creases == 2 && cage.info().corners == 1);
  // Subdivision: each quad into four.
  cagekit::Cage finer = cage.subdivide();
  CHECK(finer.info().faces == 24 && finer.info().vertices == 26);
  const cagekit::LimitPoints limit = cage.limit_points();
  CHECK(limit.positions.size() == 24 && limit.normals.size() == 24);
  std::vector<double> limit_positions(24);
  CHECK(cage.limit_points(limit_positions, nullptr) == 8 && limit_positions == limit.positions);
  // The surface: basis functions are a partition of unity and reproduce evaluate().
  cagekit::Surface surface = cage.create_surface();
  CHECK(surface.ptex_face_count() == 6 && surface.control_vertex_count() == 8);
  const uint32_t ptex = surface.ptex_face(2);
  const cagekit_surface_location location = {ptex, 0.3, 0.6};
  const std::vector<cagekit_surface_point> points = surface.evaluate({location});
  CHECK(points.size() == 1);
  const cagekit::Basis basis = surface.evaluate_basis(location);
  CHECK(!basis.indices.empty() && basis.w.size() == basis.indices.size());
  CHECK(std::fabs(std::accumulate(basis.w.begin(), basis.w.end(), 0.0) - 1) < 1e-12);
  double x = 0;
  for (size_t k = 0; k < basis.indices.size(); ++k) x += basis.w[k] * kCube[3 * basis.indices[k]];
  CHECK(std::fabs(x - points[0].position[0]) < 1e-12);
  // Moved control points: all moved by +1 in z moves the point by +1.
  std::vector<double> lifted = kCube;
  for (size_t i = 2; i < lifted.size(); i += 3) lifted[i] += 1;
  const std::vector<cagekit_surface_point> lifted_points = surface.evaluate({location}, lifted);
  CHECK(std::fabs(lifted_points[0].position[2] - points[0].position[2] - 1) < 1e-12);
  // Limit patches.
  cagekit::LimitPatches patches = cage.create_limit_patches();
  const cagekit_limit_patch_info patch_info = patches.info();
  const std::vector<cagekit_limit_patch> patch_list = patches.patches();
  CHECK(patch_info.patch_count == patch_list.size() && patch_list.size() >= 6);
  // Limit B-spline surfaces: one per ptex face, the variable parts sized by the descriptor.
  cagekit::LimitSurfaces surfaces = cage.create_limit_surfaces();
  const cagekit_limit_surface_info surface_info = surfaces.info();
  CHECK(surface_info.surface_count == 6 && surface_info.ptex_face_count == 6);
  for (uint32_t k = 0; k < surface_info.surface_count; ++k) {
    const cagekit_limit_surface s = surfaces.surface(k);
    CHECK(surfaces.knots(k, CAGEKIT_SURFACE_DIRECTION_U).size() == s.knot_count_u);
    CHECK(surfaces.knots(k, CAGEKIT_SURFACE_DIRECTION_V).size() == s.knot_count_v);
    CHECK(surfaces.control_points(k).size() == 3 * size_t(s.num_u) * s.num_v);
    for (uint32_t side = 0; side < 4; ++side) CHECK(surfaces.neighbours(k, side).size() == s.sides[side].neighbour_count);
  }
  // Files in memory and on disk.
  cagekit_write_options obj = cagekit::defaults<cagekit_write_options>();
  obj.format = CAGEKIT_FORMAT_OBJ;
  cagekit::Blob text = cage.write_memory(obj);
  cagekit::Cage read = context.read_cage(text.data(), text.size(), CAGEKIT_FORMAT_OBJ);
  CHECK(read.info().creases == 2 && read.info().vertices == 8);
  cagekit_write_report write_report{};
  cagekit::Blob mesh_text = cube.write_memory(obj, &write_report);
  CHECK(write_report.bytes == mesh_text.size() && context.read_mesh(mesh_text.data(), mesh_text.size()).counts().faces == 6);
  const std::string dir = std::getenv("CAGEKIT_TEST_TMPDIR") != nullptr ? std::getenv("CAGEKIT_TEST_TMPDIR") : ".";
  const std::string mesh_path = dir + "/test_cagekit_hpp_cube.ply", cage_path = dir + "/test_cagekit_hpp_cage.obj";
  CHECK(cube.write_file(mesh_path).bytes > 0);
  CHECK(context.read_mesh(mesh_path).counts().vertices == 8);
  CHECK(cage.write_file(cage_path).bytes > 0);
  CHECK(context.read_cage(cage_path).info().corners == 1);
  std::remove(mesh_path.c_str());
  std::remove(cage_path.c_str());
  // Holes (after the file round trip: OBJ keeps them too, but they are checked here alone).
  cage.set_holes({4u});
  CHECK(cage.holes() == std::vector<uint32_t>{4u} && cage.info().holes == 1);
}

void ownership_share_adopt_borrow_release() {
  cagekit::Context context = cagekit::Context::create();
  cagekit::Mesh cube = context.create_mesh(kCube, kCubeQuads, 4);
  cagekit::Mesh second = cube.share();
  CHECK(second.get() == cube.get());
  cube.reset();
  CHECK(!cube && second.counts().faces == 6);
  // Moves leave the source empty.
  cagekit::Mesh moved = std::move(second);
  CHECK(!second && moved);  // NOLINT: the moved-from state is specified (empty)
  second = std::move(moved);
  CHECK(second && !moved);  // NOLINT
  // release() hands the reference to C; adopt() takes it back with the context's messages.
  cagekit_mesh raw = second.release();
  CHECK(!second && raw != nullptr);
  cagekit::Mesh adopted = cagekit::Mesh::adopt(raw, context);
  CHECK(adopted.get() == raw && adopted.counts().vertices == 8);
  {
    cagekit::Mesh borrowed = cagekit::Mesh::borrow(raw, context);  // one more reference, dropped below
    CHECK(borrowed.counts().faces == 6);
  }
  CHECK(adopted.counts().faces == 6);
  // Objects outlive the Context wrapper: the C library keeps the context alive, the wrappers keep
  // its callbacks.
  int progress_calls = 0;
  cagekit::ContextOptions options;
  options.progress = [&](const char*, double) { return ++progress_calls > 0; };
  cagekit::Mesh sphere;
  {
    cagekit::Context scoped = cagekit::Context::create(options);
    const Geometry g = sphere_geometry();
    sphere = scoped.create_mesh(g.positions, g.triangles);
  }
  cagekit::Hierarchy hierarchy = sphere.create_hierarchy();
  CHECK(progress_calls > 0 && hierarchy.level_count() > 2);
  // The raw context: borrow adds a reference, adopt takes one over.
  cagekit::Context borrowed = cagekit::Context::borrow(context.get());
  CHECK(borrowed.get() == context.get());
  cagekit_context raw_context = nullptr;
  cagekit_context_desc desc = cagekit::defaults<cagekit_context_desc>();
  CHECK(cagekit_context_create(&desc, &raw_context) == CAGEKIT_SUCCESS);
  cagekit::Context adopted_context = cagekit::Context::adopt(raw_context);
  EXPECT_ERROR(CAGEKIT_ERROR_IO, adopted_context.read_cage("/nonexistent.obj"));
  // A C progress callback through set_progress (C callbacks must not throw).
  adopted_context.set_progress([](void* user, const char*, double) -> int { return ++*static_cast<int*>(user), 1; },
                               &progress_calls);
  adopted_context.set_progress(nullptr);
}

}  // namespace

int main() {
  the_simplify_fit_bind_deform_path();
  errors_are_exceptions_with_status_and_message();
  scan_to_cage_and_remeshers();
  cage_tags_surfaces_patches_and_files();
  ownership_share_adopt_borrow_release();
  if (g_failures != 0) {
    std::fprintf(stderr, "test_cagekit_hpp: %d checks failed\n", g_failures);
    return 1;
  }
  std::printf("test_cagekit_hpp: all checks passed\n");
  return 0;
}
