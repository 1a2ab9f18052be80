// LodBudgetPlanner: the cull's time-budgeted LOD choice: the visible LODs the walk meets are set aside,
// then priced by the draw-cost model and valued by projected size times accuracy, and one child is chosen
// per LOD (or none) by LodSelector so that the frame fits its budget.
#pragma once
#include "sg/core/Camera.h"
#include "sg/cull/CullSettings.h"
#include "sg/cull/LodHistory.h"
#include "sg/lod/DrawCostModel.h"
#include "sg/lod/LodSelector.h"
#include "sg/scene/FlatImage.h"

#include <vector>

namespace sg {

class LodBudgetPlanner {
public:
    // A visible LOD entry met by the walk, with the walk's state there (its planes still in play, its
    // occlusion node, its matrix) so that the chosen child is walked as it would have been.
    struct Deferred {
        uint32_t entry, mask;
        int32_t occ;
        dmat4 m;
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

    // Chooses a child for every LOD set aside (entries of `img`, whose contents are those of `version`,
    // Scene::version()): priced for `cam` by b.model, within b.budgetMs less what `fixed` (the rest of the
    // frame) costs, last frame's choices in `history` favoured by b.hysteresis. Records the choices in
    // `history` and the plan's figures (lodObjects ... lodSelectMs) in `stats`.
    void plan(const FlatImage& img, uint64_t version, const Camera& cam, const LodBudgetSettings& b,
              const DrawCostModel::Work& fixed, LodHistory& history, CullStats& stats);
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
    uint32_t workIndex(const FlatImage& img, uint32_t i);  // its header's index in work_
    void track(const FlatImage& img, uint64_t version);
    static int finestAllowed(const FlatImage& img, uint32_t i, const dvec3& eyeImg, const Camera& cam, double scale,
                             int count);

    std::vector<Deferred> deferred_;
    std::vector<int> chosen_;   // per deferred LOD: the child shown, -1: none
    std::vector<double> area_;  // per deferred LOD: its projected area, pixels
    std::vector<Work> work_;
    std::vector<uint32_t> workAt_;  // per image entry: its Work header, ~0u: not worked out yet
    std::vector<uint32_t> workOf_;  // per deferred LOD: its Work header
    const FlatImage* workImage_ = nullptr;
    uint64_t workVersion_ = 0;
    std::vector<LodSelector::Option> options_;
    std::vector<LodSelector::Object> objects_;
    LodSelector selector_;
};

}  // namespace sg
