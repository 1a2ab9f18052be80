// LodBudgetSettings: the time budget's part of the cull's settings (CullSettings::lodBudget), with the rules of
// the LOD layer that read it.
#pragma once
#include "sg/core/Settings.h"

namespace sg {

class DrawCostModel;

// Time-budgeted LOD selection (Funkhouser and Sequin's adaptive display): every visible LOD of the scene
// (those of Instance prototypes at each placement too) offers its children as options, priced by the draw-cost model
// and valued by projected size times accuracy; sg/lod/LodSelector.h picks one per LOD, or none, to fit the budget.
// The defaults are those that work (sgbench lod and the factory walkthrough measure them, docs/benchmarks.md): a
// budget no worse than stress at its coarsest, never finer than the ranges show, a late frame buying what it
// needs most.
struct LodBudgetSettings {
    bool enabled = false;
    double budgetMs = 33.3;                // predicted draw time the frame must fit; > 0
    double hysteresis = 0.1;               // last frame's choice ranks (1 + this) times higher; >= 0
    const DrawCostModel* model = nullptr;  // required when enabled; feed it measured frames
    // Whether a visible LOD may be left out to fit: off, every one is drawn at least at its cheapest level
    // (a coarse object reads better than a hole), and the budget buys the upgrades. On, LODs are left out
    // only when their cheapest levels alone overrun the budget, those showing least per millisecond first,
    // and then no LOD is drawn finer than its cheapest (LodSelector::Floor::CheapestFirst). With a
    // coarsestScale, only LODs its ranges leave out may be left out: the others are drawn at their cheapest.
    bool mayDrop = true;
    // Above 0: no LOD drawn coarser than its ranges show it at this LOD scale (CullSettings::lodScale); the
    // default is stress's largest (LodStress::Params::maxScale's default), so that when the budget cannot be met the
    // picture is no worse than stress's at its coarsest and the frame runs over as stress's does. An LOD these ranges
    // leave out is not limited. An LOD with known level errors (LOD::setError) is also drawn at no level
    // whose error projects to more than coarsestScale pixels at its bound's nearest point. 0: any level.
    double coarsestScale = 16.0;
    // Above 0: no LOD drawn finer than its ranges show it at this LOD scale; the default 1: where the ranges switch
    // where a level's error projects to a pixel: a finer level is not seen, and the triangles it would take
    // show more elsewhere (priced by projected area, the finest level of a hill beside the eye outbid the
    // buildings). An LOD these ranges leave out is not limited. A child fading out (LOD::setTransition) is
    // still shown: the ranges draw it to the end of its band. 0: any level.
    double finestScale = 1.0;
    // Above 0: upgrades past the budget (LodSelector::Overrun), up to this share of it, when they are worth
    // overrunWorth times what a millisecond bought at the budget's edge in recent frames that fit. A frame
    // whose cheapest levels already overrun is late anyway: with the wall in front of the eye drawn at its
    // coarse level, it saves a millisecond or two and shows every pixel of the wall wrong. 0: the budget is a
    // hard limit. Both finite and >= 0.
    double overrunShare = 0.15;
    double overrunWorth = 4.0;
    // The deadband that makes a still view a still picture: last frame's choices are kept as they are while the
    // camera has not moved since the last plan, every LOD planned was planned before, each one's last child is still
    // among its options, and the whole frame's predicted time with them lies within [1 - keepUnder, 1 + keepOver] of
    // the budget (as a median over the last few frames: one frame's spike of measured app or cull time, which comes off
    // the viewer's budget, moves nothing). Outside it, or when the view brings LODs in or out, the plan is made anew. 0
    // and 0: a new plan every frame. Both in [0, 1].
    double keepOver = 0.15;
    double keepUnder = 0.30;

    // Throws SettingError naming `caller` (CullSettings::validate() calls it when the budget is enabled).
    void validate(const char* caller) const;
};

}  // namespace sg
