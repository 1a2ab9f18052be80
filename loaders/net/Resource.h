// Reading a resource (a tile's content, a tileset.json) from a file, a data: URI or an http:// or https:// URL
// (libcurl), with the failures of a network named: a status, a refused connection, a stalled or dropped transfer;
// and the origin rule that keeps a resource read over the network from naming local files.
#pragma once
#include "loaders/gltf/Gltf.h"  // sg::LoadError(file, jsonPath, reason)

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace sg {

class HttpCache;  // loaders/net/HttpCache.h

// What the reads with these options did, counted as they happen (loader threads add at once).
struct ResourceCounters {
    std::atomic<uint64_t> requests{0};     // HTTP requests sent (a revalidation counts; a fresh cache hit does not)
    std::atomic<uint64_t> cacheHits{0};    // answered from the disk cache without a request
    std::atomic<uint64_t> revalidated{0};  // answered 304 Not Modified: the cached body used
    std::atomic<uint64_t> connections{0};  // new connections opened (the rest reused one)
    std::atomic<uint64_t> http2{0};        // responses that came over HTTP/2
    std::atomic<uint64_t> bytesOnWire{0};  // bodies as sent (compressed)
    std::atomic<uint64_t> bytes{0};        // what the reads returned: files, data: URIs and http(s) bodies decoded
};

struct ResourceOptions {
    double connectTimeoutSeconds = 10.0;
    // A transfer slower than 1 byte/s for this long fails (a stalled server), whatever its total length.
    double stallSeconds = 15.0;
    size_t maxBytes = size_t(1) << 31;  // larger resources are refused (before reading when the length is known)
    // PEM file of the certificate authorities https servers are checked against, instead of the system's; empty:
    // the system's. Certificates are always verified.
    std::string caFile;
    const std::atomic<bool>* cancel = nullptr;  // set by another thread: the read stops soon and throws LoadError
                                                // with reason "cancelled"
    // Request headers sent with every http(s) read, "Name: value" each (a token: "Authorization: Bearer ...").
    // libcurl keeps Authorization and Cookie headers from another host a redirect leads to.
    std::vector<std::string> headers;
    // The disk cache http(s) reads go through; none: every read is a request.
    std::shared_ptr<HttpCache> cache;
    // Requests in flight to one host (scheme, host and port) at most, whichever threads make them; the rest wait.
    size_t maxRequestsPerHost = 6;
    ResourceCounters* counters = nullptr;  // counted here when set
};

// http:// or https:// (case-insensitive scheme).
bool isUrl(const std::string& s);

// `relative` resolved against the resource `base` (a path or URL): absolute URLs and absolute paths as they are;
// otherwise relative to base's directory, with "./" and "../" segments folded for URLs, a query string of base not
// carried over, percent-encoding kept as it is. (3D Tiles content URIs are relative to the tileset.json that names
// them.) Against a URL, a path starting with "/" keeps base's scheme and host, as in a browser.
std::string resolveUri(const std::string& base, const std::string& relative);

// A data: URI (RFC 2397; case-insensitive scheme).
bool isDataUri(const std::string& s);

// The origin rule, as browsers keep it: a resource read over the network (http, https) may name only network
// resources and data: URIs; a local one (a path, a file: URL) may name anything. `relative`, named by `referrer` at
// `jsonPath` of it, resolved against it (resolveUri); throws LoadError(referrer, jsonPath, reason) when the rule
// refuses it, the reason naming the rule and the URI. Every URI a tileset, subtree or tile names goes through this.
// A relative reference from a URL with a query string carries that query's parameters (an access key, say) that
// the reference does not set itself, as 3D Tiles servers expect.
std::string resolveReference(const std::string& referrer, const std::string& relative,
                             const std::string& jsonPath = "");

// The bytes of a file, data: URI or URL (file:// URLs are read as paths). Throws LoadError(uriOrPath, "", reason): the
// reason names what happened, e.g. "HTTP 404 Not Found", "HTTP 500", "connection refused", "no data for 15 s",
// "connection closed after 1024 of 4096 bytes", "cancelled", "larger than the limit", "not a regular file",
// "no such file". Only regular files are opened (a FIFO is refused, not waited on). Redirects are followed (at most
// 5), to http and https only, and from https to https only. Thread-safe: loader threads call it at once, on
// connections they share (kept alive, HTTP/2 multiplexed), at most maxRequestsPerHost of them in flight to a host.
std::vector<unsigned char> readResource(const std::string& uriOrPath, const ResourceOptions& options = {});

}  // namespace sg
