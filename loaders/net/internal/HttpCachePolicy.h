// The freshness rules of a private HTTP cache (RFC 9111, the common parts): what may be stored, how long it stays
// fresh, how a stale entry is revalidated. Pure functions of headers and times (seconds since the epoch).
#pragma once
#include "loaders/net/HttpCache.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace sg::net {

struct CacheControl {
    bool noStore = false;
    bool noCache = false;  // stored, but revalidated before every use
    bool mustRevalidate = false;
    std::optional<int64_t> maxAge;  // s-maxage is for shared caches: ignored
};

// The directives of a Cache-Control value ("max-age=60, must-revalidate"); unknown ones and malformed values
// ignored (a max-age that is not a number is none).
CacheControl parseCacheControl(const std::string& value);

// An HTTP date (IMF-fixdate, RFC 850 or asctime); none when it is not one.
std::optional<int64_t> parseHttpDate(const std::string& value);

// The value of the last header of that lower-case name; "" when none.
std::string headerValue(const HttpHeaders& headers, const std::string& name);

// The headers a cache entry keeps: Cache-Control, Expires, Date, Age, ETag, Last-Modified, Vary.
HttpHeaders keptHeaders(const HttpHeaders& headers);

// Whether a 200 response to a GET with these headers, received at `storedAt`, may be stored and is worth it: no
// "no-store", no "Vary: *", and fresh when received or a validator (ETag, Last-Modified) to revalidate it with.
bool storable(long status, const HttpHeaders& headers, int64_t storedAt);

// How long a response stays fresh after it was made (RFC 9111 4.2.1): max-age; else Expires less Date (an Expires
// that is not a date: 0); else 10% of Date less Last-Modified (the heuristic browsers use); else 0. `storedAt`
// stands for a missing Date.
int64_t freshnessLifetime(const HttpHeaders& headers, int64_t storedAt);

// The entry's age now (RFC 9111 4.2.3): the age it had when received (Age, or how far Date was behind), plus the
// time since.
int64_t currentAge(const HttpHeaders& headers, int64_t storedAt, int64_t now);

// Whether the entry may be used without asking the server: not "no-cache", and younger than its lifetime.
bool isFresh(const HttpHeaders& headers, int64_t storedAt, int64_t now);

// The request headers that make a revalidation of the entry conditional: "If-None-Match" with its ETag,
// "If-Modified-Since" with its Last-Modified; none when it has neither (a plain request then).
std::vector<std::string> conditionalHeaders(const HttpHeaders& headers);

// The stored headers updated with a 304's (RFC 9111 4.3.4): those it sends replace the stored ones; Date and Age
// are the 304's alone (the old response's would age the refreshed entry).
HttpHeaders refreshedHeaders(const HttpHeaders& stored, const HttpHeaders& notModified);

// The request's values of the headers the response varies on ("accept-language: fr\n" each, in Vary's order;
// "" without Vary): an entry serves a request with the same values only.
std::string varyKey(const HttpHeaders& response, const std::vector<std::string>& requestHeaders);

}  // namespace sg::net
