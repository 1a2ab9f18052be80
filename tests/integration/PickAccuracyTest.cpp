// Picking against an id-buffer render: 10,000 random pixels over `city` and over a random graph (LODs,
// switches, billboards, instances, rotated and scaled transforms), each also 10,000 km from the origin;
// away from the edges between ids, the picked geometry is the one drawn at the pixel, every time.
#include "nodes/Transform.h"
#include "testbed/Accuracy.h"
#include "testbed/City.h"
#include "testbed/PickAccuracy.h"
#include "testbed/RandomScene.h"

#include <gtest/gtest.h>

#include <cstdio>

using namespace sg;

namespace {
constexpr int kW = 320, kH = 180, kViews = 50, kPixelsPerView = 200;  // 10,000 pixels per scene
const dvec3 kFar(1e7, -4e6, 3e5);

void check(const accuracy::PickAgreement& r, const char* name) {
    std::printf(
        "[ pick ] %-14s sampled %llu, compared %llu (off id edges), objects %llu, agreed %llu (%.4f%%), coplanar ties "
        "%llu\n",
        name, (unsigned long long)r.sampled, (unsigned long long)r.compared, (unsigned long long)r.objectPixels,
        (unsigned long long)r.agreed, 100.0 * r.rate(), (unsigned long long)r.coplanarTies);
    EXPECT_EQ(r.sampled, uint64_t(kViews) * kPixelsPerView);
    EXPECT_EQ(r.agreed, r.compared) << name << ": first mismatch " << r.firstMismatch;
    // Not vacuous: most pixels are compared, and many of them show objects.
    EXPECT_GT(r.compared, r.sampled / 2);
    EXPECT_GT(r.objectPixels, r.sampled / 4);
}

// Views moved with the scene: the same pictures 10,000 km out.
std::vector<Camera> shifted(std::vector<Camera> views, const dvec3& offset) {
    for (auto& c : views) c.setView(c.view() * glm::translate(dmat4(1.0), -offset));
    return views;
}

void cityCase(const dvec3& offset, const char* name) {
    auto root = make<Transform>(glm::translate(dmat4(1.0), offset));
    root->addChild(scenes::buildCity({16, false}));
    const accuracy::IdMap ids = accuracy::assignIdColors(root.get());
    Scene scene(root);
    scene.update();
    accuracy::PickHarness h(kW, kH);
    check(h.run(scene, ids, shifted(accuracy::cityViews(16, kViews, 7, kW, kH), offset), kPixelsPerView, 11), name);
}

void randomCase(const dvec3& offset, const char* name) {
    scenes::RandomSceneOptions o;
    o.offset = offset;
    o.objects = 400;  // dense enough that a quarter of the pixels show objects
    o.spread = 40.0;
    auto root = scenes::buildRandomScene(5, o);
    const accuracy::IdMap ids = accuracy::assignIdColors(root.get());
    Scene scene(root);
    scene.update();
    const Box b = scene.image().box(0);
    accuracy::PickHarness h(kW, kH);
    check(h.run(scene, ids, accuracy::boxViews(b, kViews, 13, kW, kH), kPixelsPerView, 17), name);
}
}  // namespace

TEST(PickAccuracy, City) { cityCase(dvec3(0.0), "city"); }
TEST(PickAccuracy, CityFarFromOrigin) { cityCase(kFar, "city far"); }
TEST(PickAccuracy, RandomScene) { randomCase(dvec3(0.0), "random"); }
TEST(PickAccuracy, RandomSceneFarFromOrigin) { randomCase(kFar, "random far"); }
