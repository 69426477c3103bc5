// SPDX-License-Identifier: GPL-3.0-or-later
#include "gpu_bench.h"

#include <chrono>
#include <cstdio>

#ifdef CAGEKIT_CLI_HAS_EGL
#include <cagekit/cagekit_gl.hpp>
#include <EGL/egl.h>
#include <EGL/eglext.h>
#endif

namespace cli {

#ifndef CAGEKIT_CLI_HAS_EGL

GpuBench bench_gpu_deformer(const cagekit::Context&, const cagekit::Binding&, const cagekit::Mesh&, std::vector<double>,
                            int, double) {
  GpuBench result;
  result.why = "this cagekit was built without EGL (libegl-dev), so it cannot make a GL context";
  return result;
}

#else

namespace {

cagekit_gl_proc get_proc_address(const char* name, void*) { return eglGetProcAddress(name); }

std::string egl_error(const char* what) {
  char buf[96];
  std::snprintf(buf, sizeof(buf), "%s failed (EGL error 0x%04x)", what, unsigned(eglGetError()));
  return buf;
}

}  // namespace

GpuBench bench_gpu_deformer(const cagekit::Context& context, const cagekit::Binding& binding,
                            const cagekit::Mesh& scan, std::vector<double> control, int frames, double step) {
  GpuBench result;
  EGLDisplay display = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (display == EGL_NO_DISPLAY || !eglInitialize(display, nullptr, nullptr)) {
    result.why = "no EGL display on Mesa's surfaceless platform (" + egl_error("eglInitialize") + ")";
    return result;
  }
  // Desktop GL 4.3 core first, GLES 3.1 else.
  EGLContext gl = EGL_NO_CONTEXT;
  const EGLint desktop[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
                            EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  const EGLint es[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 1, EGL_NONE};
  if (eglBindAPI(EGL_OPENGL_API)) gl = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, desktop);
  if (gl == EGL_NO_CONTEXT && eglBindAPI(EGL_OPENGL_ES_API))
    gl = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, es);
  if (gl == EGL_NO_CONTEXT || !eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, gl)) {
    result.why = "no GL 4.3 / GLES 3.1 context (" + egl_error("eglCreateContext / eglMakeCurrent") + ")";
    if (gl != EGL_NO_CONTEXT) eglDestroyContext(display, gl);
    eglTerminate(display);
    return result;
  }
  using Finish = void (*)();
  const Finish finish = reinterpret_cast<Finish>(eglGetProcAddress("glFinish"));
  if (finish == nullptr) {
    result.why = "no glFinish";
  } else {
    try {
      // Made and released while the GL context is current (this block).
      cagekit::GlDeformer deformer = cagekit::GlDeformer::create(binding, &scan, get_proc_address, nullptr);
      const cagekit_gl_deformer_info info = deformer.info();
      result.renderer = info.renderer ? info.renderer : "";
      result.version = info.version ? info.version : "";
      deformer.deform(control, CAGEKIT_NORMALS_APPROXIMATE);  // warm-up
      finish();
      const auto t0 = std::chrono::steady_clock::now();
      for (int f = 0; f < frames; ++f) {
        for (double& c : control) c += (f % 2 ? -step : step);
        deformer.deform(control, CAGEKIT_NORMALS_APPROXIMATE);
        finish();
      }
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      result.ran = true, result.fps = frames / seconds;
    } catch (const cagekit::Error& error) {
      result.why = std::string("GL deformer: ") + cagekit::status_string(error.status()) + ": " +
                   context.last_error_message();
    }
  }
  eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display, gl);
  eglTerminate(display);
  eglReleaseThread();
  return result;
}

#endif

}  // namespace cli
