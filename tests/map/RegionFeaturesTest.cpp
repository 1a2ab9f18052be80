// The map's regions as features (map/RegionFeatures.h) on the generated map: each region's node is bound to its
// row of class `region`, a pick names it, and in a level entered, the region around it too.
#include "map/MapTestData.h"
#include "sg/intersect/HitFeatures.h"

using namespace sgmap;
using namespace maptest;

namespace {

std::string text(const sg::PropertyList& props, const std::string& id) {
    for (const auto& p : props)
        if (p.first == id) return p.second.toString();
    return "(absent)";
}

double number(const sg::PropertyList& props, const std::string& id) {
    for (const auto& p : props)
        if (p.first == id) return p.second.asNumber();
    return -1.0;
}

// The features of the pick straight down at the scene point `p`, as Atlas::pickGeo makes it.
sg::HitFeatures pickedAt(Atlas& atlas, const sg::dvec3& p) {
    sg::QueryOptions o;
    o.lod = sg::LodChoice::Highest;
    sg::Hit h;
    EXPECT_GE(atlas.pick(sg::Ray{sg::dvec3(p.x, p.y, 1000.0), sg::dvec3(0, 0, -1), 2000.0}, o, &h), 0);
    return sg::featuresAt(h);
}

}  // namespace

TEST(RegionFeatures, EveryRegionIsItsRowWithNameCodeKindAndArea) {
    Atlas atlas(generatedDir());
    const Level& l = atlas.level();
    ASSERT_TRUE(l.features);
    const sg::PropertyStore& store = *l.features->store;
    const int t = l.features->sets[0].propertyTable;
    EXPECT_EQ(store.schema.classes[0].id, "region");
    EXPECT_EQ(store.tables()[size_t(t)].count, l.regions.size());
    for (size_t i = 0; i < l.regions.size(); ++i) {
        const Region& r = l.regions[i];
        EXPECT_EQ(r.node->features(), l.features.get());
        EXPECT_EQ(r.node->featureIndex(), i);
        EXPECT_EQ(store.value(t, i, 0).string, r.name);
        EXPECT_EQ(store.value(t, i, 1).string, r.id);
        EXPECT_EQ(store.value(t, i, 2).string, r.kind);
        EXPECT_EQ(store.value(t, i, 3).asNumber(), r.areaKm2);
    }
}

TEST(RegionFeatures, APickNamesTheRegionAndInsideALevelTheOneAroundIt) {
    Atlas atlas(generatedDir());
    uint64_t frame = 0;
    const size_t us = size_t(atlas.level().findId("840"));
    const Region country = atlas.level().regions[us];
    const sg::HitFeatures world = pickedAt(atlas, insidePoint(atlas, us));
    ASSERT_EQ(world.features.size(), 1u);
    EXPECT_EQ(world.features[0].classId, "region");
    EXPECT_EQ(world.features[0].featureId, int64_t(us));
    EXPECT_EQ(text(world.features[0].properties, "code"), "840");
    EXPECT_EQ(text(world.features[0].properties, "name"), country.name);
    EXPECT_EQ(number(world.features[0].properties, "area"), country.areaKm2);

    ASSERT_TRUE(enterId(atlas, "840", frame));
    const size_t s = 1;
    const Region state = atlas.level().regions[s];
    const sg::HitFeatures inside = pickedAt(atlas, insidePoint(atlas, s));
    ASSERT_EQ(inside.features.size(), 2u);  // innermost first: the state, then the country it details
    EXPECT_EQ(inside.features[0].featureId, int64_t(s));
    EXPECT_EQ(text(inside.features[0].properties, "code"), state.id);
    EXPECT_EQ(text(inside.features[0].properties, "kind"), "state");
    EXPECT_EQ(text(inside.features[1].properties, "code"), "840");
}
