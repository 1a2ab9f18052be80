// The occlusion-tree pass of CullTraversal: which occluders grow this frame's tree, and the test of one
// entry's bound against it.
#include "nodes/Occluder.h"
#include "sg/cull/CullTraversal.h"

#include <algorithm>
#include <chrono>

namespace sg {

namespace {
using Clock = std::chrono::steady_clock;

// Is the eye-relative box outside one of the frustum's planes?
bool outsideFrustum(const std::array<Plane, 6>& planes, const dvec3& lo, const dvec3& hi) {
    for (const Plane& p : planes) {
        const dvec3 far(p.n.x >= 0 ? hi.x : lo.x, p.n.y >= 0 ? hi.y : lo.y, p.n.z >= 0 ? hi.z : lo.z);
        if (p.distance(far) < 0) return true;
    }
    return false;
}
}  // namespace

// Grows this frame's tree; returns the node the walk's tests start at (kVisible: no tests at all).
int32_t CullTraversal::buildOcclusion(const FlatImage& img) {
    const CullSettings& set = *set_;
    const OcclusionSettings& os = set.occlusion;
    otree_.reset(cam_->eye(), OcclusionTree::Options{});
    // Nothing to do: no occluders in the scene, the reference render (no culling), the pass turned off,
    // an orthographic camera (the tree's planes pass through an eye point).
    if (img.occluders.empty() || os.mode == OcclusionMode::Off || set.strategy == CullStrategy::None ||
        !cam_->perspective() || os.maxOccluders == 0)
        return OcclusionTree::kVisible;
    if (os.mode == OcclusionMode::Auto && autoWait_ > 0) {
        --autoWait_;
        stats_->occlusionSkipped = true;
        return OcclusionTree::kVisible;
    }
    const auto t0 = Clock::now();
    const dvec3 eye = cam_->eye();
    const auto& planes = cam_->eyePlanes();
    const double ppu = cam_->pixelsPerUnit();
    const double zNear = std::max(-planes[4].d, 1e-9);

    // Candidates: active occluders in the frustum, large enough on screen, by distance.
    cands_.clear();
    const uint32_t chunk = FlatImage::kOccluderChunk;
    for (size_t k = 0; k < img.occluderChunks.size(); ++k) {
        const Box& b = img.occluderChunks[k];
        if (b.empty() || outsideFrustum(planes, b.min - eye, b.max - eye)) continue;
        const uint32_t end = uint32_t(std::min<size_t>(img.occluders.size(), (k + 1) * chunk));
        for (uint32_t j = uint32_t(k * chunk); j < end; ++j) {
            const FlatImage::OccluderRef& o = img.occluders[j];
            if (!o.active) continue;
            const uint32_t e = o.entry;
            if (img.flags[e] & (FlatImage::kEmpty | FlatImage::kInvalid)) continue;
            const dvec3 c = img.origin + dvec3(img.cx[e], img.cy[e], img.cz[e]) - eye,
                        h(img.ex[e], img.ey[e], img.ez[e]);
            if (outsideFrustum(planes, c - h, c + h)) continue;
            const dvec3 gap = glm::max(glm::abs(c) - h, dvec3(0.0));  // eye to the box
            const double dist = glm::length(gap);
            if (2.0 * img.r[e] * ppu < os.minOccluderPixels * std::max(dist, zNear)) continue;
            cands_.push_back({dist, j});
        }
    }
    stats_->occluderCandidates = cands_.size();
    // Nearest first: nearer occluders hide farther ones, whose parts then add nothing to the tree.
    const size_t keep = std::min(cands_.size(), size_t(os.maxOccluders) * 4);
    auto byDist = [](const Candidate& a, const Candidate& b) {
        return a.dist < b.dist || (a.dist == b.dist && a.index < b.index);
    };
    std::nth_element(cands_.begin(), cands_.begin() + ptrdiff_t(keep), cands_.end(), byDist);
    std::sort(cands_.begin(), cands_.begin() + ptrdiff_t(keep), byDist);

    otree_.reset(eye, OcclusionTree::optionsFor(*cam_, os));
    uint64_t used = 0;
    for (size_t k = 0; k < keep && used < os.maxOccluders; ++k) {
        const FlatImage::OccluderRef& o = img.occluders[cands_[k].index];
        const auto* node = static_cast<const Occluder*>(o.node);
        const dmat4* m = o.matrix == ~0u ? nullptr : &img.occluderMatrices[o.matrix];
        bool added;
        if (node->shape() == Occluder::Shape::Box) {
            const Box& lb = node->box();
            added = m ? otree_.insertBox(lb, m) : otree_.insertBox(Box{lb.min + o.shift, lb.max + o.shift});
        } else {
            polyScratch_.clear();
            for (const dvec3& v : node->polygon()) polyScratch_.push_back(m ? dvec3(*m * dvec4(v, 1.0)) : v + o.shift);
            added = otree_.insertPolygon(polyScratch_.data(), polyScratch_.size());
        }
        used += added;
    }
    stats_->occlusionRan = true;
    stats_->occludersUsed = used;
    stats_->occlusionTreeNodes = otree_.nodeCount();
    stats_->occlusionPolygonSplits = otree_.polygonSplits();
    stats_->occlusionMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    return otree_.empty() ? OcclusionTree::kVisible : otree_.root();
}

// False when entry i is occluded; else `occ` is where the tests of the entries below it start.
bool CullTraversal::occlusionTest(const FlatImage& img, const dvec3& originRel, uint32_t i, int32_t& occ) {
    const auto t0 = Clock::now();
    const dvec3 ctr = originRel + dvec3(img.cx[i], img.cy[i], img.cz[i]), h(img.ex[i], img.ey[i], img.ez[i]);
    stats_->occlusionTests++;
    // The eye in the plane of one of the bound's faces (within the float bound's rounding): a face of the
    // content may be seen exactly edge-on there, and the rasterizer draws such a face as a sliver with a
    // depth that is not the face's (nearer, through walls). Not culled; the entries below are tested.
    const double slack = 1e-6 * (std::abs(img.cx[i]) + std::abs(img.cy[i]) + std::abs(img.cz[i]) + h.x + h.y + h.z);
    const dvec3 gap = glm::abs(glm::abs(ctr) - h);
    if (gap.x <= slack || gap.y <= slack || gap.z <= slack) {
        occlusionTestMs_ += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        return true;
    }
    const auto r = otree_.testRelative(ctr - h, ctr + h, occ);
    occlusionTestMs_ += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (r != OcclusionTree::Result::Occluded) return true;
    stats_->culledOcclusion++;
    stats_->occludedEntries += img.end[i] - i;
    return false;
}

}  // namespace sg
