// The LOD budget inside the cull: every visible LOD planned at once, within the budget, nearer (larger)
// objects first when the budget is short, levels valued by their errors when the LOD has them.
#include "TestUtil.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"
#include "sg/lod/DrawCostModel.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {
// Twenty LODs in a row along +y, 10 m apart, each a fine (about 1,200 triangles) and a coarse (12) box.
struct Row {
    ref_ptr<Group> root = make<Group>();
    ref_ptr<Mesh> fine, coarse;
    std::vector<ref_ptr<LOD>> lods;
    explicit Row(bool errors) {
        std::vector<vec3> pos;
        std::vector<uint32_t> idx;
        // A 20 x 30 grid of quads in a 2 m square facing -y: 1,200 triangles.
        for (int i = 0; i <= 20; ++i)
            for (int j = 0; j <= 30; ++j) pos.push_back(vec3(-1.0f + 0.1f * i, -1.0f, -1.0f + 2.0f * j / 30.0f));
        for (int i = 0; i < 20; ++i)
            for (int j = 0; j < 30; ++j) {
                const uint32_t a = uint32_t(i * 31 + j), b = a + 31;
                idx.insert(idx.end(), {a, b, a + 1, a + 1, b, b + 1});
            }
        fine = make<Mesh>();
        fine->set(pos, std::vector<vec3>(pos.size(), vec3(0, -1, 0)), idx);
        coarse = makeBoxMesh(dvec3(-1), dvec3(1));
        auto mat = make<Material>();
        for (int k = 0; k < 20; ++k) {
            auto t = make<Transform>();
            t->setTranslation(dvec3(0, 20 + 10 * k, 0));
            auto lod = make<LOD>();
            lod->addChild(make<Geometry>(fine, mat), 0.0f, 1e6f);
            lod->addChild(make<Geometry>(coarse, mat), 1e6f, 2e6f);
            if (errors) lod->setError(1, 0.2f);
            t->addChild(lod);
            root->addChild(t);
            lods.push_back(lod);
        }
    }
};
CullSettings budgeted(const DrawCostModel& model, double ms) {
    CullSettings set;
    set.lodBudget = testutil::plainBudget(&model, ms);
    return set;
}
struct Frame {
    int fine = 0, coarse = 0;
    std::vector<double> fineY;  // where the fine ones are
    CullStats stats;
};
Frame cull(const Scene& s, const Row& row, CullSettings set) {
    Frame f;
    DrawList l;
    CullTraversal().cull(s, testutil::lookingAlongY(), set, l, f.stats);
    for (auto& it : l.items) {
        if (it.mesh == row.fine.get()) {
            f.fine++;
            f.fineY.push_back(it.model[3].y);
        }
        f.coarse += it.mesh == row.coarse.get();
    }
    return f;
}
}  // namespace

TEST(LodBudget, PlansEveryVisibleLodWithinTheBudget) {
    Row row(false);
    Scene s(row.root);
    s.update();
    const DrawCostModel model = testutil::trainedCostModel();
    CullSettings set = budgeted(model, 100.0);  // room for everything: all fine (the ranges would say the same)
    Frame f = cull(s, row, set);
    EXPECT_EQ(f.fine, 20);
    EXPECT_EQ(f.stats.lodObjects, 20u);
    EXPECT_LE(f.stats.lodPredictedMs, 100.0);

    set.lodBudget.budgetMs = 1.5;  // fixed cost plus a little: everything drawn, coarse, some fine up front
    f = cull(s, row, set);
    EXPECT_EQ(f.fine + f.coarse, 20);
    EXPECT_GE(f.coarse, 15);
    EXPECT_LE(f.stats.lodPredictedMs, 1.5 + 0.05);
    // The stats count the levels the budget chose, and the budget it planned for.
    EXPECT_EQ(f.stats.lodLevels[0], uint64_t(f.fine));
    EXPECT_EQ(f.stats.lodLevels[1], uint64_t(f.coarse));
    EXPECT_EQ(f.stats.lodBudgetMs, 1.5);
    EXPECT_GT(f.stats.lodPixels, 0.0);            // what the drawn LODs cover, for the cost model's pixel term
    for (double y : f.fineY) EXPECT_LT(y, 60.0);  // the upgrades went to the nearest (largest on screen)

    set.lodBudget.mayDrop = true;  // allowed to leave LODs out: a budget below the fixed cost drops all
    set.lodBudget.budgetMs = 0.5;
    f = cull(s, row, set);
    EXPECT_EQ(f.fine + f.coarse, 0);
    EXPECT_EQ(f.stats.lodDropped, 20u);
    EXPECT_EQ(f.stats.lodPixels, 0.0);

    set.lodBudget.model = nullptr;
    EXPECT_THROW(cull(s, row, set), std::invalid_argument);
}

TEST(LodBudget, LevelChangesCountWhatTheBudgetShowsOtherwiseThanLastFrame) {
    Row row(false);
    Scene s(row.root);
    s.update();
    const DrawCostModel model = testutil::trainedCostModel();
    CullTraversal t;  // one traversal: its history carries from frame to frame
    auto frame = [&](double ms, bool mayDrop, int& coarse) {
        CullSettings set = budgeted(model, ms);
        set.lodBudget.mayDrop = mayDrop;
        DrawList l;
        CullStats st;
        t.cull(s, testutil::lookingAlongY(), set, l, st);
        coarse = 0;
        for (auto& it : l.items) coarse += it.mesh == row.coarse.get();
        return st.lodChanged;
    };
    int coarse = 0;
    EXPECT_EQ(frame(100.0, false, coarse), 0u);  // first sight: all fine
    EXPECT_EQ(coarse, 0);
    const uint64_t changed = frame(1.5, false, coarse);
    EXPECT_EQ(changed, uint64_t(coarse));  // the ones the short budget made coarse
    EXPECT_GE(coarse, 15);
    EXPECT_EQ(frame(1.5, false, coarse), 0u);  // the same view and budget: nothing flickers
    EXPECT_EQ(frame(0.5, true, coarse), 20u);  // all left out
    EXPECT_EQ(frame(0.5, true, coarse), 0u);
    EXPECT_EQ(frame(1.5, false, coarse), 20u);  // all back
    EXPECT_GE(coarse, 15);
}

TEST(LodBudget, LevelErrorsTellWhereDetailPays) {
    // With errors on the LODs (the coarse level 0.2 m off), a mid budget buys detail where the coarse
    // error would show most: near. Without, it buys it where the objects are largest: also near. Both
    // keep within the budget; the errors make the far coarse levels nearly as good as fine.
    for (bool errors : {false, true}) {
        Row row(errors);
        Scene s(row.root);
        s.update();
        const DrawCostModel model = testutil::trainedCostModel();
        const Frame f = cull(s, row, budgeted(model, 2.0));
        EXPECT_EQ(f.fine + f.coarse, 20);
        EXPECT_GT(f.fine, 0);
        EXPECT_LT(f.fine, 20);
        for (double y : f.fineY) EXPECT_LE(y, 20.0 + 10.0 * (f.fine - 1) + 1e-3) << "errors " << errors;
    }
}

TEST(LodBudget, KnownZeroErrorsMakeTheCoarseLevelAsGoodAsTheFine) {
    // Errors given as 0 for both levels (the coarse level is the same shape): even an ample budget buys
    // no detail, since it would add nothing; with no errors given, the guess from triangles buys it all.
    for (bool known : {false, true}) {
        Row row(false);
        if (known)
            for (auto& lod : row.lods) {
                lod->setError(0, 0.0f);
                lod->setError(1, 0.0f);
                EXPECT_TRUE(lod->hasErrors());
            }
        Scene s(row.root);
        s.update();
        const DrawCostModel model = testutil::trainedCostModel();
        const Frame f = cull(s, row, budgeted(model, 100.0));
        EXPECT_EQ(f.fine + f.coarse, 20);
        EXPECT_EQ(f.coarse, known ? 20 : 0) << "errors known " << known;
    }
}

TEST(LodBudget, AMeshChangedBetweenFramesIsPricedAfresh) {
    // One traversal over frames keeps what it worked out of the LODs' children while the scene is the
    // same; a fine level made ten times heavier must then cost ten times more.
    Row row(false);
    Scene s(row.root);
    s.update();
    const DrawCostModel model = testutil::trainedCostModel();
    const CullSettings set = budgeted(model, 4.0);  // 20 fine levels (24,000 triangles) fit: 3.4 ms
    CullTraversal t;
    auto shown = [&](const Mesh* mesh) {
        DrawList l;
        CullStats st;
        t.cull(s, testutil::lookingAlongY(), set, l, st);
        int n = 0;
        for (auto& it : l.items) n += it.mesh == mesh;
        return n;
    };
    EXPECT_EQ(shown(row.fine.get()), 20);
    EXPECT_EQ(shown(row.fine.get()), 20);               // the same frame again, from what was kept
    auto heavy = makeBoxMesh(dvec3(-1), dvec3(1), 32);  // 12,288 triangles
    for (auto& lod : row.lods) static_cast<Geometry*>(lod->child(0))->setMesh(heavy);
    s.update();
    const int n = shown(heavy.get());
    EXPECT_GT(n, 0);
    EXPECT_LT(n, 4);  // (4 - 1) ms buys two at 1.2 ms each
}

// LODs under Instances (one prototype placed many times, as machines in a hall) are planned with the rest:
// each placement chooses its own level, priced and valued where it stands, and the budget holds.
TEST(LodBudget, PlansTheLodsOfInstancesPlacementByPlacement) {
    Row row(false);
    // The same twenty places, half of them through placements of one prototype LOD (its own fine and coarse
    // meshes, the row's): a direct LOD and a placed one alternate along the row.
    auto proto = make<LOD>();
    auto mat = make<Material>();
    proto->addChild(make<Geometry>(row.fine, mat), 0.0f, 1e6f);
    proto->addChild(make<Geometry>(row.coarse, mat), 1e6f, 2e6f);
    auto root = make<Group>();
    for (int k = 0; k < 20; ++k) {
        const dvec3 at(0, 20 + 10 * k, 0);
        if (k % 2) {
            root->addChild(make<Instance>(proto, glm::translate(dmat4(1.0), at)));
        } else {
            auto t = make<Transform>();
            t->setTranslation(at);
            t->addChild(row.lods[size_t(k)]);
            root->addChild(t);
        }
    }
    Scene s(root);
    s.update();
    const DrawCostModel model = testutil::trainedCostModel();
    Frame f = cull(s, row, budgeted(model, 100.0));
    EXPECT_EQ(f.stats.lodObjects, 20u);  // the placed ones too
    EXPECT_EQ(f.fine, 20);

    f = cull(s, row, budgeted(model, 1.5));  // short: the nearest fine, direct and placed alike
    EXPECT_EQ(f.stats.lodObjects, 20u);
    EXPECT_EQ(f.fine + f.coarse, 20);
    EXPECT_GE(f.coarse, 15);
    EXPECT_GE(f.fine, 2);
    EXPECT_LE(f.stats.lodPredictedMs, 1.5 + 0.05);
    for (double y : f.fineY) EXPECT_LT(y, 60.0);
    // Placed LODs far away went coarse, near ones fine: the choice is per placement, not per prototype.
    EXPECT_EQ(f.stats.lodLevels[0], uint64_t(f.fine));
    bool placedFine = false;
    for (double y : f.fineY) placedFine |= int(std::lround((y - 20.0) / 10.0)) % 2 == 1;
    EXPECT_TRUE(placedFine);
}
