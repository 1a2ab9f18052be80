// The LOD budget of CullTraversal: every visible LOD's children priced by the draw-cost model and valued
// by projected size times accuracy, then one chosen per LOD (or none) by LodSelector to fit the budget.
#include "sg/cull/CullTraversal.h"
#include "sg/lod/DrawCostModel.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace sg {

// What the budget needs of an LOD's children that only changes with the image: work (triangles, items; the
// geometries below each child, nested LODs and switches counted whole: an upper bound) and detail, growing
// ever more slowly with the triangles (a tenth of the triangles keeps ~56% of the value). Worked out for the
// LODs met, once per image version.
uint32_t CullTraversal::lodWork(const FlatImage& img, uint32_t i) {
    if (lodWorkAt_[i] != ~0u) return lodWorkAt_[i];
    const size_t at = lodWork_.size();
    lodWork_.emplace_back();  // the header: the children's count
    float trisMax = 0.0f;
    for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j]) {
        LodWork w;
        w.child = {0.0f, 0.0f, 1.0f};
        for (uint32_t e = j; e < img.end[j]; ++e) {
            if (img.kind[e] != NodeKind::Geometry || (img.flags[e] & FlatImage::kEmpty)) continue;
            if (const Mesh* mesh = img.draws[img.aux[e]].mesh) {
                w.child.tris += float(mesh->triangleCount());
                w.child.items += 1.0f;
            }
        }
        trisMax = std::max(trisMax, w.child.tris);
        lodWork_.push_back(w);
    }
    lodWork_[at].count = uint32_t(lodWork_.size() - at - 1);
    for (size_t k = at + 1; k < lodWork_.size(); ++k)
        if (trisMax > 0.0f) lodWork_[k].child.detail = std::sqrt(std::sqrt(lodWork_[k].child.tris / trisMax));
    lodWorkAt_[i] = uint32_t(at);
    return uint32_t(at);
}

void CullTraversal::planLods(const FlatImage& img) {
    const auto t0 = std::chrono::steady_clock::now();
    const LodBudgetSettings& b = set_->lodBudget;
    const DrawCostModel& model = *b.model;
    const dvec3 eyeImg = cam_->eye() - img.origin;
    const double ppu = cam_->pixelsPerUnit(), zNear = std::max(-cam_->eyePlanes()[4].d, 1e-6);
    const double screen = double(cam_->width()) * cam_->height();
    const DrawCostModel::Rates rates = model.rates();
    if (lodWorkImage_ != &img || lodWorkVersion_ != scene_->version() || lodWorkAt_.size() != img.size()) {
        lodWorkAt_.assign(img.size(), ~0u);
        lodWork_.clear();
        lodWorkImage_ = &img;
        lodWorkVersion_ = scene_->version();
    }
    // Each LOD's children's work and detail, from the image (kept while the scene's version stays); then
    // room for every option at once.
    const size_t n = deferred_.size();
    lodObjects_.resize(n);
    lodWorkOf_.resize(n);
    size_t total = 0;
    for (size_t k = 0; k < n; ++k) {
        lodWorkOf_[k] = lodWork(img, deferred_[k].entry);
        total += lodWork_[lodWorkOf_[k]].count;
    }
    if (lodOptions_.size() < total) lodOptions_.resize(total);
    lodArea_.resize(n);
    LodSelector::Option* op = lodOptions_.data();
    const bool persp = cam_->perspective();
    for (size_t k = 0; k < n; ++k) {
        const uint32_t i = deferred_[k].entry;
        const LodWork* work = &lodWork_[lodWorkOf_[k]];
        LodSelector::Object& obj = lodObjects_[k];
        obj.count = int(work->count);
        // Projected area of the LOD's bound, the value of drawing it at all.
        const double dx = img.cx[i] - eyeImg.x, dy = img.cy[i] - eyeImg.y, dz = img.cz[i] - eyeImg.z;
        const double pxPerUnit = persp ? ppu / std::max(std::sqrt(dx * dx + dy * dy + dz * dz), zNear) : ppu;
        const double size = 2.0 * img.r[i] * pxPerUnit;
        const double area = std::min(0.785398 * size * size, screen);
        const FlatImage::Lod& lod = img.lods[img.aux[i]];
        const FlatImage::Range* rg = &img.ranges[lod.firstRange];
        for (int c = 0; c < obj.count; ++c) {
            const LodWork::Child& ch = work[1 + c].child;
            const double cost =
                rates.perTriangle * ch.tris + rates.perItem * ch.items + rates.perPixel * area;  // model.marginal()
            // Accuracy: from the levels' geometric errors when the LOD has them (LOD::setError, makeLod), as
            // 1 / (1 + the error's projected pixels); else the detail guessed from the triangles.
            const double acc = lod.hasErrors ? 1.0 / (1.0 + rg[c].error * pxPerUnit) : ch.detail;
            op[c] = {std::max(0.0, cost), area * acc};
        }
        obj.options = op;
        op += obj.count;
        lodArea_[k] = area;
        const uint8_t last = lodLast_[i];
        obj.last = last != 0xff && last < obj.count ? int(last) : -1;
    }
    // What the rest of the frame already costs comes off the budget.
    const double fixed = model.predict({double(triangles_), double(out_->items.size()), 0.0});
    const LodSelector::Selection& sel =
        selector_.select(lodObjects_, std::max(0.0, b.budgetMs - fixed), b.hysteresis,
                         b.mayDrop ? LodSelector::Floor::Nothing : LodSelector::Floor::Cheapest);
    chosen_ = sel.level;
    for (size_t k = 0; k < deferred_.size(); ++k) {
        lodLast_[deferred_[k].entry] = chosen_[k] < 0 ? 0xff : uint8_t(std::min(chosen_[k], 254));
        stats_->lodDropped += chosen_[k] < 0;
        if (chosen_[k] >= 0) {
            stats_->lodLevels[std::min(chosen_[k], 3)]++;
            stats_->lodPixels += lodArea_[k];
        }
    }
    stats_->lodObjects = deferred_.size();
    stats_->lodBudgetMs = b.budgetMs;
    stats_->lodPredictedMs = fixed + sel.costMs;
    stats_->lodSelectMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace sg
