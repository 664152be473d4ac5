#pragma once
/// A 5×7 pixel font for labels on pictures the farm writes (the contact sheet): digits and the
/// few signs a frame number and a time need. Drawn by code, so no font file or library.
#include <cstdint>
#include <string>
#include <vector>

namespace rf::farm {

/// Glyph cell: 5 × 7 pixels plus one column of spacing.
inline constexpr int kGlyphW = 5, kGlyphH = 7, kGlyphAdvance = 6;

/// Whether `c` has a glyph: 0-9 . : s f # - and space.
bool hasGlyph(char c);

/// Draws text into an RGB image (3 bytes a pixel, row stride width) at (x, y), each font pixel
/// a scale × scale block; clipped at the image's edges. Characters without a glyph are skipped.
void drawText(std::vector<uint8_t>& rgb, int width, int height, int x, int y, const std::string& text, int scale,
              const uint8_t color[3]);

/// Width in pixels of text drawn at scale.
int textWidth(const std::string& text, int scale);

}  // namespace rf::farm
