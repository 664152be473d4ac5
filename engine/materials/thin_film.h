#pragma once
/// KHR_materials_iridescence's thin film: a dielectric layer of index n2 and thickness d between
/// the outside (air, n1 = 1) and the base (n3), reflecting as the Airy sum of its multiple
/// reflections with their phase shifts (Belcour and Barla 2017, as the extension's specification
/// describes it). Evaluated exactly per RGB channel at one wavelength each (kFilmWavelengthsNm),
/// averaging the s and p polarizations, with the full Fresnel amplitudes at both interfaces.
/// Every index here is real and n1 is the smallest, so no ray is totally reflected inside the
/// film and the reflectance lies in [0, 1] at every angle.
#include "engine/util/vec_math.h"

namespace rf::pbr {

/// The wavelength each colour channel is evaluated at: the dominant wavelengths of the sRGB
/// (Rec. 709) primaries, 611 nm (R), 549 nm (G) and 464 nm (B).
constexpr double kFilmWavelengthsNm[3] = {611.0, 549.0, 464.0};

/// Reflectance of the film at one wavelength for the cosine cos1 of the angle of incidence in
/// the outside medium (n1), unpolarized: the mean of |r|² over s and p, with
/// r = (r12 + r23·e^{2iδ})/(1 + r12·r23·e^{2iδ}), δ = 2π·n2·d·cos θ2/λ. d and λ in the same unit.
/// A thickness of 0 gives the bare interface n1 | n3.
double thinFilmReflectance(double n1, double n2, double n3, double thickness, double wavelength, double cos1);

/// The film over a base of index baseIor (one per channel) seen from air at cos θ, per channel at
/// kFilmWavelengthsNm; thickness in nanometres.
Color thinFilmFresnel(float cosTheta, float filmIor, float thicknessNm, const Color& baseIor);
Color thinFilmFresnel(float cosTheta, float filmIor, float thicknessNm, float baseIor);

/// The index of a dielectric whose normal-incidence reflectance (from air) is f0: the inverse of
/// ((n − 1)/(n + 1))², for f0 clamped to [0, 0.9999] as the specification does (a metal's base
/// colour becomes the film's base index so).
float iorFromF0(float f0);

}  // namespace rf::pbr
