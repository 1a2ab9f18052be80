// sg::loadTileset and implicit tiles' metadata semantics (3D Tiles 1.1): a tile's TILE_BOUNDING_BOX (or sphere,
// or region) and TILE_GEOMETRIC_ERROR from its subtree's tile metadata replace the implied volume and the error
// halved per level; other metadata is ignored; bad metadata fails its subtree by file, JSON path and reason.
#include "loaders/tiles/Tileset.h"
#include "loaders/tiles/TilesetTestUtil.h"
#include "loaders/tiles/internal/TilesetTable.h"
#include "nodes/PagedLOD.h"
#include "sg/core/NodeVisitor.h"
#include "sg/paging/Pager.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstring>
#include <functional>
#include <limits>

using namespace sg;
using namespace tilestest;
using nlohmann::json;

namespace {

// One subtree's tile metadata as the test writes it: a row per tile, its box (12 numbers) and its error.
struct Rows {
    std::vector<double> boxes, errors;
};
using Edit = std::function<void(json& tileset, json& subtree, Rows& rows)>;

// The binary subtree of one tile (subtreeLevels 1) with its metadata: views 0 the boxes, 1 the errors.
void writeMetadataSubtree(const std::string& path, json sub, const Rows& rows) {
    std::vector<unsigned char> bin(rows.boxes.size() * 8 + rows.errors.size() * 8);
    std::memcpy(bin.data(), rows.boxes.data(), rows.boxes.size() * 8);
    std::memcpy(bin.data() + rows.boxes.size() * 8, rows.errors.data(), rows.errors.size() * 8);
    if (!sub.contains("buffers")) sub["buffers"] = json::array({{{"byteLength", bin.size()}}});
    writeSubtree(path, sub.dump(), bin);
}

// An implicit quadtree of two levels over [0, 100]^2, a subtree per tile: the root (error 40 in tileset.json,
// 33 in its metadata; its metadata box [10, 90]^2 x [0, 1]) and its four children (error 0, boxes inset in their
// squares), each with a box content. `edit` changes the tileset and the subtree `which` ("0/0/0", "1/1/0", ...)
// before they are written.
std::string metadataTileset(const TempDir& d, const std::string& which = "", const Edit& edit = {}) {
    json tileset = json::parse(R"({"asset": {"version": "1.1"}, "geometricError": 100,
        "schema": {"classes": {"tile": {"properties": {
            "box": {"type": "SCALAR", "componentType": "FLOAT64", "array": true, "count": 12,
                    "semantic": "TILE_BOUNDING_BOX"},
            "error": {"type": "SCALAR", "componentType": "FLOAT64", "semantic": "TILE_GEOMETRIC_ERROR"},
            "height": {"type": "SCALAR", "componentType": "FLOAT64", "semantic": "TILE_MAXIMUM_HEIGHT"},
            "name": {"type": "STRING"}}}}},
        "root": {"boundingVolume": {"box": [50,50,0.5, 50,0,0, 0,50,0, 0,0,0.5]}, "geometricError": 40,
                 "refine": "REPLACE", "content": {"uri": "content/{level}/{x}/{y}.glb"},
                 "implicitTiling": {"subdivisionScheme": "QUADTREE", "subtreeLevels": 1, "availableLevels": 2,
                                    "subtrees": {"uri": "subtrees/{level}/{x}/{y}.subtree"}}}})");
    std::string last;
    for (int l = 0; l <= 1; ++l)
        for (int x = 0; x < (1 << l); ++x)
            for (int y = 0; y < (1 << l); ++y) {
                const std::string at = std::to_string(l) + "/" + std::to_string(x) + "/" + std::to_string(y);
                fs::create_directories(d / ("content/" + std::to_string(l) + "/" + std::to_string(x)));
                fs::create_directories(d / ("subtrees/" + std::to_string(l) + "/" + std::to_string(x)));
                const double size = 100.0 / (1 << l), inset = 0.1 * size;
                writeBoxGlb(d / ("content/" + at + ".glb"), dvec3(x * size + inset, y * size + inset, 0),
                            dvec3((x + 1) * size - inset, (y + 1) * size - inset, 1));
                const double cx = (x + 0.5) * size, cy = (y + 0.5) * size, h = 0.5 * size - inset;
                Rows rows{{cx, cy, 0.5, h, 0, 0, 0, h, 0, 0, 0, 0.5}, {l == 0 ? 33.0 : 0.0}};
                json sub = {{"tileAvailability", {{"constant", 1}}},
                            {"contentAvailability", json::array({{{"constant", 1}}})},
                            {"childSubtreeAvailability", {{"constant", l == 0 ? 1 : 0}}},
                            {"bufferViews", json::array({{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 96}},
                                                         {{"buffer", 0}, {"byteOffset", 96}, {"byteLength", 8}}})},
                            {"propertyTables",
                             json::array({{{"class", "tile"},
                                           {"count", 1},
                                           {"properties", {{"box", {{"values", 0}}}, {"error", {{"values", 1}}}}}}})},
                            {"tileMetadata", 0}};
                if (at == which && edit) edit(tileset, sub, rows);
                writeMetadataSubtree(d / ("subtrees/" + at + ".subtree"), sub, rows);
            }
    writeText(d / "tileset.json", tileset.dump());
    return d / "tileset.json";
}

std::vector<PagedLOD*> pagedLods(Node& root) {
    struct Collect : NodeVisitor {
        std::vector<PagedLOD*> found;
        void apply(PagedLOD& p) override {
            found.push_back(&p);
            traverse(p);
        }
    } c;
    root.accept(c);
    return c.found;
}

// Loading fails with a LoadError naming `file` and `path`, its reason holding `reason`.
void expectRefused(const std::string& tileset, const std::string& file, const std::string& path,
                   const std::string& reason) {
    try {
        Tileset ts = loadTileset(tileset);
        FAIL() << "read: expected " << path << ": " << reason;
    } catch (const LoadError& e) {
        EXPECT_EQ(e.file(), file) << e.what();
        EXPECT_EQ(e.jsonPath(), path) << e.what();
        EXPECT_NE(e.reason().find(reason), std::string::npos) << e.what();
    }
}

}  // namespace

// The root's PagedLOD refines by its metadata's box and error, not the tileset.json's (or the implied ones); the
// unknown semantic and the property without one are ignored.
TEST(TilesetMetadata, BoxAndErrorComeFromTheSubtree) {
    TempDir d;
    Tileset ts = loadTileset(metadataTileset(d));
    const std::vector<PagedLOD*> lods = pagedLods(*ts.root());
    ASSERT_EQ(lods.size(), 1u);
    EXPECT_DOUBLE_EQ(lods[0]->geometricError(), 33.0);
    EXPECT_NEAR(lods[0]->center().x, 50.0, 1e-9);
    EXPECT_NEAR(lods[0]->radius(), std::sqrt(40.0 * 40.0 * 2 + 0.25), 1e-9);  // [10, 90]^2 x [0, 1]
    EXPECT_EQ(refineAll(*ts.root(), ts.loadFunction()), 1u);
    EXPECT_EQ(ts.counts().contents, 5u);
    EXPECT_TRUE(ts.warnings().empty());
}

// A sphere (FLOAT32) where a box is not given; an error in FLOAT32.
TEST(TilesetMetadata, SpheresAndFloat32AreRead) {
    TempDir d;
    const Edit edit = [](json& tileset, json& sub, Rows& rows) {
        json& props = tileset["schema"]["classes"]["tile"]["properties"];
        props.erase("box");
        props["sphere"] = {{"type", "SCALAR"},
                           {"componentType", "FLOAT32"},
                           {"array", true},
                           {"count", 4},
                           {"semantic", "TILE_BOUNDING_SPHERE"}};
        props["error"]["componentType"] = "FLOAT32";
        // Four floats of sphere, then one float of error, in the bytes the test writes as doubles.
        const float values[] = {20.0f, 30.0f, 0.5f, 12.5f, 7.0f, 0.0f};
        std::memcpy(rows.boxes.data(), values, sizeof values);
        sub["propertyTables"][0]["properties"] = {{"sphere", {{"values", 0}}}, {"error", {{"values", 2}}}};
        sub["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 16}, {"byteLength", 4}});
    };
    Tileset ts = loadTileset(metadataTileset(d, "0/0/0", edit));
    const std::vector<PagedLOD*> lods = pagedLods(*ts.root());
    ASSERT_EQ(lods.size(), 1u);
    EXPECT_DOUBLE_EQ(lods[0]->geometricError(), 7.0);
    EXPECT_NEAR(lods[0]->center().x, 20.0, 1e-9);
    EXPECT_NEAR(lods[0]->center().y, 30.0, 1e-9);
    EXPECT_NEAR(lods[0]->radius(), 12.5, 1e-9);
}

TEST(TilesetMetadata, AShortOrMissingPropertyTableIsRefusedByName) {
    TempDir d;
    const std::string file =
        metadataTileset(d, "0/0/0", [](json&, json& sub, Rows&) { sub["propertyTables"][0]["count"] = 0; });
    expectRefused(file, d / "subtrees/0/0/0.subtree", "propertyTables[0].count",
                  "0 rows, fewer than the subtree's 1 available tiles");
    TempDir e;
    const std::string table = metadataTileset(e, "0/0/0", [](json&, json& sub, Rows&) { sub["tileMetadata"] = 3; });
    expectRefused(table, e / "subtrees/0/0/0.subtree", "tileMetadata", "not an integer from 0 to 0");
}

TEST(TilesetMetadata, BufferViewsOutOfRangeOrShortAreRefusedByName) {
    TempDir d;
    const std::string bad = metadataTileset(
        d, "0/0/0", [](json&, json& sub, Rows&) { sub["propertyTables"][0]["properties"]["error"]["values"] = 7; });
    expectRefused(bad, d / "subtrees/0/0/0.subtree", "propertyTables[0].properties.error.values",
                  "not an integer from 0 to 1");
    TempDir e;
    const std::string past =
        metadataTileset(e, "0/0/0", [](json&, json& sub, Rows&) { sub["bufferViews"][1]["byteOffset"] = 100; });
    expectRefused(past, e / "subtrees/0/0/0.subtree", "bufferViews[1]", "bytes 100 to 108 are past buffer 0's 104");
    TempDir f;
    const std::string shortView =
        metadataTileset(f, "0/0/0", [](json&, json& sub, Rows&) { sub["bufferViews"][0]["byteLength"] = 88; });
    expectRefused(shortView, f / "subtrees/0/0/0.subtree", "propertyTables[0].properties.box.values",
                  "holds 88 bytes, fewer than the 96 of 1 rows of 12 FLOAT64");
}

TEST(TilesetMetadata, WrongComponentTypesAndCountsAreRefusedByName) {
    TempDir d;
    const std::string type = metadataTileset(d, "0/0/0", [](json& tileset, json&, Rows&) {
        tileset["schema"]["classes"]["tile"]["properties"]["error"]["componentType"] = "UINT8";
    });
    expectRefused(type, d / "tileset.json", "schema.classes.tile.properties.error.componentType",
                  "TILE_GEOMETRIC_ERROR must be FLOAT32 or FLOAT64, not \"UINT8\"");
    TempDir e;
    const std::string count = metadataTileset(e, "0/0/0", [](json& tileset, json&, Rows&) {
        tileset["schema"]["classes"]["tile"]["properties"]["box"]["count"] = 6;
    });
    expectRefused(count, e / "tileset.json", "schema.classes.tile.properties.box.count",
                  "TILE_BOUNDING_BOX must be an array of 12 numbers");
}

TEST(TilesetMetadata, NanOrNegativeErrorsAndNanBoxesAreRefusedByName) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    TempDir d;
    expectRefused(metadataTileset(d, "0/0/0", [&](json&, json&, Rows& rows) { rows.errors[0] = nan; }),
                  d / "subtrees/0/0/0.subtree", "propertyTables[0].properties.error", "row 0: value 0 is not finite");
    TempDir e;
    expectRefused(metadataTileset(e, "0/0/0", [](json&, json&, Rows& rows) { rows.errors[0] = -1.0; }),
                  e / "subtrees/0/0/0.subtree", "propertyTables[0].properties.error",
                  "row 0: geometric error -1.000000 is negative");
    TempDir f;
    expectRefused(metadataTileset(f, "0/0/0", [&](json&, json&, Rows& rows) { rows.boxes[7] = nan; }),
                  f / "subtrees/0/0/0.subtree", "propertyTables[0].properties.box", "row 0: value 7 is not finite");
}

// The class's offset and scale apply to a semantic's values, and a property table's offset overrides the class's:
// the root's error 33 * 2 + 3; its box's centre moved by the class's offset of 5 along x.
TEST(TilesetMetadata, OffsetAndScaleAreApplied) {
    TempDir d;
    Tileset ts = loadTileset(metadataTileset(d, "0/0/0", [](json& tileset, json& sub, Rows&) {
        json& props = tileset["schema"]["classes"]["tile"]["properties"];
        props["error"]["scale"] = 2.0;
        props["error"]["offset"] = 1.0;
        props["box"]["offset"] = json::array({5, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
        sub["propertyTables"][0]["properties"]["error"]["offset"] = 3.0;
    }));
    const std::vector<PagedLOD*> lods = pagedLods(*ts.root());
    ASSERT_EQ(lods.size(), 1u);
    EXPECT_DOUBLE_EQ(lods[0]->geometricError(), 69.0);
    EXPECT_NEAR(lods[0]->center().x, 55.0, 1e-9);
    EXPECT_NEAR(lods[0]->center().y, 50.0, 1e-9);
}

// A scale that is not per component, normalized on a float: refused at their paths (by the schema reader or by the
// semantics' check, whichever sees them first: the reason is not checked).
TEST(TilesetMetadata, BadOffsetScaleOrNormalizedAreRefusedByName) {
    TempDir d;
    expectRefused(metadataTileset(d, "0/0/0",
                                  [](json& tileset, json&, Rows&) {
                                      tileset["schema"]["classes"]["tile"]["properties"]["box"]["scale"] = 2.0;
                                  }),
                  d / "tileset.json", "schema.classes.tile.properties.box.scale", "");
    TempDir e;
    expectRefused(metadataTileset(e, "0/0/0",
                                  [](json& tileset, json&, Rows&) {
                                      tileset["schema"]["classes"]["tile"]["properties"]["error"]["normalized"] = true;
                                  }),
                  e / "tileset.json", "schema.classes.tile.properties.error.normalized", "");
    TempDir f;
    expectRefused(metadataTileset(
                      f, "0/0/0",
                      [](json&, json& sub, Rows&) { sub["propertyTables"][0]["properties"]["error"]["scale"] = "x"; }),
                  f / "subtrees/0/0/0.subtree", "propertyTables[0].properties.error.scale", "a finite number");
}

// A child's bad subtree fails the load of the root's children (the root stays drawn), named; the rest works.
TEST(TilesetMetadata, ABadChildSubtreeFailsItsLoadOnly) {
    TempDir d;
    Tileset ts = loadTileset(metadataTileset(d, "1/1/0", [](json&, json&, Rows& rows) { rows.errors[0] = -2.0; }));
    Scene scene(ts.root());
    Pager pager(scene, ts.loadFunction());
    const Camera cam = lookingDownAt(dvec3(50, 50, 0), 100.0);
    for (uint64_t f = 1; f <= 3; ++f) {
        pager.update(FrameInfo{f, double(f)});
        cullOnce(scene, cam, f);
        pager.waitIdle();
    }
    const Drawn dr = cullOnce(scene, cam, 4);
    EXPECT_EQ(dr.boxes, (std::multiset<std::pair<long, long>>{{10, 10}}));  // the root's content
    EXPECT_EQ(pager.stats().failures, 1u);
    const std::string& why = pager.stats().lastError;
    EXPECT_NE(why.find("subtrees/1/1/0.subtree"), std::string::npos) << why;
    EXPECT_NE(why.find("propertyTables[0].properties.error"), std::string::npos) << why;
    EXPECT_NE(why.find("is negative"), std::string::npos) << why;
}

// The fuzz seeds of tile metadata (fuzz/tiles-corpus) are valid: the fuzzer starts from input that reads.
TEST(TilesetMetadata, TheFuzzSeedsAreRead) {
    const std::string dir = SGKIT_SOURCE_DIR "/fuzz/tiles-corpus/";
    std::ifstream in(dir + "metadata.subtree", std::ios::binary);
    const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), {});
    tiles::ImplicitTiling t;  // as the fuzzer's
    t.subtreeLevels = 3;
    t.availableLevels = 6;
    t.contents = {"c"};
    t.schema["tile"].box = tiles::SemanticProperty{"boundingBox", true, 12};
    t.schema["tile"].error = tiles::SemanticProperty{"geometricError", true, 1};
    const tiles::Subtree s = tiles::parseSubtree("metadata.subtree", bytes, t,
                                                 [](const std::string&) { return std::vector<unsigned char>(); });
    EXPECT_EQ(s.errors.size(), 11u);  // a row per available tile
    EXPECT_EQ(s.volume, tiles::Subtree::Volume::Box);
    EXPECT_EQ(s.tiles.rank(20), 10u);  // the last slot: level 2's (3, 3), after the ten others
    std::ifstream json(dir + "implicit-metadata.json", std::ios::binary);
    const std::vector<unsigned char> text((std::istreambuf_iterator<char>(json)), {});
    tiles::TilesetState state{TilesetOptions{}};  // the JSON only, as the fuzzer reads it: no subtree beside it
    EXPECT_EQ(state.addTileset(dir + "implicit-metadata.json", text, -1, -1), 0u);
}

// A region (FLOAT64): the tile's volume is Earth-centred, as a region in tileset.json is; a bad one is refused.
TEST(TilesetMetadata, RegionsAreReadEarthCentredAndBadOnesRefused) {
    auto asRegion = [](const std::vector<double>& region) {
        return [region](json& tileset, json& sub, Rows& rows) {
            json& props = tileset["schema"]["classes"]["tile"]["properties"];
            props.erase("box");
            props["region"] = {{"type", "SCALAR"},
                               {"componentType", "FLOAT64"},
                               {"array", true},
                               {"count", 6},
                               {"semantic", "TILE_BOUNDING_REGION"}};
            std::copy(region.begin(), region.end(), rows.boxes.begin());
            sub["propertyTables"][0]["properties"] = {{"region", {{"values", 0}}}, {"error", {{"values", 1}}}};
        };
    };
    TempDir d;
    Tileset ts = loadTileset(metadataTileset(d, "0/0/0", asRegion({-0.001, -0.001, 0.001, 0.001, 0.0, 10.0})));
    const std::vector<PagedLOD*> lods = pagedLods(*ts.root());
    ASSERT_EQ(lods.size(), 1u);
    EXPECT_NEAR(lods[0]->center().x, 6378137.0 + 5.0, 5.0);  // on the equator at longitude 0 (the surface curves)
    EXPECT_NEAR(lods[0]->center().y, 0.0, 1e-6);
    EXPECT_GT(lods[0]->radius(), 6378137.0 * 0.001 * std::sqrt(2.0));
    EXPECT_LT(lods[0]->radius(), 6378137.0 * 0.001 * 2.0);
    TempDir e;
    expectRefused(metadataTileset(e, "0/0/0", asRegion({0.0, 0.002, 0.001, 0.001, 0.0, 10.0})),
                  e / "subtrees/0/0/0.subtree", "propertyTables[0].properties.region",
                  "row 0: south and north must be latitudes in radians");
}
