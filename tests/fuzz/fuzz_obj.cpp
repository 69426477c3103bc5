// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer harness: the OBJ reader (cagekit::read_cage_from_memory, FileFormat::obj),
// including the `t crease` / `t corner` / `t hole` tag lines.
#include "fuzz_reader_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return cagekit_fuzz::read_one(data, size, cagekit::FileFormat::obj);
}
