// SPDX-License-Identifier: GPL-3.0-or-later
// Mesh handles: creation from caller buffers, read-back, validation, repair, statistics.

#include "capi/api_guard.h"
#include "capi/mesh_conversion.h"
#include "capi/option_conversion.h"
#include "capi/report_conversion.h"
#include "core/mesh_repair.h"
#include "core/mesh_statistics.h"
#include "core/mesh_validation.h"

using namespace cagekit_capi;

namespace cagekit_capi {

cagekit::PolygonMesh mesh_from_desc(const cagekit_mesh_desc& d) {
  constexpr uint64_t kMaxIndices = uint64_t(1) << 31;
  if (d.vertex_count > 0 && d.positions == nullptr)
    fail(Status::invalid_argument, "cagekit_mesh_desc.positions is NULL but vertex_count is " +
                                       std::to_string(d.vertex_count));
  if (raw_enum(d.position_type) != CAGEKIT_SCALAR_FLOAT32 && raw_enum(d.position_type) != CAGEKIT_SCALAR_FLOAT64)
    fail(Status::invalid_argument, "cagekit_mesh_desc.position_type is not a cagekit_scalar_type");
  const size_t scalar = d.position_type == CAGEKIT_SCALAR_FLOAT32 ? sizeof(float) : sizeof(double);
  const size_t stride = d.position_stride == 0 ? 3 * scalar : d.position_stride;
  if (stride < 3 * scalar)
    fail(Status::invalid_argument, "cagekit_mesh_desc.position_stride " + std::to_string(stride) +
                                       " is smaller than one xyz triple");
  if (d.vertex_count >= kMaxIndices || d.face_count >= kMaxIndices)
    fail(Status::limit_exceeded, "more than 2^31 vertices or faces");

  uint64_t index_count = 0;
  if (d.face_sizes) {
    for (uint32_t f = 0; f < d.face_count; ++f) {
      if (d.face_sizes[f] == 0) fail(Status::invalid_argument, "face " + std::to_string(f) + " has size 0");
      index_count += d.face_sizes[f];
    }
  } else {
    if (d.face_count > 0 && d.uniform_face_size == 0)
      fail(Status::invalid_argument, "cagekit_mesh_desc.face_sizes is NULL and uniform_face_size is 0");
    index_count = uint64_t(d.face_count) * d.uniform_face_size;
  }
  if (index_count >= kMaxIndices) fail(Status::limit_exceeded, "2^31 or more face indices");
  if (index_count > 0 && d.face_indices == nullptr)
    fail(Status::invalid_argument, "cagekit_mesh_desc.face_indices is NULL but faces were given");

  cagekit::PolygonMesh mesh;
  mesh.reserve(d.vertex_count, d.face_count, index_count);
  const auto* bytes = static_cast<const unsigned char*>(d.positions);
  for (uint32_t v = 0; v < d.vertex_count; ++v) {
    const unsigned char* p = bytes + size_t(v) * stride;
    double xyz[3];
    for (int k = 0; k < 3; ++k) {
      if (d.position_type == CAGEKIT_SCALAR_FLOAT32) {
        float value;
        std::memcpy(&value, p + k * sizeof(float), sizeof(float));
        xyz[k] = value;
      } else {
        std::memcpy(&xyz[k], p + k * sizeof(double), sizeof(double));
      }
    }
    mesh.add_vertex({xyz[0], xyz[1], xyz[2]});
  }
  mesh.face_vertices.assign(d.face_indices, d.face_indices + index_count);
  mesh.face_offsets.resize(size_t(d.face_count) + 1);
  uint32_t offset = 0;
  for (uint32_t f = 0; f < d.face_count; ++f) {
    offset += d.face_sizes ? d.face_sizes[f] : d.uniform_face_size;
    mesh.face_offsets[f + 1] = offset;
  }
  return mesh;
}

void copy_positions(const cagekit::PolygonMesh& mesh, cagekit_scalar_type type, void* out) {
  for (size_t v = 0; v < mesh.num_vertices(); ++v)
    for (int k = 0; k < 3; ++k) {
      if (type == CAGEKIT_SCALAR_FLOAT32)
        static_cast<float*>(out)[3 * v + k] = static_cast<float>(mesh.positions[v][k]);
      else
        static_cast<double*>(out)[3 * v + k] = mesh.positions[v][k];
    }
}

void copy_faces(const cagekit::PolygonMesh& mesh, uint32_t face_capacity, uint32_t* face_count_out,
                uint32_t* face_sizes, uint64_t index_capacity, uint64_t* index_count_out, uint32_t* face_indices) {
  const auto faces = static_cast<uint32_t>(mesh.num_faces());
  const uint64_t indices = mesh.num_face_vertices();
  // Both counts are reported before any capacity check fails.
  write_count("face", faces, face_count_out);
  write_count("index", indices, index_count_out);
  const bool fill_sizes = two_call_check("face", faces, face_capacity, face_count_out, {{"face_sizes", face_sizes}});
  const bool fill_indices =
      two_call_check("index", indices, index_capacity, index_count_out, {{"face_indices", face_indices}});
  if (fill_sizes)
    for (uint32_t f = 0; f < faces; ++f) face_sizes[f] = mesh.face_size(f);
  if (fill_indices) std::copy(mesh.face_vertices.begin(), mesh.face_vertices.end(), face_indices);
}

void fill_info(const cagekit::PolygonMesh& mesh, const cagekit::Cage* tags, cagekit_mesh_info* info) {
  require_not_null(info, "info");
  const cagekit::MeshStatistics s = tags ? cagekit::compute_mesh_statistics(*tags) : cagekit::compute_mesh_statistics(mesh);
  const cagekit_mesh_info out = mesh_info_to_c(s);
  write_versioned(info, out, "cagekit_mesh_info");
}

cagekit_mesh make_mesh_handle(cagekit_context context, cagekit::PolygonMesh mesh) {
  return std::make_unique<cagekit_mesh_t>(context, std::move(mesh)).release();
}

}  // namespace cagekit_capi

namespace cagekit_capi {

void read_control_points(const double* control, uint32_t control_count, uint32_t expected,
                         std::vector<cagekit::Vec3>& out) {
  require_not_null(control, "control");
  if (control_count != expected)
    fail(Status::invalid_argument, "control_count is " + std::to_string(control_count) + " but the binding's cage has " +
                                       std::to_string(expected) + " vertices");
  out.resize(expected);
  for (uint32_t j = 0; j < expected; ++j) {
    const cagekit::Vec3 p{control[3 * size_t(j)], control[3 * size_t(j) + 1], control[3 * size_t(j) + 2]};
    if (!cagekit::is_finite(p)) fail(Status::invalid_argument, "control point " + std::to_string(j) + " is not finite");
    out[j] = p;
  }
}

void require_scan_face_indices_in_range(const cagekit::PolygonMesh& scan) {
  for (uint32_t v : scan.face_vertices)
    if (v >= scan.num_vertices()) fail(Status::invalid_argument, "the scan has a face index out of range");
}

}  // namespace cagekit_capi

extern "C" {

CAGEKIT_API cagekit_status cagekit_mesh_create(cagekit_context context, const cagekit_mesh_desc* desc,
                                               cagekit_mesh* out) {
  return guarded(is_live(context) ? context : nullptr, [&] {
    require_not_null(out, "out");
    *out = nullptr;
    checked(context, "context");
    require_not_null(desc, "desc");
    cagekit_mesh_desc defaults = CAGEKIT_MESH_DESC_INIT;
    *out = make_mesh_handle(context, mesh_from_desc(read_versioned(desc, defaults, "cagekit_mesh_desc")));
  });
}

CAGEKIT_API void cagekit_mesh_retain(cagekit_mesh mesh) { retain_handle(mesh); }
CAGEKIT_API void cagekit_mesh_release(cagekit_mesh mesh) { release_handle(mesh); }

CAGEKIT_API cagekit_status cagekit_mesh_get_counts(cagekit_mesh mesh, uint32_t* vertex_count, uint32_t* face_count,
                                                   uint64_t* face_index_count) {
  return guarded(context_of(mesh), [&] {
    const cagekit::PolygonMesh& m = checked(mesh, "mesh").mesh;
    if (vertex_count) *vertex_count = static_cast<uint32_t>(m.num_vertices());
    if (face_count) *face_count = static_cast<uint32_t>(m.num_faces());
    if (face_index_count) *face_index_count = m.num_face_vertices();
  });
}

CAGEKIT_API cagekit_status cagekit_mesh_get_positions(cagekit_mesh mesh, cagekit_scalar_type type,
                                                      uint32_t vertex_capacity, uint32_t* vertex_count_out,
                                                      void* positions) {
  return guarded(context_of(mesh), [&] {
    const cagekit::PolygonMesh& m = checked(mesh, "mesh").mesh;
    if (raw_enum(type) != CAGEKIT_SCALAR_FLOAT32 && raw_enum(type) != CAGEKIT_SCALAR_FLOAT64)
      fail(Status::invalid_argument, "type is not a cagekit_scalar_type");
    if (two_call_check("vertex", static_cast<uint32_t>(m.num_vertices()), vertex_capacity, vertex_count_out,
                       {{"positions", positions}}))
      copy_positions(m, type, positions);
  });
}

CAGEKIT_API cagekit_status cagekit_mesh_get_faces(cagekit_mesh mesh, uint32_t face_capacity, uint32_t* face_count_out,
                                                  uint32_t* face_sizes, uint64_t index_capacity,
                                                  uint64_t* index_count_out, uint32_t* face_indices) {
  return guarded(context_of(mesh), [&] {
    copy_faces(checked(mesh, "mesh").mesh, face_capacity, face_count_out, face_sizes, index_capacity,
               index_count_out, face_indices);
  });
}

CAGEKIT_API cagekit_status cagekit_mesh_validate(cagekit_mesh mesh, cagekit_validation_report* report) {
  return guarded(context_of(mesh), [&] {
    const cagekit::ValidationReport r = cagekit::validate_mesh(checked(mesh, "mesh").mesh);
    if (report) {
      cagekit_validation_report out{};
      out.struct_size = sizeof(out);
      out.valid = r.ok() ? 1 : 0;
      out.issue_flags = r.flags();
      for (int k = 0; k < CAGEKIT_ISSUE_KIND_COUNT; ++k) out.issue_counts[k] = r.counts[k];
      write_versioned(report, out, "cagekit_validation_report");
    }
    if (!r.ok()) fail(Status::invalid_mesh, r.summary());
  });
}

CAGEKIT_API cagekit_status cagekit_mesh_repair(cagekit_mesh mesh, const cagekit_repair_options* options,
                                               cagekit_mesh* out, cagekit_repair_report* report) {
  return create_from(mesh, "mesh", out, [&](cagekit_mesh_t& m) {
    const cagekit::RepairOptions ro = repair_options_from_c(options);
    cagekit::RepairReport rr;
    cagekit::PolygonMesh repaired = cagekit::repair_mesh(m.mesh, ro, &rr, m.context->monitor());
    if (report) {
      const cagekit_repair_report r = repair_report_to_c(rr);
      write_versioned(report, r, "cagekit_repair_report");
    }
    return make_mesh_handle(m.context, std::move(repaired));
  });
}

CAGEKIT_API cagekit_status cagekit_mesh_get_info(cagekit_mesh mesh, cagekit_mesh_info* info) {
  return guarded(context_of(mesh), [&] {
    fill_info(checked(mesh, "mesh").mesh, nullptr, info);
  });
}

}  // extern "C"
