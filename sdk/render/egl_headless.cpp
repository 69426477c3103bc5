// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/egl_headless.h"

#include <dlfcn.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>

// Types and enum values only: every EGL function is looked up at run time.
#define EGL_EGL_PROTOTYPES 0
#define EGL_NO_PROTOTYPES
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

struct Egl {
  PFNEGLGETPROCADDRESSPROC GetProcAddress = nullptr;
  PFNEGLGETERRORPROC GetError = nullptr;
  PFNEGLQUERYSTRINGPROC QueryString = nullptr;
  PFNEGLINITIALIZEPROC Initialize = nullptr;
  PFNEGLBINDAPIPROC BindAPI = nullptr;
  PFNEGLQUERYAPIPROC QueryAPI = nullptr;
  PFNEGLCHOOSECONFIGPROC ChooseConfig = nullptr;
  PFNEGLCREATECONTEXTPROC CreateContext = nullptr;
  PFNEGLDESTROYCONTEXTPROC DestroyContext = nullptr;
  PFNEGLMAKECURRENTPROC MakeCurrent = nullptr;
  PFNEGLGETCURRENTCONTEXTPROC GetCurrentContext = nullptr;
  PFNEGLGETCURRENTDISPLAYPROC GetCurrentDisplay = nullptr;
  PFNEGLGETCURRENTSURFACEPROC GetCurrentSurface = nullptr;
  PFNEGLGETPLATFORMDISPLAYEXTPROC GetPlatformDisplayEXT = nullptr;
  PFNEGLQUERYDEVICESEXTPROC QueryDevicesEXT = nullptr;
  PFNEGLQUERYDEVICESTRINGEXTPROC QueryDeviceStringEXT = nullptr;
  // The display chosen for each DisplayChoice, made once per process.
  EGLDisplay displays[3] = {EGL_NO_DISPLAY, EGL_NO_DISPLAY, EGL_NO_DISPLAY};
  std::string display_names[3];
};

std::string hex(EGLint e) {
  char buf[16];
  std::snprintf(buf, sizeof(buf), "0x%04x", unsigned(e));
  return buf;
}

bool has_extension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

std::mutex& egl_mutex() {
  static std::mutex m;
  return m;
}

// One loaded libEGL per path, never unloaded (GL drivers do not survive dlclose well).
Egl& load_egl(const std::string& path) {
  static std::map<std::string, Egl> loaded;
  auto it = loaded.find(path);
  if (it != loaded.end()) return it->second;
  void* lib = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (lib == nullptr) {
    const char* why = dlerror();
    fail(Status::unsupported_feature, "cannot load the EGL library '" + path + "' for headless rendering (" +
                                          (why != nullptr ? why : "dlopen failed") +
                                          "); install libegl1 (and Mesa's libegl-mesa0), or draw in the host's GL "
                                          "context with cagekit_gl_render_scene_draw");
  }
  Egl egl;
  egl.GetProcAddress = reinterpret_cast<PFNEGLGETPROCADDRESSPROC>(dlsym(lib, "eglGetProcAddress"));
  if (egl.GetProcAddress == nullptr)
    fail(Status::unsupported_feature, "'" + path + "' has no eglGetProcAddress: not an EGL library");
  std::string missing;
  const auto get = [&](auto& fn, const char* name) {
    using F = std::remove_reference_t<decltype(fn)>;
    fn = reinterpret_cast<F>(dlsym(lib, name));
    if (fn == nullptr) fn = reinterpret_cast<F>(egl.GetProcAddress(name));
    if (fn == nullptr) missing += std::string(missing.empty() ? "" : ", ") + name;
  };
  get(egl.GetError, "eglGetError");
  get(egl.QueryString, "eglQueryString");
  get(egl.Initialize, "eglInitialize");
  get(egl.BindAPI, "eglBindAPI");
  get(egl.QueryAPI, "eglQueryAPI");
  get(egl.ChooseConfig, "eglChooseConfig");
  get(egl.CreateContext, "eglCreateContext");
  get(egl.DestroyContext, "eglDestroyContext");
  get(egl.MakeCurrent, "eglMakeCurrent");
  get(egl.GetCurrentContext, "eglGetCurrentContext");
  get(egl.GetCurrentDisplay, "eglGetCurrentDisplay");
  get(egl.GetCurrentSurface, "eglGetCurrentSurface");
  if (!missing.empty()) fail(Status::unsupported_feature, "'" + path + "' lacks the EGL functions " + missing);
  // Extensions: looked up, may be absent.
  egl.GetPlatformDisplayEXT =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(egl.GetProcAddress("eglGetPlatformDisplayEXT"));
  egl.QueryDevicesEXT = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(egl.GetProcAddress("eglQueryDevicesEXT"));
  egl.QueryDeviceStringEXT =
      reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(egl.GetProcAddress("eglQueryDeviceStringEXT"));
  return loaded.emplace(path, egl).first->second;
}

// The first EGL device of the wanted kind (real: not Mesa's software device), or EGL_NO_DISPLAY.
EGLDisplay device_display(Egl& egl, bool real_only, std::string& name) {
  const char* client = egl.QueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (egl.GetPlatformDisplayEXT == nullptr || egl.QueryDevicesEXT == nullptr ||
      !has_extension(client, "EGL_EXT_platform_device"))
    return EGL_NO_DISPLAY;
  EGLDeviceEXT devices[16];
  EGLint count = 0;
  if (!egl.QueryDevicesEXT(16, devices, &count)) return EGL_NO_DISPLAY;
  for (EGLint i = 0; i < count; ++i) {
    const char* ext =
        egl.QueryDeviceStringEXT != nullptr ? egl.QueryDeviceStringEXT(devices[i], EGL_EXTENSIONS) : nullptr;
    if (real_only && has_extension(ext, "EGL_MESA_device_software")) continue;
    EGLDisplay d = egl.GetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
    if (d == EGL_NO_DISPLAY || !egl.Initialize(d, nullptr, nullptr)) continue;
    const char* drm = nullptr;
#ifdef EGL_DRM_DEVICE_FILE_EXT
    if (egl.QueryDeviceStringEXT != nullptr && has_extension(ext, "EGL_EXT_device_drm"))
      drm = egl.QueryDeviceStringEXT(devices[i], EGL_DRM_DEVICE_FILE_EXT);
#endif
    name = "EGL device " + std::to_string(i) + (drm != nullptr ? std::string(" (") + drm + ")" : std::string());
    return d;
  }
  return EGL_NO_DISPLAY;
}

EGLDisplay choose_display(Egl& egl, DisplayChoice choice, std::string& name) {
  const int slot = int(choice);
  if (egl.displays[slot] != EGL_NO_DISPLAY) {
    name = egl.display_names[slot];
    return egl.displays[slot];
  }
  EGLDisplay d = EGL_NO_DISPLAY;
  if (choice != DisplayChoice::surfaceless) d = device_display(egl, choice == DisplayChoice::automatic, name);
  if (d == EGL_NO_DISPLAY && choice == DisplayChoice::device)
    fail(Status::unsupported_feature, "no EGL device could be initialised (EGL_EXT_device_enumeration / "
                                      "EGL_EXT_platform_device)");
  if (d == EGL_NO_DISPLAY) {
    const char* client = egl.QueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (egl.GetPlatformDisplayEXT == nullptr || !has_extension(client, "EGL_MESA_platform_surfaceless"))
      fail(Status::unsupported_feature,
           "no EGL display for headless rendering: no GPU device (EGL_EXT_platform_device) and no Mesa "
           "surfaceless platform (EGL_MESA_platform_surfaceless)");
    d = egl.GetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (d == EGL_NO_DISPLAY || !egl.Initialize(d, nullptr, nullptr))
      fail(Status::unsupported_feature, "the EGL surfaceless display cannot be initialised (EGL error " +
                                            hex(egl.GetError()) + ")");
    name = "EGL surfaceless";
  }
  egl.displays[slot] = d;
  egl.display_names[slot] = name;
  return d;
}

EGLContext create_context(Egl& egl, EGLDisplay d, bool es, std::string& what) {
  if (!egl.BindAPI(es ? EGL_OPENGL_ES_API : EGL_OPENGL_API)) return EGL_NO_CONTEXT;
  const char* ext = egl.QueryString(d, EGL_EXTENSIONS);
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!has_extension(ext, "EGL_KHR_no_config_context")) {
    const EGLint wanted[] = {EGL_RENDERABLE_TYPE, es ? EGL_OPENGL_ES3_BIT : EGL_OPENGL_BIT, EGL_NONE};
    EGLint count = 0;
    if (!egl.ChooseConfig(d, wanted, &config, 1, &count) || count < 1) return EGL_NO_CONTEXT;
  }
  const EGLint gl_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                  EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  const EGLint es_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 0, EGL_NONE};
  EGLContext c = egl.CreateContext(d, config, EGL_NO_CONTEXT, es ? es_attributes : gl_attributes);
  what = es ? "OpenGL ES 3.0" : "OpenGL 3.3 core";
  return c;
}

GlProc egl_loader(const char* name, void* user) {
  return reinterpret_cast<GlProc>(static_cast<Egl*>(user)->GetProcAddress(name));
}

}  // namespace

struct HeadlessGl::State {
  Egl* egl = nullptr;
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  // What was current before (restored on destruction).
  EGLenum previous_api = EGL_OPENGL_ES_API;
  EGLDisplay previous_display = EGL_NO_DISPLAY;
  EGLSurface previous_draw = EGL_NO_SURFACE, previous_read = EGL_NO_SURFACE;
  EGLContext previous_context = EGL_NO_CONTEXT;
};

HeadlessGl::HeadlessGl(const std::string& library, DisplayChoice choice) : state_(new State) {
  std::string path = library;
  if (path.empty()) {
    const char* env = std::getenv("CAGEKIT_EGL_LIBRARY");
    path = env != nullptr && env[0] != '\0' ? env : "libEGL.so.1";
  }
  std::string display_name, context_kind;
  {
    std::lock_guard<std::mutex> lock(egl_mutex());
    state_->egl = &load_egl(path);
    state_->display = choose_display(*state_->egl, choice, display_name);
  }
  Egl& egl = *state_->egl;
  state_->previous_api = egl.QueryAPI();
  state_->previous_context = egl.GetCurrentContext();
  state_->previous_display = egl.GetCurrentDisplay();
  state_->previous_draw = egl.GetCurrentSurface(EGL_DRAW);
  state_->previous_read = egl.GetCurrentSurface(EGL_READ);
  const char* ext = egl.QueryString(state_->display, EGL_EXTENSIONS);
  if (!has_extension(ext, "EGL_KHR_surfaceless_context"))
    fail(Status::unsupported_feature, display_name + " lacks EGL_KHR_surfaceless_context");
  state_->context = create_context(egl, state_->display, false, context_kind);
  if (state_->context == EGL_NO_CONTEXT) state_->context = create_context(egl, state_->display, true, context_kind);
  if (state_->context == EGL_NO_CONTEXT) {
    const EGLint error = egl.GetError();
    egl.BindAPI(state_->previous_api);
    fail(Status::unsupported_feature, display_name + " makes neither an OpenGL 3.3 core nor an OpenGL ES 3.0 context (EGL error " +
                                          hex(error) + ")");
  }
  if (!egl.MakeCurrent(state_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, state_->context)) {
    const EGLint error = egl.GetError();
    egl.DestroyContext(state_->display, state_->context);
    egl.BindAPI(state_->previous_api);
    fail(Status::unsupported_feature, "eglMakeCurrent of the headless context failed (EGL error " + hex(error) + ")");
  }
  description_ = display_name + ", " + context_kind;
}

HeadlessGl::~HeadlessGl() {
  Egl& egl = *state_->egl;
  if (state_->previous_context != EGL_NO_CONTEXT) {
    egl.BindAPI(state_->previous_api);
    egl.MakeCurrent(state_->previous_display, state_->previous_draw, state_->previous_read, state_->previous_context);
  } else {
    egl.MakeCurrent(state_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    egl.BindAPI(state_->previous_api);
  }
  egl.DestroyContext(state_->display, state_->context);
}

GlGetProcAddress HeadlessGl::get_proc_address() const { return egl_loader; }
void* HeadlessGl::user_data() const { return state_->egl; }

CAGEKIT_NAMESPACE_END
