// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Shared by the reader harnesses: read the bytes as a cage of one format; a reader may fail
// (cagekit::Error) but must never crash, and what it returns must be structurally sound.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/cage.h"
#include "core/io/mesh_io.h"
#include "core/mesh_validation.h"
#include "core/status.h"

namespace cagekit_fuzz {

// Small limits so a 64 KiB input cannot ask for gigabytes (the readers must honour them).
inline cagekit::ReadOptions fuzz_read_options() {
  cagekit::ReadOptions options;
  options.max_vertices = 1u << 20;
  options.max_faces = 1u << 20;
  options.max_face_size = 1u << 12;
  return options;
}

#define CAGEKIT_FUZZ_CHECK(cond) \
  do {                           \
    if (!(cond)) __builtin_trap(); \
  } while (0)

// Indices in range, offsets well formed, tags in range: what every reader promises.
inline void check_cage_structure(const cagekit::Cage& cage) {
  const cagekit::PolygonMesh& mesh = cage.mesh;
  CAGEKIT_FUZZ_CHECK(!mesh.face_offsets.empty());
  CAGEKIT_FUZZ_CHECK(mesh.face_offsets[0] == 0);
  for (size_t f = 0; f + 1 < mesh.face_offsets.size(); ++f)
    CAGEKIT_FUZZ_CHECK(mesh.face_offsets[f] <= mesh.face_offsets[f + 1]);
  CAGEKIT_FUZZ_CHECK(mesh.face_offsets.back() == mesh.face_vertices.size());
  const size_t nv = mesh.num_vertices();
  for (uint32_t v : mesh.face_vertices) CAGEKIT_FUZZ_CHECK(v < nv);
  for (const cagekit::Vec3& p : mesh.positions)
    CAGEKIT_FUZZ_CHECK(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
  for (const cagekit::EdgeCrease& c : cage.creases) {
    CAGEKIT_FUZZ_CHECK(c.v0 < nv && c.v1 < nv);
    CAGEKIT_FUZZ_CHECK(!std::isnan(c.sharpness));
  }
  for (const cagekit::VertexCorner& c : cage.corners) {
    CAGEKIT_FUZZ_CHECK(c.vertex < nv);
    CAGEKIT_FUZZ_CHECK(!std::isnan(c.sharpness));
  }
  for (uint32_t h : cage.holes) CAGEKIT_FUZZ_CHECK(h < mesh.num_faces());
  // Must not throw on a well-formed mesh; the report itself may list any issue.
  const cagekit::ValidationReport report = cagekit::validate_cage(cage, 4);
  (void)report.ok();
}

inline int read_one(const uint8_t* data, size_t size, cagekit::FileFormat format,
                    const cagekit::ReadOptions& options = fuzz_read_options()) {
  cagekit::Cage cage;
  try {
    cage = cagekit::read_cage_from_memory(data, size, format, "<fuzz>", options);
  } catch (const cagekit::Error&) {
    return 0;  // rejected input: fine
  }
  check_cage_structure(cage);
  return 0;
}

}  // namespace cagekit_fuzz
