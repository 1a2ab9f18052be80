// The factory window (factory without --headless, the factory-window program): its replayed keys parsed, and the
// window itself under a virtual X server: the picture of a view equals the library's headless render of the same
// camera, walking stops at a building's wall where flying goes through, M changes the LOD method shown, P saves a
// screenshot, and a build or a display that cannot give it a window says so.
#include "OutsideTools.h"
#include "common/Navigator.h"
#include "factory/KeyScript.h"
#include "factory/Options.h"
#include "integration/ProgramRun.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/intersect/HitFeatures.h"
#include "sg/intersect/PickSet.h"
#include "sg/io/ImageIO.h"
#include "sg/style/FeatureStyle.h"
#include "testbed/FactoryLighting.h"
#include "testbed/FactoryWalk.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

using namespace factory;
namespace fs = std::filesystem;

namespace {

TEST(FactoryKeyScript, TokensBecomeFrames) {
    const std::vector<ScriptFrame> s = parseKeyScript("W*3 f drag:-20,5.5 wait*2 M Esc F12");
    ASSERT_EQ(s.size(), 3u + 1 + 1 + 2 + 1 + 1 + 1);
    for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(s[size_t(i)].forward);
        EXPECT_TRUE(s[size_t(i)].pressed.empty());  // movement keys are held, not pressed
    }
    EXPECT_FALSE(s[3].forward);
    EXPECT_EQ(s[3].pressed, std::vector<Key>{Key::FlyWalk});
    EXPECT_EQ(s[4].dragX, -20.0);
    EXPECT_EQ(s[4].dragY, 5.5);
    EXPECT_TRUE(s[5].pressed.empty() && s[6].pressed.empty() && !s[5].forward);
    EXPECT_EQ(s[7].pressed, std::vector<Key>{Key::LodMode});
    EXPECT_EQ(s[8].pressed, std::vector<Key>{Key::Quit});
    EXPECT_EQ(s[9].pressed, std::vector<Key>{Key::Screenshot});
    EXPECT_TRUE(parseKeyScript("  ").empty());
    const std::vector<ScriptFrame> c = parseKeyScript("click:200,150.5");
    ASSERT_EQ(c.size(), 1u);
    EXPECT_TRUE(c[0].click);
    EXPECT_EQ(c[0].clickX, 200.0);
    EXPECT_EQ(c[0].clickY, 150.5);
    EXPECT_FALSE(s[4].click);  // a drag is not a click
    // A toggle held: pressed once, then frames of nothing.
    const std::vector<ScriptFrame> held = parseKeyScript("O*3");
    ASSERT_EQ(held.size(), 3u);
    EXPECT_EQ(held[0].pressed.size(), 1u);
    EXPECT_TRUE(held[1].pressed.empty());
}

TEST(FactoryKeyScript, BadTokensAreNamed) {
    for (const char* bad :
         {"X", "W*0", "W*", "W*2x", "drag:1", "drag:a,b", "wait*-1", "Shift", "click:1", "click:x,2"}) {
        try {
            parseKeyScript(std::string("W ") + bad);
            ADD_FAILURE() << bad << " parsed";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(std::string("'") + bad + "'"), std::string::npos) << e.what();
            EXPECT_EQ(std::string(e.what()).rfind("factory::parseKeyScript(): ", 0), 0u) << e.what();
        }
    }
}

Options parse(std::vector<const char*> args) {
    args.insert(args.begin(), "factory");
    return parseOptions(int(args.size()), const_cast<char**>(args.data()));
}

TEST(FactoryWindowOptions, TheWindowIsTheDefaultAndTakesCameraAndKeys) {
    const Options o = parse({"--camera", "1,2,3,4,5,6", "--keys", "W*2 M", "--frames", "12"});
    EXPECT_FALSE(o.headless);
    EXPECT_EQ(o.width, 1070);
    EXPECT_EQ(o.height, 865);
    EXPECT_TRUE(o.camera);
    EXPECT_EQ(o.eye, sg::dvec3(1, 2, 3));
    EXPECT_EQ(o.center, sg::dvec3(4, 5, 6));
    EXPECT_EQ(o.keys, "W*2 M");
    EXPECT_TRUE(o.framesGiven);
    EXPECT_FALSE(parse({}).framesGiven);
    EXPECT_TRUE(parse({"--help"}).help);
    for (std::vector<const char*> bad : {std::vector<const char*>{"--keys", "W*0"},
                                         {"--camera", "1,2,3"},
                                         {"--camera", "1,2,3,1,2,3"},
                                         {"--headless", "--keys", "W"},
                                         {"--headless", "--camera", "0,0,0,1,0,0"}}) {
        try {
            parse(bad);
            ADD_FAILURE() << bad[0] << " " << bad[1] << " parsed";
        } catch (const OptionError& e) {
            const std::string what = e.what();
            EXPECT_TRUE(what.find("--keys") != std::string::npos || what.find("--camera") != std::string::npos) << what;
        }
    }
}

// ---- The window under xvfb-run. ------------------------------------------------------------------------------

using Result = ProgramRun;

fs::path scratch() { return testDirectory("factory_"); }
Result run(const std::string& command) { return runProgram(scratch(), command); }

#ifdef XVFB_RUN
constexpr int kW = 400, kH = 300;

// The window, unlit (no bake, no cache), at kW x kH, quitting after `frames` with the keys replayed.
Result runWindow(const std::string& args, int frames, const std::string& keys) {
    char size[32];
    std::snprintf(size, sizeof size, " --size %dx%d", kW, kH);
    return run(xvfbRun(XVFB_RUN) + " '" FACTORY_EXE "' --no-lighting --frames " + std::to_string(frames) + size +
               " --keys '" + keys + "' " + args);
}

std::string cameraArg(const sg::dvec3& eye, const sg::dvec3& center) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "--camera %.17g,%.17g,%.17g,%.17g,%.17g,%.17g", eye.x, eye.y, eye.z, center.x,
                  center.y, center.z);
    return buf;
}

// The eye the window printed at exit: "eye (x, y, z)".
sg::dvec3 exitEye(const std::string& out) {
    const size_t at = out.find("eye (");
    sg::dvec3 e(NAN);
    if (at != std::string::npos) std::sscanf(out.c_str() + at, "eye (%lf, %lf, %lf)", &e.x, &e.y, &e.z);
    return e;
}

struct Site {
    scenes::Factory f = scenes::buildFactory();
    sg::Scene scene{f.root};
    Site() { scene.update(); }
};
Site& site() {
    static Site s;
    return s;
}

TEST(FactoryWindow, ShowsWhatTheLibraryRendersHeadless) {
    Site& s = site();
    // Over the yard towards the workshops: terrain, buildings, trees, cars, at several LOD levels.
    const sg::dvec3 eye(-20.0, -230.0, 60.0), center(-20.0, 20.0, 0.0);
    const Result r = runWindow(cameraArg(eye, center), 10, "H");  // H: the overlay off
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("factory: 10 frames"), std::string::npos) << r.out;
    // The window's camera: the navigator's view of eye and centre, as a walking path frame.
    common::Navigator nav(s.scene.image().box(0), sg::dvec3(0, 0, 1));
    nav.lookAt(eye, center);
    scenes::PathFrame p;
    p.eye = nav.eye();
    p.target = nav.eye() + 10.0 * nav.forward();
    p.walking = true;
    const sg::Camera cam = scenes::pathCamera(p, kW, kH);
    sg::Image want;
    {
        sg::OsmesaContext ctx(kW, kH);
        sg::Renderer renderer;
        renderer.setLight(scenes::factoryLight(-1));  // outside: the sun, as the window sets it
        sg::CullTraversal cull;
        sg::DrawList list;
        sg::CullStats st;
        cull.cull(s.scene, cam, sg::CullSettings{}, list, st);
        renderer.draw(list, cam);
        want = renderer.readColor();
        EXPECT_GT(st.geometries, 20u);
    }
    const sg::Image got = sg::loadPng((scratch() / "factory-window.png").string());
    ASSERT_EQ(got.width, kW);
    ASSERT_EQ(got.height, kH);
    // GLX on Xvfb and OSMesa are both Mesa's llvmpipe: the same pixels.
    EXPECT_EQ(sg::countDifferingPixels(got, want), 0u);
}

TEST(FactoryWindow, WalkingStopsAtAWallFlyingGoesThrough) {
    Site& s = site();
    // Four metres south of a solid building (not a workshop: their walls are passable), facing it.
    const sg::Box& box = s.f.buildings[4].box;
    ASSERT_NE(s.f.buildings[4].kind, "workshop");
    const double x = box.center().x, y = box.min.y - 4.0;
    const sg::dvec3 eye(x, y, s.f.terrainHeight(x, y) + 1.7), center = eye + sg::dvec3(0, 10, 0);
    const Result walk = runWindow(cameraArg(eye, center), 50, "W*45");  // 1.5 s at 4 m/s: 6 m wanted
    const Result fly = runWindow(cameraArg(eye, center), 50, "F W*45");
    ASSERT_EQ(walk.code, 0) << walk.err;
    ASSERT_EQ(fly.code, 0) << fly.err;
    EXPECT_NE(walk.out.find("; walk;"), std::string::npos) << walk.out;
    EXPECT_NE(fly.out.find("navigation: fly"), std::string::npos) << fly.out;
    const sg::dvec3 w = exitEye(walk.out), f = exitEye(fly.out);
    EXPECT_GT(w.y - y, 2.0);                                    // walked up to the wall
    EXPECT_LE(w.y, box.min.y - 0.3 + 1e-3);                     // and stopped an eye radius short of it
    EXPECT_NEAR(f.y - y, 45.0, 0.01);                           // flew the whole way (1.5 s at 30 m/s)
    EXPECT_GT(f.y, box.min.y);                                  // through the wall
    EXPECT_NEAR(w.z, s.f.terrainHeight(w.x, w.y) + 1.7, 0.05);  // on foot: 1.7 m over the ground
}

// Through a workshop's wall (passable, as on the scripted walk): inside, the window shows that workshop alone.
TEST(FactoryWindow, WalkingIntoAWorkshopSwitchesToItsInterior) {
    Site& s = site();
    const sg::Box& box = s.f.buildings[size_t(s.f.workshops[0].building)].box;
    const double x = box.center().x, y = box.min.y - 3.0;
    const sg::dvec3 eye(x, y, s.f.terrainHeight(x, y) + 1.7), center = eye + sg::dvec3(0, 10, 0);
    const Result out = runWindow(cameraArg(eye, center), 10, "wait");
    const Result in = runWindow(cameraArg(eye, center), 70, "W*60");  // 2 s at 4 m/s: 8 m, 5 m inside
    ASSERT_EQ(out.code, 0) << out.err;
    ASSERT_EQ(in.code, 0) << in.err;
    EXPECT_NE(out.out.find("; workshop -1;"), std::string::npos) << out.out;
    EXPECT_NE(in.out.find("; workshop 0;"), std::string::npos) << in.out;
    EXPECT_TRUE(box.contains(exitEye(in.out))) << in.out;
}

// The draw on a thread of its own (--threading): the same pictures as one thread draws, as the eye walks into a
// workshop (its Switch turned, the light changed to the roof's) with a screenshot on the way and the last frame.
TEST(FactoryWindow, TheThreadingModelsShowWhatOneThreadShows) {
    Site& s = site();
    const sg::Box& box = s.f.buildings[size_t(s.f.workshops[0].building)].box;
    const double x = box.center().x, y = box.min.y - 3.0;
    const sg::dvec3 eye(x, y, s.f.terrainHeight(x, y) + 1.7), center = eye + sg::dvec3(0, 10, 0);
    auto walkIn = [&](const std::string& model) {
        fs::remove_all(scratch() / model);  // the screenshot numbers start at 1
        // H: no overlay (its times differ from run to run); P: a screenshot at the door.
        return runWindow(cameraArg(eye, center) + " --threading " + model + " --out-dir " + model, 70, "H W*25 P W*35");
    };
    const Result single = walkIn("single");
    ASSERT_EQ(single.code, 0) << single.err;
    EXPECT_NE(single.out.find("; workshop 0;"), std::string::npos) << single.out;
    for (const char* model : {"draw", "cull-per-view", "app-cull-draw"}) {
        const Result r = walkIn(model);
        ASSERT_EQ(r.code, 0) << model << ": " << r.err;
        EXPECT_NE(r.out.find("; workshop 0;"), std::string::npos) << model << ": " << r.out;
        for (const char* picture : {"factory-0001.png", "factory-window.png"}) {
            const sg::Image want = sg::loadPng((scratch() / "single" / picture).string());
            const sg::Image got = sg::loadPng((scratch() / model / picture).string());
            ASSERT_EQ(got.width, kW) << model << " " << picture;
            EXPECT_EQ(sg::countDifferingPixels(got, want), 0u) << model << " " << picture;
        }
    }
}

TEST(FactoryWindow, MCyclesTheLodMethodShown) {
    const Result none = runWindow("", 10, "wait");
    const Result once = runWindow("", 10, "M");
    const Result thrice = runWindow("", 10, "M M M");
    ASSERT_EQ(none.code, 0) << none.err;
    ASSERT_EQ(once.code, 0) << once.err;
    ASSERT_EQ(thrice.code, 0) << thrice.err;
    EXPECT_NE(none.out.find("lod static"), std::string::npos) << none.out;
    EXPECT_NE(once.out.find("lod: budget"), std::string::npos) << once.out;
    EXPECT_NE(once.out.find("lod budget"), std::string::npos) << once.out;
    EXPECT_NE(thrice.out.find("lod: stress\nlod: static"), std::string::npos) << thrice.out;
}

TEST(FactoryWindow, OverlayShowsTheModeAndPSavesAScreenshot) {
    for (const char* d : {"a", "b"}) fs::remove_all(scratch() / d);  // the screenshot numbers start at 1
    const Result a = runWindow("--out-dir a", 10, "P");
    const Result b = runWindow("--out-dir b", 10, "M");
    ASSERT_EQ(a.code, 0) << a.err;
    ASSERT_EQ(b.code, 0) << b.err;
    EXPECT_NE(a.out.find("screenshot: a/factory-0001.png"), std::string::npos) << a.out;
    EXPECT_TRUE(fs::exists(scratch() / "a" / "factory-0001.png"));
    // The overlay's "LOD static" against "LOD budget": the panel differs (1x font at this size).
    const sg::Image pa = sg::loadPng((scratch() / "a" / "factory-window.png").string());
    const sg::Image pb = sg::loadPng((scratch() / "b" / "factory-window.png").string());
    size_t panel = 0;
    for (int y = 0; y < 80; ++y)
        for (int x = 0; x < 300; ++x) {
            const size_t i = (size_t(y) * kW + size_t(x)) * 4;
            panel += std::memcmp(&pa.rgba[i], &pb.rgba[i], 3) != 0;
        }
    EXPECT_GT(panel, 20u);
}

// A click picks: the workshop under the pixel is printed with its properties and drawn highlighted, as the library's
// own pick and a render with the same highlight say.
TEST(FactoryWindow, AClickNamesTheBuildingAndHighlightsIt) {
    Site& s = site();
    const sg::dvec3 eye(-20.0, -230.0, 60.0), center(-20.0, 20.0, 0.0);
    const Result r = runWindow(cameraArg(eye, center), 10, "H wait click:200,150");
    ASSERT_EQ(r.code, 0) << r.err;
    common::Navigator nav(s.scene.image().box(0), sg::dvec3(0, 0, 1));
    nav.lookAt(eye, center);
    scenes::PathFrame p;
    p.eye = nav.eye();
    p.target = nav.eye() + 10.0 * nav.forward();
    p.walking = true;
    const sg::Camera cam = scenes::pathCamera(p, kW, kH);
    sg::IntersectTraversal it;
    const sg::PickSet::Result hit = sg::PickSet().pick(it, s.scene, cam, 200, 150);
    ASSERT_TRUE(hit.hit);
    const sg::HitFeatures hf = sg::featuresAt(hit.nearest);
    ASSERT_FALSE(hf.features.empty());
    const sg::FeatureAtHit& f = hf.features[0];
    EXPECT_EQ(f.classId, "building");
    std::string line = "picked: " + f.classId;
    for (const auto& [id, v] : f.properties) line += ", " + id + " " + v.toString();
    EXPECT_NE(r.out.find(line + "\n"), std::string::npos) << line << "\nin\n" << r.out;
    // The picture: the library's render with that building highlighted.
    sg::Image want, plain;
    {
        sg::OsmesaContext ctx(kW, kH);
        sg::Renderer renderer;
        renderer.setLight(scenes::factoryLight(-1));
        sg::CullTraversal cull;
        sg::DrawList list;
        sg::CullStats st;
        cull.cull(s.scene, cam, sg::CullSettings{}, list, st);
        renderer.draw(list, cam);
        plain = renderer.readColor();
        auto style = sg::make<sg::FeatureStyle>();
        style->setHighlight(f.store, f.propertyTable, f.featureId, {1, 0.85f, 0.1f, 1});
        renderer.setFeatureStyle(style);
        renderer.draw(list, cam);
        want = renderer.readColor();
    }
    const sg::Image got = sg::loadPng((scratch() / "factory-window.png").string());
    EXPECT_EQ(sg::countDifferingPixels(got, want), 0u);
    EXPECT_GT(sg::countDifferingPixels(got, plain), 100u);  // the highlight shows
}
#else
TEST(FactoryWindow, NeedsXvfbRun) {
    SG_SKIP_OR_FAIL("xvfb-run was not found (or no factory-window): no window to test");
}
#endif

// Without a display, the window fails with 1 and says why; without GLFW in the build, `factory` says so with 2.
TEST(FactoryWindow, NoWindowIsExplained) {
    const Result r = run("DISPLAY= WAYLAND_DISPLAY= '" FACTORY_EXE "' --no-lighting --frames 10");
#ifdef FACTORY_HAS_WINDOW
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_NE(r.err.find("GlfwWindow"), std::string::npos) << r.err;
#else
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("without GLFW"), std::string::npos) << r.err;
#endif
}

}  // namespace
