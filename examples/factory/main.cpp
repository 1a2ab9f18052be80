// factory: the headless walkthrough of the factory site (testbed/Factory.h) after the Performer paper. A
// scripted path (approach, into a workshop, along its machines, out, round the site, up to an overview) with
// the viewpoint collider, drawn once per LOD method (static, time budget, stress); writes PNG frames, a
// per-frame CSV, and prints the paper's table 1 columns beside its figures (or --json).
//   factory [--headless] [--frames N] [--size WxH] [--budget-ms MS] [--out-dir DIR] [--json]
#include "factory/Options.h"
#include "factory/Report.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/io/ImageIO.h"
#include "testbed/FactoryLighting.h"

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
int frameOf(const WalkPath& p, const std::string& name, double share) {
    int first = -1, count = 0;
    for (size_t i = 0; i < p.frames.size(); ++i)
        if (p.frames[i].segment == name) {
            if (first < 0) first = int(i);
            ++count;
        }
    return first < 0 ? -1 : first + std::min(count - 1, int(share * count));
}
}  // namespace

int main(int argc, char** argv) {
    Options o;
    try {
        o = parseOptions(argc, argv);
        std::filesystem::create_directories(o.outDir);
    } catch (const OptionError& e) {
        std::fprintf(stderr, "factory: %s\n%s", e.what(), usage());
        return 2;
    } catch (const std::filesystem::filesystem_error& e) {
        std::fprintf(stderr, "factory: --out-dir '%s' cannot be created: %s\n", o.outDir.c_str(), e.what());
        return 2;
    }
    try {
        const auto t0 = Clock::now();
        std::fprintf(stderr, "factory: building the site...\n");
        scenes::Factory f = scenes::buildFactory();
        if (o.lighting) {
            std::fprintf(stderr, "factory: lighting (sun, soft shadows, ambient occlusion)...\n");
            const std::string dir = o.cacheDir.empty() ? sg::VertexLightBaker::defaultCacheDir() : o.cacheDir;
            const scenes::FactoryLightingStats ls = scenes::bakeFactoryLighting(f, dir);
            std::fprintf(stderr, "factory: lighting %s in %.1f s (%llu vertices of %d meshes; cache %s)\n",
                         ls.cached ? "read from the cache" : "baked", ls.ms / 1000.0, (unsigned long long)ls.vertices,
                         ls.targets, dir.c_str());
        }
        sg::Scene scene(f.root);
        scene.update();
        std::fprintf(stderr, "factory: site built in %.1f s; walking the path (%d frames)...\n", secondsSince(t0),
                     o.frames);
        const auto t1 = Clock::now();
        const WalkPath path = buildWalkPath(f, scene, o.frames);
        std::fprintf(stderr, "factory: path in %.1f s (%d frames inside workshop %d, %d penetrations)\n",
                     secondsSince(t1), path.insideFrames, path.workshop, path.penetrations);

        sg::OsmesaContext ctx(o.width, o.height);
        Walkthrough walk(f, scene, path, o.width, o.height);
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
        std::vector<ModeRun> runs;
        for (LodMode m : {LodMode::Static, LodMode::Budget, LodMode::Stress}) {
            const auto tm = Clock::now();
            std::fprintf(stderr, "factory: %s run...\n", modeName(m));
            const int n = int(path.frames.size());
            const auto save = [&](int i, const sg::Image& img) {
                if ((i + 1) % std::max(1, n / 4) == 0 && i + 1 < n)
                    std::fprintf(stderr, "factory: %s %d/%d frames\n", modeName(m), i + 1, n);
                const auto it = pictures.find(i);
                if (m == LodMode::Static && it != pictures.end())
                    sg::savePng((std::filesystem::path(o.outDir) / it->second).string(), img);
            };
            runs.push_back(walk.run(m, o.budgetMs, true, save));
            s.modes.push_back(summarize(runs.back()));
            std::fprintf(stderr, "factory: %s run in %.1f s\n", modeName(m), secondsSince(tm));
        }
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
