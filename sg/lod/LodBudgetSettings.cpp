#include "sg/lod/LodBudgetSettings.h"

namespace sg {

void LodBudgetSettings::validate(const char* caller) const {
    const SettingCheck c{caller};
    if (!model) c.fail("lodBudget.model", "null", "a cost model (DrawCostModel) when the budget is enabled");
    c.positive("lodBudget.budgetMs", budgetMs);
    c.atLeast("lodBudget.hysteresis", hysteresis, 0.0);
    c.atLeast("lodBudget.coarsestScale", coarsestScale, 0.0);
    c.atLeast("lodBudget.finestScale", finestScale, 0.0);
    c.atLeast("lodBudget.overrunShare", overrunShare, 0.0);
    c.atLeast("lodBudget.overrunWorth", overrunWorth, 0.0);
    c.share("lodBudget.keepOver", keepOver);
    c.share("lodBudget.keepUnder", keepUnder);
}

}  // namespace sg
