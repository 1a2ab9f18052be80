#include "sg/cull/CullTraversal.h"

#include "nodes/Billboard.h"
#include "nodes/BspGroup.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/PagedLOD.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"
#include "sg/cull/FrustumKernel.h"
#include "sg/cull/PvsTable.h"
#include "sg/scene/ImageWalk.h"
#include "sg/scene/LodValue.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace sg {

namespace {
constexpr uint32_t kAllPlanes = 0x3f;
constexpr uint8_t kBySphereSphere = 4;  // batch result bit: culled by the pre-test
}  // namespace

// Per image: the planes and frames the tests need, in that image's coordinates.
struct CullTraversal::Ctx {
    const FlatImage* img = nullptr;
    dmat4 imgToEye{1.0};   // image coordinates -> eye-relative world
    dvec3 eyeImg{0.0};     // the eye in image coordinates
    dvec3 viewDir{0.0};    // the camera's view direction (eye-relative world)
    dvec3 originRel{0.0};  // the image origin relative to the eye (occlusion tests, main image only)
    double scale = 1.0;    // lengths: image units -> world units (at most)
    bool rigid = true;     // image -> eye keeps lengths (no scale): distances can be taken in the image
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
};

namespace {
inline bool pvsHides(const uint64_t* hidden, uint32_t i) { return hidden && ((hidden[i >> 6] >> (i & 63)) & 1u); }
}  // namespace

void CullTraversal::setupCtx(Ctx& c, const FlatImage& img, const dmat4& t) {
    c.img = &img;
    c.imgToEye = t;
    c.eyeImg = dvec3(glm::inverse(t) * dvec4(0, 0, 0, 1));
    c.scale = maxScale(t);
    c.rigid = isRigid(t);
    c.viewDir = cam_->viewDirection();
    // A plane (n, d) in eye space becomes t^T (n, d) in image space (exact for affine t), normalized.
    const dmat4 tt = glm::transpose(t);
    for (size_t k = 0; k < 6; ++k) {
        const Plane& e = cam_->eyePlanes()[k];
        const dvec4 p = tt * dvec4(e.n, e.d);
        const double len = glm::length(dvec3(p));
        c.planes[k] = Plane{dvec3(p) / len, p.w / len};
    }
    c.kplanes = kernel::Planes::make(c.planes, dvec3(0.0), img.extent, kAllPlanes);
    if (set_->strategy == CullStrategy::CenterBox || set_->strategy == CullStrategy::SphereSphere) {
        const dmat4 inv = glm::inverse(t);
        Box fb;
        for (const dvec3& p : cam_->eyeCorners()) fb.expand(dvec3(inv * dvec4(p, 1.0)));
        for (int a = 0; a < 3; ++a) {
            c.fbMin[a] = std::nextafter(float(fb.min[a]), -HUGE_VALF);
            c.fbMax[a] = std::nextafter(float(fb.max[a]), HUGE_VALF);
        }
        c.fsCenter = fb.center();
        c.fsRadius = 0.0;
        for (const dvec3& p : cam_->eyeCorners())
            c.fsRadius = std::max(c.fsRadius, glm::length(dvec3(inv * dvec4(p, 1.0)) - c.fsCenter));
        c.fsRadius = c.fsRadius * (1.0 + eps::kFloatRounding) + eps::kPlaneSlack * img.extent;
    }
}

void CullTraversal::cull(const Scene& scene, const Camera& cam, const CullSettings& set, DrawList& out,
                         CullStats& stats) {
    constexpr const char* fn = "CullTraversal::cull()";
    const auto t0 = std::chrono::steady_clock::now();
    checkUpdated(scene, fn);
    scene_ = &scene;
    cam_ = &cam;
    set_ = &set;
    out_ = &out;
    stats_ = &stats;
    stats = CullStats{};
    out.clear();
    cls_.clear();
    scratch_.clear();
    triangles_ = 0;
    fade_ = 1.0f;
    const FlatImage& img = scene.image();
    checkLodScale(set.lodScale, fn);
    screenRect_ = set.screenRect && set.strategy != CullStrategy::None;
    if (screenRect_) {
        if (set.screenRectTriangles < 1 || set.screenRectTriangles > 65536)
            throw std::invalid_argument(std::string(fn) + ": screenRectTriangles " +
                                        std::to_string(set.screenRectTriangles) + " is not in 1..65536");
        viewProj_ = cam.projection() * cam.viewRotation();
    }
    clusters_.nextFrame();  // every frame: clusters of meshes no longer drawn (or of the option off) age out
    const LodBudgetSettings& lb = set.lodBudget;
    if (lb.enabled && (!lb.model || !(lb.budgetMs > 0.0 && std::isfinite(lb.budgetMs)) ||
                       !(lb.hysteresis >= 0.0 && std::isfinite(lb.hysteresis))))
        throw std::invalid_argument("CullTraversal::cull(): lodBudget needs a cost model, a positive budget (" +
                                    std::to_string(lb.budgetMs) + " ms) and a hysteresis >= 0 (" +
                                    std::to_string(lb.hysteresis) + ")");
    if (set.lodHysteresis > 0.0 || lb.enabled) {
        if (!(set.lodHysteresis < 1.0))
            throw std::invalid_argument("CullTraversal::cull(): lodHysteresis " + std::to_string(set.lodHysteresis) +
                                        " is not in [0, 1)");
        lodHistory_.track(img, scene.structureVersion());
    }
    if (img.size()) {
        Ctx c;
        setupCtx(c, img, glm::translate(dmat4(1.0), img.origin - cam.eye()));
        c.originRel = img.origin - cam.eye();
        if (set.pvs && set.strategy != CullStrategy::None && cam.perspective()) {
            const PvsTable& t = *set.pvs;
            if (pvsChecked_ != &t || pvsHash_ != t.imageHash() || pvsScene_ != &scene ||
                pvsVersion_ != scene.version() || pvsEntries_ != img.size()) {
                const std::string why = t.mismatch(scene);
                if (!why.empty())
                    throw std::invalid_argument(std::string(fn) + ": the PVS table does not match: " + why);
                pvsChecked_ = &t;
                pvsHash_ = t.imageHash();
                pvsScene_ = &scene;
                pvsVersion_ = scene.version();
                pvsEntries_ = img.size();
            }
            // (within rounding: the camera's near distance is recovered from its projection)
            const double zn = cam.nearDistance();
            if (!(zn >= t.minNear() * (1.0 - 1e-9) && zn <= t.maxNear() * (1.0 + 1e-9)))
                throw std::invalid_argument(std::string(fn) + ": the camera's near plane " +
                                            std::to_string(cam.nearDistance()) + " is outside the PVS table's [" +
                                            std::to_string(t.minNear()) + ", " + std::to_string(t.maxNear()) + "]");
            c.pvsHidden = t.hiddenFor(cam.eye());
        }
        const uint32_t mask = set.strategy == CullStrategy::None ? 0u : kAllPlanes & set.frustumPlanes;
        if (&scene != occlusionScene_ || scene.version() != occlusionVersion_) {  // Auto's back-off starts over
            occlusion_.wake();
            occlusionScene_ = &scene;
            occlusionVersion_ = scene.version();
        }
        const int32_t occ = occlusion_.build(img, cam, set, stats);
        framesTop_ = 0;
        planner_.clear();
        places_.clear();
        placeKey_.clear();
        planning_ = lb.enabled;
        visit(c, 0, mask, glm::translate(dmat4(1.0), -cam.eye()), occ);
        planning_ = false;
        const auto& deferred = planner_.deferred();
        if (!deferred.empty()) {
            // The budget's choice for every visible LOD at once; then their chosen children are walked, each
            // in its image's context (the scene's, or a prototype's at its placement, set up again).
            planner_.plan(places_, scene.version(), cam, lb, {double(triangles_), double(out.items.size()), 0.0},
                          stats);
            protoShown_.clear();
            for (size_t k = 0; k < deferred.size(); ++k) {
                const LodBudgetPlanner::Deferred& d = deferred[k];
                const int chosen = planner_.chosen(k);
                const uint8_t shown = LodHistory::child(chosen);
                const bool inScene = places_[d.place].img == &img;
                if (inScene)
                    lodHistory_.show(d.entry, shown);
                else
                    protoShown_[placeKey_[d.place] ^ (uint64_t(d.entry) << 40)] = shown;
                if (chosen < 0) continue;
                Ctx sub;
                Ctx* at = &c;
                if (!inScene) {
                    setupCtx(sub, *places_[d.place].img, places_[d.place].imgToEye);
                    sub.key = placeKey_[d.place];
                    at = &sub;
                }
                uint32_t j = d.entry + 1;
                for (int n = 0; n < chosen; ++n) j = at->img->end[j];
                visit(*at, j, d.mask, d.m, d.occ);
            }
            protoLast_.swap(protoShown_);
        }
        occlusion_.finish(set.occlusion, stats);
    }
    stats.geometries = out.items.size();
    stats.triangles = triangles_;
    if (set.sort)
        out.sort();
    else
        out.keepEmissionOrder();
    stats.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

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
    const bool eyeInside = set_->eyeInsideSkip && dx * dx + dy * dy + dz * dz <= double(img.r[i]) * img.r[i];
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
            mask == kAllPlanes ? c.kplanes : kernel::Planes::make(c.planes, dvec3(0.0), img.extent, mask);
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

void CullTraversal::visit(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ) {
    const FlatImage& img = *c.img;
    stats_->nodesVisited++;
    if (pvsHides(c.pvsHidden, i)) {
        stats_->culledPvs++;
        return;
    }
    const uint8_t fl = img.flags[i];
    if (fl & FlatImage::kEmpty) return;
    if ((fl & FlatImage::kMasked) && !(img.maskedNode(i)->nodeMask() & set_->traversalMask)) return;
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
        if (!set_->planeMasking) mask = before;
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
        if (k != NodeKind::Transform && k != NodeKind::LOD && k != NodeKind::Occluder &&
            !occlusion_.test(img, c.originRel, i, occ, *stats_, k == NodeKind::Geometry ? &m : nullptr))
            return;
    }

    switch (img.kind[i]) {
        case NodeKind::Geometry:
            // (the centre-box test clears the mask without the bound being inside)
            emit(c, i, m, maskIn == 0 || (mask == 0 && set_->strategy != CullStrategy::CenterBox));
            break;
        case NodeKind::Transform: children(c, i, mask, transformed(img, i, m), occ); break;
        case NodeKind::LOD: {
            if (planning_) {  // the budget decides, once the walk is done
                defer(c, i, mask, occ, m);
                break;
            }
            const double value = lodValue(c, i);
            const FlatImage::Lod& lod = img.lods[img.aux[i]];
            const FlatImage::Range* rg = &img.ranges[lod.firstRange];
            if (set_->lodFade && lod.fade > 0.0f) {
                fadedLod(c, i, mask, m, occ, value, lod.fade);
                break;
            }
            if (set_->lodHysteresis > 0.0 && c.img == &scene_->image()) {
                // The last child stays while the value is within its widened range; else the plain
                // ranges decide, and the first child they show is remembered.
                const double h = set_->lodHysteresis;
                const uint8_t last = lodHistory_.last(i);
                const bool keep =
                    last != LodHistory::kNone && value >= rg[last].min * (1.0 - h) && value < rg[last].max * (1.0 + h);
                uint32_t k = 0, shown = LodHistory::kNone;
                for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j], ++k) {
                    if (keep ? k != last : !(value >= rg[k].min && value < rg[k].max)) continue;
                    if (shown == LodHistory::kNone && k < LodHistory::kNone) shown = k;
                    visit(c, j, mask, m, occ);
                }
                lodHistory_.show(i, uint8_t(shown));
                break;
            }
            for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j], ++rg)
                if (value >= rg->min && value < rg->max) visit(c, j, mask, m, occ);
            break;
        }
        case NodeKind::Switch: {
            const auto* sw = static_cast<Switch*>(img.nodes[img.aux[i]]);
            uint32_t j = i + 1;
            for (size_t k = 0; j < img.end[i]; ++k, j = img.end[j])
                if (sw->isOn(k)) visit(c, j, mask, m, occ);
            break;
        }
        case NodeKind::Billboard: {
            const auto* bb = static_cast<Billboard*>(img.nodes[img.aux[i]]);
            const dvec3 eyeLocal(glm::inverse(m) * dvec4(0, 0, 0, 1));
            // Its own tests covered the children (their bounds are the billboard's).
            children(c, i, 0u, m * bb->rotationToward(eyeLocal), OcclusionTree::kVisible);
            break;
        }
        case NodeKind::Instance: visitInstance(c, i, mask, m); break;
        case NodeKind::BspGroup: {
            const auto* g = static_cast<BspGroup*>(img.nodes[img.aux[i]]);
            const dvec3 eyeLocal(glm::inverse(m) * dvec4(0, 0, 0, 1));
            // Child entry indices by child number, then the BSP's front-to-back order over them; indexed, as
            // the BspGroups below push onto scratch_ too.
            const size_t base = scratch_.size();
            for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j]) scratch_.push_back(j);
            const size_t nChildren = scratch_.size() - base;
            g->order(eyeLocal, bspOrder_);
            scratch_.insert(scratch_.end(), bspOrder_.begin(), bspOrder_.end());
            const size_t orderEnd = scratch_.size();
            for (size_t o = base + nChildren; o < orderEnd; ++o)
                if (scratch_[o] < nChildren) visit(c, scratch_[base + scratch_[o]], mask, m, occ);
            scratch_.resize(base);
            break;
        }
        case NodeKind::PagedLOD: pagedLod(c, i, mask, m, occ); break;
        case NodeKind::Occluder: break;  // used by the occlusion passes, never drawn
        case NodeKind::Group:
            if (mask && img.aux[i] && c.clsBase == ~0u) {
                wideChildren(c, i, mask, m, occ);
                break;
            }
            children(c, i, mask, m, occ);
            break;
    }
}

void CullTraversal::children(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ) {
    const FlatImage& img = *c.img;
    if (mask == 0 && set_->smallFeaturePixels == 0.0 && occ == OcclusionTree::kVisible)
        return inside(c, i + 1, img.end[i], m);
    for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j]) visit(c, j, mask, m, occ);
}

// Many children over a large subtree: classify their spheres, kept side by side, in one kernel pass.
void CullTraversal::wideChildren(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ) {
    const FlatImage& img = *c.img;
    const FlatImage::Wide w = img.wides[img.aux[i] - 1];
    const kernel::Planes kp =
        mask == kAllPlanes ? c.kplanes : kernel::Planes::make(c.planes, dvec3(0.0), img.extent, mask);
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
        visit(c, img.wideEntry[w.first + k], (r & kernel::kInside) && set_->planeMasking ? 0u : mask, m, occ);
    }
    cls_.resize(off);
}

// A child is drawn over its range widened by half the band at each end; within the band it covers the
// share of pixels that the position in the band gives. Where two children meet, one keeps the pixels whose
// pattern value is below its share and the other those at or above it: together exactly every pixel.
void CullTraversal::fadedLod(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ, double value,
                             float width) {
    const FlatImage& img = *c.img;
    const FlatImage::Range* rg = &img.ranges[img.lods[img.aux[i]].firstRange];
    const double w = width, h = 0.5 * w;
    // Shares in steps of 1/4096: exact in float, so complementary shares add up to exactly 1 on the GPU.
    auto share = [](double x) { return float(std::round(std::clamp(x, 0.0, 1.0) * 4096.0) / 4096.0); };
    const float outer = fade_;
    for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j], ++rg) {
        if (value < rg->min - h || value >= rg->max + h) continue;
        const float in = rg->min > 0.0f ? share((value - (rg->min - h)) / w) : 1.0f;  // nothing below 0 to fade from
        const float out = share((rg->max + h - value) / w);
        // Fading out: keep pattern < out (DrawList::fades > 0); fading in: keep pattern >= 1 - in (< 0).
        const float f = (in >= 1.0f && out >= 1.0f) ? 1.0f : (in < out ? -in : out);
        if (f == 0.0f) continue;
        fade_ = f;
        visit(c, j, mask, m, occ);
        fade_ = outer;
    }
}

// The detail when it is wanted and attached, else the coarse children. A wanted detail that is not loaded is
// posted for the pager once per update, and the coarse level drawn meanwhile: the frame never waits for it.
void CullTraversal::pagedLod(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m, int32_t occ) {
    const FlatImage& img = *c.img;
    const FlatImage::Paged& p = img.paged[img.aux[i]];
    auto* node = static_cast<PagedLOD*>(p.node);
    bool wanted = true;
    if (node->trigger() == PagedLOD::Trigger::Range) {
        const double value = sg::lodValue(img, p.lod, i, c.rigid, c.eyeImg, c.imgToEye, c.scale, cam_, set_->lodScale);
        wanted = value >= p.min && value < p.max;
        if (wanted) {
            stats_->pagedWanted++;
            if (node->markNeeded(scene_->updateCount()) && node->state() == PagedLOD::State::Unloaded) {
                scene_->pageRequests().post(node);
                stats_->pagedRequested++;
            }
        }
    }
    if (wanted && p.detail) {
        // The detail's image is in this image's frame, shifted to its own origin: the same planes (and the
        // plane mask), the same occlusion tree.
        const FlatImage& d = *p.detail;
        if (d.size() == 0) return;
        Ctx sub;
        setupCtx(sub, d, c.imgToEye * glm::translate(dmat4(1.0), d.origin - img.origin));
        sub.originRel = c.originRel + (d.origin - img.origin);
        visit(sub, 0, mask, m, occ);
        return;
    }
    if (wanted) stats_->pagedCoarse++;
    children(c, i, mask, m, occ);
}

double CullTraversal::lodValue(const Ctx& c, uint32_t i) const {
    return sg::lodValue(*c.img, i, c.rigid, c.eyeImg, c.imgToEye, c.scale, cam_, set_->lodScale);
}

// Entries [begin, end) inside the frustum (no test left): one forward scan over the pre-order entries
// with a stack of transform frames, instead of a call per entry. Anything unusual goes to visit().
void CullTraversal::inside(Ctx& c, uint32_t begin, uint32_t end, const dmat4& m) {
    const FlatImage& img = *c.img;
    // frames_ is a stack addressed by index; `fr` is refreshed after anything that may grow it.
    const size_t base = framesTop_;
    size_t top = base;
    if (top + 2 >= frames_.size()) frames_.resize(frames_.size() * 2 + 16);
    Frame* fr = frames_.data();
    fr[top] = {end, m};
    uint64_t visited = 0;
    uint32_t j = begin;
    while (j < end) {
        while (j >= fr[top].end) --top;
        if (pvsHides(c.pvsHidden, j)) {
            stats_->culledPvs++;
            j = img.end[j];
            continue;
        }
        const uint8_t fl = img.flags[j];
        const NodeKind kind = img.kind[j];
        // Masked, empty, invalid, below a billboard, or a rarer kind: the general path.
        if ((fl & FlatImage::kSlowPath) ||
            !(kind == NodeKind::Geometry || kind == NodeKind::Group || kind == NodeKind::Transform ||
              kind == NodeKind::LOD) ||
            (kind == NodeKind::LOD &&
             (set_->lodHysteresis > 0.0 || planning_ || (set_->lodFade && img.lods[img.aux[j]].fade > 0.0f)))) {
            const dmat4 vm = fr[top].m;
            framesTop_ = top + 1;
            visit(c, j, 0u, vm, OcclusionTree::kVisible);
            fr = frames_.data();
            j = img.end[j];
            continue;
        }
        ++visited;
        switch (kind) {
            case NodeKind::Geometry:
                emit(c, j, fr[top].m, true);
                ++j;
                break;
            case NodeKind::Group: ++j; break;  // its children follow
            case NodeKind::Transform:
                if (top + 2 >= frames_.size()) {
                    frames_.resize(frames_.size() * 2);
                    fr = frames_.data();
                }
                fr[top + 1].m = transformed(img, j, fr[top].m);
                fr[top + 1].end = img.end[j];
                ++top;
                ++j;
                break;
            default: {  // LOD
                const double value = lodValue(c, j);
                const FlatImage::Range* rg = &img.ranges[img.lods[img.aux[j]].firstRange];
                for (uint32_t k = j + 1; k < img.end[j]; k = img.end[k], ++rg) {
                    if (!(value >= rg->min && value < rg->max)) continue;
                    if (pvsHides(c.pvsHidden, k)) {
                        stats_->culledPvs++;
                    } else if (img.kind[k] == NodeKind::Geometry &&
                               !(img.flags[k] & FlatImage::kSlowPath)) {  // the usual child
                        ++visited;
                        emit(c, k, fr[top].m, true);
                    } else {
                        const dmat4 lm = fr[top].m;
                        framesTop_ = top + 1;
                        inside(c, k, img.end[k], lm);
                        fr = frames_.data();
                    }
                }
                j = img.end[j];
                break;
            }
        }
    }
    stats_->nodesVisited += visited;
    framesTop_ = base;
}

void CullTraversal::visitInstance(Ctx& c, uint32_t i, uint32_t mask, const dmat4& m) {
    const auto* in = static_cast<Instance*>(c.img->nodes[c.img->aux[i]]);
    const FlatImage* p = in->prototype() ? scene_->prototypeImage(in->prototype()) : nullptr;
    if (!p || p->size() == 0) return;
    stats_->instancesVisited++;
    const dmat4 pm = m * in->matrix();
    Ctx sub;
    setupCtx(sub, *p, glm::translate(pm, p->origin));
    sub.key = (c.key ^ i) * 0x9E3779B97F4A7C15ull + 1;  // this placement, under its parent's
    // Same six planes, transformed: planes the placement's bound was inside of stay done. The placement's
    // own bound had its occlusion test; its prototype's bounds are not world boxes, so none below.
    visit(sub, 0, set_->strategy == CullStrategy::None ? 0u : mask, pm, OcclusionTree::kVisible);
}

void CullTraversal::defer(Ctx& c, uint32_t i, uint32_t mask, int32_t occ, const dmat4& m) {
    if (c.place < 0) {
        c.place = int32_t(places_.size());
        places_.push_back({c.img, c.eyeImg, c.imgToEye, c.scale, c.rigid});
        placeKey_.push_back(c.key);
    }
    uint8_t last = LodHistory::kNone;
    if (c.img == &scene_->image()) {
        last = lodHistory_.last(i);
    } else if (const auto it = protoLast_.find(c.key ^ (uint64_t(i) << 40)); it != protoLast_.end()) {
        last = it->second;
    }
    planner_.defer({i, mask, occ, m, uint32_t(c.place), last});
}

void CullTraversal::emit(Ctx& c, uint32_t i, const dmat4& m, bool inside) {
    const FlatImage& img = *c.img;
    const FlatImage::Draw& d = img.draws[img.aux[i]];
    if (!d.mesh) return;
    // The rejection's path is its own function: the usual path stays as short as without the option.
    if (screenRect_ && !inside) return emitTrimmed(c, i, m);
    // Sort depth: the geometry's origin along the view, from the matrix already at hand (the bounds
    // stay unread: the order is a drawing heuristic, not a visibility decision).
    const bool invalid = img.flags[i] & FlatImage::kInvalid;
    const dvec3& vd = c.viewDir;
    const float depth = float(vd.x * m[3].x + vd.y * m[3].y + vd.z * m[3].z);
    DrawItem& it = out_->push(d.state, depth);
    it.mesh = d.mesh;
    it.material = d.material;
    toFloat(m, it.model);
    if (fade_ != 1.0f) out_->fades.push_back({uint32_t(out_->items.size() - 1), fade_});
    triangles_ += d.mesh->triangleCount();
    if (invalid) stats_->invalidDrawn++;
}

// emit() with the screen-rectangle rejection: the clusters off screen are left out, the rest drawn as ranges.
void CullTraversal::emitTrimmed(Ctx& c, uint32_t i, const dmat4& m) {
    const FlatImage& img = *c.img;
    const FlatImage::Draw& d = img.draws[img.aux[i]];
    const uint32_t triangles = d.mesh->triangleCount();
    if ((img.flags[i] & FlatImage::kInvalid) || triangles == 0) return emit(c, i, m, true);
    const TriangleClusters& tc = clusters_.get(*d.mesh, set_->screenRectTriangles);
    std::vector<IndexRange>& ranges = out_->ranges;
    const size_t firstRange = ranges.size();
    const uint32_t kept =
        tc.keepInViewport(viewProj_, m, ranges, stats_->screenRectClusters, stats_->culledScreenRectClusters);
    stats_->culledScreenRectTriangles += triangles - kept;
    if (kept == 0) {
        stats_->culledScreenRectGeometries++;
        ranges.resize(firstRange);
        return;
    }
    if (kept == triangles) {  // every cluster on screen: the whole mesh, batched with its like
        ranges.resize(firstRange);
        return emit(c, i, m, true);
    }
    const dvec3& vd = c.viewDir;
    const float depth = float(vd.x * m[3].x + vd.y * m[3].y + vd.z * m[3].z);
    DrawItem& it = out_->push(d.state, depth);
    it.mesh = d.mesh;
    it.material = d.material;
    toFloat(m, it.model);
    const uint32_t item = uint32_t(out_->items.size() - 1);
    if (fade_ != 1.0f) out_->fades.push_back({item, fade_});
    out_->parts.push_back({item, uint32_t(firstRange), uint32_t(ranges.size() - firstRange)});
    triangles_ += kept;
}

}  // namespace sg
