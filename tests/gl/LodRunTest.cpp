// LodRun, the frame loop of the LOD methods: with a held frame rate a frame takes at least the budget (the work,
// then the wait), and the methods see the work alone; without it the frame time is the work.
#include "TestUtil.h"
#include "nodes/Geometry.h"
#include "nodes/LOD.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "testbed/LodRun.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {
Scene& smallScene() {
    static auto root = [] {
        auto g = make<Group>();
        auto lod = make<LOD>();
        lod->addChild(make<Geometry>(makeBoxMesh(dvec3(-1, 9, -1), dvec3(1, 11, 1), 8), make<Material>()), 0.0f, 50.0f);
        lod->addChild(make<Geometry>(makeBoxMesh(dvec3(-1, 9, -1), dvec3(1, 11, 1)), make<Material>()), 50.0f, 1e6f);
        g->addChild(lod);
        return g;
    }();
    static Scene s(root);
    s.update();
    return s;
}
}  // namespace

TEST(LodRun, AHeldFrameRateWaitsOutTheBudgetAndTheMethodsSeeTheWork) {
    OsmesaContext ctx(64, 48);
    Renderer renderer;
    Camera cam = testutil::lookingAlongY(100.0);
    cam.setViewport(64, 48);
    for (sg::LodPolicy m : {sg::LodPolicy::Static, sg::LodPolicy::Budget, sg::LodPolicy::Stress}) {
        scenes::LodRun::Settings set;
        set.method = m;
        set.budgetMs = 25.0;
        set.limitRate = true;
        scenes::LodRun held(renderer, set);
        for (int f = 0; f < 3; ++f) {
            const scenes::LodFrame& fr = held.frame(smallScene(), cam);
            EXPECT_GE(fr.frameMs, 25.0) << sg::lodPolicyName(m) << " frame " << f;
            EXPECT_GE(fr.frameMs, fr.workMs);
            EXPECT_DOUBLE_EQ(fr.workMs, fr.cullMs + fr.drawMs);
        }
        set.limitRate = false;
        scenes::LodRun running(renderer, set);
        const scenes::LodFrame& fr = running.frame(smallScene(), cam);
        EXPECT_DOUBLE_EQ(fr.frameMs, fr.workMs) << sg::lodPolicyName(m);
        EXPECT_GT(fr.stats.geometries, 0u);
    }
}
