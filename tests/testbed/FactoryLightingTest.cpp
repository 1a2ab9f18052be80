// Factory lighting: the workshop's shadow falls north-east, away from the south-western sun, and the second
// start reads the same colours from the cache.
#include "nodes/Geometry.h"
#include "testbed/FactoryLighting.h"

#include <gtest/gtest.h>

#include <filesystem>

using namespace sg;

namespace {
// Level `level` of terrain tile `t`.
Geometry& tileLevel(const scenes::Factory& f, size_t t, size_t level) {
    return static_cast<Geometry&>(*f.terrain->child(t)->child(level));
}

// Colour over albedo (green channel) of the terrain vertex nearest (x, y), on the tiles' finest level.
float lightAt(const scenes::Factory& lit, const scenes::Factory& plain, double x, double y) {
    float best = 1e30f, ratio = 0.0f;
    for (size_t i = 0; i < lit.terrain->numChildren(); ++i) {
        const Mesh& m = *tileLevel(lit, i, 0).mesh();
        const Mesh& a = *tileLevel(plain, i, 0).mesh();
        for (size_t v = 0; v < m.positions().size(); ++v) {
            const float d = glm::length(vec2(m.positions()[v]) - vec2(float(x), float(y)));
            if (d < best) {
                best = d;
                ratio = m.colors()[v].g / a.colors()[v].g;
            }
        }
    }
    return ratio;
}
}  // namespace

TEST(FactoryLighting, ShadowsFallAwayFromTheSunAndTheCacheRestoresThem) {
    const auto dir = (std::filesystem::temp_directory_path() / "sgkit-factory-light").string();
    std::filesystem::remove_all(dir);
    const scenes::Factory plain = scenes::buildFactory();
    scenes::Factory f = scenes::buildFactory();
    const scenes::FactoryLightingStats first = scenes::bakeFactoryLighting(f, dir);
    EXPECT_FALSE(first.cached);
    EXPECT_GT(first.vertices, 100000u);
    // Workshop 0 spans x -145..-85, y 60..90, 10 m high: its shadow reaches 8.4 m north-east of it.
    const float shadow = lightAt(f, plain, -100.0, 94.0), westSide = lightAt(f, plain, -152.0, 75.0);
    EXPECT_LT(shadow, westSide - 0.2f) << shadow << " vs " << westSide;
    // Geometries that were lit draw unlit: the colours carry the light.
    // Every level of every tile is lit, the coarse ones too: not left in their albedo.
    for (size_t i = 0; i < f.terrain->numChildren(); ++i)
        for (size_t level = 0; level < f.terrain->child(i)->numChildren(); ++level) {
            EXPECT_TRUE(tileLevel(f, i, level).material()->unlit);
            EXPECT_NE(tileLevel(f, i, level).mesh()->colors(), tileLevel(plain, i, level).mesh()->colors()) << i;
        }

    scenes::Factory again = scenes::buildFactory();
    const scenes::FactoryLightingStats second = scenes::bakeFactoryLighting(again, dir);
    EXPECT_TRUE(second.cached);
    EXPECT_LT(second.ms, 2000.0);
    for (size_t i = 0; i < f.terrain->numChildren(); ++i)
        for (size_t level = 0; level < f.terrain->child(i)->numChildren(); ++level)
            EXPECT_EQ(tileLevel(f, i, level).mesh()->colors(), tileLevel(again, i, level).mesh()->colors());
    EXPECT_EQ(static_cast<Geometry*>(f.buildings[9].lod->child(1))->mesh()->colors(),
              static_cast<Geometry*>(again.buildings[9].lod->child(1))->mesh()->colors());
    std::filesystem::remove_all(dir);
}
