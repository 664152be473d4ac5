#include "farm/output/bitmap_font.h"

namespace rf::farm {

namespace {

struct Glyph {
    char c;
    uint8_t rows[kGlyphH];  ///< bit 4 is the leftmost column
};

// Drawn for this file on a 5×7 grid, in the common style of LCD digits.
constexpr Glyph kGlyphs[] = {
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}},
    {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}},
    {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}},
    {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}},
    {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}},
    {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}},
    {':', {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00}},
    {'s', {0x00, 0x00, 0x0E, 0x10, 0x0E, 0x01, 0x1E}},
    {'f', {0x06, 0x09, 0x08, 0x1C, 0x08, 0x08, 0x08}},
    {'#', {0x0A, 0x0A, 0x1F, 0x0A, 0x1F, 0x0A, 0x0A}},
    {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}},
    {' ', {0, 0, 0, 0, 0, 0, 0}},
};

const Glyph* find(char c) {
    for (const Glyph& g : kGlyphs)
        if (g.c == c) return &g;
    return nullptr;
}

}  // namespace

bool hasGlyph(char c) { return find(c) != nullptr; }

int textWidth(const std::string& text, int scale) {
    int n = 0;
    for (char c : text) n += hasGlyph(c);
    return n == 0 ? 0 : (n * kGlyphAdvance - 1) * scale;
}

void drawText(std::vector<uint8_t>& rgb, int width, int height, int x, int y, const std::string& text, int scale,
              const uint8_t color[3]) {
    for (char c : text) {
        const Glyph* g = find(c);
        if (!g) continue;
        for (int gy = 0; gy < kGlyphH; ++gy)
            for (int gx = 0; gx < kGlyphW; ++gx) {
                if (!(g->rows[gy] >> (kGlyphW - 1 - gx) & 1)) continue;
                for (int sy = 0; sy < scale; ++sy)
                    for (int sx = 0; sx < scale; ++sx) {
                        const int px = x + gx * scale + sx, py = y + gy * scale + sy;
                        if (px < 0 || py < 0 || px >= width || py >= height) continue;
                        uint8_t* p = &rgb[3 * (size_t(py) * width + px)];
                        p[0] = color[0];
                        p[1] = color[1];
                        p[2] = color[2];
                    }
            }
        x += kGlyphAdvance * scale;
    }
}

}  // namespace rf::farm
