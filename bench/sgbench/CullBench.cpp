// sgbench cull: the city scene and its orbit path (docs/scenes.md); cull time (draw list included), what it selected,
// build time and memory.
#include "sg/cull/CullTraversal.h"
#include "sgbench/Bench.h"
#include "testbed/City.h"

#include <chrono>
#include <cstdio>
#include <stdexcept>

namespace bench {

using Clock = std::chrono::steady_clock;

int runCull(const Args& a) {
    const std::string sceneName = a.str("scene", "city");
    if (sceneName != "city")
        throw std::invalid_argument("sgbench cull: --scene must be city (got '" + sceneName + "')");
    const int n = int(a.num("n", 316));
    if (n < 1 || n > 4000) throw std::invalid_argument("sgbench cull: --n " + std::to_string(n) + " is not in 1..4000");
    const std::string path = a.str("path", "orbit");
    if (path != "orbit" && path != "street")
        throw std::invalid_argument("sgbench cull: --path must be orbit or street");
    sg::CullSettings set;
    set.strategy = sg::parseStrategy(a.str("strategy", "aabb"));
    set.smallFeaturePixels = double(a.num("small-feature", 0));
    const int passes = int(a.num("passes", 1));

    const double rss0 = rssMb();
    const auto t0 = Clock::now();
    sg::Scene scene(scenes::buildCity({n, false}));
    scene.update();
    const double buildS = std::chrono::duration<double>(Clock::now() - t0).count();
    const double rss1 = rssMb();
    const uint64_t nodes = scenes::cityNodeCount(n);

    const int frames = path == "orbit" ? scenes::kOrbitFrames : scenes::kStreetFrames;
    std::vector<sg::Camera> cams;
    for (int f = 0; f < frames; ++f)
        cams.push_back(path == "orbit" ? scenes::cityOrbitCamera(n, f) : scenes::cityStreetCamera(n, f));
    sg::CullTraversal cull;
    sg::DrawList list;
    sg::CullStats st;
    for (auto& c : cams) cull.cull(scene, c, set, list, st);  // warm-up pass
    std::vector<double> ms;
    double geoms = 0, tris = 0, tested = 0, visited = 0, kern = 0;
    for (int p = 0; p < passes; ++p)
        for (auto& c : cams) {
            const auto s = Clock::now();
            cull.cull(scene, c, set, list, st);
            ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - s).count());
            geoms += double(st.geometries);
            tris += double(st.triangles);
            tested += double(st.boundsTested);
            visited += double(st.nodesVisited);
            kern += double(st.kernelEntries);
        }
    const double k = double(ms.size());
    Json j;
    j.add("command", "cull")
        .add("scene", "city")
        .addInt("n", n)
        .add("path", path)
        .add("strategy", sg::strategyName(set.strategy));
    j.addInt("frames", long(ms.size()));
    j.add("cull_ms_median", median(ms)).add("cull_ms_p95", percentile(ms, 0.95));
    j.add("geometries_mean", geoms / k).add("triangles_mean", tris / k);
    j.add("bounds_tested_mean", tested / k).add("nodes_visited_mean", visited / k).add("kernel_entries_mean", kern / k);
    j.add("build_s", buildS).add("rss_mb", rss1).addInt("nodes", long(nodes));
    j.add("bytes_per_node", (rss1 - rss0) * 1024.0 * 1024.0 / double(nodes));
    j.add("image_bytes_per_node", double(scene.bytes()) / double(nodes));
    j.print(a);
    return 0;
}

}  // namespace bench
