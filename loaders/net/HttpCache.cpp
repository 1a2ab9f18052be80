// HttpCache: lookups, stores, revalidations and the LRU eviction, each one short statement or one transaction on
// the cache's connection; every failure a warning, never an exception.
#include "loaders/net/HttpCache.h"
#include "loaders/net/internal/HttpCacheDb.h"
#include "loaders/net/internal/HttpCachePolicy.h"

#include <algorithm>
#include <cstdio>
#include <ctime>

namespace sg {

namespace {

// Kept headers as stored: "name: value" lines.
std::string headerText(const HttpHeaders& headers) {
    std::string text;
    for (const auto& h : headers) text += h.first + ": " + h.second + "\n";
    return text;
}

HttpHeaders parsedHeaders(const std::string& text) {
    HttpHeaders headers;
    size_t at = 0;
    while (at < text.size()) {
        size_t end = text.find('\n', at);
        if (end == std::string::npos) end = text.size();
        const std::string line = text.substr(at, end - at);
        const size_t colon = line.find(": ");
        if (colon != std::string::npos) headers.emplace_back(line.substr(0, colon), line.substr(colon + 2));
        at = end + 1;
    }
    return headers;
}

}  // namespace

HttpCache::HttpCache(const std::string& file, HttpCacheSettings settings)
    : file_(file), settings_(std::move(settings)) {
    open();
}

HttpCache::~HttpCache() = default;

void HttpCache::open() {
    bool madeAnew = false;
    for (int busy = 0;;) {
        try {
            db_ = std::make_unique<Db>(file_);
            return;
        } catch (const HttpCacheDbError& e) {
            // Another process making the file at the same moment: its lock is short.
            if ((e.code == SQLITE_BUSY || e.code == SQLITE_LOCKED) && ++busy < 5) {
                sqlite3_sleep(200);
                continue;
            }
            if (!e.notACache() || madeAnew) {
                warn("the HTTP cache " + file_ + ": " + e.what() + "; the cache is off");
                return;
            }
            warn("the HTTP cache " + file_ + " is not a cache database (" + e.what() + "): made anew");
            for (const char* suffix : {"", "-wal", "-shm", "-journal"}) std::remove((file_ + suffix).c_str());
            madeAnew = true;
        } catch (const std::exception& e) {  // out of memory
            warn("the HTTP cache " + file_ + ": " + e.what() + "; the cache is off");
            return;
        }
    }
}

bool HttpCache::enabled() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return db_ != nullptr;
}

int64_t HttpCache::now() const { return settings_.now ? settings_.now() : int64_t(std::time(nullptr)); }

void HttpCache::warn(const std::string& message) {
    std::lock_guard<std::mutex> lock(warningsMutex_);
    if (warnings_.size() < 64 && std::find(warnings_.begin(), warnings_.end(), message) == warnings_.end())
        warnings_.push_back(message);
}

std::vector<std::string> HttpCache::warnings() const {
    std::lock_guard<std::mutex> lock(warningsMutex_);
    return warnings_;
}

void HttpCache::fail(const std::string& what) {
    const int code = db_->errorCode();
    const std::string reason = db_->error();
    if (code == SQLITE_CORRUPT || code == SQLITE_NOTADB) {
        warn("the HTTP cache " + file_ + " is damaged (" + what + ": " + reason + "); the cache is off");
        db_.reset();
    } else {
        warn("the HTTP cache " + file_ + ": " + what + ": " + reason);
    }
}

bool HttpCache::write(const std::string& what, const std::function<bool()>& body) {
    if (StatementUse(db_->begin).step() != SQLITE_DONE) {
        fail(what);
        return false;
    }
    bool done = body();
    if (done && settings_.beforeCommit) settings_.beforeCommit();
    if (done && StatementUse(db_->commit).step() == SQLITE_DONE) return true;
    fail(what);
    // A failed step may have rolled back already (then this ROLLBACK fails, harmlessly).
    if (db_) StatementUse(db_->rollback).step();
    return false;
}

std::optional<CachedResponse> HttpCache::find(const std::string& url, const std::vector<std::string>& requestHeaders) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!db_) return {};
    CachedResponse r;
    int64_t id = 0;
    std::string vary;
    {
        StatementUse s(db_->find);
        const int rc = s.text(1, url).step();
        if (rc == SQLITE_DONE) return {};
        if (rc != SQLITE_ROW) {
            fail("reading " + url);
            return {};
        }
        id = s.integerAt(0);
        r.status = long(s.integerAt(1));
        r.headers = parsedHeaders(s.textAt(2));
        vary = s.textAt(3);
        r.storedAt = s.integerAt(4);
        r.body = s.blobAt(5);
    }
    if (net::varyKey(r.headers, requestHeaders) != vary) return {};
    if (StatementUse(db_->touch).integer(1, id).integer(2, now()).step() != SQLITE_DONE) fail("marking " + url);
    return r;
}

bool HttpCache::store(const std::string& url, long status, const HttpHeaders& headers,
                      const std::vector<unsigned char>& body, const std::vector<std::string>& requestHeaders) {
    const int64_t t = now();
    if (!net::storable(status, headers, t)) return false;
    const std::string kept = headerText(net::keptHeaders(headers));
    const std::string vary = net::varyKey(headers, requestHeaders);
    const uint64_t size = uint64_t(body.size()) + kept.size() + url.size();
    if (size > settings_.maxBytes) return false;
    std::lock_guard<std::mutex> lock(mutex_);
    if (!db_) return false;
    return write("storing " + url, [&] {
        if (StatementUse(db_->removeUrl).text(1, url).step() != SQLITE_DONE) return false;
        StatementUse add(db_->insert);
        add.text(1, url).integer(2, status).text(3, kept).text(4, vary).integer(5, t).integer(6, int64_t(size));
        if (add.step() != SQLITE_DONE) return false;
        const int64_t id = sqlite3_last_insert_rowid(db_->db);
        if (StatementUse(db_->insertBody).integer(1, id).blob(2, body).step() != SQLITE_DONE) return false;
        // The least recently used entries go until the rest fits (the new one stays: it fits alone).
        for (;;) {
            StatementUse total(db_->total);
            if (total.step() != SQLITE_ROW) return false;
            if (uint64_t(total.integerAt(0)) <= settings_.maxBytes) return true;
            StatementUse oldest(db_->oldest);
            const int rc = oldest.integer(1, id).step();
            if (rc == SQLITE_DONE) return true;
            if (rc != SQLITE_ROW) return false;
            if (StatementUse(db_->removeId).integer(1, oldest.integerAt(0)).step() != SQLITE_DONE) return false;
        }
    });
}

bool HttpCache::remove(const std::string& url) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!db_) return false;
    if (StatementUse(db_->removeUrl).text(1, url).step() != SQLITE_DONE) {
        fail("removing " + url);
        return false;
    }
    return sqlite3_changes(db_->db) > 0;
}

bool HttpCache::refresh(const std::string& url, const HttpHeaders& notModifiedHeaders) {
    const int64_t t = now();
    std::lock_guard<std::mutex> lock(mutex_);
    if (!db_) return false;
    bool found = false;
    write("refreshing " + url, [&] {
        StatementUse entry(db_->select);
        const int rc = entry.text(1, url).step();
        if (rc != SQLITE_ROW) return rc == SQLITE_DONE;
        const int64_t id = entry.integerAt(0), size = entry.integerAt(2);
        const std::string old = entry.textAt(1);
        const std::string fresh = headerText(net::refreshedHeaders(parsedHeaders(old), notModifiedHeaders));
        const int64_t newSize = size - int64_t(old.size()) + int64_t(fresh.size());
        StatementUse update(db_->update);
        found = update.integer(1, id).text(2, fresh).integer(3, t).integer(4, newSize).step() == SQLITE_DONE;
        return found;
    });
    return found;
}

uint64_t HttpCache::entryCount() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!db_) return 0;
    StatementUse s(db_->count);
    return s.step() == SQLITE_ROW ? uint64_t(s.integerAt(0)) : 0;
}

uint64_t HttpCache::totalBytes() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!db_) return 0;
    StatementUse s(db_->total);
    return s.step() == SQLITE_ROW ? uint64_t(s.integerAt(0)) : 0;
}

}  // namespace sg
