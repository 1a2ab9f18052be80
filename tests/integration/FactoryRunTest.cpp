// The factory walkthrough (examples/factory): a short path's invariants in process (Switch state inside the
// workshop, no collision penetrations, visible triangles below the site's total, the machine mesh stored
// once, frames equal to their no-cull references), the summary's split of the budget's frames, and the program
// itself (JSON, pictures, bad options).
#include "BackFaceCompare.h"
#include "factory/Report.h"
#include "factory/Walkthrough.h"
#include "integration/ProgramRun.h"
#include "nodes/Geometry.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/io/ImageIO.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using namespace factory;
namespace fs = std::filesystem;

namespace {

constexpr int kFrames = 40, kW = 320, kH = 240;

struct Site {
    scenes::Factory f = scenes::buildFactory();
    sg::Scene scene{f.root};
    scenes::WalkPath path;
    Site() {
        scene.update();
        path = scenes::buildWalkPath(f, scene, kFrames);
    }
};
Site& site() {
    static Site s;
    return s;
}

TEST(FactoryRun, PathEntersAWorkshopWithoutPenetrating) {
    Site& s = site();
    ASSERT_EQ(int(s.path.frames.size()), kFrames);
    EXPECT_EQ(s.path.penetrations, 0);
    EXPECT_GT(s.path.insideFrames, 0);
    EXPECT_LT(s.path.insideFrames, kFrames);  // it also walks outside
    const sg::Box& box = s.f.buildings[size_t(s.f.workshops[size_t(s.path.workshop)].building)].box;
    for (const scenes::PathFrame& p : s.path.frames) {
        EXPECT_EQ(p.workshop >= 0, box.contains(p.eye)) << p.segment;
        if (p.walking) {
            EXPECT_NEAR(p.eye.z, s.f.terrainHeight(p.eye.x, p.eye.y) + 1.7, 0.05) << p.segment;
        }
    }
}

TEST(FactoryRun, MachineMeshStoredOnce) {
    scenes::FactoryParams fewer;
    fewer.machinesPerWorkshop = 5;
    const scenes::Factory small = scenes::buildFactory(fewer);
    const scenes::Factory& full = site().f;
    // 12 more placements per workshop draw 12 more machines but store nothing more.
    EXPECT_EQ(full.storedTriangles, small.storedTriangles);
    EXPECT_EQ(full.drawnTriangles - small.drawnTriangles, uint64_t(4 * 12 * full.machineMesh->triangleCount()));
    EXPECT_EQ(full.machineMesh->triangleCount(), 2886u);
}

TEST(FactoryRun, StaticRunDrawsLessThanTheSiteAndSwitchesInside) {
    Site& s = site();
    sg::OsmesaContext ctx(kW, kH);
    Walkthrough walk(s.f, s.scene, s.path, kW, kH);
    const ModeRun run = walk.run({sg::LodPolicy::Static}, 33.0, false, false)[0];
    ASSERT_EQ(int(run.frames.size()), kFrames);
    for (const FrameRecord& r : run.frames) {
        EXPECT_GT(r.triangles, 0u);
        EXPECT_LT(r.triangles, s.f.storedTriangles) << "frame " << r.frame;
        EXPECT_GT(r.vertices, 0u);
    }
    for (int i = 0; i < kFrames; ++i) {
        const int k = s.path.frames[size_t(i)].workshop;
        sg::CullStats st;
        walk.render(i, sg::CullSettings{}, st);
        EXPECT_EQ(s.f.outside->isOn(0), k < 0) << "frame " << i;
        for (size_t w = 0; w < s.f.workshops.size(); ++w)
            EXPECT_EQ(s.f.workshops[w].interior->isOn(0), int(w) == k) << "frame " << i << " workshop " << w;
    }
}

// The walkthrough's viewers with a draw thread (and the other models): the path's static frames, the eye entering
// a workshop (its Switch turned, the light changed) and LODs fading, drawn as one thread draws them, and the same
// records; the three methods interleaved as in the program (their viewers share the one context).
TEST(FactoryRun, TheThreadingModelsDrawThePathAsOneThreadDoes) {
    Site& s = site();
    sg::OsmesaContext ctx(kW, kH);
    auto walkWith = [&](sg::ThreadingModel m, std::vector<sg::Image>& pictures) {
        Walkthrough walk(s.f, s.scene, s.path, kW, kH);
        walk.setThreading(m, [&ctx](bool current) { current ? ctx.makeCurrent() : ctx.release(); });
        pictures.assign(size_t(kFrames), sg::Image{});
        const auto keep = [&](size_t k, int i, const sg::Image& img) {
            if (k == 0) pictures[size_t(i)] = img;
        };
        return walk.run({sg::LodPolicy::Static, sg::LodPolicy::Budget}, 33.0, false, false, keep);
    };
    std::vector<sg::Image> want;
    const std::vector<ModeRun> single = walkWith(sg::ThreadingModel::SingleThreaded, want);
    for (sg::ThreadingModel m :
         {sg::ThreadingModel::DrawThread, sg::ThreadingModel::CullThreadPerView, sg::ThreadingModel::AppCullDraw}) {
        std::vector<sg::Image> got;
        const std::vector<ModeRun> runs = walkWith(m, got);
        ASSERT_EQ(runs.size(), 2u);
        ASSERT_EQ(runs[0].frames.size(), size_t(kFrames));
        for (int i = 0; i < kFrames; ++i) {
            const FrameRecord &a = runs[0].frames[size_t(i)], &b = single[0].frames[size_t(i)];
            EXPECT_EQ(a.frame, i) << sg::threadingModelName(m);
            EXPECT_EQ(a.triangles, b.triangles) << sg::threadingModelName(m) << " frame " << i;
            EXPECT_EQ(a.geometries, b.geometries) << sg::threadingModelName(m) << " frame " << i;
            EXPECT_EQ(sg::countDifferingPixels(got[size_t(i)], want[size_t(i)]), 0u)
                << sg::threadingModelName(m) << " frame " << i << " (" << s.path.frames[size_t(i)].segment << ")";
        }
        EXPECT_EQ(runs[1].frames.size(), size_t(kFrames));  // the budget's frames differ with their times
    }
}

// Distinct meshes under `n`, every Switch and LOD child and Instance prototype included.
void meshesUnder(sg::Node& n, std::set<const sg::Mesh*>& out) {
    if (n.kind() == sg::NodeKind::Geometry && static_cast<sg::Geometry&>(n).mesh())
        out.insert(static_cast<sg::Geometry&>(n).mesh());
    for (size_t i = 0; i < n.numChildren(); ++i) meshesUnder(*n.child(i), out);
}

TEST(FactoryRun, EveryMeshIsUploadedBeforeTheFirstFrame) {
    Site& s = site();
    std::set<const sg::Mesh*> meshes;
    meshesUnder(*s.f.root, meshes);
    sg::OsmesaContext ctx(kW, kH);
    Walkthrough walk(s.f, s.scene, s.path, kW, kH);
    // The interiors, off until the door, and every coarse level are there already: no frame uploads one.
    EXPECT_EQ(walk.renderer().cachedMeshes(), meshes.size());
    walk.run({sg::LodPolicy::Static}, 33.0, false, false);
    EXPECT_EQ(walk.renderer().cachedMeshes(), meshes.size());
}

TEST(FactoryRun, FramesEqualTheirNoCullReferences) {
    Site& s = site();
    sg::OsmesaContext ctx(kW, kH);
    Walkthrough walk(s.f, s.scene, s.path, kW, kH);
    sg::CullSettings none;  // the same LOD settings, nothing culled (occlusion included)
    none.strategy = sg::CullStrategy::None;
    int compared[2] = {}, culledSome[2] = {};  // outside, inside
    for (int i = 0; i < kFrames; ++i) {
        const int in = s.path.frames[size_t(i)].workshop >= 0 ? 1 : 0;
        sg::CullStats culled, all;
        const sg::Image got = walk.render(i, sg::CullSettings{}, culled);
        EXPECT_EQ(sg::countDifferingPixels(got, walk.render(i, none, all)), 0u)
            << "frame " << i << " (" << s.path.frames[size_t(i)].segment << ")";
        ++compared[in];
        culledSome[in] += culled.geometries < all.geometries;
    }
    EXPECT_GE(compared[0], 6);
    EXPECT_GE(compared[1], 6);
    // The comparison means something only where the cull left things out, inside and outside.
    EXPECT_GT(culledSome[0], 0);
    EXPECT_GT(culledSome[1], 0);
}

// The factory's path (textures, baked light, the sun's highlight, cut-out trees, fading LODs) drawn by the shader
// variants and by the one program: the same pixels, at most 1/255 a channel.
TEST(FactoryRun, TheShaderVariantsDrawThePathAsTheOneProgramDoes) {
    Site& s = site();
    sg::OsmesaContext ctx(kW, kH);
    Walkthrough walk(s.f, s.scene, s.path, kW, kH);
    for (int i = 0; i < kFrames; i += 2) {
        sg::CullStats stats;
        walk.renderer().setShaderMode(sg::Renderer::ShaderMode::OneProgram);
        const sg::Image one = walk.render(i, sg::CullSettings{}, stats);
        walk.renderer().setShaderMode(sg::Renderer::ShaderMode::Variants);
        const sg::Image variants = walk.render(i, sg::CullSettings{}, stats);
        EXPECT_EQ(sg::countDifferingPixels(one, variants, 1), 0u)
            << "frame " << i << " (" << s.path.frames[size_t(i)].segment << ")";
    }
    EXPECT_GT(walk.renderer().variantCount(), 3u);  // textured, baked, cut-out and plain draws at least
}

// The walk passes through doors and close by walls and machines: whatever back faces the renderer skips, the
// pictures are those drawn with all of them, but for ties at silhouette edges (tests/BackFaceCompare.h).
TEST(FactoryRun, SkippingBackFacesDrawsThePathAsDrawingThemDoes) {
    Site& s = site();
    sg::OsmesaContext ctx(kW, kH);
    Walkthrough walk(s.f, s.scene, s.path, kW, kH);
    uint64_t skipped = 0;
    for (int i = 0; i < kFrames; i += 2) {
        sg::CullStats stats;
        walk.renderer().setBackFaceCulling(false);
        const sg::Image all = walk.render(i, sg::CullSettings{}, stats);
        const std::vector<float> allDepth = walk.renderer().readDepth();
        walk.renderer().setBackFaceCulling(true);
        const sg::Image culled = walk.render(i, sg::CullSettings{}, stats);
        skipped += walk.renderer().lastStats().backFacesSkipped;
        const testutil::BackFaceDiff d = testutil::compareBackFaces(all, allDepth, culled, walk.renderer().readDepth(),
                                                                    walk.renderer().lastDepthReversed());
        EXPECT_EQ(d.wrong, 0u) << "frame " << i << " (" << s.path.frames[size_t(i)].segment << ")";
        EXPECT_LE(d.ties, size_t(kW * kH) / 200) << "frame " << i;
    }
    EXPECT_GT(skipped, 0u);
}

using Result = ProgramRun;

// This test's own directory, emptied: a new bake cache each run.
fs::path scratch() {
    const fs::path dir = testDirectory("factory_");
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}
Result runFactory(const std::string& args) { return runProgram(scratch(), "'" FACTORY_EXE "' " + args); }

TEST(FactoryRun, ProgramPrintsJsonAndWritesPictures) {
    const Result r =
        runFactory("--headless --json --frames 40 --size 160x120 --jitter-draws 5 --out-dir pics --cache-dir cache");
    ASSERT_EQ(r.code, 0) << r.err;
    for (const char* key : {"\"triangles_total\": ", "\"penetrations\": 0,", "\"switch_inside_frames\": ",
                            "\"same_view_jitter_p95_ms\": ", "\"static\": {", "\"budget\": {", "\"stress\": {",
                            "\"fps_median\": ", "\"image_mae\": ", "\"budget_ms\": 33.000",
                            "\"budget_abs_dev_p95_ms\": ", "\"full_detail_frames\": ", "\"frame_ms_mean_reduced\": ",
                            "\"triangles_visible_mean\": ", "\"vertices_visible_mean\": "})
        EXPECT_NE(r.out.find(key), std::string::npos) << key << " in " << r.out;
    EXPECT_EQ(r.out.find("\"switch_inside_frames\": 0,"), std::string::npos) << r.out;
    EXPECT_NE(r.err.find("factory: lighting baked"), std::string::npos) << r.err;  // a new cache directory
    const fs::path dir = testDirectory("factory_") / "pics";
    for (const char* file : {"factory-outside.png", "factory-inside.png", "factory-frames.csv"})
        EXPECT_TRUE(fs::exists(dir / file)) << file;
    // A header and one row per mode and frame.
    const std::string csv = slurpFile(dir / "factory-frames.csv");
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 3 * 40);
}

// The program with a draw thread: the static run's pictures (outside, inside the workshop, the overview) and its
// frames' counts as with one thread.
TEST(FactoryRun, ProgramWithADrawThreadWritesThePicturesOfOneThread) {
    const std::string args = "--headless --json --frames 40 --size 160x120 --jitter-draws 5 --no-lighting";
    ASSERT_EQ(runFactory(args + " --out-dir single").code, 0);
    const fs::path dir = testDirectory("factory_");
    // The static rows' mode, frame, segment, workshop, eye and counts (the times differ).
    auto staticCounts = [&](const std::string& sub) {
        std::istringstream csv(slurpFile(dir / sub / "factory-frames.csv"));
        std::string rows;
        for (std::string line; std::getline(csv, line);)
            if (line.rfind("static,", 0) == 0) {
                size_t at = 0;
                for (int comma = 0; comma < 10 && at != std::string::npos; ++comma) at = line.find(',', at + 1);
                rows += line.substr(0, at) + "\n";
            }
        return rows;
    };
    const std::string want = staticCounts("single");
    EXPECT_EQ(std::count(want.begin(), want.end(), '\n'), 40);
    for (const char* model : {"draw", "app-cull-draw"}) {
        const Result r = runProgram(dir, "'" FACTORY_EXE "' " + args + " --threading " + model + " --out-dir " + model);
        ASSERT_EQ(r.code, 0) << model << ": " << r.err;
        for (const char* file : {"factory-outside.png", "factory-inside.png", "factory-overview.png"}) {
            const sg::Image a = sg::loadPng((dir / "single" / file).string());
            const sg::Image b = sg::loadPng((dir / model / file).string());
            ASSERT_GT(a.width, 0) << file;
            EXPECT_EQ(sg::countDifferingPixels(a, b), 0u) << model << " " << file;
        }
        EXPECT_EQ(staticCounts(model), want) << model;
    }
}

TEST(FactoryRun, SummarySeparatesTheFramesDrawnAtFullDetail) {
    // A budget cannot slow a frame that is already at full detail: its mean over the others is reported apart.
    ModeRun run;
    run.mode = sg::LodPolicy::Budget;
    run.budgetMs = 33.0;
    const double ms[4] = {10.0, 20.0, 30.0, 40.0}, mae[4] = {0.0, 0.0, 1.5, 2.5};
    for (int i = 0; i < 4; ++i) {
        FrameRecord r;
        r.frame = i;
        r.frameMs = ms[i];
        r.mae = mae[i];
        run.frames.push_back(r);
    }
    ModeSummary s = summarize(run);
    EXPECT_EQ(s.fullDetailFrames, 2);
    EXPECT_DOUBLE_EQ(s.frameMsMeanReduced, 35.0);
    EXPECT_DOUBLE_EQ(s.frameMsMean, 25.0);
    for (FrameRecord& r : run.frames) r.mae = -1.0;  // not compared
    s = summarize(run);
    EXPECT_EQ(s.fullDetailFrames, 0);
    EXPECT_EQ(s.frameMsMeanReduced, -1.0);
}

TEST(FactoryRun, BadOptionsExitWithCode2) {
    for (const char* bad : {"--size 0x0", "--size 100", "--frames abc", "--frames 3", "--budget-ms -1", "--bogus",
                            "--frames", "--cache-dir", "--threading two", "--threading"}) {
        const Result r = runFactory(bad);
        EXPECT_EQ(r.code, 2) << bad << ": " << r.err;
        const std::string option = std::string(bad).substr(0, std::string(bad).find(' '));
        EXPECT_NE(r.err.find(option), std::string::npos) << bad << ": " << r.err;
    }
    // A bad threading model is refused with the valid ones named.
    const Result r = runFactory("--headless --threading two");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("--threading 'two' is not single, draw, cull-per-view or app-cull-draw"), std::string::npos)
        << r.err;
}

}  // namespace
