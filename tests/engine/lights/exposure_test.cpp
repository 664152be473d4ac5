// Exposure and tone mapping: Khronos PBR Neutral's closed form, the 2^EV scale, and the meter
// that picks one EV for a film.
#include <gtest/gtest.h>

#include "engine/lights/exposure.h"
#include "engine/util/image.h"

using namespace rf;

TEST(PbrNeutral, LeavesMidtonesAloneButForTheBlackOffset) {
    // Below the 0.76 knee only the offset (0.04 once the darkest channel passes 0.08) applies.
    const Color c = pbrNeutral(Color(0.5f, 0.3f, 0.1f));
    EXPECT_NEAR(c.r, 0.46f, 1e-6f);
    EXPECT_NEAR(c.g, 0.26f, 1e-6f);
    EXPECT_NEAR(c.b, 0.06f, 1e-6f);
    // Near black the offset is x − 6.25x², leaving 6.25x²: black stays black, smoothly.
    EXPECT_EQ(pbrNeutral(Color(0.f)), Color(0.f));
    EXPECT_NEAR(pbrNeutral(Color(0.04f)).r, 6.25f * 0.04f * 0.04f, 1e-7f);
}

TEST(PbrNeutral, RollsWhiteOffToTheClosedForm) {
    // White 1: offset 0.04, peak 0.96, new peak 1 − 0.24²/(0.96 + 0.24 − 0.76).
    const float want = 1.f - 0.24f * 0.24f / 0.44f;
    const Color c = pbrNeutral(Color(1.f));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], want, 1e-6f);
    EXPECT_NEAR(pbrNeutral(Color(1e6f)).r, 1.f, 1e-5f);
}

TEST(PbrNeutral, IsMonotoneAndStaysInRange) {
    float last = -1.f;
    for (float x = 0.f; x < 50.f; x += 0.01f) {
        const float y = pbrNeutral(Color(x, 0.5f * x, 0.25f * x)).r;
        EXPECT_GE(y, last) << x;
        EXPECT_LE(y, 1.f) << x;
        last = y;
    }
}

TEST(PbrNeutral, NonFiniteInputsGiveBlackOrWhite) {
    const float inf = std::numeric_limits<float>::infinity();
    const Color a = pbrNeutral(Color(std::nanf(""), -3.f, 0.f));
    EXPECT_EQ(a, Color(0.f));
    const Color b = pbrNeutral(Color(inf, inf, inf));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(b[k], 1.f, 1e-5f);
}

TEST(Exposure, ZeroEvIsExactlyTheRadianceScale) {
    EXPECT_EQ(exposureScale(0.f), 1.f);
    EXPECT_EQ(exposureScale(2.f), 4.f);
    EXPECT_EQ(exposureScale(-1.f), 0.5f);
    Image img(1, 1);
    img.pixel(0, 0)[0] = 0.25f;
    // One stop up doubles the linear value before the sRGB curve: 0.5 → 188.
    EXPECT_EQ(toRgb8(img, ToneMap::Clamp, exposureScale(1.f))[0], 188);
    EXPECT_EQ(toRgb8(img, ToneMap::Clamp)[0], toByte(srgbEncode(0.25f)));
}

TEST(ExposureMeter, BringsTheLogAverageToMiddleGrey) {
    Image img(4, 4);
    for (int i = 0; i < 16 * 3; ++i) img.data()[i] = 0.045f;  // 0.18 / 4: two stops under
    ExposureMeter m;
    m.add(img);
    EXPECT_NEAR(m.ev(), 2.f, 1e-5f);
    // Black pixels (an empty background) do not drag the exposure up.
    Image wide(8, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            for (int k = 0; k < 3; ++k) wide.pixel(x, y)[k] = 0.72f;  // two stops over
    ExposureMeter w;
    w.add(wide);
    EXPECT_NEAR(w.ev(), -2.f, 1e-5f);
    EXPECT_EQ(w.pixels(), 16);
}

TEST(ExposureMeter, NothingLitMeansZeroAndExtremesAreClamped) {
    ExposureMeter none;
    none.add(Image(3, 3));
    EXPECT_EQ(none.ev(), 0.f);
    Image dim(1, 1);
    for (int k = 0; k < 3; ++k) dim.pixel(0, 0)[k] = 1e-30f;
    ExposureMeter m;
    m.add(dim);
    EXPECT_EQ(m.ev(), 20.f);
}
