// SPDX-License-Identifier: GPL-3.0-or-later
#include "gpu/gl_functions.h"

#include <cstdio>
#include <cstring>

CAGEKIT_NAMESPACE_BEGIN

std::vector<std::string> GlFunctions::load(GlGetProcAddress get_proc_address, void* user_data) {
  std::vector<std::string> missing;
#define CAGEKIT_GL_LOAD(type, name)                                                 \
  name = reinterpret_cast<type>(get_proc_address("gl" #name, user_data));        \
  if (name == nullptr) missing.push_back("gl" #name);
  CAGEKIT_GL_FUNCTIONS(CAGEKIT_GL_LOAD)
#undef CAGEKIT_GL_LOAD
  return missing;
}

bool GlVersion::has_compute() const {
  if (!parsed) return false;
  const int v = major * 10 + minor;
  return es ? v >= 31 : v >= 43;
}

GlVersion parse_gl_version(const char* version) {
  GlVersion v;
  if (version == nullptr) return v;
  const char* p = version;
  static const char kEs[] = "OpenGL ES";
  if (std::strncmp(p, kEs, sizeof(kEs) - 1) == 0) {
    v.es = true;
    p += sizeof(kEs) - 1;
    // "OpenGL ES-CM 1.1" / "OpenGL ES-CL": profiles of GLES 1.x; skip to the number.
    while (*p != '\0' && *p != ' ') ++p;
    while (*p == ' ') ++p;
  }
  int major = 0, minor = 0;
  if (std::sscanf(p, "%d.%d", &major, &minor) == 2 && major > 0 && minor >= 0) {
    v.major = major, v.minor = minor, v.parsed = true;
  }
  return v;
}

CAGEKIT_NAMESPACE_END
