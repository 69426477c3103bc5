// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Saves, and restores on destruction, every piece of the host's GL state the GPU deformer
// changes: the current program, the generic GL_SHADER_STORAGE_BUFFER binding and the indexed
// bindings 0..3 (buffer, offset, size), the GL_COPY_READ_BUFFER / GL_COPY_WRITE_BUFFER bindings
// (all uploads and read-backs go through these two, so no vertex-array object of the host and
// no GL_ARRAY_BUFFER / GL_ELEMENT_ARRAY_BUFFER binding is touched by the compute path). The
// indexed bindings are restored first: glBindBufferBase/Range also set the generic binding.
#include "gpu/gl_functions.h"

CAGEKIT_NAMESPACE_BEGIN

class GlStateGuard {
 public:
  static constexpr int kStorageBindings = 4;  // the bindings shaders/deform.comp uses

  // vertex_state: also the state the reference mode's transform-feedback draw changes (bound
  // vertex array, GL_ARRAY_BUFFER, transform feedback object and its generic buffer binding,
  // GL_RASTERIZER_DISCARD, the draw framebuffer).
  explicit GlStateGuard(const GlFunctions& gl, bool vertex_state = false) : gl_(gl), vertex_state_(vertex_state) {
    if (vertex_state_) {
      gl_.GetIntegerv(GL_VERTEX_ARRAY_BINDING, &vertex_array_);
      gl_.GetIntegerv(GL_ARRAY_BUFFER_BINDING, &array_buffer_);
      gl_.GetIntegerv(GL_TRANSFORM_FEEDBACK_BINDING, &feedback_);
      gl_.GetIntegerv(GL_TRANSFORM_FEEDBACK_BUFFER_BINDING, &feedback_buffer_);
      gl_.GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_framebuffer_);
      discard_ = gl_.IsEnabled(GL_RASTERIZER_DISCARD);
    }
    gl_.GetIntegerv(GL_CURRENT_PROGRAM, &program_);
    gl_.GetIntegerv(GL_SHADER_STORAGE_BUFFER_BINDING, &storage_);
    gl_.GetIntegerv(GL_COPY_READ_BUFFER_BINDING, &copy_read_);
    gl_.GetIntegerv(GL_COPY_WRITE_BUFFER_BINDING, &copy_write_);
    for (int i = 0; i < kStorageBindings; ++i) {
      gl_.GetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, GLuint(i), &indexed_[i].buffer);
      gl_.GetInteger64i_v(GL_SHADER_STORAGE_BUFFER_START, GLuint(i), &indexed_[i].start);
      gl_.GetInteger64i_v(GL_SHADER_STORAGE_BUFFER_SIZE, GLuint(i), &indexed_[i].size);
    }
  }
  ~GlStateGuard() {
    for (int i = 0; i < kStorageBindings; ++i) {
      const Indexed& b = indexed_[i];
      // A binding made with glBindBufferBase reports size 0 (the whole buffer).
      if (b.buffer != 0 && b.size > 0)
        gl_.BindBufferRange(GL_SHADER_STORAGE_BUFFER, GLuint(i), GLuint(b.buffer), GLintptr(b.start), GLsizeiptr(b.size));
      else
        gl_.BindBufferBase(GL_SHADER_STORAGE_BUFFER, GLuint(i), GLuint(b.buffer));
    }
    gl_.BindBuffer(GL_SHADER_STORAGE_BUFFER, GLuint(storage_));
    gl_.BindBuffer(GL_COPY_READ_BUFFER, GLuint(copy_read_));
    gl_.BindBuffer(GL_COPY_WRITE_BUFFER, GLuint(copy_write_));
    gl_.UseProgram(GLuint(program_));
    if (vertex_state_) {
      gl_.BindTransformFeedback(GL_TRANSFORM_FEEDBACK, GLuint(feedback_));
      gl_.BindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, GLuint(feedback_buffer_));
      gl_.BindVertexArray(GLuint(vertex_array_));
      gl_.BindBuffer(GL_ARRAY_BUFFER, GLuint(array_buffer_));
      gl_.BindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw_framebuffer_));
      if (discard_) gl_.Enable(GL_RASTERIZER_DISCARD);
      else gl_.Disable(GL_RASTERIZER_DISCARD);
    }
  }
  GlStateGuard(const GlStateGuard&) = delete;
  GlStateGuard& operator=(const GlStateGuard&) = delete;

 private:
  struct Indexed {
    GLint buffer = 0;
    GLint64 start = 0, size = 0;
  };
  const GlFunctions& gl_;
  bool vertex_state_;
  GLint program_ = 0, storage_ = 0, copy_read_ = 0, copy_write_ = 0;
  GLint vertex_array_ = 0, array_buffer_ = 0, feedback_ = 0, feedback_buffer_ = 0, draw_framebuffer_ = 0;
  GLboolean discard_ = GL_FALSE;
  Indexed indexed_[kStorageBindings];
};

CAGEKIT_NAMESPACE_END
