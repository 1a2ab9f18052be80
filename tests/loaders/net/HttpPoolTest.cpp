// readResource from several threads at once against Debian's nginx (keep-alive, HTTP/2, gzip) and tile_server.py:
// connections reused across threads, HTTP/2 multiplexed, compressed bodies decoded within the limit, the cap on
// requests in flight per host.
#include "loaders/net/Nginx.h"
#include "loaders/net/Resource.h"
#include "loaders/net/TileServer.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <thread>
#include <vector>

using namespace sg;
namespace fs = std::filesystem;

namespace {

using Bytes = std::vector<unsigned char>;

void writeFile(const fs::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary).write(text.data(), std::streamsize(text.size()));
}

Bytes bytesOf(const std::string& s) { return Bytes(s.begin(), s.end()); }

// The reason of the LoadError `f` throws; "(read)" when it throws none.
template <typename F>
std::string reasonOf(F f) {
    try {
        f();
    } catch (const LoadError& e) {
        return e.reason();
    }
    return "(read)";
}

// Reads every URL with `threads` threads at once (thread k the URLs k, k + threads, ...); the bodies in order.
std::vector<Bytes> readAll(const std::vector<std::string>& urls, int threads, const ResourceOptions& o) {
    std::vector<Bytes> bodies(urls.size());
    std::vector<std::string> errors(static_cast<size_t>(threads));
    std::vector<std::thread> pool;
    for (int k = 0; k < threads; ++k)
        pool.emplace_back([&, k] {
            try {
                for (size_t i = size_t(k); i < urls.size(); i += size_t(threads)) bodies[i] = readResource(urls[i], o);
            } catch (const std::exception& e) {
                errors[size_t(k)] = e.what();
            }
        });
    for (std::thread& t : pool) t.join();
    for (const std::string& e : errors) EXPECT_EQ(e, "");
    return bodies;
}

std::set<uint64_t> connectionsOf(const std::vector<testutil::NginxLogLine>& log) {
    std::set<uint64_t> ids;
    for (const auto& line : log) ids.insert(line.connection);
    return ids;
}

class HttpPool : public ::testing::Test {
protected:
    void SetUp() override {
        dir = fs::path(::testing::TempDir()) / ("sgkit_pool_" + std::to_string(::getpid()) + "_" +
                                                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }

    // `n` files of a few KB, each different; their contents, in order of their names "tN.bin".
    std::vector<Bytes> makeSmallFiles(int n) {
        std::vector<Bytes> files;
        for (int i = 0; i < n; ++i) {
            std::string text;
            while (text.size() < 3000 + size_t(i) * 7)
                text += "tile " + std::to_string(i) + " " + std::to_string(text.size()) + "\n";
            writeFile(dir / ("t" + std::to_string(i) + ".bin"), text);
            files.push_back(bytesOf(text));
        }
        return files;
    }

    // The URLs of makeSmallFiles' files on `server`.
    static std::vector<std::string> smallUrls(const testutil::Nginx& server, int n) {
        std::vector<std::string> urls;
        for (int i = 0; i < n; ++i) urls.push_back(server.url("/t" + std::to_string(i) + ".bin"));
        return urls;
    }

    fs::path dir;
};

// Without connections shared across the threads and kept alive, 200 reads would open up to 200.
TEST_F(HttpPool, ThreadsReuseConnectionsOverHttp1) {
    const std::vector<Bytes> files = makeSmallFiles(200);
    testutil::NginxConfig config;
    config.root = dir.string();
    testutil::Nginx server(config);
    ResourceCounters counters;
    ResourceOptions o;
    o.counters = &counters;
    EXPECT_EQ(readAll(smallUrls(server, 200), 4, o), files);
    const auto log = server.logAtLeast(200);
    ASSERT_EQ(log.size(), 200u);
    for (const auto& line : log) EXPECT_EQ(line.protocol, "HTTP/1.1");
    const size_t connections = connectionsOf(log).size();
    EXPECT_LE(connections, 4u);  // at most one per thread reading at once
    EXPECT_EQ(counters.connections.load(), connections);
    EXPECT_EQ(counters.requests.load(), 200u);
    EXPECT_EQ(counters.http2.load(), 0u);
}

TEST_F(HttpPool, ThreadsShareHttp2Connections) {
    const std::vector<Bytes> files = makeSmallFiles(200);
    const std::string cert = (dir / "cert.pem").string(), key = (dir / "key.pem").string();
    const std::string make =
        "openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -days 2 "
        "-subj /CN=127.0.0.1 -addext subjectAltName=IP:127.0.0.1 -keyout '" +
        key + "' -out '" + cert + "' 2>/dev/null";
    ASSERT_EQ(std::system(make.c_str()), 0) << "openssl could not make a certificate: " << make;
    testutil::NginxConfig config;
    config.root = dir.string();
    config.cert = cert;
    config.key = key;
    testutil::Nginx server(config);
    ResourceCounters counters;
    ResourceOptions o;
    o.caFile = cert;
    o.counters = &counters;
    EXPECT_EQ(readAll(smallUrls(server, 200), 4, o), files);
    const auto log = server.logAtLeast(200);
    ASSERT_EQ(log.size(), 200u);
    for (const auto& line : log) EXPECT_EQ(line.protocol, "HTTP/2.0");
    EXPECT_EQ(counters.requests.load(), 200u);
    EXPECT_EQ(counters.http2.load(), counters.requests.load());
    EXPECT_LE(connectionsOf(log).size(), 4u);
    EXPECT_EQ(counters.connections.load(), connectionsOf(log).size());
}

// A JSON document of `size` bytes at least, which compresses well, as a tileset.json does.
std::string bigJson(size_t size) {
    std::string json = "{\"tiles\":[";
    for (int i = 0; json.size() < size; ++i)
        json += (i ? "," : "") + std::string("{\"id\":") + std::to_string(i) +
                ",\"geometricError\":16.5,\"content\":{\"uri\":\"tiles/" + std::to_string(i) + ".glb\"}}";
    return json + "]}";
}

// Compressed on the fly by nginx (chunked, no length announced): the limit holds for the body as decoded.
TEST_F(HttpPool, GzipBodiesAreDecodedAndTheLimitHoldsForTheDecodedBytes) {
    const std::string json = bigJson(1 << 20);
    writeFile(dir / "big.json", json);
    testutil::NginxConfig config;
    config.root = dir.string();
    testutil::Nginx server(config);
    ResourceCounters counters;
    ResourceOptions o;
    o.counters = &counters;
    EXPECT_EQ(readResource(server.url("/big.json"), o), bytesOf(json));
    EXPECT_EQ(counters.bytes.load(), json.size());
    EXPECT_LT(counters.bytesOnWire.load() * 4, counters.bytes.load());
    const auto log = server.logAtLeast(1);
    ASSERT_EQ(log.size(), 1u);
    // The log counts the chunked framing as well: a few bytes per chunk.
    EXPECT_GE(log[0].bodyBytes, counters.bytesOnWire.load());
    EXPECT_LT(log[0].bodyBytes, counters.bytesOnWire.load() + 1024);
    EXPECT_NE(log[0].acceptEncoding.find("gzip"), std::string::npos) << log[0].acceptEncoding;

    ResourceOptions limited;
    limited.maxBytes = size_t((counters.bytesOnWire.load() + json.size()) / 2);
    EXPECT_EQ(reasonOf([&] { readResource(server.url("/big.json"), limited); }), "larger than the limit");
}

// Compressed beforehand (gzip_static: a length announced, the compressed one): a compressed length under the
// limit does not admit a decoded body over it, and one within the limit is not refused for its announced length.
TEST_F(HttpPool, AnAnnouncedCompressedLengthIsNotTheDecodedSize) {
    const std::string json = bigJson(1 << 20);
    fs::create_directories(dir / "static");
    writeFile(dir / "static" / "big.json", json);
    const std::string gz = (dir / "static" / "big.json").string();
    ASSERT_EQ(std::system(("gzip -k -9 '" + gz + "'").c_str()), 0);
    const uint64_t compressed = fs::file_size(gz + ".gz");
    testutil::NginxConfig config;
    config.root = dir.string();
    config.extra = "location /static/ { gzip_static on; }";
    testutil::Nginx server(config);
    ResourceCounters counters;
    ResourceOptions o;
    o.counters = &counters;
    o.maxBytes = json.size();  // exactly the decoded size: admitted
    EXPECT_EQ(readResource(server.url("/static/big.json"), o), bytesOf(json));
    EXPECT_EQ(counters.bytesOnWire.load(), compressed);
    ASSERT_EQ(server.logAtLeast(1).size(), 1u);
    EXPECT_EQ(server.log()[0].bodyBytes, compressed);

    ResourceOptions limited;
    limited.maxBytes = size_t((compressed + json.size()) / 2);
    EXPECT_EQ(reasonOf([&] { readResource(server.url("/static/big.json"), limited); }), "larger than the limit");
}

// The requests of /stall/ paths tile_server.py has seen so far.
size_t stalledSeen(testutil::TileServer& server) {
    const Bytes seen = readResource(server.url("/seen"));
    const std::string text(seen.begin(), seen.end());
    size_t n = 0;
    for (size_t at = text.find("\"/stall/"); at != std::string::npos; at = text.find("\"/stall/", at + 1)) ++n;
    return n;
}

// Four threads, two slots: two requests reach the server; the other two only when a cancel frees the slots.
TEST_F(HttpPool, RequestsInFlightPerHostAreCapped) {
    const std::vector<std::string> names = {"a.bin", "b.bin", "c.bin", "d.bin"};
    for (const std::string& name : names) writeFile(dir / name, std::string(16384, name[0]));
    testutil::TileServer server(dir.string());
    std::atomic<bool> cancel[4] = {false, false, false, false};
    std::string reasons[4];
    std::vector<std::thread> threads;
    for (size_t i = 0; i < 4; ++i)
        threads.emplace_back([&, i] {
            ResourceOptions o;
            o.maxRequestsPerHost = 2;
            o.stallSeconds = 0;  // only the cancel ends these reads
            o.cancel = &cancel[i];
            reasons[i] = reasonOf([&] { readResource(server.url("/stall/" + names[i]), o); });
        });
    auto indexOf = [&](const std::string& line) -> size_t {  // "arrived /stall/b.bin": 1
        for (size_t i = 0; i < 4; ++i)
            if (line == "arrived /stall/" + names[i]) return i;
        ADD_FAILURE() << "not an arrival: '" << line << "'";
        return 4;
    };
    const size_t first = indexOf(server.readLine()), second = indexOf(server.readLine());
    EXPECT_EQ(stalledSeen(server), 2u);  // the other two wait for a slot
    for (size_t i : {first, second})
        if (i < 4) cancel[i] = true;
    const size_t third = indexOf(server.readLine()), fourth = indexOf(server.readLine());
    EXPECT_EQ(stalledSeen(server), 4u);
    EXPECT_EQ((std::set<size_t>{first, second, third, fourth}), (std::set<size_t>{0, 1, 2, 3}));
    for (auto& c : cancel) c = true;
    for (std::thread& t : threads) t.join();
    for (const std::string& reason : reasons) EXPECT_EQ(reason, "cancelled");
}

}  // namespace
