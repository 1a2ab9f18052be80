// The LOD budget of CullTraversal: every visible LOD's children priced by the draw-cost model and valued
// by projected size times accuracy, then one chosen per LOD (or none) by LodSelector to fit the budget.
#include "sg/CullTraversal.h"
#include "sg/DrawCostModel.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace sg {

void CullTraversal::planLods(const FlatImage& img) {
    const auto t0 = std::chrono::steady_clock::now();
    const LodBudgetSettings& b = set_->lodBudget;
    const DrawCostModel& model = *b.model;
    const dvec3 eyeImg = cam_->eye() - img.origin;
    const double ppu = cam_->pixelsPerUnit(), zNear = std::max(-cam_->eyePlanes()[4].d, 1e-6);
    const double screen = double(cam_->width()) * cam_->height();
    const DrawCostModel::Rates rates = model.rates();
    lodOptions_.resize(0);
    lodObjects_.resize(0);
    const bool persp = cam_->perspective();
    for (const DeferredLod& d : deferred_) {
        const uint32_t i = d.entry;
        // Projected area of the LOD's bound, the value of drawing it at all.
        const double dx = img.cx[i] - eyeImg.x, dy = img.cy[i] - eyeImg.y, dz = img.cz[i] - eyeImg.z;
        const double pxPerUnit = persp ? ppu / std::max(std::sqrt(dx * dx + dy * dy + dz * dz), zNear) : ppu;
        const double size = 2.0 * img.r[i] * pxPerUnit;
        const double area = std::min(0.785398 * size * size, screen);
        // Each child's work: the geometries below it (nested LODs and switches counted whole: an upper bound).
        const size_t first = lodOptions_.size();
        double trisMax = 0.0;
        const uint32_t end = img.end[i];
        for (uint32_t j = i + 1; j < end; j = img.end[j]) {
            double tris = 0.0, items = 0.0;
            for (uint32_t e = j, je = img.end[j]; e < je; ++e) {
                if (img.kind[e] != NodeKind::Geometry || (img.flags[e] & FlatImage::kEmpty)) continue;
                if (const Mesh* mesh = img.draws[img.aux[e]].mesh) {
                    tris += double(mesh->triangleCount());
                    items += 1.0;
                }
            }
            trisMax = std::max(trisMax, tris);
            const double cost = rates.perTriangle * tris + rates.perItem * items + rates.perPixel * area;  // model.marginal()
            lodOptions_.push_back({std::max(0.0, cost), tris});  // benefit finished below
        }
        // Accuracy: from the levels' geometric errors when the LOD has them (LOD::setError, makeLod), as
        // 1 / (1 + the error's projected pixels); else from detail, growing ever more slowly (a tenth of
        // the triangles keeps ~56% of the value).
        LodSelector::Option* op = lodOptions_.data() + first;
        const int count = int(lodOptions_.size() - first);
        const FlatImage::Lod& lod = img.lods[img.aux[i]];
        const FlatImage::Range* rg = &img.ranges[lod.firstRange];
        if (lod.hasErrors)
            for (int k = 0; k < count; ++k) op[k].benefit = area / (1.0 + rg[k].error * pxPerUnit);
        else
            for (int k = 0; k < count; ++k) op[k].benefit = trisMax > 0.0 ? area * std::sqrt(std::sqrt(op[k].benefit / trisMax)) : area;
        const uint8_t last = lodLast_[i];
        lodObjects_.push_back({nullptr, count, last != 0xff && last < count ? int(last) : -1});
    }
    size_t at = 0;
    for (LodSelector::Object& o : lodObjects_) {
        o.options = lodOptions_.data() + at;
        at += size_t(o.count);
    }
    // What the rest of the frame already costs comes off the budget.
    const double fixed = model.predict({double(triangles_), double(out_->items.size()), 0.0});
    const LodSelector::Selection& sel = selector_.select(lodObjects_, std::max(0.0, b.budgetMs - fixed), b.hysteresis,
                                                         b.mayDrop ? LodSelector::Floor::Nothing : LodSelector::Floor::Cheapest);
    chosen_ = sel.level;
    for (size_t k = 0; k < deferred_.size(); ++k) {
        lodLast_[deferred_[k].entry] = chosen_[k] < 0 ? 0xff : uint8_t(std::min(chosen_[k], 254));
        stats_->lodDropped += chosen_[k] < 0;
        if (chosen_[k] >= 0) stats_->lodLevels[std::min(chosen_[k], 3)]++;
    }
    stats_->lodObjects = deferred_.size();
    stats_->lodBudgetMs = b.budgetMs;
    stats_->lodPredictedMs = fixed + sel.costMs;
    stats_->lodSelectMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace sg
