// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/render_gl.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include <GL/glcorearb.h>

#include "core/status.h"
#include "render/bitmap_font.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

// ---------------------------------------------------------------------------------------------
// Entry points: all in both GL 3.3 core and GLES 3.0 (glClearDepthf: GLES 2+ and GL 4.1+; GL 3.3
// contexts fall back to glClearDepth).
// ---------------------------------------------------------------------------------------------

#define CAGEKIT_RENDER_GL(X)                                                \
  X(PFNGLGETSTRINGPROC, GetString)                                          \
  X(PFNGLGETINTEGERVPROC, GetIntegerv)                                      \
  X(PFNGLGETFLOATVPROC, GetFloatv)                                          \
  X(PFNGLGETBOOLEANVPROC, GetBooleanv)                                      \
  X(PFNGLGETERRORPROC, GetError)                                            \
  X(PFNGLISENABLEDPROC, IsEnabled)                                          \
  X(PFNGLENABLEPROC, Enable)                                                \
  X(PFNGLDISABLEPROC, Disable)                                              \
  X(PFNGLCREATESHADERPROC, CreateShader)                                    \
  X(PFNGLSHADERSOURCEPROC, ShaderSource)                                    \
  X(PFNGLCOMPILESHADERPROC, CompileShader)                                  \
  X(PFNGLGETSHADERIVPROC, GetShaderiv)                                      \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                            \
  X(PFNGLDELETESHADERPROC, DeleteShader)                                    \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram)                                  \
  X(PFNGLATTACHSHADERPROC, AttachShader)                                    \
  X(PFNGLBINDATTRIBLOCATIONPROC, BindAttribLocation)                        \
  X(PFNGLLINKPROGRAMPROC, LinkProgram)                                      \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                                    \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                          \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                                  \
  X(PFNGLUSEPROGRAMPROC, UseProgram)                                        \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                        \
  X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)                            \
  X(PFNGLUNIFORM4FVPROC, Uniform4fv)                                        \
  X(PFNGLUNIFORM3FVPROC, Uniform3fv)                                        \
  X(PFNGLUNIFORM2FPROC, Uniform2f)                                          \
  X(PFNGLUNIFORM1FPROC, Uniform1f)                                          \
  X(PFNGLGENBUFFERSPROC, GenBuffers)                                        \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                                  \
  X(PFNGLBINDBUFFERPROC, BindBuffer)                                        \
  X(PFNGLBUFFERDATAPROC, BufferData)                                        \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                              \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                              \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                        \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                      \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)              \
  X(PFNGLVERTEXATTRIB1FPROC, VertexAttrib1f)                                \
  X(PFNGLDRAWARRAYSPROC, DrawArrays)                                        \
  X(PFNGLDRAWELEMENTSPROC, DrawElements)                                    \
  X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                              \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                              \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                        \
  X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer)              \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)                \
  X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)                            \
  X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)                            \
  X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)                      \
  X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)                      \
  X(PFNGLVIEWPORTPROC, Viewport)                                            \
  X(PFNGLSCISSORPROC, Scissor)                                              \
  X(PFNGLCLEARCOLORPROC, ClearColor)                                        \
  X(PFNGLCLEARPROC, Clear)                                                  \
  X(PFNGLDEPTHFUNCPROC, DepthFunc)                                          \
  X(PFNGLDEPTHMASKPROC, DepthMask)                                          \
  X(PFNGLCOLORMASKPROC, ColorMask)                                          \
  X(PFNGLPOLYGONOFFSETPROC, PolygonOffset)                                  \
  X(PFNGLPIXELSTOREIPROC, PixelStorei)                                      \
  X(PFNGLREADPIXELSPROC, ReadPixels)                                        \
  X(PFNGLDRAWBUFFERSPROC, DrawBuffers)                                      \
  X(PFNGLREADBUFFERPROC, ReadBuffer)

using PfnClearDepthf = void(APIENTRYP)(GLfloat);
using PfnClearDepth = void(APIENTRYP)(GLdouble);

struct Gl {
#define CAGEKIT_RENDER_GL_MEMBER(type, name) type name = nullptr;
  CAGEKIT_RENDER_GL(CAGEKIT_RENDER_GL_MEMBER)
#undef CAGEKIT_RENDER_GL_MEMBER
  PfnClearDepthf ClearDepthf = nullptr;
  PfnClearDepth ClearDepth = nullptr;

  void load(GlGetProcAddress get, void* user) {
    std::string missing;
#define CAGEKIT_RENDER_GL_LOAD(type, name)                                     \
  name = reinterpret_cast<type>(get("gl" #name, user));                        \
  if (name == nullptr) missing += std::string(missing.empty() ? "" : ", ") + "gl" #name;
    CAGEKIT_RENDER_GL(CAGEKIT_RENDER_GL_LOAD)
#undef CAGEKIT_RENDER_GL_LOAD
    ClearDepthf = reinterpret_cast<PfnClearDepthf>(get("glClearDepthf", user));
    if (ClearDepthf == nullptr) ClearDepth = reinterpret_cast<PfnClearDepth>(get("glClearDepth", user));
    if (ClearDepthf == nullptr && ClearDepth == nullptr)
      missing += std::string(missing.empty() ? "" : ", ") + "glClearDepthf / glClearDepth";
    if (!missing.empty())
      fail(Status::unsupported_feature, "the GL loader does not provide the entry points the renderer needs: " + missing);
  }
  void clear_depth(float d) const {
    if (ClearDepthf != nullptr) ClearDepthf(d);
    else ClearDepth(double(d));
  }
  float get_clear_depth() const {
    GLfloat d = 1;
    GetFloatv(GL_DEPTH_CLEAR_VALUE, &d);
    return d;
  }
};

// ---------------------------------------------------------------------------------------------
// The host's state, saved and restored: program, vertex array, GL_ARRAY_BUFFER, the draw and
// read framebuffers, the renderbuffer binding, GL_PIXEL_PACK_BUFFER, viewport, scissor box,
// enables (depth test, cull face, blend, scissor test, stencil test, polygon offset fill,
// dither, rasterizer discard), depth func, depth mask, colour mask, polygon offset factor/units,
// clear colour and depth, pack alignment / row length / skip pixels / skip rows, the draw
// buffer of framebuffer 0 is not touched (the library's FBO has its own).
// ---------------------------------------------------------------------------------------------

class RenderStateGuard {
 public:
  explicit RenderStateGuard(const Gl& gl) : gl_(gl) {
    gl_.GetIntegerv(GL_CURRENT_PROGRAM, &program_);
    gl_.GetIntegerv(GL_VERTEX_ARRAY_BINDING, &vertex_array_);
    gl_.GetIntegerv(GL_ARRAY_BUFFER_BINDING, &array_buffer_);
    gl_.GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_fb_);
    gl_.GetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_fb_);
    gl_.GetIntegerv(GL_RENDERBUFFER_BINDING, &renderbuffer_);
    gl_.GetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &pack_buffer_);
    gl_.GetIntegerv(GL_VIEWPORT, viewport_);
    gl_.GetIntegerv(GL_SCISSOR_BOX, scissor_);
    for (size_t i = 0; i < kEnables; ++i) enabled_[i] = gl_.IsEnabled(kEnable[i]);
    gl_.GetIntegerv(GL_DEPTH_FUNC, &depth_func_);
    gl_.GetBooleanv(GL_DEPTH_WRITEMASK, &depth_mask_);
    gl_.GetBooleanv(GL_COLOR_WRITEMASK, color_mask_);
    gl_.GetFloatv(GL_POLYGON_OFFSET_FACTOR, &offset_factor_);
    gl_.GetFloatv(GL_POLYGON_OFFSET_UNITS, &offset_units_);
    gl_.GetFloatv(GL_COLOR_CLEAR_VALUE, clear_color_);
    clear_depth_ = gl_.get_clear_depth();
    for (size_t i = 0; i < kPacks; ++i) gl_.GetIntegerv(kPack[i], &pack_[i]);
  }
  ~RenderStateGuard() {
    gl_.UseProgram(GLuint(program_));
    gl_.BindVertexArray(GLuint(vertex_array_));
    gl_.BindBuffer(GL_ARRAY_BUFFER, GLuint(array_buffer_));
    gl_.BindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw_fb_));
    gl_.BindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read_fb_));
    gl_.BindRenderbuffer(GL_RENDERBUFFER, GLuint(renderbuffer_));
    gl_.BindBuffer(GL_PIXEL_PACK_BUFFER, GLuint(pack_buffer_));
    gl_.Viewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
    gl_.Scissor(scissor_[0], scissor_[1], scissor_[2], scissor_[3]);
    for (size_t i = 0; i < kEnables; ++i) {
      if (enabled_[i]) gl_.Enable(kEnable[i]);
      else gl_.Disable(kEnable[i]);
    }
    gl_.DepthFunc(GLenum(depth_func_));
    gl_.DepthMask(depth_mask_);
    gl_.ColorMask(color_mask_[0], color_mask_[1], color_mask_[2], color_mask_[3]);
    gl_.PolygonOffset(offset_factor_, offset_units_);
    gl_.ClearColor(clear_color_[0], clear_color_[1], clear_color_[2], clear_color_[3]);
    gl_.clear_depth(clear_depth_);
    for (size_t i = 0; i < kPacks; ++i) gl_.PixelStorei(kPack[i], pack_[i]);
  }
  RenderStateGuard(const RenderStateGuard&) = delete;
  RenderStateGuard& operator=(const RenderStateGuard&) = delete;

 private:
  static constexpr size_t kEnables = 8;
  static constexpr GLenum kEnable[kEnables] = {GL_DEPTH_TEST,    GL_CULL_FACE,           GL_BLEND,  GL_SCISSOR_TEST,
                                               GL_STENCIL_TEST,  GL_POLYGON_OFFSET_FILL, GL_DITHER, GL_RASTERIZER_DISCARD};
  static constexpr size_t kPacks = 4;
  static constexpr GLenum kPack[kPacks] = {GL_PACK_ALIGNMENT, GL_PACK_ROW_LENGTH, GL_PACK_SKIP_PIXELS,
                                           GL_PACK_SKIP_ROWS};
  const Gl& gl_;
  GLint program_ = 0, vertex_array_ = 0, array_buffer_ = 0, draw_fb_ = 0, read_fb_ = 0, renderbuffer_ = 0,
        pack_buffer_ = 0;
  GLint viewport_[4] = {}, scissor_[4] = {};
  GLboolean enabled_[kEnables] = {};
  GLint depth_func_ = GL_LESS;
  GLboolean depth_mask_ = GL_TRUE, color_mask_[4] = {GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE};
  GLfloat offset_factor_ = 0, offset_units_ = 0, clear_color_[4] = {}, clear_depth_ = 1;
  GLint pack_[kPacks] = {};
};

constexpr GLenum RenderStateGuard::kEnable[];
constexpr GLenum RenderStateGuard::kPack[];

// GL objects made by one draw, deleted on every path out.
struct Objects {
  const Gl& gl;
  std::vector<GLuint> buffers, arrays, programs, renderbuffers, framebuffers;
  explicit Objects(const Gl& g) : gl(g) {}
  ~Objects() {
    if (!framebuffers.empty()) gl.DeleteFramebuffers(GLsizei(framebuffers.size()), framebuffers.data());
    if (!renderbuffers.empty()) gl.DeleteRenderbuffers(GLsizei(renderbuffers.size()), renderbuffers.data());
    if (!arrays.empty()) gl.DeleteVertexArrays(GLsizei(arrays.size()), arrays.data());
    if (!buffers.empty()) gl.DeleteBuffers(GLsizei(buffers.size()), buffers.data());
    for (GLuint p : programs) gl.DeleteProgram(p);
  }
  GLuint buffer(GLenum target, const void* data, size_t bytes) {
    GLuint b = 0;
    gl.GenBuffers(1, &b);
    buffers.push_back(b);
    gl.BindBuffer(target, b);
    gl.BufferData(target, GLsizeiptr(bytes), data, GL_STATIC_DRAW);
    return b;
  }
  GLuint vertex_array() {
    GLuint a = 0;
    gl.GenVertexArrays(1, &a);
    arrays.push_back(a);
    gl.BindVertexArray(a);
    return a;
  }
};

struct Version {
  bool es = false, parsed = false;
  int major = 0, minor = 0;
};

Version parse_version(const char* text) {
  Version v;
  if (text == nullptr) return v;
  const char* p = text;
  const char* es_prefix = "OpenGL ES ";
  if (std::strncmp(p, es_prefix, std::strlen(es_prefix)) == 0) {
    v.es = true;
    p += std::strlen(es_prefix);
  }
  v.parsed = std::sscanf(p, "%d.%d", &v.major, &v.minor) == 2;
  return v;
}

const char* kSurfaceVertex = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in float a_scalar;
uniform mat4 u_mvp;
uniform mat4 u_view;
out vec3 v_normal;
out float v_scalar;
void main() {
  gl_Position = u_mvp * vec4(a_position, 1.0);
  v_normal = mat3(u_view) * a_normal;
  v_scalar = a_scalar;
}
)";

const char* kSurfaceFragment = R"(
in vec3 v_normal;
in float v_scalar;
uniform vec4 u_color;
uniform float u_use_scalar;
uniform vec2 u_range;
uniform vec3 u_cmap[9];
uniform float u_cmap_n;
out vec4 o_color;
void main() {
  vec3 base = u_color.rgb;
  if (u_use_scalar > 0.5) {
    float t = clamp((v_scalar - u_range.x) / max(u_range.y - u_range.x, 1e-30), 0.0, 1.0);
    float x = t * (u_cmap_n - 1.0);
    int i = int(min(floor(x), u_cmap_n - 2.0));
    base = mix(u_cmap[i], u_cmap[i + 1], x - float(i));
  }
  vec3 n = normalize(v_normal);
  // A key light from the upper left and a headlight; two-sided (scans are not always oriented).
  float key = abs(dot(n, normalize(vec3(-0.35, 0.55, 0.75))));
  float head = abs(n.z);
  o_color = vec4(base * (0.22 + 0.48 * key + 0.30 * head), 1.0);
}
)";

const char* kLineVertex = R"(
layout(location = 0) in vec3 a_position;
uniform mat4 u_mvp;
void main() { gl_Position = u_mvp * vec4(a_position, 1.0); }
)";

const char* kLineFragment = R"(
uniform vec4 u_color;
out vec4 o_color;
void main() { o_color = vec4(u_color.rgb, 1.0); }
)";

GLuint compile(const Gl& gl, GLenum type, const std::string& source, const char* name) {
  const GLuint shader = gl.CreateShader(type);
  const char* text = source.c_str();
  gl.ShaderSource(shader, 1, &text, nullptr);
  gl.CompileShader(shader);
  GLint ok = 0;
  gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    gl.GetShaderInfoLog(shader, sizeof(log) - 1, nullptr, log);
    gl.DeleteShader(shader);
    fail(Status::unsupported_feature, std::string("the render shader ") + name + " does not compile: " + log);
  }
  return shader;
}

GLuint program(const Gl& gl, Objects& objects, const std::string& header, const char* vs, const char* fs,
               const char* name) {
  const GLuint v = compile(gl, GL_VERTEX_SHADER, header + vs, name);
  GLuint f = 0;
  try {
    f = compile(gl, GL_FRAGMENT_SHADER, header + fs, name);
  } catch (...) {
    gl.DeleteShader(v);
    throw;
  }
  const GLuint p = gl.CreateProgram();
  objects.programs.push_back(p);
  gl.AttachShader(p, v);
  gl.AttachShader(p, f);
  gl.LinkProgram(p);
  gl.DeleteShader(v);
  gl.DeleteShader(f);
  GLint ok = 0;
  gl.GetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    gl.GetProgramInfoLog(p, sizeof(log) - 1, nullptr, log);
    fail(Status::unsupported_feature, std::string("the render program ") + name + " does not link: " + log);
  }
  return p;
}

// ---------------------------------------------------------------------------------------------
// Layout and cameras
// ---------------------------------------------------------------------------------------------

struct Tile {
  int x0, y0, x1, y1;         // pixel rectangle, top-down rows
  int vx0, vy0, vx1, vy1;     // the 3-D viewport inside it (top-down)
  int scale;                  // text scale
  int title_band;
  int legend_x;               // left of the legend strip (0: none)
  int legend_item;            // index of the item whose legend is drawn, or -1
};

// The image is a grid of tiles, each showing one item column from one view. Normally the item
// columns are the grid's columns and the views its rows. A scene with a single item column and
// several views would give wide, short tiles that way; it lays its views out row-major in a
// near-square grid instead (`wrapped`): the number of grid columns is the one whose tiles are
// closest to square (|log(width / height)| smallest; ties: fewer empty cells, then fewer columns).
struct Cell {
  int view = 0;       // index into the settings' views
  int column = 0;     // item column
  int tile_row = 0, tile_column = 0;
};

struct Grid {
  int columns = 1;                 // item columns
  int views = 1;
  int tile_columns = 1, tile_rows = 1;
  bool wrapped = false;
  std::vector<int> column_of;      // item -> item column
  std::vector<Cell> cells;         // every drawn tile, row-major
};

Grid grid_of(const RenderScene& scene) {
  Grid g;
  const RenderSettings& s = scene.settings();
  g.column_of = scene.item_columns(&g.columns);
  g.views = std::max(1, int(s.views.size()));
  if (g.columns == 1 && g.views > 1) {
    g.wrapped = true;
    double best_score = 0;
    int best_empty = 0;
    for (int c = 1; c <= g.views; ++c) {
      const int r = (g.views + c - 1) / c;
      const double aspect = (double(s.width) / c) / (double(s.height) / r);
      const double score = std::fabs(std::log(aspect));
      const int empty = c * r - g.views;
      if (c == 1 || score < best_score - 1e-9 || (std::fabs(score - best_score) <= 1e-9 && empty < best_empty)) {
        best_score = score;
        best_empty = empty;
        g.tile_columns = c;
        g.tile_rows = r;
      }
    }
    for (int v = 0; v < g.views; ++v) g.cells.push_back(Cell{v, 0, v / g.tile_columns, v % g.tile_columns});
  } else {
    g.tile_columns = g.columns;
    g.tile_rows = g.views;
    for (int v = 0; v < g.views; ++v)
      for (int c = 0; c < g.columns; ++c) g.cells.push_back(Cell{v, c, v, c});
  }
  return g;
}

std::string format_value(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.3g", v);
  return buf;
}

Tile tile_of(const RenderScene& scene, const Grid& g, const Cell& cell) {
  const RenderSettings& s = scene.settings();
  const int column = cell.column;
  Tile t{};
  t.x0 = int(int64_t(s.width) * cell.tile_column / g.tile_columns);
  t.x1 = int(int64_t(s.width) * (cell.tile_column + 1) / g.tile_columns);
  t.y0 = int(int64_t(s.height) * cell.tile_row / g.tile_rows);
  t.y1 = int(int64_t(s.height) * (cell.tile_row + 1) / g.tile_rows);
  t.scale = (t.x1 - t.x0) >= 480 && (t.y1 - t.y0) >= 320 ? 2 : 1;
  t.legend_item = -1;
  bool title = false;
  for (size_t i = 0; i < scene.items().size(); ++i) {
    if (g.column_of[i] != column) continue;
    const RenderItem& item = scene.items()[i];
    title = title || !item.style.title.empty();
    if (!item.scalars.empty() && item.scalar_style.legend && t.legend_item < 0) t.legend_item = int(i);
  }
  t.vx0 = t.x0;
  t.vx1 = t.x1;
  t.vy0 = t.y0;
  t.vy1 = t.y1;
  if (!s.labels) {
    t.legend_item = -1;
    return t;
  }
  if (title) {
    t.title_band = (kGlyphHeight + 4) * t.scale;
    t.vy0 = std::min(t.vy1 - 1, t.vy0 + t.title_band);
  }
  if (t.legend_item >= 0) {
    const RenderItem& item = scene.items()[size_t(t.legend_item)];
    const int labels = std::max(text_width(format_value(item.shown_max), t.scale),
                                text_width(format_value(item.shown_min), t.scale));
    const int strip = 10 * t.scale + 4 * t.scale + labels + 4 * t.scale;
    if (strip < (t.x1 - t.x0) / 2) {
      t.legend_x = t.x1 - strip;
      t.vx1 = t.legend_x;
    } else {
      t.legend_item = -1;
    }
  }
  return t;
}

struct Mat4 {
  double m[16] = {};  // column-major
  static Mat4 identity() {
    Mat4 r;
    r.m[0] = r.m[5] = r.m[10] = r.m[15] = 1;
    return r;
  }
  Mat4 operator*(const Mat4& b) const {
    Mat4 r;
    for (int c = 0; c < 4; ++c)
      for (int row = 0; row < 4; ++row) {
        double sum = 0;
        for (int k = 0; k < 4; ++k) sum += m[k * 4 + row] * b.m[c * 4 + k];
        r.m[c * 4 + row] = sum;
      }
    return r;
  }
  void to_float(float out[16]) const {
    for (int i = 0; i < 16; ++i) out[i] = float(m[i]);
  }
};

Mat4 look_at(const Vec3& eye, const Vec3& target, const Vec3& up) {
  const Vec3 f = normalized(target - eye);
  const Vec3 s = normalized(cross(f, up));
  const Vec3 u = cross(s, f);
  Mat4 r = Mat4::identity();
  r.m[0] = s.x, r.m[4] = s.y, r.m[8] = s.z;
  r.m[1] = u.x, r.m[5] = u.y, r.m[9] = u.z;
  r.m[2] = -f.x, r.m[6] = -f.y, r.m[10] = -f.z;
  r.m[12] = -dot(s, eye), r.m[13] = -dot(u, eye), r.m[14] = dot(f, eye);
  return r;
}

Mat4 perspective(double fovy, double aspect, double near_plane, double far_plane) {
  const double f = 1.0 / std::tan(fovy / 2);
  Mat4 r;
  r.m[0] = f / aspect;
  r.m[5] = f;
  r.m[10] = (far_plane + near_plane) / (near_plane - far_plane);
  r.m[11] = -1;
  r.m[14] = 2 * far_plane * near_plane / (near_plane - far_plane);
  return r;
}

// View and projection of `camera` for a viewport of `aspect`, framed on the box lo..hi.
void camera_matrices(const Camera& camera, const Vec3& lo, const Vec3& hi, double aspect, Mat4& view, Mat4& proj) {
  const Vec3 center = 0.5 * (lo + hi);
  const double radius = std::max(0.5 * norm(hi - lo), 1e-9 * std::max(1.0, norm(center)));
  const double fovy = camera.fov_degrees * M_PI / 180.0;
  Vec3 eye, target = center, up{0, 1, 0};
  if (camera.kind == ViewKind::custom) {
    eye = camera.eye;
    target = camera.target;
    up = camera.up;
  } else {
    Vec3 dir{1, 1, 1};
    switch (camera.kind) {
      case ViewKind::front: dir = {0, 0, 1}; break;
      case ViewKind::side: dir = {1, 0, 0}; break;
      case ViewKind::top: dir = {0, 1, 0}, up = {0, 0, -1}; break;
      default: dir = normalized(Vec3{1, 0.8, 1.2}); break;
    }
    const double fovx = 2 * std::atan(std::tan(fovy / 2) * aspect);
    const double distance = radius / std::sin(std::min(fovy, fovx) / 2);
    eye = center + distance * dir;
  }
  const double d = norm(center - eye);
  const double near_plane = std::max(d - 1.05 * radius, 1e-3 * radius);
  const double far_plane = std::max(d + 1.05 * radius, near_plane * 2);
  view = look_at(eye, target, up);
  proj = perspective(fovy, aspect, near_plane, far_plane);
}

}  // namespace

// ---------------------------------------------------------------------------------------------

void draw_labels(const RenderScene& scene, std::vector<uint8_t>& rgba) {
  const RenderSettings& s = scene.settings();
  if (!s.labels) return;
  const Grid g = grid_of(scene);
  // Text in black or white, whichever stands out on the background.
  const float luminance = 0.3f * s.background[0] + 0.59f * s.background[1] + 0.11f * s.background[2];
  const uint8_t ink[4] = {uint8_t(luminance > 0.5f ? 20 : 235), uint8_t(luminance > 0.5f ? 20 : 235),
                          uint8_t(luminance > 0.5f ? 20 : 235), 255};
  static const char* view_names[] = {"front", "side", "top", "iso", "view"};
  for (const Cell& cell : g.cells) {
      const int column = cell.column;
      const Tile t = tile_of(scene, g, cell);
      const int pad = 3 * t.scale;
      // Titles once per item column: in the first view's tile.
      if (cell.view == 0 && t.title_band > 0) {
        std::string title;
        for (size_t i = 0; i < scene.items().size(); ++i)
          if (g.column_of[i] == column && !scene.items()[i].style.title.empty())
            title += (title.empty() ? "" : " + ") + scene.items()[i].style.title;
        draw_text(rgba.data(), s.width, s.height, t.x0 + pad, t.y0 + 2 * t.scale, title, t.scale, ink);
      }
      // View names: at the start of each row, or in every tile of a wrapped grid.
      if (g.views > 1 && (g.wrapped || column == 0)) {
        const std::string name = view_names[int(s.views[size_t(cell.view)].kind)];
        draw_text(rgba.data(), s.width, s.height, t.x0 + pad, t.y1 - pad - kGlyphHeight * t.scale, name, t.scale,
                  ink);
      }
      if (t.legend_item < 0) continue;
      const RenderItem& item = scene.items()[size_t(t.legend_item)];
      const int bar_x = t.legend_x + 2 * t.scale, bar_w = 10 * t.scale;
      const int text_h = kGlyphHeight * t.scale;
      const int bar_y0 = t.vy0 + 2 * pad + text_h / 2 + text_h + pad;  // below the label line
      const int bar_y1 = t.y1 - pad - text_h / 2 - (g.views > 1 ? text_h + pad : 0);
      if (bar_y1 - bar_y0 < 8) continue;
      for (int y = bar_y0; y < bar_y1; ++y) {
        const double f = double(bar_y1 - 1 - y) / double(std::max(1, bar_y1 - 1 - bar_y0));
        const std::array<float, 3> c = colormap_color(item.scalar_style.colormap, f);
        const uint8_t px[4] = {uint8_t(std::lround(c[0] * 255)), uint8_t(std::lround(c[1] * 255)),
                               uint8_t(std::lround(c[2] * 255)), 255};
        for (int x = bar_x; x < bar_x + bar_w && x < s.width; ++x)
          std::memcpy(&rgba[4 * (size_t(y) * size_t(s.width) + size_t(x))], px, 4);
      }
      const int label_x = bar_x + bar_w + 3 * t.scale;
      draw_text(rgba.data(), s.width, s.height, label_x, bar_y0 - text_h / 2, format_value(item.shown_max), t.scale,
                ink);
      draw_text(rgba.data(), s.width, s.height, label_x, bar_y1 - 1 - text_h / 2, format_value(item.shown_min),
                t.scale, ink);
      // The quantity's name above the bar, right-aligned to the tile.
      const std::string& label = item.scalar_style.label;
      draw_text(rgba.data(), s.width, s.height, std::max(t.x0, t.x1 - pad - text_width(label, t.scale)),
                t.vy0 + pad, label, t.scale, ink);
    }
}

DrawResult draw_scene(const RenderScene& scene, GlGetProcAddress get_proc_address, void* user_data,
                      std::vector<uint8_t>& rgba) {
  if (get_proc_address == nullptr) fail(Status::invalid_argument, "get_proc_address must not be NULL");
  // glGetString first: without it nothing can be checked.
  const auto get_string = reinterpret_cast<PFNGLGETSTRINGPROC>(get_proc_address("glGetString", user_data));
  if (get_string == nullptr) fail(Status::unsupported_feature, "the GL loader does not provide glGetString");
  const char* version_text = reinterpret_cast<const char*>(get_string(GL_VERSION));
  if (version_text == nullptr)
    fail(Status::invalid_operation, "no GL context is current on this thread (glGetString(GL_VERSION) is NULL)");
  const Version version = parse_version(version_text);
  if (!version.parsed) fail(Status::unsupported_feature, std::string("cannot parse GL_VERSION '") + version_text + "'");
  if (version.es ? version.major < 3 : (version.major < 3 || (version.major == 3 && version.minor < 3)))
    fail(Status::unsupported_feature, std::string("the renderer needs OpenGL 3.3 or OpenGL ES 3.0; the context is ") +
                                          version_text);
  Gl gl;
  gl.load(get_proc_address, user_data);
  DrawResult result;
  const char* renderer = reinterpret_cast<const char*>(gl.GetString(GL_RENDERER));
  result.renderer = renderer != nullptr ? renderer : "";
  result.version = version_text;
  if (!version.es) {
    GLint profile = 0;
    gl.GetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    (void)profile;  // core or compatibility: both have everything used here
  }
  while (gl.GetError() != GL_NO_ERROR) {
  }
  const RenderSettings& s = scene.settings();
  GLint max_renderbuffer = 0, max_viewport[2] = {0, 0};
  gl.GetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_renderbuffer);
  gl.GetIntegerv(GL_MAX_VIEWPORT_DIMS, max_viewport);
  if (s.width > max_renderbuffer || s.height > max_renderbuffer || s.width > max_viewport[0] ||
      s.height > max_viewport[1])
    fail(Status::limit_exceeded, "the image is " + std::to_string(s.width) + " x " + std::to_string(s.height) +
                                     " but the GL context renders at most " +
                                     std::to_string(std::min(max_renderbuffer, max_viewport[0])) + " x " +
                                     std::to_string(std::min(max_renderbuffer, max_viewport[1])));

  RenderStateGuard guard(gl);
  Objects objects(gl);
  const std::string header = version.es ? "#version 300 es\nprecision highp float;\nprecision highp int;\n"
                                        : "#version 330 core\n";
  // Framebuffer: RGBA8 + 24-bit depth renderbuffers (no multisampling: identical input gives
  // identical bytes on every driver, and wireframe colours stay exact).
  GLuint fb = 0, color = 0, depth = 0;
  gl.GenFramebuffers(1, &fb);
  objects.framebuffers.push_back(fb);
  gl.GenRenderbuffers(1, &color);
  objects.renderbuffers.push_back(color);
  gl.GenRenderbuffers(1, &depth);
  objects.renderbuffers.push_back(depth);
  gl.BindRenderbuffer(GL_RENDERBUFFER, color);
  gl.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, s.width, s.height);
  gl.BindRenderbuffer(GL_RENDERBUFFER, depth);
  gl.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, s.width, s.height);
  gl.BindFramebuffer(GL_FRAMEBUFFER, fb);
  gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
  gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
  const GLenum attachment = GL_COLOR_ATTACHMENT0;
  gl.DrawBuffers(1, &attachment);
  gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
  if (gl.GetError() == GL_OUT_OF_MEMORY)
    fail(Status::out_of_memory, "GL_OUT_OF_MEMORY allocating the " + std::to_string(s.width) + " x " +
                                    std::to_string(s.height) + " framebuffer");
  const GLenum fb_status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
  if (fb_status != GL_FRAMEBUFFER_COMPLETE) {
    char hex[16];
    std::snprintf(hex, sizeof(hex), "0x%04x", unsigned(fb_status));
    fail(Status::unsupported_feature, std::string("the RGBA8 + DEPTH24 framebuffer is incomplete (") + hex + ")");
  }

  const GLuint surface_program = program(gl, objects, header, kSurfaceVertex, kSurfaceFragment, "surface");
  const GLuint line_program = program(gl, objects, header, kLineVertex, kLineFragment, "line");

  // Fixed state of the draw.
  for (GLenum off : {GL_CULL_FACE, GL_BLEND, GL_SCISSOR_TEST, GL_STENCIL_TEST, GL_DITHER, GL_RASTERIZER_DISCARD})
    gl.Disable(off);
  gl.Enable(GL_DEPTH_TEST);
  gl.DepthFunc(GL_LEQUAL);
  gl.DepthMask(GL_TRUE);
  gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  gl.Viewport(0, 0, s.width, s.height);
  gl.ClearColor(s.background[0], s.background[1], s.background[2], s.background[3]);
  gl.clear_depth(1.0f);
  gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

  // Upload every item once.
  struct Uploaded {
    GLuint surface = 0, wire = 0, crease = 0;
    GLsizei triangles = 0, wire_points = 0, crease_points = 0;
  };
  std::vector<Uploaded> uploaded(scene.items().size());
  for (size_t i = 0; i < scene.items().size(); ++i) {
    const RenderItem& item = scene.items()[i];
    Uploaded& u = uploaded[i];
    if (item.style.surface && !item.triangles.empty()) {
      u.surface = objects.vertex_array();
      objects.buffer(GL_ARRAY_BUFFER, item.positions.data(), item.positions.size() * sizeof(float));
      gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
      gl.EnableVertexAttribArray(0);
      objects.buffer(GL_ARRAY_BUFFER, item.normals.data(), item.normals.size() * sizeof(float));
      gl.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
      gl.EnableVertexAttribArray(1);
      if (!item.scalars.empty()) {
        const std::vector<float> scalars(item.scalars.begin(), item.scalars.end());
        objects.buffer(GL_ARRAY_BUFFER, scalars.data(), scalars.size() * sizeof(float));
        gl.VertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, 0, nullptr);
        gl.EnableVertexAttribArray(2);
      }
      objects.buffer(GL_ELEMENT_ARRAY_BUFFER, item.triangles.data(), item.triangles.size() * sizeof(uint32_t));
      u.triangles = GLsizei(item.triangles.size());
    }
    const auto lines = [&](const std::vector<float>& points, GLuint& array, GLsizei& count) {
      if (points.empty()) return;
      array = objects.vertex_array();
      objects.buffer(GL_ARRAY_BUFFER, points.data(), points.size() * sizeof(float));
      gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
      gl.EnableVertexAttribArray(0);
      count = GLsizei(points.size() / 3);
    };
    if (item.style.wireframe) lines(item.wire, u.wire, u.wire_points);
    if (item.style.creases) lines(item.crease, u.crease, u.crease_points);
  }
  gl.BindVertexArray(0);
  if (gl.GetError() == GL_OUT_OF_MEMORY) fail(Status::out_of_memory, "GL_OUT_OF_MEMORY uploading the scene");

  // One box frames every view: the items of all columns are drawn at the same scale.
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const RenderItem& item : scene.items())
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], item.lo[k]);
      hi[k] = std::max(hi[k], item.hi[k]);
    }
  if (scene.items().empty() || !(lo.x <= hi.x)) lo = hi = Vec3{};

  const GLint u_mvp = gl.GetUniformLocation(surface_program, "u_mvp");
  const GLint u_view = gl.GetUniformLocation(surface_program, "u_view");
  const GLint u_color = gl.GetUniformLocation(surface_program, "u_color");
  const GLint u_use_scalar = gl.GetUniformLocation(surface_program, "u_use_scalar");
  const GLint u_range = gl.GetUniformLocation(surface_program, "u_range");
  const GLint u_cmap = gl.GetUniformLocation(surface_program, "u_cmap");
  const GLint u_cmap_n = gl.GetUniformLocation(surface_program, "u_cmap_n");
  const GLint l_mvp = gl.GetUniformLocation(line_program, "u_mvp");
  const GLint l_color = gl.GetUniformLocation(line_program, "u_color");

  const Grid g = grid_of(scene);
  for (const Cell& cell : g.cells) {
      const int column = cell.column;
      const Tile t = tile_of(scene, g, cell);
      const int vw = t.vx1 - t.vx0, vh = t.vy1 - t.vy0;
      if (vw < 1 || vh < 1) continue;
      gl.Viewport(t.vx0, s.height - t.vy1, vw, vh);  // GL rows are bottom-up
      Mat4 view, proj;
      camera_matrices(s.views[size_t(cell.view)], lo, hi, double(vw) / double(vh), view, proj);
      float mvp[16], view_f[16];
      (proj * view).to_float(mvp);
      view.to_float(view_f);
      for (size_t i = 0; i < scene.items().size(); ++i) {
        if (g.column_of[i] != column) continue;
        const RenderItem& item = scene.items()[i];
        const Uploaded& u = uploaded[i];
        if (u.surface != 0) {
          gl.UseProgram(surface_program);
          gl.UniformMatrix4fv(u_mvp, 1, GL_FALSE, mvp);
          gl.UniformMatrix4fv(u_view, 1, GL_FALSE, view_f);
          gl.Uniform4fv(u_color, 1, item.style.color.data());
          const bool scalars = !item.scalars.empty();
          gl.Uniform1f(u_use_scalar, scalars ? 1.0f : 0.0f);
          if (scalars) {
            gl.Uniform2f(u_range, float(item.shown_min), float(item.shown_max));
            const int n = item.scalar_style.colormap == Colormap::viridis ? 9 : 3;
            float table[27] = {};
            for (int k = 0; k < n; ++k) {
              const std::array<float, 3> c = colormap_color(item.scalar_style.colormap, double(k) / (n - 1));
              std::copy(c.begin(), c.end(), table + 3 * k);
            }
            gl.Uniform3fv(u_cmap, 9, table);
            gl.Uniform1f(u_cmap_n, float(n));
          }
          gl.BindVertexArray(u.surface);
          if (!scalars) gl.VertexAttrib1f(2, 0.0f);
          // Pushed back so that lines on the surface (creases, a wireframe) win the depth test.
          gl.Enable(GL_POLYGON_OFFSET_FILL);
          gl.PolygonOffset(1.0f, 1.0f);
          gl.DrawElements(GL_TRIANGLES, u.triangles, GL_UNSIGNED_INT, nullptr);
          gl.Disable(GL_POLYGON_OFFSET_FILL);
        }
        if (u.wire != 0 || u.crease != 0) {
          gl.UseProgram(line_program);
          gl.UniformMatrix4fv(l_mvp, 1, GL_FALSE, mvp);
          if (u.wire != 0) {
            gl.Uniform4fv(l_color, 1, item.style.wire_color.data());
            gl.BindVertexArray(u.wire);
            gl.DrawArrays(GL_LINES, 0, u.wire_points);
          }
          if (u.crease != 0) {
            gl.Uniform4fv(l_color, 1, item.style.crease_color.data());
            gl.BindVertexArray(u.crease);
            gl.DrawArrays(GL_LINES, 0, u.crease_points);
          }
        }
      }
    }
  gl.BindVertexArray(0);

  // Read back (tightly packed, rows bottom-up) and flip.
  rgba.assign(4 * size_t(s.width) * size_t(s.height), 0);
  gl.BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
  gl.PixelStorei(GL_PACK_ROW_LENGTH, 0);
  gl.PixelStorei(GL_PACK_SKIP_PIXELS, 0);
  gl.PixelStorei(GL_PACK_SKIP_ROWS, 0);
  gl.BindFramebuffer(GL_READ_FRAMEBUFFER, fb);
  gl.ReadPixels(0, 0, s.width, s.height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  const GLenum error = gl.GetError();
  if (error == GL_OUT_OF_MEMORY) fail(Status::out_of_memory, "GL_OUT_OF_MEMORY while drawing");
  if (error != GL_NO_ERROR) {
    char hex[16];
    std::snprintf(hex, sizeof(hex), "0x%04x", unsigned(error));
    fail(Status::internal_error, std::string("GL error ") + hex + " while drawing on " + result.renderer);
  }
  const size_t stride = 4 * size_t(s.width);
  std::vector<uint8_t> line(stride);
  for (int y = 0; y < s.height / 2; ++y) {
    uint8_t* a = &rgba[size_t(y) * stride];
    uint8_t* b = &rgba[size_t(s.height - 1 - y) * stride];
    std::memcpy(line.data(), a, stride);
    std::memcpy(a, b, stride);
    std::memcpy(b, line.data(), stride);
  }
  draw_labels(scene, rgba);
  return result;
}

CAGEKIT_NAMESPACE_END
