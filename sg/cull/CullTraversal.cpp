// The frame of the cull: the settings checked, each image's context set up, the walk started at the scene's
// root, the budget's plan walked, the draw list sorted.
#include "sg/cull/PvsTable.h"
#include "sg/cull/internal/CullContext.h"
#include "sg/scene/internal/ImageWalk.h"

#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace sg {

void CullTraversal::setupCtx(Ctx& c, const FlatImage& img, const dmat4& t, bool planes) {
    // Most frames are translations (the scene's image, paged details, Instances placed without a turn or a
    // scale): no inverse and no matrix product then, which made an Instance's frame cost more than its cull.
    const bool translation =
        glm::dmat3(t) == glm::dmat3(1.0) && t[0][3] == 0.0 && t[1][3] == 0.0 && t[2][3] == 0.0 && t[3][3] == 1.0;
    const dvec3 shift(t[3]);
    if (translation) {
        c.img = &img;
        c.imgToEye = t;
        c.eyeImg = -shift;
        c.scale = 1.0;
        c.rigid = true;
    } else {
        static_cast<ImageFrame&>(c) = ImageFrame::make(img, t);
    }
    c.viewDir = cam_->viewDirection();
    if (!planes) return;
    // A plane (n, d) in eye space becomes t^T (n, d) in image space (exact for affine t), normalized; for a
    // translation that is (n, d + n.shift).
    const dmat4 tt = glm::transpose(t);
    for (size_t k = 0; k < 6; ++k) {
        const Plane& e = cam_->eyePlanes()[k];
        const dvec4 p = translation ? dvec4(e.n, e.d + glm::dot(e.n, shift)) : tt * dvec4(e.n, e.d);
        const double len = glm::length(dvec3(p));
        c.planes[k] = Plane{dvec3(p) / len, p.w / len};
    }
    c.kplanes = kernel::Planes::make(c.planes, dvec3(0.0), img.extent, cull::kAllPlanes);
    if (set_->strategy == CullStrategy::CenterBox || set_->strategy == CullStrategy::SphereSphere) {
        const dmat4 inv = translation ? glm::translate(dmat4(1.0), -shift) : glm::inverse(t);
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

namespace {
// A look-ahead's settings (CullControls::prefetchOnly): frustum and LOD ranges only, unsorted (nothing is drawn).
CullSettings lookAhead(const CullSettings& s) {
    CullSettings a = s;
    a.sort = false;
    a.occlusion.mode = OcclusionMode::Off;
    a.pvs = nullptr;
    a.lodBudget.enabled = false;
    a.lodHysteresis = 0.0;
    a.screenRect = false;
    return a;
}
}  // namespace

void CullTraversal::cull(const Scene& scene, const Camera& cam, const CullSettings& settings, DrawList& out,
                         CullStats& stats, const CullControls& controls) {
    constexpr const char* fn = "CullTraversal::cull()";
    const auto t0 = std::chrono::steady_clock::now();
    if (!controls.imageOfLastUpdate) checkUpdated(scene, fn, true);
    settings.validate(fn);
    std::optional<CullSettings> ahead;
    if (controls.prefetchOnly) ahead = lookAhead(settings);
    const CullSettings& set = ahead ? *ahead : settings;
    prefetchOnly_ = controls.prefetchOnly;
    scene_ = &scene;
    cam_ = &cam;
    set_ = &set;
    out_ = &out;
    stats_ = &stats;
    stats = CullStats{};
    out.clear();
    cls_.clear();
    scratch_.clear();
    triangles_ = points_ = lines_ = 0;
    fade_ = 1.0f;
    const FlatImage& img = scene.image();
    const LodChooser chooser({&cam, set.lodScale, set.lodHysteresis, set.lodFade});
    chooser_ = &chooser;
    lodTracked_ = set.lodHysteresis > 0.0;
    screenRect_ = set.screenRect && set.strategy != CullStrategy::None;
    if (screenRect_) viewProj_ = cam.projection() * cam.viewRotation();
    clusters_.nextFrame();  // every frame: clusters of meshes no longer drawn (or of the option off) age out
    const LodBudgetSettings& lb = set.lodBudget;
    if (set.lodHysteresis > 0.0 || lb.enabled) lodHistory_.track(img, scene.structureVersion());
    if (img.size() && !(prefetchOnly_ && img.paged.empty())) {  // a look-ahead has nothing to ask for there
        Ctx c;
        setupCtx(c, img, glm::translate(dmat4(1.0), img.origin - cam.eye()));
        c.originRel = img.origin - cam.eye();
        if (set.pvs && set.strategy != CullStrategy::None && cam.perspective()) {
            checkPvs(scene, cam, *set.pvs);
            c.pvsHidden = set.pvs->hiddenFor(cam.eye());
        }
        const uint32_t mask =
            set.strategy == CullStrategy::None ? 0u : cull::kAllPlanes & set.measureOnly.frustumPlanes;
        if (&scene != occlusionScene_ || scene.version() != occlusionVersion_) {  // Adaptive's back-off starts over
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
        if (!planner_.deferred().empty()) replayBudget(c, lb);
        occlusion_.finish(set.occlusion, stats);
    }
    chooser_ = nullptr;
    stats.geometries = out.items.size();
    stats.triangles = triangles_;
    stats.points = points_;
    stats.lines = lines_;
    if (set.sort)
        out.sort();
    else
        out.keepEmissionOrder();
    stats.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Throws unless the table matches the scene (checked again only when the table, the scene or its version
// changed) and the camera's near plane is one the table was built for.
void CullTraversal::checkPvs(const Scene& scene, const Camera& cam, const PvsTable& t) {
    constexpr const char* fn = "CullTraversal::cull()";
    const FlatImage& img = scene.image();
    if (pvsChecked_ != &t || pvsHash_ != t.imageHash() || pvsScene_ != &scene || pvsVersion_ != scene.version() ||
        pvsEntries_ != img.size()) {
        const std::string why = t.mismatch(scene);
        if (!why.empty()) throw std::invalid_argument(std::string(fn) + ": the PVS table does not match: " + why);
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
}

void CullTraversal::defer(Ctx& c, uint32_t i, uint32_t mask, int32_t occ, const dmat4& m) {
    if (c.place < 0) {
        c.place = int32_t(places_.size());
        places_.push_back(c);
        placeKey_.push_back(c.key);
    }
    uint8_t record = LodHistory::kUnseen;
    if (c.img == &scene_->image()) {
        record = lodHistory_.record(i);
    } else if (const auto it = protoLast_.find(c.key ^ (uint64_t(i) << 40)); it != protoLast_.end()) {
        record = it->second;
    }
    planner_.defer({i, mask, occ, m, uint32_t(c.place), record});
}

// The budget's choice for every visible LOD at once; then their chosen children are walked, each in its image's
// context (the scene's, or a prototype's at its placement, set up again).
void CullTraversal::replayBudget(Ctx& sceneCtx, const LodBudgetSettings& lb) {
    const auto& deferred = planner_.deferred();
    planner_.plan(places_, scene_->version(), *cam_, lb,
                  {triangleWork(double(triangles_), double(points_), double(lines_)), double(out_->items.size()), 0.0},
                  *stats_);
    protoShown_.clear();
    for (size_t k = 0; k < deferred.size(); ++k) {
        const LodBudgetPlanner::Deferred& d = deferred[k];
        const bool inScene = places_[d.place].img == &scene_->image();
        LodChooser::Known known;
        known.planned = planner_.chosen(k);
        uint8_t shown = LodChooser::kNone;
        if (known.planned >= 0) {
            Ctx sub;
            Ctx* at = &sceneCtx;
            if (!inScene) {
                setupCtx(sub, *places_[d.place].img, places_[d.place].imgToEye);
                sub.key = placeKey_[d.place];
                at = &sub;
            }
            shown = chooser_->choose(*at, d.entry, known,
                                     [&](const LodChooser::Shown& s) { visit(*at, s.entry, d.mask, d.m, d.occ); });
        }
        if (inScene) {
            stats_->lodChanged += lodHistory_.show(d.entry, shown);
        } else {
            stats_->lodChanged += LodHistory::changes(d.record, shown);
            protoShown_[placeKey_[d.place] ^ (uint64_t(d.entry) << 40)] = LodHistory::next(shown);
        }
    }
    protoLast_.swap(protoShown_);
}

}  // namespace sg
