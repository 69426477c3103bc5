// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Whole files as bytes: reading, and writing atomically (a temporary file beside the target,
// renamed over it only on success, so a failed write never leaves a partial file). Used by the
// mesh readers/writers and by other layers' file formats (e.g. the saved scan binding).
// Errors: Status::io_error with the path and the OS reason.
#include <cstdint>
#include <string>
#include <vector>

#include "core/namespace.h"

CAGEKIT_NAMESPACE_BEGIN

std::vector<uint8_t> read_whole_file(const std::string& path);
void write_file_atomically(const std::string& path, const std::vector<uint8_t>& bytes);

CAGEKIT_NAMESPACE_END
