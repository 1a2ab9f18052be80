// writeTileset: the written tileset.json read back with nlohmann-json and every content with loadGltf, against
// the scene: bounds, errors, counts, and what a reader draws from a set of eyes against what the graph draws.
#include "OutsideTools.h"
#include "loaders/gltf/Gltf.h"
#include "loaders/tiles/Tileset.h"
#include "loaders/tiles/TilesetWrite.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/PagedLOD.h"
#include "nodes/Transform.h"
#include "testbed/City.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <random>

using namespace sg;
using nlohmann::json;

namespace {

// The frame a node's children are in: a Transform's or an Instance's matrix applied.
dmat4 frameBelow(const Node& n, const dmat4& world) {
    if (n.kind() == NodeKind::Transform) return world * static_cast<const Transform&>(n).matrix();
    if (n.kind() == NodeKind::Instance) return world * static_cast<const Instance&>(n).matrix();
    return world;
}

namespace fs = std::filesystem;

std::string tempDir(const std::string& name) {
    const std::string d = ::testing::TempDir() + "sgkit_tileset_" + name;
    fs::remove_all(d);
    return d;
}

// The 3D Tiles reader's turn of glTF's +Y up to +Z up: (x, y, z) -> (x, -z, y).
const dmat4 kYupToZup(dvec4(1, 0, 0, 0), dvec4(0, 0, 1, 0), dvec4(0, -1, 0, 0), dvec4(0, 0, 0, 1));
// K of the default reference view (720 pixels, 60 degrees).
const double kPixelsPerRadian = 720.0 / (2.0 * std::tan(glm::radians(30.0)));

struct Counts {
    uint64_t all = 0, finest = 0;  // every LOD child; the finest child of each LOD only
    Box box;
};

void count(const Node& n, const dmat4& world, Counts& c) {
    if (n.kind() == NodeKind::Geometry) {
        const Mesh* m = static_cast<const Geometry&>(n).mesh();
        c.all += m->triangleCount();
        c.finest += m->triangleCount();
        c.box.expand(transformBox(world, m->box()));
        return;
    }
    const dmat4 w = frameBelow(n, world);
    for (size_t i = 0; i < n.numChildren(); ++i) {
        Counts sub;
        count(*n.child(i), w, sub);
        c.all += sub.all;
        c.box.expand(sub.box);
        if (n.kind() != NodeKind::LOD || i == 0) c.finest += sub.finest;  // the tests' LODs are finest first
    }
}

bool inside(const Box& inner, const Box& outer, double tol) {
    return glm::all(glm::greaterThanEqual(inner.min, outer.min - tol)) &&
           glm::all(glm::lessThanEqual(inner.max, outer.max + tol));
}

// What a distance LOD graph draws from `eye`: one entry per drawn Geometry, its triangle count and world bound
// centre (rounded to a millimetre), as the cull chooses (the LOD centre: given, or the world bound's).
using Drawn = std::multiset<std::tuple<uint32_t, long long, long long, long long>>;

void drawn(const Node& n, const dmat4& world, const dvec3& eye, Drawn& out) {
    if (n.kind() == NodeKind::Geometry) {
        const Mesh* m = static_cast<const Geometry&>(n).mesh();
        const dvec3 c = transformBox(world, m->box()).center();
        out.emplace(m->triangleCount(), std::llround(c.x * 1e3), std::llround(c.y * 1e3), std::llround(c.z * 1e3));
        return;
    }
    const dmat4 w = frameBelow(n, world);
    if (n.kind() == NodeKind::LOD) {
        const auto& lod = static_cast<const LOD&>(n);
        Counts c;
        count(lod, w, c);
        const dvec3 centre = lod.userCenter() ? dvec3(w * dvec4(lod.center(), 1.0)) : c.box.center();
        const double d = glm::length(eye - centre);
        for (size_t i = 0; i < lod.numChildren(); ++i)
            if (lod.range(i).min <= d && d < lod.range(i).max) drawn(*lod.child(i), w, eye, out);
        return;
    }
    for (size_t i = 0; i < n.numChildren(); ++i) drawn(*n.child(i), w, eye, out);
}

// A tile read back: its world frame (3D Tiles transforms chain from the root), box and content.
struct Tile {
    const json* j = nullptr;
    dmat4 world{1.0};
    Box box;  // world, axis-aligned (the writer's boxes are)
    ref_ptr<Node> content;
    std::vector<size_t> children;
};

struct Tileset {
    json doc;
    std::vector<Tile> tiles;  // 0 is the root
};

size_t readTile(Tileset& ts, const json& j, const dmat4& parent, const std::string& dir) {
    const size_t self = ts.tiles.size();
    ts.tiles.emplace_back();
    Tile t;
    t.j = &j;
    dmat4 m(1.0);
    if (j.contains("transform"))
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) m[c][r] = j["transform"][size_t(c * 4 + r)].get<double>();
    t.world = parent * m;
    const auto& b = j["boundingVolume"]["box"];
    EXPECT_EQ(b.size(), 12u);
    const dvec3 centre(b[0], b[1], b[2]);
    const dvec3 half(std::abs(double(b[3])) + std::abs(double(b[6])) + std::abs(double(b[9])),
                     std::abs(double(b[4])) + std::abs(double(b[7])) + std::abs(double(b[10])),
                     std::abs(double(b[5])) + std::abs(double(b[8])) + std::abs(double(b[11])));
    t.box = transformBox(t.world, Box{centre - half, centre + half});
    if (j.contains("content")) {
        const std::string path = dir + "/" + j["content"]["uri"].get<std::string>();
        EXPECT_TRUE(fs::is_regular_file(path)) << path;
        if (fs::is_regular_file(path)) t.content = loadGltf(path).root;
    }
    if (j.contains("children"))
        for (const json& c : j["children"]) t.children.push_back(readTile(ts, c, t.world, dir));
    ts.tiles[self] = std::move(t);
    return self;
}

Tileset readTileset(const std::string& dir) {
    Tileset ts;
    std::ifstream in(dir + "/tileset.json");
    EXPECT_TRUE(in.good());
    ts.doc = json::parse(in);
    EXPECT_EQ(ts.doc["asset"]["version"], "1.1");
    readTile(ts, ts.doc["root"], dmat4(1.0), dir);
    return ts;
}

// What a 3D Tiles reader with the reference view draws from `eye`: REPLACE refinement by screen-space error,
// the distance taken to the tile's box.
void drawnTiles(const Tileset& ts, size_t i, const dvec3& eye, double maxSSE, Drawn& out) {
    const Tile& t = ts.tiles[i];
    const dvec3 nearest = glm::clamp(eye, t.box.min, t.box.max);
    const double d = glm::length(eye - nearest);
    const double error = (*t.j)["geometricError"];
    const bool refine = !t.children.empty() && (d == 0.0 || error * kPixelsPerRadian / d > maxSSE);
    if (!refine) {
        if (t.content) drawn(*t.content, t.world * kYupToZup, eye, out);
        return;
    }
    for (size_t c : t.children) drawnTiles(ts, c, eye, maxSSE, out);
}

// The checks every written tileset passes against its scene.
void checkTileset(const Node& scene, const Tileset& ts, const TileWriteOptions& options) {
    Counts original;
    count(scene, dmat4(1.0), original);
    Counts leaves;
    const double tol = 1e-3;
    EXPECT_GT(ts.doc["geometricError"].get<double>(), ts.doc["root"]["geometricError"].get<double>());
    for (const Tile& t : ts.tiles) {
        const double error = (*t.j)["geometricError"];
        EXPECT_EQ((*t.j)["refine"], "REPLACE");
        for (size_t c : t.children) {
            EXPECT_TRUE(inside(ts.tiles[c].box, t.box, 1e-9)) << "a child's box leaves its parent's";
            EXPECT_LE((*ts.tiles[c].j)["geometricError"].get<double>(), error);
        }
        if (t.children.empty()) {
            EXPECT_EQ(error, 0.0);
        } else {
            EXPECT_GT(error, 0.0);
        }
        if (!t.content) continue;
        Counts c;
        count(*t.content, t.world * kYupToZup, c);
        EXPECT_TRUE(inside(c.box, t.box, tol)) << "a content leaves its tile's box";
        if (t.children.empty()) {
            EXPECT_LE(c.finest, options.maxTrianglesPerTile);
            leaves.all += c.all;
            leaves.box.expand(c.box);
        }
    }
    EXPECT_EQ(leaves.all, original.all);
    EXPECT_NEAR(glm::length(leaves.box.min - original.box.min), 0.0, tol);
    EXPECT_NEAR(glm::length(leaves.box.max - original.box.max), 0.0, tol);
}

TEST(TilesetWrite, CityPyramidHoldsTheSceneAndItsProxiesDropOnlyTheDetailedLevel) {
    const int n = 16;
    auto city = scenes::buildCity({n, false});
    const std::string dir = tempDir("city16");
    TileWriteOptions options;
    options.maxTrianglesPerTile = 20000;  // 16 cells a leaf: three levels
    const TileWriteReport r = writeTileset(*city, dir, options);
    EXPECT_GT(r.tiles, 5u);
    EXPECT_EQ(r.contents, r.tiles);
    const Tileset ts = readTileset(dir);
    EXPECT_EQ(ts.tiles.size(), r.tiles);
    checkTileset(*city, ts, options);
    // Inner tiles: the coarse building and the car of each cell below, nothing of the detailed level, and the
    // error that refines them within the detailed level's 250 m.
    size_t inner = 0;
    for (const Tile& t : ts.tiles) {
        if (t.children.empty()) continue;
        ++inner;
        Counts c, below;
        count(*t.content, dmat4(1.0), c);
        std::vector<size_t> stack = t.children;
        while (!stack.empty()) {
            const Tile& s = ts.tiles[stack.back()];
            stack.pop_back();
            if (s.children.empty()) count(*s.content, dmat4(1.0), below);
            stack.insert(stack.end(), s.children.begin(), s.children.end());
        }
        const uint64_t cells = below.all / (1200 + 12 + 12);
        EXPECT_EQ(c.all, cells * 24);
        EXPECT_NEAR((*t.j)["geometricError"].get<double>(), 16.0 * 250.0 / kPixelsPerRadian, 1e-9);
    }
    EXPECT_EQ(inner, 1u + 4u);
}

// What a reader of the tiles draws from `eye` is what the graph draws (expected); returns the tiles' draws.
Drawn expectSameDrawn(const Node& scene, const Tileset& ts, const TileWriteOptions& options, const dvec3& eye) {
    Drawn expected, got;
    drawn(scene, dmat4(1.0), eye, expected);
    drawnTiles(ts, 0, eye, options.maximumScreenSpaceError, got);
    EXPECT_EQ(got, expected) << "eye " << eye.x << " " << eye.y << " " << eye.z;
    return got;
}

TEST(TilesetWrite, AReaderDrawsWhatTheGraphDrawsFromAnyEye) {
    auto city = scenes::buildCity({16, false});
    const std::string dir = tempDir("city16eyes");
    TileWriteOptions options;
    options.maxTrianglesPerTile = 20000;
    writeTileset(*city, dir, options);
    const Tileset ts = readTileset(dir);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> xy(-600.0, 920.0), z(1.0, 300.0);
    int detailed = 0;  // eyes where the leaves' detailed level shows somewhere
    for (int k = 0; k < 200; ++k) {
        const Drawn got = expectSameDrawn(*city, ts, options, dvec3(xy(rng), xy(rng), z(rng)));
        detailed += std::any_of(got.begin(), got.end(), [](const auto& g) { return std::get<0>(g) == 1200; });
    }
    EXPECT_GT(detailed, 20);
    EXPECT_LT(detailed, 180);
}

// The city's repeated leaves are written as instances: its inner tiles are a few dozen glTF nodes instead of
// several per cell, its leaves fewer, and every tile draws what it drew written node by node.
TEST(TilesetWrite, RepeatedLeavesAreWrittenAsInstancesAndDrawTheSame) {
    auto city = scenes::buildCity({16, false});
    TileWriteOptions options;
    options.maxTrianglesPerTile = 20000;
    const std::string dirOn = tempDir("city16inst"), dirOff = tempDir("city16noinst");
    writeTileset(*city, dirOn, options);
    options.instancing = false;
    writeTileset(*city, dirOff, options);
    const Tileset on = readTileset(dirOn), off = readTileset(dirOff);
    ASSERT_EQ(on.tiles.size(), off.tiles.size());
    auto gltfNodes = [](const std::string& dir, const Tile& t) -> size_t {
        std::ifstream in(dir + "/" + (*t.j)["content"]["uri"].get<std::string>(), std::ios::binary);
        const std::string glb((std::istreambuf_iterator<char>(in)), {});
        uint32_t length = 0;
        std::memcpy(&length, glb.data() + 12, 4);
        return json::parse(glb.substr(20, length))["nodes"].size();
    };
    for (size_t i = 0; i < on.tiles.size(); ++i) {
        if (!on.tiles[i].content) continue;
        const size_t a = gltfNodes(dirOn, on.tiles[i]), b = gltfNodes(dirOff, off.tiles[i]);
        if (on.tiles[i].children.empty()) {
            EXPECT_LT(a, b);  // the cars are instanced; the buildings' LODs keep both levels, a node each
        } else {
            EXPECT_LT(a * 3, b);  // a node per building height and one for the cars (and the heights met once)
        }
    }
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> xy(-600.0, 920.0), z(1.0, 300.0);
    for (int k = 0; k < 60; ++k) {
        const dvec3 eye(xy(rng), xy(rng), z(rng));
        Drawn a, b;
        drawnTiles(on, 0, eye, options.maximumScreenSpaceError, a);
        drawnTiles(off, 0, eye, options.maximumScreenSpaceError, b);
        EXPECT_EQ(a, b) << "eye " << eye.x << " " << eye.y << " " << eye.z;
    }
}

// A tileset as loadTileset reads it, refined in full: each tile with children as its PagedLOD's world centre,
// radius and geometric error, sorted.
std::vector<std::array<double, 5>> refinedTiles(const std::string& file) {
    sg::Tileset ts = loadTileset(file);
    refineAll(*ts.root(), ts.loadFunction());
    std::vector<std::array<double, 5>> out;
    std::function<void(const Node&, const dmat4&)> walk = [&](const Node& n, const dmat4& parent) {
        const dmat4 world = frameBelow(n, parent);
        if (n.kind() == NodeKind::PagedLOD) {
            const auto& p = static_cast<const PagedLOD&>(n);
            const dvec3 c(world * dvec4(p.center(), 1.0));
            out.push_back({c.x, c.y, c.z, p.radius(), p.geometricError()});
        }
        for (size_t i = 0; i < n.numChildren(); ++i) walk(*n.child(i), world);
    };
    walk(*ts.root(), dmat4(1.0));
    // Centres a metre apart at least: rounding to a centimetre orders both tilesets alike.
    auto key = [](const std::array<double, 5>& t) {
        return std::make_tuple(std::llround(t[0] * 100), std::llround(t[1] * 100), std::llround(t[2] * 100), t[4]);
    };
    std::sort(out.begin(), out.end(), [&](const auto& a, const auto& b) { return key(a) < key(b); });
    return out;
}

// Implicit tiling holds the same tree: a tileset.json of one tile, and read back, every tile with children
// refines as the explicit tileset's does (from the same sphere, at the same error: the subtrees' metadata).
TEST(TilesetWrite, ImplicitTilingReadsAsTheSameTree) {
    auto city = scenes::buildCity({16, false});
    TileWriteOptions options;
    options.maxTrianglesPerTile = 20000;  // three levels: subtrees of two, the level-2 tiles each a subtree's root
    const std::string dirExplicit = tempDir("city16explicit"), dirImplicit = tempDir("city16implicit");
    const TileWriteReport e = writeTileset(*city, dirExplicit, options);
    options.implicit = true;
    const TileWriteReport i = writeTileset(*city, dirImplicit, options);
    EXPECT_EQ(i.tiles, e.tiles);
    EXPECT_EQ(i.contents, e.contents);
    EXPECT_TRUE(fs::is_regular_file(dirImplicit + "/subtrees/0/0/0.subtree"));
    EXPECT_TRUE(fs::is_regular_file(dirImplicit + "/subtrees/2/3/3.subtree"));
    EXPECT_TRUE(fs::is_regular_file(dirImplicit + "/tiles/2/3/3.glb"));

    std::ifstream in(dirImplicit + "/tileset.json");
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    EXPECT_EQ(text.find("\"children\""), std::string::npos);
    EXPECT_LT(text.size(), 2000u) << text;
    EXPECT_GT(fs::file_size(dirExplicit + "/tileset.json"), 5 * text.size());
    const json doc = json::parse(text);
    EXPECT_EQ(doc["root"]["implicitTiling"]["availableLevels"], 3);
    EXPECT_EQ(doc["schema"]["classes"]["tile"]["properties"]["boundingBox"]["semantic"], "TILE_BOUNDING_BOX");

    const auto want = refinedTiles(dirExplicit + "/tileset.json"), got = refinedTiles(dirImplicit + "/tileset.json");
    ASSERT_EQ(got.size(), want.size());
    EXPECT_EQ(got.size(), 5u);  // the root and the four level-1 tiles
    for (size_t k = 0; k < got.size(); ++k)
        for (size_t c = 0; c < 5; ++c) EXPECT_NEAR(got[k][c], want[k][c], 1e-9) << "tile " << k << ", value " << c;
}

// A glTF scene: LODs without a centre of their own, whose coarse level is much lower than the fine one, so that
// dropping the fine level would move the centre the cull switches by (by 9 m: the coarse level would vanish at
// other distances).
ref_ptr<Node> gltfScene(const std::string& dir) {
    auto root = make<Group>();
    auto fine = makeBoxMesh(dvec3(-4, 0, -4), dvec3(4, 20, 4), 8);
    auto coarse = makeBoxMesh(dvec3(-4, 0, -4), dvec3(4, 2, 4), 1);
    auto mat = make<Material>();
    for (int i = 0; i < 6; ++i)
        for (int k = 0; k < 6; ++k) {
            auto place = make<Transform>(glm::translate(dmat4(1.0), dvec3(30.0 * i + 5000.0, 0, -30.0 * k)));
            auto lod = make<LOD>();
            lod->addChild(make<Geometry>(fine, mat), 0.0f, 80.0f);
            lod->addChild(make<Geometry>(coarse, mat), 80.0f, 250.0f);
            place->addChild(lod);
            root->addChild(place);
        }
    fs::create_directories(dir);
    saveGltf(*root, dir + "/scene.glb");
    // As sgtile reads a glTF file: turned to +Z up.
    auto zUp = make<Transform>(kYupToZup);
    zUp->addChild(loadGltf(dir + "/scene.glb").root);
    return zUp;
}

TEST(TilesetWrite, GltfSceneKeepsItsLodCentresInTheProxies) {
    const std::string dir = tempDir("gltf");
    auto scene = gltfScene(dir + "_src");
    TileWriteOptions options;
    options.maxTrianglesPerTile = 3000;  // about 4 units a leaf
    writeTileset(*scene, dir, options);
    const Tileset ts = readTileset(dir);
    checkTileset(*scene, ts, options);
    ASSERT_FALSE(ts.tiles[0].children.empty());
    ASSERT_TRUE(ts.tiles[0].content);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> x(4700.0, 5500.0), y(-500.0, 300.0), z(0.0, 100.0);
    for (int k = 0; k < 200; ++k) {
        expectSameDrawn(*scene, ts, options, dvec3(x(rng), y(rng), z(rng)));
    }
}

TEST(TilesetWrite, SimplifiedProxiesHaveErrorsAndFewerTriangles) {
    auto city = scenes::buildCity({16, false});
    const std::string dir = tempDir("simplified");
    TileWriteOptions options;
    options.maxTrianglesPerTile = 20000;
    options.proxies = TileWriteOptions::Proxies::Simplified;
    writeTileset(*city, dir, options);
    const Tileset ts = readTileset(dir);
    checkTileset(*city, ts, options);
    for (const Tile& t : ts.tiles) {
        if (t.children.empty()) continue;
        ASSERT_TRUE(t.content);
        Counts c, below;
        count(*t.content, dmat4(1.0), c);
        for (size_t k : t.children) count(*ts.tiles[k].content, dmat4(1.0), below);
        EXPECT_LE(c.all, below.finest);
    }
}

TEST(TilesetWrite, RefusesImpossibleOptionsAndUnwritablePaths) {
    auto city = scenes::buildCity({2, false});
    TileWriteOptions bad;
    bad.maxTrianglesPerTile = 0;
    EXPECT_THROW(writeTileset(*city, tempDir("bad"), bad), std::invalid_argument);
    bad = {};
    bad.referenceFovYDegrees = 180.0;
    EXPECT_THROW(writeTileset(*city, tempDir("bad"), bad), std::invalid_argument);
    const std::string file = tempDir("file");
    std::ofstream(file) << "x";
    try {
        writeTileset(*city, file + "/out");
        FAIL() << "wrote below a file";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    }
}

// CesiumGS's 3d-tiles-tools traverse the tileset and read every content; the Khronos validator finds no error.
TEST(TilesetWrite, ThirdPartyToolsReadItAndTheGltfValidatorFindsNoError) {
#ifndef SGKIT_TILES_TOOLS
    GTEST_SKIP() << "no SGKIT_TILES_TOOLS: build the tiles-tools target";
#else
    const fs::path tool(SGKIT_TILES_TOOLS);
    const fs::path modules = tool.parent_path().parent_path();
    if (!fs::exists(tool) || !fs::exists(modules / "gltf-validator"))
        SG_SKIP_OR_FAIL(tool << " or gltf-validator absent: build the tiles-tools target");
    auto city = scenes::buildCity({16, false});
    // The explicit tileset, then the implicit one: the tools see the same tiles, with the same final geometric
    // errors and box sizes (the implicit tiles' from their metadata semantics, as the tools apply them).
    json explicitSummary;
    for (bool implicit : {false, true}) {
        const std::string dir = tempDir(implicit ? "tools_implicit" : "tools");
        TileWriteOptions options;
        options.maxTrianglesPerTile = 20000;
        options.implicit = implicit;
        const TileWriteReport r = writeTileset(*city, dir, options);
        const std::string out = dir + "_check.txt";
        const std::string cmd = "node '" SGKIT_SOURCE_DIR "/tests/loaders/tiles/check_tileset.mjs' '" +
                                modules.string() + "' '" + dir + "/tileset.json' > '" + out + "' 2>&1";
        const int status = std::system(cmd.c_str());
        std::ifstream in(out);
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        ASSERT_EQ(status, 0) << text;
        const json summary = json::parse(text);
        EXPECT_EQ(summary["tiles"], r.tiles);
        EXPECT_EQ(summary["contents"], r.contents);
        EXPECT_EQ(summary["errors"], 0);
        if (!implicit) {
            explicitSummary = summary;
        } else {
            EXPECT_EQ(summary["tiles"], explicitSummary["tiles"]);
            EXPECT_EQ(summary["finals"], explicitSummary["finals"]);
        }
    }
#endif
}

}  // namespace
