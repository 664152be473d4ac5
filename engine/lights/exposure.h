#pragma once
/// Photometric units and exposure. glTF lights are photometric (cd, lx); the renderer works in
/// radiometric units at 683 lm/W, as Blender does, so --exposure 0 shows that scale unchanged.
/// Auto exposure meters a film once and applies one EV to every frame: a turntable never flickers.
#include "engine/util/image.h"

namespace rf {

/// Luminous efficacy used for every photometric conversion (lm/W), Blender's constant.
constexpr float kLumensPerWatt = 683.f;

/// Accumulates the pixels of a few low-resolution frames of a film and picks one EV for it.
class ExposureMeter {
public:
    /// Adds every pixel with luminance above zero: a black background says nothing about how
    /// bright the model should look.
    void add(const Image& img);
    /// The EV that brings the log-average luminance of the metered pixels to middle grey (0.18),
    /// clamped to ±20; 0 when nothing lit was metered.
    float ev() const;
    long long pixels() const { return count_; }

    static constexpr float kMiddleGrey = 0.18f;

private:
    double logSum_ = 0.0;
    long long count_ = 0;
};

/// Rec. 709 luminance of a linear colour.
inline float luminance(const Color& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

}  // namespace rf
