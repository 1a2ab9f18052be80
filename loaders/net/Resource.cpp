// readResource: files through open/read, data: URIs decoded, URLs through HttpRead.cpp.
#include "loaders/net/Resource.h"
#include "loaders/net/internal/Net.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>

namespace sg {

namespace {

using net::cancelled;
using net::fail;
using net::percentDecoded;
using net::startsWithNoCase;

// The path of a file:// URL: "file:///a%20b" is "/a b"; "file://localhost/x" is "/x"; other hosts are refused
// (they would need a network file system we do not know of).
std::string filePath(const std::string& url) {
    std::string rest = url.substr(7);
    if (startsWithNoCase(rest, "localhost/")) rest = rest.substr(9);
    if (rest.empty() || rest[0] != '/') fail(url, "a file URL names a host other than localhost");
    return percentDecoded(rest.substr(0, rest.find_first_of("?#")));
}

int base64Digit(char c) {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+' || c == '-') return 62;  // '-' and '_': the URL-safe alphabet
    if (c == '/' || c == '_') return 63;
    return -1;
}

// The bytes of "data:[<media type>][;base64],<data>" (RFC 2397): percent-decoded, then base64-decoded when marked
// so ("=" padding optional). The name in errors is the URI's first 64 characters: a data URI can be megabytes.
std::vector<unsigned char> readData(const std::string& uri, const ResourceOptions& o) {
    const std::string name = uri.size() > 64 ? uri.substr(0, 64) + "..." : uri;
    const size_t comma = uri.find(',');
    if (comma == std::string::npos) fail(name, "a data: URI without ',' before its data");
    const std::string header = uri.substr(5, comma - 5);
    const bool base64 = header.size() >= 7 && startsWithNoCase(header.substr(header.size() - 7), ";base64");
    const std::string text = percentDecoded(uri.substr(comma + 1));
    if ((base64 ? text.size() / 4 * 3 : text.size()) > o.maxBytes) fail(name, "larger than the limit");
    if (!base64) return std::vector<unsigned char>(text.begin(), text.end());
    std::vector<unsigned char> out;
    out.reserve(text.size() / 4 * 3 + 2);
    uint32_t bits = 0;
    int held = 0;
    size_t end = text.size();
    while (end > 0 && text[end - 1] == '=' && text.size() - end < 2) --end;
    for (size_t i = 0; i < end; ++i) {
        const int d = base64Digit(text[i]);
        if (d < 0) fail(name, "a data: URI's base64 has '" + text.substr(i, 1) + "' at " + std::to_string(i));
        bits = ((bits << 6) | uint32_t(d)) & 0xffffu;  // the bits not yet out, at most 14
        held += 6;
        if (held >= 8) {
            held -= 8;
            out.push_back(static_cast<unsigned char>(bits >> held));
        }
    }
    if (held >= 6) fail(name, "a data: URI's base64 ends in the middle of a byte");
    return out;
}

std::vector<unsigned char> readFile(const std::string& name, const std::string& path, const ResourceOptions& o) {
    // Non-blocking: opening a FIFO must not wait for a writer (it is then refused as not regular).
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) fail(name, errno == ENOENT ? "no such file" : std::string("cannot open: ") + std::strerror(errno));
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat st {};
    if (::fstat(fd, &st) != 0) fail(name, std::string("cannot stat: ") + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) fail(name, "not a regular file");
    if (uint64_t(st.st_size) > o.maxBytes) fail(name, "larger than the limit");
    std::vector<unsigned char> bytes(size_t(st.st_size));
    // In pieces, so that a cancel is seen during a large file on a slow disk or network file system.
    const size_t piece = size_t(4) << 20;
    size_t n = 0;
    while (n < bytes.size()) {
        if (cancelled(o)) fail(name, "cancelled");
        const ssize_t r = ::read(fd, bytes.data() + n, std::min(piece, bytes.size() - n));
        if (r < 0 && errno == EINTR) continue;
        if (r < 0) fail(name, std::string("cannot read: ") + std::strerror(errno));
        if (r == 0) break;  // shrank since fstat: what is there is the file
        n += size_t(r);
    }
    bytes.resize(n);
    return bytes;
}

}  // namespace

std::vector<unsigned char> readResource(const std::string& uriOrPath, const ResourceOptions& options) {
    if (isUrl(uriOrPath)) return net::readUrl(uriOrPath, options);
    std::vector<unsigned char> bytes = isDataUri(uriOrPath) ? readData(uriOrPath, options)
                                       : startsWithNoCase(uriOrPath, "file://")
                                           ? readFile(uriOrPath, filePath(uriOrPath), options)
                                           : readFile(uriOrPath, uriOrPath, options);
    if (options.counters) options.counters->bytes += bytes.size();
    return bytes;
}

}  // namespace sg
