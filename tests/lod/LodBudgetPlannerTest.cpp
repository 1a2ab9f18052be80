// LodBudgetPlanner alone: the work of an LOD's children (kept per image version) and the plan's choices.
#include "TestUtil.h"
#include "nodes/Geometry.h"
#include "nodes/LOD.h"
#include "nodes/Transform.h"
#include "sg/cull/OcclusionTree.h"
#include "sg/lod/LodBudgetPlanner.h"
#include "sg/scene/Scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace sg;

namespace {
// A mesh of n triangles (a fan; only the count matters here).
ref_ptr<Mesh> triangles(int n) {
    std::vector<vec3> pos{vec3(0.0f)};
    std::vector<uint32_t> idx;
    for (int k = 0; k <= n; ++k) pos.push_back(vec3(std::cos(0.01f * k), 0.0f, std::sin(0.01f * k)));
    for (int k = 0; k < n; ++k) idx.insert(idx.end(), {0u, uint32_t(k + 1), uint32_t(k + 2)});
    auto m = make<Mesh>();
    m->set(pos, std::vector<vec3>(pos.size(), vec3(0, -1, 0)), idx);
    return m;
}

// `count` LODs along +y, 10 m apart from y = 20, each a fine (1,000 triangles) and a coarse (10) child.
struct Row {
    ref_ptr<Group> root = make<Group>();
    ref_ptr<Mesh> fine = triangles(1000), coarse = triangles(10);
    std::vector<ref_ptr<Geometry>> coarseGeoms;
    explicit Row(int count) {
        for (int k = 0; k < count; ++k) {
            auto t = make<Transform>();
            t->setTranslation(dvec3(0, 20 + 10 * k, 0));
            auto lod = make<LOD>();
            lod->addChild(make<Geometry>(fine, make<Material>()), 0.0f, 1e6f);
            coarseGeoms.push_back(make<Geometry>(coarse, make<Material>()));
            lod->addChild(coarseGeoms.back(), 1e6f, 2e6f);
            t->addChild(lod);
            root->addChild(t);
        }
    }
};

std::vector<uint32_t> lodEntries(const FlatImage& img) {
    std::vector<uint32_t> out;
    for (uint32_t i = 0; i < img.size(); ++i)
        if (img.kind[i] == NodeKind::LOD) out.push_back(i);
    return out;
}

}  // namespace

TEST(LodBudgetPlanner, WorksOutEachChildsTrianglesAndDetail) {
    Row row(1);
    Scene s(row.root);
    s.update();
    LodBudgetPlanner planner;
    uint32_t count = 0;
    const auto* w = planner.work(s.image(), s.version(), lodEntries(s.image())[0], count);
    ASSERT_EQ(count, 2u);
    EXPECT_EQ(w[0].tris, 1000.0f);
    EXPECT_EQ(w[0].items, 1.0f);
    EXPECT_EQ(w[0].detail, 1.0f);
    EXPECT_EQ(w[1].tris, 10.0f);
    EXPECT_NEAR(w[1].detail, std::pow(0.01, 0.25), 1e-6);  // a hundredth of the triangles: ~32% of the value
}

TEST(LodBudgetPlanner, KeepsTheWorkUntilTheVersionChanges) {
    Row row(1);
    Scene s(row.root);
    s.update();
    const uint64_t before = s.version();
    const uint32_t lod = lodEntries(s.image())[0];
    LodBudgetPlanner planner;
    uint32_t count = 0;
    EXPECT_EQ(planner.work(s.image(), before, lod, count)[1].tris, 10.0f);
    row.coarseGeoms[0]->setMesh(triangles(100));
    s.update();
    ASSERT_NE(s.version(), before);
    // Asked for the old version, the work is the one kept; for the new one it is worked out again.
    EXPECT_EQ(planner.work(s.image(), before, lod, count)[1].tris, 10.0f);
    EXPECT_EQ(planner.work(s.image(), s.version(), lod, count)[1].tris, 100.0f);
}

TEST(LodBudgetPlanner, ChoosesLevelsThatFitTheBudgetNearestFirst) {
    Row row(20);
    Scene s(row.root);
    s.update();
    const FlatImage& img = s.image();
    const std::vector<uint32_t> lods = lodEntries(img);
    ASSERT_EQ(lods.size(), 20u);
    const DrawCostModel model = testutil::trainedCostModel();
    LodBudgetSettings b = testutil::plainBudget(&model);
    LodHistory history;
    history.track(img, s.structureVersion());
    LodBudgetPlanner planner;
    auto plan = [&](double budgetMs, bool mayDrop) {
        b.budgetMs = budgetMs;
        b.mayDrop = mayDrop;
        planner.clear();
        for (uint32_t i : lods) planner.defer({i, 0u, OcclusionTree::kVisible, dmat4(1.0)});
        LodPlanStats stats;
        planner.plan(img, s.version(), testutil::lookingAlongY(), b, {}, history, stats);
        return stats;
    };

    LodPlanStats st = plan(100.0, false);  // room for everything: all fine
    EXPECT_EQ(st.lodObjects, 20u);
    EXPECT_EQ(st.lodLevels[0], 20u);
    EXPECT_LE(st.lodPredictedMs, 100.0);
    for (size_t k = 0; k < lods.size(); ++k) EXPECT_EQ(history.last(lods[k]), planner.chosen(k));

    st = plan(1.3, false);  // a little over the fixed cost: every LOD drawn, most coarse, the fine ones near
    EXPECT_EQ(st.lodLevels[0] + st.lodLevels[1], 20u);
    EXPECT_GT(st.lodLevels[0], 0u);
    EXPECT_GE(st.lodLevels[1], 10u);
    EXPECT_LE(st.lodPredictedMs, 1.3 + 1e-9);
    bool coarseSeen = false;
    for (size_t k = 0; k < lods.size(); ++k) {
        EXPECT_FALSE(coarseSeen && planner.chosen(k) == 0) << "a fine level behind a coarse one, LOD " << k;
        coarseSeen |= planner.chosen(k) == 1;
        EXPECT_EQ(history.last(lods[k]), planner.chosen(k));
    }

    st = plan(0.5, true);  // below the fixed cost, may drop: nothing drawn
    EXPECT_EQ(st.lodDropped, 20u);
    for (size_t k = 0; k < lods.size(); ++k) {
        EXPECT_EQ(planner.chosen(k), -1);
        EXPECT_EQ(history.last(lods[k]), LodHistory::kNone);
    }
}

namespace {
// The planner over a Row of twenty LODs, every one deferred at each plan().
struct RowPlan {
    Row row{20};
    Scene s{row.root};
    std::vector<uint32_t> lods;
    DrawCostModel model = testutil::trainedCostModel();
    LodBudgetSettings b;
    LodHistory history;
    LodBudgetPlanner planner;
    RowPlan() {
        s.update();
        lods = lodEntries(s.image());
        b = testutil::plainBudget(&model);
        history.track(s.image(), s.structureVersion());
    }
    LodPlanStats plan() {
        planner.clear();
        for (uint32_t i : lods) planner.defer({i, 0u, OcclusionTree::kVisible, dmat4(1.0)});
        LodPlanStats stats;
        planner.plan(s.image(), s.version(), testutil::lookingAlongY(), b, {}, history, stats);
        return stats;
    }
};
}  // namespace

// coarsestScale: no LOD drawn coarser than its ranges show it at that scale, however tight the budget; an
// LOD the ranges leave out at that scale is not limited.
TEST(LodBudgetPlanner, NoLevelCoarserThanTheRangesShowAtTheCoarsestScale) {
    RowPlan p;
    p.b.budgetMs = 1.3;  // most LODs coarse without the limit (as in ChoosesLevelsThatFitTheBudgetNearestFirst)
    auto plan = [&](double coarsestScale) {
        p.b.coarsestScale = coarsestScale;
        return p.plan();
    };
    EXPECT_GE(plan(0.0).lodLevels[1], 10u);   // off: the budget goes coarse
    const LodPlanStats limited = plan(16.0);  // 20-210 m times 16 is still in the fine range, [0, 1e6)
    EXPECT_EQ(limited.lodLevels[0], 20u);
    EXPECT_GT(limited.lodPredictedMs, 1.3);  // over the budget, as stress at its largest scale would be
    EXPECT_GE(plan(1e5).lodLevels[1], 10u);  // 2e6 and beyond: the ranges show nothing there, no limit
}

// finestScale: no LOD drawn finer than its ranges show it at that scale, however much room is left; an LOD the
// ranges leave out at that scale is not limited.
TEST(LodBudgetPlanner, NoLevelFinerThanTheRangesShowAtTheFinestScale) {
    RowPlan p;
    p.b.budgetMs = 100.0;   // room for every fine level
    p.b.finestScale = 5e4;  // 20 and 30 m look like 1e6 and 1.5e6: the coarse range; 40 m and on, none
    p.plan();
    EXPECT_EQ(p.planner.chosen(0), 1);
    EXPECT_EQ(p.planner.chosen(1), 1);
    for (size_t k = 2; k < p.lods.size(); ++k) EXPECT_EQ(p.planner.chosen(k), 0) << "LOD " << k;
    EXPECT_EQ(p.history.last(p.lods[0]), 1);  // the history has the child, not the option's index
}

// mayDrop with a coarsestScale: only LODs the ranges leave out at that scale are left out, however tight the
// budget; the others are drawn at their cheapest allowed level.
TEST(LodBudgetPlanner, LeavesOutOnlyWhatTheRangesLeaveOutAtTheCoarsestScale) {
    RowPlan p;
    p.b.budgetMs = 1e-6;  // below the fixed cost: every LOD would go
    p.b.mayDrop = true;
    p.b.coarsestScale = 1e4;  // 20-170 m look like 2e5-1.7e6: shown (fine below 100 m); 200 m and on: none
    const LodPlanStats st = p.plan();
    for (size_t k = 0; k < p.lods.size(); ++k) {
        const double d = 20.0 + 10.0 * double(k);
        if (d < 95.0) {
            EXPECT_EQ(p.planner.chosen(k), 0) << "LOD " << k;  // its coarse level is coarser than allowed
        } else if (d > 105.0 && d < 185.0) {
            EXPECT_EQ(p.planner.chosen(k), 1) << "LOD " << k;
        } else if (d > 205.0) {
            EXPECT_EQ(p.planner.chosen(k), -1) << "LOD " << k;
        }
    }
    EXPECT_EQ(st.lodDropped, 2u);  // 200 and 210 m
    p.b.coarsestScale = 0.0;       // no bound: every LOD may go
    EXPECT_EQ(p.plan().lodDropped, 20u);
}

// overrunShare: with the budget below the cheapest levels, the nearest LOD, worth many times what a ms bought
// at the edge of the frame before, is still drawn fine; without it, every LOD is coarse.
TEST(LodBudgetPlanner, ALateFrameStillBuysWhatIsWorthManyTimesTheUsualPrice) {
    RowPlan p;
    p.b.budgetMs = 2.0;  // fits: fine up to 100 m, coarse from 110 m, what a ms buys at the edge
    p.plan();
    ASSERT_EQ(p.planner.chosen(8), 0);
    ASSERT_EQ(p.planner.chosen(9), 1);
    p.b.budgetMs = 0.1;  // below the cheapest levels
    const LodPlanStats late = p.plan();
    EXPECT_EQ(late.lodLevels[1], 20u);
    p.b.overrunShare = 10.0;  // up to 1 ms over
    const LodPlanStats st = p.plan();
    // Worth four times the edge's price: about a quarter of its distance, a sixteenth of its pixels.
    EXPECT_EQ(p.planner.chosen(0), 0);
    EXPECT_EQ(p.planner.chosen(1), 0);
    for (size_t k = 5; k < p.lods.size(); ++k) EXPECT_EQ(p.planner.chosen(k), 1) << "LOD " << k;
    EXPECT_GT(st.lodPredictedMs, late.lodPredictedMs);
    EXPECT_LE(st.lodPredictedMs, late.lodPredictedMs + 1.0 + 1e-9);
    p.b.overrunShare = 0.0;  // off: the budget is a hard limit
    EXPECT_EQ(p.plan().lodLevels[1], 20u);
    // Impossible settings are refused by name.
    p.b.overrunShare = 10.0;
    for (double worth : {-1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
        p.b.overrunWorth = worth;
        try {
            p.plan();
            ADD_FAILURE() << "overrunWorth " << worth << " accepted";
        } catch (const SettingError& e) {
            EXPECT_EQ(e.setting(), "lodBudget.overrunWorth");
            EXPECT_NE(std::string(e.what()).find("LodBudgetPlanner::plan(): lodBudget.overrunWorth"), std::string::npos)
                << e.what();
        }
    }
    p.b.overrunWorth = 4.0;
    p.b.overrunShare = std::nan("");
    EXPECT_THROW(p.plan(), SettingError);
}

// finestScale and a fade band: past a switch the ranges still draw the finer child, fading out, to the end of
// the band; the budget may draw it there, not beyond.
TEST(LodBudgetPlanner, TheFinestLevelAllowedIncludesTheFadeBand) {
    auto root = make<Group>();
    const ref_ptr<Mesh> fine = triangles(1000), coarse = triangles(10);
    for (double y : {30.0, 40.0}) {  // 5 and 15 m past the switch at 25 m; the band ends at 35 m
        auto t = make<Transform>();
        t->setTranslation(dvec3(0, y, 0));
        auto lod = make<LOD>();
        lod->addChild(make<Geometry>(fine, make<Material>()), 0.0f, 25.0f);
        lod->addChild(make<Geometry>(coarse, make<Material>()), 25.0f, 1e6f);
        lod->setTransition(20.0f);
        t->addChild(lod);
        root->addChild(t);
    }
    Scene s(root);
    s.update();
    const DrawCostModel model = testutil::trainedCostModel();
    LodBudgetSettings b = testutil::plainBudget(&model);
    b.budgetMs = 100.0;
    b.finestScale = 1.0;
    LodHistory history;
    history.track(s.image(), s.structureVersion());
    LodBudgetPlanner planner;
    for (uint32_t i : lodEntries(s.image())) planner.defer({i, 0u, OcclusionTree::kVisible, dmat4(1.0)});
    LodPlanStats stats;
    planner.plan(s.image(), s.version(), testutil::lookingAlongY(), b, {}, history, stats);
    EXPECT_EQ(planner.chosen(0), 0);  // in the band: the fine child, still drawn by the ranges
    EXPECT_EQ(planner.chosen(1), 1);  // past it: no finer than the ranges show
}

// The deadband (keepOver, keepUnder): a still view under a noisy budget (a spike one frame in ten) and a cost model
// that keeps learning from noisy draws keeps its plan through 100 frames; without it the same input changes levels.
TEST(LodBudgetPlanner, AStillInputKeepsItsPlanUnderNoisyMeasurements) {
    auto run = [](double keepOver, double keepUnder) {
        RowPlan p;
        p.b.budgetMs = 1.3;  // most LODs coarse: the budget binds
        p.b.keepOver = keepOver;
        p.b.keepUnder = keepUnder;
        DrawCostModel model = testutil::trainedCostModel();
        p.b.model = &model;
        uint32_t rng = 12345;
        auto noise = [&] {  // in [-1, 1)
            rng = rng * 1664525u + 1013904223u;
            return double(rng >> 8) / double(1u << 23) - 1.0;
        };
        std::vector<int> first;
        int changedFrames = 0;
        for (int f = 0; f < 100; ++f) {
            // The room jitters by 3% and one frame in ten loses a fifth (a preempted cull); the model learns from
            // draws measured 5% off either way.
            p.b.budgetMs = 1.3 * (1.0 + 0.03 * noise()) * (f % 10 == 7 ? 0.8 : 1.0);
            const LodPlanStats st = p.plan();
            model.update({st.lodPixels > 0 ? 20000.0 : 0.0, 20.0, 0.0}, 3.0 * (1.0 + 0.05 * noise()));
            std::vector<int> now;
            for (size_t k = 0; k < p.lods.size(); ++k) now.push_back(p.planner.chosen(k));
            if (f == 0) first = now;
            if (f > 0 && now != first) ++changedFrames;
            if (f > 0) first = now;
        }
        return changedFrames;
    };
    // The defaults: the same plan frame after frame. The model's rates wander with what it learns (a random walk of
    // the noisy draws), and once in the run they wander far enough that the plan sits more than keepUnder below the
    // budget: it is made anew, a step finer, and kept from then on. Nothing flickers back and forth.
    EXPECT_LE(run(0.15, 0.30), 1);
    EXPECT_GE(run(0.0, 0.0), 10);  // a plan anew each frame follows the noise
}

// The deadband does not hold a plan the budget has left: a cut of the budget far past the band is followed at once,
// the plan is kept once the median budget settles, and LODs new in view make a plan anew at once.
TEST(LodBudgetPlanner, TheDeadbandFollowsALastingChangeAndNewLods) {
    RowPlan p;
    p.b.keepOver = 0.04;
    p.b.keepUnder = 0.08;
    p.b.budgetMs = 100.0;
    for (int f = 0; f < 5; ++f) EXPECT_EQ(p.plan().lodLevels[0], 20u);  // room for all: all fine
    p.b.budgetMs = 1.3;
    int frames = 0;
    while (p.plan().lodPredictedMs > 1.3 + 1e-9 && frames < 10) ++frames;
    EXPECT_LE(frames, 3);                  // at once: the new plan fits this frame's budget
    for (int f = 0; f < 3; ++f) p.plan();  // the median of the last five budgets settles on the new one
    EXPECT_EQ(p.plan().lodPlansKept, 1u);  // then the plan is kept
    // An LOD not planned before (a fresh history: all unseen) makes a new plan.
    p.history = LodHistory();
    p.history.track(p.s.image(), p.s.structureVersion());
    EXPECT_EQ(p.plan().lodPlansKept, 0u);
}
