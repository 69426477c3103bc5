// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// GlDeformer: the GPU deformer of a bound scan in the HOST's GL context (thesis §8.6; the
// modern SSBO/compute path of spec §3.2). Created while the host's context is current, with the
// host's get-proc-address callback; the binding is converted to float32 buffers and uploaded
// once; deform() uploads the control points (3 floats each) and runs one compute dispatch that
// writes positions and approximate normals (8.11)-(8.12) — normal (8.1) or local-frame
// displacement — interleaved into one buffer object the host binds as vertex attributes; the
// scan's triangles are in an element buffer reordered for vertex-cache locality (§8.6.4,
// meshoptimizer). Every GL call restores the bindings it changes (GlStateGuard).
//
// Thread-safety: only on the thread where the host's context is current; the context (or one
// sharing its objects) must be current for every call, the destructor included.
#include <cstdint>
#include <string>
#include <vector>

#include "gpu/gl_functions.h"
#include "multires/scan_binding.h"

CAGEKIT_NAMESPACE_BEGIN

struct GlDeformerOptions {
  bool optimize_vertex_cache = true;  // reorder the triangles (meshopt_optimizeVertexCache)
};

class GlDeformer {
 public:
  // Output layout: per vertex position xyz then normal xyz, float32, 24-byte stride.
  static constexpr uint32_t kStride = 24, kPositionOffset = 0, kNormalOffset = 12;

  // `triangles`: 3 vertex indices each (< binding.num_vertices()); may be empty (no index
  // buffer). Throws Error: invalid_operation (no context current), unsupported_feature (the
  // context lacks GL >= 4.3 / GLES >= 3.1, an entry point, a limit, or the shader does not
  // compile), limit_exceeded (a buffer larger than
  // the context's GL_MAX_SHADER_STORAGE_BLOCK_SIZE), out_of_memory (GL_OUT_OF_MEMORY),
  // invalid_argument (bad binding / triangles). No GL object is left behind on failure.
  // The binding must outlive the deformer (the reference mode reads it again).
  GlDeformer(const ScanBinding& binding, const std::vector<uint32_t>& triangles, GlGetProcAddress get_proc_address,
             void* user_data, const GlDeformerOptions& options = {});
  ~GlDeformer();
  GlDeformer(const GlDeformer&) = delete;
  GlDeformer& operator=(const GlDeformer&) = delete;

  // `control`: 3 * control_count() floats. Writes the output buffer (visible to vertex
  // attribute fetches, shader storage reads and buffer mapping after the call).
  void deform(const float* control);
  // The thesis's reference mode (§8.6 (a), spec §2.6): per vertex 16 + 3|Q| floats of vertex
  // attributes — D and the six normal coefficients (7), the part of S, S_u, S_v of the control
  // points outside Q (9, computed here in double from `control`), and (phi, phi_u, phi_v) of
  // each point of Q (3|Q|, zero where a vertex does not depend on it) — and a vertex program
  // generated for |Q| that rebuilds position and approximate normal; its output goes through
  // transform feedback into the same output buffer as deform()'s. `edited` = Q, 1..max
  // distinct control indices (max: GL_MAX_VERTEX_ATTRIBS - 5, 11 with the minimum 16). Normal
  // displacement mode only (the thesis's). Throws invalid_argument, unsupported_feature.
  void set_reference_set(const std::vector<uint32_t>& edited, const float* control);
  // Per frame: uploads the |Q| points of `control` (3 * control_count() floats; the others must
  // equal those given to set_reference_set) as uniforms and draws. Throws invalid_operation
  // before a set_reference_set.
  void deform_reference(const float* control);
  // The affine-frame variant (§8.6.2 (b), after [BK04]): every point c_j of Q moves by one
  // affine map given by where it takes four frame points q_0..q_3 (`frame`: 12 numbers, not
  // coplanar). With c_j = sum_l xi_jl q_l (8.13) the dynamic attributes are the 4 combined
  // weights (sum_j xi_jl phi_j, ...) — 28 floats per vertex whatever |Q| — and a frame uploads
  // the 4 moved frame points (12 floats) with deform_reference_affine. `edited` may then hold
  // any number of distinct control points. Throws invalid_argument, unsupported_feature.
  void set_reference_affine(const std::vector<uint32_t>& edited, const double frame[12], const float* control);
  void deform_reference_affine(const double frame[12]);
  uint32_t reference_floats_per_vertex() const { return reference_q_.empty() ? 0 : 16 + 3 * uint32_t(reference_slots_); }
  uint32_t reference_max_edited() const;

  // Copies the output buffer (6 floats per vertex) into `interleaved` (maps it for reading).
  void read_back(float* interleaved) const;

  uint32_t output_buffer() const { return output_; }
  uint32_t index_buffer() const { return index_; }
  uint32_t vertex_count() const { return vertex_count_; }
  uint32_t control_count() const { return control_count_; }
  uint32_t index_count() const { return index_count_; }
  const std::string& renderer() const { return renderer_; }
  const std::string& version() const { return version_string_; }
  bool is_es() const { return version_.es; }
  // Average cache miss ratio (transformed vertices per triangle, 16-entry FIFO) of the index
  // buffer as given and as uploaded.
  double acmr_before() const { return acmr_before_; }
  double acmr_after() const { return acmr_after_; }
  // Bytes of GL buffer memory held (binding data + control + output + indices).
  uint64_t gpu_bytes() const { return gpu_bytes_; }

 private:
  // The constructor's steps, after the binding's validation.
  void load_functions(GlGetProcAddress get_proc_address, void* user_data);
  void query_limits(size_t n);
  std::vector<uint32_t> reorder_triangles(const std::vector<uint32_t>& triangles, bool optimize);
  void check_buffer_sizes(size_t entries) const;
  void create_objects(const std::vector<uint32_t>& vertex_words, const std::vector<uint32_t>& entry_words,
                      const std::vector<uint32_t>& indices);
  void release() noexcept;
  uint32_t make_buffer(const void* data, size_t bytes, uint32_t usage);
  void compile_program();
  // The reference attributes: Q = `edited`, `slots` dynamic attributes, point k of Q weighing
  // into slot l by mix[k * slots + l].
  void build_reference(const std::vector<uint32_t>& edited, const std::vector<double>& mix, size_t slots,
                       const float* control);
  void draw_reference();

  const ScanBinding& binding_;
  GlFunctions gl_;
  // Reference mode.
  std::vector<uint32_t> reference_q_;
  size_t reference_slots_ = 0;     // dynamic attributes: |Q|, or 4 in the affine variant
  bool reference_affine_ = false;
  uint32_t reference_program_ = 0, reference_vao_ = 0, reference_attributes_ = 0, reference_feedback_ = 0;
  uint32_t reference_framebuffer_ = 0;  // 1x1, no attachments: draws need a complete framebuffer
  int32_t reference_q_location_ = -1, max_vertex_attributes_ = 0;
  uint64_t reference_bytes_ = 0;
  std::vector<float> reference_uniforms_;
  GlVersion version_;
  std::string renderer_, version_string_;
  bool local_frame_ = false;
  uint32_t vertex_count_ = 0, control_count_ = 0, index_count_ = 0;
  uint32_t program_ = 0, control_ = 0, entries_ = 0, vertices_ = 0, output_ = 0, index_ = 0;
  int32_t count_location_ = -1, mode_location_ = -1;
  double acmr_before_ = 0, acmr_after_ = 0;
  uint64_t gpu_bytes_ = 0;
  int64_t max_block_size_ = 0;
  int32_t max_groups_x_ = 0, max_groups_y_ = 0;
};

CAGEKIT_NAMESPACE_END
