// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Private to sdk/core/io: how a cage is stored in a Draco (.drc) mesh.
//
// Draco stores triangles and reorders points and faces while encoding. CageKit writes:
//   * the polygons as fans from their first corner (face f, corners c0..ck-1 -> triangles
//     (c0, c[i+1], c[i+2]) for i = 0..k-3), in face order;
//   * a GENERIC uint32 point attribute whose attribute metadata has name = "cagekit_vertex_id":
//     the original index of the vertex each point came from;
//   * geometry metadata (all optional except the version):
//       cagekit.version            int   1
//       cagekit.boundary           int   BoundaryRule value (0 edges only, 1 edges and corners)
//       cagekit.crease_vertices    int[] v0 v1 v0 v1 ... (original vertex indices, as uint32 bits)
//       cagekit.crease_sharpness   double[] one per crease
//       cagekit.corner_vertices    int[]    cagekit.corner_sharpness double[]
//       cagekit.holes              int[] face indices
//       cagekit.isolated_positions double[] x y z of each vertex no face uses (edgebreaker drops
//                                  them), in increasing vertex index order
//       cagekit.order              binary: the DracoOrder below, so that the original polygon
//                                  list (sizes, order, first corners) is rebuilt exactly.
// A file without cagekit.version is read as a plain triangle mesh.
#include <cstdint>
#include <string>
#include <vector>

#include "core/io/mesh_io.h"

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

inline constexpr const char* kDracoVertexIdName = "cagekit_vertex_id";
inline constexpr const char* kDracoVersionKey = "cagekit.version";
inline constexpr const char* kDracoBoundaryKey = "cagekit.boundary";
inline constexpr const char* kDracoCreaseVerticesKey = "cagekit.crease_vertices";
inline constexpr const char* kDracoCreaseSharpnessKey = "cagekit.crease_sharpness";
inline constexpr const char* kDracoCornerVerticesKey = "cagekit.corner_vertices";
inline constexpr const char* kDracoCornerSharpnessKey = "cagekit.corner_sharpness";
inline constexpr const char* kDracoHolesKey = "cagekit.holes";
inline constexpr const char* kDracoOrderKey = "cagekit.order";
inline constexpr const char* kDracoIsolatedPositionsKey = "cagekit.isolated_positions";
inline constexpr int kDracoLayoutVersion = 1;

// How the decoded triangles map back to the original polygons. "Original triangle t" is the
// t-th fan triangle when the polygons' fans are listed in face order.
struct DracoOrder {
  uint32_t num_vertices = 0;
  uint32_t num_faces = 0;
  uint32_t num_triangles = 0;
  std::vector<uint32_t> face_sizes;         // empty: every face is a triangle
  std::vector<uint32_t> original_triangle;  // per decoded triangle; empty: identity
  std::vector<uint32_t> rotation;           // per decoded triangle, 0..2; empty: all 0
};

std::vector<uint8_t> encode_draco_order(const DracoOrder& order);

// Decodes and checks an order blob against what was decoded (num_triangles) and the limits.
// Returns Status::success, or parse_error (malformed, inconsistent) / limit_exceeded with `error`.
Status decode_draco_order(const std::vector<uint8_t>& blob, uint32_t decoded_triangles, const ReadOptions& limits,
                          DracoOrder& order, std::string& error);

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
