// The HTTP disk cache (HttpCache) through readResource against a local server (tile_server.py's /cache/ paths:
// what a server says of freshness, and its 304s), and on its own: LRU eviction, two processes at once, a writer
// killed in the middle of a write, a corrupt file. The clock is the test's: nothing waits for time to pass.
#include "loaders/net/HttpCache.h"
#include "loaders/net/Resource.h"
#include "loaders/net/TileServer.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>

using namespace sg;
using testutil::TileServer;
namespace fs = std::filesystem;

namespace {

std::vector<unsigned char> noise(size_t n, unsigned seed) {
    std::vector<unsigned char> v(n);
    std::mt19937 rng(seed);
    for (unsigned char& b : v) b = static_cast<unsigned char>(rng() >> 24);
    return v;
}

// A directory of the test's own, removed after it.
class TempDir {
public:
    TempDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        path_ = ::testing::TempDir() + "sgkit_httpcache_" + std::to_string(::getpid()) + "_" + info->name();
        fs::remove_all(path_);
        fs::create_directories(path_);
    }
    ~TempDir() { fs::remove_all(path_); }
    std::string operator/(const std::string& name) const { return path_ + "/" + name; }
    const std::string& path() const { return path_; }

private:
    std::string path_;
};

const HttpHeaders kFor100s = {{"cache-control", "max-age=100"}};

class HttpCacheRead : public ::testing::Test {
protected:
    void SetUp() override {
        tile_ = noise(5000, 3);
        std::ofstream(dir_ / "tile.bin", std::ios::binary)
            .write(reinterpret_cast<const char*>(tile_.data()), std::streamsize(tile_.size()));
        server_ = std::make_unique<TileServer>(dir_.path());
        HttpCacheSettings s;
        s.now = [this] { return int64_t(std::time(nullptr)) + offset_.load(); };
        cache_ = std::make_shared<HttpCache>(dir_ / "http.sqlite", s);
    }

    // Read through the cache, counted.
    std::vector<unsigned char> read(const std::string& path) {
        ResourceOptions o;
        o.cache = cache_;
        o.counters = &counters_;
        return readResource(server_->url(path), o);
    }
    // The requests the server answered for `path` (as "304 PATH": those it answered 304).
    int requests(const std::string& path) {
        const std::vector<unsigned char> body = readResource(server_->url("/requests"));
        return nlohmann::json::parse(body.begin(), body.end()).value(path, 0);
    }

    TempDir dir_;
    std::vector<unsigned char> tile_;
    std::unique_ptr<TileServer> server_;
    // Seconds the cache's clock is off the system's. The server's Date is the system's time: a read made "200 s ago"
    // is made with the clock 200 s back, and aged by setting it right.
    std::atomic<int64_t> offset_{0};
    std::shared_ptr<HttpCache> cache_;
    ResourceCounters counters_;
};

}  // namespace

TEST_F(HttpCacheRead, AFreshEntryIsReadWithoutARequest) {
    const std::string path = "/cache/100/etag/tile.bin";
    EXPECT_EQ(read(path), tile_);
    EXPECT_EQ(read(path), tile_);
    EXPECT_EQ(requests(path), 1);
    EXPECT_EQ(counters_.cacheHits.load(), 1u);
    EXPECT_GE(counters_.bytes.load(), tile_.size());  // the cache's body counted (the network's may be too)
    EXPECT_TRUE(cache_->warnings().empty());
}

TEST_F(HttpCacheRead, AStaleEntryWithAnETagIsRevalidated) {
    const std::string path = "/cache/100/etag/tile.bin";
    offset_ = -200;  // the first read 200 s ago
    EXPECT_EQ(read(path), tile_);
    offset_ = 0;  // now: past max-age
    EXPECT_EQ(read(path), tile_);
    EXPECT_EQ(requests(path), 2);
    EXPECT_EQ(requests("304 " + path), 1);  // the second was If-None-Match, answered Not Modified
    EXPECT_EQ(counters_.revalidated.load(), 1u);
    EXPECT_EQ(read(path), tile_);  // the 304 made it fresh again
    EXPECT_EQ(requests(path), 2);
    EXPECT_EQ(counters_.cacheHits.load(), 1u);
}

TEST_F(HttpCacheRead, AStaleEntryWithLastModifiedIsRevalidated) {
    const std::string path = "/cache/100/lastmod/tile.bin";
    offset_ = -200;  // the first read 200 s ago
    EXPECT_EQ(read(path), tile_);
    offset_ = 0;
    EXPECT_EQ(read(path), tile_);
    EXPECT_EQ(requests(path), 2);
    EXPECT_EQ(requests("304 " + path), 1);  // If-Modified-Since
    EXPECT_EQ(counters_.revalidated.load(), 1u);
}

TEST_F(HttpCacheRead, NoStoreIsNeverStored) {
    const std::string path = "/cache/no-store/etag/tile.bin";
    EXPECT_EQ(read(path), tile_);
    EXPECT_EQ(read(path), tile_);
    EXPECT_EQ(requests(path), 2);
    EXPECT_EQ(requests("304 " + path), 0);  // nothing stored: nothing to revalidate
    EXPECT_EQ(cache_->entryCount(), 0u);
}

TEST_F(HttpCacheRead, NoCacheIsRevalidatedEveryTime) {
    const std::string path = "/cache/no-cache/etag/tile.bin";
    EXPECT_EQ(read(path), tile_);
    EXPECT_EQ(read(path), tile_);
    EXPECT_EQ(read(path), tile_);
    EXPECT_EQ(requests(path), 3);
    EXPECT_EQ(requests("304 " + path), 2);
    EXPECT_EQ(counters_.revalidated.load(), 2u);
    EXPECT_EQ(counters_.cacheHits.load(), 0u);
}

TEST_F(HttpCacheRead, ExpiresCountsFromDate) {
    const std::string path = "/cache/expires/none/tile.bin";  // Expires 100 s after Date, no validator
    offset_ = -200;                                           // the first read 200 s ago
    EXPECT_EQ(read(path), tile_);
    EXPECT_EQ(read(path), tile_);
    EXPECT_EQ(requests(path), 1);
    offset_ = 0;
    EXPECT_EQ(read(path), tile_);  // stale, nothing to revalidate with: read again, plainly
    EXPECT_EQ(requests(path), 2);
    EXPECT_EQ(requests("304 " + path), 0);
    EXPECT_EQ(read(path), tile_);  // the new response replaced the old
    EXPECT_EQ(requests(path), 2);
}

TEST_F(HttpCacheRead, AResponseThatSaysNothingIsNotStored) {
    const std::string path = "/cache/none/none/tile.bin";
    EXPECT_EQ(read(path), tile_);
    EXPECT_EQ(read(path), tile_);
    EXPECT_EQ(requests(path), 2);
    EXPECT_EQ(cache_->entryCount(), 0u);
}

TEST_F(HttpCacheRead, ACacheThatCannotBeOpenedLeavesReadsToTheNetwork) {
    cache_ = std::make_shared<HttpCache>(dir_ / "missing/dir/http.sqlite");
    EXPECT_FALSE(cache_->enabled());
    ASSERT_EQ(cache_->warnings().size(), 1u);
    EXPECT_NE(cache_->warnings()[0].find("the cache is off"), std::string::npos) << cache_->warnings()[0];
    const std::string path = "/cache/100/etag/tile.bin";
    EXPECT_EQ(read(path), tile_);
    EXPECT_EQ(read(path), tile_);
    EXPECT_EQ(requests(path), 2);
}

TEST(HttpCache, EvictsTheLeastRecentlyUsedNotTheOldest) {
    TempDir dir;
    HttpCacheSettings s;
    s.maxBytes = 2500;  // two entries of 1037 bytes (1000 of body, the header line, the URL), not three
    HttpCache cache(dir / "http.sqlite", s);
    const std::vector<unsigned char> a = noise(1000, 1), b = noise(1000, 2), c = noise(1000, 3);
    ASSERT_TRUE(cache.store("http://h/a", 200, kFor100s, a));
    ASSERT_TRUE(cache.store("http://h/b", 200, kFor100s, b));
    EXPECT_EQ(cache.totalBytes(), 2074u);
    ASSERT_TRUE(cache.find("http://h/a"));  // a used after b was stored
    ASSERT_TRUE(cache.store("http://h/c", 200, kFor100s, c));
    EXPECT_FALSE(cache.find("http://h/b"));
    EXPECT_EQ(cache.find("http://h/a").value_or(CachedResponse()).body, a);
    EXPECT_EQ(cache.find("http://h/c").value_or(CachedResponse()).body, c);
    EXPECT_EQ(cache.entryCount(), 2u);
    EXPECT_EQ(cache.totalBytes(), 2074u);
    EXPECT_FALSE(cache.store("http://h/big", 200, kFor100s, noise(3000, 4)));  // larger than the cache
    EXPECT_TRUE(cache.warnings().empty());
}

TEST(HttpCache, TwoProcessesShareOneFile) {
    TempDir dir;
    const std::string file = dir / "http.sqlite";
    int gate[2];
    ASSERT_EQ(::pipe(gate), 0);
    pid_t children[2];
    for (int child = 0; child < 2; ++child) {
        children[child] = ::fork();
        ASSERT_GE(children[child], 0);
        if (children[child] > 0) continue;
        ::close(gate[1]);
        char c;
        while (::read(gate[0], &c, 1) < 0 && errno == EINTR) {
        }                       // the gate closed: both start together
        HttpCache cache(file);  // its own connection, made after the fork
        bool ok = cache.enabled();
        for (int i = 0; i < 100; ++i) {
            const std::string url = "http://h/" + std::to_string(child) + "/" + std::to_string(i);
            ok = ok && cache.store(url, 200, kFor100s, noise(2000, unsigned(child * 1000 + i)));
            ok = ok && cache.find(url).value_or(CachedResponse()).body == noise(2000, unsigned(child * 1000 + i));
        }
        for (const std::string& w : cache.warnings()) std::fprintf(stderr, "child %d: %s\n", child, w.c_str());
        ::_exit(ok && cache.warnings().empty() ? 0 : 1);
    }
    ::close(gate[0]);
    ::close(gate[1]);
    for (pid_t pid : children) {
        int status = 0;
        ASSERT_EQ(::waitpid(pid, &status, 0), pid);
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "a child failed (its warnings above)";
    }
    HttpCache cache(file);
    EXPECT_EQ(cache.entryCount(), 200u);
    for (int child = 0; child < 2; ++child)
        for (int i = 0; i < 100; ++i) {
            const std::string url = "http://h/" + std::to_string(child) + "/" + std::to_string(i);
            EXPECT_EQ(cache.find(url).value_or(CachedResponse()).body, noise(2000, unsigned(child * 1000 + i))) << url;
        }
    EXPECT_TRUE(cache.warnings().empty());
}

TEST(HttpCache, AWriterKilledInTheMiddleLosesOnlyItsWrite) {
    TempDir dir;
    const std::string file = dir / "http.sqlite";
    const std::vector<unsigned char> kept = noise(3000, 5);
    int ready[2];
    ASSERT_EQ(::pipe(ready), 0);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        ::close(ready[0]);
        bool armed = false;
        HttpCacheSettings s;
        s.beforeCommit = [&] {
            if (!armed) return;
            // Inside the transaction, its pages written: say so and wait to be killed.
            if (::write(ready[1], "x", 1) != 1) ::_exit(2);
            for (;;) ::pause();
        };
        HttpCache cache(file, s);
        if (!cache.store("http://h/kept", 200, kFor100s, kept)) ::_exit(3);
        armed = true;
        cache.store("http://h/big", 200, kFor100s, noise(8 << 20, 6));  // more than SQLite's page cache holds
        ::_exit(4);
    }
    ::close(ready[1]);
    char c = 0;
    pollfd p{ready[0], POLLIN, 0};
    const bool arrived = ::poll(&p, 1, 60000) == 1 && ::read(ready[0], &c, 1) == 1;  // EOF: the child ended early
    ::close(ready[0]);
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(arrived && c == 'x') << "the child did not reach its commit (status " << status << ")";

    HttpCache cache(file);
    EXPECT_TRUE(cache.enabled());
    EXPECT_EQ(cache.find("http://h/kept").value_or(CachedResponse()).body, kept);
    EXPECT_FALSE(cache.find("http://h/big"));
    EXPECT_EQ(cache.entryCount(), 1u);
    EXPECT_EQ(cache.totalBytes(), kept.size() + 27 + 13);  // body, "cache-control: max-age=100\n", URL
    ASSERT_TRUE(cache.store("http://h/after", 200, kFor100s, kept));
    EXPECT_TRUE(cache.find("http://h/after"));
    EXPECT_TRUE(cache.warnings().empty());
}

TEST(HttpCache, ACorruptFileIsMadeAnewWithAWarning) {
    TempDir dir;
    const std::string file = dir / "http.sqlite";
    const std::vector<unsigned char> junk = noise(65536, 7);
    std::ofstream(file, std::ios::binary)
        .write(reinterpret_cast<const char*>(junk.data()), std::streamsize(junk.size()));
    HttpCache cache(file);
    EXPECT_TRUE(cache.enabled());
    ASSERT_EQ(cache.warnings().size(), 1u);
    EXPECT_NE(cache.warnings()[0].find("is not a cache database"), std::string::npos) << cache.warnings()[0];
    EXPECT_NE(cache.warnings()[0].find("made anew"), std::string::npos) << cache.warnings()[0];
    ASSERT_TRUE(cache.store("http://h/a", 200, kFor100s, junk));
    EXPECT_EQ(cache.find("http://h/a").value_or(CachedResponse()).body, junk);
}

TEST(HttpCache, ARefreshUpdatesTheHeadersAndTheTime) {
    TempDir dir;
    int64_t now = 1000;
    HttpCacheSettings s;
    s.now = [&] { return now; };
    HttpCache cache(dir / "http.sqlite", s);
    ASSERT_TRUE(cache.store("http://h/a", 200, {{"cache-control", "max-age=10"}, {"etag", "\"1\""}}, noise(10, 8)));
    now = 2000;
    ASSERT_TRUE(cache.refresh("http://h/a", {{"cache-control", "max-age=20"}}));
    const CachedResponse r = cache.find("http://h/a").value_or(CachedResponse());
    EXPECT_EQ(r.storedAt, 2000);
    EXPECT_EQ(r.body, noise(10, 8));
    const HttpHeaders expected = {{"etag", "\"1\""}, {"cache-control", "max-age=20"}};
    EXPECT_EQ(r.headers, expected);
    EXPECT_FALSE(cache.refresh("http://h/none", {}));
}

TEST(HttpCache, AnEntryVariesOnTheRequestHeadersItNames) {
    TempDir dir;
    HttpCache cache(dir / "http.sqlite");
    const HttpHeaders h = {{"cache-control", "max-age=100"}, {"vary", "X-Key"}};
    ASSERT_TRUE(cache.store("http://h/a", 200, h, noise(10, 9), {"X-Key: one"}));
    EXPECT_TRUE(cache.find("http://h/a", {"X-Key: one"}));
    EXPECT_FALSE(cache.find("http://h/a", {"X-Key: two"}));
    EXPECT_FALSE(cache.find("http://h/a"));
}
