// Internal: a 5x7 dot font for the labels and the colour bar's numbers.
//
// Written by hand rather than rasterized with FreeType: a font file would
// become a run-time dependency of a library that otherwise needs none, and
// the picture needs only file names and numbers: printable ASCII, and the
// few other characters this project's own labels use (°, ×, −, µ). Text is
// UTF-8; every other character is drawn as one '?'.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "detexture/render/render_point_cloud.h"

namespace detexture::render_detail {

constexpr int kGlyphWidth = 5;    ///< dots
constexpr int kGlyphHeight = 7;   ///< dots
constexpr int kGlyphAdvance = 6;  ///< dots from one character to the next
/// g, p, q and y are drawn this many dots lower, their tails below the
/// baseline: a line of text is kGlyphHeight + kGlyphDescent dots high.
constexpr int kGlyphDescent = 2;

/// The characters of UTF-8 text, one per code point. A malformed sequence
/// (a lead byte and the continuation bytes after it) becomes one U+FFFD, and
/// so does each stray continuation byte.
std::u32string code_points(const std::string& utf8);

/// The 7 rows of 5 characters ('#' = dot, '.' = none) of character c. Every
/// printable ASCII character has one, and so do °, ×, − and µ; others
/// (control characters, other scripts) get the glyph of '?'.
const std::array<const char*, kGlyphHeight>& glyph(char32_t c);

/// Width in pixels of UTF-8 text drawn with dots of scale x scale pixels.
int text_width(const std::string& text, int scale);

/// g, p, q, y, µ: drawn kGlyphDescent dots lower than the others.
bool has_descender(char32_t c);

/// Draw UTF-8 text with its top left corner at (x, y), dots of scale x scale
/// pixels, clipped to the columns [clip_x0, clip_x1) and to the image.
void draw_text(Image& image, int x, int y, const std::string& text, int scale,
               const std::array<std::uint8_t, 3>& color, int clip_x0, int clip_x1);

}  // namespace detexture::render_detail
