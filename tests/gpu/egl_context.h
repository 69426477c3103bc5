// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Headless GL contexts for the GPU tests: EGL on Mesa's surfaceless platform (llvmpipe when no
// GPU is there), desktop GL (core profile, a chosen version) or GLES. Every GL function the
// tests call is loaded through eglGetProcAddress, as a host would.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <string>

class EglContext {
 public:
  enum class Api { desktop_core, desktop_compatibility, es };
  // Makes a context of `api` and version major.minor current on this thread; ok() is false
  // (and error() says why) when the platform or the version is not available.
  EglContext(Api api, int major, int minor) {
    display_ = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display_ == EGL_NO_DISPLAY) {
      error_ = "no EGL surfaceless display (EGL_MESA_platform_surfaceless)";
      return;
    }
    if (!eglInitialize(display_, nullptr, nullptr)) {
      error_ = "eglInitialize failed: " + hex(eglGetError());
      display_ = EGL_NO_DISPLAY;
      return;
    }
    if (!eglBindAPI(api == Api::es ? EGL_OPENGL_ES_API : EGL_OPENGL_API)) {
      error_ = "eglBindAPI failed: " + hex(eglGetError());
      return;
    }
    EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, major, EGL_CONTEXT_MINOR_VERSION, minor,
                           EGL_NONE, EGL_NONE, EGL_NONE};
    if (api != Api::es)
      attributes[4] = EGL_CONTEXT_OPENGL_PROFILE_MASK,
      attributes[5] = api == Api::desktop_core ? EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT
                                               : EGL_CONTEXT_OPENGL_COMPATIBILITY_PROFILE_BIT;
    context_ = eglCreateContext(display_, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
    if (context_ == EGL_NO_CONTEXT) {
      error_ = "eglCreateContext(" +
               std::string(api == Api::es ? "GLES " : api == Api::desktop_core ? "GL core " : "GL compatibility ") +
               std::to_string(major) + "." +
               std::to_string(minor) + ") failed: " + hex(eglGetError());
      return;
    }
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
      error_ = "eglMakeCurrent failed: " + hex(eglGetError());
      return;
    }
    ok_ = true;
  }
  ~EglContext() {
    if (display_ == EGL_NO_DISPLAY) return;
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
    eglReleaseThread();
  }
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  bool ok() const { return ok_; }
  const std::string& error() const { return error_; }

  // The get-proc-address callback handed to the library (the cagekit_gl_get_proc_address_fn shape).
  static void (*get_proc_address(const char* name, void*))(void) { return eglGetProcAddress(name); }
  template <class F>
  static F load(const char* name) {
    return reinterpret_cast<F>(eglGetProcAddress(name));
  }

 private:
  static std::string hex(EGLint e) {
    char buf[16];
    std::snprintf(buf, sizeof(buf), "0x%04x", unsigned(e));
    return buf;
  }
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  bool ok_ = false;
  std::string error_;
};
