// sg::Viewer's threading models: every model draws the pictures SingleThreaded draws for the same frames (a city
// orbit, the factory's path with its Switch turning and LODs fading, two views), each frame's picture arriving
// after the model's latency; the stage rules (which thread runs which callback); a failure on any stage stops the
// viewer and is rethrown on the application thread with its stage named, the frames before it drawn; ISECT's
// answers a frame later, equal to the synchronous ones. Headless (OSMesa); run under ThreadSanitizer in CI.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/PagedLOD.h"
#include "nodes/Sequence.h"
#include "nodes/Transform.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/io/ImageIO.h"
#include "sg/viewer/Viewer.h"
#include "testbed/City.h"
#include "testbed/Factory.h"
#include "testbed/FactoryWalk.h"
#include "testbed/Figure.h"

#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace {

using namespace sg;

constexpr ThreadingModel kModels[] = {ThreadingModel::SingleThreaded, ThreadingModel::DrawThread,
                                      ThreadingModel::CullThreadPerView, ThreadingModel::AppCullDraw};

ViewerSettings settingsFor(ThreadingModel m, OsmesaContext& ctx) {
    ViewerSettings s;
    s.threading = m;
    s.bindContext = [&ctx](bool current) { current ? ctx.makeCurrent() : ctx.release(); };
    return s;
}

// `frames` frames with `model`; app(i, viewer) sets frame i's state (cameras, switches). Returns each frame's
// picture, read on the draw thread once drawn, and checks that frame() returns with the model's latency in flight.
std::vector<Image> runFrames(OsmesaContext& ctx, Scene& scene, ThreadingModel model, int frames, int views,
                             const std::function<void(int, Viewer&)>& app) {
    Viewer viewer(scene, settingsFor(model, ctx));
    for (int k = 0; k < views; ++k) viewer.addView();
    std::vector<Image> pictures(static_cast<size_t>(frames));
    viewer.onApp([&](const FrameInfo& fi) { app(int(fi.frame), viewer); });
    viewer.onDrawn([&](const FrameInfo& fi) { pictures.at(size_t(fi.frame)) = viewer.renderer().readColor(); });
    const int latency = threadingLatency(model);
    for (int i = 0; i < frames; ++i) {
        viewer.frame();
        EXPECT_EQ(viewer.framesDrawn(), uint64_t(std::max(0, i + 1 - latency))) << threadingModelName(model);
    }
    viewer.flush();
    EXPECT_EQ(viewer.framesDrawn(), uint64_t(frames));
    EXPECT_EQ(viewer.history().last().frame, uint64_t(frames - 1));
    return pictures;
}

void expectSamePictures(const std::vector<Image>& got, const std::vector<Image>& want, ThreadingModel m) {
    ASSERT_EQ(got.size(), want.size());
    for (size_t i = 0; i < got.size(); ++i) {
        ASSERT_GT(want[i].width, 0);
        EXPECT_EQ(countDifferingPixels(got[i], want[i]), 0u) << threadingModelName(m) << " frame " << i;
    }
}

TEST(ViewerThreads, EveryModelDrawsTheCityOrbitAsSingleThreaded) {
    constexpr int kN = 40, kW = 320, kH = 180, kFrames = 24;
    OsmesaContext ctx(kW, kH);
    Scene scene(scenes::buildCity({kN, false}));
    auto app = [&](int i, Viewer& v) { v.view().camera = scenes::cityOrbitCamera(kN, i * 5, kW, kH); };
    const std::vector<Image> single = runFrames(ctx, scene, ThreadingModel::SingleThreaded, kFrames, 1, app);
    // The orbit moves: the frames differ from each other, so a picture drawn for the wrong frame would show.
    EXPECT_GT(countDifferingPixels(single[0], single[kFrames - 1]), 1000u);
    for (ThreadingModel m : kModels)
        if (m != ThreadingModel::SingleThreaded)
            expectSamePictures(runFrames(ctx, scene, m, kFrames, 1, app), single, m);
}

// The factory's path: the eye enters a workshop (its Switch on, the outside off) and leaves; LODs dissolve over
// their fade bands as it moves. The app stage turns the switches each frame.
TEST(ViewerThreads, EveryModelDrawsTheFactoryPathWithItsSwitchAndFadesAsSingleThreaded) {
    constexpr int kW = 256, kH = 160, kFrames = 40;
    OsmesaContext ctx(kW, kH);
    scenes::Factory f = scenes::buildFactory();
    Scene scene(f.root);
    scene.update();
    const scenes::WalkPath path = scenes::buildWalkPath(f, scene, kFrames);
    ASSERT_GT(path.insideFrames, 0);
    size_t fading = 0;
    auto app = [&](int i, Viewer& v) {
        const scenes::PathFrame& p = path.frames[size_t(i)];
        scenes::setFactoryEye(f, p.workshop);
        v.view().camera = scenes::pathCamera(p, kW, kH);
        fading += v.view().drawList().fades.size();  // the last drawn frame's (a read on the app thread)
    };
    const std::vector<Image> single = runFrames(ctx, scene, ThreadingModel::SingleThreaded, kFrames, 1, app);
    EXPECT_GT(fading, 0u);  // the path crosses LOD fade bands
    for (ThreadingModel m : kModels)
        if (m != ThreadingModel::SingleThreaded)
            expectSamePictures(runFrames(ctx, scene, m, kFrames, 1, app), single, m);
    scenes::setFactoryEye(f, -1);
}

// Two views side by side, each with its own camera: CullThreadPerView culls them on two threads.
TEST(ViewerThreads, TwoViewsCulledOnTheirOwnThreadsDrawAsSingleThreaded) {
    constexpr int kN = 30, kW = 320, kH = 120, kFrames = 12;
    OsmesaContext ctx(kW, kH);
    Scene scene(scenes::buildCity({kN, false}));
    auto app = [&](int i, Viewer& v) {
        v.view(0).camera = scenes::cityOrbitCamera(kN, i * 7, kW / 2, kH);
        v.view(0).viewport = {0, 0, kW / 2, kH};
        v.view(1).camera = scenes::cityStreetCamera(kN, i * 11, kW / 2, kH);
        v.view(1).viewport = {kW / 2, 0, kW / 2, kH};
    };
    const std::vector<Image> single = runFrames(ctx, scene, ThreadingModel::SingleThreaded, kFrames, 2, app);
    for (ThreadingModel m : kModels)
        if (m != ThreadingModel::SingleThreaded)
            expectSamePictures(runFrames(ctx, scene, m, kFrames, 2, app), single, m);
}

ref_ptr<Geometry> box(const vec4& colour) {
    return make<Geometry>(makeBoxMesh(dvec3(-1.0), dvec3(1.0), 1), make<Material>(colour));
}

// An animated scene: walking figures (skinned, 4 and 8 influences), a quad morphed by an animated weight, and a
// Sequence turning, each moved by the viewer's animation player (or the clock) on its app stage.
struct Animated {
    ref_ptr<Group> root = make<Group>();
    std::vector<ref_ptr<Animation>> animations;
    Animated() {
        scenes::FigureOptions eight;
        eight.influences = 8;
        eight.cubic = true;
        root->addChild(scenes::makeCrowd(4, dvec3(-1.5, 0.0, 0.0), 2, 1.5, animations, {}, true));
        root->addChild(scenes::makeCrowd(2, dvec3(-1.5, 3.0, 0.0), 2, 1.5, animations, eight, true));
        auto quad = make<Mesh>();
        quad->set({{2.5f, 0, 0}, {3.5f, 0, 0}, {3.5f, 0, 1}, {2.5f, 0, 1}}, {}, {0, 1, 2, 0, 2, 3});
        MorphTarget up;
        up.positions = {{0, 0, 0}, {0, 0, 0}, {0, 0, 1}, {0, 0, 1}};
        quad->setMorphTargets({up});
        auto morphed = make<Geometry>(quad, make<Material>(vec4(0.2f, 0.4f, 0.9f, 1.0f)));
        root->addChild(morphed);
        auto grow = make<Animation>();
        grow->name = "grow";
        AnimationSampler s;
        s.times = {0.0f, 1.0f};
        s.values = {0.0f, 1.0f};
        s.width = 1;
        grow->samplers.push_back(s);
        grow->channels.push_back({0, AnimationPath::Weights, morphed, {}, "quad"});
        animations.push_back(grow);
        auto seq = make<Sequence>();
        for (const vec4& c : {vec4(1, 0, 0, 1), vec4(0, 1, 0, 1), vec4(0, 0, 1, 1)}) {
            auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(-3.0, 0.0, 0.5)));
            t->addChild(box(c));
            seq->addChild(t);
        }
        seq->defaultDuration = 0.2;
        for (size_t i = 0; i < 3; ++i) seq->setDuration(i, 0.2);
        root->addChild(seq);
    }
};

TEST(ViewerThreads, EveryModelDrawsAnAnimatedSceneAsSingleThreaded) {
    constexpr int kW = 256, kH = 160, kFrames = 24;
    OsmesaContext ctx(kW, kH);
    Camera cam;
    cam.setViewport(kW, kH);
    cam.setPerspective(50.0, double(kW) / kH, 0.1, 100.0);
    cam.setLookAt(dvec3(0.0, -9.0, 2.5), dvec3(0.0, 1.0, 1.0), dvec3(0, 0, 1));
    auto run = [&](ThreadingModel m) {
        Animated a;  // each model from the rest pose: the player moves the nodes
        Scene scene(a.root);
        double now = 0.0;
        ViewerSettings s = settingsFor(m, ctx);
        s.clock = [&now] { return now; };
        Viewer viewer(scene, s);
        viewer.addView(cam);
        for (auto& anim : a.animations) viewer.animations().play(viewer.animations().add(anim));
        std::vector<Image> pictures;
        pictures.resize(size_t(kFrames));
        viewer.onDrawn([&](const FrameInfo& fi) { pictures.at(size_t(fi.frame)) = viewer.renderer().readColor(); });
        for (int i = 0; i < kFrames; ++i) {
            now = 0.045 * i;
            viewer.frame();
        }
        viewer.flush();
        return pictures;
    };
    const std::vector<Image> single = run(ThreadingModel::SingleThreaded);
    // Things move: the figures walk, the quad grows, the sequence turns.
    EXPECT_GT(countDifferingPixels(single[0], single[kFrames / 2]), 200u);
    EXPECT_GT(countDifferingPixels(single[kFrames / 2], single[kFrames - 1]), 200u);
    for (ThreadingModel m : kModels)
        if (m != ThreadingModel::SingleThreaded) expectSamePictures(run(m), single, m);
}

// --- stage rules and failures: a small scene ---

Camera lookingAt(const dvec3& eye, int w, int h) {
    Camera c;
    c.setViewport(w, h);
    c.setPerspective(50.0, double(w) / h, 0.1, 200.0);
    c.setLookAt(eye, dvec3(0.0), dvec3(0, 0, 1));
    return c;
}

struct Small {
    static constexpr int kW = 64, kH = 48;
    OsmesaContext ctx{kW, kH};
    ref_ptr<Group> root = make<Group>();
    ref_ptr<Transform> place = make<Transform>();
    Scene scene{root};
    Small() {
        place->addChild(box(vec4(0.9f, 0.2f, 0.1f, 1.0f)));
        root->addChild(place);
    }
};

TEST(ViewerThreads, AppCallbacksRunOnTheCallingThreadAndDrawCallbacksWhereTheContextIs) {
    for (ThreadingModel m : kModels) {
        Small s;
        Viewer viewer(s.scene, settingsFor(m, s.ctx));
        viewer.addView(lookingAt(dvec3(0, -6, 0), Small::kW, Small::kH));
        const std::thread::id caller = std::this_thread::get_id();
        std::vector<std::thread::id> app, drawn;
        size_t covered = 0;
        viewer.onEvents([&] { app.push_back(std::this_thread::get_id()); });
        viewer.onApp([&](const FrameInfo&) { app.push_back(std::this_thread::get_id()); });
        viewer.onUpdate([&](const FrameInfo&) { app.push_back(std::this_thread::get_id()); });
        viewer.onOverlay([&] { drawn.push_back(std::this_thread::get_id()); });
        viewer.onPresent([&] { drawn.push_back(std::this_thread::get_id()); });
        viewer.onDrawn([&](const FrameInfo&) {
            drawn.push_back(std::this_thread::get_id());
            // The context is current here: the red box's pixels read back.
            const Image img = viewer.renderer().readColor();
            covered = 0;
            for (size_t p = 0; p < img.rgba.size(); p += 4) covered += img.rgba[p] > 200 && img.rgba[p + 1] < 100;
        });
        for (int i = 0; i < 4; ++i) viewer.frame();
        viewer.flush();
        ASSERT_EQ(app.size(), 12u);
        ASSERT_EQ(drawn.size(), 12u);
        for (const auto& id : app) EXPECT_EQ(id, caller) << threadingModelName(m);
        for (const auto& id : drawn)
            EXPECT_EQ(id == caller, m == ThreadingModel::SingleThreaded) << threadingModelName(m);
        EXPECT_GT(covered, 100u) << threadingModelName(m);
    }
}

// Which thread culls each view: the caller's for the single-threaded and draw-thread models, a thread of each view's
// own under CullThreadPerView (a fallback to one thread would draw the same pictures), the cull thread under
// AppCullDraw.
TEST(ViewerThreads, EachModelCullsItsViewsOnTheThreadsItNames) {
    for (ThreadingModel m : kModels) {
        Small s;
        Viewer viewer(s.scene, settingsFor(m, s.ctx));
        for (int k = 0; k < 3; ++k) viewer.addView(lookingAt(dvec3(0, -6 - k, 0), Small::kW, Small::kH));
        for (int i = 0; i < 4; ++i) viewer.frame();
        viewer.flush();
        const std::thread::id caller = std::this_thread::get_id();
        const std::thread::id a = viewer.view(0).cullThread(), b = viewer.view(1).cullThread(),
                              c = viewer.view(2).cullThread();
        EXPECT_NE(a, std::thread::id()) << threadingModelName(m);
        switch (m) {
            case ThreadingModel::SingleThreaded:
            case ThreadingModel::DrawThread:
                EXPECT_TRUE(a == caller && b == caller && c == caller) << threadingModelName(m);
                break;
            case ThreadingModel::CullThreadPerView:
                EXPECT_TRUE(a != b && b != c && a != c) << threadingModelName(m);
                EXPECT_TRUE(b != caller && c != caller) << threadingModelName(m);
                break;
            case ThreadingModel::AppCullDraw:
                EXPECT_TRUE(a == b && b == c && a != caller) << threadingModelName(m);
                break;
        }
    }
}

// The draw of frame N must not see the graph's later changes: the app stage of frames N+1.. removes the box
// (freeing its mesh and material unless the frame in flight holds them) and adds a new one each frame.
TEST(ViewerThreads, AFrameInFlightKeepsWhatItDrawsWhenTheAppDropsItFromTheGraph) {
    for (ThreadingModel m : kModels) {
        Small s;
        Viewer viewer(s.scene, settingsFor(m, s.ctx));
        viewer.addView(lookingAt(dvec3(0, -6, 0), Small::kW, Small::kH));
        std::map<uint64_t, Image> pictures;
        viewer.onApp([&](const FrameInfo& fi) {
            s.place->removeChild(size_t(0));
            const float g = float(fi.frame % 5) / 5.0f;
            s.place->addChild(box(vec4(0.9f, g, 0.1f, 1.0f)));
        });
        viewer.onDrawn([&](const FrameInfo& fi) { pictures[fi.frame] = viewer.renderer().readColor(); });
        for (int i = 0; i < 10; ++i) viewer.frame();
        viewer.flush();
        ASSERT_EQ(pictures.size(), 10u);
        // Frame i drew its own box's colour (green = i % 5 / 5).
        for (const auto& [frame, img] : pictures) {
            const size_t centre = (size_t(Small::kH / 2) * size_t(Small::kW) + size_t(Small::kW / 2)) * 4;
            const int g = img.rgba[centre + 1];
            EXPECT_NEAR(g, int(255.0 * double(frame % 5) / 5.0 + 0.5), 40) << threadingModelName(m) << " " << frame;
        }
    }
}

// A failing stage: StageError names it and the frame; the frames before it were drawn; the viewer runs again.
void expectStageError(Viewer& viewer, const char* stage, uint64_t frame, const char* what) {
    try {
        for (int i = 0; i < 20; ++i) viewer.frame();
        viewer.flush();
        ADD_FAILURE() << "no failure for stage " << stage;
    } catch (const StageError& e) {
        EXPECT_EQ(e.stage(), stage);
        EXPECT_EQ(e.frame(), frame);
        EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        try {
            std::rethrow_if_nested(e);
            ADD_FAILURE() << "nothing nested";
        } catch (const std::runtime_error& inner) {
            EXPECT_EQ(std::string(inner.what()), what);
        }
    }
}

TEST(ViewerThreads, AnAppCallbackThatThrowsStopsTheViewerAfterDrawingTheFramesBefore) {
    for (ThreadingModel m : kModels) {
        Small s;
        Viewer viewer(s.scene, settingsFor(m, s.ctx));
        viewer.addView(lookingAt(dvec3(0, -6, 0), Small::kW, Small::kH));
        bool armed = true;
        viewer.onApp([&](const FrameInfo& fi) {
            if (armed && fi.frame == 5) throw std::runtime_error("app broke");
        });
        expectStageError(viewer, "app", 5, "app broke");
        EXPECT_EQ(viewer.framesDrawn(), 5u) << threadingModelName(m);  // frames 0-4, none lost
        armed = false;
        viewer.frame();  // the viewer starts again
        viewer.flush();
        EXPECT_EQ(viewer.framesDrawn(), 6u) << threadingModelName(m);
    }
}

TEST(ViewerThreads, AFailedDrawIsRethrownOnTheApplicationThreadNamingTheDraw) {
    for (ThreadingModel m : kModels) {
        Small s;
        Viewer viewer(s.scene, settingsFor(m, s.ctx));
        viewer.addView(lookingAt(dvec3(0, -6, 0), Small::kW, Small::kH));
        int overlays = 0;
        viewer.onOverlay([&] {
            if (++overlays == 4) throw std::runtime_error("draw broke");
        });
        expectStageError(viewer, "draw", 3, "draw broke");
        EXPECT_EQ(viewer.framesDrawn(), 3u) << threadingModelName(m);
        viewer.frame();
        viewer.flush();
        EXPECT_EQ(viewer.framesDrawn(), 4u) << threadingModelName(m);
    }
}

TEST(ViewerThreads, ALostContextStopsTheViewerNamingTheContext) {
    for (ThreadingModel m : kModels) {
        if (m == ThreadingModel::SingleThreaded) continue;  // it never moves the context
        Small s;
        ViewerSettings vs = settingsFor(m, s.ctx);
        bool lost = false;
        const std::thread::id caller = std::this_thread::get_id();
        vs.bindContext = [&](bool current) {
            if (current && lost && std::this_thread::get_id() != caller) throw std::runtime_error("context lost");
            current ? s.ctx.makeCurrent() : s.ctx.release();
        };
        Viewer viewer(s.scene, vs);
        viewer.addView(lookingAt(dvec3(0, -6, 0), Small::kW, Small::kH));
        viewer.frame();
        viewer.flush();
        viewer.settings().threading = ThreadingModel::SingleThreaded;  // the threads stop: the context comes back
        viewer.frame();
        lost = true;
        viewer.settings().threading = m;
        try {
            viewer.frame();
            ADD_FAILURE() << "a lost context unnoticed";
        } catch (const StageError& e) {
            EXPECT_EQ(e.stage(), "context") << threadingModelName(m);
        }
        lost = false;
        viewer.frame();
        viewer.flush();
        EXPECT_EQ(viewer.framesDrawn(), 3u) << threadingModelName(m);
    }
}

TEST(ViewerThreads, TheDestructorJoinsWithFramesInFlight) {
    for (ThreadingModel m : kModels) {
        Small s;
        uint64_t drawn = 0;
        {
            Viewer viewer(s.scene, settingsFor(m, s.ctx));
            viewer.addView(lookingAt(dvec3(0, -6, 0), Small::kW, Small::kH));
            for (int i = 0; i < 7; ++i) viewer.frame();
            drawn = viewer.framesDrawn();
        }  // no flush: the frames in flight finish, the threads join
        EXPECT_EQ(drawn, uint64_t(7 - threadingLatency(m)));
        s.ctx.makeCurrent();  // the context is usable on this thread again
    }
}

TEST(ViewerThreads, AThreadedModelWithoutAWayToMoveTheContextIsRefused) {
    Small s;
    ViewerSettings vs;
    vs.threading = ThreadingModel::DrawThread;
    Viewer viewer(s.scene, vs);
    viewer.addView(lookingAt(dvec3(0, -6, 0), Small::kW, Small::kH));
    try {
        viewer.frame();
        ADD_FAILURE() << "accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("bindContext"), std::string::npos) << e.what();
    }
    EXPECT_EQ(parseThreadingModel("app-cull-draw"), ThreadingModel::AppCullDraw);
    EXPECT_THROW(parseThreadingModel("fast"), std::invalid_argument);
}

// With a draw thread the pager's details are uploaded there, within the pager's budget, before they are attached:
// the first frame that draws a detail finds its mesh uploaded already (no upload inside that frame's draw).
TEST(ViewerThreads, ThePagersDetailsAreUploadedOnTheDrawThreadBeforeTheyAreAttached) {
    for (ThreadingModel m : kModels) {
        Small s;
        s.place->removeChild(size_t(0));  // the paged node alone in view
        auto paged = make<PagedLOD>();
        paged->addChild(box(vec4(0.1f, 0.1f, 0.9f, 1.0f)));  // the coarse level
        paged->setFile("detail");
        paged->setRange(0.0f, 100.0f);
        s.root->addChild(paged);
        Viewer viewer(s.scene, settingsFor(m, s.ctx));
        viewer.addView(lookingAt(dvec3(0, -6, 0), Small::kW, Small::kH));
        Pager& pager = viewer.enablePaging([](const std::string&) -> ref_ptr<Node> {
            auto g = make<Group>();
            g->addChild(box(vec4(0.1f, 0.9f, 0.1f, 1.0f)));
            return g;
        });
        std::map<uint64_t, size_t> cached;
        std::map<uint64_t, Image> pictures;
        viewer.onDrawn([&](const FrameInfo& fi) {
            cached[fi.frame] = viewer.renderer().cachedMeshes();
            pictures[fi.frame] = viewer.renderer().readColor();
        });
        uint64_t attachedAt = 0;
        viewer.onUpdate([&](const FrameInfo& fi) {
            if (!attachedAt && paged->state() == PagedLOD::State::Loaded) attachedAt = fi.frame;
        });
        for (int i = 0; i < 200 && !attachedAt; ++i) {
            viewer.frame();
            pager.waitIdle();  // the load done; its upload and attachment are the viewer's
        }
        ASSERT_NE(attachedAt, 0u) << threadingModelName(m);
        for (int i = 0; i < 3; ++i) viewer.frame();
        viewer.flush();
        EXPECT_FALSE(pager.prepare()) << "wired for the pager stage only";
        ASSERT_TRUE(cached.count(attachedAt - 1) && cached.count(attachedAt));
        if (m == ThreadingModel::SingleThreaded) {  // uploaded in the pager stage of the frame that attaches it
            EXPECT_EQ(cached[attachedAt], cached[attachedAt - 1] + 1);
        } else {
            EXPECT_EQ(cached[attachedAt], cached[attachedAt - 1]) << threadingModelName(m);
            EXPECT_GT(cached[attachedAt - 1], cached[0]) << threadingModelName(m);
        }
        // The detail (green) is drawn from its first frame on, the coarse level (blue) before.
        auto green = [](const Image& img) {
            size_t n = 0;
            for (size_t p = 0; p < img.rgba.size(); p += 4)
                n += img.rgba[p + 1] > img.rgba[p] + 40 && img.rgba[p + 1] > img.rgba[p + 2] + 40;
            return n;
        };
        EXPECT_EQ(green(pictures[attachedAt - 1]), 0u) << threadingModelName(m);
        EXPECT_GT(green(pictures[attachedAt]), 100u) << threadingModelName(m);
    }
}

// Every model runs the look-ahead cull beside the view's (on the cull thread, or the view's own): a view flying at
// 10 m/s toward a tile 60 m ahead, wanted within 20 m, has its detail attached while the view is still 30 m or more
// from the tile, by the look-ahead's request alone.
TEST(ViewerThreads, EveryModelLooksAheadForThePager) {
    for (ThreadingModel m : kModels) {
        Small s;
        auto paged = make<PagedLOD>();
        paged->addChild(box(vec4(0.1f, 0.1f, 0.9f, 1.0f)));
        paged->setFile("detail");
        paged->setRange(0.0f, 20.0f);
        auto at = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 60, 0)));
        at->addChild(paged);
        s.root->addChild(at);
        double time = 0.0;
        ViewerSettings vs = settingsFor(m, s.ctx);
        vs.clock = [&] { return time; };
        Viewer viewer(s.scene, vs);
        View& v = viewer.addView(lookingAt(dvec3(0, -6, 0), Small::kW, Small::kH));
        v.prefetchSeconds = 2.0;
        Pager& pager = viewer.enablePaging([](const std::string&) -> ref_ptr<Node> { return box(vec4(0.1f)); });
        for (int k = 0; k <= 30; ++k) {  // 0 to 30 m
            time = 0.1 * k;
            const dvec3 eye(0, 10.0 * time, 1.0);
            v.camera.setLookAt(eye, eye + dvec3(0, 1, 0), dvec3(0, 0, 1));
            viewer.frame();
            pager.waitIdle();
        }
        viewer.flush();
        EXPECT_EQ(paged->state(), PagedLOD::State::Loaded) << threadingModelName(m);
        EXPECT_EQ(v.cullStats().pagedWanted, 0u) << threadingModelName(m);
    }
}

// --- ISECT ---

TEST(ViewerThreads, IsectAnswersAFrameLaterWhatTheSynchronousQueryAnswers) {
    for (ThreadingModel m : kModels) {
        Small s;
        Viewer viewer(s.scene, settingsFor(m, s.ctx));
        viewer.addView(lookingAt(dvec3(0, -6, 0), Small::kW, Small::kH));
        std::vector<IsectAnswer> answers;
        std::vector<uint64_t> arrived;
        ViewpointCollider collider;
        viewer.onApp([&](const FrameInfo& fi) {
            // The box moves along x each frame: an answer from another frame's scene would differ.
            s.place->setMatrix(glm::translate(dmat4(1.0), dvec3(0.1 * double(fi.frame), 0.0, 0.0)));
            if (fi.frame >= 3) return;
            const Ray ray{dvec3(0.1 * double(fi.frame), -10.0, 0.5), dvec3(0, 1, 0)};
            auto keep = [&, f = fi.frame](const IsectAnswer& a) {
                answers.push_back(a);
                arrived.push_back(f);
            };
            viewer.isect().intersect(ray, QueryOptions{}, keep);
            viewer.isect().move(collider, dvec3(0.1 * double(fi.frame), -10.0, 0.0), dvec3(0, 20.0, 0), keep);
            viewer.isect().intersect(Ray{dvec3(std::nan(""), 0, 0), dvec3(0, 1, 0)}, QueryOptions{}, keep);
        });
        std::vector<uint64_t> frameAtAnswer;
        for (int i = 0; i < 5; ++i) {
            viewer.frame();
            frameAtAnswer.push_back(answers.size());
        }
        viewer.flush();
        ASSERT_EQ(answers.size(), 9u) << threadingModelName(m);
        // Frame k's queries reached the application during frame k + 1 (before its events).
        EXPECT_EQ(frameAtAnswer, (std::vector<uint64_t>{0, 3, 6, 9, 9})) << threadingModelName(m);
        for (size_t k = 0; k < 3; ++k) {
            const IsectAnswer& hit = answers[3 * k];
            EXPECT_EQ(hit.frame, k);
            ASSERT_TRUE(hit.hit) << hit.error;
            EXPECT_NEAR(hit.nearest.point.y, -1.0, 1e-9);
            EXPECT_NEAR(hit.nearest.point.x, 0.1 * double(k), 1e-9);
            const IsectAnswer& moved = answers[3 * k + 1];
            EXPECT_TRUE(moved.error.empty()) << moved.error;
            EXPECT_LT(moved.position.y, -1.0);  // stopped by the box
            EXPECT_GT(moved.position.y, -1.0 - collider.settings().radius - 0.01);
            EXPECT_NE(answers[3 * k + 2].error.find("IntersectTraversal"), std::string::npos)
                << answers[3 * k + 2].error;
        }
        // The same question asked synchronously of the scene as it is now (frame 4's box at x = 0.4).
        IntersectTraversal sync;
        Hit h;
        ASSERT_TRUE(sync.intersect(s.scene, Ray{dvec3(0.4, -10.0, 0.5), dvec3(0, 1, 0)}, QueryOptions{}, h));
        EXPECT_NEAR(h.point.y, -1.0, 1e-9);
    }
}

}  // namespace

// A feature style is changed by the application while frames are culled and drawn on other threads (a click's
// highlight, a restyle): every model draws safely (ThreadSanitizer in CI), and once the changes stop, the last
// frame shows the last style as SingleThreaded does.
TEST(ViewerThreads, AStyleChangedEveryFrameByTheApplicationIsDrawnSafelyAndTheLastOneShows) {
    constexpr int kN = 10, kW = 160, kH = 90, kFrames = 12;
    OsmesaContext ctx(kW, kH);
    scenes::CityOptions opt;
    opt.n = kN;
    opt.features = true;
    Scene scene(scenes::buildCity(opt));
    const PropertyStore* store = nullptr;
    std::function<void(Node&)> findStore = [&](Node& n) {
        if (!store && n.features()) store = n.features()->store.get();
        for (size_t i = 0; i < n.numChildren() && !store; ++i) findStore(*n.child(i));
    };
    findStore(*scene.root());
    ASSERT_NE(store, nullptr);
    auto last = [&](ThreadingModel m) {
        auto style = make<FeatureStyle>();
        Viewer viewer(scene, settingsFor(m, ctx));
        viewer.addView();
        viewer.view().camera = scenes::cityOrbitCamera(kN, 3, kW, kH);
        viewer.renderer().setFeatureStyle(style);
        Image picture;
        viewer.onDrawn([&](const FrameInfo&) { picture = viewer.renderer().readColor(); });
        for (int i = 0; i < kFrames; ++i) {
            style->setHighlight(store, 0, i % (kN * kN), vec4(1, 0, 0, 1));
            if (i % 3 == 0)
                style->setRule([i](const PropertyStore&, int, std::vector<uint8_t>& rgba) {
                    for (size_t k = size_t(i) % 7; k * 4 + 3 < rgba.size(); k += 7) rgba[k * 4 + 3] = 0;
                });
            viewer.frame();
        }
        viewer.flush();
        viewer.frame();  // no change since the last: every model draws the same
        viewer.flush();
        return picture;
    };
    const Image single = last(ThreadingModel::SingleThreaded);
    ASSERT_GT(single.width, 0);
    for (ThreadingModel m : kModels) {
        if (m != ThreadingModel::SingleThreaded) {
            EXPECT_EQ(countDifferingPixels(last(m), single), 0u) << threadingModelName(m);
        }
    }
}
