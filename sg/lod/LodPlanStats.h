// LodPlanStats: what the LOD budget's plan of one cull counted (LodBudgetPlanner::plan); part of CullStats.
#pragma once
#include <cstdint>

namespace sg {

struct LodPlanStats {
    uint64_t lodObjects = 0;      // visible LODs planned
    uint64_t lodDropped = 0;      // left out to fit the budget
    uint64_t lodLevels[4] = {};   // LODs shown at child 0, 1, 2, and 3 or more
    double lodBudgetMs = 0.0;     // the budget planned for (LodBudgetSettings::budgetMs)
    double lodPixels = 0.0;       // projected bound areas of the LODs drawn: DrawCostModel::Work::pixels
    double lodPredictedMs = 0.0;  // predicted draw time of the whole frame
    double lodSelectMs = 0.0;
    uint64_t lodPlansKept = 0;  // 1 when last frame's choices were kept whole (LodBudgetSettings::keepOver)
};

}  // namespace sg
