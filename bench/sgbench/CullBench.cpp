// sgbench cull: the city scene and its orbit path (docs/scenes.md); cull time (draw list included), what it selected,
// build time and memory.
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"
#include "sgbench/Bench.h"
#include "testbed/City.h"

#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <stdexcept>

namespace bench {

using Clock = std::chrono::steady_clock;

namespace {

// The city with each cell's building and car placed by Instances of one prototype per kind (the building's
// LOD of the first cell of its height, the car's Geometry) instead of Transforms: how a tile read from
// EXT_mesh_gpu_instancing holds them.
void placeByInstances(sg::Node& root) {
    std::map<const sg::Mesh*, sg::ref_ptr<sg::Node>> protos;
    for (size_t t = 0; t < root.numChildren(); ++t)
        for (size_t c = 0; c < root.child(t)->numChildren(); ++c) {
            auto& cell = static_cast<sg::Group&>(*root.child(t)->child(c));
            for (size_t k = 0; k < cell.numChildren(); ++k) {
                auto* place = static_cast<sg::Transform*>(cell.child(k));
                sg::Node* x = place->child(0);
                const sg::Node* g = x->kind() == sg::NodeKind::LOD ? x->child(0) : x;
                auto& proto = protos[static_cast<const sg::Geometry*>(g)->mesh()];
                if (!proto) proto = sg::ref_ptr<sg::Node>(x);
                const sg::dmat4 m = place->matrix();
                cell.removeChild(k);
                cell.insertChild(k, sg::make<sg::Instance>(proto, m));
            }
        }
}

}  // namespace

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
    // --instanced 1: the same city placed by Instances, culled interleaved with it (ratio to the Transforms).
    std::unique_ptr<sg::Scene> instanced;
    if (a.num("instanced", 0)) {
        instanced = std::make_unique<sg::Scene>(scenes::buildCity({n, false}));
        placeByInstances(*instanced->root());
        instanced->update();
    }
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
    std::vector<double> ms, instancedMs;
    size_t instancedGeometries = 0, plainGeometries = 0;
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
            plainGeometries += st.geometries;
            if (!instanced) continue;
            const auto si = Clock::now();
            cull.cull(*instanced, c, set, list, st);
            instancedMs.push_back(std::chrono::duration<double, std::milli>(Clock::now() - si).count());
            instancedGeometries += st.geometries;
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
    if (instanced) {
        std::vector<double> ratio;
        for (size_t f = 0; f < ms.size(); ++f) ratio.push_back(instancedMs[f] / ms[f]);
        j.add("instanced_cull_ms_median", median(instancedMs)).add("instanced_ratio_median", median(ratio));
        j.addInt("instanced_geometries_differ", long(instancedGeometries) - long(plainGeometries));
    }
    j.add("build_s", buildS).add("rss_mb", rss1).addInt("nodes", long(nodes));
    j.add("bytes_per_node", (rss1 - rss0) * 1024.0 * 1024.0 / double(nodes));
    j.add("image_bytes_per_node", double(scene.bytes()) / double(nodes));
    j.print(a);
    return 0;
}

}  // namespace bench
