// factory: the walkthrough of the factory site (testbed/Factory.h) after the Performer paper. In a window
// (factory-window) without --headless; with it, a scripted path (approach, into a workshop, along its machines, out,
// round the site, up to an overview) with the viewpoint collider, drawn once per LOD method (static, time budget,
// stress); writes PNG frames, a per-frame CSV, and prints the paper's table 1 columns beside its figures (or --json).
//   factory [--headless] [--frames N] [--size WxH] [--budget-ms MS] [--out-dir DIR] [--json]; --help lists all
#include "common/WindowProgram.h"
#include "factory/Options.h"
#include "factory/Report.h"
#include "factory/Site.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/io/ImageIO.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>

using namespace factory;

namespace {
using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// The frame `share` of the way through the path's segment `name` (its first frame when absent: -1).
int frameOf(const scenes::WalkPath& p, const std::string& name, double share) {
    int first = -1, count = 0;
    for (size_t i = 0; i < p.frames.size(); ++i)
        if (p.frames[i].segment == name) {
            if (first < 0) first = int(i);
            ++count;
        }
    return first < 0 ? -1 : first + std::min(count - 1, int(share * count));
}

#ifdef FACTORY_WINDOW_PROGRAM
constexpr const char* kWindowProgram = FACTORY_WINDOW_PROGRAM;
#else
constexpr const char* kWindowProgram = nullptr;
#endif
}  // namespace

int main(int argc, char** argv) {
    Options o;
    if (const int code = readCommandLine(argc, argv, o); code >= 0) return code;
    if (!o.headless)
        return common::runWindowProgram(
            argv, kWindowProgram, "factory",
            "built without GLFW, so there is no window; --headless walks the site offscreen");
    try {
        const auto t0 = Clock::now();
        scenes::Factory f = buildSite(o);
        sg::Scene scene(f.root);
        scene.update();
        std::fprintf(stderr, "factory: site built in %.1f s; walking the path (%d frames)...\n", secondsSince(t0),
                     o.frames);
        const auto t1 = Clock::now();
        const scenes::WalkPath path = scenes::buildWalkPath(f, scene, o.frames);
        std::fprintf(stderr, "factory: path in %.1f s (%d frames inside workshop %d, %d penetrations)\n",
                     secondsSince(t1), path.insideFrames, path.workshop, path.penetrations);

        sg::OsmesaContext ctx(o.width, o.height);
        Walkthrough walk(f, scene, path, o.width, o.height);
        walk.setThreading(o.threading, [&ctx](bool current) { current ? ctx.makeCurrent() : ctx.release(); });
        const scenes::BackgroundLoad load(o.backgroundLoad);
        Summary s;
        s.width = o.width;
        s.height = o.height;
        s.frames = int(path.frames.size());
        s.trianglesTotal = f.storedTriangles;
        s.penetrations = path.penetrations;
        s.switchInsideFrames = path.insideFrames;
        s.backgroundLoad = scenes::BackgroundLoad::name(o.backgroundLoad);
        const int fixedView = frameOf(path, "circle", 0.4);
        s.sameViewJitterP95Ms = jitterP95(walk.sameView(fixedView, o.jitterDraws));

        // The pictures: from the static run, an outside view of the yard, inside the workshop, the overview.
        const std::map<int, std::string> pictures = {{fixedView, "factory-outside.png"},
                                                     {frameOf(path, "machines", 0.3), "factory-inside.png"},
                                                     {int(path.frames.size()) - 1, "factory-overview.png"}};
        const std::vector<sg::LodPolicy> modes = {sg::LodPolicy::Static, sg::LodPolicy::Budget, sg::LodPolicy::Stress};
        const int n = int(path.frames.size());
        std::fprintf(stderr, "factory: the three LOD methods, interleaved frame by frame...\n");
        const auto tm = Clock::now();
        const auto save = [&](size_t k, int i, const sg::Image& img) {
            if (k == 0 && (i + 1) % std::max(1, n / 4) == 0 && i + 1 < n)
                std::fprintf(stderr, "factory: %d/%d frames\n", i + 1, n);
            const auto it = pictures.find(i);
            if (modes[k] == sg::LodPolicy::Static && it != pictures.end())
                sg::savePng((std::filesystem::path(o.outDir) / it->second).string(), img);
        };
        const std::vector<ModeRun> runs = walk.run(modes, o.budgetMs, !o.freeRun, true, save);
        for (const ModeRun& r : runs) s.modes.push_back(summarize(r));
        std::fprintf(stderr, "factory: path drawn in %.1f s\n", secondsSince(tm));
        const std::string csv = (std::filesystem::path(o.outDir) / "factory-frames.csv").string();
        writeCsv(csv, path, runs);
        if (o.json)
            printJson(stdout, s);
        else {
            printTable(stdout, s);
            std::printf("  wrote %s and factory-outside.png, factory-inside.png, factory-overview.png in %s\n",
                        csv.c_str(), o.outDir.c_str());
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "factory: %s\n", e.what());
        return 1;
    }
}
