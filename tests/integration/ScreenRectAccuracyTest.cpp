// The screen-rectangle rejection (CullSettings::screenRect) on the PCVR city: with a conservative object test it
// draws exactly the unculled render's pixels, on the drive path and on awkward views (inside objects, the near
// plane cutting them, very wide and narrow fields of view); after center-box it adds no error of its own.
#include "testbed/Accuracy.h"
#include "testbed/PcvrCity.h"

#include <gtest/gtest.h>

#include <cstdio>

using namespace sg;

namespace {
constexpr int kW = 256, kH = 192;

CullSettings with(CullStrategy s, bool rect, uint32_t k = 32) {
    CullSettings c;
    c.strategy = s;
    c.occlusion.mode = OcclusionMode::Off;
    c.screenRect = rect;
    c.screenRectTriangles = k;
    return c;
}
}  // namespace

TEST(ScreenRectAccuracy, ConservativeOnThePcvrCityAndNoErrorOfItsOwnAfterCenterBox) {
    Scene scene(scenes::buildPcvrCity(3));
    scene.update();
    std::vector<Camera> views;
    for (int f = 0; f < scenes::kPcvrFrames; f += 20) views.push_back(scenes::pcvrCityCamera(f, kW, kH));
    for (const Camera& c : accuracy::boxViews(Box{dvec3(0, 0, 0), dvec3(400, 400, 60)}, 16, 5, kW, kH))
        views.push_back(c);
    accuracy::Harness h(kW, kH);
    const std::vector<CullSettings> settings = {
        with(CullStrategy::Aabb, true, 32), with(CullStrategy::Aabb, true, 1), with(CullStrategy::Sphere, true, 64),
        with(CullStrategy::CenterBox, false), with(CullStrategy::CenterBox, true, 32)};
    const auto results = h.run(scene, views, settings);
    for (size_t k = 0; k < results.size(); ++k) {
        const accuracy::Result& r = results[k];
        std::printf("[ accuracy ] pcvr-city %-30s K %-3u views %d differing pixels %llu, triangles %llu of %llu\n",
                    r.name.c_str(), settings[k].screenRectTriangles, r.views, (unsigned long long)r.differingTotal,
                    (unsigned long long)r.trianglesTotal, (unsigned long long)r.referenceTrianglesTotal);
    }
    for (size_t k = 0; k < 3; ++k)
        EXPECT_EQ(results[k].differingTotal, 0u) << results[k].name << " worst view " << results[k].worstView;
    // Not vacuous: the rejection drew fewer triangles than the object test alone would.
    EXPECT_LT(results[1].trianglesTotal, results[0].trianglesTotal);
    EXPECT_LT(results[4].trianglesTotal, results[3].trianglesTotal);
    // After center-box, view by view the same error as center-box alone (the rejection loses no pixel).
    EXPECT_EQ(results[3].perView, results[4].perView);
    EXPECT_GT(results[3].differingTotal, 0u) << "center-box showed no error: the harness would be blind";
}
