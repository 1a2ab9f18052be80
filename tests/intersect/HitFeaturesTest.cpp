// featuresAt: what a hit reads of the hit mesh's features (the nearest corner's id, the nearest texel's, a property
// texture and a property attribute evaluated there) and of the feature nodes on its path, innermost first.
#include "nodes/Geometry.h"
#include "nodes/Transform.h"
#include "sg/intersect/HitFeatures.h"

#include <gtest/gtest.h>

#include <cstring>

using namespace sg;

namespace {

// One quad of two triangles over [0, 1]^2, UVs equal to xy; vertex k's id is 10 + k.
struct Fixture {
    ref_ptr<PropertyStore> store = make<PropertyStore>();
    ref_ptr<Mesh> mesh = make<Mesh>();
    ref_ptr<Geometry> geometry;
    Fixture() {
        mesh->set({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {}, {0, 1, 2, 0, 2, 3},
                  {{0, 0}, {1, 0}, {1, 1}, {0, 1}});
        // A class `cell` of two properties: temperature (UINT8, a property texture's channel G, scaled by 0.5) and
        // pressure (FLOAT32, a property attribute).
        ClassDef cls;
        cls.id = "cell";
        ClassProperty t;
        t.id = "temperature";
        t.componentType = ComponentType::UInt8;
        t.scale = PropertyValue::ofNumber(0.5);
        t.normalized = false;
        ClassProperty p;
        p.id = "pressure";
        p.componentType = ComponentType::Float32;
        cls.properties = {t, p};
        store->schema.classes.push_back(cls);
        // 2 x 2 texels, G = 10, 20 (top row), 30, 40.
        std::vector<uint8_t> rgba(16, 0);
        for (int k = 0; k < 4; ++k) rgba[size_t(k) * 4 + 1] = uint8_t(10 * (k + 1));
        PropertyTextureDef tex;
        tex.name = "heat";
        tex.classIndex = 0;
        PropertyTextureDef::Property heat;
        heat.property = 0;
        heat.texture = make<Texture>(2, 2, rgba);
        heat.channels.assign(1, 1);  // G
        tex.properties.push_back(heat);
        store->propertyTextures.push_back(tex);
        PropertyAttributeDef attr;
        attr.name = "air";
        attr.classIndex = 0;
        attr.properties.push_back({1, "_PRESSURE", {}});
        store->propertyAttributes.push_back(attr);

        auto f = make<MeshFeatures>();
        FeatureIdSet ids;
        ids.featureCount = 20;
        ids.ids = {10, 11, 12, 13};
        f->sets.push_back(ids);
        f->store = store;
        f->propertyTextures = {0};
        PropertyAttributeValues values;
        values.propertyAttribute = 0;
        values.columns.resize(1);
        values.columns[0].stride = 4;
        const float pressure[4] = {100.5f, 101.5f, 102.5f, 103.5f};
        values.columns[0].bytes.resize(sizeof pressure);
        std::memcpy(values.columns[0].bytes.data(), pressure, sizeof pressure);
        f->propertyAttributes.push_back(values);
        mesh->setFeatures(f);
        geometry = make<Geometry>(mesh, make<Material>());
    }
    // A hit on triangle `tri` at barycentrics (u, v).
    Hit hit(uint32_t tri, double u, double v) const {
        Hit h;
        h.geometry = geometry.get();
        h.primitive = tri;
        h.u = u, h.v = v;
        h.path = {geometry.get()};
        return h;
    }
};

const PropertyValue& only(const std::vector<PropertiesAtHit>& list) {
    EXPECT_EQ(list.size(), 1u);
    EXPECT_EQ(list[0].properties.size(), 1u);
    return list[0].properties[0].second;
}

}  // namespace

TEST(HitFeatures, TheNearestCornersIdTheNearestTexelAndTheNearestVertexsAttribute) {
    const Fixture fx;
    // Triangle 0 is corners 0, 1, 2; near corner 1 at (1, 0): u = 0.8.
    const HitFeatures near1 = featuresAt(fx.hit(0, 0.8, 0.1));
    ASSERT_EQ(near1.features.size(), 1u);
    EXPECT_EQ(near1.features[0].featureId, 11);
    EXPECT_FALSE(near1.features[0].instance);
    // UV (0.9, 0.1): texel (1, 0), the top row's second: G = 20, scaled by 0.5.
    EXPECT_EQ(only(near1.propertyTextures).number, 10.0);
    EXPECT_EQ(near1.propertyTextures[0].classId, "cell");
    EXPECT_EQ(only(near1.propertyAttributes).number, 101.5);
    // Triangle 1 is corners 0, 2, 3; near corner 3 at (0, 1): v = 0.9. UV (0.05, 0.95): texel (0, 1), G = 30.
    const HitFeatures near3 = featuresAt(fx.hit(1, 0.05, 0.9));
    EXPECT_EQ(near3.features[0].featureId, 13);
    EXPECT_EQ(only(near3.propertyTextures).number, 15.0);
    EXPECT_EQ(only(near3.propertyAttributes).number, 103.5);
    // A hit naming no triangle of the mesh reads nothing of it.
    EXPECT_TRUE(featuresAt(fx.hit(7, 0.1, 0.1)).empty());
}

TEST(HitFeatures, FeatureNodesOnThePathFollowTheMeshsSetsInnermostFirst) {
    const Fixture fx;
    auto outer = make<Transform>(), inner = make<Transform>();
    auto sets = make<MeshFeatures>();
    FeatureIdSet s;
    s.source = FeatureIdSet::Source::Instance;
    s.ids = {7, 8, 9};
    s.label = "parts";
    sets->sets.push_back(s);
    outer->setFeatures(sets, 0);
    inner->setFeatures(sets, 2);
    Hit h = fx.hit(0, 0.1, 0.1);
    h.path = {outer.get(), inner.get(), fx.geometry.get()};
    const HitFeatures f = featuresAt(h);
    ASSERT_EQ(f.features.size(), 3u);
    EXPECT_EQ(f.features[0].featureId, 10);  // the mesh's: corner 0
    EXPECT_TRUE(f.features[1].instance);
    EXPECT_EQ(f.features[1].featureId, 9);  // inner: ids[2]
    EXPECT_EQ(f.features[1].label, "parts");
    EXPECT_EQ(f.features[2].featureId, 7);          // outer: ids[0]
    EXPECT_TRUE(f.features[1].properties.empty());  // no table
}
