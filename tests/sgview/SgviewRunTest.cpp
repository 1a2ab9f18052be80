// The sgview program itself: its headless pictures against the library's own render (OSMesa, in this process),
// the overlay's pixels, --info's counts, and bad input (exit code 2 and a message naming the option).
#include "RenderUtil.h"
#include "integration/ProgramRun.h"
#include "testbed/City.h"
#ifdef SGVIEW_TEST_GLTF
#include "loaders/gltf/Gltf.h"
#include "loaders/points/Scan.h"
#include "loaders/tiles/Tileset.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "sg/scene/AnimationPlayer.h"
#endif
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/intersect/IntersectTraversal.h"
#include "sg/io/ImageIO.h"
#include "sgview/Pick.h"
#include "sgview/ViewCamera.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

using namespace sg;
namespace fs = std::filesystem;

namespace {

using Result = ProgramRun;

// A directory of this test's own (tests run in parallel).
fs::path scratch() { return testDirectory("sgview_"); }

// Runs `command` in this test's directory; its output goes to out.txt and err.txt there.
Result run(const std::string& command) { return runProgram(scratch(), command); }

Result runSgview(const std::string& args) { return run("'" SGVIEW_EXE "' " + args); }

// What the library draws of city N=8 from `cam`, with the default cull settings: sgview's reference.
Image libraryRender(const Scene& scene, const Camera& cam) {
    OsmesaContext context(cam.width(), cam.height());
    Renderer renderer;
    return testutil::drawScene(renderer, scene, cam, true);
}

// Pixels that are not the renderer's default clear colour.
size_t nonBackground(const Image& img) {
    const int bg[3] = {int(std::lround(0.55 * 255)), int(std::lround(0.7 * 255)), int(std::lround(0.9 * 255))};
    size_t n = 0;
    for (size_t i = 0; i < img.rgba.size(); i += 4) {
        bool differs = false;
        for (size_t c = 0; c < 3; ++c) differs |= std::abs(int(img.rgba[i + c]) - bg[c]) > 1;
        n += differs;
    }
    return n;
}

struct City8 {
    City8() : scene(scenes::buildCity({8, false, true})) { scene.update(); }  // as sgview builds it: with features
    Scene scene;
};

const char* kCamera = "-20,-30,90,80,80,0,0,0,1";

}  // namespace

TEST(SgviewRun, HeadlessEqualsTheLibrarysRenderFromTheGivenCamera) {
    const std::string args = "--headless --scene city --n 8 --frames 2 --out x.png --size 400x300 --camera ";
    const Result r = runSgview(args + kCamera);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("wrote x.png (400x300), 2 frames"), std::string::npos) << r.out;
    const Image got = loadPng((scratch() / "x.png").string());
    ASSERT_EQ(got.width, 400);
    ASSERT_EQ(got.height, 300);
    City8 city;
    const Camera cam = sgview::specCamera({dvec3(-20, -30, 90), dvec3(80, 80, 0), dvec3(0, 0, 1)},
                                          sgview::sceneBound(city.scene), 400, 300);
    const Image want = libraryRender(city.scene, cam);
    EXPECT_GT(nonBackground(want), size_t(400 * 300 / 10));  // the city fills a good part of the picture
    EXPECT_EQ(countDifferingPixels(got, want), 0u);
}

TEST(SgviewRun, HeadlessAutoCameraFramesTheScene) {
    const Result r = runSgview("--headless --scene city --n 8 --frames 2 --out auto.png");
    ASSERT_EQ(r.code, 0) << r.err;
    const Image got = loadPng((scratch() / "auto.png").string());
    ASSERT_EQ(got.width, 1280);
    ASSERT_EQ(got.height, 720);
    City8 city;
    const Camera cam = sgview::autoCamera(sgview::sceneBound(city.scene), dvec3(0, 0, 1), 1280, 720);
    EXPECT_EQ(countDifferingPixels(got, libraryRender(city.scene, cam)), 0u);
    EXPECT_GT(nonBackground(got), size_t(1280 * 720 / 8));
    // Framed: the city reaches near the picture's bottom edge (its nearest corner) and not past the borders.
    auto rowHasCity = [&](int y) {
        const auto first = got.rgba.begin() + std::ptrdiff_t(y) * got.width * 4;
        return nonBackground(Image{got.width, 1, {first, first + got.width * 4}}) > 0;
    };
    EXPECT_FALSE(rowHasCity(0));
    EXPECT_FALSE(rowHasCity(719));
    bool low = false;
    for (int y = 640; y < 719; ++y) low |= rowHasCity(y);
    EXPECT_TRUE(low);
}

TEST(SgviewRun, SameCameraSameImageOtherCameraOtherImage) {
    const std::string base = "--headless --scene city --n 8 --size 320x240 ";
    ASSERT_EQ(runSgview(base + "--out a.png --camera " + kCamera).code, 0);
    ASSERT_EQ(runSgview(base + "--out b.png --camera " + kCamera).code, 0);
    ASSERT_EQ(runSgview(base + "--out c.png --camera 200,-50,40,80,80,20,0,0,1").code, 0);
    const fs::path d = scratch();
    const Image a = loadPng((d / "a.png").string()), b = loadPng((d / "b.png").string());
    const Image c = loadPng((d / "c.png").string());
    EXPECT_EQ(countDifferingPixels(a, b), 0u);
    EXPECT_GT(countDifferingPixels(a, c), size_t(320 * 240 / 10));
}

TEST(SgviewRun, OverlayDrawsTextInItsPanelOnly) {
    const std::string base = "--headless --scene city --n 8 --camera " + std::string(kCamera);
    ASSERT_EQ(runSgview(base + " --out plain.png").code, 0);
    const Result r = runSgview(base + " --out overlay.png --overlay --strategy sphere --occlusion off");
    ASSERT_EQ(r.code, 0) << r.err;
    const fs::path d = scratch();
    const Image plain = loadPng((d / "plain.png").string()), over = loadPng((d / "overlay.png").string());
    // Eight lines of 2x-scaled stb_easy_font on a dark panel at the top left (sgview's five, the viewer's stage
    // times, this frame's own figures): about 1,025 x 215 pixels.
    size_t inside = 0, outside = 0, bright = 0;
    for (int y = 0; y < plain.height; ++y)
        for (int x = 0; x < plain.width; ++x) {
            const size_t i = (size_t(y) * plain.width + x) * 4;
            const bool differs = std::memcmp(&plain.rgba[i], &over.rgba[i], 3) != 0;
            (x < 1040 && y < 230 ? inside : outside) += differs;
            bright += x < 1040 && y < 230 && over.rgba[i] > 200 && over.rgba[i + 1] > 200;  // the yellow-white text
        }
    EXPECT_EQ(outside, 0u);
    EXPECT_GT(inside, size_t(500 * 100));  // the panel
    EXPECT_GT(bright, size_t(2000));       // the letters on it
}

// The overlay over the first frame: no figure reads 0 for want of a frame before it; sgview's and the viewer's
// figures of frames not yet drawn are "-", the frame's own line has its cull and draw.
TEST(SgviewRun, TheOverlaysFirstFrameShowsFiguresNotZeros) {
    const Result r =
        runSgview("--headless --scene city --n 8 --overlay --out first.png --camera " + std::string(kCamera));
    ASSERT_EQ(r.code, 0) << r.err;
    const size_t at = r.out.find("sgview: overlay:\n");
    ASSERT_NE(at, std::string::npos) << r.out;
    const std::string text = r.out.substr(at);
    EXPECT_NE(text.find("cull - ms   draw submit - ms\nnodes visited -   culled -"), std::string::npos) << text;
    EXPECT_NE(text.find("fps -   frame - ms"), std::string::npos) << text;
    EXPECT_EQ(text.find(" 0.00 ms"), std::string::npos) << text;
    EXPECT_EQ(text.find("nodes 0 "), std::string::npos) << text;
    EXPECT_EQ(text.find("triangles 0 "), std::string::npos) << text;
    EXPECT_NE(text.find("this frame: cull "), std::string::npos) << text;
}

TEST(SgviewRun, InfoCountsTheCity) {
    const Result r = runSgview("--scene city --n 8 --info");
    ASSERT_EQ(r.code, 0) << r.err;
    std::map<std::string, uint64_t> kinds;
    std::istringstream lines(r.out);
    for (std::string line; std::getline(lines, line);) {
        std::istringstream f(line);
        std::string name;
        uint64_t count = 0;
        if (line.rfind("  ", 0) == 0 && (f >> name >> count)) kinds[name] = count;
    }
    // The builder's structure: a root, 1 tile, and per cell a Group, 2 Transforms, an LOD, 3 Geometries.
    const uint64_t cells = 64;
    EXPECT_EQ(kinds["Group"], 1 + 1 + cells);
    EXPECT_EQ(kinds["Transform"], 2 * cells);
    EXPECT_EQ(kinds["LOD"], cells);
    EXPECT_EQ(kinds["Geometry"], 3 * cells);
    EXPECT_EQ(kinds["Occluder"], 0u);
    const std::string nodes = "nodes: " + std::to_string(scenes::cityNodeCount(8)) + " distinct";
    EXPECT_NE(r.out.find(nodes), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("triangles: 77568 at full detail"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("bounds: min ("), std::string::npos);
    EXPECT_NE(r.out.find("memory: "), std::string::npos);
    EXPECT_NE(r.out.find("warnings: 0"), std::string::npos);
    const Result office = runSgview("--scene office --n 2 --info");
    ASSERT_EQ(office.code, 0) << office.err;
    EXPECT_NE(office.out.find("Occluder"), std::string::npos);
}

// --auto-occluders: a box inside each building (the cars are minor beside the towers), said among the warnings; the
// picture from a street, where they cull, is the one drawn without them.
TEST(SgviewRun, AutoOccludersMakesABoxPerBuildingAndChangesNoPixel) {
    const Result r = runSgview("--scene city --n 8 --info --auto-occluders");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("  Occluder   64"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("--auto-occluders: 64 boxes and 0 polygons for 64 geometries"), std::string::npos) << r.out;
    const std::string street = " --headless --size 320x180 --camera 80,0.5,1.7,80,100,1.7,0,0,1";
    const Result without = runSgview("--scene city --n 8 --out plain.png" + street);
    ASSERT_EQ(without.code, 0) << without.err;
    EXPECT_NE(without.out.find(", 0 culled by occlusion"), std::string::npos) << without.out;
    const Result with = runSgview("--scene city --n 8 --auto-occluders --out auto.png" + street);
    ASSERT_EQ(with.code, 0) << with.err;
    EXPECT_EQ(with.out.find(", 0 culled by occlusion"), std::string::npos) << with.out;  // they cull there
    EXPECT_NE(with.out.find(" culled by occlusion"), std::string::npos) << with.out;
    const Image plain = loadPng((scratch() / "plain.png").string()), made = loadPng((scratch() / "auto.png").string());
    EXPECT_GT(nonBackground(plain), size_t(320 * 180 / 4));
    EXPECT_EQ(countDifferingPixels(plain, made), 0u);
}

TEST(SgviewRun, BadInputExitsWithTwoAndSaysWhy) {
    const std::pair<std::string, std::string> cases[] = {
        {"--scene city --bogus", "unknown option '--bogus'"},
        {"--headless --scene city --camera 1,2,3", "--camera '1,2,3': expected eye,center,up"},
        {"--headless --scene city --camera 0,0,0,0,0,0,0,0,1",
         "--camera '0,0,0,0,0,0,0,0,1': Camera::setLookAt(): eye equals centre"},
        {"--headless --scene city --size 640", "--size '640': expected WxH"},
        {"--headless --scene city --size 0x480", "--size '0x480': expected WxH"},
        {"--headless --scene city --frames", "--frames needs a value"},
        {"--headless --scene town", "--scene 'town'"},
        {"--headless", "nothing to show"},
        {"--headless missing.gltf", "'missing.gltf': no such file"},
        {"--info missing.glb", "'missing.glb': no such file"},
        {"--headless --scene city --threading two",
         "--threading 'two': parseThreadingModel(): 'two' is not a threading model (single, draw, cull-per-view, "
         "app-cull-draw)"},
    };
    for (const auto& [args, message] : cases) {
        const Result r = runSgview(args);
        EXPECT_EQ(r.code, 2) << args;
        EXPECT_NE(r.err.find("sgview: " + message), std::string::npos) << args << "\n" << r.err;
        EXPECT_EQ(r.out, "") << args;
    }
}

TEST(SgviewRun, AFileTheLoaderRefusesIsNamed) {
    std::ofstream(scratch() / "broken.gltf") << "{ this is not glTF";
    const Result r = runSgview("--headless broken.gltf");
    EXPECT_EQ(r.code, 2);
    // Either the loader's LoadError or, in a build without the loader, that message: both name the file.
    EXPECT_NE(r.err.find("broken.gltf"), std::string::npos) << r.err;
}

TEST(SgviewRun, HelpListsTheKeys) {
    const Result r = runSgview("--help");
    EXPECT_EQ(r.code, 0);
    for (const char* s : {"--headless", "--camera", "--info", "trackball", "fly", "walk", "F12", "Escape"})
        EXPECT_NE(r.out.find(s), std::string::npos) << s;
}

TEST(SgviewRun, AnUnwritableOutputFailsWithOne) {
    const Result r = runSgview("--headless --scene city --n 2 --out no/such/dir/x.png");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("no/such/dir/x.png"), std::string::npos) << r.err;
}

TEST(SgviewRun, TheWindowShowsWhatHeadlessRenders) {
#ifndef XVFB_RUN
    GTEST_SKIP() << "xvfb-run was not found: no window without a display";
#else
    const std::string view = std::string("--scene city --n 8 --size 400x300 --camera ") + kCamera;
    const Result w = run(xvfbRun(XVFB_RUN) + " '" SGVIEW_EXE "' " + view + " --frames 3 --out window.png");
    ASSERT_EQ(w.code, 0) << w.err;
    EXPECT_NE(w.out.find("sgview: 3 frames"), std::string::npos) << w.out;
    // With the draw on a thread of its own (the picture read there before the swap): the same picture but for the
    // panel's times.
    const Result wd =
        run(xvfbRun(XVFB_RUN) + " '" SGVIEW_EXE "' " + view + " --frames 3 --out window-draw.png --threading draw");
    ASSERT_EQ(wd.code, 0) << wd.err;
    EXPECT_NE(wd.out.find("sgview: 3 frames"), std::string::npos) << wd.out;
    ASSERT_EQ(runSgview("--headless --out headless.png " + view).code, 0);
    const Image win = loadPng((scratch() / "window.png").string());
    const Image off = loadPng((scratch() / "headless.png").string());
    ASSERT_EQ(win.width, 400);
    ASSERT_EQ(win.height, 300);
    // The window draws its stats panel (1x font below 960 pixels wide: about 380 x 95) over the same picture.
    size_t panel = 0, rest = 0;
    for (int y = 0; y < 300; ++y)
        for (int x = 0; x < 400; ++x) {
            const size_t i = (size_t(y) * 400 + size_t(x)) * 4;
            const bool differs = std::memcmp(&win.rgba[i], &off.rgba[i], 3) != 0;
            (x < 400 && y < 110 ? panel : rest) += differs;
        }
    // The window's camera goes through the navigator's yaw and pitch: equal up to rounding, which may move an
    // edge pixel or two (none here today).
    EXPECT_LE(rest, size_t(400 * 300 / 1000));
    EXPECT_GT(panel, size_t(250 * 60));
    // The draw thread's window: below the panel, the one thread's pixels.
    const Image drawn = loadPng((scratch() / "window-draw.png").string());
    ASSERT_EQ(drawn.rgba.size(), win.rgba.size());
    size_t below = 0;
    for (size_t i = size_t(110) * 400 * 4; i < win.rgba.size(); i += 4)
        below += std::memcmp(&win.rgba[i], &drawn.rgba[i], 3) != 0;
    EXPECT_EQ(below, 0u);
#endif
}

// --pick prints the node path of what the picture shows at a pixel: the same line the library's pick gives
// from the same camera, a path down to a Geometry where the picture shows the city, and "nothing" in the sky.
TEST(SgviewRun, PickPrintsTheNodePathOfWhatIsAtThePixel) {
    const Result r = runSgview(std::string("--headless --scene city --n 8 --size 400x300 --out p.png --camera ") +
                               kCamera + " --pick 200,150 --pick 120,200 --pick 1,1");
    ASSERT_EQ(r.code, 0) << r.err;
    City8 city;
    const Camera cam = sgview::specCamera({dvec3(-20, -30, 90), dvec3(80, 80, 0), dvec3(0, 0, 1)},
                                          sgview::sceneBound(city.scene), 400, 300);
    const Image img = loadPng((scratch() / "p.png").string());
    IntersectTraversal picker;
    for (auto [x, y] : {std::pair{200, 150}, std::pair{120, 200}, std::pair{1, 1}}) {
        const std::string want = sgview::pickReport(picker, city.scene, cam, x, y);
        EXPECT_NE(r.out.find(want + "\n"), std::string::npos) << want << "\nin\n" << r.out;
        // What the picture shows there decides which answer is right.
        const auto first = img.rgba.begin() + (std::ptrdiff_t(y) * img.width + x) * 4;
        const bool city = nonBackground(Image{1, 1, {first, first + 4}}) > 0;
        EXPECT_EQ(want.find("Geometry") != std::string::npos, city) << want;
        EXPECT_EQ(want.find("nothing") != std::string::npos, !city) << want;
    }
    // Out of the picture: refused by name.
    const Result bad = runSgview("--headless --scene city --n 8 --size 400x300 --pick 400,10");
    EXPECT_EQ(bad.code, 2);
    EXPECT_NE(bad.err.find("--pick"), std::string::npos) << bad.err;
}

#ifdef SGVIEW_TEST_GLTF
// A glTF file in, a picture out: sgview --save writes the city as .glb (turned to glTF's +Y up), and
// --headless renders the file as the library renders what the loader makes of it.
TEST(SgviewRun, HeadlessRendersAGltfFile) {
    ASSERT_EQ(runSgview("--scene city --n 8 --save city8.glb").code, 0);
    const std::string file = (scratch() / "city8.glb").string();
    const Result r = runSgview("--headless city8.glb --out g.png --size 400x300 --camera -20,90,20,80,0,-80,0,1,0");
    ASSERT_EQ(r.code, 0) << r.err;
    Scene scene(loadGltf(file).root);
    scene.update();
    const Camera cam = sgview::specCamera({dvec3(-20, 90, 20), dvec3(80, 0, -80), dvec3(0, 1, 0)},
                                          sgview::sceneBound(scene), 400, 300);
    const Image want = libraryRender(scene, cam);
    EXPECT_GT(nonBackground(want), size_t(400 * 300 / 10));
    EXPECT_EQ(countDifferingPixels(loadPng((scratch() / "g.png").string()), want), 0u);
    // The quarter turn: the city's heights (its +Z) are the file's +Y.
    const Box b = sgview::sceneBound(scene);
    EXPECT_GT(b.max.y - b.min.y, 10.0);
    EXPECT_LT(b.max.z, 1.0);
    // A file name sgview cannot write as glTF is refused by name.
    const Result bad = runSgview("--scene city --n 8 --save city8.obj");
    EXPECT_EQ(bad.code, 2);
    EXPECT_NE(bad.err.find("--save"), std::string::npos) << bad.err;
}

// An animated file (the built-in walkers saved with their walks) posed at --time: the library's render of the same
// pose, another time another picture, --info lists the animations, and an animation it lacks is refused by name.
TEST(SgviewRun, AnAnimatedFileIsPosedAtTheTimeGiven) {
    ASSERT_EQ(runSgview("--scene figures --n 2 --save walkers.glb").code, 0);
    const std::string file = (scratch() / "walkers.glb").string();
    const std::string view = " --size 320x240 --camera 0,1.2,5,0,0.9,0,0,1,0";
    const Result r = runSgview("--headless walkers.glb --animation all --time 0.3 --out a.png" + view);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("posed 4 of 4 animations ('walk', 1.00 s) and others at 0.30 s"), std::string::npos) << r.out;
    GltfScene g = loadGltf(file);
    ASSERT_EQ(g.animations.size(), 4u);
    // As sgview does it: the scene's image built at rest, then the pose applied and refitted.
    Scene scene(g.root);
    scene.update();
    AnimationPlayer player;
    for (auto& a : g.animations) {
        const size_t i = player.add(a);
        player.play(i);
        player.seek(i, 0.3);
    }
    player.apply();
    scene.update();
    const Camera cam =
        sgview::specCamera({dvec3(0, 1.2, 5), dvec3(0, 0.9, 0), dvec3(0, 1, 0)}, sgview::sceneBound(scene), 320, 240);
    const Image want = libraryRender(scene, cam);
    const Image got = loadPng((scratch() / "a.png").string());
    EXPECT_GT(nonBackground(want), size_t(320 * 240 / 10));
    // Within 1/255 a channel: a few pixels of the skinned figures' shading differ by one step between sgview's
    // viewer and this bare render (the same in every threading model and frame count; the picture otherwise equal).
    EXPECT_EQ(countDifferingPixels(got, want, 1), 0u);
    EXPECT_LT(countDifferingPixels(got, want, 0), 20u);
    ASSERT_EQ(runSgview("--headless walkers.glb --animation all --time 0.8 --out b.png" + view).code, 0);
    EXPECT_GT(countDifferingPixels(loadPng((scratch() / "b.png").string()), got), 200u);  // they walked on
    const Result info = runSgview("--info walkers.glb");
    EXPECT_NE(info.out.find("animations: 4\n  0 'walk': 1.000 s"), std::string::npos) << info.out;
    const Result bad = runSgview("--headless walkers.glb --animation run");
    EXPECT_EQ(bad.code, 2);
    EXPECT_NE(bad.err.find("--animation run: no such animation (the scene has 0 'walk'"), std::string::npos) << bad.err;
}
#endif

// The viewer's threading models (--threading): a built-in scene's picture, and a glTF file's where the loader is
// built, as one thread draws them (several frames, so that some are in flight when the picture is asked for).
TEST(SgviewRun, TheThreadingModelsDrawThePicturesOfOneThread) {
    std::vector<std::string> views = {std::string("--scene office --n 3 --size 320x200 --frames 3")};
#ifdef SGVIEW_TEST_GLTF
    ASSERT_EQ(runSgview("--scene city --n 8 --save city8.glb").code, 0);
    views.push_back("city8.glb --size 400x300 --frames 3 --camera -20,90,20,80,0,-80,0,1,0");
#endif
    for (size_t v = 0; v < views.size(); ++v) {
        const std::string base = "--headless " + views[v] + " --out v" + std::to_string(v) + "-";
        ASSERT_EQ(runSgview(base + "single.png").code, 0) << views[v];
        const Image want = loadPng((scratch() / ("v" + std::to_string(v) + "-single.png")).string());
        EXPECT_GT(nonBackground(want), size_t(want.width * want.height / 10)) << views[v];
        for (const char* model : {"draw", "cull-per-view", "app-cull-draw"}) {
            const Result r = runSgview(base + model + ".png --threading " + model);
            ASSERT_EQ(r.code, 0) << views[v] << " " << model << ": " << r.err;
            EXPECT_NE(r.out.find(", 3 frames:"), std::string::npos) << r.out;
            EXPECT_NE(r.out.find("; threading " + std::string(model) + ","), std::string::npos) << r.out;
            const Image got = loadPng((scratch() / ("v" + std::to_string(v) + "-" + model + ".png")).string());
            EXPECT_EQ(countDifferingPixels(got, want), 0u) << views[v] << " " << model;
        }
    }
}

#ifdef SGVIEW_TEST_GLTF
// Physical materials and KHR_lights_punctual: a grey quad lit by a point light and a red spot from the file, drawn
// by sgview as the library draws it with those lights and glTF's +Y up for the sky; not as it draws it unlit by them.
TEST(SgviewRun, HeadlessLightsPhysicalMaterialsWithTheFilesLights) {
    const char* json = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
      "buffers": [{"byteLength": 108, "uri": "data:application/octet-stream;base64,AACAvwAAgL8AAAAAAACAPwAAgL8AAAAAAACAPwAAgD8AAAAAAACAvwAAgD8AAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/AAABAAIAAAACAAMA"}],
      "bufferViews": [{"buffer": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 48},
                      {"buffer": 0, "byteOffset": 96, "byteLength": 12}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]},
                    {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
                    {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}],
      "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.6, 0.6, 1], "metallicFactor": 0, "roughnessFactor": 0.5}}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
      "extensionsUsed": ["KHR_lights_punctual"],
      "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 0.8},
        {"type": "spot", "color": [1, 0.2, 0.1], "intensity": 3, "spot": {"outerConeAngle": 0.4}}]}},
      "nodes": [{"mesh": 0}, {"translation": [-0.5, 0.3, 0.6], "extensions": {"KHR_lights_punctual": {"light": 0}}},
                {"translation": [0.4, -0.3, 1.5], "extensions": {"KHR_lights_punctual": {"light": 1}}}]})";
    std::ofstream(scratch() / "lit.gltf") << json;
    const Result r = runSgview("--headless lit.gltf --out lit.png --size 200x150 --camera 0,0,3,0,0,0,0,1,0");
    ASSERT_EQ(r.code, 0) << r.err;
    const GltfScene g = loadGltf((scratch() / "lit.gltf").string());
    ASSERT_EQ(g.lights.size(), 2u);
    Scene scene(g.root);
    scene.update();
    const Camera cam =
        sgview::specCamera({dvec3(0, 0, 3), dvec3(0.0), dvec3(0, 1, 0)}, sgview::sceneBound(scene), 200, 150);
    const auto render = [&](bool withLights) {
        OsmesaContext context(200, 150);
        Renderer renderer;
        DirectionalLight light;
        light.up = vec3(0, 1, 0);
        renderer.setLight(light);
        if (withLights) renderer.setPunctualLights(g.lights);
        return testutil::drawScene(renderer, scene, cam, true);
    };
    const Image shown = loadPng((scratch() / "lit.png").string());
    EXPECT_EQ(countDifferingPixels(shown, render(true)), 0u);
    EXPECT_GT(countDifferingPixels(shown, render(false), 4), size_t(200 * 150 / 10));
}
#endif

#ifdef SGVIEW_TEST_GLTF
// A 3D Tiles tileset: a root tile whose content is the city saved as .glb (glTF's +Y up, turned back to +Z up)
// refined into a child holding the same file again, moved 200 m east: headless draws it settled (the child
// loaded by the pager) as the library draws the tileset loaded whole, with its tiles' occluders made or not; --info
// counts its tiles; a JSON file that is neither glTF nor a tileset is refused.
TEST(SgviewRun, TilesetsAreShownAndCounted) {
    ASSERT_EQ(runSgview("--scene city --n 8 --save city8.glb").code, 0);
    std::ofstream(scratch() / "tileset.json") << R"({"asset": {"version": "1.1"}, "geometricError": 1000,
      "root": {"boundingVolume": {"box": [180,80,30, 180,0,0, 0,80,0, 0,0,30]}, "geometricError": 1000,
        "refine": "ADD", "content": {"uri": "city8.glb"},
        "children": [{"transform": [1,0,0,0, 0,1,0,0, 0,0,1,0, 200,0,0,1],
          "boundingVolume": {"box": [80,80,30, 80,0,0, 0,80,0, 0,0,30]}, "geometricError": 0,
          "content": {"uri": "city8.glb"}}]}})";
    const Result info = runSgview("--info tileset.json");
    ASSERT_EQ(info.code, 0) << info.err;
    EXPECT_NE(info.out.find("tiles 2 (0 external tilesets), contents loaded 1"), std::string::npos) << info.out;
    const Result all = runSgview("--info --refine-all tileset.json");
    ASSERT_EQ(all.code, 0) << all.err;
    EXPECT_NE(all.out.find("contents loaded 2"), std::string::npos) << all.out;

    const Result r =
        runSgview("--headless tileset.json --out t.png --size 400x300 --camera 80,-150,150,200,80,0,0,0,1");
    ASSERT_EQ(r.code, 0) << r.err;
    Tileset ts = loadTileset((scratch() / "tileset.json").string());
    Scene scene(ts.root());
    scene.update();
    // sgview frames its camera by the bound before any tile is loaded (the root's volume holds the child's).
    const Camera cam = sgview::specCamera({dvec3(80, -150, 150), dvec3(200, 80, 0), dvec3(0, 0, 1)},
                                          sgview::sceneBound(scene), 400, 300);
    refineAll(*ts.root(), ts.loadFunction());
    scene.update();
    const Image want = libraryRender(scene, cam);
    EXPECT_GT(nonBackground(want), size_t(400 * 300 / 10));
    EXPECT_EQ(countDifferingPixels(loadPng((scratch() / "t.png").string()), want), 0u);

    // --auto-occluders: each tile's made as it is read (the child's too, loaded by --refine-all); the same picture.
    const Result made = runSgview("--info --refine-all --auto-occluders tileset.json");
    ASSERT_EQ(made.code, 0) << made.err;
    EXPECT_NE(made.out.find("--auto-occluders: made in each tile as it is read"), std::string::npos) << made.out;
    EXPECT_NE(made.out.find("  Occluder "), std::string::npos) << made.out;
    ASSERT_EQ(
        runSgview(
            "--headless --auto-occluders tileset.json --out ta.png --size 400x300 --camera 80,-150,150,200,80,0,0,0,1")
            .code,
        0);
    EXPECT_EQ(countDifferingPixels(loadPng((scratch() / "ta.png").string()), want), 0u);

    std::ofstream(scratch() / "other.json") << R"({"type": "FeatureCollection", "features": []})";
    const Result bad = runSgview("--info other.json");
    EXPECT_EQ(bad.code, 2);
    EXPECT_NE(bad.err.find("asset"), std::string::npos) << bad.err;
}

// A tileset with a content missing and one corrupt: --info --refine-all loads the rest and lists the failed tiles,
// each with its reason, and exits 0; a tileset.json that is not there exits 2 naming it.
TEST(SgviewRun, FailedTilesAreListedAndTheRestLoads) {
    auto box = make<Group>();
    box->addChild(make<Geometry>(makeBoxMesh(dvec3(0.0), dvec3(10.0, 1.0, 10.0)), make<Material>()));
    saveGltf(*box, (scratch() / "box.glb").string());
    std::ofstream(scratch() / "broken.glb") << "glTF but not really";
    const std::string volume = R"("boundingVolume": {"box": [5,5,1, 5,0,0, 0,5,0, 0,0,1]})";
    std::ofstream(scratch() / "tileset.json")
        << R"({"asset": {"version": "1.1"}, "geometricError": 100, "root": {)" + volume +
               R"(, "geometricError": 10, "refine": "REPLACE",
        "content": {"uri": "box.glb"}, "children": [{)" +
               volume + R"(, "geometricError": 0, "content": {"uri": "box.glb"}}, {)" + volume +
               R"(, "geometricError": 0, "content": {"uri": "gone.glb"}}, {)" + volume +
               R"(, "geometricError": 0, "content": {"uri": "broken.glb"}}]}})";
    const Result r = runSgview("--info --refine-all tileset.json");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("contents loaded 2"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("failed 2"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("root.children[1].content.uri: gone.glb: no such file"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("root.children[2].content.uri: broken.glb"), std::string::npos) << r.out;

    const Result missing = runSgview("--info --refine-all nothere.json");
    EXPECT_EQ(missing.code, 2);
    EXPECT_NE(missing.err.find("nothere.json"), std::string::npos) << missing.err;
}
#endif

#ifdef SGVIEW_TEST_GLTF
// A laser scan opens as a point cloud: drawn (every point counted), its size and shape options applied, --info
// counting its points; bad point options and a LAZ file are refused by name, with exit code 2 or 1, never a crash.
TEST(SgviewRun, AScanOpensAsPointsWithItsOptions) {
    const std::string file = (scratch() / "scan.las").string();
    {
        LasWriter w(file);
        std::vector<ScanPoint> points;
        for (int y = 0; y < 40; ++y)
            for (int x = 0; x < 50; ++x) {
                ScanPoint p;
                p.position = dvec3(x * 0.5, y * 0.5, 0.1 * x);
                p.color = glm::u8vec4(200, 40, 40, 255);
                points.push_back(p);
            }
        w.write(points);
        w.close();
    }
    const std::string camera = " --size 320x240 --camera 12,10,30,12,10,0,0,1,0 --headless";
    const Result small = runSgview("scan.las --out small.png --point-size 1" + camera);
    ASSERT_EQ(small.code, 0) << small.err;
    EXPECT_NE(small.out.find("2000 points"), std::string::npos) << small.out;
    const Result big = runSgview("scan.las --out big.png --point-size 4 --edl" + camera);
    ASSERT_EQ(big.code, 0) << big.err;
    const size_t a = nonBackground(loadPng((scratch() / "small.png").string()));
    const size_t b = nonBackground(loadPng((scratch() / "big.png").string()));
    EXPECT_GT(a, size_t(500));
    EXPECT_GT(b, 2 * a);  // 4 px points cover more than 1 px ones
    const Result info = runSgview("--info scan.las");
    ASSERT_EQ(info.code, 0) << info.err;
    EXPECT_NE(info.out.find("points: 2000,"), std::string::npos) << info.out;

    const Result zero = runSgview("scan.las --point-size 0" + camera);
    EXPECT_EQ(zero.code, 2);
    EXPECT_NE(zero.err.find("--point-size"), std::string::npos) << zero.err;
    fs::copy_file(file, scratch() / "scan.laz", fs::copy_options::overwrite_existing);
    const Result laz = runSgview("scan.laz --out laz.png" + camera);
    EXPECT_NE(laz.code, 0);
    EXPECT_LT(laz.code, 128);  // refused, not crashed
    EXPECT_NE(laz.err.find("las2las"), std::string::npos) << laz.err;
}
#endif
