// sgview's disk cache for a tileset read over http: on by default for a URL (--cache DIR here), a second run asks
// the server nothing while its responses are fresh, --no-cache asks it everything, and a cache file that is not a
// cache is a warning and made anew. Checked on Debian's nginx's access log.
#ifdef SGVIEW_TEST_GLTF
#include "integration/ProgramRun.h"
#include "loaders/net/Nginx.h"
#include "loaders/tiles/TilesetTestUtil.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace fs = std::filesystem;

TEST(SgviewCache, ASecondRunReadsFreshTilesFromTheCache) {
    const fs::path dir = testDirectory("sgview_");
    fs::create_directories(dir / "www");
    fs::create_directories(dir / "cache");
    tilestest::writeBoxTileset((dir / "www").string());
    tilestest::writeText((dir / "cache/http.sqlite").string(), "not a database, not even close to one");
    testutil::NginxConfig config;
    config.root = (dir / "www").string();
    config.extra = "expires 1h;";  // responses fresh for an hour
    const testutil::Nginx server(config);
    const std::string sgview = "'" SGVIEW_EXE "' --info --refine-all '" + server.url("/tileset.json") + "'";
    const std::string cached = sgview + " --cache '" + (dir / "cache").string() + "'";

    const ProgramRun first = runProgram(dir, cached);
    ASSERT_EQ(first.code, 0) << first.err;
    EXPECT_NE(first.out.find("contents loaded 1"), std::string::npos) << first.out;
    EXPECT_NE((first.out + first.err).find("is not a cache database"), std::string::npos) << first.out << first.err;
    EXPECT_EQ(server.logAtLeast(2).size(), 2u);  // tileset.json and box.glb

    const ProgramRun second = runProgram(dir, cached);
    ASSERT_EQ(second.code, 0) << second.err;
    EXPECT_NE(second.out.find("contents loaded 1"), std::string::npos) << second.out;
    EXPECT_EQ((second.out + second.err).find("is not a cache database"), std::string::npos) << second.out;

    const ProgramRun uncached = runProgram(dir, sgview + " --no-cache");
    ASSERT_EQ(uncached.code, 0) << uncached.err;
    // The third run's two requests are the next the server logged: the second run made none.
    const auto log = server.logAtLeast(4);
    ASSERT_EQ(log.size(), 4u);
    EXPECT_EQ(log[2].uri, "/tileset.json");
    EXPECT_EQ(log[3].uri, "/box.glb");
}
#endif
