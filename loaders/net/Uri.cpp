// resolveUri: RFC 3986's reference resolution for URLs, plain directory joining for paths; resolveReference adds
// the origin rule. And the small text helpers the readers share (internal/Net.h).
#include "loaders/net/Resource.h"
#include "loaders/net/internal/Net.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <vector>

namespace sg {

namespace net {

void fail(const std::string& name, const std::string& reason) { throw LoadError(name, "", reason); }

bool startsWithNoCase(const std::string& s, const char* prefix) {
    const size_t n = std::strlen(prefix);
    if (s.size() < n) return false;
    for (size_t i = 0; i < n; ++i)
        if (std::tolower(static_cast<unsigned char>(s[i])) != prefix[i]) return false;
    return true;
}

namespace {

int hexDigit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

}  // namespace

std::string percentDecoded(const std::string& s) {
    std::string out;
    out.reserve(s.size());
    for (size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '%' && i + 2 < s.size() && hexDigit(s[i + 1]) >= 0 && hexDigit(s[i + 2]) >= 0) {
            out += char(hexDigit(s[i + 1]) * 16 + hexDigit(s[i + 2]));
            i += 2;
        } else {
            out += s[i];
        }
    }
    return out;
}

bool cancelled(const ResourceOptions& o) { return o.cancel && o.cancel->load(std::memory_order_relaxed); }

}  // namespace net

namespace {

using net::startsWithNoCase;

// The length of a leading "scheme:" (RFC 3986: a letter, then letters, digits, "+", "-", "."), 0 when none. Two
// characters at least, so that a drive letter ("C:") reads as a path.
size_t schemeLength(const std::string& s) {
    size_t i = 0;
    while (i < s.size() &&
           (std::isalnum(static_cast<unsigned char>(s[i])) || s[i] == '+' || s[i] == '-' || s[i] == '.'))
        ++i;
    if (i < 2 || i >= s.size() || s[i] != ':' || !std::isalpha(static_cast<unsigned char>(s[0]))) return 0;
    return i + 1;
}

// RFC 3986 5.2.4 on a path that starts with "/": "." dropped, ".." takes the segment before it (none above the root).
std::string removeDotSegments(const std::string& path) {
    std::vector<std::string> kept;
    bool trailingSlash = false;
    for (size_t b = 1;;) {
        size_t e = path.find('/', b);
        const bool last = e == std::string::npos;
        if (last) e = path.size();
        const std::string seg = path.substr(b, e - b);
        if (seg == "." || seg == "..") {
            if (seg == ".." && !kept.empty()) kept.pop_back();
            trailingSlash = last;  // "a/.." names the directory a was in
        } else {
            kept.push_back(seg);
            trailingSlash = false;
        }
        if (last) break;
        b = e + 1;
    }
    std::string out;
    for (const std::string& s : kept) out += "/" + s;
    if (trailingSlash || out.empty()) out += "/";
    return out;
}

}  // namespace

bool isUrl(const std::string& s) { return startsWithNoCase(s, "http://") || startsWithNoCase(s, "https://"); }

std::string resolveUri(const std::string& base, const std::string& relative) {
    if (relative.empty()) return base;
    if (schemeLength(relative)) return relative;  // an absolute URL (http:, https:, file:, data:)
    const size_t scheme = schemeLength(base);
    if (!scheme || base.compare(scheme, 2, "//") != 0) {
        if (relative[0] == '/') return relative;
        // Paths are joined, not folded: "a/../b" is not "b" when a is a symbolic link to another directory.
        const size_t slash = base.rfind('/');
        return slash == std::string::npos ? relative : base.substr(0, slash + 1) + relative;
    }
    if (relative.compare(0, 2, "//") == 0) return base.substr(0, scheme) + relative;  // another host, same scheme
    size_t pathStart = base.find_first_of("/?#", scheme + 2);
    if (pathStart == std::string::npos) pathStart = base.size();
    size_t pathEnd = base.find_first_of("?#", pathStart);
    if (pathEnd == std::string::npos) pathEnd = base.size();
    std::string basePath = base.substr(pathStart, pathEnd - pathStart);
    if (basePath.empty()) basePath = "/";
    // The reference's own query and fragment follow the folded path untouched.
    const size_t relEnd = std::min(relative.find_first_of("?#"), relative.size());
    const std::string relPath = relative.substr(0, relEnd);
    std::string merged;
    if (relPath.empty())
        merged = basePath;
    else if (relPath[0] == '/')
        merged = relPath;
    else
        merged = basePath.substr(0, basePath.rfind('/') + 1) + relPath;
    return base.substr(0, pathStart) + removeDotSegments(merged) + relative.substr(relEnd);
}

bool isDataUri(const std::string& s) { return startsWithNoCase(s, "data:"); }

namespace {

// "https://host:port" of a URL, lower-cased; "" for anything else.
std::string originOf(const std::string& url) {
    const size_t scheme = schemeLength(url);
    if (!scheme || url.compare(scheme, 2, "//") != 0) return "";
    std::string o = url.substr(0, std::min(url.find_first_of("/?#", scheme + 2), url.size()));
    for (char& c : o) c = char(std::tolower(static_cast<unsigned char>(c)));
    return o;
}

// The "name=value" parts of a URL's query ("" when it has none).
std::vector<std::string> queryParts(const std::string& url) {
    std::vector<std::string> parts;
    const size_t hash = std::min(url.find('#'), url.size());
    const size_t q = url.find('?');
    if (q >= hash) return parts;  // none, or a "?" inside the fragment
    const std::string query = url.substr(q + 1, hash - q - 1);
    for (size_t b = 0; b <= query.size();) {
        const size_t e = std::min(query.find('&', b), query.size());
        if (e > b) parts.push_back(query.substr(b, e - b));
        b = e + 1;
    }
    return parts;
}

std::string keyOf(const std::string& part) { return part.substr(0, part.find('=')); }

// `uri` with the parameters of base's query that it does not set itself, before its fragment.
std::string withQueryOf(const std::string& uri, const std::string& base) {
    const std::vector<std::string> own = queryParts(uri);
    std::string added;
    for (const std::string& p : queryParts(base)) {
        const bool set =
            std::any_of(own.begin(), own.end(), [&](const std::string& o) { return keyOf(o) == keyOf(p); });
        if (!set) added += (added.empty() ? "" : "&") + p;
    }
    if (added.empty()) return uri;
    const size_t hash = std::min(uri.find('#'), uri.size());
    const bool hasQuery = uri.find('?') < hash;
    const bool open = hasQuery && uri[hash - 1] != '?' && uri[hash - 1] != '&';
    return uri.substr(0, hash) + (hasQuery ? (open ? "&" : "") : "?") + added + uri.substr(hash);
}

}  // namespace

std::string resolveReference(const std::string& referrer, const std::string& relative, const std::string& jsonPath) {
    std::string uri = resolveUri(referrer, relative);
    if (isUrl(referrer) && !isUrl(uri) && !isDataUri(uri)) {
        const std::string shown = relative.size() > 200 ? relative.substr(0, 200) + "..." : relative;
        throw LoadError(referrer, jsonPath,
                        "'" + shown +
                            "' refused: a resource read over the network may name only http, https and data: URIs, "
                            "not local files (origin rule)");
    }
    // The key goes only where the reference is relative: never to another server.
    if (isUrl(referrer) && !schemeLength(relative) && originOf(uri) == originOf(referrer))
        uri = withQueryOf(uri, referrer);
    return uri;
}

}  // namespace sg
