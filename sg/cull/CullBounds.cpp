// The cull's bound tests: one entry against the planes (and the strategies' pre-tests), a straddling subtree
// classified by one flat kernel pass, a wide Group's children classified side by side.
#include "sg/cull/internal/CullContext.h"

#include <cmath>

namespace sg {

namespace {
constexpr uint8_t kBySphereSphere = 4;  // batch result bit: culled by the pre-test
}  // namespace

// Runs the bound tests for entry i; false when it is culled. Clears plane bits the bound is inside of.
bool CullTraversal::test(Ctx& c, uint32_t i, uint32_t& mask) {
    const FlatImage& img = *c.img;
    const CullStrategy strat = set_->strategy;
    stats_->boundsTested++;
    if (strat == CullStrategy::CenterBox && img.kind[i] == NodeKind::Geometry) {
        // PCVR's test: the object's centre against the frustum's box, nothing else.
        const float x = img.cx[i], y = img.cy[i], z = img.cz[i];
        if (x < c.fbMin[0] || y < c.fbMin[1] || z < c.fbMin[2] || x > c.fbMax[0] || y > c.fbMax[1] || z > c.fbMax[2]) {
            stats_->culledCenterBox++;
            return false;
        }
        mask = 0;
        return true;
    }
    if (c.clsBase != ~0u) {  // inside a batch: the kernel already classified this entry
        const uint8_t r = cls_[c.clsOffset + (i - c.clsBase)];
        if (r & kernel::kOutside) {
            (r & kBySphereSphere ? stats_->culledSphereSphere : stats_->culledFrustum)++;
            return false;
        }
        if (r & kernel::kInside) {
            mask = 0;
        } else if (strat == CullStrategy::Aabb) {
            // The batch classified spheres (4 columns read, not 7); a sphere that straddles gets the box
            // test here, for this entry alone.
            const uint32_t bm =
                kernel::boxMasked(c.kplanes, mask, img.cx[i], img.cy[i], img.cz[i], img.ex[i], img.ey[i], img.ez[i]);
            if (bm == kernel::kCulledMask) {
                stats_->culledFrustum++;
                return false;
            }
            mask = bm;
        }
        return true;
    }
    // One bound, above the batches.
    // The eye inside the bound: it is seen (or cut by the near plane), skip its test; its children are
    // still tested.
    const double dx = img.cx[i] - c.eyeImg.x, dy = img.cy[i] - c.eyeImg.y, dz = img.cz[i] - c.eyeImg.z;
    const bool eyeInside =
        set_->measureOnly.eyeInsideSkip && dx * dx + dy * dy + dz * dz <= double(img.r[i]) * img.r[i];
    if (!eyeInside && strat == CullStrategy::SphereSphere) {
        const double d = glm::length(img.center(i) - img.origin - c.fsCenter);
        if (d > c.fsRadius + img.r[i]) {
            stats_->culledSphereSphere++;
            return false;
        }
    }
    const uint32_t r =
        eyeInside ? mask
        : strat == CullStrategy::Aabb
            ? kernel::boxMasked(c.kplanes, mask, img.cx[i], img.cy[i], img.cz[i], img.ex[i], img.ey[i], img.ez[i])
            : kernel::sphereMasked(c.kplanes, mask, img.cx[i], img.cy[i], img.cz[i], img.r[i]);
    if (r == kernel::kCulledMask) {
        stats_->culledFrustum++;
        return false;
    }
    mask = r;
    const uint32_t n = img.end[i] - i - 1;
    if (mask && n > 0 && n <= kBatch) {
        // The bound straddles: classify everything below it in one flat pass against the planes still
        // in play; the walk below looks its answers up.
        const kernel::Planes kp =
            mask == cull::kAllPlanes ? c.kplanes : kernel::Planes::make(c.planes, dvec3(0.0), img.extent, mask);
        const size_t off = cls_.size();
        cls_.resize(off + n);
        uint8_t* o = cls_.data() + off;
        const uint32_t b = i + 1;
        // Spheres for every strategy: a sphere bounds the content as a box does, so "outside" and "inside"
        // answers hold for boxes too; the box strategy tests only the straddling ones again (above).
        kernel::classifySpheres(kp, &img.cx[b], &img.cy[b], &img.cz[b], &img.r[b], n, o);
        if (strat == CullStrategy::SphereSphere) {
            const float fx = float(c.fsCenter.x), fy = float(c.fsCenter.y), fz = float(c.fsCenter.z),
                        fr = float(c.fsRadius);
            for (uint32_t k = 0; k < n; ++k) {
                const float dx = img.cx[b + k] - fx, dy = img.cy[b + k] - fy, dz = img.cz[b + k] - fz;
                const float reach = fr + img.r[b + k];
                if (dx * dx + dy * dy + dz * dz > reach * reach) o[k] = kernel::kOutside | kBySphereSphere;
            }
        }
        c.clsOffset = off;
        c.clsBase = b;
        stats_->kernelEntries += n;
    }
    return true;
}

// Many children over a large subtree: classify their spheres, kept side by side, in one kernel pass.
void CullTraversal::wideChildren(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ) {
    const FlatImage& img = *c.img;
    const FlatImage::Wide w = img.wides[img.aux[i] - 1];
    const kernel::Planes kp =
        mask == cull::kAllPlanes ? c.kplanes : kernel::Planes::make(c.planes, dvec3(0.0), img.extent, mask);
    const size_t off = cls_.size();
    cls_.resize(off + w.count);
    kernel::classifySpheres(kp, &img.wcx[w.first], &img.wcy[w.first], &img.wcz[w.first], &img.wr[w.first], w.count,
                            cls_.data() + off);
    stats_->kernelEntries += w.count;
    for (uint32_t k = 0; k < w.count; ++k) {
        const uint8_t r = cls_[off + k];
        if (r & kernel::kOutside) {
            stats_->boundsTested++;
            stats_->culledFrustum++;
            continue;
        }
        // Inside: no test left below. Straddling: the child's own test runs again (and may batch).
        visit(c, img.wideEntry[w.first + k], (r & kernel::kInside) && set_->measureOnly.planeMasking ? 0u : mask, m,
              occ);
    }
    cls_.resize(off);
}

}  // namespace sg
