// readCached: an http(s) read through the disk cache (ResourceOptions::cache), as a browser's: a fresh entry
// without a request, a stale one revalidated, a new response stored when its headers allow it. The cache failing
// (a full disk, a damaged file) never fails the read: the cache keeps a warning and the network answers.
#include "loaders/net/HttpCache.h"
#include "loaders/net/internal/HttpCachePolicy.h"
#include "loaders/net/internal/Net.h"

#include <exception>
#include <optional>

namespace sg::net {

namespace {

void count(std::atomic<uint64_t> ResourceCounters::*counter, const ResourceOptions& o, uint64_t n = 1) {
    if (o.counters) (o.counters->*counter) += n;
}

// The cache's entry for `url`; none when the cache cannot say (its warning kept).
std::optional<CachedResponse> lookUp(HttpCache& cache, const std::string& url, const ResourceOptions& o) {
    try {
        return cache.find(url, o.headers);
    } catch (const std::exception& e) {  // out of memory for a large body: read it from the network instead
        cache.warn("reading " + url + " from the HTTP cache: " + e.what());
        return {};
    }
}

void keep(HttpCache& cache, const std::string& url, const HttpResponse& r, const ResourceOptions& o, bool hadEntry) {
    try {
        // A response that may not be stored replaces a stored one all the same: the old one is not to be used.
        if (!cache.store(url, r.status, r.headers, r.body, o.headers) && hadEntry) cache.remove(url);
    } catch (const std::exception& e) {
        cache.warn("storing " + url + " in the HTTP cache: " + e.what());
    }
}

}  // namespace

std::vector<unsigned char> readCached(const std::string& url, const ResourceOptions& o) {
    if (cancelled(o)) fail(url, "cancelled");
    HttpCache& cache = *o.cache;
    std::optional<CachedResponse> entry = lookUp(cache, url, o);
    if (entry && isFresh(entry->headers, entry->storedAt, cache.now())) {
        count(&ResourceCounters::cacheHits, o);
        count(&ResourceCounters::bytes, o, entry->body.size());
        return std::move(entry->body);
    }
    // Stale (or no-cache): asked again, conditionally when the entry has a validator.
    const std::vector<std::string> conditions = entry ? conditionalHeaders(entry->headers) : std::vector<std::string>();
    HttpResponse r = fetchUrl(url, o, conditions);
    if (r.status == 304) {
        if (conditions.empty()) fail(url, "HTTP 304 Not Modified to a request that was not conditional");
        try {
            cache.refresh(url, r.headers);
        } catch (const std::exception& e) {
            cache.warn("refreshing " + url + " in the HTTP cache: " + e.what());
        }
        count(&ResourceCounters::revalidated, o);
        count(&ResourceCounters::bytes, o, entry->body.size());
        return std::move(entry->body);
    }
    keep(cache, url, r, o, entry.has_value());
    return std::move(r.body);
}

}  // namespace sg::net
