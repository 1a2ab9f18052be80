// The city's buildings as features (CityOptions::features): a pick on a building names it and its properties;
// cars are no feature; without the option the graph carries none.
#include "sg/intersect/HitFeatures.h"
#include "sg/intersect/IntersectTraversal.h"
#include "testbed/City.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {

const PropertyValue* find(const PropertyList& props, const std::string& id) {
    for (const auto& p : props)
        if (p.first == id) return &p.second;
    return nullptr;
}

// The nearest hit of a ray straight down at (x, y) from 100 m up.
Hit pickDown(const Scene& scene, double x, double y) {
    IntersectTraversal it;
    Hit h;
    EXPECT_TRUE(it.intersect(scene, Ray{dvec3(x, y, 100.0), dvec3(0, 0, -1)}, {}, h));
    return h;
}

uint64_t nodesBelow(const Node& n) {
    uint64_t count = 1;
    for (size_t i = 0; i < n.numChildren(); ++i) count += nodesBelow(*n.child(i));
    return count;
}

}  // namespace

TEST(CityFeatures, APickOnABuildingNamesItsIdHeightFloorsAndUse) {
    const int n = 4;
    Scene scene(scenes::buildCity({n, false, true}));
    scene.update();
    // Building (2, 3): footprint centred at (50, 70); its roof is the nearest hit from above.
    const Hit h = pickDown(scene, 50.0, 70.0);
    EXPECT_NEAR(h.point.z, double(scenes::cityHeight(2, 3)), 1e-9);
    const HitFeatures f = featuresAt(h);
    ASSERT_EQ(f.features.size(), 1u);
    const FeatureAtHit& b = f.features[0];
    EXPECT_TRUE(b.instance);
    EXPECT_EQ(b.classId, "building");
    EXPECT_EQ(b.featureId, 2 * n + 3);
    const scenes::CityBuilding want = scenes::cityBuilding(n, 2, 3);
    EXPECT_EQ(want.id, 11u);
    ASSERT_NE(find(b.properties, "id"), nullptr);
    EXPECT_EQ(find(b.properties, "id")->asNumber(), 11.0);
    ASSERT_NE(find(b.properties, "height"), nullptr);
    EXPECT_EQ(find(b.properties, "height")->asNumber(), double(scenes::cityHeight(2, 3)));
    ASSERT_NE(find(b.properties, "floors"), nullptr);
    EXPECT_EQ(find(b.properties, "floors")->asNumber(), double(scenes::cityHeight(2, 3) / 3));
    ASSERT_NE(find(b.properties, "use"), nullptr);
    EXPECT_EQ(find(b.properties, "use")->string, want.use);
}

TEST(CityFeatures, EveryBuildingIsItsOwnRowAndCarsAreNoFeature) {
    const int n = 3;
    Scene scene(scenes::buildCity({n, false, true}));
    scene.update();
    for (uint32_t i = 0; i < uint32_t(n); ++i)
        for (uint32_t j = 0; j < uint32_t(n); ++j) {
            const HitFeatures f = featuresAt(pickDown(scene, 20.0 * i + 10, 20.0 * j + 10));
            ASSERT_EQ(f.features.size(), 1u);
            EXPECT_EQ(f.features[0].featureId, int64_t(i * n + j));
            ASSERT_NE(find(f.features[0].properties, "height"), nullptr);
            EXPECT_EQ(find(f.features[0].properties, "height")->asNumber(), double(scenes::cityHeight(i, j)));
        }
    // The car of cell (1, 1): a 4 x 2 m box at (21, 21), outside the building's footprint.
    const Hit car = pickDown(scene, 23.0, 22.0);
    EXPECT_NEAR(car.point.z, 1.5, 1e-9);
    EXPECT_TRUE(featuresAt(car).empty());
}

TEST(CityFeatures, OffByDefaultAndTheOptionAddsNoNode) {
    Scene scene(scenes::buildCity({3, false}));
    scene.update();
    EXPECT_TRUE(featuresAt(pickDown(scene, 30.0, 30.0)).empty());
    EXPECT_EQ(nodesBelow(*scenes::buildCity({3, false, true})), scenes::cityNodeCount(3));
}

TEST(CityFeatures, UsesAreTheFourNamesAndFloorsAStoreyEveryThreeMetres) {
    for (uint32_t i = 0; i < 10; ++i)
        for (uint32_t j = 0; j < 10; ++j) {
            const scenes::CityBuilding b = scenes::cityBuilding(10, i, j);
            EXPECT_EQ(b.id, i * 10 + j);
            EXPECT_EQ(b.height, double(scenes::cityHeight(i, j)));
            EXPECT_EQ(b.floors, scenes::cityHeight(i, j) / 3);
            bool named = false;
            for (const char* u : scenes::kCityUses) named = named || std::string(u) == b.use;
            EXPECT_TRUE(named) << b.use;
        }
}
