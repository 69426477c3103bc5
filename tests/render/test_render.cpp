// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the render module through the C API (cagekit.h "Rendering", cagekit_gl.h), under
// Mesa llvmpipe in CI. One case per run: `test_render CASE [--generated]`; a case that needs a
// headless EGL display exits 77 (ctest SKIP_RETURN_CODE) when none can be made.
// Inputs are made here, nothing is read from the source tree: the scan is the shared fandisk
// (../shared/meshes, CAGEKIT_SHARED_MESHES) with its cage simplified to about 150 faces with
// creases through the C API; with --generated, or when the shared mesh is absent (said on
// stdout), a generated noisy block and its 6-quad creased cage (simplification again).
// `test_render picture OUT.png [W H]` writes the overview picture used to look at the output.
#include <cagekit/cagekit.h>
#include <cagekit/cagekit_gl.h>

#include <GL/glcorearb.h>
#include <png.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <random>
#include <map>
#include <string>
#include <vector>

#include <sys/stat.h>

#include "../gpu/egl_context.h"

namespace {

int failures = 0;
#define CHECK(cond)                                                              \
  do {                                                                           \
    if (!(cond)) {                                                               \
      std::fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
      ++failures;                                                                \
    }                                                                            \
  } while (0)

cagekit_context g_context = nullptr;

void ok(cagekit_status s, const char* what) {
  if (s != CAGEKIT_SUCCESS) {
    std::fprintf(stderr, "%s failed: %s: %s\n", what, cagekit_status_string(s), cagekit_last_error_message(g_context));
    std::exit(1);
  }
}

std::string meshes() { return CAGEKIT_SHARED_MESHES; }

cagekit_mesh read_mesh(const std::string& path) {
  cagekit_mesh m = nullptr;
  ok(cagekit_mesh_read_file(g_context, path.c_str(), CAGEKIT_FORMAT_AUTO, &m), path.c_str());
  return m;
}

// A noisy scan of a 2 x 1.4 x 1 block: each side a grid of about 12 cells per unit, two
// triangles per cell, watertight, outward; the side vertices moved along the side's normal by
// up to 0.4 % of the size (fixed seed).
cagekit_mesh generated_block() {
  const double size[3] = {2.0, 1.4, 1.0};
  int n[3];
  for (int k = 0; k < 3; ++k) n[k] = int(std::lround(size[k] * 12));
  std::mt19937 rng(24u);
  std::uniform_real_distribution<double> jitter(-0.004, 0.004);
  std::map<std::array<int, 3>, uint32_t> lattice;
  std::vector<double> positions;
  std::vector<uint32_t> triangles;
  auto vertex = [&](std::array<int, 3> g, int axis) {
    const auto it = lattice.find(g);
    if (it != lattice.end()) return it->second;
    const uint32_t id = uint32_t(positions.size() / 3);
    const bool on_edge = (g[0] == 0 || g[0] == n[0]) + (g[1] == 0 || g[1] == n[1]) + (g[2] == 0 || g[2] == n[2]) > 1;
    for (int k = 0; k < 3; ++k) positions.push_back(size[k] * g[k] / n[k] + (k == axis && !on_edge ? jitter(rng) : 0.0));
    lattice.emplace(g, id);
    return id;
  };
  for (int axis = 0; axis < 3; ++axis) {
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side)
      for (int i = 0; i < n[a]; ++i)
        for (int j = 0; j < n[b]; ++j) {
          uint32_t q[4];
          const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
          for (int c = 0; c < 4; ++c) {
            std::array<int, 3> g{};
            g[axis] = side ? n[axis] : 0;
            g[a] = i + di[c];
            g[b] = j + dj[c];
            q[c] = vertex(g, axis);
          }
          if (side) triangles.insert(triangles.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
          else triangles.insert(triangles.end(), {q[0], q[2], q[1], q[0], q[3], q[2]});
        }
  }
  cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
  desc.vertex_count = uint32_t(positions.size() / 3);
  desc.positions = positions.data();
  desc.face_count = uint32_t(triangles.size() / 3);
  desc.face_indices = triangles.data();
  cagekit_mesh mesh = nullptr;
  ok(cagekit_mesh_create(g_context, &desc, &mesh), "cagekit_mesh_create (generated block)");
  return mesh;
}

// The scan simplified to at most `faces` polygons and partitioned into a cage with crease tags
// (what `cagekit simplify SCAN CAGE --faces N --cage` writes).
cagekit_cage simplified_cage(cagekit_mesh scan, double faces, cagekit_cage_report* report) {
  cagekit_hierarchy hierarchy = nullptr;
  ok(cagekit_hierarchy_create(scan, nullptr, &hierarchy), "cagekit_hierarchy_create");
  uint32_t level = 0;
  ok(cagekit_hierarchy_find_level(hierarchy, CAGEKIT_LEVEL_BY_FACES, faces, &level), "find_level");
  ok(cagekit_hierarchy_set_level(hierarchy, level), "set_level");
  cagekit_cage_options options = CAGEKIT_CAGE_OPTIONS_INIT;
  *report = cagekit_cage_report{};
  report->struct_size = sizeof(*report);
  cagekit_cage cage = nullptr;
  ok(cagekit_hierarchy_build_cage(hierarchy, &options, &cage, report), "cagekit_hierarchy_build_cage");
  cagekit_hierarchy_release(hierarchy);
  return cage;
}

bool g_generated = false;  // --generated: the generated block even when the shared fandisk is there

// The scan and its creased cage of every case (see the file's header).
struct Input {
  cagekit_mesh scan = nullptr;
  cagekit_cage cage = nullptr;
  Input() {
    const std::string fandisk = meshes() + "/fandisk.obj";
    struct stat st;
    const bool shared = !g_generated && stat(fandisk.c_str(), &st) == 0;
    if (!g_generated && !shared) std::printf("shared mesh %s absent: using the generated block\n", fandisk.c_str());
    scan = shared ? read_mesh(fandisk) : generated_block();
    cagekit_cage_report report;
    cage = simplified_cage(scan, shared ? 150 : 6, &report);
    const uint64_t faces = report.quads + report.triangles + report.pentagons + report.other_polygons;
    std::printf("input: %s; cage of %llu faces (%llu quads), %llu creases\n", shared ? fandisk.c_str() : "generated block",
                (unsigned long long)faces, (unsigned long long)report.quads, (unsigned long long)report.creases);
    // A creased cage of the size asked for, or the crease and coverage checks mean nothing.
    if (shared) {
      CHECK(faces >= 100 && faces <= 400);
    } else {
      CHECK(faces == 6 && report.quads == 6);
    }
    CHECK(report.creases >= 12);
  }
  ~Input() {
    cagekit_cage_release(cage);
    cagekit_mesh_release(scan);
  }
  Input(const Input&) = delete;
  Input& operator=(const Input&) = delete;
};

struct Image {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba;
  const uint8_t* at(uint32_t x, uint32_t y) const { return &rgba[4 * (size_t(y) * width + x)]; }
};

// Draws headless; exits 77 (skip) when no EGL display / context can be made here.
Image draw(cagekit_render_scene scene, uint32_t width, uint32_t height) {
  Image image;
  image.width = width;
  image.height = height;
  uint32_t count = 0;
  ok(cagekit_render_scene_draw(scene, 0, &count, nullptr), "draw (size query)");
  CHECK(count == width * height);
  image.rgba.resize(4 * size_t(count));
  const cagekit_status s = cagekit_render_scene_draw(scene, count, &count, image.rgba.data());
  if (s == CAGEKIT_ERROR_UNSUPPORTED_FEATURE) {
    std::printf("SKIP: no headless GL here: %s\n", cagekit_last_error_message(g_context));
    std::exit(77);
  }
  ok(s, "cagekit_render_scene_draw");
  return image;
}

cagekit_render_scene new_scene(uint32_t width, uint32_t height, bool labels) {
  cagekit_render_scene scene = nullptr;
  ok(cagekit_render_scene_create(g_context, &scene), "cagekit_render_scene_create");
  cagekit_render_options options = CAGEKIT_RENDER_OPTIONS_INIT;
  options.width = width;
  options.height = height;
  options.labels = labels ? 1 : 0;
  options.display = CAGEKIT_RENDER_DISPLAY_SURFACELESS;  // llvmpipe everywhere: byte checks are stable
  ok(cagekit_render_scene_set_options(scene, &options), "cagekit_render_scene_set_options");
  return scene;
}

void set_views(cagekit_render_scene scene, std::vector<cagekit_render_view> views) {
  std::vector<cagekit_render_camera> cameras;
  for (cagekit_render_view v : views) {
    cagekit_render_camera c = CAGEKIT_RENDER_CAMERA_INIT;
    c.view = v;
    cameras.push_back(c);
  }
  ok(cagekit_render_scene_set_views(scene, uint32_t(cameras.size()), cameras.data()), "set_views");
}

bool near(const uint8_t* px, int r, int g, int b, int tolerance) {
  return std::abs(px[0] - r) <= tolerance && std::abs(px[1] - g) <= tolerance && std::abs(px[2] - b) <= tolerance;
}

// The default crease colour (0.90, 0.15, 0.55) as 8-bit (GL rounds; allow 1).
size_t crease_pixels(const Image& image) {
  size_t n = 0;
  for (uint32_t y = 0; y < image.height; ++y)
    for (uint32_t x = 0; x < image.width; ++x) n += near(image.at(x, y), 230, 38, 140, 1);
  return n;
}

// Share of non-background (white) pixels in a rectangle.
double coverage(const Image& image, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1) {
  size_t covered = 0;
  for (uint32_t y = y0; y < y1; ++y)
    for (uint32_t x = x0; x < x1; ++x) covered += !near(image.at(x, y), 255, 255, 255, 0);
  return double(covered) / double((x1 - x0) * (y1 - y0));
}

// --- cases ---------------------------------------------------------------------------------

// The image has the requested size; the objects cover a plausible share of every tile.
void case_size_and_coverage() {
  const uint32_t w = 360, h = 400;
  cagekit_render_scene scene = new_scene(w, h, false);
  set_views(scene, {CAGEKIT_RENDER_VIEW_FRONT, CAGEKIT_RENDER_VIEW_SIDE, CAGEKIT_RENDER_VIEW_TOP, CAGEKIT_RENDER_VIEW_ISO});
  const Input in;
  cagekit_mesh scan = in.scan;
  cagekit_cage cage = in.cage;
  cagekit_render_item_options item = CAGEKIT_RENDER_ITEM_OPTIONS_INIT;
  ok(cagekit_render_scene_add_mesh(scene, scan, CAGEKIT_RENDER_ITEM_MESH, &item, nullptr), "add_mesh");
  item.wireframe = 1;
  uint32_t index = 99;
  ok(cagekit_render_scene_add_cage(scene, cage, &item, &index), "add_cage");
  CHECK(index == 1);
  const Image image = draw(scene, w, h);
  CHECK(image.rgba.size() == size_t(4) * w * h);
  for (uint32_t row = 0; row < 4; ++row)
    for (uint32_t column = 0; column < 2; ++column) {
      const double c = coverage(image, column * w / 2, row * h / 4, (column + 1) * w / 2, (row + 1) * h / 4);
      std::printf("view %u item %u: %.1f %% of the tile covered\n", row, column, 100 * c);
      CHECK(c > 0.05 && c < 0.80);
    }
  // Another size: the count follows.
  cagekit_render_options options = CAGEKIT_RENDER_OPTIONS_INIT;
  options.width = 17;
  options.height = 9;
  ok(cagekit_render_scene_set_options(scene, &options), "set_options");
  uint32_t count = 0;
  ok(cagekit_render_scene_draw(scene, 0, &count, nullptr), "size query");
  CHECK(count == 17 * 9);
  std::vector<uint8_t> small(4 * 17 * 9);
  CHECK(cagekit_render_scene_draw(scene, 10, &count, small.data()) == CAGEKIT_ERROR_SIZE_INSUFFICIENT);
  CHECK(count == 17 * 9);
  ok(cagekit_render_scene_draw(scene, count, &count, small.data()), "small draw");
  cagekit_render_scene_release(scene);

  // One item, four views: a 2 x 2 grid of near-square tiles (not four wide rows), each view
  // centred in its quadrant; three views in a wide image: one row of three.
  struct Layout {
    uint32_t w, h, columns, rows;
    std::vector<cagekit_render_view> views;
  };
  const std::vector<Layout> layouts = {
      {400, 400, 2, 2, {CAGEKIT_RENDER_VIEW_FRONT, CAGEKIT_RENDER_VIEW_SIDE, CAGEKIT_RENDER_VIEW_TOP, CAGEKIT_RENDER_VIEW_ISO}},
      {600, 200, 3, 1, {CAGEKIT_RENDER_VIEW_FRONT, CAGEKIT_RENDER_VIEW_TOP, CAGEKIT_RENDER_VIEW_ISO}}};
  for (const Layout& layout : layouts) {
    cagekit_render_scene one = new_scene(layout.w, layout.h, false);
    set_views(one, layout.views);
    ok(cagekit_render_scene_add_cage(one, cage, nullptr, nullptr), "add_cage");
    const Image grid = draw(one, layout.w, layout.h);
    for (uint32_t v = 0; v < layout.views.size(); ++v) {
      const uint32_t tw = layout.w / layout.columns, th = layout.h / layout.rows;
      const uint32_t x0 = (v % layout.columns) * tw, y0 = (v / layout.columns) * th;
      const double c = coverage(grid, x0, y0, x0 + tw, y0 + th);
      // The covered pixels' bounding box is centred in the tile (a view of another layout is not).
      uint32_t lo_x = x0 + tw, hi_x = x0, lo_y = y0 + th, hi_y = y0;
      for (uint32_t y = y0; y < y0 + th; ++y)
        for (uint32_t x = x0; x < x0 + tw; ++x)
          if (!near(grid.at(x, y), 255, 255, 255, 0)) {
            lo_x = std::min(lo_x, x), hi_x = std::max(hi_x, x);
            lo_y = std::min(lo_y, y), hi_y = std::max(hi_y, y);
          }
      const double cx = 0.5 * (lo_x + hi_x) - (x0 + 0.5 * tw), cy = 0.5 * (lo_y + hi_y) - (y0 + 0.5 * th);
      std::printf("%ux%u, view %u of %zu: %.1f %% covered, centre off by (%.1f, %.1f) px\n", layout.w, layout.h, v,
                  layout.views.size(), 100 * c, cx, cy);
      CHECK(c > 0.05 && c < 0.80);
      CHECK(std::fabs(cx) <= 0.1 * tw && std::fabs(cy) <= 0.1 * th);
      CHECK(lo_x > x0 && hi_x < x0 + tw - 1 && lo_y > y0 && hi_y < y0 + th - 1);  // inside, not cut by the tile
    }
    cagekit_render_scene_release(one);
  }
}

// The crease colour appears exactly when creases are asked for.
void case_creases() {
  const Input in;
  cagekit_cage cage = in.cage;
  size_t counts[2] = {0, 0};
  for (int creases = 0; creases < 2; ++creases) {
    cagekit_render_scene scene = new_scene(320, 240, true);
    cagekit_render_item_options item = CAGEKIT_RENDER_ITEM_OPTIONS_INIT;
    item.wireframe = 1;
    item.creases = cagekit_bool32(creases);
    item.title = "cage";
    ok(cagekit_render_scene_add_cage(scene, cage, &item, nullptr), "add_cage");
    counts[creases] = crease_pixels(draw(scene, 320, 240));
    cagekit_render_scene_release(scene);
  }
  std::printf("crease-coloured pixels: %zu without creases, %zu with\n", counts[0], counts[1]);
  CHECK(counts[0] == 0);
  CHECK(counts[1] > 200);
}

double point_triangle_distance(const double* p, const double* a, const double* b, const double* c) {
  // Ericson, Real-Time Collision Detection, 5.1.5.
  auto sub = [](const double* x, const double* y, double* r) { for (int i = 0; i < 3; ++i) r[i] = x[i] - y[i]; };
  auto dot = [](const double* x, const double* y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
  double ab[3], ac[3], ap[3], bp[3], cp[3], q[3];
  sub(b, a, ab), sub(c, a, ac), sub(p, a, ap);
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  auto dist = [&](const double* x) { return std::sqrt((p[0] - x[0]) * (p[0] - x[0]) + (p[1] - x[1]) * (p[1] - x[1]) + (p[2] - x[2]) * (p[2] - x[2])); };
  if (d1 <= 0 && d2 <= 0) return dist(a);
  sub(p, b, bp);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return dist(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    for (int i = 0; i < 3; ++i) q[i] = a[i] + v * ab[i];
    return dist(q);
  }
  sub(p, c, cp);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return dist(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    for (int i = 0; i < 3; ++i) q[i] = a[i] + w * ac[i];
    return dist(q);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    for (int i = 0; i < 3; ++i) q[i] = b[i] + w * (c[i] - b[i]);
    return dist(q);
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  for (int i = 0; i < 3; ++i) q[i] = a[i] + ab[i] * v + ac[i] * w;
  return dist(q);
}

double distance_to(const double* p, const std::vector<double>& pos, const std::vector<uint32_t>& tris) {
  double best = INFINITY;
  for (size_t t = 0; t < tris.size(); t += 3)
    best = std::min(best, point_triangle_distance(p, &pos[3 * tris[t]], &pos[3 * tris[t + 1]], &pos[3 * tris[t + 2]]));
  return best;
}

// The colour map's range (the legend) is the measured maximum two-sided distance.
void case_legend_range() {
  cagekit_render_scene scene = new_scene(480, 360, true);
  const Input in;
  cagekit_mesh scan = in.scan;
  cagekit_cage cage = in.cage;
  cagekit_render_item_options item = CAGEKIT_RENDER_ITEM_OPTIONS_INIT;
  item.tessellation_level = 1;
  ok(cagekit_render_scene_add_cage(scene, cage, &item, nullptr), "add_cage");
  ok(cagekit_render_scene_set_distance_to_scan(scene, 0, scan, nullptr), "set_distance_to_scan");
  cagekit_render_item_info info{};
  info.struct_size = sizeof(info);
  ok(cagekit_render_scene_get_item_info(scene, 0, &info), "get_item_info");
  CHECK(info.has_scalars == 1);
  CHECK(info.tessellation_level == 1);
  // The surface as drawn, and the scan.
  uint32_t nv = 0, nt = 0;
  ok(cagekit_render_scene_get_item_geometry(scene, 0, 0, &nv, nullptr, 0, &nt, nullptr), "geometry counts");
  std::vector<double> pos(3 * size_t(nv));
  std::vector<uint32_t> tris(3 * size_t(nt));
  ok(cagekit_render_scene_get_item_geometry(scene, 0, nv, &nv, pos.data(), nt, &nt, tris.data()), "geometry");
  std::vector<double> values(nv);
  uint32_t count = 0;
  ok(cagekit_render_scene_get_scalars(scene, 0, nv, &count, values.data()), "get_scalars");
  CHECK(count == nv && info.vertex_count == nv);
  uint32_t sv = 0;
  ok(cagekit_mesh_get_positions(scan, CAGEKIT_SCALAR_FLOAT64, 0, &sv, nullptr), "scan count");
  std::vector<double> scan_pos(3 * size_t(sv));
  ok(cagekit_mesh_get_positions(scan, CAGEKIT_SCALAR_FLOAT64, sv, &sv, scan_pos.data()), "scan positions");
  uint32_t sf = 0;
  uint64_t si = 0;
  ok(cagekit_mesh_get_faces(scan, 0, &sf, nullptr, 0, &si, nullptr), "scan faces count");
  std::vector<uint32_t> sizes(sf), scan_tris(si);
  ok(cagekit_mesh_get_faces(scan, sf, &sf, sizes.data(), si, &si, scan_tris.data()), "scan faces");
  // Brute force, both ways.
  double forward = 0, backward = 0;
  for (uint32_t v = 0; v < nv; ++v) {
    const double d = distance_to(&pos[3 * v], scan_pos, scan_tris);
    forward = std::max(forward, d);
    CHECK(values[v] >= d - 1e-6);  // every value includes the vertex's own distance to the scan
  }
  for (uint32_t s = 0; s < sv; ++s) backward = std::max(backward, distance_to(&scan_pos[3 * s], pos, tris));
  const double expected = std::max(forward, backward);
  const double measured = *std::max_element(values.begin(), values.end());
  std::printf("two-sided max distance: brute force %.6g (surface->scan %.6g, scan->surface %.6g), scalars %.6g, "
              "legend [%.6g, %.6g]\n", expected, forward, backward, measured, info.scalar_min, info.scalar_max);
  CHECK(std::fabs(measured - expected) <= 1e-6 * std::max(1.0, expected));
  CHECK(std::fabs(info.scalar_max - expected) <= 1e-6 * std::max(1.0, expected));
  CHECK(info.scalar_min == *std::min_element(values.begin(), values.end()));
  // The legend is drawn: its bar's top is the colour map's last colour (viridis yellow).
  const Image image = draw(scene, 480, 360);
  size_t yellow = 0;
  for (uint32_t y = 0; y < image.height; ++y)
    for (uint32_t x = 0; x < image.width; ++x) yellow += near(image.at(x, y), 253, 231, 37, 0);
  CHECK(yellow >= 10);
  // A fixed range is reported as given.
  cagekit_render_scalar_options fixed = CAGEKIT_RENDER_SCALAR_OPTIONS_INIT;
  fixed.auto_range = 0;
  fixed.range_min = 0;
  fixed.range_max = 2 * expected;
  ok(cagekit_render_scene_set_scalars(scene, 0, nv, values.data(), &fixed), "set_scalars");
  ok(cagekit_render_scene_get_item_info(scene, 0, &info), "get_item_info");
  CHECK(info.scalar_min == 0 && info.scalar_max == 2 * expected);
  CHECK(cagekit_render_scene_set_scalars(scene, 0, nv - 1, values.data(), nullptr) == CAGEKIT_ERROR_INVALID_ARGUMENT);
  cagekit_render_scene_release(scene);
}

cagekit_render_scene overview_scene(uint32_t w, uint32_t h, cagekit_mesh scan, cagekit_cage cage) {
  cagekit_render_scene scene = new_scene(w, h, true);
  set_views(scene, {CAGEKIT_RENDER_VIEW_ISO, CAGEKIT_RENDER_VIEW_FRONT});
  cagekit_render_item_options item = CAGEKIT_RENDER_ITEM_OPTIONS_INIT;
  item.title = "scan";
  ok(cagekit_render_scene_add_mesh(scene, scan, CAGEKIT_RENDER_ITEM_MESH, &item, nullptr), "add_mesh");
  item.title = "cage over limit";
  item.wireframe = 1;
  item.creases = 1;
  ok(cagekit_render_scene_add_cage(scene, cage, &item, nullptr), "add_cage");
  item = CAGEKIT_RENDER_ITEM_OPTIONS_INIT;
  item.title = "error map";
  uint32_t error_item = 0;
  ok(cagekit_render_scene_add_cage(scene, cage, &item, &error_item), "add_cage");
  ok(cagekit_render_scene_set_distance_to_scan(scene, error_item, scan, nullptr), "distance");
  return scene;
}

// Identical input gives identical bytes: two draws of one scene, and two scenes built alike.
void case_deterministic() {
  const Input in;
  cagekit_mesh scan = in.scan;
  cagekit_cage cage = in.cage;
  cagekit_render_scene a = overview_scene(480, 320, scan, cage);
  cagekit_render_scene b = overview_scene(480, 320, scan, cage);
  const Image a1 = draw(a, 480, 320), a2 = draw(a, 480, 320), b1 = draw(b, 480, 320);
  CHECK(a1.rgba == a2.rgba);
  CHECK(a1.rgba == b1.rgba);
  cagekit_render_scene_release(a);
  cagekit_render_scene_release(b);
}

// No EGL display: a clean UNSUPPORTED_FEATURE naming the library (the egl_library option).
void case_no_egl() {
  cagekit_render_scene scene = nullptr;
  ok(cagekit_render_scene_create(g_context, &scene), "create");
  cagekit_render_options options = CAGEKIT_RENDER_OPTIONS_INIT;
  options.width = 64;
  options.height = 64;
  options.egl_library = "/nonexistent/libEGL-cagekit-test.so.1";
  ok(cagekit_render_scene_set_options(scene, &options), "set_options");
  std::vector<uint8_t> rgba(4 * 64 * 64);
  uint32_t count = 0;
  const cagekit_status s = cagekit_render_scene_draw(scene, 64 * 64, &count, rgba.data());
  const std::string message = cagekit_last_error_message(g_context);
  std::printf("no EGL: %s: %s\n", cagekit_status_string(s), message.c_str());
  CHECK(s == CAGEKIT_ERROR_UNSUPPORTED_FEATURE);
  CHECK(message.find("/nonexistent/libEGL-cagekit-test.so.1") != std::string::npos);
  CHECK(cagekit_render_scene_write_png(scene, "/tmp/never-written.png") == CAGEKIT_ERROR_UNSUPPORTED_FEATURE);
  // Bad arguments are named too.
  options.width = 0;
  CHECK(cagekit_render_scene_set_options(scene, &options) == CAGEKIT_ERROR_LIMIT_EXCEEDED);
  CHECK(cagekit_render_scene_draw(scene, 0, nullptr, nullptr) == CAGEKIT_ERROR_INVALID_ARGUMENT);
  cagekit_render_camera camera = CAGEKIT_RENDER_CAMERA_INIT;
  camera.view = CAGEKIT_RENDER_VIEW_CUSTOM;
  camera.eye[0] = camera.target[0] = 0;
  camera.eye[2] = camera.target[2] = 0;
  CHECK(cagekit_render_scene_set_views(scene, 1, &camera) == CAGEKIT_ERROR_INVALID_ARGUMENT);
  cagekit_render_scene_release(scene);
}

// The host context lacks a feature: GLES 2 / GL 2.1, a loader without an entry point, no context.
cagekit_gl_proc null_for_vertex_arrays(const char* name, void*) {
  if (std::strcmp(name, "glGenVertexArrays") == 0) return nullptr;
  return EglContext::get_proc_address(name, nullptr);
}

const char* g_fake_version = "";
const GLubyte* APIENTRY fake_get_string(GLenum name) {
  if (name == GL_VERSION) return reinterpret_cast<const GLubyte*>(g_fake_version);
  return EglContext::load<PFNGLGETSTRINGPROC>("glGetString")(name);
}
cagekit_gl_proc old_version_loader(const char* name, void*) {
  if (std::strcmp(name, "glGetString") == 0) return reinterpret_cast<cagekit_gl_proc>(fake_get_string);
  return EglContext::get_proc_address(name, nullptr);
}

void case_host_lacks_feature() {
  const Input in;
  cagekit_mesh scan = in.scan;
  cagekit_render_scene scene = new_scene(64, 64, false);
  ok(cagekit_render_scene_add_mesh(scene, scan, CAGEKIT_RENDER_ITEM_MESH, nullptr, nullptr), "add_mesh");
  std::vector<uint8_t> rgba(4 * 64 * 64);
  uint32_t count = 0;
  {
    // No context current on this thread.
    const cagekit_status s =
        cagekit_gl_render_scene_draw(scene, EglContext::get_proc_address, nullptr, 64 * 64, &count, rgba.data());
    std::printf("no context: %s: %s\n", cagekit_status_string(s), cagekit_last_error_message(g_context));
    CHECK(s == CAGEKIT_ERROR_INVALID_OPERATION);
  }
  EglContext core(EglContext::Api::desktop_core, 3, 3);
  if (!core.ok()) {
    std::printf("SKIP: %s\n", core.error().c_str());
    std::exit(77);
  }
  // An old context. Mesa answers a request for GLES 2.0 or GL 2.1 with a newer, compatible
  // context, so the host's loader reports the old version through glGetString(GL_VERSION).
  for (const char* version : {"OpenGL ES 2.0 Mesa (test)", "2.1 Mesa (test)", "3.2 (Core Profile) Mesa (test)"}) {
    g_fake_version = version;
    const cagekit_status s =
        cagekit_gl_render_scene_draw(scene, old_version_loader, nullptr, 64 * 64, &count, rgba.data());
    const std::string message = cagekit_last_error_message(g_context);
    std::printf("old context: %s: %s\n", cagekit_status_string(s), message.c_str());
    CHECK(s == CAGEKIT_ERROR_UNSUPPORTED_FEATURE);
    CHECK(message.find("3.3") != std::string::npos && message.find(version) != std::string::npos);
  }
  const cagekit_status s = cagekit_gl_render_scene_draw(scene, null_for_vertex_arrays, nullptr, 64 * 64, &count, rgba.data());
  const std::string message = cagekit_last_error_message(g_context);
  std::printf("missing entry point: %s: %s\n", cagekit_status_string(s), message.c_str());
  CHECK(s == CAGEKIT_ERROR_UNSUPPORTED_FEATURE);
  CHECK(message.find("glGenVertexArrays") != std::string::npos);
  cagekit_render_scene_release(scene);
}

// Drawing into the host's context leaves its GL state unchanged, and gives the headless bytes.
void case_host_state() {
  const Input in;
  cagekit_mesh scan = in.scan;
  cagekit_cage cage = in.cage;
  cagekit_render_scene scene = overview_scene(400, 300, scan, cage);
  const Image headless = draw(scene, 400, 300);
  EglContext context(EglContext::Api::desktop_core, 3, 3);
  if (!context.ok()) {
    std::printf("SKIP: %s\n", context.error().c_str());
    std::exit(77);
  }
  auto GenBuffers = EglContext::load<PFNGLGENBUFFERSPROC>("glGenBuffers");
  auto BindBuffer = EglContext::load<PFNGLBINDBUFFERPROC>("glBindBuffer");
  auto BufferData = EglContext::load<PFNGLBUFFERDATAPROC>("glBufferData");
  auto GenVertexArrays = EglContext::load<PFNGLGENVERTEXARRAYSPROC>("glGenVertexArrays");
  auto BindVertexArray = EglContext::load<PFNGLBINDVERTEXARRAYPROC>("glBindVertexArray");
  auto GenFramebuffers = EglContext::load<PFNGLGENFRAMEBUFFERSPROC>("glGenFramebuffers");
  auto BindFramebuffer = EglContext::load<PFNGLBINDFRAMEBUFFERPROC>("glBindFramebuffer");
  auto GenRenderbuffers = EglContext::load<PFNGLGENRENDERBUFFERSPROC>("glGenRenderbuffers");
  auto BindRenderbuffer = EglContext::load<PFNGLBINDRENDERBUFFERPROC>("glBindRenderbuffer");
  auto RenderbufferStorage = EglContext::load<PFNGLRENDERBUFFERSTORAGEPROC>("glRenderbufferStorage");
  auto FramebufferRenderbuffer = EglContext::load<PFNGLFRAMEBUFFERRENDERBUFFERPROC>("glFramebufferRenderbuffer");
  auto CreateProgram = EglContext::load<PFNGLCREATEPROGRAMPROC>("glCreateProgram");
  auto CreateShader = EglContext::load<PFNGLCREATESHADERPROC>("glCreateShader");
  auto ShaderSource = EglContext::load<PFNGLSHADERSOURCEPROC>("glShaderSource");
  auto CompileShader = EglContext::load<PFNGLCOMPILESHADERPROC>("glCompileShader");
  auto AttachShader = EglContext::load<PFNGLATTACHSHADERPROC>("glAttachShader");
  auto LinkProgram = EglContext::load<PFNGLLINKPROGRAMPROC>("glLinkProgram");
  auto UseProgram = EglContext::load<PFNGLUSEPROGRAMPROC>("glUseProgram");
  auto Enable = EglContext::load<PFNGLENABLEPROC>("glEnable");
  auto Disable = EglContext::load<PFNGLDISABLEPROC>("glDisable");
  auto Viewport = EglContext::load<PFNGLVIEWPORTPROC>("glViewport");
  auto Scissor = EglContext::load<PFNGLSCISSORPROC>("glScissor");
  auto ClearColor = EglContext::load<PFNGLCLEARCOLORPROC>("glClearColor");
  auto ClearDepth = EglContext::load<PFNGLCLEARDEPTHPROC>("glClearDepth");
  auto DepthFunc = EglContext::load<PFNGLDEPTHFUNCPROC>("glDepthFunc");
  auto DepthMask = EglContext::load<PFNGLDEPTHMASKPROC>("glDepthMask");
  auto ColorMask = EglContext::load<PFNGLCOLORMASKPROC>("glColorMask");
  auto PolygonOffset = EglContext::load<PFNGLPOLYGONOFFSETPROC>("glPolygonOffset");
  auto PixelStorei = EglContext::load<PFNGLPIXELSTOREIPROC>("glPixelStorei");
  auto GetIntegerv = EglContext::load<PFNGLGETINTEGERVPROC>("glGetIntegerv");
  auto GetFloatv = EglContext::load<PFNGLGETFLOATVPROC>("glGetFloatv");
  auto GetBooleanv = EglContext::load<PFNGLGETBOOLEANVPROC>("glGetBooleanv");
  auto IsEnabled = EglContext::load<PFNGLISENABLEDPROC>("glIsEnabled");
  auto GetError = EglContext::load<PFNGLGETERRORPROC>("glGetError");

  // A host state far from the defaults.
  GLuint vao = 0, buffers[2] = {0, 0}, fb = 0, rb = 0;
  GenVertexArrays(1, &vao);
  BindVertexArray(vao);
  GenBuffers(2, buffers);
  BindBuffer(GL_ARRAY_BUFFER, buffers[0]);
  BufferData(GL_ARRAY_BUFFER, 64, nullptr, GL_STATIC_DRAW);
  BindBuffer(GL_PIXEL_PACK_BUFFER, buffers[1]);
  BufferData(GL_PIXEL_PACK_BUFFER, 64, nullptr, GL_STREAM_READ);
  GenRenderbuffers(1, &rb);
  BindRenderbuffer(GL_RENDERBUFFER, rb);
  RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, 8, 8);
  GenFramebuffers(1, &fb);
  BindFramebuffer(GL_FRAMEBUFFER, fb);
  FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb);
  const char* vs = "#version 330 core\nvoid main() { gl_Position = vec4(0.0); }\n";
  const char* fs = "#version 330 core\nout vec4 c; void main() { c = vec4(1.0); }\n";
  const GLuint program = CreateProgram();
  for (auto [type, text] : {std::pair{GLenum(GL_VERTEX_SHADER), vs}, std::pair{GLenum(GL_FRAGMENT_SHADER), fs}}) {
    const GLuint shader = CreateShader(type);
    ShaderSource(shader, 1, &text, nullptr);
    CompileShader(shader);
    AttachShader(program, shader);
  }
  LinkProgram(program);
  UseProgram(program);
  Enable(GL_CULL_FACE);
  Enable(GL_BLEND);
  Enable(GL_SCISSOR_TEST);
  Disable(GL_DITHER);
  Enable(GL_POLYGON_OFFSET_FILL);
  Viewport(1, 2, 3, 4);
  Scissor(2, 3, 4, 5);
  ClearColor(0.25f, 0.5f, 0.75f, 0.125f);
  ClearDepth(0.5);
  DepthFunc(GL_GREATER);
  DepthMask(GL_FALSE);
  ColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE);
  PolygonOffset(3.0f, 4.0f);
  PixelStorei(GL_PACK_ALIGNMENT, 1);
  PixelStorei(GL_PACK_ROW_LENGTH, 7);
  CHECK(GetError() == GL_NO_ERROR);

  const GLenum int_queries[] = {GL_CURRENT_PROGRAM, GL_VERTEX_ARRAY_BINDING, GL_ARRAY_BUFFER_BINDING,
                                GL_ELEMENT_ARRAY_BUFFER_BINDING, GL_PIXEL_PACK_BUFFER_BINDING,
                                GL_DRAW_FRAMEBUFFER_BINDING, GL_READ_FRAMEBUFFER_BINDING, GL_RENDERBUFFER_BINDING,
                                GL_DEPTH_FUNC, GL_PACK_ALIGNMENT, GL_PACK_ROW_LENGTH, GL_PACK_SKIP_PIXELS,
                                GL_PACK_SKIP_ROWS, GL_ACTIVE_TEXTURE, GL_TEXTURE_BINDING_2D, GL_UNIFORM_BUFFER_BINDING};
  const GLenum enables[] = {GL_DEPTH_TEST, GL_CULL_FACE, GL_BLEND, GL_SCISSOR_TEST, GL_STENCIL_TEST,
                            GL_POLYGON_OFFSET_FILL, GL_DITHER, GL_RASTERIZER_DISCARD};
  auto snapshot = [&] {
    std::vector<double> s;
    for (GLenum q : int_queries) {
      GLint v = -1;
      GetIntegerv(q, &v);
      s.push_back(v);
    }
    GLint box[8];
    GetIntegerv(GL_VIEWPORT, box);
    GetIntegerv(GL_SCISSOR_BOX, box + 4);
    s.insert(s.end(), box, box + 8);
    for (GLenum e : enables) s.push_back(IsEnabled(e));
    GLfloat f[7];
    GetFloatv(GL_COLOR_CLEAR_VALUE, f);
    GetFloatv(GL_DEPTH_CLEAR_VALUE, f + 4);
    GetFloatv(GL_POLYGON_OFFSET_FACTOR, f + 5);
    GetFloatv(GL_POLYGON_OFFSET_UNITS, f + 6);
    s.insert(s.end(), f, f + 7);
    GLboolean b[5];
    GetBooleanv(GL_COLOR_WRITEMASK, b);
    GetBooleanv(GL_DEPTH_WRITEMASK, b + 4);
    s.insert(s.end(), b, b + 5);
    return s;
  };
  const std::vector<double> before = snapshot();
  Image hosted;
  hosted.width = 400;
  hosted.height = 300;
  hosted.rgba.resize(4 * 400 * 300);
  uint32_t count = 0;
  ok(cagekit_gl_render_scene_draw(scene, EglContext::get_proc_address, nullptr, 400 * 300, &count, hosted.rgba.data()),
     "cagekit_gl_render_scene_draw");
  const std::vector<double> after = snapshot();
  CHECK(GetError() == GL_NO_ERROR);
  for (size_t i = 0; i < before.size(); ++i)
    if (before[i] != after[i]) {
      std::fprintf(stderr, "state %zu changed: %g -> %g\n", i, before[i], after[i]);
      ++failures;
    }
  CHECK(hosted.rgba == headless.rgba);
  cagekit_render_scene_release(scene);
}

std::vector<uint8_t> read_png(const std::string& path, uint32_t& w, uint32_t& h) {
  png_image image;
  std::memset(&image, 0, sizeof(image));
  image.version = PNG_IMAGE_VERSION;
  std::vector<uint8_t> out;
  if (!png_image_begin_read_from_file(&image, path.c_str())) return out;
  image.format = PNG_FORMAT_RGBA;
  out.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, out.data(), 0, nullptr)) out.clear();
  w = image.width;
  h = image.height;
  return out;
}

// A PNG written and read back (libpng) equals the RGBA buffer; the blob holds the same bytes.
void case_png() {
  const Input in;
  cagekit_mesh scan = in.scan;
  cagekit_cage cage = in.cage;
  cagekit_render_scene scene = overview_scene(300, 200, scan, cage);
  const Image image = draw(scene, 300, 200);
  const std::string path = std::string(CAGEKIT_TEST_OUT) + "/render_png_case.png";
  ok(cagekit_render_scene_write_png(scene, path.c_str()), "write_png");
  uint32_t w = 0, h = 0;
  const std::vector<uint8_t> back = read_png(path, w, h);
  CHECK(w == 300 && h == 200);
  CHECK(back == image.rgba);
  cagekit_blob blob = nullptr;
  ok(cagekit_render_scene_encode_png(scene, &blob), "encode_png");
  FILE* f = std::fopen(path.c_str(), "rb");
  std::vector<uint8_t> file(cagekit_blob_size(blob) + 1);
  const size_t n = f != nullptr ? std::fread(file.data(), 1, file.size(), f) : 0;
  if (f != nullptr) std::fclose(f);
  CHECK(n == cagekit_blob_size(blob));
  CHECK(std::memcmp(file.data(), cagekit_blob_data(blob), n) == 0);
  cagekit_blob_release(blob);
  // A caller's buffer encodes to the same file.
  const std::string path2 = std::string(CAGEKIT_TEST_OUT) + "/render_png_case_buffer.png";
  ok(cagekit_render_encode_png(g_context, image.rgba.data(), 300, 200, path2.c_str(), nullptr), "encode buffer");
  const std::vector<uint8_t> back2 = read_png(path2, w, h);
  CHECK(back2 == image.rgba);
  CHECK(cagekit_render_scene_write_png(scene, "/nonexistent-dir/x.png") == CAGEKIT_ERROR_IO);
  cagekit_render_scene_release(scene);
}

void picture(const char* out, uint32_t w, uint32_t h) {
  const Input in;
  cagekit_mesh scan = in.scan;
  cagekit_cage cage = in.cage;
  cagekit_render_scene scene = overview_scene(w, h, scan, cage);
  ok(cagekit_render_scene_write_png(scene, out), "write_png");
  cagekit_render_scene_release(scene);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: test_render CASE [--generated] | picture OUT.png [W H] [--generated]\n");
    return 2;
  }
  cagekit_context_desc desc = CAGEKIT_CONTEXT_DESC_INIT;
  ok(cagekit_context_create(&desc, &g_context), "cagekit_context_create");
  const std::map<std::string, std::function<void()>> cases = {
      {"size_and_coverage", case_size_and_coverage}, {"creases", case_creases},
      {"legend_range", case_legend_range},           {"deterministic", case_deterministic},
      {"no_egl", case_no_egl},                       {"host_lacks_feature", case_host_lacks_feature},
      {"host_state", case_host_state},               {"png", case_png}};
  const std::string name = argv[1];
  for (int i = 2; i < argc; ++i)
    if (std::strcmp(argv[i], "--generated") == 0) g_generated = true;
  if (name == "picture" && argc >= 3) {
    const bool size = argc >= 5 && std::strcmp(argv[3], "--generated") != 0;
    picture(argv[2], size ? uint32_t(std::atoi(argv[3])) : 960, size ? uint32_t(std::atoi(argv[4])) : 640);
  } else {
    auto it = cases.find(name);
    if (it == cases.end()) {
      std::fprintf(stderr, "unknown case %s\n", argv[1]);
      return 2;
    }
    it->second();
  }
  cagekit_context_release(g_context);
  if (failures != 0) std::fprintf(stderr, "%d check(s) failed\n", failures);
  return failures == 0 ? 0 : 1;
}
