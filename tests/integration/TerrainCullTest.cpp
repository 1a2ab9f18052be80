// The terrain paper's refinements, each on its own, on the `terrain` scene: the conservative ones draw exactly
// the pixels of the unculled render; fewer planes draws a superset (same pixels, more triangles); the
// screen-radius test (small-feature culling at 1 pixel) is approximate and reports its error.
#include "testbed/Accuracy.h"
#include "testbed/Terrain.h"

#include <gtest/gtest.h>

#include <cstdio>

using namespace sg;

TEST(TerrainCull, RefinementsAreConservative) {
    constexpr int kW = 192, kH = 144;
    scenes::TerrainSceneParams prm;
    prm.spacing = 40.0;  // 257^2 samples over 10 km, as 1025^2 at 10 m: the paper's eye sees part of it
    prm.terrain.tileSamples = 17;
    const scenes::TerrainScene t = scenes::buildTerrainScene(257, 2002, prm);
    Scene scene(t.terrain.root);
    scene.update();
    std::vector<Camera> views;
    for (double fov : {60.0, 90.0, 120.0}) views.push_back(scenes::terrainCamera(t, fov, kW, kH));
    // Low over the terrain, inside tiles' boxes and the root's, looking along it and down at it.
    const double z = t.heights[size_t(128) * 257 + 128];
    for (int k = 0; k < 4; ++k) {
        Camera c;
        c.setViewport(kW, kH);
        c.setPerspective(30.0 + 30.0 * k, double(kW) / kH, k % 2 ? 1.0 : 100.0, 1.0e6);
        const double a = k * 1.1;
        const dvec3 eye(900.0 * std::cos(a), 900.0 * std::sin(a), z + 150.0 + 200.0 * k);
        c.setLookAt(eye, eye + dvec3(std::cos(a + 2.0), std::sin(a + 2.0), -0.15 - 0.2 * k), dvec3(0, 0, 1));
        views.push_back(c);
    }
    CullSettings base;
    base.occlusion.mode = OcclusionMode::Off;
    std::vector<CullSettings> s(7, base);
    s[1].measureOnly.planeMasking = false;
    s[2].measureOnly.eyeInsideSkip = false;
    s[3].measureOnly.frustumPlanes = kTerrainPaperPlanes;
    s[4].strategy = CullStrategy::Sphere;
    s[5].strategy = CullStrategy::SphereSphere;
    s[6].smallFeaturePixels = 1.0;
    const char* names[] = {"default", "no plane masking", "no eye-inside skip", "fewer planes",
                           "sphere",  "sphere-sphere",    "screen radius 1 px"};
    accuracy::Harness h(kW, kH);
    const std::vector<accuracy::Result> r = h.run(scene, views, s);
    for (size_t k = 0; k < r.size(); ++k) {
        std::printf("[ terrain  ] %-20s differing pixels %llu (max %llu in a view)  triangles %llu of %llu\n", names[k],
                    (unsigned long long)r[k].differingTotal, (unsigned long long)r[k].differingMax,
                    (unsigned long long)r[k].trianglesTotal, (unsigned long long)r[k].referenceTrianglesTotal);
        // Not vacuous: every setting culls part of the terrain on these views.
        EXPECT_LT(r[k].trianglesTotal, r[k].referenceTrianglesTotal) << names[k];
        if (k < 6) {
            EXPECT_EQ(r[k].differingTotal, 0u) << names[k] << ": worst view " << r[k].worstView;
        }
    }
    // The switches that only change the work draw exactly what the default draws; fewer planes draws more.
    EXPECT_EQ(r[1].trianglesTotal, r[0].trianglesTotal);
    EXPECT_EQ(r[2].trianglesTotal, r[0].trianglesTotal);
    EXPECT_GT(r[3].trianglesTotal, r[0].trianglesTotal);
}
