// sgbench pareto: run time against error for every cull and LOD method (testbed/Pareto.h) on every scene:
// city's orbit and street paths, office's walk, the factory's walkthrough. Writes pareto.csv, pareto.md and
// pareto.gp (drawn into pareto.png when gnuplot is installed), and says whether the default settings lie on
// each scene's Pareto front.
#include "sg/build/GeneratedOccluders.h"
#include "sg/gl/KeepFreedMemory.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sgbench/Bench.h"
#include "testbed/City.h"
#include "testbed/Factory.h"
#include "testbed/FactoryWalk.h"
#include "testbed/Office.h"
#include "testbed/Pareto.h"
#include "testbed/PcvrCity.h"
#include "testbed/Terrain.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace bench {

namespace {

void writeFile(const std::string& path, const std::string& text) {
    std::ofstream f(path);
    if (!f || !(f << text)) throw std::runtime_error("sgbench pareto: cannot write " + path);
}

// `count` frames of a path of `frames`, evenly spread from the first.
std::vector<int> spread(int frames, int count) {
    std::vector<int> f;
    for (int i = 0; i < count; ++i) f.push_back(int((long(i) * frames) / count));
    return f;
}

}  // namespace

int runPareto(const Args& a) {
    const bool quick = a.flag("quick");
    const std::string names = a.str("scenes", "city-orbit,city-street,office,factory,terrain,pcvr-city");
    const std::string out = a.str("out", ".");
    // Made (and found writable) before the run, not after minutes of it.
    std::error_code ec;
    std::filesystem::create_directories(out, ec);
    if (ec || !std::ofstream(out + "/pareto.csv"))
        throw std::invalid_argument("sgbench pareto: --out " + out + " is not a writable directory");
    const int n = int(a.num("n", 100)), r = int(a.num("r", 8));
    if (n < 1 || n > 1000)
        throw std::invalid_argument("sgbench pareto: --n " + std::to_string(n) + " is not in 1..1000");
    if (r < 1 || r > 100) throw std::invalid_argument("sgbench pareto: --r " + std::to_string(r) + " is not in 1..100");
    // 640x360: the error counts and the frames come from the same render, and llvmpipe's time per frame is
    // mostly vertices, so the quarter-size viewport keeps the run within budget with little change to the ranking.
    const int width = int(a.num("width", 640)), height = int(a.num("height", 360));
    if (width < 16 || height < 16 || width > 4096 || height > 4096)
        throw std::invalid_argument("sgbench pareto: --width and --height must be in 16..4096");
    const int views = int(a.num("views", quick ? 6 : 20));
    const int rounds = int(a.num("rounds", quick ? 1 : 3));
    if (views < 1 || rounds < 1) throw std::invalid_argument("sgbench pareto: --views and --rounds must be at least 1");
    pareto::Options opt;
    opt.rounds = rounds;
    opt.budgetMs = double(a.num("budget-ms", 33));
    if (!(opt.budgetMs > 0)) throw std::invalid_argument("sgbench pareto: --budget-ms must be positive");
    opt.strictReference = a.flag("strict-reference");
    const std::vector<pareto::Method> methods = pareto::selectMethods(pareto::methods(), a.str("methods", ""));

    std::vector<std::string> wanted;
    {
        std::stringstream ss(names);
        for (std::string s; std::getline(ss, s, ',');) wanted.push_back(s);
    }
    const std::vector<std::string> known = {"city-orbit", "city-street", "office", "factory", "terrain", "pcvr-city"};
    for (const std::string& s : wanted)
        if (std::find(known.begin(), known.end(), s) == known.end())
            throw std::invalid_argument("sgbench pareto: --scenes: no scene '" + s +
                                        "' (valid: city-orbit, city-street, office, factory, terrain, pcvr-city)");

    // --occluders generated: every scene's authored occluders removed and occluders made from its geometry instead
    // (sg/build/GeneratedOccluders.h), so that the occlusion rows use those, beside the GPU's queries (gpu-query).
    const std::string occluders = a.str("occluders", "authored");
    if (occluders != "authored" && occluders != "generated")
        throw std::invalid_argument("sgbench pareto: --occluders must be authored or generated (got '" + occluders +
                                    "')");
    auto prepared = [&](sg::ref_ptr<sg::Node> root) {
        if (occluders == "generated") {
            sg::removeOccluders(*root);
            const sg::OccluderGenStats st = sg::generateOccluders(*root);
            std::fprintf(stderr, "sgbench pareto: %llu boxes, %llu polygons generated in %.1f ms\n",
                         (unsigned long long)st.boxes, (unsigned long long)st.polygons, st.ms);
        }
        return root;
    };

    sg::OsmesaContext ctx(width, height);
    sg::Renderer renderer;
    if (renderer.softwareRasterizer()) sg::keepFreedMemory();  // as a frame loop does (sg/gl/KeepFreedMemory.h)
    std::vector<pareto::Row> rows;
    const auto start = std::chrono::steady_clock::now();
    std::unique_ptr<sg::Scene> city;  // both city paths draw one scene
    for (const std::string& name : wanted) {
        const auto t0 = std::chrono::steady_clock::now();
        pareto::SceneViews sv;
        sv.name = name;
        std::unique_ptr<sg::Scene> own;
        scenes::Factory site;
        scenes::WalkPath walk;
        scenes::TerrainScene terrain;
        int shown = -2;
        if (name == "city-orbit" || name == "city-street") {
            if (!city) {
                // With occluders (the occlusion methods need them); the two levels are the same box: error 0
                // tells the budget so (as sgbench lod).
                city = std::make_unique<sg::Scene>(prepared(scenes::buildCity({n, true})));
                setLevelErrorsToZero(*city->root());
                city->update();
            }
            sv.scene = city.get();
            sv.hasLods = true;
            const bool orbit = name == "city-orbit";
            for (int f : spread(orbit ? scenes::kOrbitFrames : scenes::kStreetFrames, views))
                sv.views.push_back(orbit ? scenes::cityOrbitCamera(n, f, width, height)
                                         : scenes::cityStreetCamera(n, f, width, height));
        } else if (name == "office") {
            own = std::make_unique<sg::Scene>(prepared(scenes::buildOffice(r)));
            own->update();
            sv.scene = own.get();
            for (int f : spread(scenes::kWalkFrames, views))
                sv.views.push_back(scenes::officeWalkCamera(r, f, width, height));
        } else if (name == "factory") {
            // The walkthrough's path (outside, through a workshop, round the site, up), each view drawn with
            // the Switch state of its eye.
            site = scenes::buildFactory();
            own = std::make_unique<sg::Scene>(prepared(site.root));
            own->update();
            walk = scenes::buildWalkPath(site, *own, 240);
            sv.scene = own.get();
            sv.hasLods = true;
            std::vector<int> workshops;
            for (int f : spread(int(walk.frames.size()), views)) {
                sv.views.push_back(scenes::pathCamera(walk.frames[size_t(f)], width, height));
                workshops.push_back(walk.frames[size_t(f)].workshop);
            }
            sv.prepare = [&site, &shown, &sv, workshops](size_t v) {
                if (workshops[v] == shown) return;
                scenes::setFactoryEye(site, shown = workshops[v]);
                sv.scene->update();
            };
        } else if (name == "terrain") {
            // 1025^2 samples (10 km), the terrain paper's eye turned round the centre in steps, its three fields
            // of view in turn.
            terrain = scenes::buildTerrainScene(1025, 2002);
            own = std::make_unique<sg::Scene>(prepared(terrain.terrain.root));
            own->update();
            sv.scene = own.get();
            sv.hasLods = true;
            const double fovs[3] = {60.0, 90.0, 120.0};
            for (int v = 0; v < views; ++v) {
                sg::Camera cam = scenes::terrainCamera(terrain, fovs[v % 3], width, height);
                const sg::dmat4 turn =
                    glm::rotate(sg::dmat4(1.0), 2.0 * glm::pi<double>() * v / views, sg::dvec3(0, 0, 1));
                cam.setView(cam.view() * turn);  // the world turned under the camera: the eye goes round
                sv.views.push_back(cam);
            }
        } else if (name == "pcvr-city") {
            // The PCVR paper's city (25 objects, 23,400 triangles) and its drive; no LODs.
            own = std::make_unique<sg::Scene>(prepared(scenes::buildPcvrCity()));
            own->update();
            sv.scene = own.get();
            for (int f : spread(scenes::kPcvrFrames, views))
                sv.views.push_back(scenes::pcvrCityCamera(f, width, height));
        }
        const std::vector<pareto::Row> got = pareto::measure(renderer, sv, methods, opt);
        rows.insert(rows.end(), got.begin(), got.end());
        std::fprintf(stderr, "sgbench pareto: %s, %zu views, %zu methods: %.1f s\n", name.c_str(), sv.views.size(),
                     got.size(), std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        for (const pareto::Row& w : got)
            if (w.queries > 0)
                std::fprintf(stderr, "sgbench pareto: %s, %s: %.1f occlusion queries per frame\n", name.c_str(),
                             w.method.c_str(), w.queries);
    }
    pareto::markFront(rows);

    const std::string md = pareto::markdown(rows);
    writeFile(out + "/pareto.csv", pareto::csv(rows));
    writeFile(out + "/pareto.md", md);
    writeFile(out + "/pareto.gp", pareto::gnuplotScript(rows, out + "/pareto.png"));
    std::cout << md << "\n";
    // Methods that draw the same lists differ by the machine's noise alone; a default beaten only by less than
    // --tolerance percent is said so, quietly.
    const double tolerance = double(a.num("tolerance", 5)) / 100.0;
    const std::vector<pareto::OffFront> off = pareto::defaultOffFront(rows, tolerance);
    for (const pareto::Row& d : rows)
        if (d.isDefault && d.onFront) std::cout << d.scene << ": the default settings lie on the Pareto front\n";
    for (const pareto::OffFront& o : off)
        std::cout << (o.beyondNoise ? "!!! DEFAULT NOT ON THE PARETO FRONT: "
                                    : "default off the strict front only within the tolerance (timing noise?): ")
                  << o.text << "\n";
    const bool plotted = std::system("command -v gnuplot >/dev/null 2>&1") == 0 &&
                         std::system(("gnuplot '" + out + "/pareto.gp'").c_str()) == 0;
    std::cout << (plotted ? "wrote " + out + "/pareto.png"
                          : "gnuplot is not installed (or failed): " + out + "/pareto.gp draws the plot")
              << "; " << out << "/pareto.csv, " << out << "/pareto.md; "
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s\n";
    return 0;
}

}  // namespace bench
