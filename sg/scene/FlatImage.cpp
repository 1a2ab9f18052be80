#include "sg/scene/FlatImage.h"

#include <algorithm>
#include <cmath>

namespace sg {

void FlatImage::resize(size_t n) {
    for (auto* v : {&cx, &cy, &cz, &r, &ex, &ey, &ez}) {
        v->resize(n);
        v->shrink_to_fit();
    }
    end.resize(n);
    end.shrink_to_fit();
    kind.resize(n);
    kind.shrink_to_fit();
    flags.resize(n);
    flags.shrink_to_fit();
    aux.resize(n);
    aux.shrink_to_fit();
}

size_t FlatImage::bytes() const {
    size_t owned = 0;  // the images this one holds: its details' and its prototypes' (with their map nodes)
    for (const Paged& p : paged)
        if (p.detail) owned += p.detail->bytes();
    for (const auto& p : prototypes) owned += p.second->bytes() + sizeof(p) + 2 * sizeof(void*);
    return owned + size() * (7 * sizeof(float) + 2 * sizeof(uint32_t) + 2) + translations.capacity() * sizeof(dvec3) +
           matrices.capacity() * sizeof(dmat4) + switchOn.capacity() + nodes.capacity() * sizeof(void*) +
           masked.capacity() * 8 + featured.capacity() * sizeof(featured[0]) + posed.capacity() * sizeof(posed[0]) +
           lods.capacity() * sizeof(Lod) + paged.capacity() * sizeof(Paged) + ranges.capacity() * sizeof(Range) +
           draws.capacity() * sizeof(Draw) + placements.capacity() * sizeof(Placement) +
           wides.capacity() * sizeof(Wide) + wideEntry.capacity() * 5 * 4 + occluders.capacity() * sizeof(OccluderRef) +
           occluderMatrices.capacity() * sizeof(dmat4) + occluderChunks.capacity() * sizeof(Box) +
           occluderSwitchBits.capacity() * sizeof(uint32_t);
}

Box FlatImage::box(size_t i) const {
    SG_ASSERT(i < size(), "FlatImage::box(): entry past the image");
    const dvec3 c = center(i), e(ex[i], ey[i], ez[i]);
    return Box{c - e, c + e};
}

static float roundUp(double x) {
    float f = static_cast<float>(x);
    if (static_cast<double>(f) < x) f = std::nextafter(f, HUGE_VALF);
    return f;
}

void FlatImage::setBound(size_t i, const Box& b, double radius) {
    SG_ASSERT(i < size(), "FlatImage::setBound(): entry past the image");
    if (b.empty()) {
        cx[i] = cy[i] = cz[i] = 0.0f;
        r[i] = ex[i] = ey[i] = ez[i] = 0.0f;
        flags[i] |= kEmpty;
        return;
    }
    // World boxes far from the origin carry double rounding of their own (transforms, centre/extent form):
    // grow by a few double ulps of the world magnitude as well.
    const dvec3 wc = b.center();
    const double dbl =
        16.0 * 2.220446049250313e-16 * (std::abs(wc.x) + std::abs(wc.y) + std::abs(wc.z) + glm::length(b.halfExtent()));
    const dvec3 c = wc - origin, e = b.halfExtent() + dvec3(dbl);
    radius += dbl;
    if (!isFinite(c) || !isFinite(e) || !std::isfinite(radius)) {
        setInvalid(i);
        return;
    }
    // Round the centre to nearest, then grow the extents and radius by exactly the centre's error.
    const float fx = static_cast<float>(c.x), fy = static_cast<float>(c.y), fz = static_cast<float>(c.z);
    const dvec3 err(std::abs(double(fx) - c.x), std::abs(double(fy) - c.y), std::abs(double(fz) - c.z));
    cx[i] = fx;
    cy[i] = fy;
    cz[i] = fz;
    ex[i] = roundUp(e.x + err.x);
    ey[i] = roundUp(e.y + err.y);
    ez[i] = roundUp(e.z + err.z);
    r[i] = roundUp(std::min(radius, glm::length(e)) + glm::length(err));
    flags[i] &= ~(kEmpty | kInvalid);
}

uint32_t FlatImage::maskOf(uint32_t i) const {
    SG_ASSERT(i < size(), "FlatImage::maskOf(): entry past the image");
    auto it = std::lower_bound(masked.begin(), masked.end(), std::make_pair(i, 0u));
    const bool listed = it != masked.end() && it->first == i;
    SG_ASSERT(listed || !(flags[i] & kMasked), "FlatImage::maskOf(): a kMasked entry is not in `masked`");
    return listed ? it->second : 0xffffffffu;
}

const FlatImage::FeatureRef* FlatImage::featureOf(uint32_t i) const {
    auto it = std::lower_bound(featured.begin(), featured.end(), i,
                               [](const std::pair<uint32_t, FeatureRef>& e, uint32_t k) { return e.first < k; });
    return it != featured.end() && it->first == i ? &it->second : nullptr;
}

const Pose* FlatImage::poseOf(uint32_t i) const {
    auto it =
        std::lower_bound(posed.begin(), posed.end(), i,
                         [](const std::pair<uint32_t, ref_ptr<const Pose>>& e, uint32_t k) { return e.first < k; });
    return it != posed.end() && it->first == i ? it->second.get() : nullptr;
}

void FlatImage::setInvalid(size_t i) {
    // NaN centre and infinite radius: every comparison a cull test makes comes out "not outside".
    cx[i] = cy[i] = cz[i] = std::nanf("");
    r[i] = ex[i] = ey[i] = ez[i] = HUGE_VALF;
    flags[i] = static_cast<uint8_t>((flags[i] | kInvalid) & ~kEmpty);
}

}  // namespace sg
