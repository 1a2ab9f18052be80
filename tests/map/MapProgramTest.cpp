// sgmap run as a program: the built-in demo headless (with each threading model), a script from standard input,
// bad options, and the window under a virtual X server (one thread, and a draw thread), whose picture equals the
// headless one of the same commands pixel for pixel.
#include "integration/ProgramRun.h"
#include "map/MapTestData.h"
#include "sg/io/ImageIO.h"

using namespace maptest;

namespace {

std::string sgmapExe() { return std::string("'") + SGMAP_EXE + "'"; }

size_t count(const std::string& s, const std::string& what) {
    size_t n = 0;
    for (size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
    return n;
}

}  // namespace

TEST(MapProgram, TheDemoGoesDownTwoLevelsPicksAndComesBack) {
    const auto dir = testDirectory("sgmap_");
    const ProgramRun r = runProgram(dir, sgmapExe() + " --headless --data '" + generatedDir() + "'");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("\nus\t840\tUnited States\t"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\nstate\t01\tState 01\t"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\ncounty\t01"), std::string::npos) << r.out;  // a county of state 01 picked
    EXPECT_NE(r.out.find("\nus\t840\n"), std::string::npos) << r.out;   // back up ...
    EXPECT_NE(r.out.find("\nworld\n"), std::string::npos) << r.out;     // ... twice
    EXPECT_EQ(count(r.out, "error"), 0u) << r.out;
    for (const char* png : {"sgmap-world.png", "sgmap-us.png", "sgmap-state.png"}) {
        const sg::Image img = sg::loadPng((dir / png).string());
        EXPECT_EQ(img.width, 1280) << png;
    }
}

TEST(MapProgram, ReadsAScriptFromStandardInputAndReportsBadOptions) {
    const auto dir = testDirectory("sgmap_");
    ProgramRun r = runProgram(dir, "printf 'enter 840\\nback\\nback\\n' | " + sgmapExe() +
                                       " --headless --size 200x120 --script - --data '" + generatedDir() + "'");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(count(r.out, "\n"), 3u) << r.out;
    EXPECT_NE(r.out.find("error\tat the world level"), std::string::npos) << r.out;
    r = runProgram(dir, sgmapExe() + " --headless --size 0x0");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("--size"), std::string::npos) << r.err;
    r = runProgram(dir, sgmapExe() + " --headless --data /nonexistent/map");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("/nonexistent/map/world.glb"), std::string::npos) << r.err;
    r = runProgram(dir, sgmapExe() + " --headless --script /nonexistent/script --data '" + generatedDir() + "'");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("/nonexistent/script"), std::string::npos) << r.err;
}

// The viewer's threading models (--threading): the demo's pictures (the world, a level paged in, a level below it,
// a region picked at each) as one thread draws them.
TEST(MapProgram, TheThreadingModelsDrawTheDemoAsOneThreadDoes) {
    const auto dir = testDirectory("sgmap_");
    auto demo = [&](const std::string& model) {
        // In a directory of its own (the demo's pictures have fixed names); the output to `dir` as runProgram's.
        ProgramRun r = runProgram(dir, "(mkdir -p " + model + " && cd " + model + " && " + sgmapExe() +
                                           " --headless --size 320x200 --threading " + model + " --data '" +
                                           generatedDir() + "')");
        EXPECT_EQ(r.code, 0) << model << ": " << r.err;
        EXPECT_EQ(count(r.out, "error"), 0u) << model << ": " << r.out;
        EXPECT_NE(r.out.find("\nstate\t01\tState 01\t"), std::string::npos) << model << ": " << r.out;
    };
    demo("single");
    for (const char* model : {"draw", "cull-per-view", "app-cull-draw"}) {
        demo(model);
        for (const char* png : {"sgmap-world.png", "sgmap-us.png", "sgmap-state.png"}) {
            const sg::Image want = sg::loadPng((dir / "single" / png).string());
            const sg::Image got = sg::loadPng((dir / model / png).string());
            ASSERT_EQ(want.width, 320) << png;
            EXPECT_EQ(sg::countDifferingPixels(got, want), 0u) << model << " " << png;
        }
    }
    const ProgramRun r = runProgram(dir, sgmapExe() + " --headless --threading two");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("--threading wants single, draw, cull-per-view or app-cull-draw, not 'two'"),
              std::string::npos)
        << r.err;
}

#ifdef XVFB_RUN
TEST(MapProgram, TheWindowDrawsWhatTheHeadlessRunDraws) {
    const auto dir = testDirectory("sgmap_");
    const std::string data = " --size 400x240 --data '" + generatedDir() + "'";
    ProgramRun r = runProgram(dir, xvfbRun(XVFB_RUN) + " " + sgmapExe() + data +
                                       " --frames 3 --commands 'overlay off;enter 840;pick 200 120'");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("us\t840\tUnited States"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\nstate\t"), std::string::npos) << r.out;
    ASSERT_EQ(runProgram(dir, "mv sgmap-window.png window.png").code, 0);
    // The same with the draw on a thread of its own (the swap there too).
    r = runProgram(dir, xvfbRun(XVFB_RUN) + " " + sgmapExe() + data +
                            " --threading draw --frames 3 --commands 'overlay off;enter 840;pick 200 120'");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("\nstate\t"), std::string::npos) << r.out;
    ASSERT_EQ(runProgram(dir, "mv sgmap-window.png window-draw.png").code, 0);
    r = runProgram(dir, "printf 'enter 840\\npick 200 120\\nscreenshot headless.png\\n' | " + sgmapExe() +
                            " --headless --script -" + data);
    ASSERT_EQ(r.code, 0) << r.err;
    const sg::Image w = sg::loadPng((dir / "window.png").string()), h = sg::loadPng((dir / "headless.png").string());
    EXPECT_EQ(sg::countDifferingPixels(sg::loadPng((dir / "window-draw.png").string()), w), 0u);
    ASSERT_EQ(w.rgba.size(), h.rgba.size());
    size_t differ = 0;
    for (size_t i = 0; i < w.rgba.size(); i += 4)
        differ += w.rgba[i] != h.rgba[i] || w.rgba[i + 1] != h.rgba[i + 1] || w.rgba[i + 2] != h.rgba[i + 2];
    EXPECT_EQ(differ, 0u);
}
#endif
