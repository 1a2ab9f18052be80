// The accuracy harness on `city` and on random graphs: every conservative strategy draws exactly the
// pixels of the unculled render on every view; the approximate ones report their error.
#include "accuracy/Accuracy.h"
#include "nodes/Transform.h"
#include "scenes/City.h"
#include "scenes/RandomScene.h"

#include <gtest/gtest.h>

#include <cstdio>

using namespace sg;

namespace {
constexpr int kW = 256, kH = 144, kViews = 200;

std::vector<CullSettings> strategies() {
    std::vector<CullSettings> s;
    for (auto st : {CullStrategy::Sphere, CullStrategy::Aabb, CullStrategy::SphereSphere, CullStrategy::CenterBox}) {
        CullSettings c;
        c.strategy = st;
        s.push_back(c);
    }
    CullSettings sf;
    sf.smallFeaturePixels = 2.0;
    s.push_back(sf);
    return s;
}

void check(const std::vector<accuracy::Result>& results, const char* scene) {
    for (const auto& r : results) {
        std::printf("[ accuracy ] %-8s %-22s views %d  differing pixels total %llu  max %llu  views with error %d  (%.4f%% of frames)\n",
                    scene, r.name.c_str(), r.views, (unsigned long long)r.differingTotal, (unsigned long long)r.differingMax,
                    r.viewsWithError, r.percentOfFrames());
        EXPECT_EQ(r.views, kViews);
        const bool conservative = r.name == "sphere" || r.name == "aabb" || r.name == "sphere-sphere";
        if (conservative) EXPECT_EQ(r.differingTotal, 0u) << r.name << " on " << scene << ": worst view " << r.worstView;
    }
    // centre-box drops partly visible objects: that must show (if it did not, the harness would be blind).
    EXPECT_GT(results[3].differingTotal, 0u) << "center-box showed no error on " << scene;
}
}  // namespace

TEST(Accuracy, CityConservativeStrategiesAreExact) {
    const int n = 12;
    Scene s(scenes::buildCity({n, false}));
    s.update();
    accuracy::Harness h(kW, kH);
    check(h.run(s, accuracy::cityViews(n, kViews, 2024, kW, kH), strategies()), "city");
}

TEST(Accuracy, RandomGraphConservativeStrategiesAreExact) {
    scenes::RandomSceneOptions o;
    o.objects = 80;
    Scene s(scenes::buildRandomScene(99, o));
    s.update();
    accuracy::Harness h(kW, kH);
    check(h.run(s, accuracy::boxViews(Box{dvec3(-70), dvec3(70)}, kViews, 7, kW, kH), strategies()), "random");
}

TEST(Accuracy, FarFromTheOriginConservativeStrategiesAreExact) {
    // The city 10,000 km from the origin, seen from the same relative views.
    const int n = 8;
    const dvec3 off(1e7, -1e7, 0);
    auto top = make<Transform>(glm::translate(dmat4(1.0), off));
    top->addChild(scenes::buildCity({n, false}));
    Scene s(top);
    s.update();
    std::vector<Camera> views = accuracy::cityViews(n, 40, 5, kW, kH);
    for (Camera& c : views) c.setView(c.view() * glm::translate(dmat4(1.0), -off));
    accuracy::Harness h(kW, kH);
    for (const auto& r : h.run(s, views, {CullSettings{}})) EXPECT_EQ(r.differingTotal, 0u) << "worst view " << r.worstView;
}

TEST(Accuracy, HarnessSeesWhatACullDrops) {
    // Negative control: small-feature culling with a huge threshold drops every object in view; the
    // harness must count those pixels, and count none for the strategy the reference uses itself.
    Scene s(scenes::buildCity({8, false}));
    s.update();
    accuracy::Harness h(kW, kH);
    const Camera cam = scenes::cityOrbitCamera(8, 10, kW, kH);
    CullSettings dropAll;
    dropAll.smallFeaturePixels = 1e9;
    Image ref, got;
    const uint64_t d = h.compare(s, cam, dropAll, &ref, &got);
    EXPECT_GT(d, uint64_t(kW * kH / 20));
    EXPECT_EQ(d, countDifferingPixels(ref, got));
    CullSettings none;
    none.strategy = CullStrategy::None;
    EXPECT_EQ(h.compare(s, cam, none), 0u);
}
