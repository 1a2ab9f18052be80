// A tileset behind a token and an access key, as 3D Tiles servers keep them: the request headers of
// TilesetOptions go with every request, the query string of the tileset's URL with every URI resolved from it on
// that server. Checked on what a real server on 127.0.0.1 (tile_server.py) was asked.
#include "loaders/net/Resource.h"
#include "loaders/net/TileServer.h"
#include "loaders/tiles/Tileset.h"
#include "loaders/tiles/TilesetTestUtil.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

using namespace sg;
using namespace tilestest;
namespace fs = std::filesystem;

namespace {

// A root with one child whose content is an external tileset (sub/tileset.json) of one box tile.
void writeTwoLevelTileset(const std::string& dir) {
    fs::create_directories(dir + "/sub");
    writeBoxGlb(dir + "/root.glb", dvec3(0), dvec3(10));
    writeBoxGlb(dir + "/sub/leaf.glb", dvec3(0), dvec3(1));
    const std::string box = R"("boundingVolume": {"box": [5,5,5, 5,0,0, 0,5,0, 0,0,5]})";
    writeText(dir + "/tileset.json", R"({"asset": {"version": "1.1"}, "geometricError": 100, "root": {)" + box +
                                         R"(, "geometricError": 10, "refine": "REPLACE", "content": {"uri": "root.glb"},
        "children": [{)" + box + R"(, "geometricError": 1, "content": {"uri": "sub/tileset.json"}}]}})");
    writeText(dir + "/sub/tileset.json", R"({"asset": {"version": "1.1"}, "geometricError": 1, "root": {)" + box +
                                             R"(, "geometricError": 0, "content": {"uri": "leaf.glb"}}})");
}

}  // namespace

TEST(TilesetAccess, EveryRequestCarriesTheTokenAndTheKey) {
    TempDir dir;
    writeTwoLevelTileset(dir.path);
    testutil::TileServer server(dir.path);
    TilesetOptions o;
    o.resource.headers = {"Authorization: Bearer t0k3n"};
    Tileset ts = loadTileset(server.url("/tileset.json?key=k1&v=2"), o);
    EXPECT_EQ(refineAll(*ts.root(), ts.loadFunction()), 1u);  // the child's load reads both documents
    EXPECT_EQ(ts.counts().externalTilesets, 1u);

    const std::vector<unsigned char> body = readResource(server.url("/seen"));
    const nlohmann::json seen = nlohmann::json::parse(body.begin(), body.end());
    std::vector<std::string> paths;
    for (const nlohmann::json& r : seen) {
        paths.push_back(r[0].get<std::string>());
        ASSERT_TRUE(r[1].is_string()) << paths.back() << " was asked without the token";
        EXPECT_EQ(r[1].get<std::string>(), "Bearer t0k3n") << paths.back();
    }
    const std::vector<std::string> expected = {"/tileset.json?key=k1&v=2", "/root.glb?key=k1&v=2",
                                               "/sub/tileset.json?key=k1&v=2", "/sub/leaf.glb?key=k1&v=2"};
    EXPECT_EQ(paths, expected);
}

// Without options nothing is added: the server sees the plain paths and no Authorization.
TEST(TilesetAccess, NoKeyNoToken) {
    TempDir dir;
    writeTwoLevelTileset(dir.path);
    testutil::TileServer server(dir.path);
    Tileset ts = loadTileset(server.url("/tileset.json"));
    refineAll(*ts.root(), ts.loadFunction());
    const std::vector<unsigned char> body = readResource(server.url("/seen"));
    const nlohmann::json seen = nlohmann::json::parse(body.begin(), body.end());
    ASSERT_EQ(seen.size(), 4u) << seen.dump();
    for (const nlohmann::json& r : seen) {
        EXPECT_EQ(r[0].get<std::string>().find('?'), std::string::npos) << r.dump();
        EXPECT_TRUE(r[1].is_null()) << r.dump();
    }
}
