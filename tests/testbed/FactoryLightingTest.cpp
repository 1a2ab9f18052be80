// Factory lighting: the workshop's shadow falls north-east, away from the south-western sun, and the second
// start reads the same colours from the cache.
#include "nodes/Geometry.h"
#include "testbed/FactoryLighting.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

using namespace sg;

namespace {
// Level `level` of terrain tile `t`.
Geometry& tileLevel(const scenes::Factory& f, size_t t, size_t level) {
    return static_cast<Geometry&>(*f.terrain->child(t)->child(level));
}

// Baked sun visibility (vertex alpha) of the terrain vertex nearest (x, y), and its colour over albedo
// (green channel): the ambient occlusion.
struct Baked {
    float sun = 0.0f, ao = 0.0f;
};
Baked lightAt(const scenes::Factory& lit, const scenes::Factory& plain, double x, double y) {
    float best = 1e30f;
    Baked out;
    for (size_t i = 0; i < lit.terrain->numChildren(); ++i) {
        const Mesh& m = *tileLevel(lit, i, 0).mesh();
        const Mesh& a = *tileLevel(plain, i, 0).mesh();
        for (size_t v = 0; v < m.positions().size(); ++v) {
            const float d = glm::length(vec2(m.positions()[v]) - vec2(float(x), float(y)));
            if (d < best) {
                best = d;
                out = {m.colors()[v].a, m.colors()[v].g / a.colors()[v].g};
            }
        }
    }
    return out;
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
    const Baked shadow = lightAt(f, plain, -100.0, 94.0), westSide = lightAt(f, plain, -152.0, 75.0);
    EXPECT_LT(shadow.sun, 0.3f);
    EXPECT_GT(westSide.sun, 0.9f);
    // Open ground far from the buildings sees the whole sky; ground at a wall's foot does not.
    EXPECT_GT(lightAt(f, plain, -160.0, -60.0).ao, 0.95f);
    EXPECT_LT(westSide.ao, 0.9f);
    // Baked geometries tell the renderer how to read their colours; their textures and highlights stay.
    const Material& ground = *tileLevel(f, 0, 0).material();
    EXPECT_TRUE(ground.bakedLight);
    EXPECT_NE(ground.texture, nullptr);
    // Every level of every tile reads its colours as baked light, and the coarse levels carry the finest's: the
    // same colour on the tile's border (where every level has the finest's vertices), some shade inside.
    bool coarseShaded = false;
    for (size_t i = 0; i < f.terrain->numChildren(); ++i) {
        const Mesh& fine = *tileLevel(f, i, 0).mesh();
        const Box box = fine.box();
        for (size_t level = 0; level < f.terrain->child(i)->numChildren(); ++level) {
            EXPECT_TRUE(tileLevel(f, i, level).material()->bakedLight);
            if (level == 0) continue;
            const Mesh& coarse = *tileLevel(f, i, level).mesh();
            coarseShaded |= coarse.colors() != tileLevel(plain, i, level).mesh()->colors();
            for (size_t v = 0; v < coarse.positions().size(); ++v) {
                const vec3 p = coarse.positions()[v];
                if (p.x != box.min.x && p.x != box.max.x && p.y != box.min.y && p.y != box.max.y) continue;
                const auto& fp = fine.positions();
                const size_t k = size_t(std::find(fp.begin(), fp.end(), p) - fp.begin());
                ASSERT_LT(k, fp.size()) << "tile " << i << " level " << level << ": a border vertex the finest lacks";
                EXPECT_EQ(coarse.colors()[v], fine.colors()[k]) << "tile " << i << " level " << level;
            }
        }
    }
    EXPECT_TRUE(coarseShaded);
    EXPECT_TRUE(f.buildings[0].roof->material()->bakedLight);
    EXPECT_GT(f.buildings[0].roof->material()->specular, 0.0f);
    EXPECT_EQ(f.buildings[0].roof->material(), f.buildings[10].roof->material());

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

TEST(FactoryLighting, TheRunTimeLightIsTheBakedSunOutsideAndTheRoofLightInside) {
    const DirectionalLight sun = scenes::factoryLight(-1);
    EXPECT_FALSE(sun.headlight);
    const vec3 baked = glm::normalize(vec3(scenes::factoryLightParams().sunDirection));
    EXPECT_GT(glm::dot(glm::normalize(sun.direction), baked), 0.9999f);  // the shadows and the shading agree
    EXPECT_GT(sun.color.r, sun.color.b);                                 // warm sun over a bluish sky
    EXPECT_LT(sun.ambient.r, sun.ambient.b);
    const DirectionalLight inside = scenes::factoryLight(0);
    EXPECT_FALSE(inside.headlight);
    EXPECT_GT(glm::normalize(inside.direction).z, 0.8f);  // from the roof glazing above
    EXPECT_GT(inside.direction.y, 0.0f);                  // which faces north
}
