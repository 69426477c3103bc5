// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer harness: the Draco reader (cagekit::read_cage_from_memory, FileFormat::draco) on
// both plain triangle-mesh streams and CageKit cage streams (cagekit.* metadata, order blob).
#include "fuzz_reader_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return cagekit_fuzz::read_one(data, size, cagekit::FileFormat::draco);
}
