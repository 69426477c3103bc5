// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The GL entry points the GPU deformer uses, loaded through the host's get-proc-address
// callback (no GL loader of our own, no link against libGL/libEGL): only these functions, valid
// in both desktop GL >= 4.3 (core or compatibility) and GLES >= 3.1. Types and enum values come
// from Khronos's <GL/glcorearb.h> (a header only; nothing is linked).
#include <string>
#include <vector>

#include <GL/glcorearb.h>

#include "core/namespace.h"

CAGEKIT_NAMESPACE_BEGIN

using GlProc = void (*)();
// Returns the address of a GL function of the current context, or null.
using GlGetProcAddress = GlProc (*)(const char* name, void* user_data);

#define CAGEKIT_GL_FUNCTIONS(X)                                                                        \
  X(PFNGLGETSTRINGPROC, GetString)                                                                     \
  X(PFNGLGETINTEGERVPROC, GetIntegerv)                                                                 \
  X(PFNGLGETINTEGERI_VPROC, GetIntegeri_v)                                                             \
  X(PFNGLGETINTEGER64I_VPROC, GetInteger64i_v)                                                         \
  X(PFNGLGETERRORPROC, GetError)                                                                       \
  X(PFNGLCREATESHADERPROC, CreateShader)                                                               \
  X(PFNGLSHADERSOURCEPROC, ShaderSource)                                                               \
  X(PFNGLCOMPILESHADERPROC, CompileShader)                                                             \
  X(PFNGLGETSHADERIVPROC, GetShaderiv)                                                                 \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                                                       \
  X(PFNGLDELETESHADERPROC, DeleteShader)                                                               \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram)                                                             \
  X(PFNGLATTACHSHADERPROC, AttachShader)                                                               \
  X(PFNGLLINKPROGRAMPROC, LinkProgram)                                                                 \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                                                               \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                                                     \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                                                             \
  X(PFNGLUSEPROGRAMPROC, UseProgram)                                                                   \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                                                   \
  X(PFNGLUNIFORM1UIPROC, Uniform1ui)                                                                   \
  X(PFNGLUNIFORM1IPROC, Uniform1i)                                                                     \
  X(PFNGLGENBUFFERSPROC, GenBuffers)                                                                   \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                                                             \
  X(PFNGLBINDBUFFERPROC, BindBuffer)                                                                   \
  X(PFNGLBINDBUFFERBASEPROC, BindBufferBase)                                                           \
  X(PFNGLBINDBUFFERRANGEPROC, BindBufferRange)                                                         \
  X(PFNGLBUFFERDATAPROC, BufferData)                                                                   \
  X(PFNGLBUFFERSUBDATAPROC, BufferSubData)                                                             \
  X(PFNGLMAPBUFFERRANGEPROC, MapBufferRange)                                                           \
  X(PFNGLUNMAPBUFFERPROC, UnmapBuffer)                                                                 \
  X(PFNGLDISPATCHCOMPUTEPROC, DispatchCompute)                                                         \
  X(PFNGLMEMORYBARRIERPROC, MemoryBarrier)                                                             \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                                                         \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                                                         \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                                                   \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                                                 \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)                                         \
  X(PFNGLGENTRANSFORMFEEDBACKSPROC, GenTransformFeedbacks)                                             \
  X(PFNGLBINDTRANSFORMFEEDBACKPROC, BindTransformFeedback)                                             \
  X(PFNGLDELETETRANSFORMFEEDBACKSPROC, DeleteTransformFeedbacks)                                       \
  X(PFNGLTRANSFORMFEEDBACKVARYINGSPROC, TransformFeedbackVaryings)                                     \
  X(PFNGLBEGINTRANSFORMFEEDBACKPROC, BeginTransformFeedback)                                           \
  X(PFNGLENDTRANSFORMFEEDBACKPROC, EndTransformFeedback)                                               \
  X(PFNGLDRAWARRAYSPROC, DrawArrays)                                                                   \
  X(PFNGLENABLEPROC, Enable)                                                                           \
  X(PFNGLDISABLEPROC, Disable)                                                                         \
  X(PFNGLISENABLEDPROC, IsEnabled)                                                                     \
  X(PFNGLUNIFORM3FVPROC, Uniform3fv)                                                                   \
  X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                                                         \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                                                         \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                                                   \
  X(PFNGLFRAMEBUFFERPARAMETERIPROC, FramebufferParameteri)

struct GlFunctions {
#define CAGEKIT_GL_MEMBER(type, name) type name = nullptr;
  CAGEKIT_GL_FUNCTIONS(CAGEKIT_GL_MEMBER)
#undef CAGEKIT_GL_MEMBER

  // Loads every entry point ("gl" + name); returns the names the callback did not provide.
  std::vector<std::string> load(GlGetProcAddress get_proc_address, void* user_data);
};

// The current context's version, parsed from GL_VERSION: "4.6 (Core Profile) Mesa ..." or
// "OpenGL ES 3.2 Mesa ...".
struct GlVersion {
  bool es = false;
  int major = 0, minor = 0;
  bool parsed = false;
  // Compute shaders and shader storage buffers are core: desktop GL >= 4.3 or GLES >= 3.1.
  bool has_compute() const;
};
GlVersion parse_gl_version(const char* version);

CAGEKIT_NAMESPACE_END
