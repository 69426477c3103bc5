// SPDX-License-Identifier: GPL-3.0-or-later
// PLY writer: binary little endian (default) or ascii. Positions are `property double x/y/z`
// so that binary output is exact; faces are `property list uchar int vertex_indices` (ushort or
// uint counts when a face has more than 255 / 65535 vertices). Tags are not written.
#include <algorithm>
#include <cstring>

#include "core/io/io_internal.h"
#include "core/io/text_writer.h"

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

namespace {

uint32_t max_face_size(const PolygonMesh& mesh) {
  uint32_t largest = 0;
  for (size_t f = 0; f < mesh.num_faces(); ++f) largest = std::max(largest, mesh.face_size(f));
  return largest;
}

int count_bytes_for(uint32_t largest_face) { return largest_face <= 0xFF ? 1 : (largest_face <= 0xFFFF ? 2 : 4); }

void write_header(const PolygonMesh& mesh, bool binary, int count_bytes, bool uint_indices, TextWriter& w) {
  w.text(binary ? "ply\nformat binary_little_endian 1.0\n" : "ply\nformat ascii 1.0\n");
  w.text("comment written by CageKit\nelement vertex ");
  w.uint(mesh.num_vertices());
  w.text("\nproperty double x\nproperty double y\nproperty double z\nelement face ");
  w.uint(mesh.num_faces());
  w.text("\nproperty list ");
  w.text(count_bytes == 1 ? "uchar" : (count_bytes == 2 ? "ushort" : "uint"));
  w.text(uint_indices ? " uint vertex_indices\nend_header\n" : " int vertex_indices\nend_header\n");
}

// Little-endian bytes whatever the host order.
void put_le(std::vector<uint8_t>& out, uint64_t bits, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(uint8_t(bits >> (8 * i)));
}

void put_double_le(std::vector<uint8_t>& out, double v) {
  uint64_t bits;
  std::memcpy(&bits, &v, sizeof(bits));
  put_le(out, bits, 8);
}

void write_binary_body(const PolygonMesh& mesh, int count_bytes, ProgressTicker& progress, std::vector<uint8_t>& out) {
  const double total = double(mesh.num_vertices() + mesh.num_faces());
  out.reserve(out.size() + mesh.num_vertices() * 24 + mesh.num_faces() * 4 + mesh.num_face_vertices() * 4);
  for (size_t v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3& p = mesh.positions[v];
    put_double_le(out, p.x);
    put_double_le(out, p.y);
    put_double_le(out, p.z);
    progress.tick(double(v) / total);
  }
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    put_le(out, mesh.face_size(f), count_bytes);
    const uint32_t* corner = mesh.face_begin(f);
    for (uint32_t k = 0; k < mesh.face_size(f); ++k) put_le(out, corner[k], 4);
    progress.tick(double(mesh.num_vertices() + f) / total);
  }
}


}  // namespace

double write_ply(const Cage& cage, const WriteOptions& options, const TaskMonitor& monitor,
                 std::vector<uint8_t>& out) {
  const PolygonMesh& mesh = cage.mesh;
  TextWriter w(out, options.obj_precision);
  ProgressTicker progress(monitor, "writing");
  const int count_bytes = count_bytes_for(max_face_size(mesh));
  const bool uint_indices = mesh.num_vertices() > 0x7FFFFFFFu;
  write_header(mesh, options.ply_binary, count_bytes, uint_indices, w);
  if (options.ply_binary) {
    write_binary_body(mesh, count_bytes, progress, out);
    return 0.0;  // doubles are written bit for bit
  }
  return write_ascii_vertices_and_faces(mesh, progress, w);
}

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
