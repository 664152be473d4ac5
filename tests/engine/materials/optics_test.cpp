// Reflection, Snell refraction, total internal reflection and exact Fresnel (catalogue 16).
// The tracer uses exact dielectric Fresnel; Schlick is only kept here to show the difference.
#include <gtest/gtest.h>

#include "engine/materials/optics.h"

using namespace rf;

namespace {
Vec3 dirAt(float deg) { return Vec3(std::sin(glm::radians(deg)), -std::cos(glm::radians(deg)), 0.f); }
const Vec3 kUp(0, 1, 0);

/// Textbook Fresnel in double for cross-checking: ni → nt, incidence angle θi.
double fresnelRef(double cosI, double ni, double nt) {
    const double sinT = ni / nt * std::sqrt(1 - cosI * cosI);
    if (sinT >= 1) return 1;
    const double cosT = std::sqrt(1 - sinT * sinT);
    const double rs = (ni * cosI - nt * cosT) / (ni * cosI + nt * cosT);
    const double rp = (nt * cosI - ni * cosT) / (nt * cosI + ni * cosT);
    return 0.5 * (rs * rs + rp * rp);
}
}  // namespace

TEST(Optics, ReflectionMirrorsAboutTheNormal) {
    const Vec3 r = reflect(dirAt(30.f), kUp);
    EXPECT_NEAR(r.x, std::sin(glm::radians(30.f)), 1e-6f);
    EXPECT_NEAR(r.y, std::cos(glm::radians(30.f)), 1e-6f);
}

TEST(Optics, TotalInternalReflectionAt45DegreesInsideGlass) {
    // Inside glass (1.5 → 1): sin²θt = 1.5²·sin²45° = 1.125 > 1.
    Vec3 out;
    EXPECT_FALSE(refract(dirAt(45.f), kUp, 1.5f, out));
    EXPECT_FLOAT_EQ(fresnelDielectric(std::cos(glm::radians(45.f)), 1.f / 1.5f), 1.f);
}

TEST(Optics, RefractsAt40DegreesInsideGlass) {
    Vec3 out;
    ASSERT_TRUE(refract(dirAt(40.f), kUp, 1.5f, out));
    const float sin2T = out.x * out.x;  // out is unit; x is sin θt
    EXPECT_NEAR(sin2T, 2.25f * std::pow(std::sin(glm::radians(40.f)), 2.f), 1e-5f);
    EXPECT_NEAR(sin2T, 0.930f, 1e-3f);
    EXPECT_LT(out.y, 0.f);  // continues through the surface
    const float F = fresnelDielectric(std::cos(glm::radians(40.f)), 1.f / 1.5f);
    EXPECT_LT(F, 1.f);
    EXPECT_NEAR(F, fresnelRef(std::cos(glm::radians(40.0)), 1.5, 1.0), 1e-5);
}

TEST(Optics, FresnelAtNormalAndGrazingIncidence) {
    EXPECT_NEAR(fresnelDielectric(1.f, 1.5f), 0.04f, 1e-6f);
    EXPECT_NEAR(fresnelDielectric(1.f, 1.f / 1.5f), 0.04f, 1e-6f);
    EXPECT_NEAR(fresnelDielectric(0.f, 1.5f), 1.f, 1e-6f);
    EXPECT_NEAR(fresnelDielectric(1e-7f, 1.5f), 1.f, 1e-5f);
}

TEST(Optics, IndexOneLeavesDirectionAndReflectsNothing) {
    for (float deg : {0.f, 30.f, 60.f, 89.f}) {
        Vec3 out;
        ASSERT_TRUE(refract(dirAt(deg), kUp, 1.f, out));
        EXPECT_NEAR(glm::length(out - dirAt(deg)), 0.f, 1e-6f) << deg;
        EXPECT_NEAR(fresnelDielectric(std::cos(glm::radians(deg)), 1.f), 0.f, 1e-7f) << deg;
    }
}

TEST(Optics, ExactFresnelMatchesTheTextbookFormulaAtAllAngles) {
    for (int deg = 0; deg <= 89; ++deg) {
        const double c = std::cos(glm::radians(double(deg)));
        EXPECT_NEAR(fresnelDielectric(float(c), 1.5f), fresnelRef(c, 1.0, 1.5), 2e-6) << deg;
        EXPECT_NEAR(fresnelDielectric(float(c), 1.f / 1.5f), fresnelRef(c, 1.5, 1.0), 2e-6) << deg;
        // A negative cosine means "from the other side": the same as swapping the media.
        EXPECT_NEAR(fresnelDielectric(float(-c), 1.5f), fresnelRef(c, 1.5, 1.0), 2e-6) << deg;
    }
}

TEST(Optics, SchlickStraysFromExactFresnelOffItsGoodRange) {
    // Schlick's formula for light leaving glass ignores total internal reflection: at 40° the
    // exact value (~0.2) differs from Schlick's by far more than Schlick's 1% near normal incidence.
    const float c40 = std::cos(glm::radians(40.f));
    const float exact = fresnelDielectric(c40, 1.f / 1.5f), schlick = fresnelSchlick(c40, 1.5f);
    EXPECT_GT(std::abs(exact - schlick) / exact, 0.2f);
    EXPECT_NEAR(fresnelSchlick(1.f, 1.5f), fresnelDielectric(1.f, 1.5f), 1e-6f);
}
