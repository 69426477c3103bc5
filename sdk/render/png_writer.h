// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// PNG encoding of an RGBA8 image (rows top first) through libpng, into memory or a file. Only
// this module links libpng. Deterministic: the same pixels give the same bytes (no time chunk).
#include <cstdint>
#include <string>
#include <vector>

#include "core/namespace.h"

CAGEKIT_NAMESPACE_BEGIN

std::vector<uint8_t> encode_png(const uint8_t* rgba, int width, int height);
// Errors: Error(io) naming the path when it cannot be written.
void write_png_file(const std::string& path, const uint8_t* rgba, int width, int height);

CAGEKIT_NAMESPACE_END
