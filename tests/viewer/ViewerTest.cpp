// sg::Viewer: a frame's stages in order, views side by side, the frame-rate phases, the LOD policies' feedback,
// paging through the pager stage, the overlay, and bad settings refused by name. Headless (OSMesa).
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/LOD.h"
#include "nodes/PagedLOD.h"
#include "nodes/Transform.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/io/ImageIO.h"
#include "sg/viewer/Viewer.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

namespace {

using namespace sg;

constexpr int kW = 96, kH = 64;

ref_ptr<Geometry> box(const vec4& colour, double half = 1.0, int divisions = 1) {
    return make<Geometry>(makeBoxMesh(dvec3(-half), dvec3(half), divisions), make<Material>(colour));
}

Camera lookingAt(const dvec3& eye, int w = kW, int h = kH) {
    Camera c;
    c.setViewport(w, h);
    c.setPerspective(50.0, double(w) / h, 0.1, 200.0);
    c.setLookAt(eye, dvec3(0.0), dvec3(0, 0, 1));
    return c;
}

// Busy for `ms` of the app stage: a frame that takes at least this long, whatever the machine.
void busy(double ms) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::microseconds(int64_t(ms * 1000.0));
    while (std::chrono::steady_clock::now() < end) {
    }
}

size_t differing(const Image& a, const Image& b) { return countDifferingPixels(a, b); }

struct Fixture {
    OsmesaContext context{2 * kW, kH};
    ref_ptr<Group> root = make<Group>();
    ref_ptr<Transform> place = make<Transform>();
    Scene scene{root};
    Fixture() {
        place->addChild(box(vec4(0.9f, 0.2f, 0.1f, 1.0f)));
        root->addChild(place);
    }
};

TEST(Viewer, AFrameRunsItsStagesInOrderAndTheAppsChangesAreDrawn) {
    Fixture f;
    Viewer viewer(f.scene);
    View& v = viewer.addView(lookingAt(dvec3(0, -6, 0)));
    std::vector<std::string> order;
    viewer.onEvents([&] { order.push_back("events"); });
    viewer.onApp([&](const FrameInfo& fi) {
        order.push_back("app " + std::to_string(fi.frame));
        f.place->setMatrix(glm::translate(dmat4(1.0), dvec3(50.0, 0.0, 0.0)));  // out of view
    });
    viewer.onUpdate([&](const FrameInfo&) { order.push_back("update"); });
    viewer.onOverlay([&] { order.push_back("overlay"); });
    viewer.onPresent([&] { order.push_back("present"); });
    viewer.frame();
    EXPECT_EQ(order, (std::vector<std::string>{"events", "app 0", "update", "overlay", "present"}));
    // The app's move reached the image before the cull: nothing in view.
    EXPECT_EQ(v.cullStats().geometries, 0u);
    EXPECT_EQ(viewer.frameNumber(), 1u);
    const StageTimes& t = viewer.lastFrame();
    EXPECT_EQ(t.frame, 0u);
    EXPECT_GE(t.frameMs, t.workMs);
    EXPECT_GE(t.workMs, t.cullMs + t.drawMs);
    EXPECT_EQ(t.waitMs, 0.0);  // free run: no wait
}

TEST(Viewer, TwoViewsSideBySideEachLookAsIfDrawnAlone) {
    Fixture f;
    // Each view alone, in a framebuffer of its own size.
    Image alone[2];
    const Camera cams[2] = {lookingAt(dvec3(0, -6, 0)), lookingAt(dvec3(4, -4, 3))};
    for (int k = 0; k < 2; ++k) {
        OsmesaContext own(kW, kH);
        Viewer one(f.scene);
        one.addView(cams[k]);
        one.frame();
        alone[k] = one.renderer().readColor();
    }
    f.context.makeCurrent();  // the fixture's, two views wide
    Viewer viewer(f.scene);
    for (int k = 0; k < 2; ++k) {
        View& v = viewer.addView(cams[k]);
        v.viewport = {k * kW, 0, kW, kH};
    }
    viewer.frame();
    for (int k = 0; k < 2; ++k) {
        const Image half = viewer.renderer().readColor({k * kW, 0, kW, kH});
        EXPECT_EQ(differing(half, alone[k]), 0u) << "view " << k;
        EXPECT_GT(viewer.view(size_t(k)).cullStats().geometries, 0u);
    }
    EXPECT_GT(differing(alone[0], alone[1]), size_t(100));  // the two views differ
    // A disabled view is neither culled nor drawn: its half keeps the other's clear colour... or what was there.
    viewer.view(1).enabled = false;
    viewer.view(1).camera = lookingAt(dvec3(0, 6, 0));
    viewer.frame();
    EXPECT_EQ(differing(viewer.renderer().readColor({kW, 0, kW, kH}), alone[1]), 0u);
}

TEST(Viewer, LimitHoldsAFrameToItsPeriodAndCountsTheWait) {
    Fixture f;
    ViewerSettings s;
    s.phase = FramePhase::Limit;
    s.frameRate = 50.0;  // 20 ms
    Viewer viewer(f.scene, s);
    viewer.addView(lookingAt(dvec3(0, -6, 0)));
    for (int i = 0; i < 3; ++i) {
        viewer.frame();
        const StageTimes& t = viewer.lastFrame();
        EXPECT_GE(t.frameMs, 20.0) << i;
        // The frame counts its work, wait and present (and whatever a busy machine adds between them).
        EXPECT_GE(t.frameMs + 1e-9, t.workMs + t.waitMs + t.presentMs) << i;
    }
    viewer.settings().phase = FramePhase::FreeRun;
    viewer.frame();
    EXPECT_EQ(viewer.lastFrame().waitMs, 0.0);
}

TEST(Viewer, LockWaitsForTheNextTickAfterALateFrameAndLimitDoesNot) {
    Fixture f;
    for (FramePhase phase : {FramePhase::Lock, FramePhase::Limit}) {
        ViewerSettings s;
        s.phase = phase;
        s.frameRate = 50.0;  // 20 ms
        Viewer viewer(f.scene, s);
        viewer.addView(lookingAt(dvec3(0, -6, 0)));
        double late = 0.0;
        viewer.onApp([&](const FrameInfo&) { busy(late); });
        viewer.frame();
        EXPECT_GE(viewer.lastFrame().frameMs, 20.0) << framePhaseName(phase);
        late = 30.0;  // more than a period
        viewer.frame();
        const StageTimes& t = viewer.lastFrame();
        EXPECT_GE(t.frameMs, 30.0);
        if (phase == FramePhase::Lock)
            EXPECT_GT(t.waitMs, 0.0);  // to the next tick (a frame ending exactly on one is all but impossible)
        else
            EXPECT_EQ(t.waitMs, 0.0);  // late: not held further
    }
}

TEST(Viewer, StressGrowsTheScaleWhileFramesRunOverItsBudget) {
    Fixture f;
    Viewer viewer(f.scene);
    View& v = viewer.addView(lookingAt(dvec3(0, -6, 0)));
    v.lod = LodPolicy::Stress;
    v.lodBudgetMs = 5.0;
    viewer.onApp([&](const FrameInfo&) { busy(10.0); });  // every frame twice its budget
    for (int i = 0; i < 4; ++i) viewer.frame();
    EXPECT_GT(v.stress().scale(), 1.0);
    EXPECT_GE(v.stress().load(), 1.0);
}

TEST(Viewer, TheBudgetPlansWithTheLibrarysDefaultsAndItsModelLearns) {
    Fixture f;
    auto lod = make<LOD>();
    lod->addChild(box(vec4(0.2f, 0.8f, 0.3f, 1.0f), 1.0, 8), 0.0f, 20.0f);
    lod->addChild(box(vec4(0.2f, 0.8f, 0.3f, 1.0f), 1.0, 1), 20.0f, 1e6f);
    f.root->addChild(lod);
    Viewer viewer(f.scene);
    View& v = viewer.addView(lookingAt(dvec3(0, -6, 0)));
    v.lod = LodPolicy::Budget;
    v.lodBudgetMs = 40.0;
    for (int i = 0; i < 3; ++i) viewer.frame();
    EXPECT_EQ(v.cullStats().lodObjects, 1u);
    EXPECT_GT(v.cullStats().lodBudgetMs, 0.0);
    EXPECT_LE(v.cullStats().lodBudgetMs, 40.0);  // what the frame's time before the draw left of it
    EXPECT_EQ(v.costModel().samples(), 3u);      // one measured draw a frame
    // The defaults that work are the library's: the budget as the view plans it.
    const LodBudgetSettings defaults;
    EXPECT_TRUE(defaults.mayDrop);
    EXPECT_EQ(defaults.coarsestScale, LodStress::Params{}.maxScale);  // stress's largest scale
    EXPECT_EQ(defaults.finestScale, 1.0);
    EXPECT_EQ(defaults.overrunShare, 0.15);
}

TEST(Viewer, ThePagerStageAttachesWhatItsThreadLoaded) {
    Fixture f;
    auto paged = make<PagedLOD>();
    paged->addChild(box(vec4(0.1f, 0.1f, 0.9f, 1.0f), 0.2));  // the coarse level: small
    paged->setFile("detail");
    paged->setRange(0.0f, 100.0f);
    f.root->addChild(paged);
    Viewer viewer(f.scene);
    View& v = viewer.addView(lookingAt(dvec3(0, -6, 0)));
    Pager& pager =
        viewer.enablePaging([](const std::string&) -> ref_ptr<Node> { return box(vec4(0.1f, 0.1f, 0.9f, 1.0f), 1.5); });
    viewer.frame();  // the cull asks for the detail
    EXPECT_EQ(v.cullStats().pagedRequested, 1u);
    viewer.frame();  // the pager stage queues it
    pager.waitIdle();
    viewer.frame();  // and attaches it before the update: drawn this frame
    EXPECT_EQ(paged->state(), PagedLOD::State::Loaded);
    EXPECT_EQ(pager.stats().loads, 1u);
    EXPECT_EQ(v.cullStats().pagedCoarse, 0u);
}

// A view flying along +y at 10 m/s toward a tile 60 m ahead whose detail is wanted within 20 m. With two seconds of
// look-ahead the detail is asked for about two seconds early, and drawn at the first frame the view wants it;
// without, that frame draws the coarse level (the pager is let finish its loads between frames, so that only the
// time of asking differs).
TEST(Viewer, AMovingViewsLookAheadLoadsTheDetailBeforeTheViewGetsThere) {
    for (const double seconds : {2.0, 0.0}) {
        SCOPED_TRACE(seconds);
        Fixture f;
        auto paged = make<PagedLOD>();
        paged->addChild(box(vec4(0.1f, 0.1f, 0.9f, 1.0f), 0.2));
        paged->setFile("detail");
        paged->setRange(0.0f, 20.0f);
        auto at = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 60, 0)));
        at->addChild(paged);
        f.root->addChild(at);
        double time = 0.0;
        ViewerSettings vs;
        vs.clock = [&] { return time; };
        Viewer viewer(f.scene, vs);
        View& v = viewer.addView();
        v.prefetchSeconds = seconds;
        Pager& pager = viewer.enablePaging(
            [](const std::string&) -> ref_ptr<Node> { return box(vec4(0.1f, 0.1f, 0.9f, 1.0f), 1.5); });
        int firstWanted = -1, firstAsked = -1;
        size_t coarseWhenWanted = 0, askedAhead = 0;
        for (int k = 0; k < 60 && firstWanted < 0; ++k) {
            time = 0.1 * k;
            const dvec3 eye(0, 10.0 * time, 1.0);
            v.camera = lookingAt(dvec3(0, -6, 0));
            v.camera.setLookAt(eye, eye + dvec3(0, 1, 0), dvec3(0, 0, 1));
            viewer.frame();
            pager.waitIdle();
            askedAhead += v.prefetchStats().pagedRequested;
            if (firstAsked < 0 && paged->state() != PagedLOD::State::Unloaded) firstAsked = k;
            if (v.cullStats().pagedWanted > 0) {
                firstWanted = k;
                coarseWhenWanted = v.cullStats().pagedCoarse;
            }
        }
        ASSERT_GE(firstWanted, 40);  // 40 m on: 20 m from the tile
        if (seconds > 0.0) {
            ASSERT_GE(firstAsked, 0);
            EXPECT_EQ(askedAhead, 1u);
            EXPECT_LE(firstAsked, firstWanted - 18);  // about two seconds (20 frames) before, smoothing aside
            EXPECT_EQ(coarseWhenWanted, 0u);
            EXPECT_EQ(paged->state(), PagedLOD::State::Loaded);
        } else {
            EXPECT_EQ(askedAhead, 0u);
            EXPECT_EQ(firstAsked, -1);  // its request reaches the pager at the next frame
            EXPECT_EQ(coarseWhenWanted, 1u);
        }
    }
}

TEST(Viewer, ThePagerStageUploadsADetailThroughTheRendererBeforeAttachingIt) {
    Fixture f;
    auto paged = make<PagedLOD>();
    paged->addChild(box(vec4(0.1f, 0.1f, 0.9f, 1.0f), 0.2));
    paged->setFile("detail");
    paged->setRange(0.0f, 100.0f);
    f.root->addChild(paged);
    Viewer viewer(f.scene);
    viewer.addView(lookingAt(dvec3(0, -6, 0)));
    Pager& pager =
        viewer.enablePaging([](const std::string&) -> ref_ptr<Node> { return box(vec4(0.9f, 0.1f, 0.1f, 1.0f), 1.5); });
    viewer.frame();
    viewer.frame();
    pager.waitIdle();
    const size_t before = viewer.renderer().cachedMeshes();
    viewer.frame();  // prepared (its mesh uploaded), attached, drawn
    ASSERT_EQ(paged->state(), PagedLOD::State::Loaded);
    EXPECT_EQ(pager.stats().frame.prepared, 1u);
    EXPECT_EQ(pager.stats().frame.uploadedObjects, 1u);
    EXPECT_GT(pager.stats().frame.uploadedBytes, 0u);
    EXPECT_EQ(viewer.renderer().cachedMeshes(), before + 1);
    EXPECT_FALSE(pager.prepare());  // wired for the pager stage only
}

TEST(Viewer, TheOverlayDrawsTheStageTimesAtTheTopLeft) {
    Fixture f;
    OsmesaContext ctx(400, 300);
    Viewer viewer(f.scene);
    viewer.addView(lookingAt(dvec3(0, -6, 0), 400, 300));
    viewer.frame();
    const Image plain = viewer.renderer().readColor();
    viewer.overlay = true;
    viewer.overlayText = [] { return std::string("a line of the program's"); };
    viewer.frame();
    const Image over = viewer.renderer().readColor();
    EXPECT_GT(differing(plain, over), size_t(1000));
    EXPECT_NE(viewer.statsText().find("a line of the program's\nfps "), std::string::npos) << viewer.statsText();
    EXPECT_NE(viewer.statsText().find("cull "), std::string::npos);
    // Only the panel changed: the bottom half is the same.
    for (int y = 200; y < 300; ++y)
        for (int x = 0; x < 400; ++x) {
            const size_t i = (size_t(y) * 400 + x) * 4;
            ASSERT_EQ(plain.rgba[i], over.rgba[i]) << x << ", " << y;
        }
}

TEST(Viewer, ImpossibleSettingsAreRefusedByName) {
    Fixture f;
    ViewerSettings s;
    s.frameRate = 0.0;
    try {
        Viewer v(f.scene, s);
        ADD_FAILURE() << "a frame rate of 0 accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()).rfind("Viewer::Viewer(): frameRate", 0), 0u) << e.what();
    }
    Viewer viewer(f.scene);
    View& v = viewer.addView(lookingAt(dvec3(0, -6, 0)));
    viewer.settings().frameRate = std::nan("");
    EXPECT_THROW(viewer.frame(), std::invalid_argument);
    viewer.settings().frameRate = 30.0;
    v.cull.lodScale = -1.0;  // the cull's own check, named
    try {
        viewer.frame();
        ADD_FAILURE() << "lodScale -1 accepted";
    } catch (const SettingError& e) {
        EXPECT_EQ(e.setting(), "lodScale");
    }
    v.cull.lodScale = 1.0;
    v.lod = LodPolicy::Budget;
    v.lodBudgetMs = -5.0;
    EXPECT_THROW(viewer.frame(), std::invalid_argument);
    v.lodBudgetMs = std::nan("");
    EXPECT_THROW(viewer.frame(), std::invalid_argument);
    v.lodBudgetMs = 0.0;  // the viewer's period then
    EXPECT_NO_THROW(viewer.frame());
    EXPECT_THROW(parseLodPolicy("fast"), std::invalid_argument);
    EXPECT_EQ(parseFramePhase("lock"), FramePhase::Lock);
    EXPECT_THROW(parseFramePhase("float"), std::invalid_argument);
}

}  // namespace

namespace {

// The draw as the GL timed it: a GL_TIME_ELAPSED query around each draw, read once the draw is finished.
TEST(Viewer, TheGlsOwnDrawTimeIsReportedBesideTheCpus) {
    Fixture f;
    Viewer viewer(f.scene);
    View& v = viewer.addView(lookingAt(dvec3(0, -3, 0)));
    if (!viewer.renderer().timerQueries()) GTEST_SKIP() << "this context has no GL_TIME_ELAPSED counter";
    // A software rasterizer's timer is not shown (ViewerVariants.TheGpuTimeIsUnknownOnASoftwareRasterizer).
    if (viewer.renderer().softwareRasterizer()) GTEST_SKIP() << "a software rasterizer: the GPU time is unknown";
    viewer.frame();
    EXPECT_GT(v.gpuMs(), 0.0);  // a box filling much of the view took the GL some time
    EXPECT_EQ(viewer.lastFrame().gpuMs, v.gpuMs());
    EXPECT_TRUE(viewer.lastFrame().gpuTimed);
    EXPECT_GT(viewer.renderer().gpuMs(), 0.0);  // read once, kept
    // Not finished (a static view with ViewerSettings::finish off): not known, and nothing waits for it.
    viewer.settings().finish = false;
    viewer.frame();
    EXPECT_EQ(v.gpuMs(), -1.0);
    EXPECT_EQ(viewer.lastFrame().gpuMs, 0.0);
    EXPECT_FALSE(viewer.lastFrame().gpuTimed);
}

}  // namespace

// A viewer that keeps freed memory for a software rasterizer makes its pager keep it too (trimming would hand it
// back after every load); one that does not keep it lets its pager trim.
TEST(Viewer, ItsPagerTrimsFreedMemoryUnlessTheViewerKeepsItForASoftwareRasterizer) {
    Fixture f;
    auto load = [](const std::string&) -> ref_ptr<Node> { return box(vec4(0.1f, 0.1f, 0.9f, 1.0f), 1.5); };
    Viewer keeping(f.scene);
    ASSERT_TRUE(keeping.renderer().softwareRasterizer());  // OSMesa's llvmpipe
    EXPECT_FALSE(keeping.enablePaging(load).settings().trimFreedMemory);
    ViewerSettings vs;
    vs.keepFreedMemory = false;
    Viewer trimming(f.scene, vs);
    EXPECT_TRUE(trimming.enablePaging(load).settings().trimFreedMemory);
}
