// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Saves, and restores on destruction, every piece of the host's GL state the GPU deformer
// changes: the current program, the generic GL_SHADER_STORAGE_BUFFER binding and the indexed
// bindings 0..3 (buffer, offset, size), the GL_COPY_READ_BUFFER / GL_COPY_WRITE_BUFFER bindings
// (all uploads and read-backs go through these two, so no vertex-array object of the host and
// no GL_ARRAY_BUFFER / GL_ELEMENT_ARRAY_BUFFER binding is touched). The indexed bindings are
// restored first: glBindBufferBase/Range also set the generic binding.
#include "gpu/gl_functions.h"

CAGEKIT_NAMESPACE_BEGIN

class GlStateGuard {
 public:
  static constexpr int kStorageBindings = 4;  // the bindings shaders/deform.comp uses

  explicit GlStateGuard(const GlFunctions& gl) : gl_(gl) {
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
  }
  GlStateGuard(const GlStateGuard&) = delete;
  GlStateGuard& operator=(const GlStateGuard&) = delete;

 private:
  struct Indexed {
    GLint buffer = 0;
    GLint64 start = 0, size = 0;
  };
  const GlFunctions& gl_;
  GLint program_ = 0, storage_ = 0, copy_read_ = 0, copy_write_ = 0;
  Indexed indexed_[kStorageBindings];
};

CAGEKIT_NAMESPACE_END
