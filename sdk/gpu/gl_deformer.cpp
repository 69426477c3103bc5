// SPDX-License-Identifier: GPL-3.0-or-later
#include "gpu/gl_deformer.h"

#include <meshoptimizer.h>

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

}  // namespace

GlDeformer::GlDeformer(const ScanBinding& b, const std::vector<uint32_t>& triangles, GlGetProcAddress get_proc_address,
                       void* user_data, const GlDeformerOptions& options) {
  if (get_proc_address == nullptr) fail(Status::invalid_argument, "gl deformer: get_proc_address must not be NULL");
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

  // Feature check, before anything else is loaded: version first (its message is the useful one).
  gl_.GetString = reinterpret_cast<PFNGLGETSTRINGPROC>(get_proc_address("glGetString", user_data));
  if (gl_.GetString == nullptr)
    fail(Status::unsupported_format, "gl deformer: the get-proc-address callback has no glGetString (is a context current?)");
  const char* version = reinterpret_cast<const char*>(gl_.GetString(GL_VERSION));
  if (version == nullptr)
    fail(Status::unsupported_format, "gl deformer: glGetString(GL_VERSION) returned NULL: no GL context is current");
  version_string_ = version;
  version_ = parse_gl_version(version);
  if (!version_.parsed)
    fail(Status::unsupported_format, "gl deformer: cannot parse GL_VERSION \"" + version_string_ + "\"");
  if (!version_.has_compute())
    fail(Status::unsupported_format, "gl deformer: needs OpenGL 4.3 or OpenGL ES 3.1 (compute shaders, shader "
                                     "storage buffers); the current context is \"" + version_string_ + "\"");
  const char* renderer = reinterpret_cast<const char*>(gl_.GetString(GL_RENDERER));
  renderer_ = renderer ? renderer : "";
  const std::vector<std::string> missing = gl_.load(get_proc_address, user_data);
  if (!missing.empty())
    fail(Status::unsupported_format, "gl deformer: the get-proc-address callback did not provide " + join(missing));

  GLint blocks = 0, bindings = 0, groups_x = 0, groups_y = 0;
  GLint64 block_size = 0;
  gl_.GetIntegerv(GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS, &blocks);
  gl_.GetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &bindings);
  gl_.GetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &groups_x);
  gl_.GetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 1, &groups_y);
  {
    // GL_MAX_SHADER_STORAGE_BLOCK_SIZE is a 64-bit value; glGetInteger64v is not in the table,
    // the int query clamps (fine: the GLES minimum is 2^24, desktop 2^27).
    GLint size32 = 0;
    gl_.GetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &size32);
    block_size = size32 < 0 ? GLint64(INT32_MAX) : GLint64(size32);
  }
  if (blocks < 4 || bindings < 4)
    fail(Status::unsupported_format, "gl deformer: needs 4 shader storage blocks in a compute shader; the context has " +
                                         std::to_string(blocks) + " (bindings: " + std::to_string(bindings) + ")");
  if (groups_x < 1 || groups_y < 1)
    fail(Status::unsupported_format, "gl deformer: GL_MAX_COMPUTE_WORK_GROUP_COUNT is 0");
  max_block_size_ = block_size, max_groups_x_ = groups_x, max_groups_y_ = groups_y;
  const uint64_t groups = (uint64_t(n) + kLocalSize - 1) / kLocalSize;
  if (groups > uint64_t(groups_x) * uint64_t(groups_y))
    fail(Status::limit_exceeded, "gl deformer: " + std::to_string(n) + " vertices need more compute work groups than "
                                     "the context allows");

  vertex_count_ = uint32_t(n);
  control_count_ = b.num_control_vertices;
  local_frame_ = b.mode == DisplacementMode::local_frame;

  // Float32 conversion of the binding (once).
  std::vector<uint32_t> vertex_words(kVertexWords * n, 0), entry_words(kEntryWords * std::max<size_t>(entries, 1), 0);
  for (size_t i = 0; i < n; ++i) {
    uint32_t* w = &vertex_words[kVertexWords * i];
    w[0] = b.row_offsets[i], w[1] = b.row_offsets[i + 1];
    if (w[0] > w[1] || w[1] > entries) fail(Status::invalid_argument, "gl deformer: the binding's rows are inconsistent");
    w[2] = float_bits(b.displacement[i]);
    w[3] = float_bits(local_frame_ ? b.tangent_offset[2 * i] : 0.0);
    w[4] = float_bits(local_frame_ ? b.tangent_offset[2 * i + 1] : 0.0);
    for (int k = 0; k < 6; ++k) w[5 + k] = float_bits(b.normal_coefficients[6 * i + k]);
  }
  for (size_t e = 0; e < entries; ++e) {
    uint32_t* w = &entry_words[kEntryWords * e];
    w[0] = b.control_index[e], w[1] = float_bits(b.phi[e]), w[2] = float_bits(b.phi_u[e]), w[3] = float_bits(b.phi_v[e]);
  }

  std::vector<uint32_t> indices = triangles;
  if (!indices.empty()) {
    acmr_before_ = meshopt_analyzeVertexCache(indices.data(), indices.size(), n, 16, 0, 0).acmr;
    if (options.optimize_vertex_cache) meshopt_optimizeVertexCache(indices.data(), triangles.data(), triangles.size(), n);
    acmr_after_ = meshopt_analyzeVertexCache(indices.data(), indices.size(), n, 16, 0, 0).acmr;
  }
  index_count_ = uint32_t(indices.size());

  const uint64_t sizes[] = {4ull * kVertexWords * n, 4ull * kEntryWords * entries, 24ull * n,
                            12ull * std::max<uint32_t>(control_count_, 1)};
  for (uint64_t s : sizes)
    if (s > uint64_t(max_block_size_))
      fail(Status::limit_exceeded, "gl deformer: a buffer of " + std::to_string(s) + " bytes exceeds the context's "
                                       "GL_MAX_SHADER_STORAGE_BLOCK_SIZE of " + std::to_string(max_block_size_));

  const GlStateGuard guard(gl_);
  try {
    while (gl_.GetError() != GL_NO_ERROR) {  // earlier errors of the host are not ours
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
  const GLuint buffers[] = {control_, entries_, vertices_, output_, index_};
  if (gl_.DeleteBuffers != nullptr) gl_.DeleteBuffers(5, buffers);  // 0 names are ignored
  if (program_ != 0 && gl_.DeleteProgram != nullptr) gl_.DeleteProgram(program_);
  control_ = entries_ = vertices_ = output_ = index_ = program_ = 0;
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
  if (shader == 0) fail(Status::unsupported_format, "gl deformer: glCreateShader(GL_COMPUTE_SHADER) failed");
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
    fail(Status::unsupported_format, "gl deformer: shaders/deform.comp does not compile on \"" + renderer_ + "\": " + log);
  }
  program_ = gl_.CreateProgram();
  gl_.AttachShader(program_, shader);
  gl_.LinkProgram(program_);
  gl_.DeleteShader(shader);  // flagged; freed with the program
  gl_.GetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = log_of(program_, gl_.GetProgramiv, gl_.GetProgramInfoLog);
    fail(Status::unsupported_format, "gl deformer: shaders/deform.comp does not link on \"" + renderer_ + "\": " + log);
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

CAGEKIT_NAMESPACE_END
