// sgview reading a tileset over https from Debian's nginx: with --ca-file naming the test's own authority it shows
// the tiles; without it the certificate is refused (exit code 2, the certificate named).
#ifdef SGVIEW_TEST_GLTF
#include "integration/ProgramRun.h"
#include "loaders/net/Nginx.h"
#include "loaders/net/TestCertificates.h"
#include "loaders/tiles/TilesetTestUtil.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace fs = std::filesystem;

TEST(SgviewTls, ATilesetOverHttpsIsReadWithTheCaFileOnly) {
    const fs::path dir = testDirectory("sgview_");
    fs::create_directories(dir / "www");
    fs::create_directories(dir / "certs");
    tilestest::writeBoxTileset((dir / "www").string());
    const testutil::TestCertificates certs((dir / "certs").string());
    testutil::NginxConfig config;
    config.root = (dir / "www").string();
    config.cert = certs.cert("good");
    config.key = certs.key("good");
    const testutil::Nginx server(config);
    // --no-cache: every run asks the server (a cached tileset would not meet the certificate).
    const std::string sgview = "'" SGVIEW_EXE "' --info '" + server.url("/tileset.json") + "' --no-cache";

    const ProgramRun refused = runProgram(dir, sgview);
    EXPECT_EQ(refused.code, 2) << refused.out;
    EXPECT_NE(refused.err.find("the server's certificate is not trusted"), std::string::npos) << refused.err;

    const ProgramRun shown = runProgram(dir, sgview + " --ca-file '" + certs.ca() + "'");
    ASSERT_EQ(shown.code, 0) << shown.err;
    EXPECT_NE(shown.out.find("tiles 1 (0 external tilesets), contents loaded 1"), std::string::npos) << shown.out;
}
#endif
