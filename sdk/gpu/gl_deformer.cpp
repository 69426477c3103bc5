// SPDX-License-Identifier: GPL-3.0-or-later
#include "gpu/gl_deformer.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/status.h"
#include "gpu/gl_state_guard.h"
// gpu/shaders.h is generated at build time from shaders/*.comp (sdk/gpu/CMakeLists.txt).
#include "gpu/shaders.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

constexpr uint32_t kLocalSize = 64;  // local_size_x of shaders/deform.comp
constexpr uint32_t kVertexWords = 12, kEntryWords = 4;

uint32_t float_bits(double value) {
  const float f = static_cast<float>(value);
  uint32_t bits;
  std::memcpy(&bits, &f, sizeof(bits));
  return bits;
}

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// The binding and the triangles: sizes that fit 32-bit GPU indexing, consistent arrays, indices
// in range.
void validate_binding(const ScanBinding& b, const std::vector<uint32_t>& triangles) {
  const size_t n = b.num_vertices(), entries = b.num_entries();
  if (n == 0) fail(Status::invalid_argument, "gl deformer: the binding has no vertices");
  if (n > UINT32_MAX / kVertexWords || entries > UINT32_MAX / kEntryWords ||
      triangles.size() > UINT32_MAX || b.num_control_vertices > UINT32_MAX / 3)
    fail(Status::limit_exceeded, "gl deformer: the binding is too large for 32-bit GPU indexing");
  if (b.row_offsets.size() != n + 1 || b.phi.size() != entries || b.phi_u.size() != entries ||
      b.phi_v.size() != entries || b.displacement.size() != n || b.normal_coefficients.size() != 6 * n ||
      (b.mode == DisplacementMode::local_frame && b.tangent_offset.size() != 2 * n))
    fail(Status::invalid_argument, "gl deformer: the binding's arrays are inconsistent");
  if (triangles.size() % 3 != 0) fail(Status::invalid_argument, "gl deformer: triangle indices not a multiple of 3");
  for (uint32_t v : triangles)
    if (v >= n) fail(Status::invalid_argument, "gl deformer: a triangle index is out of range");
  for (uint32_t j : b.control_index)
    if (j >= b.num_control_vertices) fail(Status::invalid_argument, "gl deformer: a basis entry's control index is out of range");
}

// The binding converted to float32 (once): kVertexWords words per vertex (its row of basis
// entries, displacement, tangent offset, normal coefficients), kEntryWords per basis entry.
struct BindingWords {
  std::vector<uint32_t> vertices, entries;
};

BindingWords binding_words(const ScanBinding& b, bool local_frame) {
  const size_t n = b.num_vertices(), entries = b.num_entries();
  BindingWords words;
  std::vector<uint32_t>& vertex_words = words.vertices;
  std::vector<uint32_t>& entry_words = words.entries;
  vertex_words.assign(kVertexWords * n, 0);
  entry_words.assign(kEntryWords * std::max<size_t>(entries, 1), 0);
  for (size_t i = 0; i < n; ++i) {
    uint32_t* w = &vertex_words[kVertexWords * i];
    w[0] = b.row_offsets[i], w[1] = b.row_offsets[i + 1];
    if (w[0] > w[1] || w[1] > entries) fail(Status::invalid_argument, "gl deformer: the binding's rows are inconsistent");
    w[2] = float_bits(b.displacement[i]);
    w[3] = float_bits(local_frame ? b.tangent_offset[2 * i] : 0.0);
    w[4] = float_bits(local_frame ? b.tangent_offset[2 * i + 1] : 0.0);
    for (int k = 0; k < 6; ++k) w[5 + k] = float_bits(b.normal_coefficients[6 * i + k]);
  }
  for (size_t e = 0; e < entries; ++e) {
    uint32_t* w = &entry_words[kEntryWords * e];
    w[0] = b.control_index[e], w[1] = float_bits(b.phi[e]), w[2] = float_bits(b.phi_u[e]), w[3] = float_bits(b.phi_v[e]);
  }
  return words;
}

}  // namespace

GlDeformer::GlDeformer(const ScanBinding& b, const std::vector<uint32_t>& triangles, GlGetProcAddress get_proc_address,
                       void* user_data, const GlDeformerOptions& options)
    : binding_(b) {
  if (get_proc_address == nullptr) fail(Status::invalid_argument, "gl deformer: get_proc_address must not be NULL");
  validate_binding(b, triangles);
  load_functions(get_proc_address, user_data);
  query_limits(b.num_vertices());
  vertex_count_ = uint32_t(b.num_vertices());
  control_count_ = b.num_control_vertices;
  local_frame_ = b.mode == DisplacementMode::local_frame;
  const BindingWords words = binding_words(b, local_frame_);
  const std::vector<uint32_t> indices = reorder_triangles(triangles, options.optimize_vertex_cache);
  check_buffer_sizes(b.num_entries());
  create_objects(words.vertices, words.entries, indices);
}

// Feature check, before anything else is loaded: version first (its message is the useful one).
void GlDeformer::load_functions(GlGetProcAddress get_proc_address, void* user_data) {
  gl_.GetString = reinterpret_cast<PFNGLGETSTRINGPROC>(get_proc_address("glGetString", user_data));
  if (gl_.GetString == nullptr)
    fail(Status::invalid_operation, "gl deformer: the get-proc-address callback has no glGetString (is a context current?)");
  const char* version = reinterpret_cast<const char*>(gl_.GetString(GL_VERSION));
  if (version == nullptr)
    fail(Status::invalid_operation, "gl deformer: glGetString(GL_VERSION) returned NULL: no GL context is current");
  version_string_ = version;
  version_ = parse_gl_version(version);
  if (!version_.parsed)
    fail(Status::unsupported_feature, "gl deformer: cannot parse GL_VERSION \"" + version_string_ + "\"");
  if (!version_.has_compute())
    fail(Status::unsupported_feature, "gl deformer: needs OpenGL 4.3 or OpenGL ES 3.1 (compute shaders, shader "
                                     "storage buffers); the current context is \"" + version_string_ + "\"");
  const char* renderer = reinterpret_cast<const char*>(gl_.GetString(GL_RENDERER));
  renderer_ = renderer ? renderer : "";
  const std::vector<std::string> missing = gl_.load(get_proc_address, user_data);
  if (!missing.empty())
    fail(Status::unsupported_feature, "gl deformer: the get-proc-address callback did not provide " + join(missing));
}

// The context's limits the deformer needs: storage blocks, work groups for n vertices, block size.
void GlDeformer::query_limits(size_t n) {
  GLint blocks = 0, bindings = 0, groups_x = 0, groups_y = 0;
  GLint64 block_size = 0;
  gl_.GetIntegerv(GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS, &blocks);
  gl_.GetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &bindings);
  gl_.GetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &groups_x);
  gl_.GetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 1, &groups_y);
  gl_.GetIntegerv(GL_MAX_VERTEX_ATTRIBS, &max_vertex_attributes_);
  {
    // GL_MAX_SHADER_STORAGE_BLOCK_SIZE is a 64-bit value; glGetInteger64v is not in the table,
    // the int query clamps (fine: the GLES minimum is 2^24, desktop 2^27).
    GLint size32 = 0;
    gl_.GetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &size32);
    block_size = size32 < 0 ? GLint64(INT32_MAX) : GLint64(size32);
  }
  if (blocks < 4 || bindings < 4)
    fail(Status::unsupported_feature, "gl deformer: needs 4 shader storage blocks in a compute shader; the context has " +
                                         std::to_string(blocks) + " (bindings: " + std::to_string(bindings) + ")");
  if (groups_x < 1 || groups_y < 1)
    fail(Status::unsupported_feature, "gl deformer: GL_MAX_COMPUTE_WORK_GROUP_COUNT is 0");
  max_block_size_ = block_size, max_groups_x_ = groups_x, max_groups_y_ = groups_y;
  const uint64_t groups = (uint64_t(n) + kLocalSize - 1) / kLocalSize;
  if (groups > uint64_t(groups_x) * uint64_t(groups_y))
    fail(Status::limit_exceeded, "gl deformer: " + std::to_string(n) + " vertices need more compute work groups than "
                                     "the context allows");
}

// The index buffer's contents: the triangles, reordered for the vertex cache when asked, with the
// cache miss ratios before and after.
std::vector<uint32_t> GlDeformer::reorder_triangles(const std::vector<uint32_t>& triangles, bool optimize) {
  const size_t n = vertex_count_;
  std::vector<uint32_t> indices = triangles;
  if (!indices.empty()) {
    acmr_before_ = meshopt_analyzeVertexCache(indices.data(), indices.size(), n, 16, 0, 0).acmr;
    if (optimize) meshopt_optimizeVertexCache(indices.data(), triangles.data(), triangles.size(), n);
    acmr_after_ = meshopt_analyzeVertexCache(indices.data(), indices.size(), n, 16, 0, 0).acmr;
  }
  index_count_ = uint32_t(indices.size());
  return indices;
}

void GlDeformer::check_buffer_sizes(size_t entries) const {
  const size_t n = vertex_count_;
  const uint64_t sizes[] = {4ull * kVertexWords * n, 4ull * kEntryWords * entries, 24ull * n,
                            12ull * std::max<uint32_t>(control_count_, 1)};
  for (uint64_t s : sizes)
    if (s > uint64_t(max_block_size_))
      fail(Status::limit_exceeded, "gl deformer: a buffer of " + std::to_string(s) + " bytes exceeds the context's "
                                       "GL_MAX_SHADER_STORAGE_BLOCK_SIZE of " + std::to_string(max_block_size_));
}

// The program and the buffers; on failure, none of them is left behind.
void GlDeformer::create_objects(const std::vector<uint32_t>& vertex_words, const std::vector<uint32_t>& entry_words,
                                const std::vector<uint32_t>& indices) {
  const size_t n = vertex_count_;
  const GlStateGuard guard(gl_);
  try {
    // Earlier errors of the host are not ours (bounded: a lost context may keep reporting one).
    for (int k = 0; k < 64 && gl_.GetError() != GL_NO_ERROR; ++k) {
    }
    compile_program();
    vertices_ = make_buffer(vertex_words.data(), 4 * vertex_words.size(), GL_STATIC_DRAW);
    entries_ = make_buffer(entry_words.data(), 4 * entry_words.size(), GL_STATIC_DRAW);
    control_ = make_buffer(nullptr, 12 * size_t(std::max<uint32_t>(control_count_, 1)), GL_DYNAMIC_DRAW);
    output_ = make_buffer(nullptr, 24 * n, GL_DYNAMIC_COPY);
    if (!indices.empty()) index_ = make_buffer(indices.data(), 4 * indices.size(), GL_STATIC_DRAW);
    const GLenum error = gl_.GetError();
    if (error == GL_OUT_OF_MEMORY) fail(Status::out_of_memory, "gl deformer: GL_OUT_OF_MEMORY while uploading the binding");
    if (error != GL_NO_ERROR)
      fail(Status::internal_error, "gl deformer: GL error " + std::to_string(error) + " while creating its objects");
  } catch (...) {
    release();
    throw;
  }
}

GlDeformer::~GlDeformer() { release(); }

void GlDeformer::release() noexcept {
  const GLuint buffers[] = {control_, entries_, vertices_, output_, index_, reference_attributes_};
  if (gl_.DeleteBuffers != nullptr) gl_.DeleteBuffers(6, buffers);  // 0 names are ignored
  if (program_ != 0 && gl_.DeleteProgram != nullptr) gl_.DeleteProgram(program_);
  if (reference_program_ != 0 && gl_.DeleteProgram != nullptr) gl_.DeleteProgram(reference_program_);
  if (reference_vao_ != 0 && gl_.DeleteVertexArrays != nullptr) gl_.DeleteVertexArrays(1, &reference_vao_);
  if (reference_feedback_ != 0 && gl_.DeleteTransformFeedbacks != nullptr)
    gl_.DeleteTransformFeedbacks(1, &reference_feedback_);
  if (reference_framebuffer_ != 0 && gl_.DeleteFramebuffers != nullptr)
    gl_.DeleteFramebuffers(1, &reference_framebuffer_);
  control_ = entries_ = vertices_ = output_ = index_ = program_ = 0;
  reference_attributes_ = reference_program_ = reference_vao_ = reference_feedback_ = reference_framebuffer_ = 0;
}

uint32_t GlDeformer::make_buffer(const void* data, size_t bytes, uint32_t usage) {
  GLuint name = 0;
  gl_.GenBuffers(1, &name);
  if (name == 0) fail(Status::internal_error, "gl deformer: glGenBuffers returned no name");
  // GL_COPY_WRITE_BUFFER: binding it changes no vertex-array object of the host.
  gl_.BindBuffer(GL_COPY_WRITE_BUFFER, name);
  gl_.BufferData(GL_COPY_WRITE_BUFFER, GLsizeiptr(bytes), data, usage);
  gpu_bytes_ += bytes;
  return name;
}

void GlDeformer::compile_program() {
  const char* prefix = version_.es ? "#version 310 es\nprecision highp float;\nprecision highp int;\n#line 1\n"
                                   : "#version 430 core\n#line 1\n";
  const char* sources[] = {prefix, kShaderDeformComp};
  const GLuint shader = gl_.CreateShader(GL_COMPUTE_SHADER);
  if (shader == 0) fail(Status::unsupported_feature, "gl deformer: glCreateShader(GL_COMPUTE_SHADER) failed");
  gl_.ShaderSource(shader, 2, sources, nullptr);
  gl_.CompileShader(shader);
  auto log_of = [](GLuint object, PFNGLGETSHADERIVPROC get_iv, PFNGLGETSHADERINFOLOGPROC get_log) {
    GLint length = 0;
    get_iv(object, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    get_log(object, GLsizei(log.size()), nullptr, &log[0]);
    log.resize(std::strlen(log.c_str()));
    return log;
  };
  GLint ok = 0;
  gl_.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = log_of(shader, gl_.GetShaderiv, gl_.GetShaderInfoLog);
    gl_.DeleteShader(shader);
    fail(Status::unsupported_feature, "gl deformer: shaders/deform.comp does not compile on \"" + renderer_ + "\": " + log);
  }
  program_ = gl_.CreateProgram();
  gl_.AttachShader(program_, shader);
  gl_.LinkProgram(program_);
  gl_.DeleteShader(shader);  // flagged; freed with the program
  gl_.GetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = log_of(program_, gl_.GetProgramiv, gl_.GetProgramInfoLog);
    fail(Status::unsupported_feature, "gl deformer: shaders/deform.comp does not link on \"" + renderer_ + "\": " + log);
  }
  count_location_ = gl_.GetUniformLocation(program_, "u_vertex_count");
  mode_location_ = gl_.GetUniformLocation(program_, "u_local_frame");
  if (count_location_ < 0 || mode_location_ < 0)
    fail(Status::internal_error, "gl deformer: the compute shader lacks its uniforms");
}

void GlDeformer::deform(const float* control) {
  const GlStateGuard guard(gl_);
  gl_.BindBuffer(GL_COPY_WRITE_BUFFER, control_);
  if (control_count_ > 0) gl_.BufferSubData(GL_COPY_WRITE_BUFFER, 0, GLsizeiptr(12) * control_count_, control);
  gl_.UseProgram(program_);
  gl_.Uniform1ui(count_location_, vertex_count_);
  gl_.Uniform1i(mode_location_, local_frame_ ? 1 : 0);
  gl_.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, control_);
  gl_.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, entries_);
  gl_.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, vertices_);
  gl_.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, output_);
  const uint32_t groups = (vertex_count_ + kLocalSize - 1) / kLocalSize;
  const uint32_t gx = std::min<uint32_t>(groups, uint32_t(max_groups_x_));
  const uint32_t gy = (groups + gx - 1) / gx;
  gl_.DispatchCompute(gx, gy, 1);
  gl_.MemoryBarrier(GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

void GlDeformer::read_back(float* interleaved) const {
  const GlStateGuard guard(gl_);
  gl_.BindBuffer(GL_COPY_READ_BUFFER, output_);
  const GLsizeiptr bytes = GLsizeiptr(24) * vertex_count_;
  const void* mapped = gl_.MapBufferRange(GL_COPY_READ_BUFFER, 0, bytes, GL_MAP_READ_BIT);
  if (mapped == nullptr) fail(Status::internal_error, "gl deformer: glMapBufferRange of the output buffer failed");
  std::memcpy(interleaved, mapped, size_t(bytes));
  if (gl_.UnmapBuffer(GL_COPY_READ_BUFFER) == GL_FALSE)
    fail(Status::internal_error, "gl deformer: the output buffer's contents were lost while mapped; deform again");
}

// ---- the thesis's reference mode (vertex attributes + a vertex program generated for |Q|) ----

uint32_t GlDeformer::reference_max_edited() const {
  return max_vertex_attributes_ > 5 ? uint32_t(max_vertex_attributes_ - 5) : 0;
}

namespace {

// shaders/reference.vert specialised for |Q| = q (thesis §8.6 (c): generated whenever Q is defined).
std::string reference_prefix(bool es, size_t q) {
  std::string s = es ? "#version 310 es\nprecision highp float;\n" : "#version 430 core\n";
  s += "#define REFERENCE_Q " + std::to_string(q) + "\n#define REFERENCE_INPUTS";
  for (size_t k = 0; k < q; ++k)
    s += " layout(location = " + std::to_string(5 + k) + ") in vec3 a_w" + std::to_string(k) + ";";
  s += "\n#define REFERENCE_SUM";
  for (size_t k = 0; k < q; ++k) {
    const std::string w = "a_w" + std::to_string(k), c = "u_q[" + std::to_string(k) + "]";
    s += " s += " + w + ".x * " + c + "; su += " + w + ".y * " + c + "; sv += " + w + ".z * " + c + ";";
  }
  return s + "\n#line 1\n";
}

}  // namespace

void GlDeformer::set_reference_set(const std::vector<uint32_t>& edited, const float* control) {
  // Slot k of the dynamic attributes is the k-th point of Q itself (weight 1).
  std::vector<double> mix(edited.size() * edited.size(), 0.0);
  for (size_t k = 0; k < edited.size(); ++k) mix[k * edited.size() + k] = 1.0;
  build_reference(edited, mix, edited.size(), control);
  reference_affine_ = false;
}

void GlDeformer::set_reference_affine(const std::vector<uint32_t>& edited, const double frame[12], const float* control) {
  // Affine coordinates xi_j of every point c_j of Q in the frame (q_0..q_3):
  // [q_0 q_1 q_2 q_3; 1 1 1 1] xi_j = [c_j; 1], a 4x4 solve (Gaussian elimination, pivoting).
  for (int k = 0; k < 12; ++k)
    if (!std::isfinite(frame[k])) fail(Status::invalid_argument, "gl deformer: the affine frame is not finite");
  const Vec3 q0{frame[0], frame[1], frame[2]}, e1 = Vec3{frame[3], frame[4], frame[5]} - q0,
             e2 = Vec3{frame[6], frame[7], frame[8]} - q0, e3 = Vec3{frame[9], frame[10], frame[11]} - q0;
  const double volume = dot(e1, cross(e2, e3));
  const double scale = std::max({norm(e1), norm(e2), norm(e3)});
  if (!(std::abs(volume) > 1e-9 * scale * scale * scale))
    fail(Status::invalid_argument, "gl deformer: the affine frame's four points are (nearly) coplanar");
  std::vector<double> mix(4 * edited.size());
  for (size_t k = 0; k < edited.size(); ++k) {
    if (edited[k] >= control_count_)
      fail(Status::invalid_argument, "gl deformer: edited control point " + std::to_string(edited[k]) + " is out of range");
    // c - q0 = a e1 + b e2 + c e3 (Cramer), xi = (1 - a - b - c, a, b, c).
    const Vec3 d = Vec3{double(control[3 * size_t(edited[k])]), double(control[3 * size_t(edited[k]) + 1]),
                        double(control[3 * size_t(edited[k]) + 2])} - q0;
    const double a = dot(d, cross(e2, e3)) / volume, bb = dot(e1, cross(d, e3)) / volume,
                 c = dot(e1, cross(e2, d)) / volume;
    mix[4 * k] = 1 - a - bb - c, mix[4 * k + 1] = a, mix[4 * k + 2] = bb, mix[4 * k + 3] = c;
  }
  build_reference(edited, mix, 4, control);
  reference_affine_ = true;
}

void GlDeformer::build_reference(const std::vector<uint32_t>& edited, const std::vector<double>& mix, size_t slots,
                                 const float* control) {
  const ScanBinding& b = binding_;
  if (b.mode != DisplacementMode::normal)
    fail(Status::invalid_operation, "gl deformer: the reference mode is the thesis's normal-displacement mode; the "
                                   "binding uses local-frame displacement");
  const uint32_t max_q = reference_max_edited();
  if (edited.empty() || slots > max_q)
    fail(Status::invalid_argument, "gl deformer: the reference mode takes 1.." + std::to_string(max_q) +
                                       " edited control points (vertex attributes), got " + std::to_string(edited.size()));
  std::vector<int> slot(control_count_, -1);
  for (size_t k = 0; k < edited.size(); ++k) {
    if (edited[k] >= control_count_)
      fail(Status::invalid_argument, "gl deformer: edited control point " + std::to_string(edited[k]) + " is out of range");
    if (slot[edited[k]] >= 0)
      fail(Status::invalid_argument, "gl deformer: edited control point " + std::to_string(edited[k]) + " is listed twice");
    slot[edited[k]] = int(k);
  }
  const size_t q = slots, floats = 16 + 3 * q, n = vertex_count_;
  if (uint64_t(floats) * 4 * n > uint64_t(PTRDIFF_MAX)) fail(Status::limit_exceeded, "gl deformer: reference data too large");
  std::vector<float> data(floats * n, 0.0f);
  for (size_t i = 0; i < n; ++i) {
    float* v = &data[floats * i];
    const double* k = &b.normal_coefficients[6 * i];
    v[0] = float(b.displacement[i]), v[1] = float(k[0]), v[2] = float(k[1]), v[3] = float(k[2]);
    v[4] = float(k[3]), v[5] = float(k[4]), v[6] = float(k[5]);
    double fixed[9] = {};
    for (uint32_t e = b.row_offsets[i]; e < b.row_offsets[i + 1]; ++e) {
      const uint32_t j = b.control_index[e];
      if (slot[j] >= 0) {
        for (size_t l = 0; l < slots; ++l) {
          const double x = mix[size_t(slot[j]) * slots + l];
          if (x == 0) continue;
          float* w = &v[16 + 3 * l];
          w[0] += float(x * b.phi[e]), w[1] += float(x * b.phi_u[e]), w[2] += float(x * b.phi_v[e]);
        }
        continue;
      }
      for (int c = 0; c < 3; ++c) {
        const double x = control[3 * size_t(j) + c];
        fixed[c] += b.phi[e] * x, fixed[3 + c] += b.phi_u[e] * x, fixed[6 + c] += b.phi_v[e] * x;
      }
    }
    for (int c = 0; c < 9; ++c) v[7 + c] = float(fixed[c]);
  }

  const GlStateGuard guard(gl_, true);
  // The vertex program for this |Q| (recompiled when |Q| changes; one program per deformer).
  if (reference_program_ == 0 || reference_slots_ != q) {
    if (reference_program_ != 0) gl_.DeleteProgram(reference_program_), reference_program_ = 0;
    reference_q_.clear();
    const std::string vs_prefix = reference_prefix(version_.es, q);
    const std::string fs_prefix = version_.es ? "#version 310 es\nprecision highp float;\n#line 1\n" : "#version 430 core\n#line 1\n";
    GLuint shaders[2] = {gl_.CreateShader(GL_VERTEX_SHADER), gl_.CreateShader(GL_FRAGMENT_SHADER)};
    const char* sources[2][2] = {{vs_prefix.c_str(), kShaderReferenceVert}, {fs_prefix.c_str(), kShaderReferenceFrag}};
    std::string log;
    for (int k = 0; k < 2; ++k) {
      gl_.ShaderSource(shaders[k], 2, sources[k], nullptr);
      gl_.CompileShader(shaders[k]);
      GLint ok = 0;
      gl_.GetShaderiv(shaders[k], GL_COMPILE_STATUS, &ok);
      if (!ok) {
        char buffer[2048] = {};
        gl_.GetShaderInfoLog(shaders[k], sizeof(buffer), nullptr, buffer);
        log += buffer;
      }
    }
    const GLuint program = gl_.CreateProgram();
    gl_.AttachShader(program, shaders[0]), gl_.AttachShader(program, shaders[1]);
    const char* varyings[2] = {"v_position", "v_normal"};
    gl_.TransformFeedbackVaryings(program, 2, varyings, GL_INTERLEAVED_ATTRIBS);  // = the output layout
    gl_.LinkProgram(program);
    gl_.DeleteShader(shaders[0]), gl_.DeleteShader(shaders[1]);
    GLint linked = 0;
    gl_.GetProgramiv(program, GL_LINK_STATUS, &linked);
    if (!linked || !log.empty()) {
      char buffer[2048] = {};
      gl_.GetProgramInfoLog(program, sizeof(buffer), nullptr, buffer);
      gl_.DeleteProgram(program);
      fail(Status::unsupported_feature, "gl deformer: the reference vertex program does not build on \"" + renderer_ +
                                           "\": " + log + buffer);
    }
    reference_program_ = program;
    reference_q_location_ = gl_.GetUniformLocation(program, "u_q");
  }
  if (reference_vao_ == 0) gl_.GenVertexArrays(1, &reference_vao_);
  if (reference_feedback_ == 0) gl_.GenTransformFeedbacks(1, &reference_feedback_);
  if (reference_attributes_ == 0) gl_.GenBuffers(1, &reference_attributes_);
  if (reference_framebuffer_ == 0) {
    // The transform-feedback draw needs a complete draw framebuffer even with rasterisation
    // discarded (a surfaceless host has none): one without attachments, 1x1 (GL 4.3 / GLES 3.1).
    gl_.GenFramebuffers(1, &reference_framebuffer_);
    gl_.BindFramebuffer(GL_DRAW_FRAMEBUFFER, reference_framebuffer_);
    gl_.FramebufferParameteri(GL_DRAW_FRAMEBUFFER, GL_FRAMEBUFFER_DEFAULT_WIDTH, 1);
    gl_.FramebufferParameteri(GL_DRAW_FRAMEBUFFER, GL_FRAMEBUFFER_DEFAULT_HEIGHT, 1);
  }
  gl_.BindVertexArray(reference_vao_);
  gl_.BindBuffer(GL_ARRAY_BUFFER, reference_attributes_);
  gl_.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(4 * data.size()), data.data(), GL_STATIC_DRAW);
  gpu_bytes_ += 4 * data.size() - reference_bytes_;
  reference_bytes_ = 4 * data.size();
  const GLsizei stride = GLsizei(4 * floats);
  auto attribute = [&](GLuint location, GLint size, size_t offset) {
    gl_.VertexAttribPointer(location, size, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(4 * offset));
    gl_.EnableVertexAttribArray(location);
  };
  attribute(0, 4, 0), attribute(1, 3, 4), attribute(2, 3, 7), attribute(3, 3, 10), attribute(4, 3, 13);
  for (size_t k = 0; k < q; ++k) attribute(GLuint(5 + k), 3, 16 + 3 * k);
  reference_q_ = edited;
  reference_slots_ = q;
  reference_uniforms_.assign(3 * q, 0.0f);
}

void GlDeformer::deform_reference(const float* control) {
  if (reference_q_.empty() || reference_affine_)
    fail(Status::invalid_operation, "gl deformer: deform_reference needs a set_reference_set first");
  for (size_t k = 0; k < reference_q_.size(); ++k)
    for (int c = 0; c < 3; ++c) reference_uniforms_[3 * k + c] = control[3 * size_t(reference_q_[k]) + c];
  draw_reference();
}

void GlDeformer::deform_reference_affine(const double frame[12]) {
  if (reference_q_.empty() || !reference_affine_)
    fail(Status::invalid_operation, "gl deformer: deform_reference_affine needs a set_reference_affine first");
  for (int k = 0; k < 12; ++k) {
    if (!std::isfinite(frame[k])) fail(Status::invalid_argument, "gl deformer: the moved frame is not finite");
    reference_uniforms_[size_t(k)] = float(frame[k]);
  }
  draw_reference();
}

void GlDeformer::draw_reference() {
  const GlStateGuard guard(gl_, true);
  gl_.UseProgram(reference_program_);
  gl_.Uniform3fv(reference_q_location_, GLsizei(reference_slots_), reference_uniforms_.data());
  gl_.BindVertexArray(reference_vao_);
  gl_.BindFramebuffer(GL_DRAW_FRAMEBUFFER, reference_framebuffer_);
  gl_.BindTransformFeedback(GL_TRANSFORM_FEEDBACK, reference_feedback_);
  gl_.BindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, output_);
  gl_.Enable(GL_RASTERIZER_DISCARD);
  gl_.BeginTransformFeedback(GL_POINTS);
  gl_.DrawArrays(GL_POINTS, 0, GLsizei(vertex_count_));
  gl_.EndTransformFeedback();
  // Unbind the output from our transform feedback object so that the host may use it freely.
  gl_.BindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, 0);
  gl_.MemoryBarrier(GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

CAGEKIT_NAMESPACE_END
