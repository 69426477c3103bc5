// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer harness: the PLY reader (cagekit::read_cage_from_memory, FileFormat::ply).
#include "fuzz_reader_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return cagekit_fuzz::read_one(data, size, cagekit::FileFormat::ply);
}
