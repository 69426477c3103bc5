// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/status.h"
#include "render/scan_distance.h"
#include "subdiv/uniform_refinement.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

void require_valid_indices(const PolygonMesh& mesh, const char* what) {
  const size_t n = mesh.num_vertices();
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    if (!is_finite(mesh.positions[i]))
      fail(Status::invalid_mesh, std::string(what) + ": vertex " + std::to_string(i) + " is not finite");
  for (size_t f = 0; f < mesh.num_faces(); ++f)
    for (uint32_t k = 0; k < mesh.face_size(f); ++k)
      if (mesh.face_vertex(f, k) >= n)
        fail(Status::invalid_mesh, std::string(what) + ": face " + std::to_string(f) + " names vertex " +
                                       std::to_string(mesh.face_vertex(f, k)) + " of " + std::to_string(n));
}

void grow(RenderItem& item, const Vec3& p) {
  for (int i = 0; i < 3; ++i) {
    item.lo[i] = std::min(item.lo[i], p[i]);
    item.hi[i] = std::max(item.hi[i], p[i]);
  }
}

void push(std::vector<float>& out, const Vec3& p) {
  out.push_back(float(p.x));
  out.push_back(float(p.y));
  out.push_back(float(p.z));
}

// Positions, area-weighted vertex normals and fan triangles of `mesh`, skipping the faces in
// `skip` (sorted).
void fill_surface(RenderItem& item, const PolygonMesh& mesh, const std::vector<uint32_t>& skip) {
  const size_t n = mesh.num_vertices();
  std::vector<Vec3> normal(n);
  item.positions.clear();
  item.positions.reserve(3 * n);
  for (const Vec3& p : mesh.positions) {
    push(item.positions, p);
    grow(item, p);
  }
  item.triangles.clear();
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    if (!skip.empty() && std::binary_search(skip.begin(), skip.end(), uint32_t(f))) continue;
    mesh.for_each_fan_triangle(f, [&](uint32_t a, uint32_t b, uint32_t c) {
      item.triangles.insert(item.triangles.end(), {a, b, c});
      const Vec3 w = cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
      normal[a] += w;
      normal[b] += w;
      normal[c] += w;
    });
  }
  item.normals.clear();
  item.normals.reserve(3 * n);
  for (const Vec3& v : normal) push(item.normals, normalized(v));
}

// Each undirected edge of the mesh once, as segments.
void fill_edges(std::vector<float>& out, const PolygonMesh& mesh) {
  std::vector<uint64_t> keys;
  keys.reserve(mesh.num_face_vertices());
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t size = mesh.face_size(f);
    for (uint32_t k = 0; k < size; ++k) {
      const uint32_t a = mesh.face_vertex(f, k), b = mesh.face_vertex(f, (k + 1) % size);
      keys.push_back((uint64_t(std::min(a, b)) << 32) | std::max(a, b));
    }
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  out.reserve(out.size() + 6 * keys.size());
  for (uint64_t key : keys) {
    push(out, mesh.positions[size_t(key >> 32)]);
    push(out, mesh.positions[size_t(key & 0xffffffffu)]);
  }
}

void fill_creases(std::vector<float>& out, const Cage& cage) {
  for (const EdgeCrease& c : cage.creases) {
    if (c.sharpness <= 0 || c.v0 >= cage.mesh.num_vertices() || c.v1 >= cage.mesh.num_vertices()) continue;
    push(out, cage.mesh.positions[c.v0]);
    push(out, cage.mesh.positions[c.v1]);
  }
}

Rgba with_default(const Rgba& c, const Rgba& fallback) { return c[3] > 0 ? c : fallback; }

void check_color(const Rgba& c, const char* name) {
  for (float v : c)
    if (!(v >= 0.0f && v <= 1.0f))
      fail(Status::invalid_argument, std::string(name) + " components must be in [0, 1]");
}

}  // namespace

Rgba default_surface_color(ItemKind kind) {
  switch (kind) {
    case ItemKind::cage: return {0.62f, 0.74f, 0.90f, 1.0f};          // light blue
    case ItemKind::deformed_scan: return {0.90f, 0.72f, 0.50f, 1.0f}; // tan
    case ItemKind::mesh: break;
  }
  return {0.78f, 0.78f, 0.76f, 1.0f};  // light grey
}

std::array<float, 3> colormap_color(Colormap map, double t) {
  if (!(t >= 0.0)) t = 0.0;  // NaN too
  if (t > 1.0) t = 1.0;
  // Viridis (matplotlib's, sampled at 9 points and interpolated linearly) and a diverging
  // blue-white-red.
  static const float viridis[9][3] = {{0.267f, 0.005f, 0.329f}, {0.279f, 0.175f, 0.483f}, {0.230f, 0.322f, 0.546f},
                                      {0.173f, 0.449f, 0.558f}, {0.128f, 0.567f, 0.551f}, {0.153f, 0.683f, 0.504f},
                                      {0.360f, 0.785f, 0.388f}, {0.678f, 0.864f, 0.190f}, {0.993f, 0.906f, 0.144f}};
  static const float bwr[3][3] = {{0.230f, 0.299f, 0.754f}, {0.970f, 0.970f, 0.970f}, {0.706f, 0.016f, 0.150f}};
  const float(*table)[3] = map == Colormap::viridis ? viridis : bwr;
  const int n = map == Colormap::viridis ? 9 : 3;
  const double x = t * (n - 1);
  const int i = std::min(n - 2, int(x));
  const float f = float(x - i);
  return {table[i][0] + f * (table[i + 1][0] - table[i][0]), table[i][1] + f * (table[i + 1][1] - table[i][1]),
          table[i][2] + f * (table[i + 1][2] - table[i][2])};
}

const RenderItem& RenderScene::item(size_t i) const {
  if (i >= items_.size())
    fail(Status::invalid_argument, "item " + std::to_string(i) + " is not in the scene (" +
                                       std::to_string(items_.size()) + " items)");
  return items_[i];
}

RenderItem& RenderScene::mutable_item(size_t i) { return const_cast<RenderItem&>(item(i)); }

static void check_style(const ItemStyle& style) {
  check_color(style.color, "color");
  check_color(style.wire_color, "wire_color");
  check_color(style.crease_color, "crease_color");
  if (style.level < 0 || style.level > kMaxRenderLevel)
    fail(Status::invalid_argument, "tessellation_level must be 0 (automatic) .. " + std::to_string(kMaxRenderLevel) +
                                       ", not " + std::to_string(style.level));
}

size_t RenderScene::add_mesh(const PolygonMesh& mesh, ItemKind kind, const ItemStyle& style) {
  check_style(style);
  require_valid_indices(mesh, "mesh");
  RenderItem item;
  item.kind = kind;
  item.style = style;
  item.style.color = with_default(style.color, default_surface_color(kind));
  item.style.wire_color = with_default(style.wire_color, kDefaultWireColor);
  item.style.crease_color = with_default(style.crease_color, kDefaultCreaseColor);
  fill_surface(item, mesh, {});
  if (style.wireframe) fill_edges(item.wire, mesh);
  items_.push_back(std::move(item));
  return items_.size() - 1;
}

size_t RenderScene::add_cage(const Cage& cage, const ItemStyle& style, const TaskMonitor& monitor) {
  check_style(style);
  require_valid_indices(cage.mesh, "cage");
  int level = style.level;
  if (level == 0) {
    level = 1;
    const double quads = double(cage.mesh.num_face_vertices());  // faces after one level
    while (level < 4 && quads * std::pow(4.0, level) <= 262144.0) ++level;
  }
  RefineOptions options;
  options.levels = level;
  options.limit_positions = true;
  const Cage limit = refine_uniform(cage, options, monitor);
  RenderItem item;
  item.kind = ItemKind::cage;
  item.level = level;
  item.style = style;
  item.style.color = with_default(style.color, default_surface_color(ItemKind::cage));
  item.style.wire_color = with_default(style.wire_color, kDefaultWireColor);
  item.style.crease_color = with_default(style.crease_color, kDefaultCreaseColor);
  std::vector<uint32_t> holes = limit.holes;
  std::sort(holes.begin(), holes.end());
  fill_surface(item, limit.mesh, holes);
  if (style.wireframe) {
    fill_edges(item.wire, cage.mesh);
    for (const Vec3& p : cage.mesh.positions) grow(item, p);
  }
  if (style.creases) {
    fill_creases(item.crease, cage);  // the tagged control edges
    fill_creases(item.crease, limit);  // and the crease curves on the limit surface
    for (const Vec3& p : cage.mesh.positions) grow(item, p);
  }
  items_.push_back(std::move(item));
  return items_.size() - 1;
}

void RenderScene::set_scalars(size_t index, const std::vector<double>& values, const ScalarStyle& style) {
  RenderItem& item = mutable_item(index);
  if (values.size() != item.vertex_count())
    fail(Status::invalid_argument, "item " + std::to_string(index) + " draws " + std::to_string(item.vertex_count()) +
                                       " vertices but " + std::to_string(values.size()) + " scalars were given");
  if (int(style.colormap) < 0 || int(style.colormap) > 1)
    fail(Status::invalid_argument, "colormap is not a cagekit_render_colormap");
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i]))
      fail(Status::invalid_argument, "scalar " + std::to_string(i) + " is not finite");
    lo = std::min(lo, values[i]);
    hi = std::max(hi, values[i]);
  }
  if (values.empty()) lo = hi = 0;
  if (!style.auto_range) {
    if (!std::isfinite(style.range_min) || !std::isfinite(style.range_max) || !(style.range_min < style.range_max))
      fail(Status::invalid_argument, "range_min must be below range_max (both finite) when auto_range is 0");
    lo = style.range_min;
    hi = style.range_max;
  }
  item.scalars.assign(values.begin(), values.end());
  item.scalar_style = style;
  item.shown_min = lo;
  item.shown_max = hi;
}

void RenderScene::set_distance_to_scan(size_t index, const PolygonMesh& scan, const ScalarStyle& style,
                                       const TaskMonitor& monitor) {
  require_valid_indices(scan, "scan");
  const RenderItem& item = this->item(index);
  PolygonMesh surface;
  surface.reserve(item.vertex_count(), item.triangles.size() / 3, item.triangles.size());
  for (size_t v = 0; v < item.vertex_count(); ++v)
    surface.add_vertex(Vec3{item.positions[3 * v], item.positions[3 * v + 1], item.positions[3 * v + 2]});
  for (size_t t = 0; t < item.triangles.size(); t += 3) surface.add_face(&item.triangles[t], 3);
  ScalarStyle s = style;
  if (s.label.empty()) s.label = "distance to scan";
  set_scalars(index, two_sided_distance_to_scan(surface, scan, monitor), s);
}

void RenderScene::set_settings(RenderSettings s) {
  if (s.width < 1 || s.height < 1 || s.width > kMaxImageSide || s.height > kMaxImageSide)
    fail(Status::limit_exceeded, "the image is " + std::to_string(s.width) + " x " + std::to_string(s.height) +
                                     "; each side must be 1 .. " + std::to_string(kMaxImageSide));
  check_color(s.background, "background");
  if (s.views.empty()) fail(Status::invalid_argument, "a scene needs at least one view");
  if (s.views.size() > kMaxViews)
    fail(Status::limit_exceeded, std::to_string(s.views.size()) + " views, more than " + std::to_string(kMaxViews));
  for (size_t i = 0; i < s.views.size(); ++i) {
    const Camera& c = s.views[i];
    if (int(c.kind) < 0 || int(c.kind) > 4) fail(Status::invalid_argument, "view " + std::to_string(i) + " is not a cagekit_render_view");
    if (!(c.fov_degrees > 1.0 && c.fov_degrees < 170.0))
      fail(Status::invalid_argument, "view " + std::to_string(i) + ": fov_degrees must be in (1, 170)");
    if (c.kind == ViewKind::custom) {
      if (!is_finite(c.eye) || !is_finite(c.target) || !is_finite(c.up) || norm(c.eye - c.target) == 0.0 ||
          norm(cross(c.eye - c.target, c.up)) == 0.0)
        fail(Status::invalid_argument, "view " + std::to_string(i) +
                                           ": eye, target and up must be finite, eye != target, up not along the view");
    }
  }
  settings_ = std::move(s);
}

std::vector<int> RenderScene::item_columns(int* column_count) const {
  std::vector<int> column(items_.size(), 0);
  int next = 0;
  for (size_t i = 0; i < items_.size(); ++i) column[i] = (items_[i].style.overlay && i > 0) ? column[i - 1] : next++;
  if (column_count != nullptr) *column_count = std::max(1, next);
  return column;
}

CAGEKIT_NAMESPACE_END
