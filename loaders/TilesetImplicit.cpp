// Implicit tiling (3D Tiles 1.1): subtree files read and checked, and an implicit tile's contents and children
// worked out from them when the tile is first built.
#include "loaders/GltfDetail.h"
#include "loaders/TilesetTable.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>

namespace sg::tiles {
namespace {

using json = nlohmann::json;

[[noreturn]] void fail(const std::string& file, const std::string& path, const std::string& reason) {
    throw LoadError(file, path, reason);
}

uint64_t u64(const unsigned char* p) {
    uint64_t v = 0;
    for (int i = 7; i >= 0; --i) v = v << 8 | p[i];
    return v;
}

// Tiles in the first `levels` levels of a quadtree (k = 4) or octree (k = 8): (k^levels - 1) / (k - 1).
uint64_t levelOffset(uint32_t levels, bool octree) {
    const uint64_t k = octree ? 8 : 4;
    uint64_t n = 0, p = 1;
    for (uint32_t l = 0; l < levels; ++l, p *= k) n += p;
    return n;
}

uint64_t power(bool octree, uint32_t levels) { return uint64_t(1) << ((octree ? 3 : 2) * levels); }

// An unsigned integer at `key` of `j`, at most `most`.
uint64_t count(const std::string& file, const json& j, const char* key, const std::string& path, uint64_t most) {
    const json v = j.is_object() ? j.value(key, json()) : json();
    if (!v.is_number_unsigned() || v.get<uint64_t>() > most)
        fail(file, path + "." + key, "missing, or not an integer from 0 to " + std::to_string(most));
    return v.get<uint64_t>();
}

struct Reader {
    const std::string& file;
    const json& doc;
    std::vector<std::vector<unsigned char>> buffers;

    Availability availability(const json& a, const std::string& path, uint64_t bits) const {
        if (!a.is_object()) fail(file, path, "missing, or not an object");
        Availability out;
        if (a.contains("constant")) {
            const json& c = a["constant"];
            if (c != 0 && c != 1) fail(file, path + ".constant", "must be 0 or 1");
            out.constant = true;
            out.value = c == 1;
            return out;
        }
        const char* key = a.contains("bitstream") ? "bitstream" : "bufferView";  // bufferView: the 1.0 extension's
        const json views = doc.value("bufferViews", json::array());
        if (!views.is_array()) fail(file, "bufferViews", "must be an array");
        const uint64_t v = count(file, a, key, path, views.empty() ? 0 : views.size() - 1);
        if (views.empty()) fail(file, path + "." + key, "names a buffer view, but there are none");
        const std::string vp = "bufferViews[" + std::to_string(v) + "]";
        const json& view = views[size_t(v)];
        const uint64_t b = count(file, view, "buffer", vp, buffers.empty() ? 0 : buffers.size() - 1);
        if (buffers.empty()) fail(file, vp + ".buffer", "names a buffer, but there are none");
        const uint64_t off = view.contains("byteOffset") ? count(file, view, "byteOffset", vp, UINT32_MAX) : 0;
        const uint64_t len = count(file, view, "byteLength", vp, UINT32_MAX);
        if (off + len > buffers[size_t(b)].size())
            fail(file, vp,
                 "bytes " + std::to_string(off) + " to " + std::to_string(off + len) + " are past buffer " +
                     std::to_string(b) + "'s " + std::to_string(buffers[size_t(b)].size()));
        if (len * 8 < bits)
            fail(file, path,
                 "the bitstream's " + std::to_string(len) + " bytes hold fewer than the " + std::to_string(bits) +
                     " bits its levels need");
        const unsigned char* p = buffers[size_t(b)].data() + off;
        out.bits.assign(p, p + (bits + 7) / 8);
        return out;
    }
};

}  // namespace

uint64_t morton(uint32_t x, uint32_t y, uint32_t z, bool octree) {
    const int dims = octree ? 3 : 2;
    uint64_t m = 0;
    for (int b = 0; b < 21; ++b) {
        m |= uint64_t((x >> b) & 1) << (dims * b);
        m |= uint64_t((y >> b) & 1) << (dims * b + 1);
        if (octree) m |= uint64_t((z >> b) & 1) << (dims * b + 2);
    }
    return m;
}

std::string expandTemplate(std::string t, uint32_t level, uint32_t x, uint32_t y, uint32_t z) {
    const std::pair<const char*, uint32_t> keys[] = {{"{level}", level}, {"{x}", x}, {"{y}", y}, {"{z}", z}};
    for (const auto& [key, value] : keys)
        for (size_t at = t.find(key); at != std::string::npos; at = t.find(key, at))
            t.replace(at, std::strlen(key), std::to_string(value));
    return t;
}

Subtree parseSubtree(const std::string& file, const std::vector<unsigned char>& bytes, const ImplicitTiling& tiling,
                     const std::function<std::vector<unsigned char>(const std::string&)>& readBuffer) {
    const unsigned char* p = bytes.data();
    size_t jsonBegin = 0, jsonLen = bytes.size();
    std::vector<unsigned char> chunk;  // the binary chunk
    if (bytes.size() >= 4 && std::memcmp(p, "subt", 4) == 0) {
        if (bytes.size() < 24)
            fail(file, "header", "a subtree file's header is 24 bytes; the file has " + std::to_string(bytes.size()));
        const uint32_t version = uint32_t(p[4]) | uint32_t(p[5]) << 8 | uint32_t(p[6]) << 16 | uint32_t(p[7]) << 24;
        if (version != 1) fail(file, "header.version", "version " + std::to_string(version) + " is not 1");
        const uint64_t j = u64(p + 8), b = u64(p + 16);
        if (j > bytes.size() - 24 || b > bytes.size() - 24 - j)
            fail(file, "header",
                 "JSON of " + std::to_string(j) + " and binary of " + std::to_string(b) +
                     " bytes are past the file's " + std::to_string(bytes.size()));
        jsonBegin = 24;
        jsonLen = size_t(j);
        chunk.assign(p + 24 + j, p + 24 + j + b);
    }
    gltf::checkJsonDepth(file, p + jsonBegin, jsonLen);
    json doc;
    try {
        doc = json::parse(p + jsonBegin, p + jsonBegin + jsonLen);
    } catch (const json::exception& e) {
        fail(file, "", std::string("JSON: ") + e.what());
    }
    if (!doc.is_object()) fail(file, "", "a subtree must be a JSON object");
    Reader r{file, doc, {}};
    const json buffers = doc.value("buffers", json::array());
    if (!buffers.is_array()) fail(file, "buffers", "must be an array");
    for (size_t i = 0; i < buffers.size(); ++i) {
        const std::string path = "buffers[" + std::to_string(i) + "]";
        const uint64_t len = count(file, buffers[i], "byteLength", path, UINT32_MAX);
        std::vector<unsigned char> data;
        if (buffers[i].contains("uri")) {
            if (!buffers[i]["uri"].is_string()) fail(file, path + ".uri", "must be a string");
            data = readBuffer(resolveUri(file, buffers[i]["uri"].get<std::string>()));
        } else {
            data = chunk;  // the binary chunk
        }
        if (data.size() < len)
            fail(file, path,
                 "holds " + std::to_string(data.size()) + " bytes, not its byteLength " + std::to_string(len));
        data.resize(size_t(len));
        r.buffers.push_back(std::move(data));
    }
    const uint64_t tiles = levelOffset(tiling.subtreeLevels, tiling.octree);
    Subtree s;
    s.tiles = r.availability(doc.value("tileAvailability", json()), "tileAvailability", tiles);
    s.children = r.availability(doc.value("childSubtreeAvailability", json()), "childSubtreeAvailability",
                                power(tiling.octree, tiling.subtreeLevels));
    const json contents = doc.value("contentAvailability", json::array());
    if (!contents.is_array()) fail(file, "contentAvailability", "must be an array");
    for (size_t i = 0; i < tiling.contents.size(); ++i)
        s.contents.push_back(i < contents.size()
                                 ? r.availability(contents[i], "contentAvailability[" + std::to_string(i) + "]", tiles)
                                 : Availability{true, false, {}});  // not given: none
    return s;
}

TileDesc TilesetState::resolve(uint32_t i) {
    TileDesc d = tile(i);
    if (!d.pending) return d;
    const ImplicitTiling& t = *d.implicit;
    const uint32_t levels = t.subtreeLevels, rootLevel = d.level / levels * levels, r = d.level - rootLevel;
    const uint32_t sx = d.x >> r, sy = d.y >> r, sz = d.z >> r;  // the subtree's root, in its level

    std::shared_ptr<const Subtree> sub;
    const auto key = std::make_tuple(d.implicit.get(), rootLevel, sx, sy, sz);
    {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = subtrees_.find(key);
        if (it != subtrees_.end()) sub = it->second;
    }
    if (!sub) {  // read outside the lock: other loads go on meanwhile
        const std::string uri = expandTemplate(t.subtrees, rootLevel, sx, sy, sz);
        auto read = [this](const std::string& u) { return readResource(u, options.resource); };
        sub = std::make_shared<const Subtree>(parseSubtree(uri, read(uri), t, read));
        std::lock_guard<std::mutex> lock(mutex_);
        subtrees_.emplace(key, sub);
    }

    const uint64_t at = levelOffset(r, t.octree) + morton(d.x - (sx << r), d.y - (sy << r), d.z - (sz << r), t.octree);
    std::vector<std::string> contents;
    for (size_t c = 0; c < t.contents.size(); ++c)
        if (sub->contents[c][at]) contents.push_back(expandTemplate(t.contents[c], d.level, d.x, d.y, d.z));
    std::vector<TileDesc> kids;
    for (uint32_t c = 0; d.level + 1 < t.availableLevels && c < (t.octree ? 8u : 4u); ++c) {
        const uint32_t cx = 2 * d.x + (c & 1), cy = 2 * d.y + (c >> 1 & 1), cz = t.octree ? 2 * d.z + (c >> 2 & 1) : 0;
        // In this subtree, or the root of one below it.
        const uint32_t below = r + 1;
        const uint64_t m = morton(cx - (sx << below), cy - (sy << below), cz - (sz << below), t.octree);
        if (!(below < levels ? sub->tiles[levelOffset(below, t.octree) + m] : sub->children[m])) continue;
        TileDesc k;
        k.parent = i;
        k.level = d.level + 1;
        k.x = cx;
        k.y = cy;
        k.z = cz;
        k.sphere = implicitSphere(t, k.level, cx, cy, cz);
        k.region = t.region;
        k.geometricError = t.geometricError / std::ldexp(1.0, int(k.level));
        k.add = d.add;
        k.file = d.file;
        k.path = d.path + " (implicit tile " + std::to_string(k.level) + "/" + std::to_string(cx) + "/" +
                 std::to_string(cy) + (t.octree ? "/" + std::to_string(cz) : "") + ")";
        k.source = d.source;
        k.depth = d.depth + 1;
        k.implicit = d.implicit;
        k.pending = true;
        kids.push_back(std::move(k));
    }

    std::lock_guard<std::mutex> lock(mutex_);
    if (tiles_[i].pending) {  // another load may have resolved it meanwhile
        tiles_[i].contents = std::move(contents);
        for (TileDesc& k : kids) {
            tiles_[i].children.push_back(uint32_t(tiles_.size()));
            tiles_.push_back(std::move(k));
        }
        counts_.tiles += kids.size();
        tiles_[i].pending = false;
    }
    return tiles_[i];
}

}  // namespace sg::tiles
