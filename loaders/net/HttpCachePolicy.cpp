// The freshness rules of the disk cache (RFC 9111): pure functions of a response's headers and times.
#include "loaders/net/internal/HttpCachePolicy.h"

#include <curl/curl.h>
#include <algorithm>
#include <cctype>

namespace sg::net {

namespace {

std::string lowered(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::string trimmed(const std::string& s) {
    const size_t b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
    return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

// The items of a comma-separated header value, trimmed; commas inside quotes do not split.
std::vector<std::string> listItems(const std::string& value) {
    std::vector<std::string> items;
    std::string item;
    bool quoted = false;
    for (char c : value) {
        if (c == '"') quoted = !quoted;
        if (c == ',' && !quoted) {
            items.push_back(trimmed(item));
            item.clear();
        } else {
            item += c;
        }
    }
    items.push_back(trimmed(item));
    return items;
}

// A delta-seconds value (RFC 9111 1.2.2): digits only; past 2^31 it is 2^31, as the RFC asks.
std::optional<int64_t> deltaSeconds(const std::string& s) {
    if (s.empty() || !std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; })) return {};
    int64_t v = 0;
    for (char c : s) v = std::min<int64_t>(v * 10 + (c - '0'), int64_t(1) << 31);
    return v;
}

bool isKept(const std::string& name) {
    static const char* const kKept[] = {"cache-control", "expires", "date", "age", "etag", "last-modified", "vary"};
    return std::find_if(std::begin(kKept), std::end(kKept), [&](const char* k) { return name == k; }) !=
           std::end(kKept);
}

}  // namespace

CacheControl parseCacheControl(const std::string& value) {
    CacheControl cc;
    for (const std::string& item : listItems(value)) {
        const size_t eq = item.find('=');
        const std::string name = lowered(trimmed(item.substr(0, eq)));
        std::string arg = eq == std::string::npos ? "" : trimmed(item.substr(eq + 1));
        if (arg.size() >= 2 && arg.front() == '"' && arg.back() == '"') arg = arg.substr(1, arg.size() - 2);
        if (name == "no-store") cc.noStore = true;
        if (name == "no-cache") cc.noCache = true;  // no-cache="field" too: the whole entry, to be safe
        if (name == "must-revalidate") cc.mustRevalidate = true;
        if (name == "max-age") {
            const std::optional<int64_t> s = deltaSeconds(arg);
            // Two max-ages disagreeing: the shorter, so that nothing is kept longer than either allows.
            if (s && (!cc.maxAge || *s < *cc.maxAge)) cc.maxAge = s;
        }
    }
    return cc;
}

std::optional<int64_t> parseHttpDate(const std::string& value) {
    if (trimmed(value).empty()) return {};
    const time_t t = curl_getdate(value.c_str(), nullptr);
    if (t == time_t(-1)) return {};
    return int64_t(t);
}

std::string headerValue(const HttpHeaders& headers, const std::string& name) {
    for (auto it = headers.rbegin(); it != headers.rend(); ++it)
        if (it->first == name) return it->second;
    return "";
}

HttpHeaders keptHeaders(const HttpHeaders& headers) {
    HttpHeaders kept;
    for (const auto& h : headers)
        if (isKept(h.first)) kept.push_back(h);
    return kept;
}

bool storable(long status, const HttpHeaders& headers, int64_t storedAt) {
    if (status != 200) return false;
    if (parseCacheControl(headerValue(headers, "cache-control")).noStore) return false;
    for (const std::string& v : listItems(headerValue(headers, "vary")))
        if (v == "*") return false;  // varies on more than the request: never the same answer twice
    const bool validator = !headerValue(headers, "etag").empty() || !headerValue(headers, "last-modified").empty();
    return validator || isFresh(headers, storedAt, storedAt);
}

int64_t freshnessLifetime(const HttpHeaders& headers, int64_t storedAt) {
    const CacheControl cc = parseCacheControl(headerValue(headers, "cache-control"));
    if (cc.maxAge) return *cc.maxAge;
    const int64_t date = parseHttpDate(headerValue(headers, "date")).value_or(storedAt);
    const std::string expires = headerValue(headers, "expires");
    if (!expires.empty()) {
        const std::optional<int64_t> e = parseHttpDate(expires);
        return e ? std::max<int64_t>(0, *e - date) : 0;  // "Expires: 0" and the like: already expired
    }
    const std::optional<int64_t> modified = parseHttpDate(headerValue(headers, "last-modified"));
    if (modified && *modified < date) return (date - *modified) / 10;
    return 0;
}

int64_t currentAge(const HttpHeaders& headers, int64_t storedAt, int64_t now) {
    const int64_t date = parseHttpDate(headerValue(headers, "date")).value_or(storedAt);
    const int64_t apparent = std::max<int64_t>(0, storedAt - date);
    const int64_t initial = std::max(apparent, deltaSeconds(headerValue(headers, "age")).value_or(0));
    return initial + std::max<int64_t>(0, now - storedAt);
}

bool isFresh(const HttpHeaders& headers, int64_t storedAt, int64_t now) {
    if (parseCacheControl(headerValue(headers, "cache-control")).noCache) return false;
    return freshnessLifetime(headers, storedAt) > currentAge(headers, storedAt, now);
}

std::vector<std::string> conditionalHeaders(const HttpHeaders& headers) {
    std::vector<std::string> extra;
    const std::string etag = headerValue(headers, "etag"), modified = headerValue(headers, "last-modified");
    if (!etag.empty()) extra.push_back("If-None-Match: " + etag);
    if (!modified.empty()) extra.push_back("If-Modified-Since: " + modified);
    return extra;
}

HttpHeaders refreshedHeaders(const HttpHeaders& stored, const HttpHeaders& notModified) {
    const HttpHeaders fresh = keptHeaders(notModified);
    HttpHeaders out;
    for (const auto& h : stored) {
        const bool replaced =
            std::any_of(fresh.begin(), fresh.end(), [&](const auto& f) { return f.first == h.first; });
        if (!replaced && h.first != "date" && h.first != "age") out.push_back(h);
    }
    out.insert(out.end(), fresh.begin(), fresh.end());
    return out;
}

std::string varyKey(const HttpHeaders& response, const std::vector<std::string>& requestHeaders) {
    std::string key;
    for (const std::string& item : listItems(headerValue(response, "vary"))) {
        if (item.empty()) continue;
        const std::string name = lowered(item);
        std::string value;
        for (const std::string& h : requestHeaders) {
            const size_t colon = h.find(':');
            if (colon != std::string::npos && lowered(trimmed(h.substr(0, colon))) == name)
                value = trimmed(h.substr(colon + 1));
        }
        key += name + ": " + value + "\n";
    }
    return key;
}

}  // namespace sg::net
