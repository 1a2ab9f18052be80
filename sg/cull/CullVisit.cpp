// The cull's walk: visit() runs an entry's tests, then the handler of its node kind, each a few lines.
#include "nodes/Billboard.h"
#include "nodes/BspGroup.h"
#include "nodes/Instance.h"
#include "nodes/PagedLOD.h"
#include "nodes/Switch.h"
#include "sg/cull/internal/CullContext.h"
#include "sg/scene/internal/ImageWalk.h"

#include <algorithm>
#include <cmath>

namespace sg {

// Entry i's tests in order (the PVS, masks, the planes, small features, occlusion), then its kind's handler.
void CullTraversal::visit(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ) {
    const FlatImage& img = *c.img;
    stats_->nodesVisited++;
    if (cull::pvsHides(c.pvsHidden, i)) {
        stats_->culledPvs++;
        return;
    }
    const uint8_t fl = img.flags[i];
    if (fl & FlatImage::kEmpty) return;
    if ((fl & FlatImage::kMasked) && !(img.maskOf(i) & set_->traversalMask)) return;
    const uint32_t maskIn = mask;
    // A batch started by this entry's test covers its subtree: restore the enclosing one on return.
    struct BatchScope {
        CullTraversal& t;
        Ctx& c;
        const uint32_t base;
        const size_t off;
        ~BatchScope() {
            if (c.clsBase != base) t.cls_.resize(c.clsOffset);
            c.clsBase = base;
            c.clsOffset = off;
        }
    } scope{*this, c, c.clsBase, c.clsOffset};
    if (mask && !(fl & FlatImage::kNoTest) && !(fl & FlatImage::kInvalid)) {
        const uint32_t before = mask;
        if (!test(c, i, mask)) return;
        if (!set_->measureOnly.planeMasking) mask = before;
    }
    if (set_->smallFeaturePixels > 0.0 && !(fl & FlatImage::kInvalid)) {
        const double dist = glm::length(img.center(i) - img.origin - c.eyeImg);
        if (cam_->pixelSize(2.0 * img.r[i] * c.scale, dist) < set_->smallFeaturePixels) {
            stats_->culledSmallFeature++;
            return;
        }
    }
    // Occlusion: Transform and LOD entries leave it to their children (same bounds, one test fewer).
    if (occ != OcclusionTree::kVisible && !(fl & FlatImage::kInvalid)) {
        const NodeKind k = img.kind[i];
        const bool posed = fl & FlatImage::kPosed;  // its mesh's boxes are of the bind pose: the bound alone
        if (k != NodeKind::Transform && k != NodeKind::LOD && k != NodeKind::Occluder &&
            !occlusion_.test(img, c.originRel, i, occ, *stats_, k == NodeKind::Geometry && !posed ? &m : nullptr))
            return;
    }
    if (fl & FlatImage::kFeature) return featureNode(c, i, mask, maskIn, m, occ);
    handle(c, i, mask, maskIn, m, occ);
}

// A feature node: the items its subtree emits are noted with it as one range once the walk leaves it (emit itself
// checks nothing, and visit() only the flag: scenes without features pay nothing per item).
void CullTraversal::featureNode(Ctx& c, uint32_t i, uint32_t mask, uint32_t maskIn, const dmat4& m, int32_t occ) {
    const size_t first = out_->items.size();
    handle(c, i, mask, maskIn, m, occ);
    const FlatImage::FeatureRef* f = c.img->featureOf(i);
    if (f && out_->items.size() > first)
        out_->features.push_back({uint32_t(first), uint32_t(out_->items.size()), f->features.get(), f->index});
}

// Entry i's kind's handler, its tests passed (`maskIn`: the planes' mask before its own test).
inline void CullTraversal::handle(Ctx& c, uint32_t i, uint32_t mask, uint32_t maskIn, const dmat4& m, int32_t occ) {
    switch (c.img->kind[i]) {
        case NodeKind::Geometry:
            // (the centre-box test clears the mask without the bound being inside)
            emit(c, i, m, maskIn == 0 || (mask == 0 && set_->strategy != CullStrategy::CenterBox));
            break;
        case NodeKind::Transform: children(c, i, mask, transformed(*c.img, i, m), occ); break;
        case NodeKind::LOD: lod(c, i, mask, occ, m, [&](uint32_t j) { visit(c, j, mask, m, occ); }); break;
        case NodeKind::Switch: switchChildren(c, i, mask, m, occ); break;
        case NodeKind::Billboard: billboard(c, i, m); break;
        case NodeKind::Instance: instance(c, i, mask, m); break;
        case NodeKind::BspGroup: bspGroup(c, i, mask, m, occ); break;
        case NodeKind::PagedLOD: pagedLod(c, i, mask, m, occ); break;
        case NodeKind::Occluder: break;  // used by the occlusion passes, never drawn
        case NodeKind::Group: group(c, i, mask, m, occ); break;
    }
}

void CullTraversal::group(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ) {
    if (mask && c.img->aux[i] && c.clsBase == ~0u) return wideChildren(c, i, mask, m, occ);
    children(c, i, mask, m, occ);
}

void CullTraversal::switchChildren(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ) {
    const FlatImage& img = *c.img;
    const uint8_t* on = img.switchOn.data() + img.aux[i];  // the bits as of the update, not the node's
    uint32_t j = i + 1;
    for (size_t k = 0; j < img.end[i]; ++k, j = img.end[j])
        if (on[k]) visit(c, j, mask, m, occ);
}

void CullTraversal::billboard(Ctx& c, uint32_t i, const dmat4& m) {
    const auto* bb = static_cast<Billboard*>(c.img->nodes[c.img->aux[i]]);
    const dvec3 eyeLocal(glm::inverse(m) * dvec4(0, 0, 0, 1));
    // Its own tests covered the children (their bounds are the billboard's).
    children(c, i, 0u, m * bb->rotationToward(eyeLocal), OcclusionTree::kVisible);
}

void CullTraversal::instance(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m) {
    const FlatImage::Placement& place = c.img->placements[c.img->aux[i]];
    const FlatImage* p = place.proto;
    if (!p || p->size() == 0 || (prefetchOnly_ && p->paged.empty())) return;
    stats_->instancesVisited++;
    const dmat4 pm =
        place.matrix != FlatImage::kNone ? m * c.img->matrices[place.matrix] : glm::translate(m, place.translation);
    const uint32_t subMask = set_->strategy == CullStrategy::None ? 0u : mask;
    if (placementDepth_ == placementCtx_.size()) placementCtx_.push_back(std::make_shared<Ctx>());
    Ctx& sub = *placementCtx_[placementDepth_];
    setupCtx(sub, *p, glm::translate(pm, p->origin), subMask != 0);  // no planes for a placement inside them
    sub.originRel = dvec3(0.0);
    sub.clsOffset = 0;
    sub.clsBase = ~0u;
    sub.pvsHidden = nullptr;
    sub.place = -1;
    sub.key = (c.key ^ i) * 0x9E3779B97F4A7C15ull + 1;  // this placement, under its parent's
    sub.pagedDepth = c.pagedDepth;
    // Same six planes, transformed: planes the placement's bound was inside of stay done. The placement's
    // own bound had its occlusion test; its prototype's bounds are not world boxes, so none below.
    struct Depth {
        size_t& d;
        ~Depth() { --d; }
    } depth{++placementDepth_};
    visit(sub, 0, subMask, pm, OcclusionTree::kVisible);
}

void CullTraversal::bspGroup(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ) {
    const FlatImage& img = *c.img;
    const auto* g = static_cast<BspGroup*>(img.nodes[img.aux[i]]);
    const dvec3 eyeLocal(glm::inverse(m) * dvec4(0, 0, 0, 1));
    // Child entry indices by child number, then the BSP's front-to-back order over them; indexed, as the
    // BspGroups below push onto scratch_ too.
    const size_t base = scratch_.size();
    for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j]) scratch_.push_back(j);
    const size_t nChildren = scratch_.size() - base;
    g->order(eyeLocal, bspOrder_);
    scratch_.insert(scratch_.end(), bspOrder_.begin(), bspOrder_.end());
    const size_t orderEnd = scratch_.size();
    for (size_t o = base + nChildren; o < orderEnd; ++o)
        if (scratch_[o] < nChildren) visit(c, scratch_[base + scratch_[o]], mask, m, occ);
    scratch_.resize(base);
}

// How much paged entry i's detail is needed, for the pager's queue (bigger first, as Cesium orders its requests):
//     priority = -depth + 0.99 * (0.75 * need + 0.25 * centred)
// - depth: the paged nodes whose details hold this entry. It dominates: a parent's detail is asked for before
//   its children's, so that no level is skipped on the way down.
// - need = clamp(log2(excess) / 10, 0, 1), excess how far the LOD value is past the threshold that made the detail
//   wanted: value / min in pixel-size mode (min 0 counts as 1 pixel), max / value in distance mode (the nearer,
//   the more; an unbounded range gives 1 + 1 / value). 1 where no value is measured (finest rules, no camera).
// - centred = (1 + cos a) / 2, a the angle between the view direction and the direction to the node's centre:
//   what is in the middle of the view first.
// Within one depth the priority lies in [-depth, -depth + 0.99].
float CullTraversal::pagedPriority(const Ctx& c, uint32_t i) const {
    const FlatImage::Paged& p = c.img->paged[c.img->aux[i]];
    double need = 1.0;
    const LodChooser::Rules& r = chooser_->rules();
    if (!r.finest && (r.camera || p.lod.mode != uint8_t(LOD::Mode::PixelSize))) {
        const double v = chooser_->value(c, p.lod, i);
        double excess;
        if (p.lod.mode == uint8_t(LOD::Mode::PixelSize))
            excess = v / std::max(double(p.min), 1.0);
        else
            excess = std::isfinite(p.max) ? double(p.max) / std::max(v, 1e-9) : 1.0 + 1.0 / std::max(v, 1e-9);
        need = std::clamp(std::log2(std::max(excess, 1e-30)) / 10.0, 0.0, 1.0);
    }
    const dvec3 rel(c.imgToEye * dvec4(p.lod.cx, p.lod.cy, p.lod.cz, 1.0));
    const double len = glm::length(rel);
    const double cosA = len > 0.0 ? std::clamp(glm::dot(rel / len, c.viewDir), -1.0, 1.0) : 1.0;
    const double centred = 0.5 * (1.0 + cosA);
    return float(-double(c.pagedDepth) + 0.99 * (0.75 * need + 0.25 * centred));
}

// The detail when it is wanted and attached, else the coarse children. A wanted detail that is not loaded is
// posted for the pager once per update, with its priority, and the coarse level drawn meanwhile: the frame
// never waits for it. Every wanted node keeps the priority of its last mark, so that a request queued already
// follows the view.
void CullTraversal::pagedLod(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ) {
    const FlatImage& img = *c.img;
    const FlatImage::Paged& p = img.paged[img.aux[i]];
    auto* node = static_cast<PagedLOD*>(p.node);
    const bool wanted = chooser_->detailWanted(c, i);
    if (wanted && node->trigger() == PagedLOD::Trigger::Range) {
        stats_->pagedWanted++;
        if (node->markNeeded(scene_->updateCount())) {
            const float priority = pagedPriority(c, i) - (prefetchOnly_ ? kPrefetchPriorityDrop : 0.0f);
            node->setNeedPriority(priority);  // a request queued already takes it at the pager's update
            const PagedLOD::State st = node->state();
            // A failed node is asked for again once its back-off has passed (the pager sets retryTime()).
            if (st == PagedLOD::State::Unloaded ||
                (st == PagedLOD::State::Failed && scene_->frame().time >= node->retryTime())) {
                scene_->pageRequests().post(node, priority, p.frame);
                stats_->pagedRequested++;
            }
        }
    }
    if (wanted && p.detail) {
        // The detail's image is in this image's frame, shifted to its own origin: the same planes (and the
        // plane mask), the same occlusion tree.
        const FlatImage& d = *p.detail;
        if (d.size() == 0 || (prefetchOnly_ && d.paged.empty())) return;  // nothing to look ahead for there
        Ctx sub;
        setupCtx(sub, d, c.imgToEye * glm::translate(dmat4(1.0), d.origin - img.origin));
        sub.originRel = c.originRel + (d.origin - img.origin);
        sub.pagedDepth = c.pagedDepth + 1;
        visit(sub, 0, mask, m, occ);
        return;
    }
    if (wanted) stats_->pagedCoarse++;
    // A look-ahead walks the coarse level only for the paged nodes in it (a tile's content holds none).
    if (prefetchOnly_ && std::find(img.kind.begin() + i + 1, img.kind.begin() + img.end[i], NodeKind::PagedLOD) ==
                             img.kind.begin() + img.end[i])
        return;
    children(c, i, mask, m, occ);
}

void CullTraversal::children(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ) {
    const FlatImage& img = *c.img;
    if (mask == 0 && set_->smallFeaturePixels == 0.0 && occ == OcclusionTree::kVisible)
        return inside(c, i + 1, img.end[i], m);
    for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j]) visit(c, j, mask, m, occ);
}

}  // namespace sg
