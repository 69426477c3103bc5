// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The render module's own headless GL context: libEGL is loaded at run time (dlopen), so
// libcagekit has no NEEDED entry on libEGL and loads on a host without it; only a headless
// render then fails, with a message naming what is missing.
//
// Display: with DisplayChoice::automatic, the first EGL device (EGL_EXT_device_enumeration +
// EGL_EXT_platform_device) that is not Mesa's software device, else Mesa's surfaceless platform
// (EGL_MESA_platform_surfaceless: llvmpipe without a GPU). Context: desktop GL 3.3 core, else
// OpenGL ES 3.0; no surface (EGL_KHR_surfaceless_context), the renderer draws into its own FBO.
// The EGL context that was current on the thread (and the bound API) is restored on destruction.
// The display is initialised once per process and never terminated (another user of the same
// EGLDisplay, such as the host, would lose its contexts).
#include <memory>
#include <string>

#include "render/render_gl.h"
#include "render/scene.h"

CAGEKIT_NAMESPACE_BEGIN

class HeadlessGl {
 public:
  // library: the libEGL to load (empty: $CAGEKIT_EGL_LIBRARY, else "libEGL.so.1").
  // Errors: Error(unsupported_feature) naming the missing library, platform, extension or
  // context version.
  HeadlessGl(const std::string& library, DisplayChoice display);
  ~HeadlessGl();
  HeadlessGl(const HeadlessGl&) = delete;
  HeadlessGl& operator=(const HeadlessGl&) = delete;

  GlGetProcAddress get_proc_address() const;
  void* user_data() const;
  // "EGL device <name>" or "EGL surfaceless", and the context kind.
  const std::string& description() const { return description_; }

 private:
  struct State;
  std::unique_ptr<State> state_;
  std::string description_;
};

CAGEKIT_NAMESPACE_END
