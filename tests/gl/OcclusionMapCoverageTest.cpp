// The occlusion map's rasterizer against the GPU's: random triangles drawn by OpenGL and rasterized into the
// map; every screen pixel whose centre lies in a map pixel the map counts as covered is drawn by the GPU.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "sg/cull/CullTraversal.h"
#include "sg/cull/OcclusionMap.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"

#include <gtest/gtest.h>

#include <random>

using namespace sg;

TEST(OcclusionMapCoverage, EveryCoveredMapPixelIsDrawnByTheGpu) {
    // A viewport whose pixels do not line up with the map's (1.25 x 0.78 screen pixels per map pixel).
    constexpr int kW = 320, kH = 200;
    OsmesaContext context(kW, kH);
    Renderer renderer;
    Camera cam;
    cam.setLookAt(dvec3(0.0), dvec3(0, 0, -1), dvec3(0, 1, 0));
    cam.setPerspective(70.0, double(kW) / kH, 0.5, 1000.0);
    cam.setViewport(kW, kH);
    OcclusionSettings os;
    os.method = OcclusionMethod::Hom;
    auto white = make<Material>(vec4(1.0f));
    white->unlit = true;

    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1.2, 1.2), dz(1.0, 80.0);
    uint64_t checked = 0;
    for (int t = 0; t < 150; ++t) {
        std::vector<vec3> pos;
        dvec3 v[3];
        for (int k = 0; k < 3; ++k) {
            const double d = dz(rng);
            v[k] = dvec3(u(rng) * d, u(rng) * d, -d);
            pos.push_back(vec3(v[k]));
            v[k] = dvec3(pos.back());  // the GPU gets floats: the map gets the same points
        }
        auto mesh = make<Mesh>();
        mesh->set(pos, std::vector<vec3>(3, vec3(0, 0, 1)), {0, 1, 2});
        auto root = make<Group>();
        root->addChild(make<Geometry>(mesh, white));
        Scene scene(root);
        scene.update();
        DrawList list;
        CullStats stats;
        CullSettings none;
        none.strategy = CullStrategy::None;
        CullTraversal().cull(scene, cam, none, list, stats);
        renderer.draw(list, cam, vec4(0, 0, 0, 1));
        const Image img = renderer.readColor();

        OcclusionMap map;
        const OcclusionMap::Options o = OcclusionMap::optionsFor(cam, os);
        map.reset(cam, o);
        if (!map.addPolygon(v, 3)) continue;
        map.finish();
        for (int sy = 0; sy < kH; ++sy)
            for (int sx = 0; sx < kW; ++sx) {
                // The map pixel holding this screen pixel's centre (both counted from the bottom left).
                const int mx = int((sx + 0.5) / kW * o.width), my = int((sy + 0.5) / kH * o.height);
                if (map.opacity(0, mx, my) != 1.0f) continue;
                ++checked;
                const uint8_t* p = &img.rgba[(size_t(kH - 1 - sy) * kW + size_t(sx)) * 4];
                ASSERT_EQ(p[0], 255) << "triangle " << t << ": screen pixel " << sx << "," << sy << " (map " << mx
                                     << "," << my << ") is covered in the map, not drawn by the GPU";
            }
    }
    EXPECT_GT(checked, 200000u);
}
