// The TopoJSON reader on small hand-written topologies: delta-decoded quantized arcs, the transform, reversed
// arcs, holes, multipolygons, nested collections, ids and names; and malformed input, each error naming the
// file, the JSON path and why; every truncation of a valid file is refused cleanly.
#include "map/data/TopoJson.h"

#include <gtest/gtest.h>

#include <fstream>
#include <random>

using namespace sg;

namespace {

// Two regions sharing the arc x=5 (arc 2), the right one walking it reversed; the left one has a hole; a
// third region is a multipolygon of two squares. Quantized: positions are deltas, scaled by 0.5.
const char* kTopology = R"({
  "type": "Topology",
  "transform": {"scale": [0.5, 0.5], "translate": [100, -10]},
  "objects": {
    "shapes": {"type": "GeometryCollection", "geometries": [
      {"type": "Polygon", "id": 7, "properties": {"name": "Left"}, "arcs": [[0, 2], [3]]},
      {"type": "Polygon", "id": "08", "properties": {"name": "Right"}, "arcs": [[1, -3]]},
      {"type": "MultiPolygon", "id": "multi", "arcs": [[[4]], [[5]]]},
      {"type": null, "id": "empty", "properties": {"name": "Nowhere"}},
      {"type": "GeometryCollection", "id": "nested", "geometries": [{"type": "Polygon", "arcs": [[4]]}]}
    ]},
    "ignored": {"type": "Polygon", "arcs": [[4]]}
  },
  "arcs": [
    [[10, 20], [-10, 0], [0, -20], [10, 0]],
    [[10, 0], [10, 0], [0, 20], [-10, 0]],
    [[10, 0], [0, 20]],
    [[2, 2], [0, 4], [4, 0], [0, -4], [-4, 0]],
    [[40, 40], [2, 0], [0, 2], [-2, 0], [0, -2]],
    [[50, 40], [2, 0], [0, 2], [-2, 0], [0, -2]]
  ]
})";

double area(const GeoRing& r) {
    double s = 0.0;
    for (size_t i = 0, j = r.size() - 1; i < r.size(); j = i++) s += (r[j].x - r[i].x) * (r[j].y + r[i].y);
    return s / 2.0;
}

glm::dvec2 at(double qx, double qy) { return {qx * 0.5 + 100.0, qy * 0.5 - 10.0}; }

// The LoadError of parsing `text`, with a failure when it parses.
LoadError errorOf(const std::string& text) {
    try {
        parseTopoJson("bad.json", text);
    } catch (const LoadError& e) {
        return e;
    }
    ADD_FAILURE() << "parsed: " << text;
    return LoadError("", "", "");
}

std::string replaced(std::string s, const std::string& from, const std::string& to) {
    const size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? s : s.replace(at, from.size(), to);
}

}  // namespace

TEST(TopoJson, DecodesQuantizedArcsReversalHolesAndMultipolygons) {
    const auto objects = parseTopoJson("t.json", kTopology);
    ASSERT_EQ(objects.size(), 1u) << "only GeometryCollections are read";
    const auto& shapes = objects.at("shapes");
    ASSERT_EQ(shapes.size(), 5u);

    const GeoRegion& left = shapes[0];
    EXPECT_EQ(left.id, "7");
    EXPECT_EQ(left.name, "Left");
    ASSERT_EQ(left.polygons.size(), 1u);
    // Arc 0 then arc 2 (their shared point once), the closing point not repeated.
    const GeoRing expected{at(10, 20), at(0, 20), at(0, 0), at(10, 0)};
    EXPECT_EQ(left.polygons[0].outer, expected);
    ASSERT_EQ(left.polygons[0].holes.size(), 1u);
    EXPECT_EQ(left.polygons[0].holes[0].size(), 4u);
    EXPECT_DOUBLE_EQ(std::abs(area(left.polygons[0].outer)), 10 * 20 * 0.25);
    EXPECT_DOUBLE_EQ(std::abs(area(left.polygons[0].holes[0])), 4 * 4 * 0.25);

    const GeoRegion& right = shapes[1];
    EXPECT_EQ(right.id, "08");
    ASSERT_EQ(right.polygons.size(), 1u);
    // Arc 1, then arc 2 walked backwards (~2 is -3): from (10,20) down to where arc 1 began.
    const GeoRing expectedRight{at(10, 0), at(20, 0), at(20, 20), at(10, 20)};
    EXPECT_EQ(right.polygons[0].outer, expectedRight);

    EXPECT_EQ(shapes[2].id, "multi");
    ASSERT_EQ(shapes[2].polygons.size(), 2u);
    EXPECT_EQ(shapes[2].polygons[1].outer[0], at(50, 40));
    EXPECT_TRUE(shapes[3].polygons.empty()) << "a null geometry is a region without polygons";
    EXPECT_EQ(shapes[3].name, "Nowhere");
    ASSERT_EQ(shapes[4].polygons.size(), 1u) << "a nested collection's polygons form one region";
}

TEST(TopoJson, ReadsAbsoluteCoordinatesWithoutATransformAndDropsRepeatedPoints) {
    const char* text = R"({"type": "Topology", "objects": {"o": {"type": "GeometryCollection", "geometries": [
        {"type": "Polygon", "arcs": [[0]]}]}},
        "arcs": [[[1.5, 2.5], [3.5, 2.5], [3.5, 2.5], [3.5, 4.5], [1.5, 2.5]]]})";
    const auto r = parseTopoJson("abs.json", text).at("o");
    ASSERT_EQ(r.size(), 1u);
    const GeoRing expected{{1.5, 2.5}, {3.5, 2.5}, {3.5, 4.5}};
    EXPECT_EQ(r[0].polygons[0].outer, expected);
    EXPECT_TRUE(r[0].id.empty());
}

TEST(TopoJson, ReadsAFile) {
    const std::string path = ::testing::TempDir() + "sgkit_topo.json";
    std::ofstream(path) << kTopology;
    EXPECT_EQ(readTopoJson(path).at("shapes").size(), 5u);
    try {
        readTopoJson(path + ".missing");
        FAIL() << "a missing file must throw";
    } catch (const LoadError& e) {
        EXPECT_EQ(e.file(), path + ".missing");
    }
}

TEST(TopoJson, MalformedInputNamesTheJsonPathAndWhy) {
    const std::string t = kTopology;
    struct Case {
        std::string text, path, reason;
    };
    const Case cases[] = {
        {"[1, 2]", "", "a topology must be a JSON object"},
        {replaced(t, "\"Topology\"", "\"FeatureCollection\""), "type", "must be \"Topology\""},
        {replaced(t, "\"arcs\": [\n    [[10, 20]", "\"arcs\": 5, \"x\": [\n    [[10, 20]"), "arcs", "must be an array"},
        {replaced(t, "[[0, 2], [3]]", "[[0, 9], [3]]"), "objects.shapes.geometries[0].arcs[0][1]", "out of range"},
        {replaced(t, "[[1, -3]]", "[[1, -10]]"), "objects.shapes.geometries[1].arcs[0][1]", "out of range"},
        {replaced(t, "[[0, 2], [3]]", "[[0, 2.5], [3]]"), "objects.shapes.geometries[0].arcs[0][1]", "integer"},
        // JSON has no NaN or infinity: a number too large for a double is refused by the parser, and a finite
        // transform that overflows is refused where the first position does.
        {replaced(t, "[0.5, 0.5]", "[1e999, 0.5]"), "", "number overflow"},
        {replaced(t, "[0.5, 0.5]", "[1e308, 0.5]"), "arcs[0][0]", "non-finite"},
        {replaced(t, "[0.5, 0.5]", "[\"x\", 0.5]"), "transform.scale[0]", "must be a number"},
        {replaced(t, "[0.5, 0.5]", "[0, 0.5]"), "transform.scale", "must not be zero"},
        {replaced(t, "[[10, 0], [0, 20]]", "[[10, 0]]"), "arcs[2]", "at least two positions"},
        {replaced(t, "[[10, 0], [0, 20]]", "[[10, 0], [0]]"), "arcs[2][1]", "two numbers"},
        {replaced(t, "\"type\": \"MultiPolygon\"", "\"type\": \"Blob\""), "objects.shapes.geometries[2].type",
         "unknown geometry type"},
        {replaced(t, "{\"name\": \"Left\"}", "{\"name\": 3}"), "objects.shapes.geometries[0].properties.name",
         "must be a string"},
        {replaced(t, "\"id\": 7", "\"id\": [7]"), "objects.shapes.geometries[0].id", "string or a number"},
        {replaced(t, "\"arcs\": [[[4]], [[5]]]", "\"arcs\": [[4], [5]]"), "objects.shapes.geometries[2].arcs[0][0]",
         "must be an array"},
    };
    for (const Case& c : cases) {
        const LoadError e = errorOf(c.text);
        EXPECT_EQ(e.file(), "bad.json");
        EXPECT_EQ(e.jsonPath(), c.path) << e.what();
        EXPECT_NE(e.reason().find(c.reason), std::string::npos) << e.what();
    }
}

TEST(TopoJson, EveryTruncationIsRefusedWithALoadError) {
    const std::string t = kTopology;
    for (size_t n = 0; n < t.size(); n += 7) {
        try {
            parseTopoJson("cut.json", t.substr(0, n));
            ADD_FAILURE() << "a file cut at " << n << " parsed";
        } catch (const LoadError& e) {
            EXPECT_EQ(e.file(), "cut.json");
        }
    }
}

TEST(TopoJson, DeeplyNestedCollectionsAreRefused) {
    std::string g = R"({"type": "Polygon", "arcs": [[0]]})";
    for (int k = 0; k < 100; ++k) g = R"({"type": "GeometryCollection", "geometries": [)" + g + "]}";
    const std::string text = R"({"type": "Topology", "objects": {"o": {"type": "GeometryCollection", "geometries": [)" +
                             g + R"(]}}, "arcs": [[[0, 0], [1, 0], [1, 1], [0, 0]]]})";
    const LoadError e = errorOf(text);
    EXPECT_NE(e.reason().find("nested deeper than"), std::string::npos) << e.what();
}

TEST(TopoJson, RandomlyCorruptedFilesParseOrThrowLoadErrorOnly) {
    const std::string t = kTopology;
    const std::string alphabet = "0123456789-~[]{},:\"e.ntrufalsPolygonMultiArcs ";
    std::mt19937 rng(21);
    int refused = 0;
    for (int i = 0; i < 2000; ++i) {
        std::string s = t;
        const int edits = 1 + int(rng() % 3);
        for (int k = 0; k < edits; ++k) s[rng() % s.size()] = alphabet[rng() % alphabet.size()];
        try {
            for (const auto& [name, regions] : parseTopoJson("fuzz.json", s))
                for (const auto& r : regions)
                    for (const auto& p : r.polygons) EXPECT_GE(p.outer.size(), 3u) << name;
        } catch (const LoadError& e) {
            ++refused;
            EXPECT_EQ(e.file(), "fuzz.json");
        }
    }
    EXPECT_GT(refused, 100) << "the corruptions must reach the checks";
}
