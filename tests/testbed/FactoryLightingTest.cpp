// Factory lighting: the workshop's shadow falls north-east, away from the south-western sun, the coarse levels
// carry the finest's light, and the second start reads the same colours from the cache.
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

// The colour of one outer wall of a building model (side 0-3: facing -x, +x, -y, +y) averaged over its surface
// (each triangle its vertices' mean, weighted by its area): the triangles that face that way within 0.4 m of the
// walls' plane (`box`: the building's in the model's frame). The slab, the parapets' insides and other faces the roof
// or the walls hide are left out: levels keep different shares of them. Alpha -1 when the side has under 10 m2 of such
// triangles.
vec4 outerWallColor(const Mesh& m, const Box& box, int side) {
    dvec4 sum(0.0);
    double area = 0.0;
    for (uint32_t t = 0; t < m.triangleCount(); ++t) {
        const uint32_t a = m.index(3 * t), b = m.index(3 * t + 1), c = m.index(3 * t + 2);
        const dvec3 pa(m.positions()[a]), pb(m.positions()[b]), pc(m.positions()[c]);
        const dvec3 cross = glm::cross(pb - pa, pc - pa), mid = (pa + pb + pc) / 3.0;
        const double w = 0.5 * glm::length(cross);
        if (w <= 0.0) continue;
        const dvec3 n = cross / (2.0 * w);
        const bool out[4] = {
            n.x < -0.99 && std::abs(mid.x - box.min.x) < 0.4, n.x > 0.99 && std::abs(mid.x - box.max.x) < 0.4,
            n.y < -0.99 && std::abs(mid.y - box.min.y) < 0.4, n.y > 0.99 && std::abs(mid.y - box.max.y) < 0.4};
        if (!out[side]) continue;
        sum += w * dvec4(m.colors()[a] + m.colors()[b] + m.colors()[c]) / 3.0;
        area += w;
    }
    return area < 10.0 ? vec4(0.0f, 0.0f, 0.0f, -1.0f) : vec4(sum / area);
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
    // A building's coarse levels carry its detailed level's light: each outer wall about as bright and as sunlit as
    // the detailed one (within 30%: the simplified walls stand a little off the detailed ones and their faces span
    // several storeys). Light of their own, sampled behind the detailed walls, is near black; unlit, they would be
    // the albedo in full sun (alpha 1).
    int compared = 0;
    for (const scenes::FactoryBuilding& b : f.buildings)
        for (int side = 0; side < 4; ++side) {
            const dvec3 at = b.place->matrix()[3];
            const Box walls{b.box.min - at, b.box.max - at};
            const vec4 fine = outerWallColor(*static_cast<Geometry&>(*b.lod->child(0)).mesh(), walls, side);
            ASSERT_GE(fine.a, 0.0f) << b.kind << " side " << side;
            EXPECT_GT(fine.g, 0.2f) << b.kind << " side " << side;
            for (size_t level = 1; level < b.lod->numChildren(); ++level) {
                const auto& g = static_cast<Geometry&>(*b.lod->child(level));
                EXPECT_TRUE(g.material()->bakedLight) << b.kind << " level " << level;
                const vec4 coarse = outerWallColor(*g.mesh(), walls, side);
                if (coarse.a < 0.0f) continue;  // the simplifier pulled that wall in
                ++compared;
                for (int c = 0; c < 4; ++c)
                    EXPECT_NEAR(coarse[c], fine[c], 0.3f * std::max(fine[c], 0.1f))
                        << b.kind << " level " << level << " side " << side << " channel " << c;
            }
        }
    EXPECT_GE(compared, 40);  // most sides of every building, at every coarse level
    EXPECT_TRUE(f.buildings[0].roof->material()->bakedLight);
    EXPECT_GT(f.buildings[0].roof->material()->specular, 0.0f);
    EXPECT_EQ(f.buildings[0].roof->material(), f.buildings[10].roof->material());

    scenes::Factory again = scenes::buildFactory();
    const scenes::FactoryLightingStats second = scenes::bakeFactoryLighting(again, dir);
    EXPECT_TRUE(second.cached);
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
