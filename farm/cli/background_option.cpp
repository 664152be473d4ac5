#include "farm/cli/background_option.h"

#include <cmath>
#include <sstream>

#include "farm/cli/cli.h"
#include "engine/util/image.h"

namespace rf::cli {

namespace {

int hexDigit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

}  // namespace

BackgroundChoice parseBackground(const std::string& text) {
    const UsageError bad("--background: expected transparent, #RRGGBB or R,G,B (linear, ≥ 0), got \"" + text + "\"");
    BackgroundChoice c;
    if (text == "transparent") {
        c.kind = BackgroundChoice::Transparent;
        return c;
    }
    float v[3] = {0.f, 0.f, 0.f};
    if (!text.empty() && text[0] == '#') {
        if (text.size() != 7) throw bad;
        for (int k = 0; k < 3; ++k) {
            const int hi = hexDigit(text[1 + 2 * k]), lo = hexDigit(text[2 + 2 * k]);
            if (hi < 0 || lo < 0) throw bad;
            v[k] = srgbDecode(float(hi * 16 + lo) / 255.f);
        }
    } else {
        std::istringstream in(text);
        for (int k = 0; k < 3; ++k) {
            char comma = ',';
            if ((k > 0 && !(in >> comma)) || comma != ',' || !(in >> v[k]) || !std::isfinite(v[k]) || v[k] < 0.f) throw bad;
        }
        if (!in.eof() && in.peek() != EOF) throw bad;
    }
    c.kind = BackgroundChoice::Colour;
    c.r = v[0];
    c.g = v[1];
    c.b = v[2];
    return c;
}

}  // namespace rf::cli
