// The origin rule: a tileset, subtree or tile read over the network may name only network resources and data:
// URIs, as a browser keeps a web page from reading local files; a local tileset may name anything. Each way a
// remote document can name a file is tried with a local file that would load, from a real server on 127.0.0.1.
#include "loaders/net/Resource.h"
#include "loaders/net/TileServer.h"
#include "loaders/tiles/Tileset.h"
#include "loaders/tiles/TilesetTestUtil.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

using namespace sg;
using namespace tilestest;
namespace fs = std::filesystem;

namespace {

std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string base64(const std::string& bytes) {
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 2]));
        for (size_t k = 0; k < 4; ++k) out += i + k <= bytes.size() ? digits[(v >> (18 - 6 * k)) & 63] : '=';
    }
    return out;
}

bool namesTheRule(const LoadError& e) { return e.reason().find("(origin rule)") != std::string::npos; }

// The one tile content of `ts` that failed (a refused content is a failed tile, the tileset loads); FAIL when there
// is not one.
TileFailure failureOf(const Tileset& ts) {
    const std::vector<TileFailure> f = ts.failures();
    if (f.size() != 1) {
        ADD_FAILURE() << f.size() << " tile failures, not 1";
        return {};
    }
    EXPECT_TRUE(f[0].final);
    return f[0];
}
bool namesTheRule(const TileFailure& f) { return f.reason.find("(origin rule)") != std::string::npos; }

// A tileset of one tile whose content is `uri`, in `dir`/`name`.
void oneTile(const std::string& path, const std::string& uri, const std::string& extra = "") {
    writeText(path, R"({"asset": {"version": "1.1"}, "geometricError": 10, )" + extra + R"("root": {
        "boundingVolume": {"box": [0,0,5, 5,0,0, 0,5,0, 0,0,5]}, "geometricError": 0,
        "content": {"uri": ")" +
                        uri + R"("}}})");
}

// A folder of the test's.
struct Dir {
    std::string path;
    std::string operator/(const std::string& f) const { return path + "/" + f; }
};

// Two folders apart: `served` is on the server, `local` is not; local/secret.glb loads as a tile.
struct Origin : ::testing::Test {
    TempDir root;
    Dir served{root / "served"}, local{root / "local"};
    std::unique_ptr<testutil::TileServer> server;
    void SetUp() override {
        fs::create_directories(served.path);
        fs::create_directories(local / "x");
        writeBoxGlb(local / "secret.glb", dvec3(0), dvec3(1));
        server = std::make_unique<testutil::TileServer>(served.path);
    }
    std::string secretUrl() const { return "file://" + local / "secret.glb"; }
};

}  // namespace

TEST(ResourceOrigin, ANetworkResourceNamesOnlyNetworkResourcesAndDataUris) {
    const std::string base = "https://h.org/a/tileset.json";
    EXPECT_EQ(resolveReference(base, "b/0.glb"), "https://h.org/a/b/0.glb");
    EXPECT_EQ(resolveReference(base, "http://other.org/x.glb"), "http://other.org/x.glb");
    EXPECT_EQ(resolveReference(base, "//cdn.org/x.glb"), "https://cdn.org/x.glb");
    EXPECT_EQ(resolveReference(base, "data:,{}"), "data:,{}");
    EXPECT_EQ(resolveReference(base, "DATA:;base64,e30="), "DATA:;base64,e30=");
    // A path is a path on the server, as in a browser: never a local one.
    EXPECT_EQ(resolveReference(base, "/etc/passwd"), "https://h.org/etc/passwd");
    EXPECT_EQ(resolveReference(base, "../../../../etc/passwd"), "https://h.org/etc/passwd");
    for (const std::string bad : {"file:///etc/passwd", "FILE:///etc/passwd", "file://localhost/etc/passwd",
                                  "ftp://h.org/x.glb", "gopher://h/x", "dict://h/x"}) {
        const LoadError e = errorOf([&] { resolveReference(base, bad, "root.content.uri"); });
        EXPECT_EQ(e.file(), base) << bad;
        EXPECT_EQ(e.jsonPath(), "root.content.uri") << bad;
        EXPECT_TRUE(namesTheRule(e)) << e.what();
        EXPECT_NE(e.reason().find(bad), std::string::npos) << e.what();
    }
    EXPECT_TRUE(namesTheRule(errorOf([] { resolveReference("HTTP://h/t.json", "file:///x"); })));
}

TEST(ResourceOrigin, ALocalResourceNamesAnything) {
    EXPECT_EQ(resolveReference("/data/tileset.json", "file:///other/x.glb"), "file:///other/x.glb");
    EXPECT_EQ(resolveReference("/data/tileset.json", "/other/x.glb"), "/other/x.glb");
    EXPECT_EQ(resolveReference("/data/tileset.json", "https://h/x.glb"), "https://h/x.glb");
    EXPECT_EQ(resolveReference("file:///data/tileset.json", "file:///x.glb"), "file:///x.glb");
    EXPECT_EQ(resolveReference("data/tileset.json", "x.glb"), "data/x.glb");
}

TEST(ResourceData, DataUrisAreRead) {
    auto text = [](const std::string& uri, const ResourceOptions& o = {}) {
        const std::vector<unsigned char> b = readResource(uri, o);
        return std::string(b.begin(), b.end());
    };
    EXPECT_EQ(text("data:,hello%20world"), "hello world");
    EXPECT_EQ(text("data:application/octet-stream;base64,aGVsbG8="), "hello");
    EXPECT_EQ(text("data:;base64,aGVsbG8"), "hello");  // padding left out
    EXPECT_EQ(text("data:;base64,aGk="), "hi");
    EXPECT_EQ(text("data:;base64,aGk%3D"), "hi");  // percent-encoded padding
    EXPECT_EQ(text("data:;base64,"), "");
    const std::string noise = std::string("\x00\xff\xfe\x10 binary\x7f", 12);
    EXPECT_EQ(text("data:;BASE64," + base64(noise)), noise);
    EXPECT_EQ(errorOf([] { readResource("data:;base64,aGV$bG8="); }).reason(), "a data: URI's base64 has '$' at 3");
    EXPECT_EQ(errorOf([] { readResource("data:;base64,aGVsb"); }).reason(),
              "a data: URI's base64 ends in the middle of a byte");
    EXPECT_EQ(errorOf([] { readResource("data:hello"); }).reason(), "a data: URI without ',' before its data");
    ResourceOptions small;
    small.maxBytes = 4;
    EXPECT_EQ(errorOf([&] { readResource("data:;base64,aGVsbG8gd29ybGQ=", small); }).reason(), "larger than the limit");
    EXPECT_EQ(errorOf([&] { readResource("data:,hello", small); }).reason(), "larger than the limit");
    // A long URI is named by its start only.
    const LoadError long_ = errorOf([] { readResource("data:;base64," + std::string(1000, '*')); });
    EXPECT_LT(long_.file().size(), 80u);
}

// The case a user met: a tileset on a server whose content is a file: URL. Refused by the rule, naming the tileset
// and the JSON path; the same tileset read from the disk loads the file.
TEST_F(Origin, ARemoteTilesetNamingALocalFileIsRefused) {
    oneTile(served / "tileset.json", secretUrl());
    const LoadError e = errorOf([&] { loadTileset(server->url("/tileset.json")); });
    EXPECT_TRUE(namesTheRule(e)) << e.what();
    EXPECT_EQ(e.file(), server->url("/tileset.json"));
    EXPECT_EQ(e.jsonPath(), "root.content.uri");

    Tileset mine = loadTileset(served / "tileset.json");
    EXPECT_EQ(mine.counts().contents, 1u);
    ASSERT_TRUE(mine.root());
}

// A path in a remote tileset is a path on its server: the file is asked of the server (which has none), not read.
TEST_F(Origin, APathInARemoteTilesetIsAskedOfTheServer) {
    oneTile(served / "tileset.json", local / "secret.glb");
    const TileFailure f = failureOf(loadTileset(server->url("/tileset.json")));
    EXPECT_EQ(f.uri, server->url(local / "secret.glb"));
    EXPECT_EQ(f.reason, "HTTP 404 Not Found");
}

// A local tileset may name a remote one, which may name no local file; nor may a remote tileset's external one.
TEST_F(Origin, AnExternalTilesetReadOverTheNetworkNamesNoLocalFile) {
    oneTile(served / "external.json", secretUrl());
    oneTile(local / "tileset.json", server->url("/external.json"));
    const TileFailure f = failureOf(loadTileset(local / "tileset.json"));  // the external tileset is not read
    EXPECT_TRUE(namesTheRule(f)) << f.reason;
    EXPECT_EQ(f.uri, server->url("/external.json"));

    oneTile(served / "tileset.json", "external.json");
    EXPECT_TRUE(namesTheRule(failureOf(loadTileset(server->url("/tileset.json")))));
    // Through a local path, the external tileset is local: it may.
    oneTile(local / "x/external.json", secretUrl());
    oneTile(local / "tileset.json", "x/external.json");
    const Tileset ts = loadTileset(local / "tileset.json");
    EXPECT_EQ(ts.counts().externalTilesets, 1u);
    EXPECT_EQ(ts.counts().contents, 2u);  // the external tileset and the model it names
}

TEST_F(Origin, ARemoteSubtreeAndItsBuffersNameNoLocalFile) {
    const std::string implicit = R"({"asset": {"version": "1.1"}, "geometricError": 10, "root": {
        "boundingVolume": {"box": [0,0,5, 5,0,0, 0,5,0, 0,0,5]}, "geometricError": 1,
        "implicitTiling": {"subdivisionScheme": "QUADTREE", "subtreeLevels": 2, "availableLevels": 2,
                           "subtrees": {"uri": "SUBTREES"}}}})";
    auto tileset = [&](const std::string& subtrees) {
        std::string t = implicit;
        t.replace(t.find("SUBTREES"), 8, subtrees);
        writeText(served / "tileset.json", t);
    };
    // The subtrees' template on the local disk.
    const std::string good = R"({"tileAvailability": {"constant": 1}, "childSubtreeAvailability": {"constant": 0}})";
    writeText(local / "0.0.0.json", good);
    tileset("file://" + local / "{level}.{x}.{y}.json");
    LoadError e = errorOf([&] { loadTileset(server->url("/tileset.json")); });
    EXPECT_TRUE(namesTheRule(e)) << e.what();
    EXPECT_EQ(e.jsonPath(), "root.implicitTiling.subtrees.uri");
    writeText(local / "tileset.json", readText(served / "tileset.json"));
    EXPECT_EQ(loadTileset(local / "tileset.json").counts().tiles, 5u);  // from the disk: read

    // A subtree on the server whose buffer is a local file (the availability bits, all set).
    writeText(local / "bits.bin", std::string(1, char(0x1f)));
    writeText(served / "0.0.0.json", R"({"buffers": [{"uri": ")" + std::string("file://") + local / "bits.bin" +
                                         R"(", "byteLength": 1}], "bufferViews": [{"buffer": 0, "byteOffset": 0,
        "byteLength": 1}], "tileAvailability": {"bitstream": 0}, "childSubtreeAvailability": {"constant": 0}})");
    tileset("{level}.{x}.{y}.json");
    e = errorOf([&] { loadTileset(server->url("/tileset.json")); });
    EXPECT_TRUE(namesTheRule(e)) << e.what();
    EXPECT_EQ(e.file(), server->url("/0.0.0.json"));
    EXPECT_EQ(e.jsonPath(), "buffers[0].uri");
    // The same subtree beside a local tileset reads its buffer.
    writeText(local / "0.0.0.json", readText(served / "0.0.0.json"));
    writeText(local / "tileset.json", readText(served / "tileset.json"));
    EXPECT_EQ(loadTileset(local / "tileset.json").counts().tiles, 5u);
}

TEST_F(Origin, ARemoteSchemaUriNamesNoLocalFile) {
    writeText(local / "schema.json", R"({"id": "s", "classes": {}})");
    writeBoxGlb(served / "box.glb", dvec3(0), dvec3(1));
    oneTile(served / "tileset.json", "box.glb", R"("schemaUri": "file://)" + local / "schema.json" + R"(", )");
    const LoadError e = errorOf([&] { loadTileset(server->url("/tileset.json")); });
    EXPECT_TRUE(namesTheRule(e)) << e.what();
    EXPECT_EQ(e.jsonPath(), "schemaUri");
}

// An i3dm's glTF by URI (gltfFormat 0), named by a tile read over the network.
TEST_F(Origin, ARemoteInstancedTileNamesNoLocalModel) {
    auto u32 = [](std::string& s, uint32_t v) {
        for (int i = 0; i < 4; ++i) s += char((v >> (8 * i)) & 0xff);
    };
    const std::string feature = R"({"INSTANCES_LENGTH":1,"POSITION":{"byteOffset":0}})";
    std::string ft = feature;
    while ((32 + ft.size()) % 8) ft += ' ';
    std::string positions(16, '\0');  // one position at the origin, padded to 8 bytes
    std::string body = secretUrl();
    while ((32 + ft.size() + positions.size() + body.size()) % 8) body += '\0';
    std::string tile = "i3dm";
    u32(tile, 1);
    u32(tile, uint32_t(32 + ft.size() + positions.size() + body.size()));
    for (uint32_t v : {uint32_t(ft.size()), uint32_t(positions.size()), 0u, 0u, 0u}) u32(tile, v);  // gltfFormat 0
    tile += ft + positions + body;
    writeText(served / "trees.i3dm", tile);
    oneTile(served / "tileset.json", "trees.i3dm");
    const TileFailure f = failureOf(loadTileset(server->url("/tileset.json")));
    EXPECT_TRUE(namesTheRule(f)) << f.reason;
    EXPECT_EQ(f.uri, server->url("/trees.i3dm"));

    writeText(local / "trees.i3dm", tile);
    oneTile(local / "tileset.json", "trees.i3dm");
    EXPECT_EQ(loadTileset(local / "tileset.json").counts().contents, 1u);
}

// A glTF (JSON) tile read over the network is parsed from memory: its external buffers, local or not, are not read.
TEST_F(Origin, ARemoteGltfReadsNoLocalBuffer) {
    const std::string bin = std::string(36, '\0');  // three vec3 positions
    writeText(local / "tri.bin", bin);
    const std::string gltf = R"({"asset": {"version": "2.0"}, "buffers": [{"uri": "file://)" + local / "tri.bin" +
                             R"(", "byteLength": 36}], "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [0, 0, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}], "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}], "scene": 0})";
    writeText(served / "tri.gltf", gltf);
    oneTile(served / "tileset.json", "tri.gltf");
    const TileFailure f = failureOf(loadTileset(server->url("/tileset.json")));
    EXPECT_EQ(f.uri, server->url("/tri.gltf"));
    EXPECT_NE(f.reason.find("not read when loading from memory"), std::string::npos) << f.reason;
}

// data: URIs are allowed from anywhere: a glb tile inlined in a remote tileset loads.
TEST_F(Origin, ARemoteTilesetMayInlineItsContentAsADataUri) {
    writeBoxGlb(local / "box.glb", dvec3(0), dvec3(1));
    oneTile(served / "tileset.json", "data:model/gltf-binary;base64," + base64(readText(local / "box.glb")));
    Tileset ts = loadTileset(server->url("/tileset.json"));
    EXPECT_EQ(ts.counts().contents, 1u);
}

// A server may not redirect a read to a local file.
TEST_F(Origin, ARedirectToAFileIsRefused) {
    const std::string to = server->url("/goto?to=" + secretUrl());
    const LoadError e = errorOf([&] { readResource(to); });
    EXPECT_EQ(e.file(), to);
    EXPECT_TRUE(namesTheRule(e)) << e.what();
    EXPECT_NE(e.reason().find(secretUrl()), std::string::npos) << e.what();
}

// What was asked for over TLS is not redirected in the clear; https to https and http to https are followed. The
// server's certificate is made here and trusted through ResourceOptions::caFile.
TEST_F(Origin, AnHttpsResourceIsNotRedirectedToHttp) {
    const std::string cert = served / "cert.pem", key = served / "key.pem";
    const std::string make =
        "openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -days 2 "
        "-subj /CN=127.0.0.1 -addext subjectAltName=IP:127.0.0.1 -keyout '" +
        key + "' -out '" + cert + "' 2>/dev/null";
    ASSERT_EQ(std::system(make.c_str()), 0) << "openssl could not make a certificate: " << make;
    writeBoxGlb(served / "box.glb", dvec3(0), dvec3(1));
    testutil::TileServer tls(served.path, cert, key);
    ResourceOptions o;
    o.caFile = cert;
    const std::vector<unsigned char> box = readResource(served / "box.glb");
    EXPECT_EQ(readResource(tls.url("/box.glb"), o), box);
    EXPECT_EQ(readResource(tls.url("/redirect/2/box.glb"), o), box);                  // https to https
    EXPECT_EQ(readResource(server->url("/goto?to=" + tls.url("/box.glb")), o), box);  // http to https
    const std::string down = tls.url("/goto?to=" + server->url("/box.glb"));
    const LoadError e = errorOf([&] { readResource(down, o); });
    EXPECT_TRUE(namesTheRule(e)) << e.what();
    EXPECT_NE(e.reason().find("https"), std::string::npos) << e.what();
    EXPECT_EQ(readResource(server->url("/goto?to=" + server->url("/box.glb"))), box);  // http to http: followed
    // Not trusted without the test's authority: the certificate is checked.
    EXPECT_NE(errorOf([&] { readResource(tls.url("/box.glb")); }).reason().find("certificate"), std::string::npos);
}
