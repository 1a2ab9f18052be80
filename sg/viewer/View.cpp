#include "sg/viewer/View.h"

#include <algorithm>
#include <stdexcept>

namespace sg {

namespace {
constexpr double kMissFrames = 10.0;   // the budget's miss is smoothed over about this many frames
constexpr double kMaxMissShare = 0.2;  // and comes off its plan up to this share of the budget
}  // namespace

namespace {
const EnumName<LodPolicy> kLodPolicies[] = {
    {LodPolicy::Static, "static"}, {LodPolicy::Stress, "stress"}, {LodPolicy::Budget, "budget"}};
}  // namespace

const char* lodPolicyName(LodPolicy p) { return enumName(kLodPolicies, p); }
LodPolicy parseLodPolicy(const std::string& name) {
    return parseEnum(kLodPolicies, name, "parseLodPolicy()", "an LOD policy");
}

CullSettings View::frameSettings(double periodMs, double spentMs, bool held) {
    CullSettings set = cull;
    const double budget = budgetMs(periodMs);
    if (lod != LodPolicy::Static && !(budget > 0.0 && std::isfinite(budget)))
        throw std::invalid_argument("Viewer::frame(): the view's LOD budget " + std::to_string(budget) +
                                    " ms is not a positive time");
    if (lod == LodPolicy::Stress) {
        if (stressBudgetMs_ != budget) {  // a new budget: stress starts again from scale 1
            LodStress::Params p;
            p.budgetMs = budget;
            stress_ = LodStress(p);
            stressBudgetMs_ = budget;
        }
        set.lodScale *= stress_.scale();
    }
    if (lod == LodPolicy::Budget) {
        set.lodBudget.enabled = true;
        set.lodBudget.model = &model_;
        // The frame's time before the draw comes off, and with a held frame rate the plan's usual miss.
        set.lodBudget.budgetMs =
            std::max(1.0, budget - spentMs - (held ? std::min(missMs_, kMaxMissShare * budget) : 0.0));
    }
    return set;
}

void View::learn(double workMs, bool timed) {
    if (lod == LodPolicy::Stress) stress_.update(workMs);
    if (!timed) return;
    model_.update({triangleWork(double(stats_.triangles), double(stats_.points), double(stats_.lines)),
                   double(stats_.geometries), stats_.lodPixels},
                  drawMs_);
    // The plan's own prediction against the measured time: the loop closes on what the budget planned (a frame
    // with no LOD in view was not planned).
    if (lod == LodPolicy::Budget && stats_.lodObjects > 0) {
        model_.correct(stats_.lodPredictedMs, drawMs_);
        missMs_ += (std::max(0.0, drawMs_ - stats_.lodPredictedMs) - missMs_) / kMissFrames;  // overruns only
    }
}

}  // namespace sg
