// Terrain occluders (TerrainParams::occluders) in pictures: a town behind a hill is culled and the image is the
// unculled render's, pixel for pixel; on the `terrain` scene's low views the pass with them draws the same pixels.
#include "nodes/Geometry.h"
#include "testbed/Accuracy.h"
#include "testbed/Terrain.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace sg;

namespace {
constexpr int kW = 256, kH = 144;

CullSettings pass(OcclusionMethod m) {
    CullSettings c;
    c.occlusion.mode = OcclusionMode::EveryFrame;
    c.occlusion.method = m;
    return c;
}

Camera view(const dvec3& eye, const dvec3& at, double zNear = 1.0) {
    Camera c;
    c.setViewport(kW, kH);
    c.setPerspective(60.0, double(kW) / kH, zNear, 1.0e5);
    c.setLookAt(eye, at, dvec3(0, 0, 1));
    return c;
}
}  // namespace

TEST(TerrainOccludersImage, TownBehindAHillIsCulledAndTheImageIsExact) {
    // 640 m square, flat at 0 but for a hill at its centre: a 60 m plateau 80 m across, sloping to the plain by 140 m.
    const int n = 65;
    std::vector<double> h(size_t(n) * size_t(n));
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double r = std::hypot(i - 32.0, j - 32.0);
            h[size_t(j) * size_t(n) + size_t(i)] = 60.0 * std::clamp((14.0 - r) / 6.0, 0.0, 1.0);
        }
    TerrainParams p;
    p.tileSamples = 9;
    p.occluders = true;
    const Terrain t = buildTerrain(h, n, 10.0, dvec3(-320.0, -320.0, 0.0), p);
    auto root = make<Group>();
    root->addChild(t.root);
    // The town: twelve buildings 8 to 20 m high, 200 to 280 m east of the hill's centre.
    auto roofs = make<Material>(vec4(0.7f, 0.3f, 0.25f, 1.0f));
    for (int k = 0; k < 12; ++k) {
        const double x = 200.0 + 25.0 * (k % 4), y = -30.0 + 22.0 * (k / 4);
        root->addChild(make<Geometry>(makeBoxMesh(dvec3(x, y, 0.0), dvec3(x + 15.0, y + 14.0, 8.0 + k)), roofs));
    }
    Scene scene(root);
    scene.update();
    // From the west, low over the plain, looking east over the hill at the town; and one from above the plateau,
    // where the town shows (nothing culled there, and still exact).
    const std::vector<Camera> views = {view(dvec3(-250.0, 0.0, 3.0), dvec3(240.0, 0.0, 5.0)),
                                       view(dvec3(-200.0, 40.0, 15.0), dvec3(240.0, 0.0, 5.0)),
                                       view(dvec3(-300.0, -60.0, 1.6), dvec3(240.0, 10.0, 0.0), 0.5),
                                       view(dvec3(0.0, 0.0, 120.0), dvec3(240.0, 0.0, 0.0))};
    accuracy::Harness hs(kW, kH);
    for (OcclusionMethod m : {OcclusionMethod::Auto, OcclusionMethod::Hom}) {
        uint64_t culled = 0;
        for (size_t v = 0; v < views.size(); ++v) {
            CullStats st;
            const uint64_t diff = hs.compare(scene, views[v], pass(m), nullptr, nullptr, &st);
            EXPECT_EQ(diff, 0u) << "view " << v << ": " << accuracy::describeCamera(views[v]);
            if (v < 3) {
                EXPECT_GT(st.culledOcclusion, 0u) << "view " << v << " method " << occlusionMethodName(m);
            }
            culled += st.culledOcclusion;
        }
        std::printf("[ terrain occluders ] %s: %llu bounds culled by occlusion over %zu views\n",
                    occlusionMethodName(m), (unsigned long long)culled, views.size());
    }
}

TEST(TerrainOccludersImage, TerrainSceneLowViewsAreExact) {
    scenes::TerrainSceneParams prm;
    prm.spacing = 40.0;
    prm.terrain.tileSamples = 17;
    prm.terrain.occluders = true;
    const scenes::TerrainScene t = scenes::buildTerrainScene(129, 2002, prm);
    Scene scene(t.terrain.root);
    scene.update();
    // Low over the terrain, at several heights above the ground beneath, looking along it.
    std::vector<Camera> views;
    for (int k = 0; k < 8; ++k) {
        const double a = k * 0.8, r = 300.0 + 250.0 * k;
        const double x = r * std::cos(a), y = r * std::sin(a);
        const int i = std::clamp(int((x - t.origin.x) / t.spacing), 0, 128),
                  j = std::clamp(int((y - t.origin.y) / t.spacing), 0, 128);
        const dvec3 eye(x, y, double(t.heights[size_t(j) * 129 + size_t(i)]) + 20.0 + 40.0 * (k % 3));
        views.push_back(
            view(eye, eye + dvec3(std::cos(a + 2.5), std::sin(a + 2.5), -0.05 - 0.03 * (k % 4)), k % 2 ? 1.0 : 5.0));
    }
    accuracy::Harness hs(kW, kH);
    const std::vector<accuracy::Result> r =
        hs.run(scene, views, {pass(OcclusionMethod::Auto), pass(OcclusionMethod::Hom)});
    for (const accuracy::Result& x : r) {
        std::printf(
            "[ terrain occluders ] %-24s differing %llu, occluders used %llu, culled %llu, triangles %llu of "
            "%llu\n",
            x.name.c_str(), (unsigned long long)x.differingTotal, (unsigned long long)x.occludersUsedTotal,
            (unsigned long long)x.culledOcclusionTotal, (unsigned long long)x.trianglesTotal,
            (unsigned long long)x.referenceTrianglesTotal);
        EXPECT_EQ(x.differingTotal, 0u) << x.name << ": worst view " << x.worstView;
        EXPECT_GT(x.occludersUsedTotal, 0u) << x.name;
    }
}
