// Vector and matrix types, bounds and planes, and the one place that states the epsilon policy.
#pragma once
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <array>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <limits>
#include <string>

namespace sg {

using glm::dmat4;
using glm::dvec3;
using glm::dvec4;
using glm::mat4;
using glm::vec2;
using glm::vec3;
using glm::vec4;

// Epsilon policy. World space is double precision; the cull kernels run in float on coordinates
// relative to an image origin. Every rounding is pushed in the conservative direction (when in doubt,
// draw): bounds are inflated by their own rounding error when stored as float, and frustum planes are
// moved outward by kPlaneSlack times the magnitudes involved before the float kernels use them.
namespace eps {
constexpr double kPlaneSlack = 8.0 * 1.1920928955078125e-07;  // 8 float ulps, relative
constexpr double kDegenerate = 1e-12;                          // |det| below this: singular
}  // namespace eps

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Axis-aligned box in double precision; empty when min > max.
struct Box {
    dvec3 min{kInf};
    dvec3 max{-kInf};
    bool empty() const { return !(min.x <= max.x && min.y <= max.y && min.z <= max.z); }
    dvec3 center() const { return (min + max) * 0.5; }
    dvec3 halfExtent() const { return (max - min) * 0.5; }
    void expand(const dvec3& p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    void expand(const Box& b) {
        if (b.empty()) return;
        min = glm::min(min, b.min);
        max = glm::max(max, b.max);
    }
    bool contains(const dvec3& p) const {
        return p.x >= min.x && p.y >= min.y && p.z >= min.z && p.x <= max.x && p.y <= max.y && p.z <= max.z;
    }
};

struct Sphere {
    dvec3 center{0.0};
    double radius = -1.0;  // negative: empty
};

// Plane n.x + d = 0 with unit n; positive side is "inside".
struct Plane {
    dvec3 n{0.0, 0.0, 1.0};
    double d = 0.0;
    double distance(const dvec3& p) const { return glm::dot(n, p) + d; }
};

inline bool isFinite(const dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Returns "" when every element is finite, else a description of the first bad element.
std::string nonFiniteElement(const dmat4& m);

// Axis-aligned box of the box b transformed by m (affine), exact for the 8 corners.
Box transformBox(const dmat4& m, const Box& b);

// Largest factor by which m can stretch a length (column norms bound it; conservative).
double maxScale(const dmat4& m);

// True when m is a pure translation.
bool isTranslation(const dmat4& m);

// m * translate(t) without a full product (9 multiply-adds).
inline dmat4 mulTranslate(const dmat4& m, const dvec3& t) {
    dmat4 r = m;
    r[3] = m[0] * t.x + m[1] * t.y + m[2] * t.z + m[3];
    return r;
}

// The 16 doubles of a matrix to floats (two at a time where SSE2 is there: every x86-64).
inline void toFloat(const dmat4& m, mat4& out) {
    const double* s = &m[0][0];
    float* d = &out[0][0];
#if defined(__SSE2__)
    for (int k = 0; k < 16; k += 4) {
        const __m128 lo = _mm_cvtpd_ps(_mm_loadu_pd(s + k)), hi = _mm_cvtpd_ps(_mm_loadu_pd(s + k + 2));
        _mm_storeu_ps(d + k, _mm_movelh_ps(lo, hi));
    }
#else
    for (int k = 0; k < 16; ++k) d[k] = float(s[k]);
#endif
}

// Six planes (left, right, bottom, top, near, far), normals inward and unit length, of clip = proj * view.
std::array<Plane, 6> frustumPlanes(const dmat4& clip);

std::string toString(const dmat4& m);

}  // namespace sg
