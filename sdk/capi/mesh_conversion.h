// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Conversions between the C API's caller buffers/structs and the core types, shared by the
// mesh, cage and I/O entry points.
#include "capi/api_guard.h"

namespace cagekit_capi {

cagekit::PolygonMesh mesh_from_desc(const cagekit_mesh_desc& desc);
void copy_positions(const cagekit::PolygonMesh& mesh, cagekit_scalar_type type, void* out);
void copy_faces(const cagekit::PolygonMesh& mesh, uint32_t face_capacity, uint32_t* face_count_out,
                uint32_t* face_sizes, uint64_t index_capacity, uint64_t* index_count_out, uint32_t* face_indices);
// Statistics of `mesh`, with the tag counts of `tags` when it is a cage (tags->mesh == mesh).
void fill_info(const cagekit::PolygonMesh& mesh, const cagekit::Cage* tags, cagekit_mesh_info* info);
cagekit_mesh make_mesh_handle(cagekit_context context, cagekit::PolygonMesh mesh);
// The caller's control points (`control_count` xyz doubles) into `out`, checked: not NULL,
// exactly `expected` of them (the binding's cage), every coordinate finite. Used by the CPU and
// GL deformers' calls.
void read_control_points(const double* control, uint32_t control_count, uint32_t expected,
                         std::vector<cagekit::Vec3>& out);
// A scan to bind or to draw: every face index must name one of its vertices.
void require_scan_face_indices_in_range(const cagekit::PolygonMesh& scan);

}  // namespace cagekit_capi
