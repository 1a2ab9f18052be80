#include "sg/cull/internal/FrustumKernel.h"

namespace sg::kernel {

Planes Planes::make(const std::array<Plane, 6>& world, const dvec3& origin, double extent, uint32_t mask) {
    Planes p;
    for (int i = 0; i < 6; ++i) {
        if (!(mask & (1u << i))) {
            p.nx[i] = p.ny[i] = p.nz[i] = 0.0f;
            p.d[i] = 3.0e38f;  // always inside, never outside
            continue;
        }
        const Plane& w = world[size_t(i)];
        const double d = w.d + glm::dot(w.n, origin);
        // Float error of n.c + d is a few ulps of |d| + |c|; the plane moves outward by more than that.
        const double slack = eps::kPlaneSlack * (std::abs(d) + extent) + 1e-30;
        p.nx[i] = float(w.n.x);
        p.ny[i] = float(w.n.y);
        p.nz[i] = float(w.n.z);
        p.d[i] = float(d + slack);
        if (double(p.d[i]) < d + slack) p.d[i] = std::nextafter(p.d[i], HUGE_VALF);
    }
    return p;
}

#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__)
#define SG_MULTIVERSION __attribute__((target_clones("arch=haswell", "default")))
#else
#define SG_MULTIVERSION
#endif

SG_MULTIVERSION
void classifySpheres(const Planes& p, const float* __restrict cx, const float* __restrict cy,
                     const float* __restrict cz, const float* __restrict r, uint32_t n,
                     uint8_t* __restrict out) noexcept {
    // Outside one plane <=> the smallest signed distance < -r; inside all <=> it is > r. A NaN centre
    // gives a NaN minimum, which is neither: such bounds are never culled.
    for (uint32_t k = 0; k < n; ++k) {
        float m = p.nx[0] * cx[k] + p.ny[0] * cy[k] + p.nz[0] * cz[k] + p.d[0];
        for (int i = 1; i < 6; ++i) {
            const float dist = p.nx[i] * cx[k] + p.ny[i] * cy[k] + p.nz[i] * cz[k] + p.d[i];
            m = dist < m ? dist : m;
        }
        out[k] = uint8_t((m < -r[k]) | ((m > r[k]) << 1));
    }
}

SG_MULTIVERSION
void classifyBoxes(const Planes& p, const float* __restrict cx, const float* __restrict cy, const float* __restrict cz,
                   const float* __restrict ex, const float* __restrict ey, const float* __restrict ez, uint32_t n,
                   uint8_t* __restrict out) noexcept {
    float ax[6], ay[6], az[6];
    for (int i = 0; i < 6; ++i) {
        ax[i] = std::abs(p.nx[i]);
        ay[i] = std::abs(p.ny[i]);
        az[i] = std::abs(p.nz[i]);
    }
    // Per plane: nearest vertex at dist + reach, farthest at dist - reach; take the minimum of each.
    // Starting from plane 0 (not from a large number) lets a NaN from a NaN centre reach the result.
    // An infinite extent makes every plane's value infinite or NaN: never outside, never inside.
    for (uint32_t k = 0; k < n; ++k) {
        const float d0 = p.nx[0] * cx[k] + p.ny[0] * cy[k] + p.nz[0] * cz[k] + p.d[0];
        const float r0 = ax[0] * ex[k] + ay[0] * ey[k] + az[0] * ez[k];
        float lo = d0 + r0, hi = d0 - r0;
        for (int i = 1; i < 6; ++i) {
            const float dist = p.nx[i] * cx[k] + p.ny[i] * cy[k] + p.nz[i] * cz[k] + p.d[i];
            const float reach = ax[i] * ex[k] + ay[i] * ey[k] + az[i] * ez[k];
            const float a = dist + reach, b = dist - reach;
            lo = a < lo ? a : lo;
            hi = b < hi ? b : hi;
        }
        out[k] = uint8_t((lo < 0.0f) | ((hi > 0.0f) << 1));
    }
}

uint8_t classifySphereNaive(const std::array<Plane, 6>& world, const dvec3& c, double r) noexcept {
    bool inside = true;
    for (const Plane& pl : world) {
        const double dist = pl.distance(c);
        if (dist < -r) return kOutside;
        if (!(dist > r)) inside = false;
    }
    return inside ? kInside : 0;
}

}  // namespace sg::kernel
