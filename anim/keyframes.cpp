#include "anim/keyframes.h"

#include <algorithm>
#include <cmath>

namespace rf::anim {

bool parseInterp(const std::string& name, Interp& out) {
    if (name == "step") out = Interp::Step;
    else if (name == "linear" || name == "slerp") out = Interp::Linear;
    else if (name == "hermite" || name == "cubic") out = Interp::Hermite;
    else if (name == "catmull-rom") out = Interp::CatmullRom;
    else if (name == "ease" || name == "ease-in-out") out = Interp::EaseInOut;
    else if (name == "ease-in") out = Interp::EaseIn;
    else if (name == "ease-out") out = Interp::EaseOut;
    else return false;
    return true;
}

DQuat slerpShort(const DQuat& a, const DQuat& bIn, double u) {
    DQuat b = bIn;
    double d = glm::dot(a, b);
    if (d < 0.0) {  // q and −q are one rotation: go the short way
        b = -b;
        d = -d;
    }
    DQuat r;
    if (d > 1.0 - 1e-6) {
        // sin θ → 0: the sine weights lose all precision, while nlerp is exact to O(θ³) here.
        r = DQuat(a.w + u * (b.w - a.w), a.x + u * (b.x - a.x), a.y + u * (b.y - a.y), a.z + u * (b.z - a.z));
    } else {
        const double theta = std::acos(std::min(d, 1.0));
        const double s = std::sin(theta);
        const double wa = std::sin((1.0 - u) * theta) / s, wb = std::sin(u * theta) / s;
        r = DQuat(wa * a.w + wb * b.w, wa * a.x + wb * b.x, wa * a.y + wb * b.y, wa * a.z + wb * b.z);
    }
    const double len = std::sqrt(glm::dot(r, r));
    return len > 0.0 ? DQuat(r.w / len, r.x / len, r.y / len, r.z / len) : a;
}

void KeyTrack::addKey(double time, const double* value, Interp interp, const double* in, const double* out) {
    const int k = static_cast<int>(times_.size());
    if (!std::isfinite(time)) throw KeyError(k, "time", "expected a finite time");
    if (!times_.empty() && !(time > times_.back()))
        throw KeyError(k, "time", time == times_.back() ? "times must increase (equal to the previous key's)"
                                                          : "times must increase (earlier than the previous key's)");
    std::vector<double> v(value, value + dim_);
    for (double x : v)
        if (!std::isfinite(x)) throw KeyError(k, "value", "expected finite numbers");
    if (rotation_) {
        const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
        if (!(len > 1e-12)) throw KeyError(k, "value", "a rotation quaternion must not be zero");
        for (double& x : v) x /= len;
    }
    for (const double* t : {in, out})
        if (t)
            for (int c = 0; c < dim_; ++c)
                if (!std::isfinite(t[c])) throw KeyError(k, t == in ? "in" : "out", "expected finite tangents");
    times_.push_back(time);
    values_.insert(values_.end(), v.begin(), v.end());
    for (int c = 0; c < dim_; ++c) {
        inTan_.push_back(in ? in[c] : 0.0);
        outTan_.push_back(out ? out[c] : 0.0);
    }
    interp_.push_back(interp);
}

namespace {
double ease(Interp i, double u) {
    switch (i) {
        case Interp::EaseInOut: return u * u * (3.0 - 2.0 * u);
        case Interp::EaseIn: return u * u;
        case Interp::EaseOut: return 1.0 - (1.0 - u) * (1.0 - u);
        default: return u;
    }
}
}  // namespace

void KeyTrack::evaluate(double t, double* out) const {
    const size_t n = times_.size();
    if (n == 0) {
        std::fill(out, out + dim_, 0.0);
        return;
    }
    size_t k;
    if (!(t > times_.front())) k = 0;  // also NaN: the first key
    else if (t >= times_.back()) k = n - 1;
    else k = n;
    if (k == n) {
        const size_t i = static_cast<size_t>(std::upper_bound(times_.begin(), times_.end(), t) - times_.begin()) - 1;
        if (t == times_[i]) {
            k = i;  // exactly at a key: that key's value, bit for bit
        } else {
            const double td = times_[i + 1] - times_[i];  // > 0: addKey enforces increasing times
            const double u = (t - times_[i]) / td;
            const double* a = value(i);
            const double* b = value(i + 1);
            const Interp how = interp_[i];
            if (how == Interp::Step) {
                std::copy(a, a + dim_, out);
            } else if (how == Interp::Hermite) {
                for (int c = 0; c < dim_; ++c)
                    out[c] = hermite(a[c], td * outTan_[i * dim_ + c], b[c], td * inTan_[(i + 1) * dim_ + c], u);
            } else if (how == Interp::CatmullRom) {
                catmullRom(i, u, out);
            } else {
                const double w = ease(how, u);
                if (rotation_) {
                    const DQuat q = slerpShort(DQuat(a[3], a[0], a[1], a[2]), DQuat(b[3], b[0], b[1], b[2]), w);
                    out[0] = q.x, out[1] = q.y, out[2] = q.z, out[3] = q.w;
                    return;
                }
                for (int c = 0; c < dim_; ++c) out[c] = a[c] + w * (b[c] - a[c]);
            }
            if (rotation_) {  // Hermite on quaternions (glTF CUBICSPLINE): renormalise
                double len = 0.0;
                for (int c = 0; c < 4; ++c) len += out[c] * out[c];
                len = std::sqrt(len);
                if (len > 0.0)
                    for (int c = 0; c < 4; ++c) out[c] /= len;
                else
                    std::copy(a, a + 4, out);
            }
            return;
        }
    }
    std::copy(value(k), value(k) + dim_, out);
}

void KeyTrack::catmullRom(size_t i, double u, double* out) const {
    // Centripetal Catmull–Rom (alpha = 1/2) written as a Hermite segment from P1 to P2 whose
    // tangents come from the non-uniform knot spacing d = |ΔP|^alpha. Missing end neighbours are
    // mirrored (P0 = 2·P1 − P2). A zero spacing (duplicate points) takes the limit of the formula
    // instead of dividing by zero: a repeated neighbour gives a zero tangent at that end, and
    // P1 == P2 gives a constant segment.
    const size_t n = times_.size();
    const int d = dim_;
    std::vector<double> p(4 * d);
    std::copy(value(i), value(i) + d, &p[d]);
    std::copy(value(i + 1), value(i + 1) + d, &p[2 * d]);
    for (int c = 0; c < d; ++c) {
        p[c] = i > 0 ? value(i - 1)[c] : 2 * p[d + c] - p[2 * d + c];
        p[3 * d + c] = i + 2 < n ? value(i + 2)[c] : 2 * p[2 * d + c] - p[d + c];
    }
    auto spacing = [&](int a, int b) {
        double s = 0.0;
        for (int c = 0; c < d; ++c) s += (p[b * d + c] - p[a * d + c]) * (p[b * d + c] - p[a * d + c]);
        return std::pow(s, 0.25);  // |Δ|^(1/2)
    };
    const double d01 = spacing(0, 1), d12 = spacing(1, 2), d23 = spacing(2, 3);
    if (!(d12 > 0.0)) {
        std::copy(&p[d], &p[2 * d], out);
        return;
    }
    for (int c = 0; c < d; ++c) {
        const double P0 = p[c], P1 = p[d + c], P2 = p[2 * d + c], P3 = p[3 * d + c];
        const double m1 = d01 > 0.0 ? (P2 - P1) + d12 * ((P1 - P0) / d01 - (P2 - P0) / (d01 + d12)) : 0.0;
        const double m2 = d23 > 0.0 ? (P2 - P1) + d12 * ((P3 - P2) / d23 - (P3 - P1) / (d12 + d23)) : 0.0;
        out[c] = hermite(P1, m1, P2, m2, u);
    }
}

double KeyTrack::evaluateScalar(double t) const {
    std::vector<double> v(std::max(dim_, 4), 0.0);
    evaluate(t, v.data());
    return v[0];
}

DVec3 KeyTrack::evaluateVec3(double t) const {
    std::vector<double> v(std::max(dim_, 4), 0.0);
    evaluate(t, v.data());
    return DVec3(v[0], v[1], v[2]);
}

DQuat KeyTrack::evaluateQuat(double t) const {
    std::vector<double> v(std::max(dim_, 4), 0.0);
    evaluate(t, v.data());
    return DQuat(v[3], v[0], v[1], v[2]);
}

}  // namespace rf::anim
