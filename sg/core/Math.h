// Vector and matrix types, bounds and planes, and the epsilon policy with its shared tolerances (sg::eps).
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
using glm::dvec2;
using glm::dvec3;
using glm::dvec4;
using glm::mat3;
using glm::mat4;
using glm::vec2;
using glm::vec3;
using glm::vec4;

// Epsilon policy. World space is double precision; the cull kernels run in float on coordinates
// relative to an image origin. Every rounding is pushed in the conservative direction (when in doubt,
// draw): bounds are inflated by their own rounding error when stored as float, and frustum planes are
// moved outward by kPlaneSlack times the magnitudes involved before the float kernels use them.
// sg::eps names the tolerances of the geometric predicates shared across the library. Not here: a
// tolerance one algorithm tunes for itself (the occlusion tree's split and near-plane margins, with
// their comments), guards that only keep a divisor away from zero, margins on timings and statistics,
// cost-model coefficients, user settings and test data.
namespace eps {
constexpr double kPlaneSlack = 8.0 * 1.1920928955078125e-07;  // 8 float ulps, relative
// Rounding of a value computed in or stored as float, relative (8 float ulps, rounded up): bounds grow by it.
constexpr double kFloatRounding = 1e-6;
// |det| of a 3x3 at or below this (times its column lengths' product when scale-free): singular.
constexpr double kDegenerate = 1e-12;
// Rounding allowance of a short double computation, relative to its magnitudes (~4500 double ulps).
constexpr double kRounding = 1e-12;
// A point within this times the shape's size of a plane lies on it (relative: any unit, any scale).
constexpr double kCoplanar = 1e-9;
// The cross product of two unit vectors shorter than this: parallel, the direction between them undefined.
constexpr double kParallel = 1e-9;
// |A^T A - I| (sum of the column norms) below this: A is a rotation, lengths and angles kept.
constexpr double kRigid = 1e-9;
// A length at or below this is zero: no direction is taken from it (world units, far below any feature).
constexpr double kZeroLength = 1e-12;
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

// m * translate(t) without a full product (12 multiply-adds). With SSE2 the result is written in
// 16-byte pieces, the width the cull later reads it with (a store the load can forward from).
inline dmat4 mulTranslate(const dmat4& m, const dvec3& t) {
    dmat4 r = m;
#if defined(__SSE2__)
    const double* a = &m[0][0];
    double* o = &r[0][0];
    const __m128d tx = _mm_set1_pd(t.x), ty = _mm_set1_pd(t.y), tz = _mm_set1_pd(t.z);
    for (int k = 0; k < 4; k += 2) {
        __m128d v = _mm_add_pd(_mm_mul_pd(_mm_loadu_pd(a + k), tx), _mm_loadu_pd(a + 12 + k));
        v = _mm_add_pd(v, _mm_mul_pd(_mm_loadu_pd(a + 4 + k), ty));
        v = _mm_add_pd(v, _mm_mul_pd(_mm_loadu_pd(a + 8 + k), tz));
        _mm_storeu_pd(o + 12 + k, v);
    }
#else
    r[3] = m[0] * t.x + m[1] * t.y + m[2] * t.z + m[3];
#endif
    return r;
}

// The affine part of a matrix (its 12 upper-row doubles) to floats.
inline void toFloat(const dmat4& m, glm::mat4x3& out) {
    for (int c = 0; c < 4; ++c) out[c] = vec3(m[c]);
}

// An affine matrix has (0 0 0 1) as its last row; "" when so, else a description of the row.
std::string nonAffineRow(const dmat4& m);

// "" when m is a finite, affine and invertible matrix (|det| of the upper 3x3 above kDegenerate times
// the product of its column lengths, so that the test does not depend on the scale), else why it is not:
// the one check of every node that places children with a matrix (bounds and picking invert it).
std::string nonInvertibleAffine(const dmat4& m);

// Six planes (left, right, bottom, top, near, far), normals inward and unit length, of clip = proj * view.
std::array<Plane, 6> frustumPlanes(const dmat4& clip);

std::string toString(const dmat4& m);

}  // namespace sg
