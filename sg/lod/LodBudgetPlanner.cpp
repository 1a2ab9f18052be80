#include "sg/lod/LodBudgetPlanner.h"

#include "sg/lod/internal/LodChooser.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

namespace sg {

namespace {
constexpr double kPriceFrames = 8.0;  // the time constant of the price of a millisecond, frames
}  // namespace

std::vector<uint32_t>& LodBudgetPlanner::track(const FlatImage& img, uint64_t version) {
    if (workVersion_ != version) {
        images_.clear();
        work_.clear();
        workVersion_ = version;
    }
    for (ImageWork& w : images_)
        if (w.img == &img && w.at.size() == img.size()) return w.at;
    for (ImageWork& w : images_)  // the same image, another size: its work is stale (work_ keeps the old)
        if (w.img == &img) {
            w.at.assign(img.size(), ~0u);
            return w.at;
        }
    images_.push_back({&img, std::vector<uint32_t>(img.size(), ~0u)});
    return images_.back().at;
}

const LodBudgetPlanner::ChildWork* LodBudgetPlanner::work(const FlatImage& img, uint64_t version, uint32_t i,
                                                          uint32_t& count) {
    const uint32_t at = workIndex(img, track(img, version), i);
    count = work_[at].count;
    return &work_[at + 1].child;
}

// Detail grows ever more slowly with the triangles: a tenth of the triangles keeps ~56% of the value.
uint32_t LodBudgetPlanner::workIndex(const FlatImage& img, std::vector<uint32_t>& workAt, uint32_t i) {
    if (workAt[i] != ~0u) return workAt[i];
    const size_t at = work_.size();
    work_.emplace_back();  // the header: the children's count
    float trisMax = 0.0f;
    for (uint32_t j = i + 1; j < img.end[i]; j = img.end[j]) {
        Work w;
        w.child = {0.0f, 0.0f, 1.0f};
        for (uint32_t e = j; e < img.end[j]; ++e) {
            if (img.kind[e] != NodeKind::Geometry || (img.flags[e] & FlatImage::kEmpty)) continue;
            if (const Mesh* mesh = img.draws[img.aux[e]].mesh) {
                w.child.tris += float(triangleWork(*mesh));
                w.child.items += 1.0f;
            }
        }
        trisMax = std::max(trisMax, w.child.tris);
        work_.push_back(w);
    }
    work_[at].count = uint32_t(work_.size() - at - 1);
    for (size_t k = at + 1; k < work_.size(); ++k)
        if (trisMax > 0.0f) work_[k].child.detail = std::sqrt(std::sqrt(work_[k].child.tris / trisMax));
    workAt[i] = uint32_t(at);
    return uint32_t(at);
}

void LodBudgetPlanner::plan(const FlatImage& img, uint64_t version, const Camera& cam, const LodBudgetSettings& b,
                            const DrawCostModel::Work& fixedWork, LodHistory& history, LodPlanStats& stats) {
    ImageFrame f;
    f.img = &img;
    f.eyeImg = cam.eye() - img.origin;
    one_.assign(1, f);
    for (Deferred& d : deferred_) {
        d.place = 0;
        d.record = history.record(d.entry);
    }
    plan(one_, version, cam, b, fixedWork, stats);
    for (size_t k = 0; k < deferred_.size(); ++k) history.show(deferred_[k].entry, LodHistory::child(chosen_[k]));
}

void LodBudgetPlanner::plan(const std::vector<ImageFrame>& places, uint64_t version, const Camera& cam,
                            const LodBudgetSettings& b, const DrawCostModel::Work& fixedWork, LodPlanStats& stats) {
    const auto t0 = std::chrono::steady_clock::now();
    b.validate("LodBudgetPlanner::plan()");
    const DrawCostModel& model = *b.model;
    const double screen = double(cam.width()) * cam.height();
    const DrawCostModel::Rates rates = model.rates();
    const LodChooser chooser({&cam});
    // Each LOD's children's work and detail, from its image (kept while the scene's version stays); then
    // room for every option at once.
    const size_t n = deferred_.size();
    objects_.resize(n);
    workOf_.resize(n);
    size_t total = 0;
    for (size_t k = 0; k < n; ++k) {
        const FlatImage& img = *places[deferred_[k].place].img;
        workOf_[k] = workIndex(img, track(img, version), deferred_[k].entry);
        total += work_[workOf_[k]].count;
    }
    if (options_.size() < total) options_.resize(total);
    area_.resize(n);
    first_.resize(n);
    LodSelector::Option* op = options_.data();
    for (size_t k = 0; k < n; ++k) {
        const uint32_t i = deferred_[k].entry;
        const ImageFrame& place = places[deferred_[k].place];
        const FlatImage& img = *place.img;
        const Work* work = &work_[workOf_[k]];
        LodSelector::Object& obj = objects_[k];
        obj.count = int(work->count);
        // Projected area of the LOD's bound, the value of drawing it at all. Its centre's distance and a
        // length's pixels are the world's: through the placement for a prototype's entry.
        const double dist = place.distance(img.cx[i], img.cy[i], img.cz[i]);
        const double pxPerUnit = cam.pixelSize(1.0, dist) * place.scale;  // pixels per image unit
        const double size = 2.0 * img.r[i] * pxPerUnit;
        // A level's error shows most at the bound's nearest point: beside a building's wall its coarse level is
        // metres off on screen, however far its centre is.
        const double nearest = std::max(dist - img.r[i] * place.scale, cam.nearDistance());
        const double errPxPerUnit = cam.pixelSize(1.0, nearest) * place.scale;
        const double area = std::min(0.785398 * size * size, screen);
        const FlatImage::Lod& lod = img.lods[img.aux[i]];
        const FlatImage::Range* rg = &img.ranges[lod.firstRange];
        for (int c = 0; c < obj.count; ++c) {
            const ChildWork& ch = work[1 + c].child;
            const double cost =
                rates.perTriangle * ch.tris + rates.perItem * ch.items + rates.perPixel * area;  // model.marginal()
            // Accuracy: from the levels' geometric errors when the LOD has them (LOD::setError, makeLod), as
            // 1 / (1 + the error's projected pixels at the nearest point); else the detail guessed from the
            // triangles.
            const double acc = lod.hasErrors ? 1.0 / (1.0 + rg[c].error * errPxPerUnit) : ch.detail;
            op[c] = {std::max(0.0, cost), area * acc};
        }
        // The options: children `first` .. `limit` - 1 (finest first), as the settings' scales bound them.
        int first = 0, limit = obj.count, a, z;
        obj.keep = false;
        if (b.coarsestScale > 0.0) {
            chooser.shownAt(place, i, b.coarsestScale, false, a, z);
            if (z >= 0) limit = z + 1;
            // Left out (b.mayDrop) only where those ranges leave it out too: never a hole where stress at its
            // coarsest draws something.
            obj.keep = z >= 0;
        }
        if (b.coarsestScale > 0.0 && lod.hasErrors) {
            // And none whose error shows more than coarsestScale pixels at the bound's nearest point: the
            // ranges measure from the centre, and beside a building's wall its coarse level is metres off
            // on screen, however far its centre is. The finest level always stays.
            int c = 1;
            while (c < limit && rg[c].error * errPxPerUnit <= b.coarsestScale) ++c;
            limit = c;
        }
        if (b.finestScale > 0.0) {
            // With the fade band: at a switch the ranges still draw the finer child, fading out, and its
            // detail (a shadow baked into a terrain tile's vertices) shows until the band ends.
            chooser.shownAt(place, i, b.finestScale, true, a, z);
            if (a >= 0) first = std::min(a, limit - 1);
        }
        obj.options = op + first;
        obj.count = limit - first;
        first_[k] = first;
        op += work->count;
        area_[k] = area;
        const uint8_t shown = LodHistory::shown(deferred_[k].record);
        const int last = shown == LodHistory::kNone ? -1 : int(shown);
        obj.last = last >= first && last < limit ? last - first : -1;
    }
    // What the rest of the frame already costs comes off the budget.
    const double fixed = model.predict(fixedWork);
    chosen_.resize(n);
    // Only a still view keeps its plan: a moving one plans anew each frame (its areas change, and a plan kept from
    // frames ago would hold levels the view no longer wants).
    const bool still = cam.view() == lastView_ && cam.projection() == lastProjection_ && planned_;
    lastView_ = cam.view();
    lastProjection_ = cam.projection();
    planned_ = true;
    if (keepLast(b, fixed) && still) {
        finish(fixed, lastCost_, stats);
        stats.lodBudgetMs = b.budgetMs;
        stats.lodPlansKept = 1;
        stats.lodSelectMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        return;
    }
    LodSelector::Overrun overrun;
    if (b.overrunShare > 0.0 && price_ > 0.0 && std::isfinite(b.overrunShare * b.overrunWorth * price_)) {
        overrun.minRatio = b.overrunWorth * price_;
        overrun.maxMs = b.overrunShare * b.budgetMs;
    }
    const LodSelector::Selection& sel =
        selector_.select(objects_, std::max(0.0, b.budgetMs - fixed), b.hysteresis,
                         b.mayDrop ? LodSelector::Floor::CheapestFirst : LodSelector::Floor::Cheapest, overrun);
    if (sel.fit && sel.leftRatio > 0.0 && std::isfinite(sel.leftRatio))
        price_ = price_ > 0.0 ? price_ * std::pow(sel.leftRatio / price_, 1.0 / kPriceFrames) : sel.leftRatio;
    for (size_t k = 0; k < n; ++k) chosen_[k] = sel.level[k] < 0 ? -1 : sel.level[k] + first_[k];
    finish(fixed, sel.costMs, stats);
    stats.lodBudgetMs = b.budgetMs;
    stats.lodSelectMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// The deadband (LodBudgetSettings::keepOver, keepUnder): whether last frame's choices stand, and then chosen_ holds
// them and lastCost_ their predicted cost. The frame's budget is noted first; the test holds the whole frame's
// prediction (`fixed`, the rest of the frame, plus the kept choices) to the median budget of the last few frames
// (steadyBudget_), so that one frame whose cull was preempted does not drop a hundred far LODs for a frame (a lasting
// change is followed within kBudgets / 2 + 1 frames); a new plan fits this frame's budget. The band is a share of the
// whole budget, not of the room left to the LODs: one LOD's step can be a third of that room.
bool LodBudgetPlanner::keepLast(const LodBudgetSettings& b, double fixed) {
    budgets_[budgetAt_++ % kBudgets] = b.budgetMs;
    const size_t have = std::min<size_t>(budgetAt_, kBudgets);
    std::array<double, kBudgets> sorted{};
    std::copy(budgets_.begin(), budgets_.begin() + long(have), sorted.begin());
    std::nth_element(sorted.begin(), sorted.begin() + long(have / 2), sorted.begin() + long(have));
    const double steady = sorted[have / 2];
    if (b.keepOver <= 0.0 && b.keepUnder <= 0.0) return false;
    double cost = 0.0;
    for (size_t k = 0; k < deferred_.size(); ++k) {
        const uint8_t record = deferred_[k].record;
        if (record == LodHistory::kUnseen) return false;  // new in view: a plan anew
        const LodSelector::Object& obj = objects_[k];
        const uint8_t shown = LodHistory::shown(record);
        if (shown == LodHistory::kNone) {
            if (obj.keep) return false;  // left out, but may not be now
            chosen_[k] = -1;
            continue;
        }
        if (obj.last < 0) return false;  // its last child is no longer an option (the view moved)
        cost += obj.options[obj.last].costMs;
        chosen_[k] = obj.last + first_[k];
    }
    lastCost_ = cost;
    const double total = fixed + cost;
    return !deferred_.empty() && total <= steady * (1.0 + b.keepOver) && total >= steady * (1.0 - b.keepUnder);
}

void LodBudgetPlanner::finish(double fixed, double cost, LodPlanStats& stats) const {
    for (size_t k = 0; k < chosen_.size(); ++k) {
        stats.lodDropped += chosen_[k] < 0;
        if (chosen_[k] >= 0) {
            stats.lodLevels[std::min(chosen_[k], 3)]++;
            stats.lodPixels += area_[k];
        }
    }
    stats.lodObjects = chosen_.size();
    stats.lodPredictedMs = fixed + cost;
}

}  // namespace sg
