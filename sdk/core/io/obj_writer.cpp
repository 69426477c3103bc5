// SPDX-License-Identifier: GPL-3.0-or-later
// OBJ writer: "v x y z" with obj_precision significant digits, "f a b c ..." (1-based) and the
// OpenSubdiv-style tag lines of obj_tags.h.
#include <algorithm>

#include "core/io/io_internal.h"
#include "core/io/obj_tags.h"
#include "core/io/text_writer.h"

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

double write_obj(const Cage& cage, const WriteOptions& options, const TaskMonitor& monitor,
                 std::vector<uint8_t>& out) {
  const PolygonMesh& mesh = cage.mesh;
  TextWriter w(out, options.obj_precision);
  ProgressTicker progress(monitor, "writing");
  const double total = static_cast<double>(mesh.num_vertices() + mesh.num_faces());
  out.reserve(mesh.num_vertices() * 40 + mesh.num_face_vertices() * 8 + 256);

  w.text("# CageKit OBJ: ");
  w.uint(mesh.num_vertices());
  w.text(" vertices, ");
  w.uint(mesh.num_faces());
  w.text(" faces\n");
  double error = 0;
  for (size_t v = 0; v < mesh.num_vertices(); ++v) {
    w.text("v ");
    error = std::max(error, w.point(mesh.positions[v]));
    w.ch('\n');
    progress.tick(static_cast<double>(v) / total);
  }
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    w.ch('f');
    const uint32_t* corner = mesh.face_begin(f);
    for (uint32_t k = 0; k < mesh.face_size(f); ++k) {
      w.ch(' ');
      w.uint(uint64_t(corner[k]) + 1);
    }
    w.ch('\n');
    progress.tick(static_cast<double>(mesh.num_vertices() + f) / total);
  }
  write_obj_tags(cage, w);
  return error;
}

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
