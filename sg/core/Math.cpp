#include "sg/core/Math.h"

#include <cstdio>

namespace sg {

std::string nonFiniteElement(const dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) {
                char buf[96];
                std::snprintf(buf, sizeof buf, "element [%d][%d] is %g", c, r, m[c][r]);
                return buf;
            }
    return {};
}

std::string nonAffineRow(const dmat4& m) {
    if (m[0][3] == 0.0 && m[1][3] == 0.0 && m[2][3] == 0.0 && m[3][3] == 1.0) return {};
    char buf[128];
    std::snprintf(buf, sizeof buf, "last row is (%g %g %g %g), not (0 0 0 1): only affine transforms are drawn",
                  m[0][3], m[1][3], m[2][3], m[3][3]);
    return buf;
}

std::string nonInvertibleAffine(const dmat4& m) {
    std::string why = nonFiniteElement(m);
    if (why.empty()) why = nonAffineRow(m);
    if (!why.empty()) return why;
    const double det = glm::determinant(glm::dmat3(m));
    const double scale = glm::length(dvec3(m[0])) * glm::length(dvec3(m[1])) * glm::length(dvec3(m[2]));
    if (!(std::abs(det) > eps::kDegenerate * scale) || scale == 0.0)
        return "matrix is singular (det " + std::to_string(det) + ") " + toString(m);
    return {};
}

Box transformBox(const dmat4& m, const Box& b) {
    Box out;
    if (b.empty()) return out;
    // Centre/extent form: the new half extent is |M3x3| * e, exact for the transformed corners' AABB.
    const dvec3 c = b.center(), e = b.halfExtent();
    const dvec3 wc = dvec3(m * dvec4(c, 1.0));
    dvec3 we;
    for (int r = 0; r < 3; ++r) we[r] = std::abs(m[0][r]) * e.x + std::abs(m[1][r]) * e.y + std::abs(m[2][r]) * e.z;
    out.min = wc - we;
    out.max = wc + we;
    return out;
}

double maxScale(const dmat4& m) {
    const dvec3 x(m[0]), y(m[1]), z(m[2]);
    const double a = glm::length(x), b = glm::length(y), c = glm::length(z);
    const double big = std::max(a, std::max(b, c));
    // Orthogonal columns (rotation times scale): the longest column is the exact stretch. Otherwise the
    // Frobenius norm, which bounds the spectral norm from above.
    const double tol = eps::kRounding * big * big;
    if (std::abs(glm::dot(x, y)) <= tol && std::abs(glm::dot(x, z)) <= tol && std::abs(glm::dot(y, z)) <= tol)
        return big * (1.0 + eps::kRounding);
    return std::sqrt(a * a + b * b + c * c);
}

bool isTranslation(const dmat4& m) {
    const dmat4 id(1.0);
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 4; ++r)
            if (m[c][r] != id[c][r]) return false;
    return m[3][3] == 1.0;
}

std::array<Plane, 6> frustumPlanes(const dmat4& clip) {
    // Gribb-Hartmann: rows of the clip matrix combined; glm is column-major, so row r is clip[*][r].
    auto row = [&](int r) { return dvec4(clip[0][r], clip[1][r], clip[2][r], clip[3][r]); };
    const dvec4 r0 = row(0), r1 = row(1), r2 = row(2), r3 = row(3);
    const dvec4 raw[6] = {r3 + r0, r3 - r0, r3 + r1, r3 - r1, r3 + r2, r3 - r2};
    std::array<Plane, 6> out;
    for (int i = 0; i < 6; ++i) {
        const dvec3 n(raw[i]);
        const double len = glm::length(n);
        out[i].n = len > 0 ? n / len : n;
        out[i].d = len > 0 ? raw[i].w / len : raw[i].w;
    }
    return out;
}

std::string toString(const dmat4& m) {
    std::string s = "[";
    char buf[32];
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            std::snprintf(buf, sizeof buf, "%s%g", (c || r) ? " " : "", m[c][r]);
            s += buf;
        }
    return s + "]";
}

}  // namespace sg
