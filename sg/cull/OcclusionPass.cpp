#include "sg/cull/OcclusionPass.h"

#include "nodes/Occluder.h"
#include "sg/lod/internal/LodChooser.h"
#include "sg/scene/ImageFrame.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

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
// Whether the conditions listed for a path (FlatImage::OccluderRef::switchFirst, Paged::condFirst) hold this frame:
// its Switch children on, its masked nodes seen, its PagedLODs showing their coarse children (the walk takes a
// detail where it is wanted and attached, CullTraversal::pagedLod).
bool pathHolds(const ImageFrame& f, uint32_t first, uint32_t count, const LodChooser& lods, uint32_t mask) {
    const FlatImage& img = *f.img;
    for (uint32_t k = 0; k < count; ++k) {
        const uint32_t c = img.occluderSwitchBits[first + k];
        if (c & FlatImage::kMaskCondition) {
            if (!(img.maskOf(c & ~FlatImage::kMaskCondition) & mask)) return false;
        } else if (c & FlatImage::kPagedCondition) {
            const uint32_t e = c & ~FlatImage::kPagedCondition;
            if (img.paged[img.aux[e]].detail && lods.detailWanted(f, e)) return false;
        } else if (!img.switchOn[c]) {
            return false;
        }
    }
    return true;
}

// An occluder's conditions this frame: its path's, and a generated one's (Occluder::eyeOutside, openings, oneSided,
// shownWith, belowSurface).
bool conditionsHold(const ImageFrame& f, const FlatImage::OccluderRef& o, const Camera& cam, const CullSettings& set,
                    const LodChooser& lods) {
    const FlatImage& img = *f.img;
    const auto* node = static_cast<const Occluder*>(o.node);
    const dmat4* m = o.matrix == ~0u ? nullptr : &img.occluderMatrices[o.matrix];
    const dvec3 eye = cam.eye();
    if (!pathHolds(f, o.switchFirst, o.switchCount, lods, set.traversalMask)) return false;
    // How far from the eye the near plane's corners reach: a surface farther than this is not clipped by it.
    auto nearReach = [&] {
        const dmat4& p = cam.projection();
        const double sx = (1.0 + std::abs(p[2][0])) / p[0][0], sy = (1.0 + std::abs(p[2][1])) / p[1][1];
        return 1.001 * cam.nearDistance() * std::sqrt(1.0 + sx * sx + sy * sy);
    };
    if (!node->eyeOutside().empty()) {
        // Outside the box's world bound is outside the box. And the surface a sight line crosses before the
        // occluder lies in that box: grown by the reach of the near plane's corners, no such crossing is clipped.
        const Box& lb = node->eyeOutside();
        Box wb = m ? transformBox(*m, lb) : Box{lb.min + o.shift, lb.max + o.shift};
        const double reach = nearReach();
        wb.min -= dvec3(reach), wb.max += dvec3(reach);
        if (wb.contains(eye)) return false;
    }
    if (!node->openings().empty()) {
        // Every plane has the box on its positive side and its opening's cap on the other (MeshOccluders.cpp): a
        // segment from an eye on the positive side to the box stays there and meets no cap, so what it crosses of
        // the closed solid's surface is drawn. The margin covers the eye's rounding into the frame.
        // (The terms the inverse sums are up to its scale times the eye's magnitude, whatever the sum's.)
        dvec3 le = eye - o.shift;
        double terms = std::abs(eye.x) + std::abs(eye.y) + std::abs(eye.z);
        if (m) {
            const dmat4 inv = glm::inverse(*m);
            le = dvec3(inv * dvec4(eye, 1.0));
            terms *= maxScale(inv);
        }
        const double margin = 1e-12 * terms + 1e-9 * (std::abs(le.x) + std::abs(le.y) + std::abs(le.z)) + 1e-300;
        for (const Plane& p : node->openings())
            if (!(p.distance(le) > margin)) return false;
    }
    if (const OccluderSurface* s = node->belowSurface()) {
        // A box below a height field z = h(x, y) that is drawn whole and without cracks over its rectangle (the
        // column over it is convex), the eye in that column and higher than every surface point within `reach` of
        // it by more than `reach`: the segment from the eye to any point of the box stays in the column, starts
        // above the surface and ends below it, so it crosses the surface; the first crossing is farther than
        // `reach` from the eye (its xy is, or it lies lower than eye.z - reach), so the near plane does not clip
        // it, and it is nearer than anything the box hides, so neither does the far plane, nor the frustum's
        // sides (the segment runs inside the view's cone). No terrain occluder stands in front of that first
        // crossing (the segment is above the surface before it, the boxes below), so its tile is drawn, or hidden
        // by some other occluder: whatever the box hides is behind drawn pixels. That needs every tile drawn:
        // small-feature culling may drop one, the budget may leave its LOD out, hysteresis picks levels by last
        // frame's choice (the builder's ranges cover [0, FLT_MAX) from the finest level up, so the plain ranges
        // always show one, and it sets no fade bands, so no tile dissolves; the pass also checks the tile's own LOD by
        // Occluder::shownWith, fade band included); the builder puts no Switch or node mask over a tile (an
        // application that hides tiles, or gives them transitions, removes these).
        if (set.smallFeaturePixels > 0.0 || set.lodBudget.enabled || set.lodHysteresis > 0.0) return false;
        dvec3 le = eye - o.shift;
        double reach = nearReach();
        if (m) {
            // The eye in the frame, and a reach there that covers the world's: |M v| >= |v| / |M^-1|_2, and the
            // Frobenius norm bounds the 2-norm from above.
            const dmat4 inv = glm::inverse(*m);
            le = dvec3(inv * dvec4(eye, 1.0));
            const glm::dmat3 l(inv);
            reach *= std::sqrt(glm::dot(l[0], l[0]) + glm::dot(l[1], l[1]) + glm::dot(l[2], l[2]));
        }
        if (!(le.x >= s->min.x && le.x <= s->max.x && le.y >= s->min.y && le.y <= s->max.y)) return false;
        // The highest sample of every cell whose rectangle comes within reach of the eye's xy (a square about it,
        // padded past the float rounding of the cells' drawn edges).
        const double cw = (s->max.x - s->min.x) / s->cellsX, ch = (s->max.y - s->min.y) / s->cellsY;
        const double pad =
            reach + 1e-6 * (std::abs(s->min.x) + std::abs(s->max.x) + std::abs(s->min.y) + std::abs(s->max.y));
        auto cell = [](double v, int count) { return int(std::clamp(std::floor(v), 0.0, double(count - 1))); };
        const int i0 = cell((le.x - pad - s->min.x) / cw, s->cellsX),
                  i1 = cell((le.x + pad - s->min.x) / cw, s->cellsX);
        const int j0 = cell((le.y - pad - s->min.y) / ch, s->cellsY),
                  j1 = cell((le.y + pad - s->min.y) / ch, s->cellsY);
        double top = -std::numeric_limits<double>::infinity();
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) top = std::max(top, s->highest[size_t(j) * size_t(s->cellsX) + size_t(i)]);
        if (!(le.z - reach > top)) return false;
    }
    if (node->oneSided()) {
        const auto& p = node->polygon();
        dvec3 n(0.0), v0 = m ? dvec3(*m * dvec4(p[0], 1.0)) : p[0] + o.shift;
        for (size_t k = 0; k < p.size(); ++k) {
            const dvec3 a = m ? dvec3(*m * dvec4(p[k], 1.0)) : p[k] + o.shift,
                        b = m ? dvec3(*m * dvec4(p[(k + 1) % p.size()], 1.0)) : p[(k + 1) % p.size()] + o.shift;
            n += glm::cross(a - v0, b - v0);
        }
        if (!(glm::dot(n, eye - v0) > 0.0)) return false;  // its back, or edge on: not drawn from here
    }
    if (node->shownWith()) {
        // The box lies inside every level, so it stands for the LOD wherever the LOD's ranges (with the fade band
        // about the value, where a level may be dissolving to nothing) cover the value. The budget and hysteresis
        // choose levels by other rules: not used with them.
        if (o.lod == ~0u || set.lodBudget.enabled || set.lodHysteresis > 0.0) return false;
        const FlatImage::Lod& l = LodChooser::lod(img, o.lod);
        const double v = lods.value(f, l, o.lod);
        const double h = set.lodFade ? 0.5 * double(l.fade) : 0.0;
        double lo = std::max(v - h, 0.0);
        const double hi = v + h;
        // Cover [lo, hi] with the children's ranges, joined end to end.
        const FlatImage::Range* rg = &img.ranges[l.firstRange];
        size_t count = 0;
        for (uint32_t j = o.lod + 1; j < img.end[o.lod]; j = img.end[j]) ++count;
        for (bool moved = true; moved && lo <= hi;) {
            moved = false;
            for (size_t c = 0; c < count; ++c)
                if (rg[c].min <= lo && lo < rg[c].max) {
                    lo = rg[c].max;
                    moved = true;
                }
        }
        if (lo <= hi) return false;
    }
    return true;
}

constexpr double kWakeShare =
    0.25;  // Adaptive: the eye's move, over its distance to the nearest occluder, that wakes it
}  // namespace

int32_t OcclusionPass::build(const FlatImage& img, const Camera& cam, const CullSettings& set, CullStats& stats) {
    const OcclusionSettings& os = set.occlusion;
    os.validate("OcclusionPass::build()");
    testMs_ = 0.0;
    hom_ = false;
    tree_.reset(cam.eye(), OcclusionTree::Options{});
    // Nothing to do: no occluders in the scene (nor paged details that may hold some), the reference render (no
    // culling), the pass turned off, an orthographic camera (the tree's planes pass through an eye point).
    if ((img.occluders.empty() && img.paged.empty()) || os.mode == OcclusionMode::Off ||
        set.strategy == CullStrategy::None || !cam.perspective() ||
        (os.method == OcclusionMethod::Hom ? os.homMaxOccluders : os.maxOccluders) == 0 ||
        (os.method == OcclusionMethod::Auto && os.homMaxOccluders == 0))
        return OcclusionTree::kVisible;
    // Adaptive's back-off holds while the view is much as it was when the pass last ran: the eye has moved less
    // than a quarter of the way to the nearest occluder it had then (an eye inside an occluder's box, at 0,
    // wakes it with any step: leaving a building, the site behind the next one is culled at once).
    if (os.mode == OcclusionMode::Adaptive && skipLeft_ > 0 && ranNear_ >= 0.0 &&
        glm::length(cam.eye() - ranEye_) > kWakeShare * ranNear_)
        wake();
    if (os.mode == OcclusionMode::Adaptive && skipLeft_ > 0) {
        --skipLeft_;
        stats.occlusionSkipped = true;
        return OcclusionTree::kVisible;
    }
    const auto t0 = Clock::now();
    const dvec3 eye = cam.eye();
    const auto& planes = cam.eyePlanes();

    // A thin occluder lying on a face of the scene's bound, the eye on its inner side (a floor, a ground slab), hides
    // only what is within its own thickness: it would take the place of a wall.
    const Box sb = img.size() ? img.box(0) : Box{};
    const dvec3 sLo = sb.min - eye, sHi = sb.max - eye, sExt = sb.max - sb.min;
    auto flatOnBound = [&](const dvec3& c, const dvec3& h) {
        for (int a = 0; a < 3; ++a) {
            if (2.0 * h[a] > 0.1 * sExt[a]) continue;
            const double tol = 1e-3 * sExt[a];
            if ((c[a] + h[a] < 0.0 && c[a] - h[a] <= sLo[a] + tol) ||
                (c[a] - h[a] > 0.0 && c[a] + h[a] >= sHi[a] - tol))
                return true;
        }
        return false;
    };
    // Candidates: active occluders in the frustum, large enough on screen, by distance; in the scene's image and in
    // the images of the paged details drawn this frame (a tileset's tiles).
    cands_.clear();
    const LodChooser lods({&cam, set.lodScale});
    auto gather = [&](const FlatImage& im, const ImageFrame& f) {
        const uint32_t chunk = FlatImage::kOccluderChunk;
        for (size_t k = 0; k < im.occluderChunks.size(); ++k) {
            const Box& b = im.occluderChunks[k];
            if (b.empty() || outsideFrustum(planes, b.min - eye, b.max - eye)) continue;
            const uint32_t end = uint32_t(std::min<size_t>(im.occluders.size(), (k + 1) * chunk));
            for (uint32_t j = uint32_t(k * chunk); j < end; ++j) {
                const FlatImage::OccluderRef& o = im.occluders[j];
                if (!o.active) continue;
                const uint32_t e = o.entry;
                if (im.flags[e] & (FlatImage::kEmpty | FlatImage::kInvalid)) continue;
                const dvec3 c = im.origin + dvec3(im.cx[e], im.cy[e], im.cz[e]) - eye, h(im.ex[e], im.ey[e], im.ez[e]);
                if (outsideFrustum(planes, c - h, c + h)) continue;
                if (flatOnBound(c, h)) continue;
                const dvec3 gap = glm::max(glm::abs(c) - h, dvec3(0.0));  // eye to the box
                const double dist = glm::length(gap);
                if (cam.pixelSize(2.0 * im.r[e], dist) < os.minOccluderPixels) continue;
                if (o.conditional && !conditionsHold(f, o, cam, set, lods)) continue;  // the dearest test last
                cands_.push_back({dist, j, 0.0, &im});
            }
        }
    };
    images_.clear();
    images_.push_back(&img);
    for (size_t at = 0; at < images_.size(); ++at) {
        const FlatImage& im = *images_[at];
        const ImageFrame f = ImageFrame::make(im, glm::translate(dmat4(1.0), im.origin - eye));
        gather(im, f);
        // A detail's image is in world coordinates as the scene's is (CullTraversal::pagedLod places it by its
        // origin alone). It is drawn where the walk reaches its PagedLOD and takes the detail: the same test here.
        for (const FlatImage::Paged& p : im.paged) {
            if (!p.detail || p.detail->size() == 0 || !p.plainPath) continue;
            const uint32_t e = p.entry;
            if (im.flags[e] & (FlatImage::kEmpty | FlatImage::kInvalid)) continue;
            const Box db = p.detail->box(0);
            if (db.empty() || outsideFrustum(planes, db.min - eye, db.max - eye)) continue;
            if (lods.detailWanted(f, e) && pathHolds(f, p.condFirst, p.condCount, lods, set.traversalMask))
                images_.push_back(p.detail.get());
        }
    }
    stats.occluderCandidates = cands_.size();
    ranEye_ = eye;
    ranNear_ = -1.0;  // no candidate: nothing the eye could come nearer to
    for (const Candidate& c : cands_) ranNear_ = ranNear_ < 0.0 ? c.dist : std::min(ranNear_, c.dist);
    uint64_t used = 0;
    hom_ = os.method == OcclusionMethod::Hom;
    if (!hom_) {
        used = addToTree(cam, os);
        hom_ = os.method == OcclusionMethod::Auto && treeLeavesOccludersVisible(eye, os.autoMapShare);
    }
    stats.occlusionMap = hom_;
    obbLevels_ = os.homObbLevels;
    if (hom_ && obbLevels_ > 0) obbs_.nextFrame();
    if (hom_) {
        // Larger and nearer first: the solid angle (radius over distance, squared) over the distance.
        for (Candidate& c : cands_) {
            const double d = std::max(c.dist, cam.nearDistance()), r = c.img->r[c.img->occluders[c.index].entry];
            c.dist = -(r * r) / (d * d * d);
        }
        tree_.reset(eye, OcclusionTree::Options{});
        used = addToMap(cam, os);
    }
    stats.occlusionRan = true;
    stats.occludersUsed = used;
    stats.occlusionTreeNodes = tree_.nodeCount();
    stats.occlusionPolygonSplits = tree_.polygonSplits();
    stats.occlusionMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (hom_) return map_.empty() ? OcclusionTree::kVisible : 0;  // 0: test against the map
    return tree_.empty() ? OcclusionTree::kVisible : tree_.root();
}

namespace {
struct ByDist {
    template <class C>
    bool operator()(const C& a, const C& b) const {
        return a.dist < b.dist || (a.dist == b.dist && a.index < b.index);
    }
};
struct ByOrder {
    template <class C>
    bool operator()(const C& a, const C& b) const {
        return a.order < b.order || (a.order == b.order && ByDist()(a, b));
    }
};
}  // namespace

namespace {
double sq(double x) { return x * x; }
}  // namespace

uint64_t OcclusionPass::addToTree(const Camera& cam, const OcclusionSettings& os) {
    // Near and large first: the distance over the squared radius (the size on screen times the size), so that nearer,
    // larger occluders hide farther ones, whose parts then add nothing to the tree, and a desk beside the eye does not
    // take a wall's place (docs/benchmarks.md, "Generated occluders": nearest first, and the size on screen alone, did
    // that with occluders made from every mesh).
    for (Candidate& c : cands_)
        c.order = std::max(c.dist, cam.nearDistance()) /
                  std::max(sq(double(c.img->r[c.img->occluders[c.index].entry])), 1e-300);
    const size_t keep = std::min(cands_.size(), size_t(os.maxOccluders) * 4);
    std::nth_element(cands_.begin(), cands_.begin() + ptrdiff_t(keep), cands_.end(), ByOrder());
    std::sort(cands_.begin(), cands_.begin() + ptrdiff_t(keep), ByOrder());
    tree_.reset(cam.eye(), OcclusionTree::optionsFor(cam, os));
    uint64_t used = 0;
    size_t k = 0;
    for (; k < keep && used < os.maxOccluders; ++k) {
        const FlatImage& img = *cands_[k].img;
        const FlatImage::OccluderRef& o = img.occluders[cands_[k].index];
        const auto* node = static_cast<const Occluder*>(o.node);
        const dmat4* m = o.matrix == ~0u ? nullptr : &img.occluderMatrices[o.matrix];
        bool added;
        if (node->shape() == Occluder::Shape::Box) {
            const Box& lb = node->box();
            added = m ? tree_.insertBox(lb, m) : tree_.insertBox(Box{lb.min + o.shift, lb.max + o.shift});
        } else {
            polyScratch_.clear();
            for (const dvec3& v : node->polygon()) polyScratch_.push_back(m ? dvec3(*m * dvec4(v, 1.0)) : v + o.shift);
            added = tree_.insertPolygon(polyScratch_.data(), polyScratch_.size());
        }
        used += added;
    }
    treeStop_ = k;
    treeKept_ = keep;
    return used;
}

bool OcclusionPass::treeLeavesOccludersVisible(const dvec3& eye, double share) {
    // The next nearest candidates after those the tree took (sorted by distance up to treeKept_): the ones
    // the map would add. Fewer than 8: nothing much to add.
    const size_t n = treeKept_ > treeStop_ ? treeKept_ - treeStop_ : 0;
    if (n < 8) return false;
    // The nearest of those the tree did not take (it takes them near and large first): the map would add them.
    std::nth_element(cands_.begin() + ptrdiff_t(treeStop_), cands_.begin() + ptrdiff_t(treeKept_), cands_.end(),
                     ByDist());
    size_t visible = 0;
    for (size_t k = treeStop_; k < treeKept_; ++k) {
        const FlatImage& img = *cands_[k].img;
        const uint32_t e = img.occluders[cands_[k].index].entry;
        const dvec3 c = img.origin + dvec3(img.cx[e], img.cy[e], img.cz[e]) - eye, h(img.ex[e], img.ey[e], img.ez[e]);
        int32_t resume = tree_.root();
        visible += tree_.testRelative(c - h, c + h, resume) != OcclusionTree::Result::Occluded;
    }
    return double(visible) > share * double(n);
}

uint64_t OcclusionPass::addToMap(const Camera& cam, const OcclusionSettings& os) {
    map_.reset(cam, OcclusionMap::optionsFor(cam, os));
    const size_t keep = std::min(cands_.size(), size_t(os.homMaxOccluders));
    std::nth_element(cands_.begin(), cands_.begin() + ptrdiff_t(keep), cands_.end(), ByDist());
    const dvec3 eye = cam.eye();
    uint64_t used = 0;
    for (size_t k = 0; k < keep; ++k) {
        const FlatImage& img = *cands_[k].img;
        const FlatImage::OccluderRef& o = img.occluders[cands_[k].index];
        const auto* node = static_cast<const Occluder*>(o.node);
        const dmat4* m = o.matrix == ~0u ? nullptr : &img.occluderMatrices[o.matrix];
        auto rel = [&](const dvec3& v) { return (m ? dvec3(*m * dvec4(v, 1.0)) : v + o.shift) - eye; };
        bool added;
        if (node->shape() == Occluder::Shape::Box) {
            const Box& lb = node->box();
            dvec3 c[8];
            for (int j = 0; j < 8; ++j)
                c[j] = rel(
                    dvec3((j & 1) ? lb.max.x : lb.min.x, (j & 2) ? lb.max.y : lb.min.y, (j & 4) ? lb.max.z : lb.min.z));
            added = map_.addBox(c);
        } else {
            polyScratch_.clear();
            for (const dvec3& v : node->polygon()) polyScratch_.push_back(rel(v));
            added = map_.addPolygon(polyScratch_.data(), polyScratch_.size());
        }
        used += added;
    }
    map_.finish();
    return used;
}

bool OcclusionPass::obbHidden(const ObbTree& tree, uint32_t n, const dmat4& toEye, int levels) const {
    const ObbTree::Node& nd = tree.node(n);
    dvec3 c[8];
    nd.corners(c);
    for (dvec3& p : c) p = dvec3(toEye * dvec4(p, 1.0));
    const auto r = map_.test(c);
    if (r == OcclusionMap::Result::Occluded) return true;
    if (r == OcclusionMap::Result::Visible || nd.first == 0 || levels == 0) return false;
    return obbHidden(tree, nd.first, toEye, levels - 1) && obbHidden(tree, nd.first + 1, toEye, levels - 1);
}

bool OcclusionPass::test(const FlatImage& img, const dvec3& originRel, uint32_t i, int32_t& occ, CullStats& stats,
                         const dmat4* toEye) {
    const auto t0 = Clock::now();
    const dvec3 ctr = originRel + dvec3(img.cx[i], img.cy[i], img.cz[i]), h(img.ex[i], img.ey[i], img.ez[i]);
    stats.occlusionTests++;
    // The eye in the plane of one of the bound's faces (within the float bound's rounding): a face of the
    // content may be seen exactly edge-on there, and the rasterizer draws such a face as a sliver with a
    // depth that is not the face's (nearer, through walls). Not culled; the entries below are tested.
    const double slack =
        eps::kFloatRounding * (std::abs(img.cx[i]) + std::abs(img.cy[i]) + std::abs(img.cz[i]) + h.x + h.y + h.z);
    const dvec3 gap = glm::abs(glm::abs(ctr) - h);
    if (gap.x <= slack || gap.y <= slack || gap.z <= slack) {
        testMs_ += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        return true;
    }
    bool occluded;
    if (hom_) {
        const auto r = map_.test(ctr - h, ctr + h);
        if (r == OcclusionMap::Result::Visible) occ = OcclusionTree::kVisible;
        occluded = r == OcclusionMap::Result::Occluded;
        if (r == OcclusionMap::Result::NotOccluded && toEye && obbLevels_ > 0 && img.kind[i] == NodeKind::Geometry) {
            const ObbTree& tree = obbs_.get(*img.draws[img.aux[i]].mesh);
            occluded = !tree.empty() && obbHidden(tree, 0, *toEye, obbLevels_);
            stats.culledObb += occluded;
        }
    } else {
        occluded = tree_.testRelative(ctr - h, ctr + h, occ) == OcclusionTree::Result::Occluded;
    }
    testMs_ += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (!occluded) return true;
    stats.culledOcclusion++;
    stats.occludedEntries += img.end[i] - i;
    return false;
}

void OcclusionPass::finish(const OcclusionSettings& s, CullStats& stats) {
    stats.occlusionMs += testMs_;
    stats.occlusionBoxSplits = tree_.boxSplits();
    // Did it pay? The share of the walk it removed.
    if (stats.occlusionRan && s.mode == OcclusionMode::Adaptive)
        recordGain(double(stats.occludedEntries) / double(stats.occludedEntries + stats.nodesVisited + 1),
                   s.adaptiveMinGain);
}

void OcclusionPass::recordGain(double gain, double minGain) {
    if (gain < minGain) {
        backoff_ = std::min(64, std::max(4, backoff_ * 2));
        skipLeft_ = backoff_;
    } else {
        backoff_ = 0;
        skipLeft_ = 0;
    }
}

}  // namespace sg
