// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer harness: the Draco reader (cagekit::read_cage_from_memory, FileFormat::draco) on
// both plain triangle-mesh streams and CageKit cage streams (cagekit.* metadata, order blob).
#include "fuzz_reader_common.h"

// Smaller limits than the other readers'. The reader checks the triangle and vertex counts a
// stream declares before libdraco allocates for them, but libdraco then sizes each attribute
// from the point count and the attribute's declared components and type (up to 255 x 8 bytes per
// point) before reading its values, and those declarations come after the connectivity. At the
// shared 2^20 limits one such allocation can pass libFuzzer's 2 GB malloc limit; at 2^16
// triangles and vertices (at most 2^16 + 3 x 2^16 points) it stays near 0.5 GB. Hosts bound it
// with ReadOptions and the context's memory budget (std::bad_alloc becomes out_of_memory).
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  cagekit::ReadOptions options = cagekit_fuzz::fuzz_read_options();
  options.max_vertices = 1u << 16;
  options.max_faces = 1u << 16;
  return cagekit_fuzz::read_one(data, size, cagekit::FileFormat::draco, options);
}
