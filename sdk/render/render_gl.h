// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Drawing a RenderScene with GL 3.3 core or GLES 3.0 in the context current on the calling
// thread (the module's headless one, or the host's), into an FBO of the library's own; the
// pixels are read back with glReadPixels and the text (titles, view names, legends) is drawn on
// the CPU with the built-in bitmap font. Every piece of GL state touched is saved first and
// restored after (RenderStateGuard in render_gl.cpp lists it).
#include <cstdint>
#include <string>
#include <vector>

#include "render/scene.h"

CAGEKIT_NAMESPACE_BEGIN

using GlProc = void (*)();
using GlGetProcAddress = GlProc (*)(const char* name, void* user_data);

struct DrawResult {
  std::string renderer, version;  // GL_RENDERER, GL_VERSION of the context used
};

// rgba: resized to 4 * width * height bytes, top row first.
// Errors: Error(invalid_operation) when no context is current, Error(unsupported_feature) for a
// context older than GL 3.3 / GLES 3.0, an entry point the loader does not provide (named) or a
// shader that does not compile, Error(limit_exceeded) for an image above the context's
// renderbuffer / viewport limits, Error(out_of_memory) on GL_OUT_OF_MEMORY.
DrawResult draw_scene(const RenderScene& scene, GlGetProcAddress get_proc_address, void* user_data,
                      std::vector<uint8_t>& rgba);

// Overlays titles, view names and legends (CPU); used by draw_scene.
void draw_labels(const RenderScene& scene, std::vector<uint8_t>& rgba);

CAGEKIT_NAMESPACE_END
