// The geometric predicates of the intersection queries (ray-box, sphere-triangle, swept sphere-triangle),
// in double, with their rounding policy stated here.
// Internal header (an internal/ folder): not installed; its shape may change freely.
#pragma once
#include "sg/core/Math.h"

#include <cmath>
#include <cstdint>

namespace sg {
namespace isect {

// Ray-box slab test against float bounds: true when o + t d meets [mn, mx] for some t in [0, tMax], with
// tNear the entry distance. The far distance is widened by 2 gamma(3) (pbrt's bound on the rounding of
// the slab distances), so that a ray grazing a face, as rays through a closed mesh's edges do, is never
// pruned. `inv` is 1 / d per component; NaN slab distances (0 * inf) leave the interval unchanged.
template <class T>
inline bool slab(const T* mn, const T* mx, const dvec3& o, const dvec3& inv, double tMax, double& tNear) noexcept {
    constexpr double g3 = 3.0 * 1.1102230246251565e-16 / (1.0 - 3.0 * 1.1102230246251565e-16);
    constexpr double kWiden = 1.0 + 2.0 * g3;
    double t0 = 0.0, t1 = tMax;
    for (int a = 0; a < 3; ++a) {
        double n = (double(mn[a]) - o[a]) * inv[a];
        double f = (double(mx[a]) - o[a]) * inv[a];
        if (n > f) std::swap(n, f);
        f *= kWiden;
        t0 = n > t0 ? n : t0;
        t1 = f < t1 ? f : t1;
        if (t0 > t1) return false;
    }
    tNear = t0;
    return true;
}

// Barycentric weights (u of b, v of c) of a point p in triangle (a, b, c)'s plane.
void barycentric(const dvec3& p, const dvec3& a, const dvec3& b, const dvec3& c, double& u, double& v) noexcept;

// The point of triangle (a, b, c) nearest to p (Ericson, Real-Time Collision Detection 5.1.5).
dvec3 closestPointOnTriangle(const dvec3& p, const dvec3& a, const dvec3& b, const dvec3& c) noexcept;

// The closest points of the ray o + t d (t in [0, tMax], tMax may be infinite; d not zero) and the segment
// p0 + u (p1 - p0) (u in [0, 1]; it may be a point): Ericson, Real-Time Collision Detection 5.1.9, with the ray's
// interval in place of [0, 1]. A segment parallel to the ray gives one of the closest pairs.
void closestRaySegment(const dvec3& o, const dvec3& d, double tMax, const dvec3& p0, const dvec3& p1, double& t,
                       double& u) noexcept;

// First contact of a sphere of radius r whose centre moves from c0 to c0 + d with triangle (a, b, c), both
// sides: false when none before `tBest` (a fraction of d). On contact, t, the contact point on the triangle
// and the unit normal from it toward the centre. A sphere that already overlaps the triangle at c0 reports
// t = 0 only when the motion brings it closer (moving out or along is free).
bool sweepSphereTriangle(const dvec3& c0, const dvec3& d, double r, const dvec3& a, const dvec3& b, const dvec3& c,
                         double tBest, double& t, dvec3& point, dvec3& normal) noexcept;

// A BVH node's box in float, rounded outward: it still contains every float vertex the double box holds.
inline void floatBoxOutward(const Box& b, float* mn, float* mx) noexcept {
    for (int a = 0; a < 3; ++a) {
        mn[a] = std::nextafter(float(b.min[a]), -HUGE_VALF);
        mx[a] = std::nextafter(float(b.max[a]), HUGE_VALF);
    }
}

// The axis along which v is longest (the lower one on a tie): where a BVH splits.
inline int longestAxis(const dvec3& v) noexcept { return v.x >= v.y && v.x >= v.z ? 0 : (v.y >= v.z ? 1 : 2); }

// A nearest-hit BVH walk's two children onto its stack (node index and entry distance), the nearer on top so that it
// is popped first; a child its test missed (hl, hr false) is left out.
inline void pushChildren(uint32_t* stack, double* dist, int& top, uint32_t l, bool hl, double tl, uint32_t r, bool hr,
                         double tr) noexcept {
    if (hl && hr) {
        if (tl <= tr) {
            stack[top] = r, dist[top++] = tr;
            stack[top] = l, dist[top++] = tl;
        } else {
            stack[top] = l, dist[top++] = tl;
            stack[top] = r, dist[top++] = tr;
        }
    } else if (hl) {
        stack[top] = l, dist[top++] = tl;
    } else if (hr) {
        stack[top] = r, dist[top++] = tr;
    }
}

}  // namespace isect
}  // namespace sg
