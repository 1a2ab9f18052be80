// Picking points against an id-buffer render: points drawn as 5-pixel squares, each in its own flat colour (unlit),
// in four layers at different depths; every pixel whose 5 x 5 neighbourhood shows one point (the centre pixel of a
// point seen whole), picked through pixelRay() with pickCone(camera, 3.5), picks that point.
//
// Why it must agree: a point nearer than the one shown and within the cone would cover one of those 25 pixels (a
// 5-pixel square within 4.5 pixels of the centre does), so none is there. The cone of 3.5 pixels at the image's
// centre spans at most 3.5 / cos^2 of the angle off the axis, 4.0 pixels in this 30-degree view's corners: within
// the 4.5. Points of one layer stand at least 6 pixels apart (no ties in depth), and the layers 2 units apart,
// far more than the ray's slant across a cone changes the order along it.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/PointShading.h"
#include "sg/gl/Renderer.h"
#include "sg/intersect/IntersectTraversal.h"
#include "sg/intersect/PickCone.h"
#include "sg/intersect/PickSet.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

using namespace sg;

namespace {
constexpr int kSize = 256, kLayers = 4;
constexpr double kFovy = 30.0, kGridPixels = 8.0, kJitterPixels = 1.0;

vec4 idColor(uint32_t id) {
    return vec4(float(id & 255) / 255.0f, float((id >> 8) & 255) / 255.0f, float((id >> 16) & 255) / 255.0f, 1.0f);
}

// Layers of points on jittered grids facing the camera (looking down -z from the origin), each shifted at random;
// point k has the id k + 1.
ref_ptr<Geometry> pointLayers() {
    std::mt19937_64 g(21);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<vec3> p;
    std::vector<vec4> colors;
    const double tanHalf = std::tan(glm::radians(kFovy / 2.0));
    for (int l = 0; l < kLayers; ++l) {
        const double z = 10.0 + 2.0 * l, pixel = 2.0 * tanHalf * z / kSize, step = kGridPixels * pixel;
        const double half = tanHalf * z, shiftX = step * 0.5 * (u(g) + 1.0), shiftY = step * 0.5 * (u(g) + 1.0);
        for (double y = -half - step + shiftY; y < half + step; y += step)
            for (double x = -half - step + shiftX; x < half + step; x += step) {
                p.emplace_back(float(x + kJitterPixels * pixel * u(g)), float(y + kJitterPixels * pixel * u(g)),
                               float(-z));
                colors.push_back(idColor(uint32_t(p.size())));
            }
    }
    auto mesh = make<Mesh>();
    mesh->setPoints(std::move(p), std::move(colors));
    auto material = make<Material>(vec4(1.0f));
    material->unlit = true;
    return make<Geometry>(mesh, material);
}
}  // namespace

TEST(PointPickAccuracy, EveryPointSeenWholeIsPicked) {
    auto geometry = pointLayers();
    auto root = make<Group>();
    root->addChild(geometry);
    Scene scene(root);
    scene.update();
    Camera cam;
    cam.setLookAt(dvec3(0.0), dvec3(0, 0, -1), dvec3(0, 1, 0));
    cam.setPerspective(kFovy, 1.0, 1.0, 100.0);
    cam.setViewport(kSize, kSize);

    OsmesaContext ctx(kSize, kSize);
    Renderer renderer;
    PointShading shading;
    shading.pointSize = 5.0f;
    renderer.setPointShading(shading);
    CullTraversal cull;
    CullSettings settings;
    settings.occlusion.mode = OcclusionMode::Off;
    DrawList list;
    CullStats stats;
    cull.cull(scene, cam, settings, list, stats);
    renderer.draw(list, cam, vec4(0.0f, 0.0f, 0.0f, 1.0f));
    const Image img = renderer.readColor();
    ASSERT_EQ(img.width, kSize);
    ASSERT_EQ(img.height, kSize);
    auto id = [&](int x, int y) {
        const size_t p = 4 * (size_t(y) * size_t(kSize) + size_t(x));
        return uint32_t(img.rgba[p]) | uint32_t(img.rgba[p + 1]) << 8 | uint32_t(img.rgba[p + 2]) << 16;
    };

    const PickCone pc = pickCone(cam, 3.5);
    QueryOptions opt;
    opt.camera = &cam;
    opt.lod = LodChoice::AsDrawn;
    opt.coneWidth = pc.coneWidth;
    opt.coneSlope = pc.coneSlope;
    IntersectTraversal it;
    uint64_t compared = 0, agreed = 0;
    std::string firstMismatch;
    // Every pixel qualifies or not by the picture alone: all those that do are picked (a superset of any random
    // sample of them).
    for (int y = 2; y < kSize - 2; ++y)
        for (int x = 2; x < kSize - 2; ++x) {
            const uint32_t drawn = id(x, y);
            bool whole = drawn != 0;
            for (int dy = -2; dy <= 2 && whole; ++dy)
                for (int dx = -2; dx <= 2 && whole; ++dx) whole = id(x + dx, y + dy) == drawn;
            if (!whole) continue;
            ++compared;
            Hit h;
            uint32_t picked = 0;
            if (it.intersect(scene, pixelRay(cam, x + 0.5, y + 0.5), opt, h))
                picked = h.geometry == geometry.get() ? h.primitive + 1 : ~0u;
            if (picked == drawn)
                ++agreed;
            else if (firstMismatch.empty())
                firstMismatch = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") drawn " +
                                std::to_string(drawn) + " picked " + std::to_string(picked);
        }
    std::printf("[ pick ] points: %llu pixels showing a whole point, %llu picked right\n", (unsigned long long)compared,
                (unsigned long long)agreed);
    // Not vacuous: the front layer alone has about (256 / 8)^2 = 1024 points, most of them seen whole.
    EXPECT_GT(compared, 500u);
    EXPECT_EQ(agreed, compared) << "first mismatch: " << firstMismatch;
}
