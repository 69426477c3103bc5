// SPDX-License-Identifier: GPL-3.0-or-later
// Rendering (issue 24): the C shim over render/RenderScene. Built without the render module
// (CAGEKIT_WITH_RENDER off), every entry point but retain / release answers
// CAGEKIT_ERROR_UNSUPPORTED_FEATURE.
#include <cstring>
#include <memory>
#include <string>

#include <cagekit/cagekit_gl.h>

#include "capi/api_guard.h"

#if CAGEKIT_WITH_RENDER
#include <mutex>

#include "render/egl_headless.h"
#include "render/png_writer.h"
#include "render/render_gl.h"
#include "render/scene.h"
#endif

using namespace cagekit_capi;

#if CAGEKIT_WITH_RENDER

struct cagekit_render_scene_t : ContextBound {
  static constexpr HandleType kType = static_cast<HandleType>(0x524e4431);  // "RND1"
  explicit cagekit_render_scene_t(cagekit_context c) : ContextBound(kType, c) {}
  cagekit::RenderScene scene;
};

namespace {

cagekit::Rgba rgba_of(const float c[4]) { return {c[0], c[1], c[2], c[3]}; }

cagekit::ItemStyle style_from_c(const cagekit_render_item_options* in) {
  const cagekit_render_item_options defaults = CAGEKIT_RENDER_ITEM_OPTIONS_INIT;
  const cagekit_render_item_options o = read_versioned(in, defaults, "cagekit_render_item_options");
  cagekit::ItemStyle s;
  s.surface = bool_from_c(o.surface, "cagekit_render_item_options.surface");
  s.wireframe = bool_from_c(o.wireframe, "cagekit_render_item_options.wireframe");
  s.creases = bool_from_c(o.creases, "cagekit_render_item_options.creases");
  s.overlay = bool_from_c(o.overlay, "cagekit_render_item_options.overlay");
  if (o.tessellation_level > uint32_t(cagekit::kMaxRenderLevel))
    fail(Status::invalid_argument, "cagekit_render_item_options.tessellation_level must be 0 .. " +
                                       std::to_string(cagekit::kMaxRenderLevel) + ", not " +
                                       std::to_string(o.tessellation_level));
  s.level = int(o.tessellation_level);
  s.color = rgba_of(o.color);
  s.wire_color = rgba_of(o.wire_color);
  s.crease_color = rgba_of(o.crease_color);
  if (o.title != nullptr) s.title = o.title;
  return s;
}

cagekit::ScalarStyle scalar_style_from_c(const cagekit_render_scalar_options* in) {
  const cagekit_render_scalar_options defaults = CAGEKIT_RENDER_SCALAR_OPTIONS_INIT;
  const cagekit_render_scalar_options o = read_versioned(in, defaults, "cagekit_render_scalar_options");
  const int32_t map = raw_enum(o.colormap);
  if (map < 0 || map > 1)
    fail(Status::invalid_argument, "cagekit_render_scalar_options.colormap is not a cagekit_render_colormap");
  cagekit::ScalarStyle s;
  s.colormap = cagekit::Colormap(map);
  s.auto_range = bool_from_c(o.auto_range, "cagekit_render_scalar_options.auto_range");
  s.range_min = o.range_min;
  s.range_max = o.range_max;
  s.legend = bool_from_c(o.legend, "cagekit_render_scalar_options.legend");
  if (o.label != nullptr) s.label = o.label;
  return s;
}

uint32_t pixel_count(const cagekit::RenderScene& scene) {
  return uint32_t(scene.settings().width) * uint32_t(scene.settings().height);
}

// Draws in the library's own headless context.
std::vector<uint8_t> draw_headless(const cagekit::RenderScene& scene) {
  cagekit::HeadlessGl context(scene.settings().egl_library, scene.settings().display);
  std::vector<uint8_t> rgba;
  cagekit::draw_scene(scene, context.get_proc_address(), context.user_data(), rgba);
  return rgba;
}

void copy_pixels(const std::vector<uint8_t>& rgba, uint8_t* out) { std::memcpy(out, rgba.data(), rgba.size()); }

}  // namespace

extern "C" {

CAGEKIT_API cagekit_status cagekit_render_scene_create(cagekit_context context, cagekit_render_scene* out) {
  return guarded(is_live(context) ? context : nullptr, [&] {
    require_not_null(out, "out");
    *out = nullptr;
    cagekit_context_t& c = checked(context, "context");
    *out = new cagekit_render_scene_t(&c);
  });
}

CAGEKIT_API void cagekit_render_scene_retain(cagekit_render_scene scene) { retain_handle(scene); }
CAGEKIT_API void cagekit_render_scene_release(cagekit_render_scene scene) { release_handle(scene); }

CAGEKIT_API cagekit_status cagekit_render_scene_set_options(cagekit_render_scene scene,
                                                            const cagekit_render_options* options) {
  return guarded(context_of(scene), [&] {
    cagekit_render_scene_t& s = checked(scene, "scene");
    const cagekit_render_options defaults = CAGEKIT_RENDER_OPTIONS_INIT;
    const cagekit_render_options o = read_versioned(options, defaults, "cagekit_render_options");
    cagekit::RenderSettings settings = s.scene.settings();
    if (o.width < 1 || o.height < 1 || o.width > uint32_t(cagekit::kMaxImageSide) ||
        o.height > uint32_t(cagekit::kMaxImageSide))
      fail(Status::limit_exceeded, "the image is " + std::to_string(o.width) + " x " + std::to_string(o.height) +
                                       "; each side must be 1 .. " + std::to_string(cagekit::kMaxImageSide));
    settings.width = int(o.width);
    settings.height = int(o.height);
    settings.background = rgba_of(o.background);
    settings.labels = bool_from_c(o.labels, "cagekit_render_options.labels");
    const int32_t display = raw_enum(o.display);
    if (display < 0 || display > 2)
      fail(Status::invalid_argument, "cagekit_render_options.display is not a cagekit_render_display");
    settings.display = cagekit::DisplayChoice(display);
    settings.egl_library = o.egl_library != nullptr ? o.egl_library : "";
    s.scene.set_settings(std::move(settings));
  });
}

CAGEKIT_API cagekit_status cagekit_render_scene_get_options(cagekit_render_scene scene, cagekit_render_options* options) {
  return guarded(context_of(scene), [&] {
    const cagekit_render_scene_t& s = checked(scene, "scene");
    require_not_null(options, "options");
    const cagekit::RenderSettings& settings = s.scene.settings();
    cagekit_render_options o = CAGEKIT_RENDER_OPTIONS_INIT;
    o.width = uint32_t(settings.width);
    o.height = uint32_t(settings.height);
    for (int i = 0; i < 4; ++i) o.background[i] = settings.background[size_t(i)];
    o.labels = settings.labels ? CAGEKIT_TRUE : CAGEKIT_FALSE;
    o.display = cagekit_render_display(int(settings.display));
    o.egl_library = settings.egl_library.empty() ? nullptr : settings.egl_library.c_str();
    write_versioned(options, o, "cagekit_render_options");
  });
}

CAGEKIT_API cagekit_status cagekit_render_scene_set_views(cagekit_render_scene scene, uint32_t view_count,
                                                          const cagekit_render_camera* cameras) {
  return guarded(context_of(scene), [&] {
    cagekit_render_scene_t& s = checked(scene, "scene");
    require_not_null(cameras, "cameras");
    if (view_count == 0) fail(Status::invalid_argument, "view_count must be at least 1");
    if (view_count > cagekit::kMaxViews)
      fail(Status::limit_exceeded, std::to_string(view_count) + " views, more than " +
                                       std::to_string(cagekit::kMaxViews));
    // Cameras are an array of the caller's struct: its size comes from the first struct_size.
    const size_t stride = cameras[0].struct_size;
    if (stride < sizeof(size_t) || stride > (1u << 16))
      fail(Status::invalid_argument, "cameras[0].struct_size is " + std::to_string(stride) +
                                         "; set it to sizeof(cagekit_render_camera)");
    const cagekit_render_camera defaults = CAGEKIT_RENDER_CAMERA_INIT;
    cagekit::RenderSettings settings = s.scene.settings();
    settings.views.clear();
    for (uint32_t i = 0; i < view_count; ++i) {
      const auto* in = reinterpret_cast<const cagekit_render_camera*>(reinterpret_cast<const char*>(cameras) +
                                                                      size_t(i) * stride);
      if (in->struct_size != stride)
        fail(Status::invalid_argument, "cameras[" + std::to_string(i) + "].struct_size differs from cameras[0]'s");
      const cagekit_render_camera c = read_versioned(in, defaults, "cagekit_render_camera");
      const int32_t view = raw_enum(c.view);
      if (view < 0 || view > 4)
        fail(Status::invalid_argument, "cameras[" + std::to_string(i) + "].view is not a cagekit_render_view");
      cagekit::Camera camera;
      camera.kind = cagekit::ViewKind(view);
      camera.eye = {c.eye[0], c.eye[1], c.eye[2]};
      camera.target = {c.target[0], c.target[1], c.target[2]};
      camera.up = {c.up[0], c.up[1], c.up[2]};
      camera.fov_degrees = c.fov_degrees;
      settings.views.push_back(camera);
    }
    s.scene.set_settings(std::move(settings));
  });
}

CAGEKIT_API cagekit_status cagekit_render_scene_add_mesh(cagekit_render_scene scene, cagekit_mesh mesh,
                                                         cagekit_render_item_kind kind,
                                                         const cagekit_render_item_options* options,
                                                         uint32_t* item_out) {
  return guarded(context_of(scene), [&] {
    cagekit_render_scene_t& s = checked(scene, "scene");
    const cagekit_mesh_t& m = checked(mesh, "mesh");
    const int32_t k = raw_enum(kind);
    if (k != CAGEKIT_RENDER_ITEM_MESH && k != CAGEKIT_RENDER_ITEM_DEFORMED_SCAN)
      fail(Status::invalid_argument, "kind must be CAGEKIT_RENDER_ITEM_MESH or CAGEKIT_RENDER_ITEM_DEFORMED_SCAN "
                                     "(cages: cagekit_render_scene_add_cage)");
    const size_t index = s.scene.add_mesh(m.mesh, cagekit::ItemKind(k), style_from_c(options));
    if (item_out != nullptr) *item_out = uint32_t(index);
  });
}

CAGEKIT_API cagekit_status cagekit_render_scene_add_cage(cagekit_render_scene scene, cagekit_cage cage,
                                                         const cagekit_render_item_options* options,
                                                         uint32_t* item_out) {
  return guarded(context_of(scene), [&] {
    cagekit_render_scene_t& s = checked(scene, "scene");
    const cagekit_cage_t& c = checked(cage, "cage");
    const size_t index = s.scene.add_cage(c.cage, style_from_c(options), s.context->monitor());
    if (item_out != nullptr) *item_out = uint32_t(index);
  });
}

CAGEKIT_API cagekit_status cagekit_render_scene_set_scalars(cagekit_render_scene scene, uint32_t item,
                                                            uint32_t value_count, const double* values,
                                                            const cagekit_render_scalar_options* options) {
  return guarded(context_of(scene), [&] {
    cagekit_render_scene_t& s = checked(scene, "scene");
    if (value_count > 0) require_not_null(values, "values");
    const cagekit::ScalarStyle style = scalar_style_from_c(options);
    s.scene.set_scalars(item, std::vector<double>(values, values + value_count), style);
  });
}

CAGEKIT_API cagekit_status cagekit_render_scene_set_distance_to_scan(cagekit_render_scene scene, uint32_t item,
                                                                     cagekit_mesh scan,
                                                                     const cagekit_render_scalar_options* options) {
  return guarded(context_of(scene), [&] {
    cagekit_render_scene_t& s = checked(scene, "scene");
    const cagekit_mesh_t& m = checked(scan, "scan");
    const cagekit::ScalarStyle style = scalar_style_from_c(options);
    s.scene.item(item);  // range check first
    s.scene.set_distance_to_scan(item, m.mesh, style, s.context->monitor());
  });
}

CAGEKIT_API cagekit_status cagekit_render_scene_get_scalars(cagekit_render_scene scene, uint32_t item,
                                                            uint32_t value_capacity, uint32_t* value_count_out,
                                                            double* values) {
  return guarded(context_of(scene), [&] {
    const cagekit_render_scene_t& s = checked(scene, "scene");
    const cagekit::RenderItem& it = s.scene.item(item);
    if (two_call_check<uint32_t>("value", uint32_t(it.scalars.size()), value_capacity, value_count_out,
                                 {{"values", values}}))
      for (size_t i = 0; i < it.scalars.size(); ++i) values[i] = it.scalars[i];
  });
}

CAGEKIT_API cagekit_status cagekit_render_scene_get_item_geometry(cagekit_render_scene scene, uint32_t item,
                                                                  uint32_t vertex_capacity, uint32_t* vertex_count_out,
                                                                  double* positions, uint32_t triangle_capacity,
                                                                  uint32_t* triangle_count_out, uint32_t* triangles) {
  return guarded(context_of(scene), [&] {
    const cagekit_render_scene_t& s = checked(scene, "scene");
    const cagekit::RenderItem& it = s.scene.item(item);
    const uint32_t vertices = uint32_t(it.vertex_count()), tris = uint32_t(it.triangles.size() / 3);
    write_count<uint32_t>("vertex", vertices, vertex_count_out);
    write_count<uint32_t>("triangle", tris, triangle_count_out);
    if (two_call_check<uint32_t>("vertex", vertices, vertex_capacity, vertex_count_out, {{"positions", positions}}))
      for (size_t i = 0; i < it.positions.size(); ++i) positions[i] = double(it.positions[i]);
    if (two_call_check<uint32_t>("triangle", tris, triangle_capacity, triangle_count_out,
                                 {{"triangles", triangles}}))
      std::memcpy(triangles, it.triangles.data(), it.triangles.size() * sizeof(uint32_t));
  });
}

CAGEKIT_API cagekit_status cagekit_render_scene_get_item_count(cagekit_render_scene scene, uint32_t* count) {
  return guarded(context_of(scene), [&] {
    const cagekit_render_scene_t& s = checked(scene, "scene");
    require_not_null(count, "count");
    *count = uint32_t(s.scene.items().size());
  });
}

CAGEKIT_API cagekit_status cagekit_render_scene_get_item_info(cagekit_render_scene scene, uint32_t item,
                                                              cagekit_render_item_info* info) {
  return guarded(context_of(scene), [&] {
    const cagekit_render_scene_t& s = checked(scene, "scene");
    require_not_null(info, "info");
    const cagekit::RenderItem& it = s.scene.item(item);
    cagekit_render_item_info out{};
    out.struct_size = sizeof(out);
    out.kind = cagekit_render_item_kind(int(it.kind));
    out.column = uint32_t(s.scene.item_columns(nullptr)[item]);
    out.vertex_count = uint32_t(it.vertex_count());
    out.triangle_count = uint32_t(it.triangles.size() / 3);
    out.tessellation_level = uint32_t(it.level);
    out.has_scalars = it.scalars.empty() ? CAGEKIT_FALSE : CAGEKIT_TRUE;
    out.scalar_min = it.scalars.empty() ? 0.0 : it.shown_min;
    out.scalar_max = it.scalars.empty() ? 0.0 : it.shown_max;
    for (int k = 0; k < 3; ++k) {
      out.bounds_min[k] = it.lo[k] <= it.hi[k] ? it.lo[k] : 0.0;
      out.bounds_max[k] = it.lo[k] <= it.hi[k] ? it.hi[k] : 0.0;
    }
    write_versioned(info, out, "cagekit_render_item_info");
  });
}

CAGEKIT_API cagekit_status cagekit_render_scene_draw(cagekit_render_scene scene, uint32_t pixel_capacity,
                                                     uint32_t* pixel_count_out, uint8_t* rgba) {
  return guarded(context_of(scene), [&] {
    const cagekit_render_scene_t& s = checked(scene, "scene");
    if (two_call_check<uint32_t>("pixel", pixel_count(s.scene), pixel_capacity, pixel_count_out, {{"rgba", rgba}}))
      copy_pixels(draw_headless(s.scene), rgba);
  });
}

CAGEKIT_API cagekit_status cagekit_render_scene_write_png(cagekit_render_scene scene, const char* path) {
  return guarded(context_of(scene), [&] {
    const cagekit_render_scene_t& s = checked(scene, "scene");
    require_not_null(path, "path");
    const std::vector<uint8_t> rgba = draw_headless(s.scene);
    cagekit::write_png_file(path, rgba.data(), s.scene.settings().width, s.scene.settings().height);
  });
}

CAGEKIT_API cagekit_status cagekit_render_scene_encode_png(cagekit_render_scene scene, cagekit_blob* out) {
  return create_from(scene, "scene", out, [&](cagekit_render_scene_t& s) {
    const std::vector<uint8_t> rgba = draw_headless(s.scene);
    return std::make_unique<cagekit_blob_t>(
        cagekit::encode_png(rgba.data(), s.scene.settings().width, s.scene.settings().height));
  });
}

CAGEKIT_API cagekit_status cagekit_render_encode_png(cagekit_context context, const uint8_t* rgba, uint32_t width,
                                                     uint32_t height, const char* path, cagekit_blob* out) {
  return guarded(context, [&] {
    checked(context, "context");
    require_not_null(rgba, "rgba");
    if (path == nullptr) {
      require_not_null(out, "out");
      *out = nullptr;
    }
    if (width < 1 || height < 1 || width > uint32_t(cagekit::kMaxImageSide) ||
        height > uint32_t(cagekit::kMaxImageSide))
      fail(Status::limit_exceeded, "the image is " + std::to_string(width) + " x " + std::to_string(height) +
                                       "; each side must be 1 .. " + std::to_string(cagekit::kMaxImageSide));
    if (path != nullptr) {
      cagekit::write_png_file(path, rgba, int(width), int(height));
    } else {
      *out = new cagekit_blob_t(cagekit::encode_png(rgba, int(width), int(height)));
    }
  });
}

CAGEKIT_API cagekit_status cagekit_gl_render_scene_draw(cagekit_render_scene scene,
                                                        cagekit_gl_get_proc_address_fn get_proc_address,
                                                        void* user_data, uint32_t pixel_capacity,
                                                        uint32_t* pixel_count_out, uint8_t* rgba) {
  return guarded(context_of(scene), [&] {
    const cagekit_render_scene_t& s = checked(scene, "scene");
    require_not_null(reinterpret_cast<const void*>(get_proc_address), "get_proc_address");
    if (two_call_check<uint32_t>("pixel", pixel_count(s.scene), pixel_capacity, pixel_count_out, {{"rgba", rgba}})) {
      std::vector<uint8_t> image;
      cagekit::draw_scene(s.scene, reinterpret_cast<cagekit::GlGetProcAddress>(get_proc_address), user_data, image);
      copy_pixels(image, rgba);
    }
  });
}

}  // extern "C"

#else  // !CAGEKIT_WITH_RENDER

struct cagekit_render_scene_t {};

namespace {
cagekit_status unsupported(cagekit_context context) {
  return record_error(context, CAGEKIT_ERROR_UNSUPPORTED_FEATURE,
                      "libcagekit was built without the render module (CMake option CAGEKIT_WITH_RENDER=OFF)");
}
}  // namespace

extern "C" {

CAGEKIT_API cagekit_status cagekit_render_scene_create(cagekit_context context, cagekit_render_scene* out) {
  if (out != nullptr) *out = nullptr;
  return unsupported(is_live(context) ? context : nullptr);
}
CAGEKIT_API void cagekit_render_scene_retain(cagekit_render_scene) {}
CAGEKIT_API void cagekit_render_scene_release(cagekit_render_scene) {}
CAGEKIT_API cagekit_status cagekit_render_scene_set_options(cagekit_render_scene, const cagekit_render_options*) {
  return unsupported(nullptr);
}
CAGEKIT_API cagekit_status cagekit_render_scene_get_options(cagekit_render_scene, cagekit_render_options*) {
  return unsupported(nullptr);
}
CAGEKIT_API cagekit_status cagekit_render_scene_set_views(cagekit_render_scene, uint32_t, const cagekit_render_camera*) {
  return unsupported(nullptr);
}
CAGEKIT_API cagekit_status cagekit_render_scene_add_mesh(cagekit_render_scene, cagekit_mesh, cagekit_render_item_kind,
                                                         const cagekit_render_item_options*, uint32_t*) {
  return unsupported(nullptr);
}
CAGEKIT_API cagekit_status cagekit_render_scene_add_cage(cagekit_render_scene, cagekit_cage,
                                                         const cagekit_render_item_options*, uint32_t*) {
  return unsupported(nullptr);
}
CAGEKIT_API cagekit_status cagekit_render_scene_set_scalars(cagekit_render_scene, uint32_t, uint32_t, const double*,
                                                            const cagekit_render_scalar_options*) {
  return unsupported(nullptr);
}
CAGEKIT_API cagekit_status cagekit_render_scene_set_distance_to_scan(cagekit_render_scene, uint32_t, cagekit_mesh,
                                                                     const cagekit_render_scalar_options*) {
  return unsupported(nullptr);
}
CAGEKIT_API cagekit_status cagekit_render_scene_get_scalars(cagekit_render_scene, uint32_t, uint32_t, uint32_t*,
                                                            double*) {
  return unsupported(nullptr);
}
CAGEKIT_API cagekit_status cagekit_render_scene_get_item_geometry(cagekit_render_scene, uint32_t, uint32_t, uint32_t*,
                                                                  double*, uint32_t, uint32_t*, uint32_t*) {
  return unsupported(nullptr);
}
CAGEKIT_API cagekit_status cagekit_render_scene_get_item_count(cagekit_render_scene, uint32_t*) {
  return unsupported(nullptr);
}
CAGEKIT_API cagekit_status cagekit_render_scene_get_item_info(cagekit_render_scene, uint32_t, cagekit_render_item_info*) {
  return unsupported(nullptr);
}
CAGEKIT_API cagekit_status cagekit_render_scene_draw(cagekit_render_scene, uint32_t, uint32_t*, uint8_t*) {
  return unsupported(nullptr);
}
CAGEKIT_API cagekit_status cagekit_render_scene_write_png(cagekit_render_scene, const char*) {
  return unsupported(nullptr);
}
CAGEKIT_API cagekit_status cagekit_render_scene_encode_png(cagekit_render_scene, cagekit_blob* out) {
  if (out != nullptr) *out = nullptr;
  return unsupported(nullptr);
}
CAGEKIT_API cagekit_status cagekit_render_encode_png(cagekit_context context, const uint8_t*, uint32_t, uint32_t,
                                                     const char*, cagekit_blob* out) {
  if (out != nullptr) *out = nullptr;
  return unsupported(is_live(context) ? context : nullptr);
}
CAGEKIT_API cagekit_status cagekit_gl_render_scene_draw(cagekit_render_scene, cagekit_gl_get_proc_address_fn, void*,
                                                        uint32_t, uint32_t*, uint8_t*) {
  return unsupported(nullptr);
}

}  // extern "C"

#endif  // CAGEKIT_WITH_RENDER
