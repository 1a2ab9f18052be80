// The map's levels: prisms (top facing up, walls facing out), region properties through a .glb round trip,
// the generated stand-in map's layout, and, when the source data has been fetched (tools/fetch-map-data.sh),
// the whole conversion: every country, state and county present, triangle areas equal to polygon areas.
#include "OutsideTools.h"
#include "map/data/MapConvert.h"
#include "map/data/TopoJson.h"
#include "nodes/Geometry.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>

using namespace sg;
namespace fs = std::filesystem;

namespace {

std::string tempDir(const std::string& name) {
    const fs::path p = fs::path(::testing::TempDir()) / ("sgkit_map_" + name);
    fs::remove_all(p);
    fs::create_directories(p);
    return p.string();
}

// Where the source data is: $SGKIT_MAP_SOURCE, else the build tree's mapdata/source.
std::string sourceDir() {
    if (const char* e = std::getenv("SGKIT_MAP_SOURCE")) return e;
    return SGKIT_MAP_SOURCE_DIR;
}
bool haveSource() {
    return fs::exists(fs::path(sourceDir()) / "countries-50m.json") &&
           fs::exists(fs::path(sourceDir()) / "counties-10m.json");
}
#define SKIP_WITHOUT_SOURCE()                                                                                  \
    if (!haveSource())                                                                                         \
    SG_SKIP_OR_FAIL("no map source data in "                                                                   \
                    << sourceDir()                                                                             \
                    << " (run tools/fetch-map-data.sh there, or cmake --build BUILD --target map-data; needs " \
                       "the network)")

const Geometry& geometry(const Node& n) {
    EXPECT_EQ(n.kind(), NodeKind::Geometry);
    return static_cast<const Geometry&>(n);
}

// Regions of a loaded level: id (the name when the source has no id) -> properties.
std::map<std::string, GltfProperties> regions(const GltfScene& s) {
    std::map<std::string, GltfProperties> out;
    for (size_t i = 0; i < s.root->numChildren(); ++i) {
        auto it = s.properties.find(s.root->child(i));
        EXPECT_NE(it, s.properties.end()) << "region node " << i << " has no properties";
        if (it == s.properties.end()) continue;
        const std::string& id = it->second.strings.at("id");
        out[id.empty() ? it->second.strings.at("name") : id] = it->second;
    }
    return out;
}

}  // namespace

TEST(MapConvert, RegionsBecomePrismsWithTopsUpAndWallsOut) {
    GeoRegion a{"1", "Square", {{{{0, 0}, {10, 0}, {10, 10}, {0, 10}}, {{{4, 4}, {4, 6}, {6, 6}, {6, 4}}}}}};
    GeoRegion b{"2", "Clockwise", {{{{20, 0}, {20, 10}, {30, 10}, {30, 0}}, {}}}};
    MapLevelOptions o;
    o.kind = "state";
    o.height = 3.0;
    o.children = {{"2", "states/2.glb"}};
    const MapLevel level = buildMapLevel({a, b}, {96.0, 100.0}, o);
    ASSERT_EQ(level.root->numChildren(), 2u);
    EXPECT_EQ(level.regions, 2u);
    EXPECT_EQ(level.emptyRegions, 0u);
    EXPECT_LT(level.maxAreaError, 1e-12);
    for (size_t r = 0; r < 2; ++r) {
        const Mesh& m = *geometry(*level.root->child(r)).mesh();
        const glm::dvec2 centre = r == 0 ? glm::dvec2(5, 5) : glm::dvec2(25, 5);
        double top = 0.0;
        for (uint32_t t = 0; t < m.triangleCount(); ++t) {
            const vec3 p0 = m.positions()[m.index(3 * t)], p1 = m.positions()[m.index(3 * t + 1)],
                       p2 = m.positions()[m.index(3 * t + 2)];
            const vec3 face = glm::cross(p1 - p0, p2 - p0);
            const vec3 n = m.normals()[m.index(3 * t)];
            EXPECT_GT(glm::dot(face, n), -1e-6f) << "triangle " << t << " winds against its normal";
            if (n.z > 0.5f) {
                EXPECT_EQ(p0.z, 3.0f);
                top += face.z / 2.0;
            } else {
                // A wall on an outer edge faces away from the centre; one on the hole's edge faces into the hole.
                const glm::dvec2 mid((p0.x + p1.x + p2.x) / 3.0, (p0.y + p1.y + p2.y) / 3.0);
                const bool holeWall = r == 0 && std::abs(mid.x - 5) < 1.01 && std::abs(mid.y - 5) < 1.01;
                const double out = glm::dot(glm::dvec2(n.x, n.y), mid - centre);
                EXPECT_TRUE(holeWall ? out < 0 : out > 0) << "region " << r << " wall " << t;
            }
        }
        EXPECT_NEAR(top, r == 0 ? 96.0 : 100.0, 1e-9);
    }
    const auto& props = level.properties.at(level.root->child(1));
    EXPECT_EQ(props.strings.at("name"), "Clockwise");
    EXPECT_EQ(props.strings.at("kind"), "state");
    EXPECT_EQ(props.strings.at("child"), "states/2.glb");
    EXPECT_EQ(props.numbers.at("area_km2"), 100.0);
    EXPECT_EQ(level.properties.at(level.root->child(0)).strings.count("child"), 0u);
}

// A border along a parallel is a straight run in degrees, where the region is triangulated, and an arc bending
// into the region once projected by the conic: the top faces cover the region up to the arc, not the chords of
// flat ears turned over.
TEST(MapConvert, TopFacesStopAtABorderAlongAParallel) {
    GeoRing ring{{-110.0, 45.0}, {-90.0, 45.0}};
    for (double lon = -90.0; lon >= -110.0; lon -= 0.25) ring.push_back({lon, 49.0});
    const GeoRegion r{"1", "North", {{ring, {}}}};
    const MapProjection p = MapProjection::usState("48");
    MapLevelOptions o;  // the region as the converter gives it: longitudes about the projection's centre
    const MapLevel level = buildMapLevel({p.cutAtEdge(r)}, {1.0}, o, {p});
    EXPECT_TRUE(level.problems.empty()) << level.problems.front();
    const Mesh& m = *geometry(*level.root->child(0)).mesh();
    auto covering = [&](double lon, double lat) {
        const glm::dvec2 q = p.project(lon, lat);
        int n = 0;
        for (uint32_t t = 0; t < m.triangleCount(); ++t) {
            glm::dvec2 v[3];
            bool top = true;
            for (int k = 0; k < 3; ++k) {
                const vec3 a = m.positions()[m.index(3 * t + k)];
                v[k] = glm::dvec2(a.x, a.y);
                top = top && m.normals()[m.index(3 * t + k)].z > 0.5f;
            }
            if (!top) continue;
            double s[3];
            for (int k = 0; k < 3; ++k) {
                const glm::dvec2 e = v[(k + 1) % 3] - v[k], f = q - v[k];
                s[k] = e.x * f.y - e.y * f.x;
            }
            n += (s[0] >= 0 && s[1] >= 0 && s[2] >= 0) || (s[0] <= 0 && s[1] <= 0 && s[2] <= 0);
        }
        return n;
    };
    // 1.1 km either side of the parallel (the chords between the run's points sag under 0.3 km).
    for (double lon = -109.9; lon < -90.0; lon += 0.5) {
        EXPECT_EQ(covering(lon, 49.01), 0) << lon;
        EXPECT_EQ(covering(lon, 48.99), 1) << lon;
    }
}

TEST(MapConvert, HeightMayEncodeArea) {
    GeoRegion small{"s", "", {{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {}}}};
    GeoRegion big{"b", "", {{{{0, 0}, {4, 0}, {4, 4}, {0, 4}}, {}}}};
    MapLevelOptions o;
    o.height = 8.0;
    o.heightEncodesArea = true;
    const MapLevel level = buildMapLevel({small, big}, {1.0, 16.0}, o);
    auto height = [&](size_t i) { return geometry(*level.root->child(i)).mesh()->box().max.z; };
    EXPECT_FLOAT_EQ(height(1), 8.0f);
    EXPECT_FLOAT_EQ(height(0), 8.0f * (0.25f + 0.75f * 0.25f));
}

TEST(MapConvert, TheWrittenLevelLoadsBackWithItsProperties) {
    GeoRegion a{"48201", "Harris", {{{{0, 0}, {10, 0}, {10, 10}, {0, 10}}, {}}}};
    MapLevelOptions o;
    o.kind = "county";
    const MapLevel level = buildMapLevel({a}, {1777.5}, o);
    const std::string path = tempDir("roundtrip") + "/level.glb";
    writeMapLevel(level, path, {{{"level", "state"}, {"parent", "48"}}, {{"version", 2.0}}});
    const GltfScene s = loadGltf(path);
    ASSERT_EQ(s.root->numChildren(), 1u);
    const Node* n = s.root->child(0);
    EXPECT_EQ(n->name(), "Harris");
    const GltfProperties& p = s.properties.at(n);
    EXPECT_EQ(p.strings.at("id"), "48201");
    EXPECT_EQ(p.strings.at("name"), "Harris");
    EXPECT_EQ(p.strings.at("kind"), "county");
    EXPECT_DOUBLE_EQ(p.numbers.at("area_km2"), 1777.5);
    EXPECT_EQ(s.sceneProperties.strings.at("parent"), "48");
    EXPECT_EQ(s.sceneProperties.numbers.at("version"), 2.0);
    EXPECT_EQ(geometry(*n).mesh()->triangleCount(), geometry(*level.root->child(0)).mesh()->triangleCount());
}

TEST(MapConvert, GeneratedMapHasTheLayoutOfTheRealOne) {
    const std::string dir = tempDir("generated");
    const MapConvertReport r = generateFallbackMap(dir, 3);
    EXPECT_EQ(r.emptyRegions, 0u);
    EXPECT_LT(r.maxAreaError, 1e-9);
    EXPECT_TRUE(r.problems.empty());
    const GltfScene world = loadGltf(dir + "/world.glb");
    const auto countries = regions(world);
    ASSERT_TRUE(countries.count("840"));
    EXPECT_EQ(countries.at("840").strings.at("child"), "us.glb");
    EXPECT_EQ(countries.at("840").strings.at("kind"), "country");
    EXPECT_EQ(world.sceneProperties.strings.at("source"), "generated");
    const auto states = regions(loadGltf(dir + "/us.glb"));
    EXPECT_GE(states.size(), 10u);
    size_t counties = 0;
    for (const auto& [id, p] : states) {
        const std::string child = dir + "/" + p.strings.at("child");
        ASSERT_TRUE(fs::exists(child)) << child;
        const GltfScene s = loadGltf(child);
        EXPECT_EQ(s.sceneProperties.strings.at("parent"), id);
        for (const auto& [cid, cp] : regions(s)) {
            EXPECT_EQ(cid.substr(0, id.size()), id) << "a county's id starts with its state's";
            EXPECT_GT(cp.numbers.at("area_km2"), 0.0);
            ++counties;
        }
    }
    EXPECT_GT(counties, 5 * states.size());
    EXPECT_EQ(r.files, 2 + states.size());
    // Fixed seed: the same bytes again.
    const std::string again = tempDir("generated_again");
    generateFallbackMap(again, 3);
    std::ifstream f1(dir + "/states/01.glb", std::ios::binary), f2(again + "/states/01.glb", std::ios::binary);
    const std::string b1((std::istreambuf_iterator<char>(f1)), {}), b2((std::istreambuf_iterator<char>(f2)), {});
    EXPECT_FALSE(b1.empty());
    EXPECT_EQ(b1, b2);
}

TEST(MapConvertRealData, SourceHoldsEveryCountryStateAndCounty) {
    SKIP_WITHOUT_SOURCE();
    const auto world = readTopoJson(sourceDir() + "/countries-50m.json");
    const auto us = readTopoJson(sourceDir() + "/counties-10m.json");
    EXPECT_EQ(world.at("countries").size(), 241u);
    EXPECT_EQ(us.at("states").size(), 56u);
    EXPECT_EQ(us.at("counties").size(), 3231u);
    // Every county has polygons but Falls Church, VA, which the 10m quantization has made a line.
    for (const auto& c : us.at("counties")) EXPECT_EQ(c.polygons.empty(), c.id == "51610") << c.id;
}

TEST(MapConvertRealData, EveryRegionIsTriangulatedWithItsArea) {
    SKIP_WITHOUT_SOURCE();
    const std::string out = tempDir("real");
    const MapConvertReport r = convertMapData(sourceDir(), out);
    EXPECT_EQ(r.regions, 241u + 56u + 3231u) << "no region dropped";
    EXPECT_EQ(r.emptyRegions, 0u);
    EXPECT_LE(r.maxAreaError, 1e-6) << r.worst;
    for (const auto& p : r.problems) ADD_FAILURE() << p;
    // One county is a line in the source (Falls Church, VA, at 10m quantization): kept, without a top face.
    ASSERT_EQ(r.withoutArea.size(), 1u);
    EXPECT_NE(r.withoutArea[0].find("51610"), std::string::npos) << r.withoutArea[0];
    EXPECT_EQ(r.files, 2u + 56u);

    // Texas: 254 counties, Harris among them, its area about 4,600 km^2 (the Census gives 4,602 with water).
    const GltfScene tx = loadGltf(out + "/states/48.glb");
    const auto counties = regions(tx);
    EXPECT_EQ(counties.size(), 254u);
    ASSERT_TRUE(counties.count("48201"));
    EXPECT_EQ(counties.at("48201").strings.at("name"), "Harris");
    EXPECT_NEAR(counties.at("48201").numbers.at("area_km2"), 4600.0, 150.0);
    EXPECT_EQ(tx.sceneProperties.strings.at("parent"), "48");

    // The U.S. file: every state leads to a file that exists; Texas's area about 696,000 km^2.
    const auto states = regions(loadGltf(out + "/us.glb"));
    EXPECT_EQ(states.size(), 56u);
    for (const auto& [id, p] : states) EXPECT_TRUE(fs::exists(out + "/" + p.strings.at("child"))) << id;
    EXPECT_NEAR(states.at("48").numbers.at("area_km2"), 696000.0, 0.02 * 696000.0);

    // Insets: no state or territory moved beside the conterminous ones overlaps any other state's bounds.
    const GltfScene usScene = loadGltf(out + "/us.glb");
    const std::set<std::string> moved{"02", "15", "60", "66", "69", "72", "78"};
    std::map<std::string, Box> boxes;
    for (size_t i = 0; i < usScene.root->numChildren(); ++i)
        boxes[usScene.properties.at(usScene.root->child(i)).strings.at("id")] =
            geometry(*usScene.root->child(i)).mesh()->box();
    for (const auto& [a, ba] : boxes)
        for (const auto& [b, bb] : boxes) {
            if (a >= b || (!moved.count(a) && !moved.count(b))) continue;
            if ((a == "66" && b == "69") || (a == "72" && b == "78")) continue;  // drawn together, as they lie
            const bool overlap =
                ba.min.x <= bb.max.x && bb.min.x <= ba.max.x && ba.min.y <= bb.max.y && bb.min.y <= ba.max.y;
            EXPECT_FALSE(overlap) << a << " and " << b;
        }

    // Each state's counties lie on the state's prism: the same bounds in the plane (the files share coordinates).
    for (const auto& [id, box] : boxes) {
        const GltfScene s = loadGltf(out + "/states/" + id + ".glb");
        Box counties;
        for (size_t i = 0; i < s.root->numChildren(); ++i) counties.expand(geometry(*s.root->child(i)).mesh()->box());
        EXPECT_NEAR(counties.min.x, box.min.x, 0.5) << id;
        EXPECT_NEAR(counties.min.y, box.min.y, 0.5) << id;
        EXPECT_NEAR(counties.max.x, box.max.x, 0.5) << id;
        EXPECT_NEAR(counties.max.y, box.max.y, 0.5) << id;
    }

    // The world: the United States leads to the U.S. file; no triangle of Russia or Fiji spans the map (they
    // cross the antimeridian: each is cut there).
    const GltfScene world = loadGltf(out + "/world.glb");
    const auto countries = regions(world);
    EXPECT_EQ(countries.size(), 240u) << "241 countries; Australia's id 036 is also Ashmore and Cartier's";
    EXPECT_EQ(countries.at("840").strings.at("child"), "us.glb");
    EXPECT_NEAR(countries.at("643").numbers.at("area_km2"), 17.1e6, 0.03 * 17.1e6) << "Russia";
    const double width = 2 * MapProjection::world().project(180, 0).x;
    for (size_t i = 0; i < world.root->numChildren(); ++i) {
        const std::string id = world.properties.at(world.root->child(i)).strings.at("id");
        if (id != "643" && id != "242") continue;
        const Mesh& m = *geometry(*world.root->child(i)).mesh();
        float widest = 0.0f;
        for (uint32_t t = 0; t < m.triangleCount(); ++t) {
            float lo = 1e30f, hi = -1e30f;
            for (int k = 0; k < 3; ++k) {
                lo = std::min(lo, m.positions()[m.index(3 * t + k)].x);
                hi = std::max(hi, m.positions()[m.index(3 * t + k)].x);
            }
            widest = std::max(widest, hi - lo);
        }
        EXPECT_LT(widest, 0.5 * width) << world.root->child(i)->name();
    }
}
