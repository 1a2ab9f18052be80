// OcclusionPass alone: the tree it builds from a scene's occluders, its test of one entry, the Adaptive back-off.
#include "TestUtil.h"
#include "nodes/Geometry.h"
#include "nodes/Occluder.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"
#include "sg/cull/OcclusionPass.h"
#include "sg/scene/Scene.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {
// A wall (box occluder) across the view at y = 20..21, a box behind it and a box in front of it.
struct Walled {
    ref_ptr<Group> root = make<Group>();
    ref_ptr<Mesh> behind = makeBoxMesh(dvec3(-1, 40, -1), dvec3(1, 42, 1));
    ref_ptr<Mesh> front = makeBoxMesh(dvec3(-1, 10, -1), dvec3(1, 12, 1));
    explicit Walled(bool occluder = true) {
        if (occluder) {
            auto o = make<Occluder>();
            o->setBox(Box{dvec3(-10, 20, -10), dvec3(10, 21, 10)});
            root->addChild(o);
        }
        root->addChild(make<Geometry>(behind, make<Material>()));
        root->addChild(make<Geometry>(front, make<Material>()));
    }
};

uint32_t entryOf(const FlatImage& img, const Mesh* mesh) {
    for (uint32_t i = 0; i < img.size(); ++i)
        if (img.kind[i] == NodeKind::Geometry && img.draws[img.aux[i]].mesh == mesh) return i;
    ADD_FAILURE() << "no entry draws the mesh";
    return 0;
}

CullSettings mode(OcclusionMode m) {
    CullSettings set;
    set.occlusion.mode = m;
    set.occlusion.method = OcclusionMethod::Tree;
    return set;
}
}  // namespace

TEST(OcclusionPass, CullsTheBoxBehindTheOccluderNotTheOneInFront) {
    Walled w;
    Scene s(w.root);
    s.update();
    const Camera cam = testutil::lookingAlongY(500.0);
    const FlatImage& img = s.image();
    OcclusionPass pass;
    CullStats stats;
    const int32_t root = pass.build(img, cam, mode(OcclusionMode::EveryFrame), stats);
    ASSERT_NE(root, OcclusionTree::kVisible);
    EXPECT_TRUE(stats.occlusionRan);
    EXPECT_EQ(stats.occludersUsed, 1u);
    EXPECT_FALSE(pass.tree().empty());

    const dvec3 originRel = img.origin - cam.eye();
    int32_t occ = root;
    EXPECT_FALSE(pass.test(img, originRel, entryOf(img, w.behind.get()), occ, stats));
    EXPECT_EQ(stats.culledOcclusion, 1u);
    occ = root;
    EXPECT_TRUE(pass.test(img, originRel, entryOf(img, w.front.get()), occ, stats));
    EXPECT_EQ(occ, OcclusionTree::kVisible);  // wholly visible: nothing below needs a test
    EXPECT_EQ(stats.occlusionTests, 2u);
}

TEST(OcclusionPass, TheOcclusionMapCullsTheBoxBehindTheOccluderNotTheOneInFront) {
    Walled w;
    Scene s(w.root);
    s.update();
    const Camera cam = testutil::lookingAlongY(500.0);
    const FlatImage& img = s.image();
    OcclusionPass pass;
    CullStats stats;
    CullSettings set = mode(OcclusionMode::EveryFrame);
    set.occlusion.method = OcclusionMethod::Hom;
    const int32_t start = pass.build(img, cam, set, stats);
    ASSERT_NE(start, OcclusionTree::kVisible);
    EXPECT_TRUE(stats.occlusionRan);
    EXPECT_EQ(stats.occludersUsed, 1u);
    EXPECT_TRUE(pass.tree().empty());
    EXPECT_GT(pass.map().coveredPixels(), 0u);

    const dvec3 originRel = img.origin - cam.eye();
    int32_t occ = start;
    EXPECT_FALSE(pass.test(img, originRel, entryOf(img, w.behind.get()), occ, stats));
    EXPECT_EQ(stats.culledOcclusion, 1u);
    occ = start;
    EXPECT_TRUE(pass.test(img, originRel, entryOf(img, w.front.get()), occ, stats));
    EXPECT_EQ(stats.occlusionTests, 2u);
    // A bad map size is refused by name, not drawn wrong.
    set.occlusion.homWidth = 100;
    EXPECT_THROW(pass.build(img, cam, set, stats), std::invalid_argument);
}

TEST(OcclusionPass, OrientedBoxesHideATurnedBarItsWorldBoxDoesNot) {
    // A strip occluder and a bar behind it, both turned 45 degrees about the view axis: the bar lies in the
    // strip's shadow, its world box (a square on screen) does not.
    auto turn = make<Transform>(glm::rotate(dmat4(1.0), glm::radians(45.0), dvec3(0, 1, 0)));
    auto strip = make<Occluder>();
    strip->setBox(Box{dvec3(-12, 20, -1.5), dvec3(12, 21, 1.5)});
    turn->addChild(strip);
    turn->addChild(make<Geometry>(makeBoxMesh(dvec3(-20, 40, -0.5), dvec3(20, 41, 0.5), 16), make<Material>()));
    Scene s(turn);
    s.update();
    const Camera cam = testutil::lookingAlongY(500.0);
    CullSettings set = mode(OcclusionMode::EveryFrame);
    set.occlusion.method = OcclusionMethod::Hom;
    CullTraversal cull;
    DrawList list;
    CullStats stats;
    cull.cull(s, cam, set, list, stats);
    EXPECT_EQ(list.items.size(), 1u);
    EXPECT_EQ(stats.culledObb, 0u);
    set.occlusion.homObbLevels = 6;  // screen rectangles stay axis-aligned: the bar in pieces
    stats = CullStats{};
    cull.cull(s, cam, set, list, stats);
    EXPECT_EQ(list.items.size(), 0u);
    EXPECT_EQ(stats.culledObb, 1u);
    EXPECT_EQ(stats.culledOcclusion, 1u);
}

TEST(OcclusionPass, DoesNothingWithoutOccludersOrWhenOff) {
    const Camera cam = testutil::lookingAlongY(500.0);
    {
        Walled w(false);
        Scene s(w.root);
        s.update();
        OcclusionPass pass;
        CullStats stats;
        EXPECT_EQ(pass.build(s.image(), cam, mode(OcclusionMode::EveryFrame), stats), OcclusionTree::kVisible);
        EXPECT_FALSE(stats.occlusionRan);
        EXPECT_TRUE(pass.tree().empty());
    }
    Walled w;
    Scene s(w.root);
    s.update();
    OcclusionPass pass;
    CullStats stats;
    EXPECT_EQ(pass.build(s.image(), cam, mode(OcclusionMode::Off), stats), OcclusionTree::kVisible);
    CullSettings none = mode(OcclusionMode::EveryFrame);
    none.strategy = CullStrategy::None;  // the reference render culls nothing
    EXPECT_EQ(pass.build(s.image(), cam, none, stats), OcclusionTree::kVisible);
    Camera ortho = cam;
    ortho.setProjection(glm::ortho(-10.0, 10.0, -10.0, 10.0, 0.5, 500.0));
    EXPECT_EQ(pass.build(s.image(), ortho, mode(OcclusionMode::EveryFrame), stats), OcclusionTree::kVisible);
    EXPECT_FALSE(stats.occlusionRan);
}

TEST(OcclusionPass, AdaptiveBacksOffDoublingUpTo64FramesAndResetsWhenItPays) {
    OcclusionPass pass;
    EXPECT_EQ(pass.framesToSkip(), 0);
    std::vector<int> skips;
    for (int f = 0; f < 6; ++f) {
        pass.recordGain(0.05, 0.1);  // did not pay
        skips.push_back(pass.framesToSkip());
    }
    EXPECT_EQ(skips, (std::vector<int>{4, 8, 16, 32, 64, 64}));
    pass.recordGain(0.1, 0.1);  // paid: every frame again, and the next back-off starts over at 4
    EXPECT_EQ(pass.framesToSkip(), 0);
    pass.recordGain(0.0, 0.1);
    EXPECT_EQ(pass.framesToSkip(), 4);
}

TEST(OcclusionPass, AdaptiveSkipsTheFramesOfItsBackOffThenRunsAgain) {
    Walled w;
    Scene s(w.root);
    s.update();
    const Camera cam = testutil::lookingAlongY(500.0);
    const CullSettings set = mode(OcclusionMode::Adaptive);
    OcclusionPass pass;
    pass.recordGain(0.0, set.occlusion.adaptiveMinGain);
    for (int f = 0; f < 4; ++f) {
        CullStats stats;
        EXPECT_EQ(pass.build(s.image(), cam, set, stats), OcclusionTree::kVisible) << "frame " << f;
        EXPECT_TRUE(stats.occlusionSkipped);
        EXPECT_FALSE(stats.occlusionRan);
    }
    CullStats stats;
    EXPECT_NE(pass.build(s.image(), cam, set, stats), OcclusionTree::kVisible);
    EXPECT_TRUE(stats.occlusionRan);
    // A frame where it culled little (one entry of a hundred visited): the back-off doubles.
    stats.occludedEntries = 1;
    stats.nodesVisited = 100;
    pass.finish(set.occlusion, stats);
    EXPECT_EQ(pass.framesToSkip(), 8);
}

// The back-off learned of one view does not outlive it: once the eye has moved a quarter of its distance to
// the nearest occluder, or the scene has changed, the next frame runs the pass again.
TEST(OcclusionPass, AdaptiveRunsAgainWhenTheEyeMovesOrTheSceneChanges) {
    auto root = make<Group>();
    auto o = make<Occluder>();
    o->setBox(Box{dvec3(-10, 20, -10), dvec3(10, 21, 10)});
    root->addChild(o);
    auto before = make<Group>();  // boxes in front of the wall: the wall hides nothing
    for (int k = 0; k < 20; ++k) {
        const double x = -9.3 + k;  // no side in the eye's plane x = 0
        before->addChild(make<Geometry>(makeBoxMesh(dvec3(x, 10, -1), dvec3(x + 0.5, 11, 1)), make<Material>()));
    }
    root->addChild(before);
    auto away = make<Transform>();  // more boxes, beside the wall at first
    away->setTranslation(dvec3(300, 0, 0));
    for (int k = 0; k < 20; ++k) {
        const double x = -9.3 + k;  // no side in the eye's plane x = 0
        away->addChild(make<Geometry>(makeBoxMesh(dvec3(x, 40, -1), dvec3(x + 0.5, 41, 1)), make<Material>()));
    }
    root->addChild(away);
    Scene s(root);
    s.update();
    Camera cam = testutil::lookingAlongY(500.0);  // the eye 20 from the wall
    CullSettings set = mode(OcclusionMode::Adaptive);
    CullTraversal cull;
    DrawList list;
    CullStats st;
    auto frame = [&] {
        st = CullStats{};
        cull.cull(s, cam, set, list, st);
    };
    frame();  // the wall hides nothing: the pass did not pay, and backs off
    ASSERT_TRUE(st.occlusionRan);
    frame();
    ASSERT_TRUE(st.occlusionSkipped);
    auto moveEye = [&](double dy) {
        cam.setLookAt(cam.eye() + dvec3(0, dy, 0), cam.eye() + dvec3(0, dy + 1, 0), dvec3(0, 0, 1));
    };
    moveEye(3.0);  // less than a quarter of 20: still backing off
    frame();
    EXPECT_TRUE(st.occlusionSkipped);
    moveEye(3.0);  // 6 in all since it ran: it runs
    frame();
    EXPECT_TRUE(st.occlusionRan);
    frame();
    EXPECT_TRUE(st.occlusionSkipped);  // and, still not paying, backs off again
    // The boxes move behind the wall: a new scene version, and the pass runs on the next frame.
    away->setTranslation(dvec3(0.0));
    s.update();
    frame();
    EXPECT_TRUE(st.occlusionRan);
    EXPECT_FALSE(st.occlusionSkipped);
    auto behindDrawn = [&] {
        int n = 0;
        for (const DrawItem& it : list.items)
            for (size_t k = 0; k < away->numChildren(); ++k)
                n += it.mesh == static_cast<Geometry*>(away->child(k))->mesh();
        return n;
    };
    EXPECT_EQ(behindDrawn(), 0);  // every box behind the wall culled
    EXPECT_GT(st.geometries, 0u);
    CullStats all;
    CullTraversal().cull(s, cam, mode(OcclusionMode::Off), list, all);
    EXPECT_GT(behindDrawn(), 10);  // where the frustum alone keeps them
}
