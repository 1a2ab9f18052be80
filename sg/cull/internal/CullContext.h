// What the parts of CullTraversal share (CullTraversal.cpp: the frame; CullVisit.cpp: the walk and a handler
// per node kind; CullBounds.cpp: the bound tests; CullEmit.cpp: the fast path and the draw items): the per-image
// context and the LOD handler, which the walk and the fast path both use.
// Internal header (an internal/ folder): not installed; its shape may change freely.
#pragma once
#include "sg/cull/CullTraversal.h"
#include "sg/cull/internal/FrustumKernel.h"
#include "sg/lod/internal/LodChooser.h"

#include <array>

namespace sg {

// Per image: where it is (ImageFrame), and the planes and frames the tests need, in that image's coordinates.
struct CullTraversal::Ctx : ImageFrame {
    dvec3 viewDir{0.0};    // the camera's view direction (eye-relative world)
    dvec3 originRel{0.0};  // the image origin relative to the eye (occlusion tests, main image only)
    std::array<Plane, 6> planes{};
    kernel::Planes kplanes{};
    float fbMin[3]{}, fbMax[3]{};  // the frustum's bounding box (centre-box strategy)
    dvec3 fsCenter{0.0};           // the frustum's bounding sphere (sphere-sphere strategy)
    double fsRadius = 0.0;
    size_t clsOffset = 0;  // into cls_, valid when clsBase != kNone
    uint32_t clsBase = ~0u;
    const uint64_t* pvsHidden = nullptr;  // the eye cell's hidden entries (main image only), or null
    // The LOD budget: this image's index in places_ once one of its LODs is set aside (-1: none yet), and
    // which placement it is (0: the scene's image; an Instance's: its parent's key and its entry, mixed).
    int32_t place = -1;
    uint64_t key = 0;
    uint32_t pagedDepth = 0;  // the paged nodes whose details hold this image (0: the scene's image)
};

namespace cull {
constexpr uint32_t kAllPlanes = 0x3f;
inline bool pvsHides(const uint64_t* hidden, uint32_t i) { return hidden && ((hidden[i >> 6] >> (i & 63)) & 1u); }
}  // namespace cull

// LOD entry i: the chooser's children, each walked by walk(entry) with the fade it gives; the scene's LODs
// remember what they showed (hysteresis). While the budget plans, the entry is set aside instead.
template <class Walk>
void CullTraversal::lod(Ctx& c, uint32_t i, uint32_t mask, int32_t occ, const dmat4& m, const Walk& walk) {
    if (planning_) return defer(c, i, mask, occ, m);
    auto show = [&](const LodChooser::Shown& s) {
        if (!s.setsFade) return walk(s.entry);
        const float outer = fade_;
        fade_ = s.fade;
        walk(s.entry);
        fade_ = outer;
    };
    if (!(lodTracked_ && c.img == &scene_->image())) {
        chooser_->choose(c, i, {}, show);
        return;
    }
    LodChooser::Known k;
    k.last = lodHistory_.last(i);
    stats_->lodChanged += lodHistory_.show(i, chooser_->choose(c, i, k, show));
}

}  // namespace sg
