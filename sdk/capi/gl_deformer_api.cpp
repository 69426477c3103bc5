// SPDX-License-Identifier: GPL-3.0-or-later
// GPU deformer in the host's GL context (thesis §8.6): the C shim over gpu/GlDeformer.
#include <memory>

#define CAGEKIT_ENABLE_EXPERIMENTAL  // defines the experimental reference mode too
#include <cagekit/cagekit_gl.h>

#include "capi/api_guard.h"
#include "capi/mesh_conversion.h"
#include "capi/option_conversion.h"
#include "gpu/gl_deformer.h"

using namespace cagekit_capi;

// Keeps its binding alive (a reference). Defined here rather than in handles.h: only this file
// uses it. The destructor deletes the GL objects (the host's context must be current).
struct cagekit_gl_deformer_t : ContextBound {
  static constexpr HandleType kType = static_cast<HandleType>(0x474c4431);  // "GLD1"
  cagekit_gl_deformer_t(cagekit_context c, cagekit_binding_t* b, std::unique_ptr<cagekit::GlDeformer> d)
      : ContextBound(kType, c), binding(b), deformer(std::move(d)) {
    retain_handle(binding);
  }
  ~cagekit_gl_deformer_t() override {
    deformer.reset();
    release_handle(binding);
  }
  cagekit_binding_t* binding;
  std::unique_ptr<cagekit::GlDeformer> deformer;
  std::vector<float> control, read_back;
  std::vector<cagekit::Vec3> control_points;  // the last call's, before the conversion to float
};

namespace {

static_assert(GL_FLOAT == 0x1406 && GL_UNSIGNED_INT == 0x1405, "the header documents these values");

// The polygons of `mesh`, fan-triangulated.
std::vector<uint32_t> triangles_of(const cagekit::PolygonMesh& mesh) {
  std::vector<uint32_t> out;
  size_t count = 0;
  for (size_t f = 0; f < mesh.num_faces(); ++f) count += mesh.face_size(f) >= 3 ? 3 * (mesh.face_size(f) - 2) : 0;
  out.reserve(count);
  for (size_t f = 0; f < mesh.num_faces(); ++f)
    mesh.for_each_fan_triangle(f, [&](uint32_t a, uint32_t b, uint32_t c) { out.insert(out.end(), {a, b, c}); });
  return out;
}

// The caller's control points as floats, checked.
void read_control(cagekit_gl_deformer_t& d, const double* control, uint32_t control_count) {
  read_control_points(control, control_count, d.deformer->control_count(), d.control_points);
  d.control.resize(3 * d.control_points.size());
  for (size_t j = 0; j < d.control_points.size(); ++j)
    for (int i = 0; i < 3; ++i) d.control[3 * j + size_t(i)] = static_cast<float>(d.control_points[j][i]);
}

}  // namespace

extern "C" {

CAGEKIT_API cagekit_status cagekit_gl_deformer_create(cagekit_binding binding, cagekit_mesh scan,
                                                      cagekit_gl_get_proc_address_fn get_proc_address,
                                                      void* user_data, const cagekit_gl_deformer_options* options,
                                                      cagekit_gl_deformer* out) {
  return create_from(binding, "binding", out, [&](cagekit_binding_t& b) {
    if (get_proc_address == nullptr) fail(Status::invalid_argument, "get_proc_address must not be NULL");
    const cagekit::GlDeformerOptions go = gl_deformer_options_from_c(options);
    std::vector<uint32_t> triangles;
    if (scan != nullptr) {
      const cagekit_mesh_t& m = checked(scan, "scan");
      if (m.mesh.num_vertices() != b.binding.num_vertices())
        fail(Status::invalid_argument, "scan has " + std::to_string(m.mesh.num_vertices()) + " vertices but the binding " +
                                           std::to_string(b.binding.num_vertices()));
      require_scan_face_indices_in_range(m.mesh);
      triangles = triangles_of(m.mesh);
    }
    auto deformer = std::make_unique<cagekit::GlDeformer>(
        b.binding, triangles, reinterpret_cast<cagekit::GlGetProcAddress>(get_proc_address), user_data, go);
    return std::make_unique<cagekit_gl_deformer_t>(b.context, &b, std::move(deformer));
  });
}

CAGEKIT_API void cagekit_gl_deformer_retain(cagekit_gl_deformer deformer) { retain_handle(deformer); }
CAGEKIT_API void cagekit_gl_deformer_release(cagekit_gl_deformer deformer) { release_handle(deformer); }

CAGEKIT_API cagekit_status cagekit_gl_deformer_deform(cagekit_gl_deformer deformer, const double* control,
                                                      uint32_t control_count, cagekit_normal_mode normals_mode) {
  return guarded(context_of(deformer), [&] {
    cagekit_gl_deformer_t& d = checked(deformer, "deformer");
    const int32_t mode = raw_enum(normals_mode);
    if (mode == CAGEKIT_NORMALS_EXACT)
      fail(Status::unsupported_feature, "the GL deformer computes approximate normals only (exact normals: use the CPU "
                                       "deformer)");
    if (mode != CAGEKIT_NORMALS_APPROXIMATE) fail(Status::invalid_argument, "normals_mode is not a cagekit_normal_mode");
    read_control(d, control, control_count);
    d.deformer->deform(d.control.data());
  });
}

CAGEKIT_API cagekit_status cagekit_gl_deformer_set_reference_set(cagekit_gl_deformer deformer, const uint32_t* edited,
                                                                 uint32_t edited_count, const double* control,
                                                                 uint32_t control_count) {
  return guarded(context_of(deformer), [&] {
    cagekit_gl_deformer_t& d = checked(deformer, "deformer");
    if (edited_count > 0) require_not_null(edited, "edited");
    read_control(d, control, control_count);
    d.deformer->set_reference_set(std::vector<uint32_t>(edited, edited + edited_count), d.control.data());
  });
}

CAGEKIT_API cagekit_status cagekit_gl_deformer_deform_reference(cagekit_gl_deformer deformer, const double* control,
                                                                uint32_t control_count) {
  return guarded(context_of(deformer), [&] {
    cagekit_gl_deformer_t& d = checked(deformer, "deformer");
    read_control(d, control, control_count);
    d.deformer->deform_reference(d.control.data());
  });
}

CAGEKIT_API cagekit_status cagekit_gl_deformer_set_reference_affine(cagekit_gl_deformer deformer,
                                                                    const uint32_t* edited, uint32_t edited_count,
                                                                    const double* frame, const double* control,
                                                                    uint32_t control_count) {
  return guarded(context_of(deformer), [&] {
    cagekit_gl_deformer_t& d = checked(deformer, "deformer");
    if (edited_count > 0) require_not_null(edited, "edited");
    require_not_null(frame, "frame");
    read_control(d, control, control_count);
    d.deformer->set_reference_affine(std::vector<uint32_t>(edited, edited + edited_count), frame, d.control.data());
  });
}

CAGEKIT_API cagekit_status cagekit_gl_deformer_deform_reference_affine(cagekit_gl_deformer deformer,
                                                                       const double* frame) {
  return guarded(context_of(deformer), [&] {
    cagekit_gl_deformer_t& d = checked(deformer, "deformer");
    require_not_null(frame, "frame");
    d.deformer->deform_reference_affine(frame);
  });
}

CAGEKIT_API cagekit_status cagekit_gl_deformer_get_buffers(cagekit_gl_deformer deformer,
                                                           cagekit_gl_deformer_buffers* buffers) {
  return guarded(context_of(deformer), [&] {
    const cagekit::GlDeformer& d = *checked(deformer, "deformer").deformer;
    require_not_null(buffers, "buffers");
    cagekit_gl_deformer_buffers out{};
    out.struct_size = sizeof(out);
    out.position_buffer = out.normal_buffer = d.output_buffer();
    out.position_offset = cagekit::GlDeformer::kPositionOffset;
    out.normal_offset = cagekit::GlDeformer::kNormalOffset;
    out.position_stride = out.normal_stride = cagekit::GlDeformer::kStride;
    out.component_type = GL_FLOAT;
    out.vertex_count = d.vertex_count();
    out.index_buffer = d.index_buffer();
    out.index_count = d.index_count();
    out.index_type = GL_UNSIGNED_INT;
    write_versioned(buffers, out, "cagekit_gl_deformer_buffers");
  });
}

CAGEKIT_API cagekit_status cagekit_gl_deformer_get_info(cagekit_gl_deformer deformer, cagekit_gl_deformer_info* info) {
  return guarded(context_of(deformer), [&] {
    const cagekit::GlDeformer& d = *checked(deformer, "deformer").deformer;
    require_not_null(info, "info");
    cagekit_gl_deformer_info out{};
    out.struct_size = sizeof(out);
    out.renderer = d.renderer().c_str();
    out.version = d.version().c_str();
    out.is_es = d.is_es() ? 1 : 0;
    out.vertex_count = d.vertex_count();
    out.control_count = d.control_count();
    out.index_count = d.index_count();
    out.acmr_before = d.acmr_before();
    out.acmr_after = d.acmr_after();
    out.gpu_bytes = d.gpu_bytes();
    out.reference_floats_per_vertex = d.reference_floats_per_vertex();
    out.reference_max_edited = d.reference_max_edited();
    write_versioned(info, out, "cagekit_gl_deformer_info");
  });
}

CAGEKIT_API cagekit_status cagekit_gl_deformer_read_back(cagekit_gl_deformer deformer, uint32_t vertex_capacity,
                                                         uint32_t* vertex_count_out, double* positions,
                                                         double* normals) {
  return guarded(context_of(deformer), [&] {
    cagekit_gl_deformer_t& d = checked(deformer, "deformer");
    const uint32_t n = d.deformer->vertex_count();
    if (!two_call_check("vertex", n, vertex_capacity, vertex_count_out,
                        {{"positions", positions}, {"normals", normals}}))
      return;
    if (!positions && !normals) return;  // nothing wanted: no wait for the GPU
    d.read_back.resize(6 * size_t(n));
    d.deformer->read_back(d.read_back.data());
    for (size_t i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) {
        if (positions) positions[3 * i + k] = d.read_back[6 * i + k];
        if (normals) normals[3 * i + k] = d.read_back[6 * i + 3 + k];
      }
  });
}

}  // extern "C"
