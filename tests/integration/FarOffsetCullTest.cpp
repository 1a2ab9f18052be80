// The built-in scenes (city with its occluders, office, a random graph, the factory) moved 10 km, 1,000 km and 10,000
// km from the origin, the cameras with them: every conservative method (boxes, spheres, sphere-sphere, the occlusion
// tree, the occlusion map) draws exactly the unculled render at each offset, and the pictures match those drawn at the
// origin.
#include "Scaled.h"
#include "nodes/Transform.h"
#include "testbed/Accuracy.h"
#include "testbed/City.h"
#include "testbed/Factory.h"
#include "testbed/Office.h"
#include "testbed/PcvrCity.h"
#include "testbed/RandomScene.h"
#include "testbed/Terrain.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <string>

using namespace sg;

namespace {
constexpr int kW = 256, kH = 144, kViews = testutil::scaled(30);

// The scene under a translation by `off` and the views moved with it, at each offset: exact against the
// unculled render there; the unculled (hence the culled) pictures compared with the origin's.
void checkOffsets(const std::function<ref_ptr<Node>()>& build, const std::vector<Camera>& views, const char* name,
                  bool expectOcclusion) {
    accuracy::Harness h(kW, kH);
    CullSettings none;
    none.strategy = CullStrategy::None;
    std::vector<Image> origin;
    for (double o : {0.0, 1e4, 1e6, 1e7}) {
        const dvec3 off(o, -o, 0.25 * o);
        auto top = make<Transform>(glm::translate(dmat4(1.0), off));
        top->addChild(build());
        Scene s(top);
        s.update();
        std::vector<Camera> moved;
        for (const Camera& c : views) {
            Camera m = c;
            m.setView(c.view() * glm::translate(dmat4(1.0), -off));
            moved.push_back(m);
        }
        uint64_t occlusionCulled = 0;
        for (const accuracy::Result& r : h.run(s, moved, accuracy::conservativeSettings())) {
            EXPECT_EQ(r.differingTotal, 0u)
                << name << " at " << o << " m, " << r.name << ": worst view " << r.worstView;
            occlusionCulled += r.culledOcclusionTotal;
        }
        if (expectOcclusion) {
            EXPECT_GT(occlusionCulled, 0u) << name << " at " << o << " m";
        }
        // The reference at this offset against the origin's, view by view.
        uint64_t differing = 0, worst = 0;
        for (size_t v = 0; v < moved.size(); ++v) {
            Image ref;
            h.compare(s, moved[v], none, &ref);
            if (o == 0.0) {
                origin.push_back(ref);
                continue;
            }
            const uint64_t d = countDifferingPixels(origin[v], ref);
            differing += d;
            worst = std::max(worst, d);
        }
        std::printf(
            "[ far ] %-8s offset %8.0e m: pixels differing from the origin's pictures %llu (worst view %llu) "
            "of %d x %d x %zu\n",
            name, o, (unsigned long long)differing, (unsigned long long)worst, kW, kH, moved.size());
        EXPECT_EQ(differing, 0u) << name << " at " << o << " m";
    }
}
}  // namespace

TEST(FarOffsetCull, CityWithOccluders) {
    const int n = 8;
    checkOffsets(
        [&] {
            return ref_ptr<Node>(scenes::buildCity({n, true}));
        },
        accuracy::cityOcclusionViews(n, kViews, 61, kW, kH), "city", true);
}

TEST(FarOffsetCull, Office) {
    const int r = 5;
    checkOffsets([&] { return ref_ptr<Node>(scenes::buildOffice(r)); }, accuracy::officeViews(r, kViews, 62, kW, kH),
                 "office", true);
}

TEST(FarOffsetCull, RandomGraph) {
    scenes::RandomSceneOptions o;
    o.objects = 80;
    checkOffsets([&] { return ref_ptr<Node>(scenes::buildRandomScene(63, o)); },
                 accuracy::boxViews(Box{dvec3(-70), dvec3(70)}, kViews, 64, kW, kH), "random", false);
}

TEST(FarOffsetCull, Factory) {
    // Built once (the largest scene): the same graph under each offset's translation. Orbit views and the
    // four workshops seen from inside (their interiors off, as the defaults leave them).
    const scenes::Factory f = scenes::buildFactory();
    std::vector<Camera> views;
    const int orbit = testutil::scaled(8);
    for (int k = 0; k < orbit; ++k)
        views.push_back(scenes::factoryOrbitCamera(k * scenes::kFactoryOrbitFrames / orbit, kW, kH));
    for (int w = 0; w < 4; ++w) views.push_back(scenes::factoryWorkshopCamera(f, w, kW, kH));
    checkOffsets([&] { return ref_ptr<Node>(f.root); }, views, "factory", true);
}

TEST(FarOffsetCull, TerrainAndPcvrCity) {
    // The terrain (257^2 samples, its quadtree of LOD tiles) from the terrain paper's eye at its three fields of
    // view, and the PCVR city along its drive.
    const scenes::TerrainScene t = scenes::buildTerrainScene(257, 2002);
    std::vector<Camera> views;
    for (double fov : {60.0, 90.0, 120.0}) views.push_back(scenes::terrainCamera(t, fov, kW, kH));
    checkOffsets([&] { return ref_ptr<Node>(t.terrain.root); }, views, "terrain", false);
    std::vector<Camera> drive;
    const int n = testutil::scaled(8);
    for (int k = 0; k < n; ++k) drive.push_back(scenes::pcvrCityCamera(k * scenes::kPcvrFrames / n, kW, kH));
    checkOffsets([&] { return ref_ptr<Node>(scenes::buildPcvrCity()); }, drive, "pcvr-city", false);
}
