/*
 * CageKit — the GPU deformer inside a host's OpenGL / OpenGL ES context (opt-in).
 * SPDX-License-Identifier: GPL-3.0-or-later
 *
 * A graphics binding in the manner of OpenXR's: include this header next to <cagekit/cagekit.h>
 * only where the host draws with GL. It declares no GL types and needs no GL header: buffer
 * names are uint32_t and entry points come from the host's get-proc-address callback. The
 * conventions of <cagekit/cagekit.h> (handles, status codes, versioned structs) apply. C99.
 */
#ifndef CAGEKIT_CAGEKIT_GL_H
#define CAGEKIT_CAGEKIT_GL_H

#include <cagekit/cagekit.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------------------------ */
/* GPU deformer in the host's GL context (thesis §8.6)                                          */
/* ------------------------------------------------------------------------------------------ */

/* Deforms a bound scan on the GPU, inside the HOST's OpenGL (>= 4.3, core or compatibility) or
 * OpenGL ES (>= 3.1) context, as OpenXR's graphics bindings attach to a host context: the
 * library has no GL loader and no window system of its own; it reaches GL only through the
 * host's get-proc-address callback. The binding is uploaded once (float32); each deform call
 * uploads the control points and runs one compute dispatch that writes positions and
 * approximate normals (8.11)-(8.12) into a buffer object the host binds as vertex attributes;
 * the scan's triangles are in an element buffer reordered for vertex-cache locality (§8.6.4).
 *
 * Rules (as OpenSubdiv's GL evaluators):
 * - Every call, release included, must be made on the thread where the host's GL context (the
 *   one current at create, or one sharing its objects) is current. Not thread-safe otherwise.
 * - Every call restores the GL state it changes (current program, GL_SHADER_STORAGE_BUFFER
 *   generic and indexed 0..3 bindings, GL_COPY_READ_BUFFER / GL_COPY_WRITE_BUFFER bindings); no
 *   vertex-array object, GL_ARRAY_BUFFER or GL_ELEMENT_ARRAY_BUFFER binding is touched.
 * - create drains glGetError() first (errors the host had not read are discarded); deform,
 *   get_* and read_back never call glGetError.
 * - The GL buffer names belong to the deformer: the host may bind them and read them, not
 *   delete, resize or write them. They are deleted by the last release. */
typedef struct cagekit_gl_deformer_t* cagekit_gl_deformer;

/* A GL entry point as returned by eglGetProcAddress / glXGetProcAddress / wglGetProcAddress
 * (cast by the library to the function's real type). */
typedef void (*cagekit_gl_proc)(void);
/* The host's loader: the address of GL function `name` ("glDispatchCompute", ...) of its
 * current context, or NULL if it has none. Called only during cagekit_gl_deformer_create, on
 * the calling thread. On platforms where the window system's function does not return core
 * functions (WGL: GL 1.1 ones), the host resolves those itself. */
typedef cagekit_gl_proc (*cagekit_gl_get_proc_address_fn)(const char* name, void* user_data);

typedef struct cagekit_gl_deformer_options {
  size_t struct_size;                  /* sizeof(cagekit_gl_deformer_options) */
  cagekit_bool32 optimize_vertex_cache; /* 1 (default): reorder the triangles for the post-transform
                                          vertex cache (meshoptimizer); 0: keep the scan's order */
} cagekit_gl_deformer_options;

#define CAGEKIT_GL_DEFORMER_OPTIONS_INIT { sizeof(cagekit_gl_deformer_options), 1 }

/* Where the deformed vertices are, for glVertexAttribPointer / glDrawElements. Today positions
 * and normals are interleaved in one buffer (position_buffer == normal_buffer, stride 24), but
 * hosts should use the fields as given. Components are GL_FLOAT (0x1406), 3 per attribute;
 * indices are GL_UNSIGNED_INT (0x1405), GL_TRIANGLES, into the scan's vertex order. */
typedef struct cagekit_gl_deformer_buffers {
  size_t struct_size;                  /* sizeof(cagekit_gl_deformer_buffers) */
  uint32_t position_buffer;            /* GL buffer name */
  uint32_t position_offset;            /* bytes */
  uint32_t position_stride;            /* bytes */
  uint32_t normal_buffer;              /* GL buffer name; unit normals */
  uint32_t normal_offset;
  uint32_t normal_stride;
  uint32_t component_type;             /* GL_FLOAT */
  uint32_t vertex_count;               /* = the binding's vertex count */
  uint32_t index_buffer;               /* GL buffer name; 0 when created without a scan mesh */
  uint32_t index_count;                /* 3 per triangle (polygons fan-triangulated) */
  uint32_t index_type;                 /* GL_UNSIGNED_INT */
} cagekit_gl_deformer_buffers;

typedef struct cagekit_gl_deformer_info {
  size_t struct_size;                  /* sizeof(cagekit_gl_deformer_info) */
  const char* renderer;                /* GL_RENDERER and GL_VERSION at create: owned by the */
  const char* version;                 /* deformer, valid until its last release */
  cagekit_bool32 is_es;                /* 1: OpenGL ES context */
  uint32_t vertex_count;
  uint32_t control_count;
  uint32_t index_count;
  double acmr_before;                  /* average cache miss ratio (16-entry FIFO) of the scan's */
  double acmr_after;                   /* triangles as given and as uploaded */
  uint64_t gpu_bytes;                  /* bytes of GL buffer memory the deformer holds */
  uint32_t reference_floats_per_vertex; /* experimental reference mode (below): 16 + 3|Q| once a set
                                          is given (28 in the affine-frame variant), else 0 */
  uint32_t reference_max_edited;       /* experimental reference mode: the largest |Q|
                                          (GL_MAX_VERTEX_ATTRIBS - 5) */
} cagekit_gl_deformer_info;

/* Creates a GPU deformer of `binding` in the host's current GL context. `scan` (may be NULL:
 * no index buffer) supplies the triangles to draw; it must have the binding's vertex count (it
 * is normally the mesh the binding was made from). options may be NULL. On error no GL object
 * is left behind.
 * Ownership: *out receives one reference (release it with cagekit_gl_deformer_release); the
 *   deformer keeps `binding` alive; `scan` is read during the call only; get_proc_address is
 *   called during the call only (it and user_data are not kept).
 * Errors: INVALID_HANDLE (binding, or a non-NULL scan), INVALID_ARGUMENT (out or
 *   get_proc_address NULL, bad struct_size or option, a scan whose vertex count differs or with a
 *   face index out of range), INVALID_OPERATION (no GL context current), UNSUPPORTED_FEATURE (a
 *   context older than GL 4.3 / GLES 3.1, an entry point the callback does not provide, fewer
 *   than 4 compute shader storage blocks, or the shader does not compile: the message names what
 *   is missing), LIMIT_EXCEEDED (a buffer above GL_MAX_SHADER_STORAGE_BLOCK_SIZE, too many
 *   vertices for the work-group limits), OUT_OF_MEMORY (host memory or GL_OUT_OF_MEMORY).
 * Threading: GL thread only (see above); reads `binding` and `scan`. */
CAGEKIT_API cagekit_status cagekit_gl_deformer_create(cagekit_binding binding, cagekit_mesh scan,
                                                      cagekit_gl_get_proc_address_fn get_proc_address,
                                                      void* user_data, const cagekit_gl_deformer_options* options,
                                                      cagekit_gl_deformer* out);
/* Adds a reference. NULL is ignored.
 * Errors: none.
 * Threading: GL thread only (see above). */
CAGEKIT_API void cagekit_gl_deformer_retain(cagekit_gl_deformer deformer);
/* Drops a reference. The last release deletes the GL objects and drops the deformer's reference
 * to its binding. NULL is ignored.
 * Errors: none.
 * Threading: GL thread only: the host's context must be current on the calling thread at the last
 *   release (releasing after the context is destroyed leaks nothing on the CPU side but is
 *   undefined on the GL side, as for any GL object). */
CAGEKIT_API void cagekit_gl_deformer_release(cagekit_gl_deformer deformer);

/* Recomputes every vertex: `control` holds control_count xyz triples (the cage's vertices,
 * moved; converted to float). Only CAGEKIT_NORMALS_APPROXIMATE is done on the GPU. The result
 * is in the buffers of cagekit_gl_deformer_get_buffers, ready for vertex fetch (a memory
 * barrier is issued); GL commands are queued, not waited for.
 * Ownership: `control` is read during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (control NULL, control_count not the binding's, a
 *   non-finite control point, a normals_mode out of range), UNSUPPORTED_FEATURE (normals_mode
 *   CAGEKIT_NORMALS_EXACT), OUT_OF_MEMORY.
 * Threading: GL thread only; modifies the deformer. */
CAGEKIT_API cagekit_status cagekit_gl_deformer_deform(cagekit_gl_deformer deformer, const double* control,
                                                      uint32_t control_count, cagekit_normal_mode normals_mode);

/* The GL names and layout of the output and index buffers (fixed for the deformer's life).
 * Ownership: the GL buffers belong to the deformer (see above).
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (buffers NULL or bad struct_size).
 * Threading: GL thread only (see above); reads the deformer. Makes no GL call. */
CAGEKIT_API cagekit_status cagekit_gl_deformer_get_buffers(cagekit_gl_deformer deformer,
                                                           cagekit_gl_deformer_buffers* buffers);
/* Fills *info: the GL context's renderer and version, counts, cache figures and GL memory.
 * Ownership: info->renderer and info->version are owned by the deformer, valid until its last
 *   release.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (info NULL or bad struct_size).
 * Threading: GL thread only (see above); reads the deformer. Makes no GL call. */
CAGEKIT_API cagekit_status cagekit_gl_deformer_get_info(cagekit_gl_deformer deformer, cagekit_gl_deformer_info* info);

/* Copies the last deform's result to the CPU (waits for the GPU; for tests and tools, not for
 * drawing): positions and normals receive an xyz triple per vertex. Two-call (cagekit.h,
 * Buffers) over the vertices, shared by positions and normals (either may be NULL); with
 * vertex_capacity 0 only *vertex_count_out is written and no GL call is made. Before a first
 * deform the contents are undefined.
 * Ownership: positions and normals are the caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (vertex_count_out NULL), SIZE_INSUFFICIENT, INTERNAL
 *   (the buffer could not be mapped), OUT_OF_MEMORY.
 * Threading: GL thread only; modifies the deformer (its read-back copy): one thread at a time. */
CAGEKIT_API cagekit_status cagekit_gl_deformer_read_back(cagekit_gl_deformer deformer, uint32_t vertex_capacity,
                                                         uint32_t* vertex_count_out, double* positions,
                                                         double* normals);

/* ------------------------------------------------------------------------------------------ */
/* Rendering a scene in the host's GL context                                                 */
/* ------------------------------------------------------------------------------------------ */

/* Draws `scene` (cagekit.h, "Rendering") in the HOST's current OpenGL (>= 3.3, core or
 * compatibility) or OpenGL ES (>= 3.0) context instead of a headless one, and copies the image
 * into `rgba` as cagekit_render_scene_draw does (width x height pixels of 4 bytes, rows top
 * first; two-call over pixels; with pixel_capacity 0 no GL call is made). The library draws into
 * a framebuffer object of its own (RGBA8 + 24-bit depth renderbuffers), with programs, vertex
 * arrays and buffers made and deleted within the call, and reads it back with glReadPixels.
 * Every piece of GL state it changes is restored before it returns: current program, vertex
 * array, GL_ARRAY_BUFFER, GL_PIXEL_PACK_BUFFER, draw and read framebuffer and renderbuffer
 * bindings, viewport, scissor box, the enables GL_DEPTH_TEST, GL_CULL_FACE, GL_BLEND,
 * GL_SCISSOR_TEST, GL_STENCIL_TEST, GL_POLYGON_OFFSET_FILL, GL_DITHER, GL_RASTERIZER_DISCARD,
 * depth func and mask, colour mask, polygon offset, clear colour and depth, and the pack
 * parameters (alignment, row length, skip pixels / rows). The call drains glGetError() first
 * (errors the host had not read are discarded).
 * Ownership: `rgba` is the caller's, written during the call only; get_proc_address and
 *   user_data are used during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (get_proc_address NULL, pixel_count_out NULL, rgba
 *   NULL with a nonzero capacity), SIZE_INSUFFICIENT, INVALID_OPERATION (no GL context current),
 *   UNSUPPORTED_FEATURE (a context older than GL 3.3 / GLES 3.0, an entry point the callback does
 *   not provide, or a shader that does not compile: the message names it; also in builds without
 *   the render module), LIMIT_EXCEEDED (an image above the context's framebuffer limits),
 *   OUT_OF_MEMORY (GL_OUT_OF_MEMORY).
 * Threading: on the thread where the host's context is current; reads `scene`. */
CAGEKIT_API cagekit_status cagekit_gl_render_scene_draw(cagekit_render_scene scene,
                                                        cagekit_gl_get_proc_address_fn get_proc_address,
                                                        void* user_data, uint32_t pixel_capacity,
                                                        uint32_t* pixel_count_out, uint8_t* rgba);

/* ------------------------------------------------------------------------------------------ */
/* Experimental: the thesis's vertex-attribute path                                           */
/* ------------------------------------------------------------------------------------------ */

/* Declared only when the host defines CAGEKIT_ENABLE_EXPERIMENTAL before including this header.
 * These calls are outside the stable contract: they may change or go in any minor version.
 * They reproduce the thesis's measurements; hosts draw with cagekit_gl_deformer_deform, which
 * is faster and has no limit on the number of edited points. */
#if defined(CAGEKIT_ENABLE_EXPERIMENTAL)

/* The thesis's own GPU path (§8.6 (a)-(c)): all data
 * as vertex attributes — 16 + 3|Q| floats per vertex for the set Q of edited control points (the
 * 7 displacement / normal coefficients, the part of S, S_u, S_v of the points outside Q, and
 * phi, phi_u, phi_v of each point of Q) — and a vertex program generated for |Q|, whose
 * output goes through transform feedback into the same buffer as cagekit_gl_deformer_deform's.
 * set_reference_set defines Q (`edited`, edited_count distinct indices, 1 ..
 * info.reference_max_edited: 11 with the GL minimum of 16 attributes) and the positions of the
 * other control points (`control`, control_count xyz triples); it rebuilds the attribute
 * buffer (as the thesis does whenever Q changes). deform_reference then reads only the points
 * of Q from `control` (3|Q| floats uploaded as uniforms per frame); the others must still equal
 * those given to set_reference_set. Normal displacement mode only (a binding made with
 * CAGEKIT_DISPLACEMENT_NORMAL); approximate normals.
 * Ownership: the arrays are read during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (NULL arrays, counts, an index out of range or
 *   repeated, a non-finite point), INVALID_OPERATION (a local-frame binding, deform_reference
 *   before a set), UNSUPPORTED_FEATURE (the program does not build), OUT_OF_MEMORY.
 * Threading: GL thread only; modifies the deformer. They change no GL state of the host (also
 *   restored: vertex array, GL_ARRAY_BUFFER, transform feedback object and buffer binding,
 *   GL_RASTERIZER_DISCARD). */
CAGEKIT_API cagekit_status cagekit_gl_deformer_set_reference_set(cagekit_gl_deformer deformer, const uint32_t* edited,
                                                                 uint32_t edited_count, const double* control,
                                                                 uint32_t control_count);
CAGEKIT_API cagekit_status cagekit_gl_deformer_deform_reference(cagekit_gl_deformer deformer, const double* control,
                                                                uint32_t control_count);
/* The affine-frame variant of the reference mode (§8.6.2 (b), after Botsch & Kobbelt 2004):
 * every point of Q moves by one affine map, given by where it takes four frame points.
 * set_reference_affine: Q = `edited` (edited_count distinct indices, any number), `frame` the 12
 * coordinates of the frame points q_0..q_3 (not coplanar) in the pose of `control` (control_count
 * xyz triples, all control points). Each point of Q is written c_j = sum_l xi_jl q_l (8.13), so
 * the per-vertex data is 28 floats whatever |Q| (7 coefficients, 9 fixed, 3 x 4 combined
 * weights). deform_reference_affine then uploads only the 4 moved frame points (`frame`, 12
 * numbers). Normal displacement mode only.
 * Ownership: the arrays are read during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (NULL arrays, counts, an index out of range or
 *   repeated, a non-finite or coplanar frame), INVALID_OPERATION (a local-frame binding,
 *   deform_reference_affine before a set_reference_affine), UNSUPPORTED_FEATURE, OUT_OF_MEMORY.
 * Threading: GL thread only; modifies the deformer. The host's GL state is left unchanged. */
CAGEKIT_API cagekit_status cagekit_gl_deformer_set_reference_affine(cagekit_gl_deformer deformer,
                                                                    const uint32_t* edited, uint32_t edited_count,
                                                                    const double* frame, const double* control,
                                                                    uint32_t control_count);
CAGEKIT_API cagekit_status cagekit_gl_deformer_deform_reference_affine(cagekit_gl_deformer deformer,
                                                                       const double* frame);

#endif /* CAGEKIT_ENABLE_EXPERIMENTAL */

#ifdef __cplusplus
}
#endif

#endif /* CAGEKIT_CAGEKIT_GL_H */
