#pragma once
/// Typed key tracks: a value of 1, 3 or 4 (quaternion) components per key, evaluated at any time
/// with per-key interpolation. The same evaluator serves the timeline's tracks and glTF samplers.
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/util/vec_math.h"

namespace rf::anim {

/// How the segment from a key to the next one is filled.
enum class Interp {
    Step,        ///< hold this key's value until the next key
    Linear,      ///< lerp; slerp (short path) on rotation tracks
    Hermite,     ///< cubic Hermite with explicit in/out tangents in units per second
    CatmullRom,  ///< centripetal Catmull–Rom (Yuksel et al. 2011) through the neighbouring keys
    EaseInOut,   ///< lerp/slerp with a smoothstep parameter
    EaseIn,      ///< lerp/slerp with parameter u²
    EaseOut,     ///< lerp/slerp with parameter 1 − (1 − u)²
};

/// Parses "step", "linear", "slerp", "hermite", "catmull-rom", "ease", "ease-in-out",
/// "ease-in", "ease-out"; returns false for anything else.
bool parseInterp(const std::string& name, Interp& out);

/// A track broke a key rule; `key` is the offending key, `field` the key's member ("time", …).
class KeyError : public std::invalid_argument {
public:
    KeyError(int key, std::string field, const std::string& message)
        : std::invalid_argument(message), key_(key), field_(std::move(field)) {}
    int key() const { return key_; }
    const std::string& field() const { return field_; }

private:
    int key_;
    std::string field_;
};

/// Keys of one animated quantity. Rotation tracks hold unit quaternions as (x, y, z, w).
class KeyTrack {
public:
    KeyTrack() = default;
    /// dim: components per key (1, 3 or 4); rotation: dim == 4 and values are quaternions.
    KeyTrack(int dim, bool rotation) : dim_(dim), rotation_(rotation) {}

    /// Appends a key. Throws KeyError unless time is finite and greater than the previous key's,
    /// and the value finite (a rotation non-zero; it is normalised). in/out: tangents per second
    /// (Hermite only; nullptr = zero).
    void addKey(double time, const double* value, Interp interp, const double* in = nullptr, const double* out = nullptr);

    /// Value at time t: clamped to the first/last key outside the key range, bit-exact at a key.
    void evaluate(double t, double* out) const;
    double evaluateScalar(double t) const;
    DVec3 evaluateVec3(double t) const;
    /// Rotation tracks: the unit quaternion at t.
    DQuat evaluateQuat(double t) const;

    int dim() const { return dim_; }
    bool rotation() const { return rotation_; }
    bool empty() const { return times_.empty(); }
    size_t size() const { return times_.size(); }
    double startTime() const { return times_.empty() ? 0.0 : times_.front(); }
    double endTime() const { return times_.empty() ? 0.0 : times_.back(); }

private:
    const double* value(size_t k) const { return &values_[k * dim_]; }
    void catmullRom(size_t i, double u, double* out) const;

    int dim_ = 1;
    bool rotation_ = false;
    std::vector<double> times_;
    std::vector<double> values_;   ///< dim per key
    std::vector<double> inTan_;    ///< dim per key, per second
    std::vector<double> outTan_;   ///< dim per key, per second
    std::vector<Interp> interp_;
};

/// Spherical linear interpolation on the short path (b is negated when a·b < 0, since q and −q
/// are the same rotation). Unit-length and finite for any unit a, b, including a·b = ±1.
DQuat slerpShort(const DQuat& a, const DQuat& b, double u);

/// Cubic Hermite basis: p0 + tangents m0, m1 already scaled by the segment length.
inline double hermite(double p0, double m0, double p1, double m1, double u) {
    const double u2 = u * u, u3 = u2 * u;
    return (2 * u3 - 3 * u2 + 1) * p0 + (u3 - 2 * u2 + u) * m0 + (-2 * u3 + 3 * u2) * p1 + (u3 - u2) * m1;
}

}  // namespace rf::anim
