// Tile contents that fail to load: told apart into those that may load later (the network's failures, retried by
// the pager) and those that will not (a missing or corrupt content, drawn as an empty tile), and listed.
#include "loaders/tiles/internal/TilesetTable.h"

#include <cstring>

namespace sg::tiles {
namespace {

// The reasons readResource gives (loaders/net/Resource.h) for a failure of the network that may pass: a server
// that errs or is overloaded (HTTP 5xx, 408 Request Timeout, 429 Too Many Requests) or a connection that could
// not be made or did not last. A missing resource (HTTP 404, no such file), a refusal (HTTP 403, the origin rule,
// the size limit) and a content that does not parse stay as they are however often they are read: final, so
// that asking again would only delay the tiles read with it. CesiumJS and cesium-native draw such a tile empty.
bool mayPass(const std::string& reason) {
    static const char* const kPassing[] = {"HTTP 5",      "HTTP 408",           "HTTP 429",
                                           "connection ", "cannot connect",     "cannot resolve the host",
                                           "no data for", "less than 1 byte/s", "out of memory"};
    for (const char* p : kPassing)
        if (reason.compare(0, std::strlen(p), p) == 0) return true;
    return false;
}

}  // namespace

bool TilesetState::contentFailed(uint32_t t, const TileDesc& d, size_t c, const LoadError& e) {
    const std::string& uri = d.contents[c];
    // A cancelled read (the program is closing) says nothing of the content: the load fails, nothing is recorded.
    if (e.reason() == "cancelled" || (options.resource.cancel && options.resource.cancel->load())) return false;
    // Only a read over the network may pass: a file's reasons are final, and so is a parse error of what was read.
    const bool passing = isUrl(e.file()) && mayPass(e.reason());
    // The reason alone when it is the content's own read; else what failed inside it too (an external tileset's
    // JSON path, a composite's inner tile, an instanced model's file).
    const std::string reason = e.file() == uri && e.jsonPath().empty() ? e.reason() : e.what();
    std::lock_guard<std::mutex> lock(mutex_);
    TileFailure& f = failures_[{t, uri}];
    const bool told = f.final && f.reason == reason;  // warned already (a detail loaded again after it expired)
    f.file = d.file;
    f.path = c < d.contentPaths.size() ? d.contentPaths[c] : d.path;
    f.uri = uri;
    f.reason = reason;
    f.attempts++;
    f.final = !passing || f.attempts >= options.transientAttempts;
    if (f.final && !told)
        warnings_.push_back(f.file + ": " + f.path + ": " + uri + ": " + reason +
                            (passing ? " (failed " + std::to_string(f.attempts) + " times; given up)" : "") +
                            "; the tile is drawn without it");
    return f.final;
}

void TilesetState::contentLoaded(uint32_t t, const std::string& uri) {
    std::lock_guard<std::mutex> lock(mutex_);
    counts_.contents++;
    if (!failures_.empty()) failures_.erase({t, uri});
}

std::vector<TileFailure> TilesetState::failures() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<TileFailure> out;
    out.reserve(failures_.size());
    for (const auto& [key, f] : failures_) out.push_back(f);
    return out;
}

}  // namespace sg::tiles
