// readResource against files and a real local HTTP server (tile_server.py, started per test), well-behaved and not;
// resolveUri's cases.
#include "loaders/net/Resource.h"
#include "loaders/net/TileServer.h"

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <future>
#include <memory>
#include <random>
#include <stdexcept>
#include <thread>

extern char** environ;

using namespace sg;
using testutil::TileServer;
namespace fs = std::filesystem;

namespace {

// The LoadError a read throws; a read that succeeds fails the test.
LoadError readError(const std::string& what, const ResourceOptions& options = {}) {
    try {
        readResource(what, options);
    } catch (const LoadError& e) {
        return e;
    }
    ADD_FAILURE() << what << " was read";
    return LoadError(what, "", "(read)");
}

class Resource : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new std::string(::testing::TempDir() + "sgkit_resource_" + std::to_string(::getpid()));
        fs::create_directories(*dir_ + "/sub");
        // A few MB of noise, odd-sized: a transfer that loses, repeats or reorders a piece differs.
        big_ = new std::vector<unsigned char>(3 * 1024 * 1024 + 17);
        std::mt19937 rng(7);
        for (unsigned char& b : *big_) b = static_cast<unsigned char>(rng() >> 24);
        std::ofstream(*dir_ + "/big.bin", std::ios::binary)
            .write(reinterpret_cast<const char*>(big_->data()), std::streamsize(big_->size()));
        std::ofstream(*dir_ + "/sub/tileset.json") << R"({"asset":{"version":"1.0"}})";
        ::mkfifo((*dir_ + "/fifo").c_str(), 0600);
    }
    static void TearDownTestSuite() {
        fs::remove_all(*dir_);
        delete dir_;
        delete big_;
    }
    void SetUp() override { server_ = std::make_unique<TileServer>(*dir_); }
    void TearDown() override { server_.reset(); }

    std::string url(const std::string& path) const { return server_->url(path); }
    static std::string file(const std::string& name) { return *dir_ + "/" + name; }
    static const std::vector<unsigned char>& big() { return *big_; }

    static std::string* dir_;
    static std::vector<unsigned char>* big_;
    std::unique_ptr<TileServer> server_;
};
std::string* Resource::dir_ = nullptr;
std::vector<unsigned char>* Resource::big_ = nullptr;

TEST_F(Resource, ReadsAFileAndAFileUrl) {
    EXPECT_EQ(readResource(file("big.bin")), big());
    EXPECT_EQ(readResource("file://" + file("big.bin")), big());
    const std::vector<unsigned char> json = readResource(file("sub/tileset.json"));
    EXPECT_EQ(std::string(json.begin(), json.end()), R"({"asset":{"version":"1.0"}})");
}

TEST_F(Resource, ReadsAUrlAsTheFileBytes) {
    EXPECT_EQ(readResource(url("/big.bin")), big());
    EXPECT_EQ(readResource(url("/slow/big.bin")), big());      // in pieces, with pauses
    EXPECT_EQ(readResource(url("/nolength/big.bin")), big());  // no Content-Length: the end is the close
    EXPECT_EQ(readResource(url("/sub/tileset.json?key=1")), readResource(file("sub/tileset.json")));
}

TEST_F(Resource, StatusErrorsNameTheUrlAndTheStatus) {
    const LoadError notFound = readError(url("/status/404/big.bin"));
    EXPECT_EQ(notFound.file(), url("/status/404/big.bin"));
    EXPECT_EQ(notFound.reason(), "HTTP 404 Not Found");
    EXPECT_NE(std::string(notFound.what()).find(url("/status/404/big.bin")), std::string::npos) << notFound.what();
    EXPECT_EQ(readError(url("/missing.bin")).reason(), "HTTP 404 Not Found");
    const LoadError serverError = readError(url("/status/500/big.bin"));
    EXPECT_EQ(serverError.file(), url("/status/500/big.bin"));
    EXPECT_EQ(serverError.reason().rfind("HTTP 500", 0), 0u) << serverError.reason();
}

TEST_F(Resource, AStalledServerFails) {
    ResourceOptions o;
    o.stallSeconds = 1;
    EXPECT_EQ(readError(url("/stall/big.bin"), o).reason(), "no data for 1 s");
}

TEST_F(Resource, ADroppedConnectionSaysHowMuchCame) {
    const size_t n = big().size();
    EXPECT_EQ(readError(url("/drop/big.bin")).reason(),
              "connection closed after " + std::to_string(n / 2) + " of " + std::to_string(n) + " bytes");
    EXPECT_EQ(readResource(url("/big.bin")), big());  // the next read on this thread is not troubled by it
}

TEST_F(Resource, ACancelStopsAStalledRead) {
    std::atomic<bool> cancel{false};
    ResourceOptions o;
    o.stallSeconds = 600;  // only the cancel can end it
    o.cancel = &cancel;
    auto reason = std::async(std::launch::async, [&] { return readError(url("/stall/big.bin"), o).reason(); });
    // The server says when the request has arrived and its first bytes are out: the read is then waiting.
    EXPECT_EQ(server_->readLine(), "arrived /stall/big.bin");
    cancel = true;
    if (reason.wait_for(std::chrono::seconds(60)) != std::future_status::ready) {
        ADD_FAILURE() << "the cancel did not stop the read";
        server_.reset();  // the connection closes: the read ends and the thread can be joined
    }
    EXPECT_EQ(reason.get(), "cancelled");
}

TEST_F(Resource, ACancelBeforeTheReadStopsIt) {
    const std::atomic<bool> cancel{true};
    ResourceOptions o;
    o.cancel = &cancel;
    EXPECT_EQ(readError(url("/big.bin"), o).reason(), "cancelled");
    EXPECT_EQ(readError(file("big.bin"), o).reason(), "cancelled");
}

TEST_F(Resource, ARefusedConnectionSaysSo) {
    // A port nothing listens on: bound, then closed.
    const int s = ::socket(AF_INET, SOCK_STREAM, 0);
    ASSERT_GE(s, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    ASSERT_EQ(::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    ASSERT_EQ(::getsockname(s, reinterpret_cast<sockaddr*>(&a), &len), 0);
    ::close(s);
    const std::string u = "http://127.0.0.1:" + std::to_string(ntohs(a.sin_port)) + "/big.bin";
    const LoadError e = readError(u);
    EXPECT_EQ(e.file(), u);
    EXPECT_EQ(e.reason(), "connection refused");
}

TEST_F(Resource, LargerThanTheLimitIsRefused) {
    ResourceOptions o;
    o.maxBytes = big().size() - 1;
    EXPECT_EQ(readError(file("big.bin"), o).reason(), "larger than the limit");
    EXPECT_EQ(readError(url("/big.bin"), o).reason(), "larger than the limit");
    EXPECT_EQ(readError(url("/nolength/big.bin"), o).reason(), "larger than the limit");  // found while reading
    o.maxBytes = big().size();
    EXPECT_EQ(readResource(url("/big.bin"), o), big());
    EXPECT_EQ(readResource(url("/nolength/big.bin"), o), big());
    EXPECT_EQ(readResource(file("big.bin"), o), big());
    // Refused on the announced length, before the body: this server sends 1,024 bytes (under the limit) and stalls,
    // so a read that waited for the body would fail on the stall instead.
    o.maxBytes = 2000;
    o.stallSeconds = 2;
    EXPECT_EQ(readError(url("/stall/big.bin"), o).reason(), "larger than the limit");
}

TEST_F(Resource, OnlyRegularFilesAreOpened) {
    EXPECT_EQ(readError(*dir_).reason(), "not a regular file");
    EXPECT_EQ(readError(file("fifo")).reason(), "not a regular file");  // refused, not waited on for a writer
    EXPECT_EQ(readError(file("none.bin")).reason(), "no such file");
    EXPECT_EQ(readError("file://" + file("none.bin")).reason(), "no such file");
}

TEST_F(Resource, RedirectsAreFollowedFiveTimes) {
    EXPECT_EQ(readResource(url("/redirect/5/big.bin")), big());
    EXPECT_EQ(readError(url("/redirect/6/big.bin")).reason(), "more than 5 redirects");
}

TEST_F(Resource, ThreadsReadAtOnce) {
    // 8 reads on 4 threads, half of them slow, half counted by the server: each arrives once, whole.
    std::vector<std::vector<unsigned char>> got(8);
    std::vector<std::string> errors(8);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            for (int i = t; i < 8; i += 4) {
                try {
                    got[size_t(i)] = readResource(url(i % 2 ? "/count/big.bin" : "/slow/big.bin"));
                } catch (const std::exception& e) {
                    errors[size_t(i)] = e.what();
                }
            }
        });
    for (std::thread& t : threads) t.join();
    for (size_t i = 0; i < 8; ++i) {
        EXPECT_EQ(errors[i], "") << i;
        EXPECT_TRUE(got[i] == big()) << "read " << i << ": " << got[i].size() << " bytes";
    }
    const std::vector<unsigned char> counts = readResource(url("/requests"));
    EXPECT_EQ(std::string(counts.begin(), counts.end()), R"({"/count/big.bin": 4})");
}

TEST(ResourceUri, IsUrl) {
    EXPECT_TRUE(isUrl("http://h/x"));
    EXPECT_TRUE(isUrl("HTTPS://h/x"));
    EXPECT_TRUE(isUrl("Http://h"));
    EXPECT_FALSE(isUrl("file:///x"));
    EXPECT_FALSE(isUrl("ftp://h/x"));
    EXPECT_FALSE(isUrl("http:/h/x"));
    EXPECT_FALSE(isUrl("/data/http://h"));
    EXPECT_FALSE(isUrl("tiles/0.b3dm"));
}

TEST(ResourceUri, PathsAreJoinedToTheBaseDirectory) {
    EXPECT_EQ(resolveUri("/data/tiles/tileset.json", "0/1.b3dm"), "/data/tiles/0/1.b3dm");
    EXPECT_EQ(resolveUri("tiles/tileset.json", "a.b3dm"), "tiles/a.b3dm");
    EXPECT_EQ(resolveUri("tileset.json", "a.b3dm"), "a.b3dm");
    EXPECT_EQ(resolveUri("/data/tiles/tileset.json", "../other/x.glb"), "/data/tiles/../other/x.glb");
    EXPECT_EQ(resolveUri("/data/tileset.json", "/abs/x.glb"), "/abs/x.glb");
    EXPECT_EQ(resolveUri("/data/tileset.json", "https://h/x.glb"), "https://h/x.glb");
}

TEST(ResourceUri, UrlsAreResolvedAsTheWebDoes) {
    EXPECT_EQ(resolveUri("https://h.org/a/b/tileset.json", "c/d.b3dm"), "https://h.org/a/b/c/d.b3dm");
    EXPECT_EQ(resolveUri("https://h.org/a/b/tileset.json", "../c/./d.b3dm"), "https://h.org/a/c/d.b3dm");
    EXPECT_EQ(resolveUri("https://h.org/a/tileset.json", "../../../x.b3dm"), "https://h.org/x.b3dm");
    EXPECT_EQ(resolveUri("https://h.org/a/tileset.json", "./sub/"), "https://h.org/a/sub/");
    EXPECT_EQ(resolveUri("https://h.org/a/b/tileset.json", ".."), "https://h.org/a/");
    // base's query is not carried over; the reference's own is kept.
    EXPECT_EQ(resolveUri("http://h:8080/a/tileset.json?key=1&v=2", "x.b3dm"), "http://h:8080/a/x.b3dm");
    EXPECT_EQ(resolveUri("http://h:8080/a/tileset.json?key=1", "x.b3dm?v=3"), "http://h:8080/a/x.b3dm?v=3");
    EXPECT_EQ(resolveUri("http://h/a/tileset.json?p=/q/r", "x.b3dm"), "http://h/a/x.b3dm");
    // absolute URLs and paths from the root of the host.
    EXPECT_EQ(resolveUri("http://h/a/tileset.json", "https://other.org/x.b3dm"), "https://other.org/x.b3dm");
    EXPECT_EQ(resolveUri("http://h:8080/a/tileset.json", "/root/x.b3dm"), "http://h:8080/root/x.b3dm");
    EXPECT_EQ(resolveUri("https://h/a/tileset.json", "//cdn.org/x.b3dm"), "https://cdn.org/x.b3dm");
    EXPECT_EQ(resolveUri("http://h", "tileset.json"), "http://h/tileset.json");
    EXPECT_EQ(resolveUri("http://h?k=1", "tileset.json"), "http://h/tileset.json");
    // percent-encoding as it is.
    EXPECT_EQ(resolveUri("http://h/a%20b/tileset.json", "c%2Fd%20e.b3dm"), "http://h/a%20b/c%2Fd%20e.b3dm");
    EXPECT_EQ(resolveUri("file:///data/t/tileset.json", "x/../y.glb"), "file:///data/t/y.glb");
}

// A tileset URL's access key goes with every reference resolved from it on the same server, not elsewhere.
TEST(ResourceUri, AReferenceCarriesTheQueryOfItsReferrer) {
    EXPECT_EQ(resolveReference("http://h/a/tileset.json?key=1&v=2", "x.b3dm"), "http://h/a/x.b3dm?key=1&v=2");
    EXPECT_EQ(resolveReference("http://h/a/tileset.json?key=1&v=2", "x.b3dm?v=3"), "http://h/a/x.b3dm?v=3&key=1");
    EXPECT_EQ(resolveReference("http://h/a/tileset.json?key=1", "../b/x.b3dm#f"), "http://h/b/x.b3dm?key=1#f");
    EXPECT_EQ(resolveReference("http://h/a/tileset.json?key=1", "/root/x.b3dm"), "http://h/root/x.b3dm?key=1");
    EXPECT_EQ(resolveReference("http://h/a/tileset.json?key=1", "x.b3dm?"), "http://h/a/x.b3dm?key=1");
    // A "?" in the fragment is the fragment's, not a query that would set the key.
    EXPECT_EQ(resolveReference("http://h/a/tileset.json?a=1", "x.b3dm#f?a=2"), "http://h/a/x.b3dm?a=1#f?a=2");
    // Not to another host, nor where the reference is absolute, nor into data.
    EXPECT_EQ(resolveReference("http://h/a/tileset.json?key=1", "//cdn.org/x.b3dm"), "http://cdn.org/x.b3dm");
    EXPECT_EQ(resolveReference("http://h/a/tileset.json?key=1", "http://h/x.b3dm"), "http://h/x.b3dm");
    EXPECT_EQ(resolveReference("http://h/a/tileset.json?key=1", "data:,abc"), "data:,abc");
    EXPECT_EQ(resolveReference("http://h/a/tileset.json", "x.b3dm"), "http://h/a/x.b3dm");
    // A local tileset's query (none is read from a path) is not added.
    EXPECT_EQ(resolveReference("/data/tileset.json", "x.b3dm"), "/data/x.b3dm");
}

// ResourceOptions::headers go with the request, and a header that would break the request is refused.
TEST_F(Resource, RequestHeadersAreSent) {
    ResourceOptions o;
    o.headers = {"Authorization: Bearer abc.def", "X-Sgkit-Test: 7"};
    const std::vector<unsigned char> body = readResource(url("/echo"), o);
    const std::string text(body.begin(), body.end());
    EXPECT_NE(text.find("\"Authorization\": \"Bearer abc.def\""), std::string::npos) << text;
    EXPECT_NE(text.find("\"X-Sgkit-Test\": \"7\""), std::string::npos) << text;
    o.headers = {"Authorization: a\r\nX-Evil: 1"};
    EXPECT_NE(readError(url("/echo"), o).reason().find("not \"Name: value\" on one line"), std::string::npos);
    o.headers = {"no colon"};
    EXPECT_NE(readError(url("/echo"), o).reason().find("no colon"), std::string::npos);
}

}  // namespace
