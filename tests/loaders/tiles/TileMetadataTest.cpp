// 3D Tiles 1.1 metadata of a tileset, its groups, a tile and its content, read from tileset.json with the schema's
// transforms applied and reached from the content's nodes; bad metadata refused by file, JSON path and reason.
#include "loaders/tiles/TileMetadata.h"
#include "loaders/tiles/Tileset.h"
#include "loaders/tiles/TilesetTestUtil.h"
#include "sg/core/NodeVisitor.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <functional>
#include <string>

using namespace sg;
using namespace tilestest;
using nlohmann::json;

namespace {

// A tileset of one tile with a box content: the schema, the tileset's metadata, a group, the tile's and the
// content's metadata. `edit` changes the JSON before it is written.
std::string metadataTileset(const TempDir& d, const std::function<void(json&)>& edit = {}) {
    json j = json::parse(R"({"asset": {"version": "1.1"}, "geometricError": 10,
        "schema": {"id": "city",
            "classes": {
                "building": {"properties": {
                    "height": {"type": "SCALAR", "componentType": "UINT8", "normalized": true, "scale": 100,
                               "offset": 5},
                    "name": {"type": "STRING"},
                    "pos": {"type": "VEC2", "componentType": "FLOAT32", "offset": [1, 2]},
                    "kind": {"type": "ENUM", "enumType": "kinds"},
                    "floors": {"type": "SCALAR", "componentType": "INT32", "noData": -1, "default": 0}}},
                "area": {"properties": {"label": {"type": "STRING", "required": true}}}},
            "enums": {"kinds": {"values": [{"name": "house", "value": 0}, {"name": "shed", "value": 1}]}}},
        "metadata": {"class": "area", "properties": {"label": "town"}},
        "groups": [{"class": "area", "properties": {"label": "north"}}],
        "root": {"boundingVolume": {"box": [0,0,0, 10,0,0, 0,10,0, 0,0,10]}, "geometricError": 0, "refine": "ADD",
            "metadata": {"class": "building",
                         "properties": {"height": 51, "name": "Hall", "pos": [3, 4], "kind": "shed", "floors": -1}},
            "content": {"uri": "box.glb", "group": 0,
                        "metadata": {"class": "area", "properties": {"label": "inside"}}}}})");
    if (edit) edit(j);
    writeBoxGlb(d / "box.glb", dvec3(0, 0, 0), dvec3(1, 1, 1));
    writeText(d / "tileset.json", j.dump());
    return d / "tileset.json";
}

Geometry* firstGeometry(Node& root) {
    struct Find : NodeVisitor {
        Geometry* found = nullptr;
        void apply(Geometry& g) override {
            if (!found) found = &g;
        }
    } f;
    root.accept(f);
    return f.found;
}

void expectRefused(const std::string& tileset, const std::string& path, const std::string& reason) {
    try {
        Tileset ts = loadTileset(tileset);
        FAIL() << "read: expected " << path << ": " << reason;
    } catch (const LoadError& e) {
        EXPECT_EQ(e.jsonPath(), path) << e.what();
        EXPECT_NE(e.reason().find(reason), std::string::npos) << e.what();
    }
}

}  // namespace

// height: 51 of UINT8 normalized is 0.2, times 100 plus 5 is 25; pos: (3, 4) + (1, 2); floors: -1 is noData, so
// the default 0; kind: the enum's name.
TEST(TileMetadata, TileAndContentMetadataAreReadFromTheContentsNodes) {
    TempDir d;
    Tileset ts = loadTileset(metadataTileset(d));
    ASSERT_TRUE(ts.schema());
    EXPECT_EQ(ts.schema()->id, "city");
    ASSERT_TRUE(ts.metadata());
    EXPECT_EQ(ts.metadata()->classId, "area");
    ASSERT_TRUE(ts.metadata()->find("label"));
    EXPECT_EQ(*ts.metadata()->find("label"), PropertyValue::ofString("town"));
    ASSERT_EQ(ts.groups()->size(), 1u);
    EXPECT_EQ(*ts.groups()->at(0).find("label"), PropertyValue::ofString("north"));

    Geometry* g = firstGeometry(*ts.root());
    ASSERT_TRUE(g);
    const TileMetadata* m = tileMetadataOf(*g);
    ASSERT_TRUE(m);
    EXPECT_EQ(tileMetadataOf(*ts.root()), nullptr);  // above the content
    ASSERT_TRUE(m->tile);
    EXPECT_EQ(m->tile->classId, "building");
    ASSERT_TRUE(m->tile->find("height"));
    EXPECT_NEAR(m->tile->find("height")->asNumber(), 25.0, 1e-9);
    EXPECT_EQ(*m->tile->find("name"), PropertyValue::ofString("Hall"));
    const PropertyValue* pos = m->tile->find("pos");
    ASSERT_TRUE(pos);
    ASSERT_EQ(pos->items.size(), 2u);
    EXPECT_DOUBLE_EQ(pos->items[0].asNumber(), 4.0);
    EXPECT_DOUBLE_EQ(pos->items[1].asNumber(), 6.0);
    EXPECT_EQ(*m->tile->find("kind"), PropertyValue::ofString("shed"));
    ASSERT_TRUE(m->tile->find("floors"));
    EXPECT_EQ(m->tile->find("floors")->asNumber(), 0.0);

    ASSERT_EQ(m->contents.size(), 1u);
    ASSERT_TRUE(m->contents[0].metadata);
    EXPECT_EQ(*m->contents[0].metadata->find("label"), PropertyValue::ofString("inside"));
    EXPECT_EQ(m->contents[0].group, 0);
    ASSERT_TRUE(m->groups);
    EXPECT_EQ(*m->groups->at(0).find("label"), PropertyValue::ofString("north"));
}

TEST(TileMetadata, BadMetadataIsRefusedByPath) {
    TempDir a, b, c, e, f, g;
    expectRefused(metadataTileset(a, [](json& j) { j["root"]["content"]["group"] = 1; }), "root.content.group",
                  "1 groups");
    expectRefused(metadataTileset(b, [](json& j) { j["root"]["metadata"]["class"] = "tree"; }), "root.metadata.class",
                  "not in the schema");
    expectRefused(metadataTileset(c, [](json& j) { j["root"]["metadata"]["properties"]["name"] = 5; }),
                  "root.metadata.properties.name", "STRING");
    expectRefused(metadataTileset(e, [](json& j) { j["root"]["metadata"]["properties"]["kind"] = "castle"; }),
                  "root.metadata.properties.kind", "ENUM");
    expectRefused(metadataTileset(f, [](json& j) { j["groups"][0]["properties"].erase("label"); }),
                  "groups[0].properties.label", "requires it");
    expectRefused(metadataTileset(g,
                                  [](json& j) {
                                      j.erase("schema");
                                      j.erase("metadata");
                                      j.erase("groups");
                                      j["root"]["content"].erase("group");
                                  }),
                  "root.metadata", "without a schema");
}
