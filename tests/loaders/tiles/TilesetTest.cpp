// sg::loadTileset: tileset.json into paged nodes, the refinement rules (screen-space error, REPLACE and ADD,
// no holes), transforms and glTF's +Y up, external tilesets, and bad input refused by name.
#include "TestUtil.h"
#include "loaders/net/TileServer.h"
#include "loaders/tiles/Tileset.h"
#include "loaders/tiles/TilesetTestUtil.h"
#include "loaders/tiles/internal/SharedMeshes.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/PagedLOD.h"
#include "nodes/Transform.h"
#include "sg/core/NodeVisitor.h"
#include "sg/cull/CullTraversal.h"

#include <gtest/gtest.h>

#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>

using namespace sg;
using namespace tilestest;
namespace fs = std::filesystem;

TEST(Tileset, RootContentIsReadAndTurnedZUp) {
    TempDir d;
    Tileset ts = loadTileset(quadTileset(d));
    ASSERT_TRUE(ts.root());
    EXPECT_EQ(ts.counts().tiles, 5u);
    EXPECT_EQ(ts.counts().contents, 1u);  // the root's only: the children page
    Scene scene(ts.root());
    scene.update(FrameInfo{1, 0.0});
    // The root content's box comes back +Z up (x, y in [0, 100], z in [0, 5]); the bound also holds the
    // children's volume (the PagedLOD's sphere).
    const Box b = scene.image().box(0);
    EXPECT_LE(b.min.z, 0.0 + 1e-9);
    EXPECT_GE(b.max.z, 5.0 - 1e-9);
    EXPECT_LE(b.min.x, 0.0 + 1e-9);
    EXPECT_GE(b.max.y, 100.0 - 1e-9);
}

// A tile refines while its geometric error at the eye's distance to its sphere projects to more than 16
// pixels: for a 400x300 view at 60 degrees, 259.8 pixels per unit at distance 1, so an error of 10 refines
// closer than 10 * 259.8 / 16 = 162.4 units from the sphere (radius 71.1 about (50, 50, 5)).
TEST(Tileset, RefinesByScreenSpaceError) {
    TempDir d;
    Tileset ts = loadTileset(quadTileset(d));
    Scene scene(ts.root());
    const double ppu = 300.0 / (2.0 * std::tan(glm::radians(30.0)));
    const double reach = 10.0 * ppu / 16.0 + std::sqrt(50.0 * 50 + 50 * 50 + 5 * 5);
    const dvec3 centre(50, 50, 5);
    Drawn farther = cullOnce(scene, lookingDownAt(centre, reach * 1.01), 1);
    EXPECT_EQ(farther.stats.pagedWanted, 0u);
    EXPECT_EQ(farther.boxes.size(), 1u);  // the root's content
    Drawn nearer = cullOnce(scene, lookingDownAt(centre, reach * 0.99), 2);
    EXPECT_EQ(nearer.stats.pagedWanted, 1u);
    EXPECT_EQ(nearer.stats.pagedRequested, 1u);
    EXPECT_EQ(nearer.stats.pagedCoarse, 1u);  // not loaded: the root's content stays
    EXPECT_EQ(nearer.boxes.size(), 1u);
}

// REPLACE: once the children are attached the root's content gives way; until then (the load gated) it stays.
TEST(Tileset, ReplaceKeepsTheParentUntilEveryChildIsLoaded) {
    TempDir d;
    Tileset ts = loadTileset(quadTileset(d));
    Scene scene(ts.root());
    std::mutex m;
    std::condition_variable cv;
    bool open = false;
    PageLoadFunction inner = ts.loadFunction();
    Pager pager(scene, [&](const PageSource& f) {
        std::unique_lock<std::mutex> lock(m);
        cv.wait(lock, [&] { return open; });
        return inner(f);
    });
    const Camera cam = lookingDownAt(dvec3(50, 50, 5), 100.0);
    for (uint64_t f = 1; f <= 3; ++f) {
        pager.update(FrameInfo{f, double(f)});
        Drawn dr = cullOnce(scene, cam, f);
        ASSERT_EQ(dr.boxes.size(), 1u) << "frame " << f;  // the root's content, never a hole
        EXPECT_EQ(dr.boxes.count({0, 0}), 1u);
    }
    {
        std::lock_guard<std::mutex> lock(m);
        open = true;
    }
    cv.notify_all();
    pager.waitIdle();
    pager.update(FrameInfo{4, 4.0});
    Drawn dr = cullOnce(scene, cam, 4);
    EXPECT_EQ(dr.boxes.size(), 4u);  // the four children, the root's content gone
    EXPECT_EQ(dr.boxes.count({5, 5}), 1u);
    EXPECT_EQ(dr.boxes.count({55, 55}), 1u);
    EXPECT_EQ(dr.boxes.count({0, 0}), 0u);
    EXPECT_EQ(ts.counts().contents, 5u);
}

TEST(Tileset, RefineAllShowsReplaceChildrenAndKeepsAddParents) {
    for (const std::string refine : {"REPLACE", "ADD"}) {
        TempDir d;
        Tileset ts = loadTileset(quadTileset(d, refine));
        EXPECT_EQ(refineAll(*ts.root(), ts.loadFunction()), 1u);
        Scene scene(ts.root());
        // Far away: refined whatever the error.
        Drawn dr = cullOnce(scene, lookingDownAt(dvec3(50, 50, 5), 5000.0));
        EXPECT_EQ(dr.boxes.count({0, 0}), refine == "ADD" ? 1u : 0u) << refine;
        EXPECT_EQ(dr.boxes.size(), refine == "ADD" ? 5u : 4u) << refine;
    }
}

TEST(Tileset, TransformsChain) {
    TempDir d;
    writeBoxGlb(d / "a.glb", dvec3(0), dvec3(1));
    writeText(d / "tileset.json", R"({"asset": {"version": "1.0"}, "geometricError": 10, "root": {
        "transform": [1,0,0,0, 0,1,0,0, 0,0,1,0, 1000,0,0,1], "refine": "ADD",
        "boundingVolume": {"sphere": [0,0,0,10]}, "geometricError": 5, "children": [{
            "transform": [2,0,0,0, 0,2,0,0, 0,0,2,0, 0,50,0,1],
            "boundingVolume": {"sphere": [0,0,0,2]}, "geometricError": 0, "content": {"uri": "a.glb"}}]}})");
    Tileset ts = loadTileset(d / "tileset.json");
    refineAll(*ts.root(), ts.loadFunction());
    Scene scene(ts.root());
    scene.update(FrameInfo{1, 0.0});
    // The child's box [0, 1]^3 scaled by 2 and moved by (1000, 50, 0).
    const Box b = scene.image().box(0);
    EXPECT_NEAR(b.min.x, 1000.0 - 10.0, 1e-3);  // the root's sphere holds x from 990 (bounds are float)
    Drawn dr = cullOnce(scene, lookingDownAt(dvec3(1001, 51, 0), 50.0));
    ASSERT_EQ(dr.boxes.size(), 1u);
    EXPECT_EQ(*dr.boxes.begin(), std::make_pair(1000l, 50l));
}

// A tile's PagedLOD names its tileset file and the tile's index (no key written into the name and parsed back);
// the load function refuses an index the tileset does not have.
TEST(Tileset, ATilesPagedNodeCarriesItsTileToTheLoadFunction) {
    TempDir d;
    Tileset ts = loadTileset(quadTileset(d));
    struct Find : NodeVisitor {
        std::vector<PagedLOD*> paged;
        void apply(PagedLOD& p) override {
            paged.push_back(&p);
            traverse(p);
        }
    } find;
    ts.root()->accept(find);
    ASSERT_EQ(find.paged.size(), 1u);
    const PagedLOD& root = *find.paged[0];
    EXPECT_EQ(root.file(), d / "tileset.json");
    EXPECT_EQ(root.part(), 0u);  // the root tile
    const PageLoadFunction load = ts.loadFunction();
    const ref_ptr<Node> children = load(PageSource{root.file(), root.part()});
    ASSERT_TRUE(children);
    EXPECT_EQ(children->numChildren(), 4u);
    try {
        load(PageSource{root.file(), 999});
        ADD_FAILURE() << "tile 999 was loaded";
    } catch (const LoadError& e) {
        EXPECT_NE(e.reason().find("tile 999 is not in the tileset"), std::string::npos) << e.what();
    }
}

TEST(Tileset, ExternalTilesetsAreReadAndCyclesRefused) {
    TempDir d;
    quadTileset(d);
    fs::rename(d / "tileset.json", d / "inner.json");
    writeText(d / "tileset.json", R"({"asset": {"version": "1.1"}, "geometricError": 100, "root": {
        "boundingVolume": {"box": [50,50,5, 50,0,0, 0,50,0, 0,0,5]}, "geometricError": 100, "refine": "REPLACE",
        "content": {"uri": "inner.json"}}})");
    Tileset ts = loadTileset(d / "tileset.json");
    EXPECT_EQ(ts.counts().externalTilesets, 1u);
    EXPECT_EQ(ts.counts().tiles, 6u);
    refineAll(*ts.root(), ts.loadFunction());
    Scene scene(ts.root());
    EXPECT_EQ(cullOnce(scene, lookingDownAt(dvec3(50, 50, 5), 500.0)).boxes.size(), 4u);

    // inner.json naming tileset.json again: that content is refused (a failed tile), the rest is read.
    writeText(d / "inner.json", R"({"asset": {"version": "1.1"}, "geometricError": 100, "root": {
        "boundingVolume": {"sphere": [0,0,0,1]}, "geometricError": 1, "content": {"uri": "tileset.json"}}})");
    const Tileset cycle = loadTileset(d / "tileset.json");
    ASSERT_EQ(cycle.failures().size(), 1u);
    EXPECT_EQ(cycle.failures()[0].file, d / "inner.json");
    EXPECT_EQ(cycle.failures()[0].path, "root.content.uri");
    EXPECT_NE(cycle.failures()[0].reason.find("refers back to itself"), std::string::npos)
        << cycle.failures()[0].reason;
}

// Bad tileset.json: refused with the file, the JSON path and the reason.
TEST(Tileset, BadTilesetsAreRefusedByName) {
    struct Case {
        const char* root;
        const char* path;
        const char* reason;
    };
    const Case cases[] = {
        {R"({"boundingVolume": {"sphere": [0,0,0,1]}})", "root.geometricError", "missing"},
        {R"({"boundingVolume": {"sphere": [0,0,0,1]}, "geometricError": "x"})", "root.geometricError", "number"},
        {R"({"boundingVolume": {"sphere": [0,0,0,-1]}, "geometricError": 1})", "root.boundingVolume.sphere[3]",
         "negative"},
        {R"({"boundingVolume": {"box": [0,0,0]}, "geometricError": 1})", "root.boundingVolume.box", "12 numbers"},
        {R"({"boundingVolume": {}, "geometricError": 1})", "root.boundingVolume", "no box, sphere or region"},
        {R"({"boundingVolume": {"region": [0,0,1,-1,0,1]}, "geometricError": 1})", "root.boundingVolume.region",
         "latitudes"},
        {R"({"boundingVolume": {"sphere": [0,0,0,1]}, "geometricError": -1})", "root.geometricError", "negative"},
        {R"({"boundingVolume": {"sphere": [0,0,0,1]}, "geometricError": 1, "transform": [0,0,0,0, 0,0,0,0, 0,0,0,0, 0,0,0,1]})",
         "root.transform", "singular"},
        {R"({"boundingVolume": {"sphere": [0,0,0,1]}, "geometricError": 1, "transform": [1,0,0,1, 0,1,0,0, 0,0,1,0, 0,0,0,1]})",
         "root.transform", "affine"},
        {R"({"boundingVolume": {"sphere": [0,0,0,1]}, "geometricError": 1, "refine": "MERGE"})", "root.refine", "ADD"},
        {R"({"boundingVolume": {"sphere": [0,0,0,1]}, "geometricError": 1, "children": [7]})", "root.children[0]",
         "object"},
        {R"({"boundingVolume": {"sphere": [0,0,0,1]}, "geometricError": 1, "content": {}})", "root.content.uri",
         "missing"},
    };
    TempDir d;
    for (const Case& c : cases) {
        writeText(d / "tileset.json",
                  std::string(R"({"asset": {"version": "1.1"}, "geometricError": 1, "root": )") + c.root + "}");
        try {
            loadTileset(d / "tileset.json");
            ADD_FAILURE() << "accepted: " << c.root;
        } catch (const LoadError& e) {
            EXPECT_EQ(e.file(), d / "tileset.json");
            EXPECT_EQ(e.jsonPath(), c.path) << e.what();
            EXPECT_NE(e.reason().find(c.reason), std::string::npos) << e.what();
        }
    }
    // Not a tileset at all: a glTF's JSON, a JSON array, not JSON.
    for (const char* text : {R"({"asset": {"version": "2.0"}, "scenes": []})", "[1, 2]", "tileset"}) {
        writeText(d / "tileset.json", text);
        EXPECT_THROW(loadTileset(d / "tileset.json"), LoadError) << text;
        EXPECT_FALSE(isTilesetFile(d / "tileset.json")) << text;
    }
    EXPECT_THROW(loadTileset(d / "missing.json"), LoadError);
}

// A bad child content is a failed tile, named, drawn empty: its parent's load brings the other three.
TEST(Tileset, ABadContentIsAnEmptyTileAndTheRestLoads) {
    TempDir d;
    const std::string file = quadTileset(d);
    writeText(d / "q2.glb", "glTF but not really");
    Tileset ts = loadTileset(file);
    Scene scene(ts.root());
    Pager pager(scene, ts.loadFunction());
    const Camera cam = lookingDownAt(dvec3(50, 50, 5), 100.0);
    pager.update(FrameInfo{1, 1.0});
    cullOnce(scene, cam, 1);
    pager.update(FrameInfo{2, 2.0});
    pager.waitIdle();
    pager.update(FrameInfo{3, 3.0});
    Drawn dr = cullOnce(scene, cam, 3);
    EXPECT_EQ(dr.boxes, (std::multiset<std::pair<long, long>>{{5, 5}, {55, 5}, {55, 55}}));
    EXPECT_EQ(pager.stats().failures, 0u);
    ASSERT_EQ(ts.failures().size(), 1u);
    EXPECT_EQ(ts.failures()[0].uri, d / "q2.glb");
    EXPECT_EQ(ts.failures()[0].path, "root.children[2].content.uri");
}

namespace {

// An implicit quadtree over [0, 100]^2 (subtrees of 2 levels, 3 levels in all): the root, three of the four
// level-1 tiles ((1, 1) unavailable), and below (0, 0) one level-2 tile (0, 0) in a subtree of its own, written
// as JSON with constant availability. Every available tile has a content: a box inset in its square.
std::string implicitTileset(const TempDir& d, const std::string& tileBits = "\x0f") {
    fs::create_directories(d / "subtrees/0/0");
    fs::create_directories(d / "subtrees/2/0");
    for (int l = 0; l <= 2; ++l)
        for (int x = 0; x < (1 << l); ++x)
            for (int y = 0; y < (1 << l); ++y) {
                fs::create_directories(d / ("content/" + std::to_string(l) + "/" + std::to_string(x)));
                const double size = 100.0 / (1 << l), inset = 0.08 * size;
                writeBoxGlb(
                    d / ("content/" + std::to_string(l) + "/" + std::to_string(x) + "/" + std::to_string(y) + ".glb"),
                    dvec3(x * size + inset, y * size + inset, 0),
                    dvec3((x + 1) * size - inset, (y + 1) * size - inset, 1));
            }
    // tiles: bit 0 the root, bits 1-4 level 1 in Morton order ((0,0), (1,0), (0,1), (1,1)); contents the same;
    // child subtrees: 16 bits for level 2, only (0, 0).
    std::vector<unsigned char> bin(tileBits.begin(), tileBits.end());
    const size_t tilesLen = bin.size();
    bin.push_back(0x0f);
    bin.push_back(0x01);
    bin.push_back(0x00);
    writeSubtree(d / "subtrees/0/0/0.subtree",
                 R"({"buffers": [{"byteLength": )" + std::to_string(bin.size()) + R"(}], "bufferViews": [
                   {"buffer": 0, "byteOffset": 0, "byteLength": )" +
                     std::to_string(tilesLen) + R"(},
                   {"buffer": 0, "byteOffset": )" +
                     std::to_string(tilesLen) + R"(, "byteLength": 1},
                   {"buffer": 0, "byteOffset": )" +
                     std::to_string(tilesLen + 1) + R"(, "byteLength": 2}],
                   "tileAvailability": {"bitstream": 0}, "contentAvailability": [{"bitstream": 1}],
                   "childSubtreeAvailability": {"bitstream": 2}})",
                 bin);
    writeText(d / "subtrees/2/0/0.subtree", R"({"tileAvailability": {"constant": 1},
        "contentAvailability": [{"constant": 1}], "childSubtreeAvailability": {"constant": 0}})");
    writeText(d / "tileset.json", R"({"asset": {"version": "1.1"}, "geometricError": 100, "root": {
        "boundingVolume": {"box": [50,50,0.5, 50,0,0, 0,50,0, 0,0,0.5]}, "geometricError": 40, "refine": "REPLACE",
        "content": {"uri": "content/{level}/{x}/{y}.glb"},
        "implicitTiling": {"subdivisionScheme": "QUADTREE", "subtreeLevels": 2, "availableLevels": 3,
                           "subtrees": {"uri": "subtrees/{level}/{x}/{y}.subtree"}}}})");
    return d / "tileset.json";
}

}  // namespace

// Implicit tiling: tiles and contents where the bitstreams say, a subtree below read when its tiles are needed,
// geometric errors halved per level; refined in full, the available leaves replace the root.
TEST(Tileset, ImplicitQuadtreesFollowTheirAvailability) {
    TempDir d;
    Tileset ts = loadTileset(implicitTileset(d));
    EXPECT_EQ(ts.counts().tiles, 4u);  // the root and its three available children, known from the first subtree
    EXPECT_EQ(ts.counts().contents, 1u);
    EXPECT_EQ(refineAll(*ts.root(), ts.loadFunction()), 2u);  // the root's children, then (0, 0)'s
    EXPECT_EQ(ts.counts().tiles, 5u);
    EXPECT_EQ(ts.counts().contents, 5u);
    Scene scene(ts.root());
    const Drawn dr = cullOnce(scene, lookingDownAt(dvec3(50, 50, 0), 500.0));
    // Level 1 (1, 0) and (0, 1) (50 wide, inset 4), level 2 (0, 0) (25 wide, inset 2); nothing at (1, 1).
    EXPECT_EQ(dr.boxes, (std::multiset<std::pair<long, long>>{{54, 4}, {4, 54}, {2, 2}}));
}

TEST(Tileset, ImplicitTilesRefineAtHalfTheErrorPerLevel) {
    TempDir d;
    Tileset ts = loadTileset(implicitTileset(d));
    Scene scene(ts.root());
    // The root (error 40, sphere radius ~70.7) refines within 40 * 259.8 / 16 = 649.5 of its sphere; a level-1
    // tile (error 20, radius ~35.4) within 324.8 of its own.
    Pager pager(scene, ts.loadFunction());
    const Camera cam = lookingDownAt(dvec3(25, 25, 0), 300.0);
    for (uint64_t f = 1; f <= 6; ++f) {
        pager.update(FrameInfo{f, double(f)});
        cullOnce(scene, cam, f);
        pager.waitIdle();
    }
    EXPECT_EQ(ts.counts().contents, 5u);  // the level-1 tile under the eye refined too
    const Drawn far = cullOnce(scene, lookingDownAt(dvec3(25, 25, 0), 600.0), 7);
    EXPECT_EQ(far.boxes.count({2, 2}), 0u);  // there (0, 0) shows itself, not its child
    EXPECT_EQ(far.boxes.count({4, 4}), 1u);
}

TEST(Tileset, ShortBitstreamsAreRefusedByName) {
    TempDir d;
    try {
        loadTileset(implicitTileset(d, ""));  // no bytes for the 5 tile bits
        FAIL() << "a short bitstream was read";
    } catch (const LoadError& e) {
        EXPECT_EQ(e.file(), d / "subtrees/0/0/0.subtree");
        EXPECT_EQ(e.jsonPath(), "tileAvailability");
        EXPECT_NE(e.reason().find("fewer than the 5 bits"), std::string::npos) << e.what();
    }
}

// Over HTTP from a local server: the same tiles as from the files.
TEST(Tileset, ReadFromAServerAsFromFiles) {
    TempDir d;
    quadTileset(d);
    testutil::TileServer server(d.path);
    Tileset ts = loadTileset(server.url("/tileset.json"));
    EXPECT_EQ(refineAll(*ts.root(), ts.loadFunction()), 1u);
    EXPECT_EQ(ts.counts().contents, 5u);
    Scene scene(ts.root());
    const Drawn dr = cullOnce(scene, lookingDownAt(dvec3(50, 50, 5), 500.0));
    EXPECT_EQ(dr.boxes, (std::multiset<std::pair<long, long>>{{5, 5}, {55, 5}, {5, 55}, {55, 55}}));
}

// A server that answers 500, drops the connection mid-file or stalls (failures that may pass): the load fails with a
// reason naming the URL, the parent stays drawn, and frames go on while the stalled read waits. (A 404 is final:
// TilesetFailuresTest.cpp.)
TEST(Tileset, ServerFaultsFailTheLoadAndKeepTheParent) {
    for (const std::string fault : {"status/500", "drop", "stall"}) {
        TempDir d;
        const std::string file = quadTileset(d);
        replaceInFile(file, "\"q2.glb\"", "\"" + fault + "/q2.glb\"");
        testutil::TileServer server(d.path);
        TilesetOptions options;
        options.resource.stallSeconds = 1.0;
        Tileset ts = loadTileset(server.url("/tileset.json"), options);
        Scene scene(ts.root());
        Pager pager(scene, ts.loadFunction());
        const Camera cam = lookingDownAt(dvec3(50, 50, 5), 100.0);
        pager.update(FrameInfo{1, 1.0});
        cullOnce(scene, cam, 1);
        pager.update(FrameInfo{2, 2.0});  // queued: the loader starts
        if (fault == "stall") {
            ASSERT_EQ(server.readLine(), "arrived /stall/q2.glb");
            for (uint64_t f = 3; f < 6; ++f) {  // the read is stalled: frames are not held by it
                pager.update(FrameInfo{f, double(f)});
                EXPECT_EQ(cullOnce(scene, cam, f).boxes.count({0, 0}), 1u) << fault;
            }
        }
        pager.waitIdle();
        pager.update(FrameInfo{9, 9.0});
        const Drawn dr = cullOnce(scene, cam, 9);
        EXPECT_EQ(dr.boxes, (std::multiset<std::pair<long, long>>{{0, 0}})) << fault;  // the root's content
        EXPECT_EQ(pager.stats().failures, 1u) << fault;
        const std::string& why = pager.stats().lastError;
        EXPECT_NE(why.find(server.url("/" + fault + "/q2.glb")), std::string::npos) << why;
        const char* reason = fault == "drop" ? "connection closed after" : fault == "stall" ? "no data" : "HTTP 500";
        EXPECT_NE(why.find(reason), std::string::npos) << why;
    }
}

// A tile whose content the server fails with a 500 fails its load, is asked for again only after the pager's
// back-off, the parent drawn meanwhile; failing again, past TilesetOptions::transientAttempts, it is given up and
// its siblings show.
TEST(Tileset, AFailedTileIsRetriedAfterItsBackOff) {
    TempDir d;
    replaceInFile(quadTileset(d), "\"q2.glb\"", "\"status/500/q2.glb\"");
    testutil::TileServer server(d.path);
    TilesetOptions options;
    options.transientAttempts = 2;
    Tileset ts = loadTileset(server.url("/tileset.json"), options);
    Scene scene(ts.root());
    PagerSettings ps;
    ps.retrySeconds = 10.0;
    Pager pager(scene, ts.loadFunction(), ps);
    const Camera cam = lookingDownAt(dvec3(50, 50, 5), 100.0);
    auto frame = [&](uint64_t f, double t) {
        pager.update(FrameInfo{f, t});
        Drawn dr = cullOnce(scene, cam, f, t);
        pager.waitIdle();
        return dr;
    };
    frame(1, 0.0);
    frame(2, 0.1);
    frame(3, 0.2);
    EXPECT_EQ(pager.stats().failures, 1u);
    EXPECT_NE(pager.stats().lastError.find("HTTP 500"), std::string::npos) << pager.stats().lastError;
    ASSERT_EQ(ts.failures().size(), 1u);
    EXPECT_FALSE(ts.failures()[0].final);
    for (uint64_t f = 4; f < 8; ++f) EXPECT_EQ(frame(f, 0.1 * double(f)).boxes.size(), 1u);  // within the back-off
    EXPECT_EQ(pager.stats().requests, 1u);
    for (uint64_t f = 8; f < 12; ++f) frame(f, 20.0 + double(f));  // past it: asked again, given up, attached
    EXPECT_EQ(pager.stats().requests, 2u);
    EXPECT_EQ(pager.stats().failures, 1u);
    EXPECT_EQ(cullOnce(scene, cam, 12, 40.0).boxes, (std::multiset<std::pair<long, long>>{{5, 5}, {55, 5}, {55, 55}}));
    ASSERT_EQ(ts.failures().size(), 1u);
    EXPECT_TRUE(ts.failures()[0].final);
    EXPECT_EQ(ts.failures()[0].attempts, 2u);
}

TEST(SharedMeshes, EqualMeshesOfDifferentLoadsBecomeOneAndOthersStayApart) {
    tiles::SharedMeshes pool;
    auto box = [](double x) { return makeBoxMesh(dvec3(0.0), dvec3(x, 1.0, 1.0)); };
    auto graph = [&](ref_ptr<Mesh> a, ref_ptr<Mesh> b) {
        auto g = make<Group>();
        g->addChild(make<Geometry>(a, nullptr));
        g->addChild(make<Geometry>(b, nullptr));
        g->addChild(make<Geometry>(a, nullptr));  // shared within the load already
        return g;
    };
    auto first = graph(box(1.0), box(2.0));
    EXPECT_EQ(pool.share(*first), 0u);
    EXPECT_EQ(pool.size(), 2u);

    // An equal copy is replaced by the first load's mesh; one differing in a single coordinate is not.
    auto nearly = box(2.0);
    std::vector<vec3> p = nearly->positions();
    p[0].x = std::nextafter(p[0].x, 10.0f);
    nearly->set(p, nearly->normals(), std::vector<uint32_t>(nearly->indices16().begin(), nearly->indices16().end()));
    auto second = graph(box(1.0), nearly);
    EXPECT_EQ(pool.share(*second), 1u);
    auto mesh = [](const ref_ptr<Group>& g, size_t i) { return static_cast<Geometry*>(g->child(i))->mesh(); };
    EXPECT_EQ(mesh(second, 0), mesh(first, 0));
    EXPECT_EQ(mesh(second, 2), mesh(first, 0));
    EXPECT_NE(mesh(second, 1), mesh(first, 1));
    EXPECT_EQ(pool.size(), 3u);
    EXPECT_EQ(pool.replaced(), 1u);

    // Meshes no graph holds any more leave the pool as loads go on.
    first = nullptr;
    second = nullptr;
    for (int i = 0; i < 8; ++i) pool.share(*graph(box(10.0 + i), box(20.0 + i)));
    EXPECT_LE(pool.size(), 8u);
}

// Point tiles never repeat their points: they are not pooled, so that a pool entry cannot keep one alive (the
// renderer's cache holding it too, neither would let go).
TEST(SharedMeshes, PointMeshesAreNotPooled) {
    tiles::SharedMeshes pool;
    auto cloud = [] {
        auto m = make<Mesh>();
        m->setPoints({{0, 0, 0}, {1, 2, 3}});
        auto g = make<Group>();
        g->addChild(make<Geometry>(m, nullptr));
        return g;
    };
    auto first = cloud(), second = cloud();
    EXPECT_EQ(pool.share(*first), 0u);
    EXPECT_EQ(pool.share(*second), 0u);
    EXPECT_EQ(pool.size(), 0u);
    EXPECT_NE(static_cast<Geometry*>(first->child(0))->mesh(), static_cast<Geometry*>(second->child(0))->mesh());
}

TEST(Tileset, AViewerRequestVolumeShowsAndRefinesTheTileOnlyWithTheEyeInside) {
    TempDir d;
    Tileset ts = loadTileset(quadTileset(d, "REPLACE", R"("viewerRequestVolume": {"sphere": [50,50,5, 300]},)"));
    EXPECT_TRUE(ts.warnings().empty());
    Scene scene(ts.root());
    // Inside (95 m from the centre, close enough to refine): drawn, and its children asked for.
    const Drawn inside = cullOnce(scene, lookingDownAt(dvec3(50, 50, 0), 100.0), 1);
    EXPECT_FALSE(inside.boxes.empty());
    EXPECT_GT(inside.stats.pagedRequested, 0u);
    // Outside (1,000 m up): neither drawn nor asked for, though the tile is in view.
    const Drawn outside = cullOnce(scene, lookingDownAt(dvec3(50, 50, 0), 1000.0), 2);
    EXPECT_TRUE(outside.boxes.empty());
    EXPECT_EQ(outside.stats.pagedRequested + outside.stats.pagedWanted, 0u);
    // A bad volume is refused by its path.
    TempDir bad;
    try {
        loadTileset(quadTileset(bad, "REPLACE", R"("viewerRequestVolume": {"sphere": [50,50,5, -1]},)"));
        FAIL() << "a negative radius was accepted";
    } catch (const LoadError& e) {
        EXPECT_NE(std::string(e.what()).find("root.viewerRequestVolume.sphere[3]"), std::string::npos) << e.what();
    }
}
