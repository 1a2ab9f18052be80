#include "sg/cull/LodBudgetPlanner.h"

#include "sg/scene/LodValue.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace sg {

void LodBudgetPlanner::track(const FlatImage& img, uint64_t version) {
    if (workImage_ == &img && workVersion_ == version && workAt_.size() == img.size()) return;
    workAt_.assign(img.size(), ~0u);
    work_.clear();
    workImage_ = &img;
    workVersion_ = version;
}

const LodBudgetPlanner::ChildWork* LodBudgetPlanner::work(const FlatImage& img, uint64_t version, uint32_t i,
                                                          uint32_t& count) {
    track(img, version);
    const uint32_t at = workIndex(img, i);
    count = work_[at].count;
    return &work_[at + 1].child;
}

// Detail grows ever more slowly with the triangles: a tenth of the triangles keeps ~56% of the value.
uint32_t LodBudgetPlanner::workIndex(const FlatImage& img, uint32_t i) {
    if (workAt_[i] != ~0u) return workAt_[i];
    const size_t at = work_.size();
    work_.emplace_back();  // the header: the children's count
    float trisMax = 0.0f;
    for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j]) {
        Work w;
        w.child = {0.0f, 0.0f, 1.0f};
        for (uint32_t e = j; e < img.end[j]; ++e) {
            if (img.kind[e] != NodeKind::Geometry || (img.flags[e] & FlatImage::kEmpty)) continue;
            if (const Mesh* mesh = img.draws[img.aux[e]].mesh) {
                w.child.tris += float(mesh->triangleCount());
                w.child.items += 1.0f;
            }
        }
        trisMax = std::max(trisMax, w.child.tris);
        work_.push_back(w);
    }
    work_[at].count = uint32_t(work_.size() - at - 1);
    for (size_t k = at + 1; k < work_.size(); ++k)
        if (trisMax > 0.0f) work_[k].child.detail = std::sqrt(std::sqrt(work_[k].child.tris / trisMax));
    workAt_[i] = uint32_t(at);
    return uint32_t(at);
}

// The options the budget may choose from: children 0 .. the last that the ranges show at `scale`; all of
// them when the ranges show none there.
int LodBudgetPlanner::finestAllowed(const FlatImage& img, uint32_t i, const dvec3& eyeImg, const Camera& cam,
                                    double scale, int count) {
    const double value = lodValue(img, i, true, eyeImg, dmat4(1.0), 1.0, &cam, scale);
    const FlatImage::Lod& lod = img.lods[img.aux[i]];
    const FlatImage::Range* rg = &img.ranges[lod.firstRange];
    int last = -1;
    for (int c = 0; c < count; ++c)
        if (value >= rg[c].min && value < rg[c].max) last = c;
    return last < 0 ? count : last + 1;
}

void LodBudgetPlanner::plan(const FlatImage& img, uint64_t version, const Camera& cam, const LodBudgetSettings& b,
                            const DrawCostModel::Work& fixedWork, LodHistory& history, CullStats& stats) {
    const auto t0 = std::chrono::steady_clock::now();
    const DrawCostModel& model = *b.model;
    const dvec3 eyeImg = cam.eye() - img.origin;
    const double screen = double(cam.width()) * cam.height();
    const DrawCostModel::Rates rates = model.rates();
    track(img, version);
    // Each LOD's children's work and detail, from the image (kept while the scene's version stays); then
    // room for every option at once.
    const size_t n = deferred_.size();
    objects_.resize(n);
    workOf_.resize(n);
    size_t total = 0;
    for (size_t k = 0; k < n; ++k) {
        workOf_[k] = workIndex(img, deferred_[k].entry);
        total += work_[workOf_[k]].count;
    }
    if (options_.size() < total) options_.resize(total);
    area_.resize(n);
    LodSelector::Option* op = options_.data();
    for (size_t k = 0; k < n; ++k) {
        const uint32_t i = deferred_[k].entry;
        const Work* work = &work_[workOf_[k]];
        LodSelector::Object& obj = objects_[k];
        obj.count = int(work->count);
        // Projected area of the LOD's bound, the value of drawing it at all.
        const double dx = img.cx[i] - eyeImg.x, dy = img.cy[i] - eyeImg.y, dz = img.cz[i] - eyeImg.z;
        const double pxPerUnit = cam.pixelSize(1.0, std::sqrt(dx * dx + dy * dy + dz * dz));
        const double size = 2.0 * img.r[i] * pxPerUnit;
        const double area = std::min(0.785398 * size * size, screen);
        const FlatImage::Lod& lod = img.lods[img.aux[i]];
        const FlatImage::Range* rg = &img.ranges[lod.firstRange];
        for (int c = 0; c < obj.count; ++c) {
            const ChildWork& ch = work[1 + c].child;
            const double cost =
                rates.perTriangle * ch.tris + rates.perItem * ch.items + rates.perPixel * area;  // model.marginal()
            // Accuracy: from the levels' geometric errors when the LOD has them (LOD::setError, makeLod), as
            // 1 / (1 + the error's projected pixels); else the detail guessed from the triangles.
            const double acc = lod.hasErrors ? 1.0 / (1.0 + rg[c].error * pxPerUnit) : ch.detail;
            op[c] = {std::max(0.0, cost), area * acc};
        }
        if (b.coarsestScale > 0.0) obj.count = finestAllowed(img, i, eyeImg, cam, b.coarsestScale, obj.count);
        obj.options = op;
        op += work->count;
        area_[k] = area;
        const uint8_t last = history.last(i);
        obj.last = last != LodHistory::kNone && last < obj.count ? int(last) : -1;
    }
    // What the rest of the frame already costs comes off the budget.
    const double fixed = model.predict(fixedWork);
    const LodSelector::Selection& sel =
        selector_.select(objects_, std::max(0.0, b.budgetMs - fixed), b.hysteresis,
                         b.mayDrop ? LodSelector::Floor::CheapestFirst : LodSelector::Floor::Cheapest);
    chosen_ = sel.level;
    for (size_t k = 0; k < n; ++k) {
        history.show(deferred_[k].entry, LodHistory::child(chosen_[k]));
        stats.lodDropped += chosen_[k] < 0;
        if (chosen_[k] >= 0) {
            stats.lodLevels[std::min(chosen_[k], 3)]++;
            stats.lodPixels += area_[k];
        }
    }
    stats.lodObjects = n;
    stats.lodBudgetMs = b.budgetMs;
    stats.lodPredictedMs = fixed + sel.costMs;
    stats.lodSelectMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace sg
