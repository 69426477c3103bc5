// SPDX-License-Identifier: GPL-3.0-or-later
// Multiresolution editing (thesis ch. 8): binding handles and CPU deformers.
#include <algorithm>

#include "capi/api_guard.h"
#include "capi/mesh_conversion.h"
#include "capi/option_conversion.h"
#include "capi/option_rules.h"
#include "multires/deformer_vertex_order.h"

using namespace cagekit_capi;

cagekit_cpu_deformer_t::cagekit_cpu_deformer_t(cagekit_context c, cagekit_binding_t* b, int threads)
    : ContextBound(kType, c), binding(b), deformer(b->binding, threads) {
  retain_handle(binding);
}

cagekit_cpu_deformer_t::~cagekit_cpu_deformer_t() { release_handle(binding); }

namespace {

cagekit::NormalMode checked_normal_mode(const cagekit_normal_mode& mode) {
  const int32_t raw = raw_enum(mode);
  if (raw != CAGEKIT_NORMALS_APPROXIMATE && raw != CAGEKIT_NORMALS_EXACT)
    fail(Status::invalid_argument, "normals_mode is not a cagekit_normal_mode");
  return raw == CAGEKIT_NORMALS_EXACT ? cagekit::NormalMode::exact : cagekit::NormalMode::approximate;
}

void read_control(cagekit_cpu_deformer_t& d, const double* control, uint32_t control_count) {
  read_control_points(control, control_count, d.binding->binding.num_control_vertices, d.control);
}

// The deformers' outputs (two-call over the bound vertices). False for a capacity of 0: the call
// is a query of the count, and deforms nothing.
bool check_outputs(const cagekit_cpu_deformer_t& d, uint32_t capacity, uint32_t* count_out, const void* positions,
                   const void* normals) {
  return two_call_check("vertex", static_cast<uint32_t>(d.binding->binding.num_vertices()), capacity, count_out,
                        {{"positions", positions}, {"normals", normals}});
}

// deform / deform_f32: straight into the caller's xyz triples (T = double or float).
template <typename T>
cagekit_status deform_into(cagekit_cpu_deformer deformer, const double* control, uint32_t control_count,
                           cagekit_normal_mode normals_mode, uint32_t vertex_capacity, uint32_t* vertex_count_out,
                           T* positions, T* normals) {
  return guarded(context_of(deformer), [&] {
    cagekit_cpu_deformer_t& d = checked(deformer, "deformer");
    if (!check_outputs(d, vertex_capacity, vertex_count_out, positions, normals)) return;
    const cagekit::NormalMode mode = checked_normal_mode(normals_mode);
    read_control(d, control, control_count);
    d.deformed = false;
    d.deformer.deform(d.control, positions, normals, mode);
    d.deformed = true;
    d.exact = mode == cagekit::NormalMode::exact;
  });
}

template <typename T>
cagekit_status update_into(cagekit_cpu_deformer deformer, const double* control, uint32_t control_count,
                           const uint32_t* moved, uint32_t moved_count, cagekit_normal_mode normals_mode,
                           uint32_t vertex_capacity, uint32_t* vertex_count_out, T* positions, T* normals,
                           uint32_t* updated_count) {
  return guarded(context_of(deformer), [&] {
    cagekit_cpu_deformer_t& d = checked(deformer, "deformer");
    if (!check_outputs(d, vertex_capacity, vertex_count_out, positions, normals)) return;
    const cagekit::NormalMode mode = checked_normal_mode(normals_mode);
    if (!d.deformed) fail(Status::invalid_operation, "cagekit_cpu_deformer_update before a first successful deform");
    if ((mode == cagekit::NormalMode::exact) != d.exact)
      fail(Status::invalid_operation, "normals_mode differs from the last deform's");
    if (moved_count > 0) require_not_null(moved, "moved");
    read_control(d, control, control_count);
    const std::vector<uint32_t> moved_list(moved, moved + moved_count);
    for (uint32_t j : moved_list)
      if (j >= control_count) fail(Status::invalid_argument, "moved index " + std::to_string(j) + " is out of range");
    // The deformer's own copy of the control points is the reference for the deltas: only the
    // listed points are read (the header documents that the others must be unchanged).
    d.deformer.update(d.control, moved_list, positions, normals, mode);
    if (updated_count) *updated_count = static_cast<uint32_t>(d.deformer.last_updated().size());
  });
}

}  // namespace

extern "C" {

CAGEKIT_API cagekit_status cagekit_multires_bind(cagekit_cage cage, cagekit_mesh scan,
                                                 const cagekit_bind_options* options, cagekit_binding* out) {
  return create_from(cage, "cage", out, [&](cagekit_cage_t& c) {
    cagekit_mesh_t& m = checked(scan, "scan");
    const cagekit::BindOptions bo = bind_options_from_c(options);
    require_scan_face_indices_in_range(m.mesh);
    cagekit::ScanBinding binding = cagekit::bind_scan_to_cage(c.cage, m.mesh, bo, c.context->monitor());
    return std::make_unique<cagekit_binding_t>(c.context, std::move(binding), c.cage, bo);
  });
}

CAGEKIT_API void cagekit_binding_retain(cagekit_binding binding) { retain_handle(binding); }
CAGEKIT_API void cagekit_binding_release(cagekit_binding binding) { release_handle(binding); }

CAGEKIT_API cagekit_status cagekit_binding_get_info(cagekit_binding binding, cagekit_binding_info* info) {
  return guarded(context_of(binding), [&] {
    const cagekit::ScanBinding& b = checked(binding, "binding").binding;
    require_not_null(info, "info");
    cagekit_binding_info out{};
    out.struct_size = sizeof(out);
    out.vertex_count = static_cast<uint32_t>(b.num_vertices());
    out.control_count = b.num_control_vertices;
    out.basis_entries = b.num_entries();
    out.max_sideways_residual = b.max_sideways_residual;
    out.vertices_with_sideways_residual = b.vertices_with_sideways_residual;
    out.bbox_diagonal = b.bbox_diagonal;
    out.has_exact_normals = b.phi_uu.size() == b.num_entries() && !b.displacement_gradient.empty();
    out.deform_bytes_per_vertex = cagekit::deform_bytes_per_vertex(b);
    out.compact_cells = static_cast<uint32_t>(b.compact.num_cells());
    out.irregular_vertices = static_cast<uint32_t>(b.compact.num_irregular_vertices());
    out.has_sector_split = b.source_vertex.empty() ? 0 : 1;
    out.scan_vertex_count = static_cast<uint32_t>(b.source_vertex.empty() ? b.num_vertices() : b.scan_vertex_count);
    write_versioned(info, out, "cagekit_binding_info");
  });
}

CAGEKIT_API cagekit_status cagekit_binding_get_vertex_sources(cagekit_binding binding, uint32_t vertex_capacity,
                                                              uint32_t* vertex_count_out, uint32_t* sources) {
  return guarded(context_of(binding), [&] {
    const cagekit::ScanBinding& b = checked(binding, "binding").binding;
    const uint32_t n = static_cast<uint32_t>(b.num_vertices());
    if (!two_call_check("vertex", n, vertex_capacity, vertex_count_out, {{"sources", sources}})) return;
    for (uint32_t i = 0; i < n; ++i) sources[i] = b.source_vertex.empty() ? i : b.source_vertex[i];
  });
}

CAGEKIT_API cagekit_status cagekit_binding_get_deformer_vertex_order(cagekit_binding binding, uint32_t vertex_capacity,
                                                                     uint32_t* vertex_count_out, uint32_t* order) {
  return guarded(context_of(binding), [&] {
    const cagekit::ScanBinding& b = checked(binding, "binding").binding;
    require_not_null(vertex_count_out, "vertex_count_out");  // before the order is computed
    const std::vector<uint32_t> o = cagekit::deformer_vertex_order(b);
    if (!two_call_check("vertex", static_cast<uint32_t>(o.size()), vertex_capacity, vertex_count_out,
                        {{"order", order}}))
      return;
    std::copy(o.begin(), o.end(), order);
  });
}

CAGEKIT_API cagekit_status cagekit_binding_get_faces(cagekit_binding binding, uint32_t face_capacity,
                                                     uint32_t* face_count_out, uint32_t* face_sizes,
                                                     uint64_t index_capacity, uint64_t* index_count_out,
                                                     uint32_t* face_indices) {
  return guarded(context_of(binding), [&] {
    const cagekit::ScanBinding& b = checked(binding, "binding").binding;
    cagekit::PolygonMesh faces;  // without a split: no faces (the scan's own apply)
    if (!b.source_vertex.empty()) faces.face_offsets = b.face_offsets, faces.face_vertices = b.face_vertices;
    copy_faces(faces, face_capacity, face_count_out, face_sizes, index_capacity, index_count_out, face_indices);
  });
}

CAGEKIT_API cagekit_status cagekit_cpu_deformer_create(cagekit_binding binding, uint32_t threads,
                                                       cagekit_cpu_deformer* out) {
  return create_from(binding, "binding", out, [&](cagekit_binding_t& b) {
    apply(kThreads, threads, "threads", threads);
    return std::make_unique<cagekit_cpu_deformer_t>(b.context, &b, int(threads));
  });
}

CAGEKIT_API void cagekit_cpu_deformer_retain(cagekit_cpu_deformer deformer) { retain_handle(deformer); }
CAGEKIT_API void cagekit_cpu_deformer_release(cagekit_cpu_deformer deformer) { release_handle(deformer); }

CAGEKIT_API cagekit_status cagekit_cpu_deformer_deform(cagekit_cpu_deformer deformer, const double* control,
                                                       uint32_t control_count, cagekit_normal_mode normals_mode,
                                                       uint32_t vertex_capacity, uint32_t* vertex_count_out,
                                                       double* positions, double* normals) {
  return deform_into(deformer, control, control_count, normals_mode, vertex_capacity, vertex_count_out, positions,
                     normals);
}

CAGEKIT_API cagekit_status cagekit_cpu_deformer_deform_f32(cagekit_cpu_deformer deformer, const double* control,
                                                           uint32_t control_count, cagekit_normal_mode normals_mode,
                                                           uint32_t vertex_capacity, uint32_t* vertex_count_out,
                                                           float* positions, float* normals) {
  return deform_into(deformer, control, control_count, normals_mode, vertex_capacity, vertex_count_out, positions,
                     normals);
}

CAGEKIT_API cagekit_status cagekit_cpu_deformer_update(cagekit_cpu_deformer deformer, const double* control,
                                                       uint32_t control_count, const uint32_t* moved,
                                                       uint32_t moved_count, cagekit_normal_mode normals_mode,
                                                       uint32_t vertex_capacity, uint32_t* vertex_count_out,
                                                       double* positions, double* normals, uint32_t* updated_count) {
  return update_into(deformer, control, control_count, moved, moved_count, normals_mode, vertex_capacity,
                     vertex_count_out, positions, normals, updated_count);
}

CAGEKIT_API cagekit_status cagekit_cpu_deformer_update_f32(cagekit_cpu_deformer deformer, const double* control,
                                                           uint32_t control_count, const uint32_t* moved,
                                                           uint32_t moved_count, cagekit_normal_mode normals_mode,
                                                           uint32_t vertex_capacity, uint32_t* vertex_count_out,
                                                           float* positions, float* normals, uint32_t* updated_count) {
  return update_into(deformer, control, control_count, moved, moved_count, normals_mode, vertex_capacity,
                     vertex_count_out, positions, normals, updated_count);
}

}  // extern "C"
