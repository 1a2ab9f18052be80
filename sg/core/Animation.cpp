// Animation samplers: their checks and their interpolation, as glTF 2.0's Appendix C defines it. (Animation::validate()
// checks the nodes the channels drive, so it is defined with the node types: nodes/AnimationTargets.cpp.)
#include "sg/core/Animation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sg {

const char* pathName(AnimationPath p) {
    switch (p) {
        case AnimationPath::Translation: return "translation";
        case AnimationPath::Rotation: return "rotation";
        case AnimationPath::Scale: return "scale";
        case AnimationPath::Weights: return "weights";
        case AnimationPath::Property: return "pointer";
    }
    return "unknown";
}

namespace {

// What is wrong with a sampler, or empty: Animation::validate() puts it after the sampler's place.
std::string problem(const AnimationSampler& s) {
    if (s.times.empty()) return "no keys";
    if (s.width == 0) return "width is 0";
    for (size_t i = 0; i < s.times.size(); ++i) {
        if (!std::isfinite(s.times[i])) return "times[" + std::to_string(i) + "] is not finite";
        if (i > 0 && !(s.times[i] > s.times[i - 1]))
            return "times[" + std::to_string(i) + "] (" + std::to_string(s.times[i]) + ") is not after times[" +
                   std::to_string(i - 1) + "] (" + std::to_string(s.times[i - 1]) + ")";
    }
    const size_t groups = s.interpolation == Interpolation::CubicSpline ? 3 : 1;
    const size_t expected = s.times.size() * size_t(s.width) * groups;
    if (s.values.size() != expected)
        return std::to_string(s.values.size()) + " values for " + std::to_string(s.times.size()) + " keys of width " +
               std::to_string(s.width) + (groups == 3 ? " (x 3 for CUBICSPLINE)" : "") + ": expected " +
               std::to_string(expected);
    for (size_t i = 0; i < s.values.size(); ++i)
        if (!std::isfinite(s.values[i])) return "values[" + std::to_string(i) + "] is not finite";
    return {};
}

// Spherical interpolation of quaternions a and b (x y z w) along the shorter arc (b negated when the dot is
// negative: q and -q are the same rotation). Keys a little off unit length (files round them) are normalised first,
// so that the angle between them is the rotations' own.
void slerp(const float* fa, const float* fb, double u, double* out) {
    double a[4], b[4], la = 0.0, lb = 0.0;
    for (int j = 0; j < 4; ++j) {
        a[j] = fa[j], b[j] = fb[j];
        la += a[j] * a[j], lb += b[j] * b[j];
    }
    for (int j = 0; j < 4; ++j) {
        if (la > 0.0) a[j] /= std::sqrt(la);
        if (lb > 0.0) b[j] /= std::sqrt(lb);
    }
    double d = 0.0;
    for (int j = 0; j < 4; ++j) d += a[j] * b[j];
    const double sign = d < 0.0 ? -1.0 : 1.0;
    d *= sign;
    double wa = 1.0 - u, wb = u;
    // Nearly the same rotation: sin(angle) is too small to divide by, and a straight mix is as good.
    const bool nearlySame = d > 1.0 - 1e-9;
    if (!nearlySame) {
        const double angle = std::acos(d), s = std::sin(angle);
        wa = std::sin((1.0 - u) * angle) / s;
        wb = std::sin(u * angle) / s;
    }
    double len2 = 0.0;
    for (int j = 0; j < 4; ++j) {
        out[j] = wa * a[j] + sign * wb * b[j];
        len2 += out[j] * out[j];
    }
    if (nearlySame && len2 > 0.0)
        for (int j = 0; j < 4; ++j) out[j] /= std::sqrt(len2);
}

void normalise4(double* q) {
    const double len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (len > 0.0)
        for (int j = 0; j < 4; ++j) q[j] /= len;
}

}  // namespace

void AnimationSampler::validate() const {
    const std::string why = problem(*this);
    if (!why.empty()) throw std::invalid_argument("AnimationSampler::validate(): " + why);
}

void AnimationSampler::sample(double t, bool rotation, double* out, uint32_t* hint) const {
    const size_t n = times.size(), w = width;
    const bool cubic = interpolation == Interpolation::CubicSpline;
    const size_t stride = cubic ? 3 * w : w, at = cubic ? w : 0;  // a key's values, and where its value starts
    if (n == 0 || w == 0 || values.size() < n * stride) {         // not validated: nothing to read
        std::fill(out, out + w, 0.0);
        return;
    }
    const auto copyKey = [&](size_t k) {
        for (size_t j = 0; j < w; ++j) out[j] = values[k * stride + at + j];
    };
    if (n == 1 || !(t > times.front())) return copyKey(0);  // before the first key (or NaN): the first value
    if (t >= times.back()) return copyKey(n - 1);
    // The key k with times[k] <= t < times[k + 1]: from the hint when t has moved forward a little, else by halves.
    size_t k = hint && *hint < n - 1 && times[*hint] <= t ? *hint : 0;
    if (!(t < times[k + 1])) {
        if (k + 2 < n && t < times[k + 2])
            ++k;
        else
            k = size_t(std::upper_bound(times.begin() + std::ptrdiff_t(k), times.end(), t) - times.begin()) - 1;
    }
    if (hint) *hint = uint32_t(k);
    if (interpolation == Interpolation::Step) return copyKey(k);
    const double td = double(times[k + 1]) - double(times[k]), u = (t - double(times[k])) / td;
    const float* v0 = &values[k * stride + at];
    const float* v1 = &values[(k + 1) * stride + at];
    if (!cubic) {
        if (rotation && w == 4) return slerp(v0, v1, u, out);
        for (size_t j = 0; j < w; ++j) out[j] = double(v0[j]) + u * (double(v1[j]) - double(v0[j]));
        return;
    }
    // Hermite: the value and out-tangent of key k, the in-tangent and value of key k + 1; tangents are per second,
    // so they are scaled by the interval.
    const float* b0 = &values[k * stride + 2 * w];  // key k's out-tangent
    const float* a1 = &values[(k + 1) * stride];    // key k + 1's in-tangent
    const double u2 = u * u, u3 = u2 * u;
    const double h00 = 2 * u3 - 3 * u2 + 1, h10 = (u3 - 2 * u2 + u) * td, h01 = -2 * u3 + 3 * u2, h11 = (u3 - u2) * td;
    for (size_t j = 0; j < w; ++j) out[j] = h00 * v0[j] + h10 * b0[j] + h01 * v1[j] + h11 * a1[j];
    if (rotation && w == 4) normalise4(out);
}

double Animation::duration() const {
    double d = 0.0;
    for (const AnimationSampler& s : samplers)
        if (!s.times.empty()) d = std::max(d, s.end());
    return d;
}

}  // namespace sg
