// SPDX-License-Identifier: GPL-3.0-or-later
//
// CageKit — the C++17 layer of the opt-in GL binding <cagekit/cagekit_gl.h>: cagekit::GlDeformer,
// an RAII owner of a cagekit_gl_deformer, with the conventions of <cagekit/cagekit.hpp>. Include
// it only where the host draws with GL. The GL rules of cagekit_gl.h apply to every member,
// the destructor included: call them on the thread where the host's GL context is current.
// The experimental reference-mode calls are wrapped when the host defines
// CAGEKIT_ENABLE_EXPERIMENTAL before including this header (as for the C header).
#ifndef CAGEKIT_CAGEKIT_GL_HPP
#define CAGEKIT_CAGEKIT_GL_HPP

#include <cagekit/cagekit.hpp>
#include <cagekit/cagekit_gl.h>

namespace cagekit {

// CAGEKIT_GL_DEFORMER_OPTIONS_INIT.
template <>
inline cagekit_gl_deformer_options defaults<cagekit_gl_deformer_options>() noexcept {
  cagekit_gl_deformer_options value = CAGEKIT_GL_DEFORMER_OPTIONS_INIT;
  return value;
}

namespace detail {

// std::function behind cagekit_gl_get_proc_address_fn (called during create only): an
// exception cancels the create (a null entry point) and is rethrown by GlDeformer::create.
using GlProcLoader = std::function<cagekit_gl_proc(const char* name)>;

inline cagekit_gl_proc gl_proc_trampoline(const char* name, void* user_data) noexcept {
  try {
    return (*static_cast<const GlProcLoader*>(user_data))(name);
  } catch (...) {
    pending_exception() = std::current_exception();
    return nullptr;
  }
}

}  // namespace detail

class GlDeformer
    : public detail::Handle<GlDeformer, cagekit_gl_deformer, cagekit_gl_deformer_retain, cagekit_gl_deformer_release> {
  CAGEKIT_HPP_HANDLE(GlDeformer, cagekit_gl_deformer, cagekit_gl_deformer_retain, cagekit_gl_deformer_release)

  // A GPU deformer of `binding` in the current GL context. `scan` (may be null: no index buffer)
  // supplies the triangles; get_proc_address is the host's loader (eglGetProcAddress, ...),
  // called during create only.
  static GlDeformer create(const Binding& binding, const Mesh* scan, cagekit_gl_get_proc_address_fn get_proc_address,
                           void* user_data,
                           const cagekit_gl_deformer_options& options = defaults<cagekit_gl_deformer_options>()) {
    cagekit_gl_deformer out = nullptr;
    const detail::ContextRef& context = detail::Access::context_of(binding);
    detail::check(cagekit_gl_deformer_create(binding.get(), scan != nullptr ? scan->get() : nullptr, get_proc_address,
                                             user_data, &options, &out),
                  context, "cagekit_gl_deformer_create");
    return detail::Access::wrap<GlDeformer>(out, context);
  }
  // The same with a C++ loader (it may throw: the create fails and rethrows its exception).
  static GlDeformer create(const Binding& binding, const Mesh* scan, detail::GlProcLoader get_proc_address,
                           const cagekit_gl_deformer_options& options = defaults<cagekit_gl_deformer_options>()) {
    return create(binding, scan, detail::gl_proc_trampoline, &get_proc_address, options);
  }

  // Recomputes every vertex from `control` (xyz per cage vertex) into the GL buffers.
  void deform(View<const double> control, cagekit_normal_mode mode = CAGEKIT_NORMALS_APPROXIMATE) {
    const char* fn = "cagekit_gl_deformer_deform";
    check(cagekit_gl_deformer_deform(handle_, control.data(), detail::triples(control.size(), "control", fn), mode), fn);
  }
  cagekit_gl_deformer_buffers buffers() const {
    cagekit_gl_deformer_buffers buffers = defaults<cagekit_gl_deformer_buffers>();
    check(cagekit_gl_deformer_get_buffers(handle_, &buffers), "cagekit_gl_deformer_get_buffers");
    return buffers;
  }
  cagekit_gl_deformer_info info() const {
    cagekit_gl_deformer_info info = defaults<cagekit_gl_deformer_info>();
    check(cagekit_gl_deformer_get_info(handle_, &info), "cagekit_gl_deformer_get_info");
    return info;
  }
  // The last deform's result on the CPU (waits for the GPU): xyz per vertex.
  Deformed<double> read_back() {
    const char* fn = "cagekit_gl_deformer_read_back";
    Deformed<double> out;
    uint32_t count = 0;
    check(cagekit_gl_deformer_read_back(handle_, 0, &count, nullptr, nullptr), fn);
    out.positions.resize(3 * static_cast<size_t>(count));
    out.normals.resize(3 * static_cast<size_t>(count));
    if (count != 0)
      check(cagekit_gl_deformer_read_back(handle_, count, &count, out.positions.data(), out.normals.data()), fn);
    out.vertex_count = count;
    return out;
  }
  // Into caller memory (either view may be empty); returns the vertex count.
  uint32_t read_back(View<double> positions, View<double> normals) {
    const char* fn = "cagekit_gl_deformer_read_back";
    uint32_t count = 0;
    check(cagekit_gl_deformer_read_back(handle_, detail::shared_triples(positions.size(), normals.size(), fn), &count,
                                        positions.empty() ? nullptr : positions.data(),
                                        normals.empty() ? nullptr : normals.data()),
          fn);
    return count;
  }

#if defined(CAGEKIT_ENABLE_EXPERIMENTAL)
  // Experimental (outside the stable contract, as in cagekit_gl.h): the thesis's vertex-attribute path.
  void set_reference_set(View<const uint32_t> edited, View<const double> control) {
    const char* fn = "cagekit_gl_deformer_set_reference_set";
    check(cagekit_gl_deformer_set_reference_set(handle_, edited.data(), detail::count32(edited.size(), "edited", fn),
                                                control.data(), detail::triples(control.size(), "control", fn)),
          fn);
  }
  void deform_reference(View<const double> control) {
    const char* fn = "cagekit_gl_deformer_deform_reference";
    check(cagekit_gl_deformer_deform_reference(handle_, control.data(), detail::triples(control.size(), "control", fn)),
          fn);
  }
  // frame: the 12 coordinates of the four frame points.
  void set_reference_affine(View<const uint32_t> edited, View<const double> frame, View<const double> control) {
    const char* fn = "cagekit_gl_deformer_set_reference_affine";
    check_frame(frame, fn);
    check(cagekit_gl_deformer_set_reference_affine(handle_, edited.data(),
                                                   detail::count32(edited.size(), "edited", fn), frame.data(),
                                                   control.data(), detail::triples(control.size(), "control", fn)),
          fn);
  }
  void deform_reference_affine(View<const double> frame) {
    const char* fn = "cagekit_gl_deformer_deform_reference_affine";
    check_frame(frame, fn);
    check(cagekit_gl_deformer_deform_reference_affine(handle_, frame.data()), fn);
  }

 private:
  static void check_frame(View<const double> frame, const char* fn) {
    if (frame.size() != 12)
      throw Error(CAGEKIT_ERROR_INVALID_ARGUMENT, fn,
                  "frame holds " + std::to_string(frame.size()) + " values, not the 12 of four points");
  }
#endif  // CAGEKIT_ENABLE_EXPERIMENTAL
};

// Draws `scene` in the host's current GL context (cagekit_gl_render_scene_draw): the image is read
// back; the host's GL state is left as it was.
inline Image draw_in_current_context(const RenderScene& scene, cagekit_gl_get_proc_address_fn get_proc_address,
                                     void* user_data) {
  const char* fn = "cagekit_gl_render_scene_draw";
  const detail::ContextRef& context = detail::Access::context_of(scene);
  const cagekit_render_options options = scene.options();
  Image image;
  image.width = options.width;
  image.height = options.height;
  uint32_t count = 0;
  detail::check(cagekit_gl_render_scene_draw(scene.get(), get_proc_address, user_data, 0, &count, nullptr), context, fn);
  image.rgba.resize(4 * size_t(count));
  detail::check(cagekit_gl_render_scene_draw(scene.get(), get_proc_address, user_data, count, &count, image.rgba.data()),
                context, fn);
  return image;
}
// The same with a C++ loader (it may throw: the draw fails and rethrows its exception).
inline Image draw_in_current_context(const RenderScene& scene, detail::GlProcLoader get_proc_address) {
  return draw_in_current_context(scene, detail::gl_proc_trampoline, &get_proc_address);
}

}  // namespace cagekit

#endif  // CAGEKIT_CAGEKIT_GL_HPP
