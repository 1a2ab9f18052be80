// libFuzzer target for what the network reader parses of a server's or a tileset's words: the first line is a URI
// reference (resolved against a URL with an access key, against a path, and read as a data: URI), the other lines
// are a response's headers ("Name: value") given to the HTTP cache's freshness rules (Cache-Control, dates, Age,
// validators, Vary). Everything either returns or throws sg::LoadError; anything else (a crash, a sanitizer report,
// another exception, a hang past -timeout) is a finding. Seeds in fuzz/net-corpus/.
#include "loaders/net/Resource.h"
#include "loaders/net/internal/HttpCachePolicy.h"

#include <cctype>
#include <cstddef>
#include <cstdint>
#include <string>

namespace {

void references(const std::string& ref) {
    sg::resolveUri("https://h.org/a/b/tileset.json?key=k&v=1", ref);
    sg::resolveUri("tiles/a/tileset.json", ref);
    for (const char* base : {"https://h.org/a/tileset.json?key=k&v=1", "/data/tileset.json", "http://h:8080"}) {
        try {
            sg::resolveReference(base, ref, "root.content.uri");
        } catch (const sg::LoadError&) {
        }
    }
    sg::ResourceOptions small;
    small.maxBytes = 1 << 16;
    try {
        sg::readResource("data:" + ref, small);
    } catch (const sg::LoadError&) {
    }
}

void freshness(const sg::HttpHeaders& h) {
    using namespace sg::net;
    const int64_t at = 1'700'000'000;
    for (const auto& [name, value] : h) {
        parseCacheControl(value);
        parseHttpDate(value);
    }
    storable(200, h, at);
    freshnessLifetime(h, at);
    currentAge(h, at, at + 3600);
    isFresh(h, at, at + 60);
    conditionalHeaders(h);
    keptHeaders(h);
    refreshedHeaders(h, h);
    varyKey(h, {"Accept-Encoding: gzip", "Authorization: Bearer t"});
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const size_t nl = text.find('\n');
    references(text.substr(0, nl));
    sg::HttpHeaders headers;
    for (size_t b = nl == std::string::npos ? text.size() : nl + 1; b < text.size();) {
        const size_t e = std::min(text.find('\n', b), text.size());
        const std::string line = text.substr(b, e - b);
        const size_t colon = line.find(':');
        if (colon != std::string::npos) {
            std::string name = line.substr(0, colon);
            for (char& c : name) c = char(std::tolower(static_cast<unsigned char>(c)));
            headers.emplace_back(name, line.substr(colon + 1 + (colon + 1 < line.size() && line[colon + 1] == ' ')));
        }
        b = e + 1;
    }
    freshness(headers);
    return 0;
}
