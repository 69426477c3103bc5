/* SPDX-License-Identifier: GPL-3.0-or-later
 *
 * samples/egl_host: a headless GL host of CageKit's GPU deformer (thesis §8.6), C99, public C
 * API only. It makes an EGL context (Mesa's surfaceless platform, or with --device the first
 * EGL device, which is a real GPU where there is one), binds a scan to its cage, drags control
 * points over N frames, renders the shaded scan into an offscreen framebuffer, writes the last
 * frame to a PNG, and prints frames per second of the CPU path (cagekit_cpu_deformer + upload),
 * of the GPU path (cagekit_gl_deformer: the vertices never leave the GPU) and of the thesis's
 * vertex-attribute path (the deformer's reference mode, |Q| = the 4 dragged points).
 *
 *   cagekit_egl_host [--scan SCAN --cage CAGE] [--frames N] [--size PIXELS] [--es] [--device]
 *                    [--out IMAGE.png]
 *
 * Without --scan/--cage it generates a bumpy sphere and fits a refined cube cage to it.
 * Exit status: 0 success, 1 a CageKit or GL error (message on stderr), 2 usage,
 * 77 no EGL display or context (nothing to test on this machine).
 */
#define _POSIX_C_SOURCE 200112L
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cagekit/cagekit.h>
#define CAGEKIT_ENABLE_EXPERIMENTAL /* the third pass runs the thesis's reference mode */
#include <cagekit/cagekit_gl.h>

/* ---- GL entry points, loaded through eglGetProcAddress like the library does ---------------- */
#define GL_FUNCTIONS(X)                                                                            \
  X(PFNGLGETSTRINGPROC, GetString) X(PFNGLGETERRORPROC, GetError) X(PFNGLVIEWPORTPROC, Viewport)   \
  X(PFNGLCLEARCOLORPROC, ClearColor) X(PFNGLCLEARPROC, Clear) X(PFNGLENABLEPROC, Enable)           \
  X(PFNGLFINISHPROC, Finish) X(PFNGLREADPIXELSPROC, ReadPixels)                                    \
  X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers) X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)        \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                                               \
  X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers) X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)    \
  X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)                                             \
  X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)                                             \
  X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer)                                     \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)                                       \
  X(PFNGLCREATESHADERPROC, CreateShader) X(PFNGLSHADERSOURCEPROC, ShaderSource)                    \
  X(PFNGLCOMPILESHADERPROC, CompileShader) X(PFNGLGETSHADERIVPROC, GetShaderiv)                    \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog) X(PFNGLDELETESHADERPROC, DeleteShader)            \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram) X(PFNGLATTACHSHADERPROC, AttachShader)                  \
  X(PFNGLBINDATTRIBLOCATIONPROC, BindAttribLocation) X(PFNGLLINKPROGRAMPROC, LinkProgram)          \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv) X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                  \
  X(PFNGLUSEPROGRAMPROC, UseProgram) X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)            \
  X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv) X(PFNGLUNIFORMMATRIX3FVPROC, UniformMatrix3fv)    \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays) X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)        \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays) X(PFNGLGENBUFFERSPROC, GenBuffers)            \
  X(PFNGLBINDBUFFERPROC, BindBuffer) X(PFNGLBUFFERDATAPROC, BufferData)                            \
  X(PFNGLBUFFERSUBDATAPROC, BufferSubData) X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                                             \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray) X(PFNGLDRAWELEMENTSPROC, DrawElements)

#define GL_DECLARE(type, name) static type gl##name;
GL_FUNCTIONS(GL_DECLARE)

static int load_gl(void) {
  int ok = 1;
#define GL_LOAD(type, name)                                             \
  gl##name = (type)eglGetProcAddress("gl" #name);                       \
  if (!gl##name) { fprintf(stderr, "egl_host: no gl" #name "\n"); ok = 0; }
  GL_FUNCTIONS(GL_LOAD)
  return ok;
}

/* The callback handed to CageKit (cagekit_gl_get_proc_address_fn). */
static cagekit_gl_proc get_proc_address(const char* name, void* user_data) {
  (void)user_data;
  return (cagekit_gl_proc)eglGetProcAddress(name);
}

/* ---- small helpers ---------------------------------------------------------------------------- */
static double now_seconds(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static cagekit_context g_context;

static int check(cagekit_status status, const char* what) {
  if (CAGEKIT_FAILED(status)) {
    fprintf(stderr, "egl_host: %s: %s: %s\n", what, cagekit_status_string(status), cagekit_last_error_message(g_context));
    return 0;
  }
  return 1;
}

static void* checked_malloc(size_t bytes) {
  void* p = malloc(bytes ? bytes : 1);
  if (!p) {
    fprintf(stderr, "egl_host: out of memory\n");
    exit(1);
  }
  return p;
}

/* ---- PNG writer: stored (uncompressed) deflate blocks, CRC-32 and Adler-32 by hand ----------- */
static uint32_t crc_table[256];
static void crc_init(void) {
  uint32_t n, k;
  for (n = 0; n < 256; ++n) {
    uint32_t c = n;
    for (k = 0; k < 8; ++k) c = (c & 1) ? 0xedb88320u ^ (c >> 1) : c >> 1;
    crc_table[n] = c;
  }
}
static uint32_t crc_update(uint32_t crc, const unsigned char* data, size_t n) {
  size_t i;
  for (i = 0; i < n; ++i) crc = crc_table[(crc ^ data[i]) & 0xff] ^ (crc >> 8);
  return crc;
}
static void put32(unsigned char* p, uint32_t v) {
  p[0] = (unsigned char)(v >> 24), p[1] = (unsigned char)(v >> 16), p[2] = (unsigned char)(v >> 8), p[3] = (unsigned char)v;
}
static int write_chunk(FILE* f, const char* type, const unsigned char* data, uint32_t length) {
  unsigned char head[8], tail[4];
  uint32_t crc;
  put32(head, length);
  memcpy(head + 4, type, 4);
  crc = crc_update(0xffffffffu, head + 4, 4);
  crc = crc_update(crc, data, length) ^ 0xffffffffu;
  put32(tail, crc);
  return fwrite(head, 1, 8, f) == 8 && (length == 0 || fwrite(data, 1, length, f) == length) && fwrite(tail, 1, 4, f) == 4;
}
/* rgb: width * height * 3 bytes, top row first. */
static int write_png(const char* path, const unsigned char* rgb, uint32_t width, uint32_t height) {
  static const unsigned char signature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
  const size_t row = 1 + 3 * (size_t)width, raw_size = row * height;
  const size_t blocks = (raw_size + 65534) / 65535;
  unsigned char* raw = (unsigned char*)checked_malloc(raw_size);
  unsigned char* z = (unsigned char*)checked_malloc(2 + raw_size + 5 * blocks + 4);
  unsigned char ihdr[13];
  size_t y, at = 0, done = 0;
  uint32_t a = 1, b = 0;
  FILE* f;
  int ok;
  for (y = 0; y < height; ++y) {
    raw[y * row] = 0; /* filter: none */
    memcpy(raw + y * row + 1, rgb + y * 3 * (size_t)width, 3 * (size_t)width);
  }
  for (y = 0; y < raw_size; ++y) a = (a + raw[y]) % 65521, b = (b + a) % 65521;
  z[at++] = 0x78, z[at++] = 0x01;
  while (done < raw_size) {
    const size_t n = raw_size - done < 65535 ? raw_size - done : 65535;
    z[at++] = (unsigned char)(done + n == raw_size ? 1 : 0);
    z[at++] = (unsigned char)(n & 0xff), z[at++] = (unsigned char)(n >> 8);
    z[at++] = (unsigned char)(~n & 0xff), z[at++] = (unsigned char)((~n >> 8) & 0xff);
    memcpy(z + at, raw + done, n);
    at += n, done += n;
  }
  put32(z + at, (b << 16) | a);
  at += 4;
  put32(ihdr, width), put32(ihdr + 4, height);
  ihdr[8] = 8, ihdr[9] = 2, ihdr[10] = 0, ihdr[11] = 0, ihdr[12] = 0; /* 8-bit RGB */
  f = fopen(path, "wb");
  ok = f != NULL && fwrite(signature, 1, 8, f) == 8 && write_chunk(f, "IHDR", ihdr, 13) &&
       write_chunk(f, "IDAT", z, (uint32_t)at) && write_chunk(f, "IEND", NULL, 0);
  if (f && fclose(f) != 0) ok = 0;
  if (!ok) fprintf(stderr, "egl_host: cannot write %s\n", path);
  free(raw), free(z);
  return ok;
}

/* ---- the generated scene: a bumpy UV sphere and a refined cube cage fitted to it ------------- */
static int make_sphere(cagekit_mesh* out) {
  const uint32_t rings = 64, segments = 128, n = 2 + (rings - 1) * segments;
  const uint32_t tris = 2 * segments * (rings - 1);
  double* p = (double*)checked_malloc(3 * sizeof(double) * n);
  uint32_t* f = (uint32_t*)checked_malloc(3 * sizeof(uint32_t) * tris);
  uint32_t r, s, v = 0, t = 0;
  cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
  int ok;
  const double pi = 3.14159265358979323846;
  for (r = 0; r <= rings; ++r) {
    const double theta = pi * r / rings;
    for (s = 0; s < (r == 0 || r == rings ? 1u : segments); ++s) {
      const double phi = 2 * pi * s / segments;
      const double bump = 1.0 + 0.04 * sin(7 * theta) * sin(6 * phi) + 0.015 * sin(23 * theta) * sin(19 * phi);
      p[3 * v] = bump * sin(theta) * cos(phi), p[3 * v + 1] = bump * cos(theta), p[3 * v + 2] = bump * sin(theta) * sin(phi);
      ++v;
    }
  }
  for (s = 0; s < segments; ++s) { /* caps */
    const uint32_t s1 = (s + 1) % segments, last = 1 + (rings - 2) * segments;
    f[t++] = 0, f[t++] = 1 + s1, f[t++] = 1 + s;
    f[t++] = n - 1, f[t++] = last + s, f[t++] = last + s1;
  }
  for (r = 1; r + 1 < rings; ++r)
    for (s = 0; s < segments; ++s) {
      const uint32_t s1 = (s + 1) % segments, a = 1 + (r - 1) * segments, b = 1 + r * segments;
      f[t++] = a + s, f[t++] = a + s1, f[t++] = b + s;
      f[t++] = a + s1, f[t++] = b + s1, f[t++] = b + s;
    }
  desc.vertex_count = n;
  desc.positions = p;
  desc.face_count = tris;
  desc.face_indices = f;
  ok = check(cagekit_mesh_create(g_context, &desc, out), "sphere");
  free(p), free(f);
  return ok;
}

static int make_cage(cagekit_mesh scan, cagekit_cage* out) {
  static const uint32_t faces[24] = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};
  double p[24];
  int i, ok;
  uint32_t pass_count;
  cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
  cagekit_mesh cube = NULL;
  cagekit_cage coarse = NULL, refined = NULL;
  cagekit_subdivide_options twice = CAGEKIT_SUBDIVIDE_OPTIONS_INIT;
  cagekit_fit_options fit = CAGEKIT_FIT_OPTIONS_INIT;
  for (i = 0; i < 8; ++i)
    p[3 * i] = 1.2 * ((i & 1) - 0.5), p[3 * i + 1] = 1.2 * (((i >> 1) & 1) - 0.5), p[3 * i + 2] = 1.2 * (((i >> 2) & 1) - 0.5);
  desc.vertex_count = 8, desc.positions = p, desc.face_count = 6, desc.uniform_face_size = 4, desc.face_indices = faces;
  twice.levels = 2;
  fit.max_passes = 3;
  ok = check(cagekit_mesh_create(g_context, &desc, &cube), "cube") && check(cagekit_cage_create(cube, &coarse), "cube cage") &&
       check(cagekit_cage_subdivide(coarse, &twice, &refined), "refined cage") &&
       check(cagekit_cage_fit(refined, scan, &fit, out, NULL, 0, &pass_count, NULL), "fitting the cage");
  cagekit_cage_release(refined), cagekit_cage_release(coarse), cagekit_mesh_release(cube);
  return ok;
}

static double* positions_of(cagekit_mesh mesh, uint32_t* count) {
  double* xyz;
  if (!check(cagekit_mesh_get_positions(mesh, CAGEKIT_SCALAR_FLOAT64, 0, count, NULL), "positions")) return NULL;
  xyz = (double*)checked_malloc(3 * sizeof(double) * *count);
  if (!check(cagekit_mesh_get_positions(mesh, CAGEKIT_SCALAR_FLOAT64, *count, count, xyz), "positions")) {
    free(xyz);
    return NULL;
  }
  return xyz;
}

/* ---- EGL ---------------------------------------------------------------------------------------- */
static EGLDisplay open_display(int use_device) {
  EGLDisplay display = EGL_NO_DISPLAY;
  if (use_device) {
    PFNEGLQUERYDEVICESEXTPROC query_devices = (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
    EGLDeviceEXT devices[8];
    EGLint count = 0;
    if (query_devices && query_devices(8, devices, &count) && count > 0)
      display = eglGetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[0], NULL);
    if (display == EGL_NO_DISPLAY) fprintf(stderr, "egl_host: no EGL device; trying the surfaceless platform\n");
  }
  if (display == EGL_NO_DISPLAY) display = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
  if (display != EGL_NO_DISPLAY && !eglInitialize(display, NULL, NULL)) display = EGL_NO_DISPLAY;
  return display;
}

static GLuint compile(GLenum type, const char* version, const char* body) {
  const char* sources[2];
  GLuint shader = glCreateShader(type);
  GLint ok = 0;
  sources[0] = version, sources[1] = body;
  glShaderSource(shader, 2, sources, NULL);
  glCompileShader(shader);
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetShaderInfoLog(shader, sizeof(log), NULL, log);
    fprintf(stderr, "egl_host: shader: %s\n", log);
    glDeleteShader(shader);
    return 0;
  }
  return shader;
}

static const char* kVertex =
    "layout(location = 0) in vec3 a_position;\n"
    "layout(location = 1) in vec3 a_normal;\n"
    "uniform mat4 u_mvp;\n"
    "uniform mat3 u_rotation;\n"
    "out vec3 v_normal;\n"
    "void main() { v_normal = u_rotation * a_normal; gl_Position = u_mvp * vec4(a_position, 1.0); }\n";
static const char* kFragment =
    "in vec3 v_normal;\n"
    "out vec4 color;\n"
    "void main() {\n"
    "  vec3 n = normalize(v_normal);\n"
    "  vec3 l = normalize(vec3(0.4, 0.6, 0.7));\n"
    "  float diffuse = max(dot(n, l), 0.0);\n"
    "  float specular = pow(max(dot(reflect(-l, n), vec3(0.0, 0.0, 1.0)), 0.0), 24.0);\n"
    "  vec3 base = vec3(0.85, 0.55, 0.25);\n"
    "  color = vec4(base * (0.15 + 0.8 * diffuse) + vec3(0.35) * specular, 1.0);\n"
    "}\n";

/* ---- main --------------------------------------------------------------------------------------- */
int main(int argc, char** argv) {
  const char *scan_path = NULL, *cage_path = NULL, *out_path = "egl_host.png";
  int frames = 60, size = 512, es = 0, use_device = 0, i, status = 1;
  EGLDisplay display;
  EGLContext gl_context = EGL_NO_CONTEXT;
  cagekit_mesh scan = NULL;
  cagekit_cage cage = NULL;
  cagekit_binding binding = NULL;
  cagekit_cpu_deformer cpu = NULL;
  cagekit_gl_deformer gpu = NULL;
  for (i = 1; i < argc; ++i) {
    if (!strcmp(argv[i], "--scan") && i + 1 < argc) scan_path = argv[++i];
    else if (!strcmp(argv[i], "--cage") && i + 1 < argc) cage_path = argv[++i];
    else if (!strcmp(argv[i], "--out") && i + 1 < argc) out_path = argv[++i];
    else if (!strcmp(argv[i], "--frames") && i + 1 < argc) frames = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--size") && i + 1 < argc) size = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--es")) es = 1;
    else if (!strcmp(argv[i], "--device")) use_device = 1;
    else {
      fprintf(stderr, "usage: %s [--scan SCAN --cage CAGE] [--frames N] [--size PIXELS] [--es] [--device] [--out IMAGE.png]\n",
              argv[0]);
      return 2;
    }
  }
  if (frames < 1 || frames > 100000 || size < 16 || size > 8192 || (!scan_path) != (!cage_path)) {
    fprintf(stderr, "egl_host: --frames 1..100000, --size 16..8192, --scan and --cage together\n");
    return 2;
  }
  crc_init();

  /* The host's context: GL 4.3 core or GLES 3.1, surfaceless (no window). */
  display = open_display(use_device);
  if (display == EGL_NO_DISPLAY) {
    fprintf(stderr, "egl_host: no EGL display (surfaceless Mesa or device); nothing to do here\n");
    return 77;
  }
  {
    EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, es ? 3 : 4, EGL_CONTEXT_MINOR_VERSION, es ? 1 : 3,
                           EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    if (es) attributes[4] = EGL_NONE;
    if (!eglBindAPI(es ? EGL_OPENGL_ES_API : EGL_OPENGL_API) ||
        (gl_context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes)) == EGL_NO_CONTEXT ||
        !eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, gl_context)) {
      fprintf(stderr, "egl_host: cannot make a %s context current (EGL error 0x%04x)\n", es ? "GLES 3.1" : "GL 4.3 core",
              (unsigned)eglGetError());
      eglTerminate(display);
      return 77;
    }
  }
  if (!load_gl()) goto done;

  if (!check(cagekit_context_create(NULL, &g_context), "context")) goto done;
  if (scan_path) {
    if (!check(cagekit_mesh_read_file(g_context, scan_path, CAGEKIT_FORMAT_AUTO, &scan), scan_path) ||
        !check(cagekit_cage_read_file(g_context, cage_path, CAGEKIT_FORMAT_AUTO, &cage), cage_path))
      goto done;
  } else if (!make_sphere(&scan) || !make_cage(scan, &cage)) {
    goto done;
  }
  {
    cagekit_bind_options bind = CAGEKIT_BIND_OPTIONS_INIT;
    cagekit_binding_info info;
    cagekit_gl_deformer_info gi;
    cagekit_gl_deformer_buffers buffers;
    cagekit_mesh cage_mesh = NULL;
    uint32_t m = 0, n, k, j;
    double *rest = NULL, *control = NULL, *cpu_p = NULL, *cpu_n = NULL, lo[3] = {1e300, 1e300, 1e300},
           hi[3] = {-1e300, -1e300, -1e300}, center[3], radius = 0, t0, cpu_seconds = 0, gpu_seconds = 0, reference_seconds = 0, cpu_deform_seconds = 0;
    float *interleaved = NULL, mvp[16], rotation[9], scale;
    unsigned char *pixels = NULL, *rgb = NULL;
    GLuint fbo = 0, color_rb = 0, depth_rb = 0, program = 0, vs, fs, vao_gpu = 0, vao_cpu = 0, cpu_vbo = 0;
    const char* version = es ? "#version 310 es\nprecision highp float;\n" : "#version 430 core\n";
    int drag[4] = {0, 0, 0, 0}, ok = 0;
    const double yaw = 0.6, pitch = 0.35;

    info.struct_size = sizeof(info);
    gi.struct_size = sizeof(gi);
    buffers.struct_size = sizeof(buffers);
    if (!check(cagekit_multires_bind(cage, scan, &bind, &binding), "binding the scan to the cage") ||
        !check(cagekit_binding_get_info(binding, &info), "binding info") ||
        !check(cagekit_cpu_deformer_create(binding, 0, &cpu), "CPU deformer") ||
        !check(cagekit_gl_deformer_create(binding, scan, get_proc_address, NULL, NULL, &gpu), "GL deformer") ||
        !check(cagekit_gl_deformer_get_info(gpu, &gi), "GL deformer info") ||
        !check(cagekit_gl_deformer_get_buffers(gpu, &buffers), "GL deformer buffers") ||
        !check(cagekit_cage_get_mesh(cage, &cage_mesh), "cage mesh"))
      goto scene_done;
    rest = positions_of(cage_mesh, &m);
    cagekit_mesh_release(cage_mesh);
    if (!rest) goto scene_done;
    n = info.vertex_count;
    printf("egl_host: %s, %s; scan %u vertices, %u triangles; cage %u control points; ACMR %.3f -> %.3f\n", gi.renderer,
           gi.version, n, gi.index_count / 3, m, gi.acmr_before, gi.acmr_after);

    /* Camera: orthographic, around the rest cage's bounding box. */
    for (j = 0; j < m; ++j)
      for (k = 0; k < 3; ++k) {
        if (rest[3 * j + k] < lo[k]) lo[k] = rest[3 * j + k];
        if (rest[3 * j + k] > hi[k]) hi[k] = rest[3 * j + k];
      }
    for (k = 0; k < 3; ++k) center[k] = 0.5 * (lo[k] + hi[k]), radius += 0.25 * (hi[k] - lo[k]) * (hi[k] - lo[k]);
    radius = sqrt(radius);
    scale = (float)(1.0 / (1.1 * radius));
    {
      const float cy = (float)cos(yaw), sy = (float)sin(yaw), cp = (float)cos(pitch), sp = (float)sin(pitch);
      /* R = Rx(pitch) * Ry(yaw), column-major */
      const float r[9] = {cy, sp * sy, -cp * sy, 0, cp, sp, sy, -sp * cy, cp * cy};
      memcpy(rotation, r, sizeof(r));
      for (k = 0; k < 3; ++k)
        for (j = 0; j < 3; ++j) mvp[4 * k + j] = scale * r[3 * k + j] * (j == 2 ? -0.5f : 1.0f); /* z: depth, flipped */
      mvp[3] = mvp[7] = mvp[11] = 0;
      for (j = 0; j < 3; ++j)
        mvp[12 + j] = -(mvp[j] * (float)center[0] + mvp[4 + j] * (float)center[1] + mvp[8 + j] * (float)center[2]);
      mvp[15] = 1;
    }

    /* The drag: the 4 control points furthest along +x move out by up to 30% of the size. */
    for (k = 0; k < 4; ++k) {
      int best = -1;
      for (j = 0; j < m; ++j) {
        int taken = 0, q;
        for (q = 0; q < (int)k; ++q) taken |= drag[q] == (int)j;
        if (!taken && (best < 0 || rest[3 * j] > rest[3 * best])) best = (int)j;
      }
      drag[k] = best;
    }
    control = (double*)checked_malloc(3 * sizeof(double) * m);
    cpu_p = (double*)checked_malloc(3 * sizeof(double) * n);
    cpu_n = (double*)checked_malloc(3 * sizeof(double) * n);
    interleaved = (float*)checked_malloc(6 * sizeof(float) * n);

    /* Offscreen framebuffer, the shading program, one VAO per path. */
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glGenRenderbuffers(1, &color_rb);
    glBindRenderbuffer(GL_RENDERBUFFER, color_rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, size, size);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_rb);
    glGenRenderbuffers(1, &depth_rb);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, size, size);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      fprintf(stderr, "egl_host: framebuffer incomplete\n");
      goto gl_done;
    }
    vs = compile(GL_VERTEX_SHADER, version, kVertex);
    fs = compile(GL_FRAGMENT_SHADER, version, kFragment);
    if (!vs || !fs) goto gl_done;
    program = glCreateProgram();
    glAttachShader(program, vs), glAttachShader(program, fs);
    glLinkProgram(program);
    glDeleteShader(vs), glDeleteShader(fs);
    {
      GLint linked = 0;
      glGetProgramiv(program, GL_LINK_STATUS, &linked);
      if (!linked) {
        fprintf(stderr, "egl_host: the shading program does not link\n");
        goto gl_done;
      }
    }
    glUseProgram(program);
    glUniformMatrix4fv(glGetUniformLocation(program, "u_mvp"), 1, GL_FALSE, mvp);
    glUniformMatrix3fv(glGetUniformLocation(program, "u_rotation"), 1, GL_FALSE, rotation);
    glViewport(0, 0, size, size);
    glEnable(GL_DEPTH_TEST);
    glClearColor(0.12f, 0.14f, 0.18f, 1.0f);

    glGenVertexArrays(1, &vao_gpu);
    glBindVertexArray(vao_gpu); /* the deformer's buffers, bound as the host likes */
    glBindBuffer(GL_ARRAY_BUFFER, buffers.position_buffer);
    glVertexAttribPointer(0, 3, buffers.component_type, GL_FALSE, (GLsizei)buffers.position_stride,
                          (const void*)(size_t)buffers.position_offset);
    glBindBuffer(GL_ARRAY_BUFFER, buffers.normal_buffer);
    glVertexAttribPointer(1, 3, buffers.component_type, GL_FALSE, (GLsizei)buffers.normal_stride,
                          (const void*)(size_t)buffers.normal_offset);
    glEnableVertexAttribArray(0), glEnableVertexAttribArray(1);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buffers.index_buffer);

    glGenBuffers(1, &cpu_vbo);
    glGenVertexArrays(1, &vao_cpu);
    glBindVertexArray(vao_cpu); /* the CPU path: the host uploads the deformed vertices */
    glBindBuffer(GL_ARRAY_BUFFER, cpu_vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(24 * (size_t)n), NULL, GL_STREAM_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 24, (const void*)0);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 24, (const void*)12);
    glEnableVertexAttribArray(0), glEnableVertexAttribArray(1);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buffers.index_buffer);

    /* Three passes of the same drag: CPU path, GPU path (compute), GPU reference mode of the
     * thesis (vertex attributes for the 4 dragged points, transform feedback). */
    {
      uint32_t edited[4];
      for (j = 0; j < 4; ++j) edited[j] = (uint32_t)drag[j];
      if (!check(cagekit_gl_deformer_set_reference_set(gpu, edited, 4, rest, m), "reference mode")) goto gl_done;
    }
    for (k = 0; k < 3; ++k) {
      int frame;
      t0 = now_seconds();
      for (frame = 1; frame <= frames; ++frame) {
        const double amount = 0.6 * radius * frame / frames;
        memcpy(control, rest, 3 * sizeof(double) * m);
        for (j = 0; j < 4; ++j) control[3 * drag[j]] += amount, control[3 * drag[j] + 1] += 0.3 * amount;
        if (k == 0) {
          const double d0 = now_seconds();
          uint32_t v, written;
          if (!check(cagekit_cpu_deformer_deform(cpu, control, m, CAGEKIT_NORMALS_APPROXIMATE, n, &written, cpu_p,
                                                 cpu_n),
                     "CPU deform"))
            goto gl_done;
          cpu_deform_seconds += now_seconds() - d0;
          for (v = 0; v < 3 * n; v += 3) {
            float* o = interleaved + 2 * v;
            o[0] = (float)cpu_p[v], o[1] = (float)cpu_p[v + 1], o[2] = (float)cpu_p[v + 2];
            o[3] = (float)cpu_n[v], o[4] = (float)cpu_n[v + 1], o[5] = (float)cpu_n[v + 2];
          }
          glBindVertexArray(vao_cpu);
          glBindBuffer(GL_ARRAY_BUFFER, cpu_vbo);
          glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(24 * (size_t)n), interleaved);
        } else if (k == 1) {
          if (!check(cagekit_gl_deformer_deform(gpu, control, m, CAGEKIT_NORMALS_APPROXIMATE), "GPU deform")) goto gl_done;
          glBindVertexArray(vao_gpu);
        } else {
          if (!check(cagekit_gl_deformer_deform_reference(gpu, control, m), "GPU reference deform")) goto gl_done;
          glBindVertexArray(vao_gpu);
        }
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glDrawElements(GL_TRIANGLES, (GLsizei)buffers.index_count, GL_UNSIGNED_INT, (const void*)0);
        glFinish();
      }
      if (k == 0) cpu_seconds = now_seconds() - t0;
      else if (k == 1) gpu_seconds = now_seconds() - t0;
      else reference_seconds = now_seconds() - t0;
    }
    printf("egl_host: %d frames of %u vertices: CPU path %.1f fps (deform alone %.1f fps), GPU path %.1f fps, "
           "GPU reference mode (|Q| = 4, 28 floats per vertex) %.1f fps (%s)\n",
           frames, n, frames / cpu_seconds, frames / cpu_deform_seconds, frames / gpu_seconds, frames / reference_seconds,
           gi.renderer);

    /* The last GPU frame to PNG (rows bottom-up in GL). */
    pixels = (unsigned char*)checked_malloc(4 * (size_t)size * size);
    rgb = (unsigned char*)checked_malloc(3 * (size_t)size * size);
    glReadPixels(0, 0, size, size, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
    if (glGetError() != GL_NO_ERROR) {
      fprintf(stderr, "egl_host: a GL error occurred while rendering\n");
      goto gl_done;
    }
    {
      size_t y, x, lit = 0;
      for (y = 0; y < (size_t)size; ++y)
        for (x = 0; x < (size_t)size; ++x) {
          const unsigned char* s = pixels + 4 * ((size - 1 - y) * (size_t)size + x);
          unsigned char* d = rgb + 3 * (y * (size_t)size + x);
          d[0] = s[0], d[1] = s[1], d[2] = s[2];
          lit += s[0] != 31 || s[1] != 36 || s[2] != 46;
        }
      if (!write_png(out_path, rgb, (uint32_t)size, (uint32_t)size)) goto gl_done;
      printf("egl_host: wrote %s (%d x %d, %.1f%% of the pixels show the scan)\n", out_path, size, size,
             100.0 * lit / ((double)size * size));
    }
    ok = 1;
  gl_done:
    glBindVertexArray(0);
    glUseProgram(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (vao_gpu) glDeleteVertexArrays(1, &vao_gpu);
    if (vao_cpu) glDeleteVertexArrays(1, &vao_cpu);
    if (cpu_vbo) glDeleteBuffers(1, &cpu_vbo);
    if (program) glDeleteProgram(program);
    if (fbo) glDeleteFramebuffers(1, &fbo);
    if (color_rb) glDeleteRenderbuffers(1, &color_rb);
    if (depth_rb) glDeleteRenderbuffers(1, &depth_rb);
  scene_done:
    free(rest), free(control), free(cpu_p), free(cpu_n), free(interleaved), free(pixels), free(rgb);
    if (ok) status = 0;
  }
done:
  cagekit_gl_deformer_release(gpu); /* the context is still current: its GL objects go now */
  cagekit_cpu_deformer_release(cpu);
  cagekit_binding_release(binding);
  cagekit_cage_release(cage);
  cagekit_mesh_release(scan);
  cagekit_context_release(g_context);
  eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (gl_context != EGL_NO_CONTEXT) eglDestroyContext(display, gl_context);
  eglTerminate(display);
  eglReleaseThread();
  return status;
}
