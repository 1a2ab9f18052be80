// Tile contents that fail to load: a missing or corrupt one (or a missing external tileset) is a warning and an
// empty tile, the rest of the tileset loads; over HTTP a 404 is final and a 500 fails the load until
// TilesetOptions::transientAttempts is reached.
#include "loaders/net/TileServer.h"
#include "loaders/tiles/Tileset.h"
#include "loaders/tiles/TilesetTestUtil.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

using namespace sg;
using namespace tilestest;

namespace {

// A tile over the quadrant (x, y) of [0, 100]^2 with `content` (and `more` JSON before it).
std::string quadrant(double x, double y, const std::string& content, const std::string& more = "") {
    return R"({"boundingVolume": {"box": [)" + std::to_string(x) + "," + std::to_string(y) +
           R"(,5, 25,0,0, 0,25,0, 0,0,5]}, "geometricError": 0, )" + more + R"("content": {"uri": ")" + content +
           R"("}})";
}

// A root (root.glb) refined into four tiles: q0.glb; missing.glb (no such file); corrupt.glb (a glb header, then
// random bytes); and missing.json (an external tileset that is not there) with a child of its own, q3.glb.
std::string faultyTileset(const TempDir& d) {
    writeBoxGlb(d / "root.glb", dvec3(0, 0, 0), dvec3(100, 100, 5));
    writeBoxGlb(d / "q0.glb", dvec3(5, 5, 0), dvec3(45, 45, 10));
    writeBoxGlb(d / "q3.glb", dvec3(55, 55, 0), dvec3(95, 95, 10));
    std::string corrupt = "glTF";
    corrupt += std::string("\x02\x00\x00\x00\x00\x01\x00\x00", 8);  // version 2, 256 bytes
    std::mt19937 random(7);
    while (corrupt.size() < 256) corrupt += char(random() & 0xff);
    writeText(d / "corrupt.glb", corrupt);
    const std::string children =
        quadrant(25, 25, "q0.glb") + "," + quadrant(75, 25, "missing.glb") + "," + quadrant(25, 75, "corrupt.glb") +
        "," + quadrant(75, 75, "missing.json", R"("children": [)" + quadrant(75, 75, "q3.glb") + R"(], )");
    writeText(d / "tileset.json", R"({"asset": {"version": "1.1"}, "geometricError": 100, "root": {
        "boundingVolume": {"box": [50,50,5, 50,0,0, 0,50,0, 0,0,5]}, "geometricError": 10, "refine": "REPLACE",
        "content": {"uri": "root.glb"}, "children": [)" +
                                      children + "]}}");
    return d / "tileset.json";
}

// The warning naming `path`; "" when none does.
std::string warningOf(const Tileset& ts, const std::string& path) {
    for (const std::string& w : ts.warnings())
        if (w.find(path + ":") != std::string::npos) return w;
    return "";
}

}  // namespace

TEST(TilesetFailures, MissingAndCorruptContentsAreWarningsAndTheRestLoads) {
    TempDir d;
    Tileset ts = loadTileset(faultyTileset(d));
    EXPECT_EQ(ts.counts().failed, 0u);                        // the children are not read yet
    EXPECT_EQ(refineAll(*ts.root(), ts.loadFunction()), 1u);  // the four, and the child of the missing one
    EXPECT_EQ(ts.counts().contents, 3u);                      // root.glb, q0.glb, q3.glb
    EXPECT_EQ(ts.counts().failed, 3u);

    const std::vector<TileFailure> f = ts.failures();
    ASSERT_EQ(f.size(), 3u);
    const char* paths[] = {"root.children[1].content.uri", "root.children[2].content.uri",
                           "root.children[3].content.uri"};
    const char* files[] = {"missing.glb", "corrupt.glb", "missing.json"};
    for (size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(f[i].file, d / "tileset.json");
        EXPECT_EQ(f[i].path, paths[i]);
        EXPECT_EQ(f[i].uri, d / files[i]);
        EXPECT_TRUE(f[i].final);
        EXPECT_EQ(f[i].attempts, 1u);
        const std::string w = warningOf(ts, paths[i]);
        EXPECT_NE(w.find(files[i]), std::string::npos) << w;
        EXPECT_NE(w.find(f[i].reason), std::string::npos) << w;
    }
    EXPECT_EQ(f[0].reason, "no such file");
    EXPECT_EQ(f[2].reason, "no such file");
    EXPECT_FALSE(f[1].reason.empty());

    // The root gave way to its children: q0 and the missing external tileset's child are drawn.
    Scene scene(ts.root());
    const Drawn dr = cullOnce(scene, lookingDownAt(dvec3(50, 50, 5), 500.0));
    EXPECT_EQ(dr.boxes, (std::multiset<std::pair<long, long>>{{5, 5}, {55, 55}}));
}

// The root tile's own content missing: the tileset loads without it; tileset.json missing is still refused.
TEST(TilesetFailures, AMissingRootContentIsAWarningAndAMissingTilesetIsRefused) {
    TempDir d;
    quadTileset(d);
    std::filesystem::remove(d / "root.glb");
    Tileset ts = loadTileset(d / "tileset.json");
    ASSERT_EQ(ts.failures().size(), 1u);
    EXPECT_EQ(ts.failures()[0].path, "root.content.uri");
    EXPECT_NE(warningOf(ts, "root.content.uri").find("no such file"), std::string::npos);
    EXPECT_EQ(refineAll(*ts.root(), ts.loadFunction()), 1u);
    EXPECT_EQ(ts.counts().contents, 4u);
    EXPECT_THROW(loadTileset(d / "missing.json"), LoadError);
}

// Over HTTP: a 404 is final at once; a 500 fails the load (the pager would ask again) until its last attempt,
// after which it is final too and the load brings the other tiles.
TEST(TilesetFailures, A404IsFinalAndA500FailsTheLoadUntilItsLastAttempt) {
    TempDir d;
    const std::string file = quadTileset(d);
    replaceInFile(file, "\"q1.glb\"", "\"status/404/q1.glb\"");
    replaceInFile(file, "\"q2.glb\"", "\"status/500/q2.glb\"");
    testutil::TileServer server(d.path);
    TilesetOptions options;
    options.transientAttempts = 2;
    Tileset ts = loadTileset(server.url("/tileset.json"), options);
    const PageLoadFunction load = ts.loadFunction();
    try {
        refineAll(*ts.root(), load);
        ADD_FAILURE() << "the load holding a 500 succeeded at its first attempt";
    } catch (const LoadError& e) {
        EXPECT_EQ(e.file(), server.url("/status/500/q2.glb"));
        EXPECT_EQ(e.reason().rfind("HTTP 500", 0), 0u) << e.what();
    }
    std::vector<TileFailure> f = ts.failures();
    ASSERT_EQ(f.size(), 2u);
    EXPECT_EQ(f[0].path, "root.children[1].content.uri");
    EXPECT_TRUE(f[0].final);
    EXPECT_EQ(f[0].reason, "HTTP 404 Not Found");
    EXPECT_EQ(f[1].path, "root.children[2].content.uri");
    EXPECT_FALSE(f[1].final);
    EXPECT_TRUE(warningOf(ts, "root.children[2].content.uri").empty());  // not given up yet

    // The second attempt: the 500 is given up, the load succeeds with the two good tiles.
    EXPECT_EQ(refineAll(*ts.root(), load), 1u);
    f = ts.failures();
    ASSERT_EQ(f.size(), 2u);
    EXPECT_TRUE(f[1].final);
    EXPECT_EQ(f[1].attempts, 2u);
    EXPECT_NE(warningOf(ts, "root.children[2].content.uri").find("HTTP 500"), std::string::npos);
    EXPECT_EQ(f[0].attempts, 2u);  // asked again with its load, and warned of once
    const std::vector<std::string> warnings = ts.warnings();
    EXPECT_EQ(std::count_if(warnings.begin(), warnings.end(),
                            [](const std::string& w) { return w.find("status/404/q1.glb") != std::string::npos; }),
              1);
    Scene scene(ts.root());
    const Drawn dr = cullOnce(scene, lookingDownAt(dvec3(50, 50, 5), 500.0));
    EXPECT_EQ(dr.boxes, (std::multiset<std::pair<long, long>>{{5, 5}, {55, 55}}));

    // refineAll with the tileset's attempts goes through in one call.
    Tileset again = loadTileset(server.url("/tileset.json"), options);
    EXPECT_EQ(refineAll(*again.root(), again.loadFunction(), options.transientAttempts), 1u);
    EXPECT_EQ(again.counts().failed, 2u);
}
