// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer harness: the STL reader, binary and ascii (cagekit::read_cage_from_memory,
// FileFormat::stl), including the binary-or-ascii decision and the corner welding.
#include "fuzz_reader_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return cagekit_fuzz::read_one(data, size, cagekit::FileFormat::stl);
}
