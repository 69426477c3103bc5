// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A render scene: items (a mesh, a cage drawn as its Catmull-Clark limit surface, a deformed
// scan), per-item style and per-vertex scalars with a colour map, and the views tiled into one
// image. Geometry is prepared on the CPU when an item is added (cages are refined with
// refine_uniform + limit positions), so drawing only uploads and rasterises.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/cage.h"
#include "core/polygon_mesh.h"
#include "core/task_monitor.h"

CAGEKIT_NAMESPACE_BEGIN

using Rgba = std::array<float, 4>;

// Values match the C header's cagekit_render_colormap.
enum class Colormap : int { viridis = 0, blue_white_red = 1 };
// Values match cagekit_render_view.
enum class ViewKind : int { front = 0, side = 1, top = 2, iso = 3, custom = 4 };
// Values match cagekit_render_item_kind.
enum class ItemKind : int { mesh = 0, cage = 1, deformed_scan = 2 };

struct ItemStyle {
  bool surface = true;
  bool wireframe = false;
  bool creases = false;
  bool overlay = false;  // drawn in the previous item's column
  int level = 0;         // cages: refinement level of the limit surface, 0 = automatic
  Rgba color{0, 0, 0, 0};  // alpha 0: the kind's default
  Rgba wire_color{0, 0, 0, 0};
  Rgba crease_color{0, 0, 0, 0};
  std::string title;
};

struct ScalarStyle {
  Colormap colormap = Colormap::viridis;
  bool auto_range = true;
  double range_min = 0, range_max = 0;  // used when !auto_range
  bool legend = true;
  std::string label;
};

struct RenderItem {
  ItemKind kind = ItemKind::mesh;
  ItemStyle style;
  int level = 0;  // the refinement level used (cages)
  // Drawn surface: float positions, unit normals, triangles.
  std::vector<float> positions, normals;  // xyz per vertex
  std::vector<uint32_t> triangles;
  // Lines, as segment end points (xyz, two per segment).
  std::vector<float> wire, crease;
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};  // bounding box of everything drawn
  // Per-vertex scalar (empty: none), kept as given (get_scalars returns these values, and the
  // range shown is their min / max exactly; the draw uploads them as float), and the range shown.
  std::vector<double> scalars;
  ScalarStyle scalar_style;
  double shown_min = 0, shown_max = 0;
  size_t vertex_count() const { return positions.size() / 3; }
};

struct Camera {
  ViewKind kind = ViewKind::iso;
  Vec3 eye{0, 0, 1}, target{0, 0, 0}, up{0, 1, 0};  // custom only
  double fov_degrees = 30;
};

// Values match cagekit_render_display.
enum class DisplayChoice : int { automatic = 0, surfaceless = 1, device = 2 };

struct RenderSettings {
  int width = 800, height = 600;
  Rgba background{1, 1, 1, 1};
  bool labels = true;  // titles, view names and legends
  std::vector<Camera> views{Camera{}};
  std::string egl_library;  // empty: $CAGEKIT_EGL_LIBRARY, else libEGL.so.1
  DisplayChoice display = DisplayChoice::automatic;
};

// Bounds on what a scene accepts (hostile sizes fail with limit_exceeded).
constexpr int kMaxImageSide = 16384;
constexpr int kMaxRenderLevel = 6;
constexpr size_t kMaxViews = 64;

class RenderScene {
 public:
  // Adds a mesh (faces fan-triangulated; faces with bad indices are an invalid_mesh error).
  size_t add_mesh(const PolygonMesh& mesh, ItemKind kind, const ItemStyle& style);
  // Adds a cage: its limit surface refined `style.level` times (0: the largest level <= 4 that
  // keeps <= 262144 faces, at least 1), the control edges as wireframe, the crease-tagged
  // control edges and the refined crease edges on the limit surface as creases.
  size_t add_cage(const Cage& cage, const ItemStyle& style, const TaskMonitor& monitor = {});
  void set_scalars(size_t item, const std::vector<double>& values, const ScalarStyle& style);
  // Two-sided distance to `scan` for every vertex of the item's drawn surface (see
  // scan_distance.h), set as its scalars.
  void set_distance_to_scan(size_t item, const PolygonMesh& scan, const ScalarStyle& style,
                            const TaskMonitor& monitor = {});

  const std::vector<RenderItem>& items() const { return items_; }
  const RenderItem& item(size_t i) const;
  RenderSettings& settings() { return settings_; }
  const RenderSettings& settings() const { return settings_; }
  void set_settings(RenderSettings s);

  // Layout: the column of each item (an overlay item shares its predecessor's column).
  std::vector<int> item_columns(int* column_count) const;

 private:
  RenderItem& mutable_item(size_t i);
  std::vector<RenderItem> items_;
  RenderSettings settings_;
};

// The colour of t in [0, 1] (clamped) under `map`, components in [0, 1].
std::array<float, 3> colormap_color(Colormap map, double t);
// Default colours by kind.
Rgba default_surface_color(ItemKind kind);
constexpr Rgba kDefaultWireColor{0.10f, 0.10f, 0.12f, 1.0f};
constexpr Rgba kDefaultCreaseColor{0.90f, 0.15f, 0.55f, 1.0f};  // magenta-red, not in either colour map

CAGEKIT_NAMESPACE_END
