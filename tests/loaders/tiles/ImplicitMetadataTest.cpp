// Implicit tiles' tile and content metadata (3D Tiles 1.1): every property of a subtree's tileMetadata and
// contentMetadata tables, a row per available tile (or content) in the order of the availability bits, reached
// from the content's nodes with the schema's offset and scale applied; bad tables refused by subtree file, JSON
// path and reason.
#include "loaders/tiles/TileMetadata.h"
#include "loaders/tiles/Tileset.h"
#include "loaders/tiles/TilesetTestUtil.h"
#include "sg/core/NodeVisitor.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstring>
#include <functional>
#include <map>
#include <string>

using namespace sg;
using namespace tilestest;
using nlohmann::json;

namespace {

// The subtree's binary chunk: view 0 the tile availability (bits 0, 1, 2, 4: the root, 1/0/0, 1/1/0 and 1/1/1;
// not 1/0/1), view 1 the content availability (bits 0, 1, 4), views 2 and 3 the tiles' names and their string
// offsets, view 4 their levels (UINT8), view 5 their heights (FLOAT32, raw 1 to 4), view 6 the contents' counts.
std::vector<unsigned char> subtreeBytes() {
    std::vector<unsigned char> b(80, 0);
    b[0] = 0x17;
    b[8] = 0x13;
    std::memcpy(&b[16], "rootabc", 7);
    const uint32_t offsets[] = {0, 4, 5, 6, 7};
    std::memcpy(&b[24], offsets, sizeof offsets);
    const uint8_t levels[] = {0, 1, 1, 1};
    std::memcpy(&b[48], levels, sizeof levels);
    const float heights[] = {1.0f, 2.0f, 3.0f, 4.0f};
    std::memcpy(&b[56], heights, sizeof heights);
    const uint16_t counts[] = {10, 20, 30};
    std::memcpy(&b[72], counts, sizeof counts);
    return b;
}

json view(int offset, int length) { return {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}}; }

json subtreeJson() {
    json tiles = {
        {"class", "tile"},
        {"count", 4},
        {"properties",
         {{"name", {{"values", 2}, {"stringOffsets", 3}}}, {"level", {{"values", 4}}}, {"height", {{"values", 5}}}}}};
    json contents = {{"class", "content"}, {"count", 3}, {"properties", {{"count", {{"values", 6}}}}}};
    json sub;
    sub["buffers"] = json::array({{{"byteLength", 80}}});
    sub["bufferViews"] =
        json::array({view(0, 1), view(8, 1), view(16, 7), view(24, 20), view(48, 4), view(56, 16), view(72, 6)});
    sub["tileAvailability"] = {{"bitstream", 0}};
    sub["contentAvailability"] = json::array({{{"bitstream", 1}}});
    sub["childSubtreeAvailability"] = {{"constant", 0}};
    sub["propertyTables"] = json::array({tiles, contents});
    sub["tileMetadata"] = 0;
    sub["contentMetadata"] = json::array({1});
    return sub;
}

// An implicit quadtree of two levels over [0, 100]^2 in one subtree (subtreeLevels 2), with the schema's classes
// `tile` {name, level, height (offset 100, scale 2)} and `content` {count}; a box content for each tile whose
// content is available. `edit` changes the subtree's JSON before it is written.
std::string implicitTileset(const TempDir& d, const std::function<void(json&)>& edit = {}) {
    const json tileset = json::parse(R"({"asset": {"version": "1.1"}, "geometricError": 100,
        "schema": {"classes": {
            "tile": {"properties": {
                "name": {"type": "STRING"},
                "level": {"type": "SCALAR", "componentType": "UINT8"},
                "height": {"type": "SCALAR", "componentType": "FLOAT32", "offset": 100, "scale": 2}}},
            "content": {"properties": {"count": {"type": "SCALAR", "componentType": "UINT16"}}}}},
        "root": {"boundingVolume": {"box": [50,50,0.5, 50,0,0, 0,50,0, 0,0,0.5]}, "geometricError": 40,
                 "refine": "REPLACE", "content": {"uri": "content/{level}/{x}/{y}.glb"},
                 "implicitTiling": {"subdivisionScheme": "QUADTREE", "subtreeLevels": 2, "availableLevels": 2,
                                    "subtrees": {"uri": "subtrees/{level}/{x}/{y}.subtree"}}}})");
    const int withContent[][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 1}};
    for (const auto& [l, x, y] : withContent) {
        fs::create_directories(d / ("content/" + std::to_string(l) + "/" + std::to_string(x)));
        const double size = 100.0 / (1 << l);
        writeBoxGlb(d / ("content/" + std::to_string(l) + "/" + std::to_string(x) + "/" + std::to_string(y) + ".glb"),
                    dvec3(x * size + 1, y * size + 1, 0), dvec3((x + 1) * size - 1, (y + 1) * size - 1, 1));
    }
    json sub = subtreeJson();
    if (edit) edit(sub);
    fs::create_directories(d / "subtrees/0/0");
    writeSubtree(d / "subtrees/0/0/0.subtree", sub.dump(), subtreeBytes());
    writeText(d / "tileset.json", tileset.dump());
    return d / "tileset.json";
}

std::vector<TileContent*> tileContents(Node& root) {
    struct Collect : NodeVisitor {
        std::vector<TileContent*> found;
        void apply(Group& g) override {
            if (auto* c = dynamic_cast<TileContent*>(&g)) found.push_back(c);
            traverse(g);
        }
    } c;
    root.accept(c);
    return c.found;
}

double number(const MetadataEntity& e, const std::string& id) {
    const PropertyValue* v = e.find(id);
    return v ? v->asNumber() : -1.0;
}

void expectRefused(const std::string& tileset, const std::string& file, const std::string& path,
                   const std::string& reason) {
    try {
        Tileset ts = loadTileset(tileset);
        refineAll(*ts.root(), ts.loadFunction());
        FAIL() << "read: expected " << path << ": " << reason;
    } catch (const LoadError& e) {
        EXPECT_EQ(e.file(), file) << e.what();
        EXPECT_EQ(e.jsonPath(), path) << e.what();
        EXPECT_NE(e.reason().find(reason), std::string::npos) << e.what();
    }
}

}  // namespace

// The tiles with a content are the root (tile row 0, content row 0), 1/0/0 (rows 1 and 1) and 1/1/1 (tile row 3,
// as 1/1/0 without a content takes row 2; content row 2). Heights: 2 * raw + 100.
TEST(ImplicitMetadata, TilesAndContentsGetTheirRows) {
    TempDir d;
    Tileset ts = loadTileset(implicitTileset(d));
    refineAll(*ts.root(), ts.loadFunction());
    EXPECT_TRUE(ts.warnings().empty());
    struct Expected {
        double level, height, count;
    };
    const std::map<std::string, Expected> expected = {{"root", {0, 102, 10}}, {"a", {1, 104, 20}}, {"c", {1, 108, 30}}};
    std::map<std::string, Expected> seen;
    for (TileContent* c : tileContents(*ts.root())) {
        ASSERT_GT(c->numChildren(), 0u);
        const TileMetadata* m = tileMetadataOf(*c->child(0));
        ASSERT_NE(m, nullptr);
        ASSERT_TRUE(m->tile.has_value());
        EXPECT_EQ(m->tile->classId, "tile");
        EXPECT_EQ(m->schema, ts.schema());
        ASSERT_EQ(m->contents.size(), 1u);
        ASSERT_TRUE(m->contents[0].metadata.has_value());
        EXPECT_EQ(m->contents[0].metadata->classId, "content");
        const PropertyValue* name = m->tile->find("name");
        ASSERT_NE(name, nullptr);
        seen[name->string] = {number(*m->tile, "level"), number(*m->tile, "height"),
                              number(*m->contents[0].metadata, "count")};
    }
    ASSERT_EQ(seen.size(), expected.size());
    for (const auto& [name, e] : expected) {
        ASSERT_EQ(seen.count(name), 1u) << name;
        EXPECT_EQ(seen[name].level, e.level) << name;
        EXPECT_EQ(seen[name].height, e.height) << name;
        EXPECT_EQ(seen[name].count, e.count) << name;
    }
}

TEST(ImplicitMetadata, TableIndicesPastThePropertyTablesAreRefusedByName) {
    TempDir d;
    expectRefused(implicitTileset(d, [](json& sub) { sub["contentMetadata"][0] = 2; }), d / "subtrees/0/0/0.subtree",
                  "contentMetadata[0]", "not an integer from 0 to 1");
    TempDir e;
    expectRefused(implicitTileset(e, [](json& sub) { sub["tileMetadata"] = 7; }), e / "subtrees/0/0/0.subtree",
                  "tileMetadata", "not an integer from 0 to 1");
}

TEST(ImplicitMetadata, CountsOtherThanTheAvailableAreRefusedByName) {
    TempDir d;
    expectRefused(implicitTileset(d, [](json& sub) { sub["propertyTables"][1]["count"] = 2; }),
                  d / "subtrees/0/0/0.subtree", "propertyTables[1].count",
                  "2 rows, not one per the subtree's 3 available");
    TempDir e;
    expectRefused(implicitTileset(e, [](json& sub) { sub["propertyTables"][0]["count"] = 5; }),
                  e / "subtrees/0/0/0.subtree", "propertyTables[0].count",
                  "5 rows, not one per the subtree's 4 available tiles");
}

TEST(ImplicitMetadata, BadBufferViewsAreRefusedByName) {
    TempDir d;
    expectRefused(implicitTileset(d, [](json& sub) { sub["propertyTables"][1]["properties"]["count"]["values"] = 9; }),
                  d / "subtrees/0/0/0.subtree", "propertyTables[1].properties.count.values",
                  "not an integer from 0 to 6");
    TempDir e;
    expectRefused(implicitTileset(e, [](json& sub) { sub["bufferViews"][6]["byteOffset"] = 76; }),
                  e / "subtrees/0/0/0.subtree", "bufferViews[6]", "bytes 76 to 82 are past buffer 0's 80");
    TempDir f;  // inside the buffer, but short of 3 rows of UINT16
    expectRefused(implicitTileset(f, [](json& sub) { sub["bufferViews"][6]["byteLength"] = 4; }),
                  f / "subtrees/0/0/0.subtree", "propertyTables[1]", "too short");
}
