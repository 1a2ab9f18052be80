// What the readers of loaders/net share: the failure they throw, scheme tests, percent-decoding, and the read of
// an http(s) URL (HttpRead.cpp).
#pragma once
#include "loaders/net/Resource.h"

#include <string>
#include <utility>
#include <vector>

namespace sg::net {

[[noreturn]] void fail(const std::string& name, const std::string& reason);

// Whether s starts with the lower-case `prefix`, ignoring the case of s.
bool startsWithNoCase(const std::string& s, const char* prefix);

// "%20" and the like decoded; a "%" not followed by two hex digits kept as it is.
std::string percentDecoded(const std::string& s);

bool cancelled(const ResourceOptions& o);

// The bytes of an http:// or https:// URL: through o.cache when set (readCached), else fetchUrl's body. Throws
// LoadError(url, "", reason).
std::vector<unsigned char> readUrl(const std::string& url, const ResourceOptions& o);

// One response of an http(s) server, after any redirects.
struct HttpResponse {
    long status = 0;                                           // 2xx, or 304 when the request was conditional
    std::vector<unsigned char> body;                           // decoded (gzip and the like undone); empty for a 304
    std::vector<std::pair<std::string, std::string>> headers;  // the final response's, names lower-cased, in order
    std::string url;                                           // where the final response came from

    // The value of the last header of that (lower-case) name; "" when none.
    std::string header(const std::string& name) const;
};

// One request with libcurl: ResourceOptions::headers, then `extra` ("If-None-Match: ..." of a revalidation).
// A status other than 2xx and 304 throws LoadError(url, "", "HTTP 404 Not Found"), as every failure of the network.
HttpResponse fetchUrl(const std::string& url, const ResourceOptions& o, const std::vector<std::string>& extra = {});

// readUrl through o.cache (loaders/net/HttpCache.h): a fresh entry without a request, a stale one revalidated.
std::vector<unsigned char> readCached(const std::string& url, const ResourceOptions& o);

}  // namespace sg::net
