// Small geometry on occluder shapes shared by the mesh analysis (MeshOccluders.cpp, OpenMeshOccluders.cpp) and the
// graph's generator (GeneratedOccluders.cpp): box volume, the flatness float positions allow, convex polygons' normal,
// area and clipping. Internal header: not installed (an internal/ folder, cmake/LayerCheck.cmake).
#pragma once
#include "sg/core/Math.h"

#include <vector>

namespace sg::occluders {

inline double volume(const Box& b) {
    const dvec3 e = b.max - b.min;
    return e.x * e.y * e.z;
}

// How far from one plane points of a mesh with this bound may lie and still be on it: float positions are rounded to
// ~6e-8 of their coordinates, so a flat face far from the origin or not along the axes is flat to that.
inline double flatTolerance(const Box& bound) {
    return 1e-6 *
           (glm::length(bound.max - bound.min) + glm::length(glm::max(glm::abs(bound.min), glm::abs(bound.max))));
}

// A planar polygon's unit normal (Newell's, about its first corner; zero when it has no area) and its area.
inline dvec3 polygonNormal(const std::vector<dvec3>& p) {
    dvec3 n(0.0);
    for (size_t k = 1; k + 1 < p.size(); ++k) n += glm::cross(p[k] - p[0], p[k + 1] - p[0]);
    const double l = glm::length(n);
    return l > 0.0 ? n / l : n;
}
inline double polygonArea(const std::vector<dvec3>& p) {
    dvec3 n(0.0);
    for (size_t k = 1; k + 1 < p.size(); ++k) n += glm::cross(p[k] - p[0], p[k + 1] - p[0]);
    return 0.5 * glm::length(n);
}

// The part of convex polygon p inside convex polygon q, both on one plane (within `tol`) facing one way (unit normal
// n, counter-clockwise about it); empty when they are not, or when nothing is left.
inline std::vector<dvec3> clipConvex(std::vector<dvec3> p, const std::vector<dvec3>& q, const dvec3& n, double tol) {
    if (glm::dot(polygonNormal(q), n) < 1.0 - 1e-9 || std::abs(glm::dot(q[0] - p[0], n)) > tol) return {};
    for (size_t k = 0; k < q.size() && p.size() >= 3; ++k) {
        const dvec3 a = q[k], e = q[(k + 1) % q.size()] - a, in = glm::cross(n, e);  // left of the edge: inside
        std::vector<dvec3> out;
        for (size_t j = 0; j < p.size(); ++j) {
            const dvec3 u = p[j], v = p[(j + 1) % p.size()];
            const double du = glm::dot(u - a, in), dv = glm::dot(v - a, in);
            if (du >= 0.0) out.push_back(u);
            if ((du >= 0.0) != (dv >= 0.0)) out.push_back(u + (v - u) * (du / (du - dv)));
        }
        p = std::move(out);
    }
    return p.size() >= 3 ? p : std::vector<dvec3>{};
}

}  // namespace sg::occluders
