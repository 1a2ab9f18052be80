// The factory's generated textures: each has a picture (not one colour), repeats without a seam, comes
// out the same for a seed and differs for another; the factory's materials carry them.
#include "nodes/Geometry.h"
#include "testbed/Factory.h"
#include "testbed/FactoryTextures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

using namespace sg;

namespace {

struct Generated {
    std::string name;
    std::function<ref_ptr<Texture>(uint32_t)> make;
    bool seeded, wrapsVertically;  // wall textures repeat by storey, with a band at each storey's top
};

const std::vector<Generated>& generated() {
    static const std::vector<Generated> all = {
        {"window", [](uint32_t) { return scenes::factoryWindowTexture(); }, false, false},
        {"brick", scenes::factoryBrickTexture, true, false},
        {"roof", scenes::factoryRoofTexture, true, true},
        {"grass", scenes::factoryGrassTexture, true, true},
        {"asphalt", scenes::factoryAsphaltTexture, true, true},
    };
    return all;
}

float luma(const Texture& t, int x, int y) {
    const uint8_t* p = &t.rgba()[(size_t(y) * size_t(t.width()) + size_t(x)) * 4];
    return 0.299f * p[0] + 0.587f * p[1] + 0.114f * p[2];
}

// Mean absolute luma step between column x and column x + 1 (wrapping), over every row.
double columnStep(const Texture& t, int x) {
    double sum = 0.0;
    for (int y = 0; y < t.height(); ++y) sum += std::abs(luma(t, x, y) - luma(t, (x + 1) % t.width(), y));
    return sum / t.height();
}
double rowStep(const Texture& t, int y) {
    double sum = 0.0;
    for (int x = 0; x < t.width(); ++x) sum += std::abs(luma(t, x, y) - luma(t, x, (y + 1) % t.height()));
    return sum / t.width();
}

}  // namespace

TEST(FactoryTextures, EachHasAPictureAndRepeatsWithoutASeam) {
    for (const Generated& g : generated()) {
        SCOPED_TRACE(g.name);
        const ref_ptr<Texture> t = g.make(1996);
        ASSERT_GT(t->width(), 0);
        // Not one colour: the luma spreads.
        double mean = 0.0, var = 0.0;
        const int n = t->width() * t->height();
        for (int y = 0; y < t->height(); ++y)
            for (int x = 0; x < t->width(); ++x) mean += luma(*t, x, y) / n;
        for (int y = 0; y < t->height(); ++y)
            for (int x = 0; x < t->width(); ++x) var += (luma(*t, x, y) - mean) * (luma(*t, x, y) - mean) / n;
        EXPECT_GT(std::sqrt(var), 4.0);
        // The step from the last column into the first is no larger than steps inside the picture.
        double inside = 0.0;
        for (int x = 0; x + 1 < t->width(); ++x) inside += columnStep(*t, x) / (t->width() - 1);
        EXPECT_LE(columnStep(*t, t->width() - 1), 2.0 * inside + 1.0) << "inside " << inside;
        if (g.wrapsVertically) {
            double insideRows = 0.0;
            for (int y = 0; y + 1 < t->height(); ++y) insideRows += rowStep(*t, y) / (t->height() - 1);
            EXPECT_LE(rowStep(*t, t->height() - 1), 2.0 * insideRows + 1.0) << "inside " << insideRows;
        }
        // Opaque everywhere.
        for (int i = 0; i < n; ++i) ASSERT_EQ(t->rgba()[size_t(i) * 4 + 3], 255);
    }
}

TEST(FactoryTextures, WallTexturesKeepAWhiteCornerForUntexturedParts) {
    for (const ref_ptr<Texture>& t : {scenes::factoryWindowTexture(), scenes::factoryBrickTexture(7)})
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 2; ++x)
                for (int c = 0; c < 4; ++c)
                    EXPECT_EQ(t->rgba()[(size_t(y) * size_t(t->width()) + size_t(x)) * 4 + size_t(c)], 255);
}

TEST(FactoryTextures, SameSeedSamePixelsOtherSeedOthers) {
    for (const Generated& g : generated()) {
        if (!g.seeded) continue;
        SCOPED_TRACE(g.name);
        EXPECT_EQ(g.make(1996)->rgba(), g.make(1996)->rgba());
        EXPECT_NE(g.make(1996)->rgba(), g.make(1997)->rgba());
    }
    EXPECT_EQ(scenes::factoryTreeTexture(5)->rgba(), scenes::factoryTreeTexture(5)->rgba());
    EXPECT_NE(scenes::factoryTreeTexture(5)->rgba(), scenes::factoryTreeTexture(6)->rgba());
}

TEST(FactoryTextures, TheFactorysMaterialsCarryThem) {
    scenes::FactoryParams p;
    p.trees = 4;
    p.cars = 2;
    const scenes::Factory f = scenes::buildFactory(p);
    auto material = [](Node* n) { return static_cast<Geometry*>(n)->material(); };
    // The ground: one grass material for every level of every tile, filtered anisotropically, UVs in world
    // metres.
    const Material* grass = material(f.terrain->child(0)->child(0));
    ASSERT_NE(grass->texture, nullptr);
    EXPECT_GT(grass->texture->maxAnisotropy, 1.0f);
    for (size_t i = 0; i < f.terrain->numChildren(); ++i)
        for (size_t level = 0; level < f.terrain->child(i)->numChildren(); ++level) {
            Node* g = f.terrain->child(i)->child(level);
            EXPECT_EQ(material(g), grass);
            const Mesh& tile = *static_cast<Geometry*>(g)->mesh();
            for (size_t v : {size_t(0), tile.positions().size() - 1})
                EXPECT_NEAR(tile.uvs()[v].x * scenes::kFactoryGrassMetres, tile.positions()[v].x, 1e-3);
        }
    // Walls: rendered with windows on the workshops, brick on the auxiliary buildings; one roof material.
    const Material* rendered = material(f.buildings[0].lod->child(0));
    const Material* brick = material(f.buildings[4].lod->child(0));
    ASSERT_NE(rendered->texture, nullptr);
    ASSERT_NE(brick->texture, nullptr);
    EXPECT_NE(rendered->texture, brick->texture);
    for (const scenes::FactoryBuilding& b : f.buildings) {
        EXPECT_EQ(material(b.lod->child(0)), b.kind == "auxiliary" ? brick : rendered) << b.kind;
        EXPECT_EQ(material(b.lod->child(1)), material(b.lod->child(0)));
        ASSERT_NE(b.roof, nullptr);
        EXPECT_EQ(b.roof->material(), f.buildings[0].roof->material());
    }
    EXPECT_NE(f.buildings[0].roof->material()->texture, nullptr);
    EXPECT_GT(f.buildings[0].roof->material()->specular, 0.0f);
    // The machines shine too.
    EXPECT_GT(static_cast<Geometry*>(f.machine->child(0))->material()->specular, 0.0f);
    // Roads and the car park: asphalt, anisotropic, in one mesh.
    int asphalt = 0;
    const Group& outside = static_cast<const Group&>(*f.outside->child(0));
    for (size_t i = 0; i < outside.numChildren(); ++i) {
        Node* n = outside.child(i);
        if (n->kind() != NodeKind::Geometry) continue;
        const Material* m = static_cast<Geometry*>(n)->material();
        if (m && m->texture && m->texture->maxAnisotropy > 1.0f && m != grass) ++asphalt;
    }
    EXPECT_EQ(asphalt, 1);
}
