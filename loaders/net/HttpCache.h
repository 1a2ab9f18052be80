// A disk cache of http(s) responses in one SQLite file, for ResourceOptions::cache: what a server said may be kept
// is answered from disk, a stale entry is revalidated, the least recently used entries go past a size cap. Several
// threads and several processes may use one file at once.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sg {

// Header names lower-cased, values as sent, in order.
using HttpHeaders = std::vector<std::pair<std::string, std::string>>;

struct HttpCacheSettings {
    // The cache's size cap (bodies, kept headers and URLs): past it the least recently used entries are removed. A
    // response larger than this is not stored.
    uint64_t maxBytes = uint64_t(512) << 20;
    // The clock, in seconds since the epoch; empty: the system's. Tests move it instead of waiting.
    std::function<int64_t()> now;
    // Called inside each write's transaction, before it commits (tests stop a writer there).
    std::function<void()> beforeCommit;
};

// A stored response: its body, the headers that freshness and revalidation need, and when it was received.
struct CachedResponse {
    long status = 200;
    std::vector<unsigned char> body;
    HttpHeaders headers;   // Cache-Control, Expires, Date, Age, ETag, Last-Modified, Vary (those it had)
    int64_t storedAt = 0;  // seconds since the epoch: when the response (or the last 304 for it) arrived
};

class HttpCache {
public:
    // Opens (or creates) `file`. Never throws for the file: one that is not a cache database (corrupt, another
    // program's) is made anew with a warning; one that cannot be opened or made leaves the cache off (enabled()
    // false, every find a miss, every store nothing) with a warning saying why.
    explicit HttpCache(const std::string& file, HttpCacheSettings settings = {});
    ~HttpCache();
    HttpCache(const HttpCache&) = delete;
    HttpCache& operator=(const HttpCache&) = delete;

    bool enabled() const;
    const std::string& file() const { return file_; }
    int64_t now() const;

    // The entry for `url` (with its query), as stored, fresh or not, and marked as used now; none when absent, when
    // it varies (Vary) on a request header that `requestHeaders` ("Name: value" each) sets otherwise, or when the
    // cache cannot be read (a warning kept).
    std::optional<CachedResponse> find(const std::string& url, const std::vector<std::string>& requestHeaders = {});

    // Keeps a response to a GET of `url` when the freshness rules allow it (status 200, no "no-store", no
    // "Vary: *", a lifetime or a validator to revalidate with); replaces what was stored for it, then removes
    // the least recently used entries past maxBytes. Returns whether it was stored.
    bool store(const std::string& url, long status, const HttpHeaders& headers, const std::vector<unsigned char>& body,
               const std::vector<std::string>& requestHeaders = {});

    // Forgets `url` (a response that may not be stored replaces a stored one). Returns whether it was there.
    bool remove(const std::string& url);

    // A 304 Not Modified for `url`: the stored headers updated with the 304's, the stored time made now. Returns
    // whether an entry was there to update.
    bool refresh(const std::string& url, const HttpHeaders& notModifiedHeaders);

    // Entries and their bytes as counted against maxBytes.
    uint64_t entryCount();
    uint64_t totalBytes();

    // What went wrong with the file since it was opened, each distinct message once (the first 64).
    std::vector<std::string> warnings() const;
    void warn(const std::string& message);  // kept with the cache's own (readCached's failures to store, say)

private:
    struct Db;
    std::string file_;
    HttpCacheSettings settings_;
    mutable std::mutex mutex_;  // one connection, used by one thread at a time
    std::unique_ptr<Db> db_;    // null: the cache is off
    mutable std::mutex warningsMutex_;
    std::vector<std::string> warnings_;

    void open();
    void fail(const std::string& what);  // a warning naming SQLite's error; a corrupt file turns the cache off
    bool write(const std::string& what, const std::function<bool()>& body);  // one transaction
};

}  // namespace sg
