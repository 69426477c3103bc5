// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A 5x7 bitmap font compiled into the library (CageKit's own glyphs; no font file, no font
// library): digits, capital letters (lower case is drawn as upper case) and the punctuation
// labels need. Drawn on the CPU into an RGBA8 image, top row first.
#include <cstdint>
#include <string>

#include "core/namespace.h"

CAGEKIT_NAMESPACE_BEGIN

constexpr int kGlyphWidth = 5, kGlyphHeight = 7, kGlyphAdvance = 6;

// The 7 rows of `c`'s glyph, bit 4 = leftmost column; characters without a glyph draw as '?'.
const uint8_t* glyph_rows(char c);

// Width in pixels of `text` at `scale` (kGlyphAdvance * scale per character, less the last gap).
int text_width(const std::string& text, int scale);

// Draws `text` with its top-left corner at (x, y) in a width x height RGBA8 image (rows top
// first), clipped to the image.
void draw_text(uint8_t* rgba, int width, int height, int x, int y, const std::string& text, int scale,
               const uint8_t color[4]);

CAGEKIT_NAMESPACE_END
