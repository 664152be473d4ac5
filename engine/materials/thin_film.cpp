#include "engine/materials/thin_film.h"

#include <algorithm>
#include <cmath>

namespace rf::pbr {

double thinFilmReflectance(double n1, double n2, double n3, double thickness, double wavelength, double cos1) {
    cos1 = std::clamp(cos1, 0.0, 1.0);
    const double sin1sq = 1.0 - cos1 * cos1;
    // Snell's law: n1 sin θ1 = n2 sin θ2 = n3 sin θ3. With n1 the smallest index both stay real.
    const double cos2 = std::sqrt(std::max(0.0, 1.0 - (n1 / n2) * (n1 / n2) * sin1sq));
    const double cos3 = std::sqrt(std::max(0.0, 1.0 - (n1 / n3) * (n1 / n3) * sin1sq));
    // Fresnel amplitudes, one sign convention for both interfaces (only r12·r23 and the squares
    // enter the reflectance).
    auto ratio = [](double a, double b) { return a + b > 0.0 ? (a - b) / (a + b) : 1.0; };
    const double r12s = ratio(n1 * cos1, n2 * cos2), r23s = ratio(n2 * cos2, n3 * cos3);
    const double r12p = ratio(n2 * cos1, n1 * cos2), r23p = ratio(n3 * cos2, n2 * cos3);
    // |r12 + r23 e^{iψ}|² / |1 + r12 r23 e^{iψ}|² with ψ = 2δ, expanded.
    const double psi = 4.0 * 3.14159265358979323846 * n2 * thickness * cos2 / wavelength;
    const double c = std::cos(psi);
    auto airy = [c](double a, double b) {
        const double num = a * a + b * b + 2.0 * a * b * c;
        const double den = 1.0 + a * a * b * b + 2.0 * a * b * c;
        return den > 0.0 ? std::clamp(num / den, 0.0, 1.0) : 1.0;
    };
    return 0.5 * (airy(r12s, r23s) + airy(r12p, r23p));
}

Color thinFilmFresnel(float cosTheta, float filmIor, float thicknessNm, const Color& baseIor) {
    Color out;
    for (int i = 0; i < 3; ++i)
        out[i] = float(thinFilmReflectance(1.0, filmIor, baseIor[i], thicknessNm, kFilmWavelengthsNm[i], cosTheta));
    return out;
}

Color thinFilmFresnel(float cosTheta, float filmIor, float thicknessNm, float baseIor) {
    return thinFilmFresnel(cosTheta, filmIor, thicknessNm, Color(baseIor));
}

float iorFromF0(float f0) {
    const float s = std::sqrt(std::clamp(std::isfinite(f0) ? f0 : 0.f, 0.f, 0.9999f));
    return (1.f + s) / (1.f - s);
}

}  // namespace rf::pbr
