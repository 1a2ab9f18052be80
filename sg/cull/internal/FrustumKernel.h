// Frustum kernels: classify flat arrays of bounds against up to six planes, branch-free so that the
// compiler vectorizes them (an AVX2 clone is chosen at run time where the CPU has it).
// Internal header (an internal/ folder): not installed; its shape may change freely.
#pragma once
#include "sg/core/Math.h"

#include <array>
#include <cstdint>

namespace sg::kernel {

enum : uint8_t { kOutside = 1, kInside = 2 };  // neither bit: the bound straddles a plane

// Six planes in float, as columns; a plane left out of a test is set to "everything inside".
struct Planes {
    alignas(32) float nx[6], ny[6], nz[6], d[6];
    // Planes relative to `origin` (world = origin + p), moved outward by the float slack for coordinates
    // up to `extent` from the origin; only planes whose bit is set in `mask` are kept.
    static Planes make(const std::array<Plane, 6>& world, const dvec3& origin, double extent, uint32_t mask);
};

// out[k] = kOutside if the sphere (c, r) is entirely outside one plane, kInside if inside all, else 0.
// Non-finite inputs compare false both ways: "straddles", never culled.
void classifySpheres(const Planes& p, const float* cx, const float* cy, const float* cz, const float* r, uint32_t n,
                     uint8_t* out) noexcept;
// The same for boxes (centre, half extents), with the nearest/farthest-vertex distance |n|.e.
void classifyBoxes(const Planes& p, const float* cx, const float* cy, const float* cz, const float* ex, const float* ey,
                   const float* ez, uint32_t n, uint8_t* out) noexcept;

// One sphere, scalar, with plane masking: returns the planes still straddled (0: fully inside), or
// kCulledMask when outside. The walk's test above the flat batches.
constexpr uint32_t kCulledMask = 0x80000000u;
inline uint32_t sphereMasked(const Planes& p, uint32_t mask, float cx, float cy, float cz, float r) noexcept {
    uint32_t out = mask;
    for (int i = 0; i < 6; ++i) {
        if (!(mask & (1u << i))) continue;
        const float dist = p.nx[i] * cx + p.ny[i] * cy + p.nz[i] * cz + p.d[i];
        if (dist < -r) return kCulledMask;
        if (dist > r) out &= ~(1u << i);
    }
    return out;
}
inline uint32_t boxMasked(const Planes& p, uint32_t mask, float cx, float cy, float cz, float ex, float ey,
                          float ez) noexcept {
    uint32_t out = mask;
    for (int i = 0; i < 6; ++i) {
        if (!(mask & (1u << i))) continue;
        const float dist = p.nx[i] * cx + p.ny[i] * cy + p.nz[i] * cz + p.d[i];
        const float reach = std::abs(p.nx[i]) * ex + std::abs(p.ny[i]) * ey + std::abs(p.nz[i]) * ez;
        if (reach != reach) return mask;  // 0 * inf: unbounded, never culled
        if (dist < -reach) return kCulledMask;
        if (dist > reach) out &= ~(1u << i);
    }
    return out;
}

// Naive twin of classifySpheres (double precision, one sphere at a time, early exit): the reference
// the benchmark and the agreement test hold the kernel to.
uint8_t classifySphereNaive(const std::array<Plane, 6>& world, const dvec3& c, double r) noexcept;

}  // namespace sg::kernel
