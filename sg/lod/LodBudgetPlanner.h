// LodBudgetPlanner: the cull's time-budgeted LOD choice: the visible LODs the walk meets are set aside,
// then priced by the draw-cost model and valued by projected size times accuracy, and one child is chosen
// per LOD (or none) by LodSelector so that the frame fits its budget.
#pragma once
#include "sg/core/Camera.h"
#include "sg/lod/DrawCostModel.h"
#include "sg/lod/LodBudgetSettings.h"
#include "sg/lod/LodHistory.h"
#include "sg/lod/LodPlanStats.h"
#include "sg/lod/LodSelector.h"
#include "sg/scene/FlatImage.h"
#include "sg/scene/ImageFrame.h"

#include <array>
#include <vector>

namespace sg {

class LodBudgetPlanner {
public:
    // A visible LOD entry met by the walk, with the walk's state there (its planes still in play, its
    // occlusion node, its matrix) so that the chosen child is walked as it would have been. `place`: the
    // image it is an entry of and where that image is (an index into plan()'s places, ImageFrames: the scene's
    // image, or an Instance's prototype at one placement); `record`: what it showed before (LodHistory's record).
    struct Deferred {
        uint32_t entry, mask;
        int32_t occ;
        dmat4 m;
        uint32_t place = 0;
        uint8_t record = LodHistory::kUnseen;
    };
    // What the budget needs of one LOD child, from the image: the work below it (triangles and draw items
    // of its geometries, nested LODs and switches counted whole: an upper bound) and its detail, a guess at
    // its accuracy from its share of the finest child's triangles.
    struct ChildWork {
        float tris, items, detail;
    };

    // A new frame: no LOD set aside.
    void clear() { deferred_.clear(); }
    void defer(const Deferred& d) { deferred_.push_back(d); }
    const std::vector<Deferred>& deferred() const { return deferred_; }

    // Chooses a child for every LOD set aside (entries of their places' images, whose contents are those
    // of `version`, Scene::version()): priced for `cam` by b.model, within b.budgetMs less what `fixed`
    // (the rest of the frame) costs, each LOD's `last` child favoured by b.hysteresis. Records the plan's
    // figures (lodObjects ... lodSelectMs) in `stats`.
    void plan(const std::vector<ImageFrame>& places, uint64_t version, const Camera& cam, const LodBudgetSettings& b,
              const DrawCostModel::Work& fixed, LodPlanStats& stats);
    // The same for LODs that are all entries of the scene's image `img` (their place 0), their last children
    // read from `history` and this frame's choices recorded there.
    void plan(const FlatImage& img, uint64_t version, const Camera& cam, const LodBudgetSettings& b,
              const DrawCostModel::Work& fixed, LodHistory& history, LodPlanStats& stats);
    // The child the plan chose for deferred()[k]; -1: none.
    int chosen(size_t k) const { return chosen_[k]; }

    // The children's work of LOD entry i of `img` (`count` of them). Worked out once per image and
    // version: kept until either changes.
    const ChildWork* work(const FlatImage& img, uint64_t version, uint32_t i, uint32_t& count);

private:
    // An LOD's header (count of children) followed by one entry per child.
    union Work {
        uint32_t count;
        ChildWork child;
    };
    // Its header's index in work_; `at`: the image's headers by entry (~0u: not worked out yet).
    uint32_t workIndex(const FlatImage& img, std::vector<uint32_t>& at, uint32_t i);
    std::vector<uint32_t>& track(const FlatImage& img, uint64_t version);  // the image's headers by entry
    bool keepLast(const LodBudgetSettings& b, double fixed);
    void finish(double fixed, double cost, LodPlanStats& stats) const;

    std::vector<Deferred> deferred_;
    std::vector<int> chosen_;   // per deferred LOD: the child shown, -1: none
    std::vector<double> area_;  // per deferred LOD: its projected area, pixels
    std::vector<int> first_;    // per deferred LOD: its finest option's child (LodBudgetSettings::finestScale)
    std::vector<Work> work_;
    // Per image met (the scene's, prototypes'): per entry, its Work header; all of them forgotten when the
    // scene's version changes.
    struct ImageWork {
        const FlatImage* img;
        std::vector<uint32_t> at;
    };
    std::vector<ImageWork> images_;
    uint64_t workVersion_ = 0;
    std::vector<uint32_t> workOf_;  // per deferred LOD: its Work header
    std::vector<ImageFrame> one_;   // plan()'s single place, for the scene's image alone
    std::vector<LodSelector::Option> options_;
    std::vector<LodSelector::Object> objects_;
    LodSelector selector_;
    // What a millisecond bought at the budget's edge (LodSelector::Selection::leftRatio) in recent frames that
    // fit, smoothed in logs; 0: no such frame yet.
    double price_ = 0.0;
    // The budgets of the last frames, for the deadband's median.
    static constexpr size_t kBudgets = 5;
    std::array<double, kBudgets> budgets_{};
    uint64_t budgetAt_ = 0;
    double lastCost_ = 0.0;
    dmat4 lastView_{1.0}, lastProjection_{1.0};  // the camera of the last plan: only a still view keeps its plan
    bool planned_ = false;
};

}  // namespace sg
