// readUrl: http and https through libcurl, an easy handle per loader thread whose transfers run on the connections
// all threads share (HttpShare.cpp), HTTP/2 where the server offers it, compressed bodies decoded; the failures of a
// network named (a status, a refused connection, a stalled or dropped transfer) and redirects kept to the web.
#include "loaders/net/internal/HttpPool.h"
#include "loaders/net/internal/Net.h"

#include <curl/curl.h>
#include <strings.h>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <mutex>

namespace sg::net {

namespace {

// What the callbacks of one transfer share. Callbacks are C: they never throw, they stop the transfer and leave
// the reason here.
struct Transfer {
    CURL* curl = nullptr;
    const ResourceOptions* options = nullptr;
    std::vector<unsigned char> bytes;
    std::string failure;   // why a callback stopped the transfer
    std::string phrase;    // the reason phrase of the last status line ("Not Found"; HTTP/2 has none)
    std::string location;  // the Location of the last redirect
    // The stall clock: since the request went out, or since the body last grew.
    bool sent = false;
    curl_off_t lastBytes = 0;
    std::chrono::steady_clock::time_point lastChange;
    curl_slist* headers = nullptr;  // the request's own headers (ResourceOptions::headers), freed with it
    std::vector<std::pair<std::string, std::string>> received;  // the last response's headers, names lower-case
    bool encoded = false;  // the last response has a Content-Encoding: its length is the compressed one

    Transfer() = default;
    Transfer(const Transfer&) = delete;
    Transfer& operator=(const Transfer&) = delete;
    ~Transfer() { curl_slist_free_all(headers); }
};

std::string statusReason(long status, const std::string& phrase) {
    return "HTTP " + std::to_string(status) + (phrase.empty() ? "" : " " + phrase);
}

size_t onHeader(char* data, size_t size, size_t count, void* user) noexcept {
    auto& t = *static_cast<Transfer*>(user);
    const size_t n = size * count;
    // Each response of a redirect chain starts with its status line, "HTTP/1.1 404 Not Found".
    if (n > 9 && ::strncasecmp(data, "location:", 9) == 0) {
        try {
            std::string value(data + 9, n - 9);
            const size_t b = value.find_first_not_of(" \t"), e = value.find_last_not_of(" \t\r\n");
            t.location = b == std::string::npos ? "" : value.substr(b, e - b + 1);
        } catch (...) {
            t.location.clear();
        }
    }
    if (n > 5 && std::memcmp(data, "HTTP/", 5) == 0) {
        t.received.clear();  // a redirect's headers are not the resource's
        t.encoded = false;
        try {
            std::string line(data, n);
            while (!line.empty() && (line.back() == '\r' || line.back() == '\n')) line.pop_back();
            const size_t code = line.find(' ');
            const size_t text = code == std::string::npos ? code : line.find(' ', code + 1);
            t.phrase = text == std::string::npos ? "" : line.substr(text + 1);
        } catch (...) {
            t.phrase.clear();
        }
    } else if (const void* colon = std::memchr(data, ':', n)) {
        try {
            const size_t c = size_t(static_cast<const char*>(colon) - data);
            std::string name(data, c), value(data + c + 1, n - c - 1);
            for (char& ch : name) ch = char(std::tolower(static_cast<unsigned char>(ch)));
            const size_t b = value.find_first_not_of(" \t"), e = value.find_last_not_of(" \t\r\n");
            t.received.emplace_back(std::move(name), b == std::string::npos ? "" : value.substr(b, e - b + 1));
            const auto& [field, text] = t.received.back();
            if (field == "content-encoding" && !text.empty() && ::strcasecmp(text.c_str(), "identity") != 0)
                t.encoded = true;
        } catch (...) {
            return 0;  // out of memory: the transfer fails
        }
    }
    return n;
}

// The most bytes on the wire that a body within `maxBytes` can take: its length, or compressed a little more (gzip,
// brotli and zstd add a few bytes per block to what does not compress; 1/64 and 1 KiB more is ample). A compressed
// body announced or grown past this cannot decode within the limit; under it, the decoded bytes decide.
uint64_t wireLimit(size_t maxBytes, bool encoded) {
    const uint64_t m = maxBytes;
    if (!encoded) return m;
    return m >= UINT64_MAX / 2 ? UINT64_MAX : m + m / 64 + 1024;
}

size_t onData(char* data, size_t size, size_t count, void* user) noexcept {
    auto& t = *static_cast<Transfer*>(user);
    const size_t n = size * count;
    long status = 0;
    curl_easy_getinfo(t.curl, CURLINFO_RESPONSE_CODE, &status);
    if (status >= 400) {  // an error page is not the resource: stop rather than read it
        t.failure = statusReason(status, t.phrase);
        return 0;
    }
    // The bytes decoded count: a length not announced, or a compressed one, grew past the limit.
    if (n > t.options->maxBytes - t.bytes.size()) {
        t.failure = "larger than the limit";
        return 0;
    }
    try {
        if (t.bytes.empty()) {
            curl_off_t length = -1;
            curl_easy_getinfo(t.curl, CURLINFO_CONTENT_LENGTH_DOWNLOAD_T, &length);
            if (length > 0 && uint64_t(length) > wireLimit(t.options->maxBytes, t.encoded)) {
                t.failure = "larger than the limit";  // refused before reading it
                return 0;
            }
            if (length > 0 && uint64_t(length) <= t.options->maxBytes) t.bytes.reserve(size_t(length));
        }
        t.bytes.insert(t.bytes.end(), data, data + n);
    } catch (...) {
        t.failure = "out of memory";
        return 0;
    }
    return n;
}

std::string seconds(double s) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g s", s);
    return buf;
}

// Called at least once a second, even while nothing arrives: a cancel or a stall is seen within about a second.
int onProgress(void* user, curl_off_t downloadTotal, curl_off_t downloadNow, curl_off_t, curl_off_t) noexcept {
    auto& t = *static_cast<Transfer*>(user);
    const ResourceOptions& o = *t.options;
    if (cancelled(o)) {
        t.failure = "cancelled";
        return 1;
    }
    // Compressed, the body on the wire is checked against the most a body within the limit can take: a server
    // could send on and on what decodes to little.
    const uint64_t wire = wireLimit(o.maxBytes, t.encoded);
    if ((downloadTotal > 0 && uint64_t(downloadTotal) > wire) || (downloadNow > 0 && uint64_t(downloadNow) > wire)) {
        t.failure = "larger than the limit";
        return 1;
    }
    // libcurl's low-speed check averages over its last few seconds, so that a burst before a stall keeps a
    // transfer alive for about 5 s more than asked: a body that does not grow is timed here. The clock starts once
    // the request is sent (connecting has its own timeout).
    const auto now = std::chrono::steady_clock::now();
    if (!t.sent) {
        curl_off_t pretransfer = 0;
        curl_easy_getinfo(t.curl, CURLINFO_PRETRANSFER_TIME_T, &pretransfer);
        t.sent = pretransfer > 0;
        t.lastChange = now;
    } else if (downloadNow != t.lastBytes) {
        t.lastBytes = downloadNow;
        t.lastChange = now;
    } else if (o.stallSeconds > 0 && std::chrono::duration<double>(now - t.lastChange).count() >= o.stallSeconds) {
        t.failure = "no data for " + seconds(o.stallSeconds);
        return 1;
    }
    return 0;
}

// One handle per thread, kept between reads and reset before each. The connections are not the handle's but the
// transfer thread's (performShared): open for the next tile from the same server, whichever thread reads it (a TLS
// handshake can cost more than a small tile).
CURL* threadHandle() {
    static std::once_flag once;
    static CURLcode init = CURLE_FAILED_INIT;
    std::call_once(once, [] { init = curl_global_init(CURL_GLOBAL_DEFAULT); });
    if (init != CURLE_OK) return nullptr;
    struct Handle {
        CURL* curl = nullptr;
        ~Handle() {
            if (curl) curl_easy_cleanup(curl);
        }
    };
    thread_local Handle handle;
    if (handle.curl)
        curl_easy_reset(handle.curl);
    else
        handle.curl = curl_easy_init();
    return handle.curl;
}

// "connection closed after 1024 of 4096 bytes": what came of the body (before any decoding) and what was announced.
std::string closedAfter(CURL* curl, const char* what) {
    curl_off_t got = 0, length = -1;
    curl_easy_getinfo(curl, CURLINFO_SIZE_DOWNLOAD_T, &got);
    curl_easy_getinfo(curl, CURLINFO_CONTENT_LENGTH_DOWNLOAD_T, &length);
    std::string s = std::string("connection ") + what + " after " + std::to_string(got);
    return s + (length >= 0 ? " of " + std::to_string(length) : std::string()) + " bytes";
}

// The seconds under 1 byte/s that end a transfer (LOW_SPEED_TIME), 0 for never.
long stallTime(const ResourceOptions& o) {
    return o.stallSeconds > 0 ? std::max(1L, long(std::ceil(o.stallSeconds))) : 0L;
}

// Only the web: a remote tileset must not redirect a read to file:// (or anything else libcurl speaks), and
// what was asked for over TLS is not handed over in the clear.
void setProtocols(CURL* curl, const std::string& url) {
    const bool secure = startsWithNoCase(url, "https://");
#if LIBCURL_VERSION_NUM >= 0x075500
    curl_easy_setopt(curl, CURLOPT_PROTOCOLS_STR, "http,https");
    curl_easy_setopt(curl, CURLOPT_REDIR_PROTOCOLS_STR, secure ? "https" : "http,https");
#else
    curl_easy_setopt(curl, CURLOPT_PROTOCOLS, long(CURLPROTO_HTTP | CURLPROTO_HTTPS));
    curl_easy_setopt(curl, CURLOPT_REDIR_PROTOCOLS,
                     secure ? long(CURLPROTO_HTTPS) : long(CURLPROTO_HTTP | CURLPROTO_HTTPS));
#endif
}

// What is asked for and how: the URL, redirects, protocols, certificates, encodings. `error`: libcurl's message
// buffer (CURL_ERROR_SIZE bytes).
void setRequest(CURL* curl, const std::string& url, const ResourceOptions& o, char* error) {
    curl_easy_setopt(curl, CURLOPT_URL, url.c_str());
    curl_easy_setopt(curl, CURLOPT_ERRORBUFFER, error);
    curl_easy_setopt(curl, CURLOPT_NOSIGNAL, 1L);  // no SIGALRM for timeouts: other threads run
    curl_easy_setopt(curl, CURLOPT_FOLLOWLOCATION, 1L);
    curl_easy_setopt(curl, CURLOPT_MAXREDIRS, 5L);
    setProtocols(curl, url);
    if (!o.caFile.empty()) curl_easy_setopt(curl, CURLOPT_CAINFO, o.caFile.c_str());
    // gzip, deflate, br and zstd, as libcurl was built with them: tileset.json and glTF JSON compress well.
    curl_easy_setopt(curl, CURLOPT_ACCEPT_ENCODING, "");
    curl_easy_setopt(curl, CURLOPT_USERAGENT, "sgkit");
    // HTTP/2 where the server offers it (TLS ALPN), else HTTP/1.1 kept alive. Over https a read waits for a
    // connection being opened to say whether it multiplexes rather than open another; over http (HTTP/1.1 here)
    // it would wait for that connection's transfer to end, so it does not.
    curl_easy_setopt(curl, CURLOPT_HTTP_VERSION, long(CURL_HTTP_VERSION_2TLS));
    if (startsWithNoCase(url, "https://")) curl_easy_setopt(curl, CURLOPT_PIPEWAIT, 1L);
    shareCaches(curl);
}

// ResourceOptions::headers on the transfer: "Name: value" each, without line breaks (which would start another
// header or the body).
void setHeaders(const std::string& url, const ResourceOptions& o, const std::vector<std::string>& extra, Transfer& t) {
    std::vector<std::string> all = o.headers;
    all.insert(all.end(), extra.begin(), extra.end());
    for (const std::string& h : all) {
        const size_t colon = h.find(':');
        if (colon == 0 || colon == std::string::npos || h.find_first_of("\r\n") != std::string::npos)
            fail(url, "the request header '" + h + "' is not \"Name: value\" on one line");
        curl_slist* more = curl_slist_append(t.headers, h.c_str());
        if (!more) fail(url, "out of memory");
        t.headers = more;
    }
    if (t.headers) curl_easy_setopt(t.curl, CURLOPT_HTTPHEADER, t.headers);
}

// The connect timeout, the stall and the size limits.
void setLimits(CURL* curl, const ResourceOptions& o) {
    curl_easy_setopt(curl, CURLOPT_CONNECTTIMEOUT_MS, long(std::max(1.0, o.connectTimeoutSeconds * 1000.0)));
    // A trickle is less than 1 byte/s for LOW_SPEED_TIME (whole seconds; a body that stops growing is timed by
    // onProgress); no total timeout, so that a large tile on a slow but moving link completes.
    const long stall = stallTime(o);
    if (stall > 0) {
        curl_easy_setopt(curl, CURLOPT_LOW_SPEED_LIMIT, 1L);
        curl_easy_setopt(curl, CURLOPT_LOW_SPEED_TIME, stall);
    }
    // An announced length over the limit is refused before the body is read. libcurl compares it before it knows
    // whether the body is compressed, so this lets through what a compressed body within the limit could take;
    // onData and onProgress refuse the rest, the decoded bytes counted.
    const uint64_t maxOff = uint64_t(INT64_MAX);
    curl_easy_setopt(curl, CURLOPT_MAXFILESIZE_LARGE, curl_off_t(std::min(wireLimit(o.maxBytes, true), maxOff)));
}

// The callbacks, and the transfer they share.
void setCallbacks(CURL* curl, Transfer& t) {
    curl_easy_setopt(curl, CURLOPT_HEADERFUNCTION, &onHeader);
    curl_easy_setopt(curl, CURLOPT_HEADERDATA, &t);
    curl_easy_setopt(curl, CURLOPT_WRITEFUNCTION, &onData);
    curl_easy_setopt(curl, CURLOPT_WRITEDATA, &t);
    curl_easy_setopt(curl, CURLOPT_XFERINFOFUNCTION, &onProgress);
    curl_easy_setopt(curl, CURLOPT_XFERINFODATA, &t);
    curl_easy_setopt(curl, CURLOPT_NOPROGRESS, 0L);
}

// libcurl's result as the reason of a LoadError; returns for CURLE_OK only. `error`: libcurl's message buffer.
void checkResult(const std::string& url, CURLcode rc, long osErrno, const char* error, const Transfer& t) {
    CURL* curl = t.curl;
    const ResourceOptions& o = *t.options;
    const std::string detail = error[0] ? error : curl_easy_strerror(rc);
    switch (rc) {
        case CURLE_OK: break;
        case CURLE_WRITE_ERROR:
        case CURLE_ABORTED_BY_CALLBACK: fail(url, t.failure.empty() ? detail : t.failure);
        case CURLE_FILESIZE_EXCEEDED: fail(url, "larger than the limit");
        case CURLE_COULDNT_CONNECT:
            fail(url, osErrno == ECONNREFUSED ? std::string("connection refused") : "cannot connect: " + detail);
        case CURLE_COULDNT_RESOLVE_HOST: fail(url, "cannot resolve the host: " + detail);
        case CURLE_OPERATION_TIMEDOUT: {
            // The same code for both timeouts: a request sent (pre-transfer time set) means the connection was made.
            curl_off_t sent = 0;
            curl_easy_getinfo(curl, CURLINFO_PRETRANSFER_TIME_T, &sent);
            if (sent > 0) fail(url, "less than 1 byte/s for " + seconds(double(stallTime(o))));
            fail(url, "connection timed out after " + seconds(o.connectTimeoutSeconds));
        }
        case CURLE_PARTIAL_FILE: fail(url, closedAfter(curl, "closed"));
        case CURLE_GOT_NOTHING: fail(url, "connection closed without a response");
        case CURLE_RECV_ERROR: fail(url, closedAfter(curl, osErrno == ECONNRESET ? "reset" : "failed"));
        case CURLE_TOO_MANY_REDIRECTS: fail(url, "more than 5 redirects");
        // libcurl's text names the problem ("certificate has expired", "no alternative certificate subject name
        // matches target host name"), not always that it is the server's certificate that was refused.
        case CURLE_PEER_FAILED_VERIFICATION: fail(url, "the server's certificate is not trusted: " + detail);
        case CURLE_SSL_CONNECT_ERROR: fail(url, "the TLS handshake failed: " + detail);
        case CURLE_SSL_CACERT_BADFILE: {
            // The authorities' file is the user's choice: say what is wrong with it, not "error setting certificate
            // file".
            if (o.caFile.empty()) fail(url, "the system's certificate authorities cannot be read: " + detail);
            std::FILE* f = std::fopen(o.caFile.c_str(), "rb");
            const std::string why = f ? "it holds no PEM certificate" : std::strerror(errno);
            if (f) std::fclose(f);
            fail(url, "the certificate authorities file '" + o.caFile + "' cannot be used: " + why);
        }
        case CURLE_UNSUPPORTED_PROTOCOL: {  // only a redirect can get here: the URL itself is http or https
            const bool secure = startsWithNoCase(url, "https://");
            const std::string where = t.location.empty() ? std::string() : " '" + t.location + "'";
            fail(url,
                 "redirected to" + where + ", refused: " +
                     (secure ? "an https resource is redirected to https only" : "redirects go to http or https only") +
                     " (origin rule)");
        }
        default: fail(url, detail);
    }
}

// ResourceOptions::counters: the requests sent (redirects too; a failed read counts), the connections opened for
// them, whether the response came over HTTP/2, the body on the wire and decoded.
void count(const Transfer& t) {
    ResourceCounters* c = t.options->counters;
    if (!c) return;
    long redirects = 0, connects = 0, version = 0;
    curl_off_t wire = 0;
    curl_easy_getinfo(t.curl, CURLINFO_REDIRECT_COUNT, &redirects);
    curl_easy_getinfo(t.curl, CURLINFO_NUM_CONNECTS, &connects);
    curl_easy_getinfo(t.curl, CURLINFO_HTTP_VERSION, &version);
    curl_easy_getinfo(t.curl, CURLINFO_SIZE_DOWNLOAD_T, &wire);
    c->requests += 1 + uint64_t(std::max(0L, redirects));
    c->connections += uint64_t(std::max(0L, connects));
    if (version == CURL_HTTP_VERSION_2_0) ++c->http2;
    c->bytesOnWire += uint64_t(std::max<curl_off_t>(0, wire));
    c->bytes += t.bytes.size();
}

// A completed transfer's status, and its body against the announced length.
void checkResponse(const std::string& url, long status, const Transfer& t) {
    if (status == 304) return;  // Not Modified: a conditional request's answer, without a body
    if (status < 200 || status >= 300) fail(url, statusReason(status, t.phrase));
    // libcurl reports a short body as CURLE_PARTIAL_FILE; checked again here, since a truncated tile parses badly.
    curl_off_t got = 0, length = -1;
    curl_easy_getinfo(t.curl, CURLINFO_SIZE_DOWNLOAD_T, &got);
    curl_easy_getinfo(t.curl, CURLINFO_CONTENT_LENGTH_DOWNLOAD_T, &length);
    if (length >= 0 && got != length) fail(url, closedAfter(t.curl, "closed"));
}

}  // namespace

std::string HttpResponse::header(const std::string& name) const {
    for (auto it = headers.rbegin(); it != headers.rend(); ++it)
        if (it->first == name) return it->second;
    return "";
}

std::vector<unsigned char> readUrl(const std::string& url, const ResourceOptions& o) {
    if (o.cache) return readCached(url, o);
    return fetchUrl(url, o).body;
}

HttpResponse fetchUrl(const std::string& url, const ResourceOptions& o, const std::vector<std::string>& extra) {
    if (cancelled(o)) fail(url, "cancelled");
    CURL* curl = threadHandle();
    if (!curl) fail(url, "libcurl could not be initialised");
    // The handle outlives this call: the pointers to this frame (error buffer, callbacks' data) must go with it.
    struct Forget {
        CURL* curl;
        ~Forget() { curl_easy_reset(curl); }
    } forget{curl};
    Transfer t;
    t.curl = curl;
    t.options = &o;
    char error[CURL_ERROR_SIZE] = "";
    setRequest(curl, url, o, error);
    setHeaders(url, o, extra, t);
    setLimits(curl, o);
    setCallbacks(curl, t);

    CURLcode rc;
    {
        const HostSlot slot(url, o);  // waits for a slot of the host (ResourceOptions::maxRequestsPerHost)
        rc = performShared(curl);
    }
    count(t);
    long status = 0, osErrno = 0;
    curl_easy_getinfo(curl, CURLINFO_RESPONSE_CODE, &status);
    curl_easy_getinfo(curl, CURLINFO_OS_ERRNO, &osErrno);
    checkResult(url, rc, osErrno, error, t);
    checkResponse(url, status, t);
    HttpResponse r;
    r.status = status;
    r.body = std::move(t.bytes);
    r.headers = std::move(t.received);
    const char* effective = nullptr;
    curl_easy_getinfo(curl, CURLINFO_EFFECTIVE_URL, &effective);
    r.url = effective ? effective : url;
    return r;
}

}  // namespace sg::net
