// Implicit tiling (3D Tiles 1.1): subtree files read and checked, and an implicit tile's contents and children
// worked out from them when the tile is first built.
#include "loaders/gltf/internal/GltfDetail.h"
#include "loaders/tiles/internal/TilesetImplicitMetadata.h"
#include "loaders/tiles/internal/TilesetTable.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <optional>

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

// An unsigned integer `v` (at `at`), at most `most`.
uint64_t countOf(const std::string& file, const json& v, const std::string& at, uint64_t most) {
    if (!v.is_number_unsigned() || v.get<uint64_t>() > most)
        fail(file, at, "missing, or not an integer from 0 to " + std::to_string(most));
    return v.get<uint64_t>();
}

// An unsigned integer at `key` of `j`, at most `most`.
uint64_t count(const std::string& file, const json& j, const char* key, const std::string& path, uint64_t most) {
    return countOf(file, j.is_object() ? j.value(key, json()) : json(), (path.empty() ? "" : path + ".") + key, most);
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
        const auto [p, len] = view(a, key, path);
        if (len * 8 < bits)
            fail(file, path,
                 "the bitstream's " + std::to_string(len) + " bytes hold fewer than the " + std::to_string(bits) +
                     " bits its levels need");
        out.bits.assign(p, p + (bits + 7) / 8);
        return out;
    }

    // The bytes of the buffer view that a[key] names, checked against its buffer.
    std::pair<const unsigned char*, uint64_t> view(const json& a, const char* key, const std::string& path) const {
        return viewAt(a.is_object() ? a.value(key, json()) : json(), path + "." + key);
    }

    // The bytes of buffer view `index` (named at `at`), checked against its buffer.
    std::pair<const unsigned char*, uint64_t> viewAt(const json& index, const std::string& at) const {
        const json views = doc.value("bufferViews", json::array());
        if (!views.is_array()) fail(file, "bufferViews", "must be an array");
        const uint64_t v = countOf(file, index, at, views.empty() ? 0 : views.size() - 1);
        if (views.empty()) fail(file, at, "names a buffer view, but there are none");
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
        return {buffers[size_t(b)].data() + off, len};
    }

    // A semantic property's offset and scale: the table's where it gives them, else the class's.
    std::pair<std::vector<double>, std::vector<double>> transform(const SemanticProperty& sp, const json& prop,
                                                                  const std::string& path) const {
        std::pair<std::vector<double>, std::vector<double>> r{sp.offset, sp.scale};
        for (const char* key : {"offset", "scale"}) {
            if (!prop.is_object() || !prop.contains(key)) continue;
            if (!transformComponents(prop[key], sp.components, key[0] == 'o' ? r.first : r.second))
                fail(file, path + "." + key,
                     sp.components == 1 ? "must be a finite number"
                                        : "must be an array of " + std::to_string(sp.components) + " finite numbers");
        }
        return r;
    }

    // Tile metadata (3D Tiles 1.1): the rows of the semantics the reader applies, checked. `rows`: the subtree's
    // available tiles, each with a row in availability order.
    void tileMetadata(const ImplicitTiling& tiling, uint64_t rows, Subtree& s) const {
        const json tables = doc.value("propertyTables", json::array());
        if (!tables.is_array()) fail(file, "propertyTables", "must be an array");
        if (tables.empty()) fail(file, "tileMetadata", "names a property table, but there are none");
        const uint64_t t = count(file, doc, "tileMetadata", "", tables.size() - 1);
        const std::string tp = "propertyTables[" + std::to_string(t) + "]";
        const json& table = tables[size_t(t)];
        const json cls = table.is_object() ? table.value("class", json()) : json();
        if (!cls.is_string()) fail(file, tp + ".class", "missing, or not a string");
        const auto it = tiling.schema.find(cls.get<std::string>());
        if (it == tiling.schema.end())
            fail(file, tp + ".class", "class " + cls.get<std::string>() + " is not in the tileset's schema");
        const TileSemantics& sem = it->second;
        if (sem.problem) {
            const auto& [f, path, reason] = *sem.problem;
            fail(f, path, reason + " (tile metadata of " + file + ")");
        }
        const uint64_t n = count(file, table, "count", tp, UINT32_MAX);
        if (n < rows)
            fail(file, tp + ".count",
                 std::to_string(n) + " rows, fewer than the subtree's " + std::to_string(rows) + " available tiles");
        const json props = table.value("properties", json::object());
        if (!props.is_object()) fail(file, tp + ".properties", "must be an object");

        // A property's values, rows x components, as doubles; empty if the table does not give it.
        auto values = [&](const SemanticProperty& sp) {
            std::vector<double> out;
            if (!props.contains(sp.name)) return out;
            const std::string pp = tp + ".properties." + sp.name;
            const auto [p, len] = view(props[sp.name], "values", pp);
            const uint64_t size = sp.float64 ? 8 : 4, need = rows * sp.components * size;
            if (len < need)
                fail(file, pp + ".values",
                     "holds " + std::to_string(len) + " bytes, fewer than the " + std::to_string(need) + " of " +
                         std::to_string(rows) + " rows of " + std::to_string(sp.components) + " " +
                         (sp.float64 ? "FLOAT64" : "FLOAT32"));
            const auto [offset, scale] = transform(sp, props[sp.name], pp);
            out.resize(size_t(rows * sp.components));
            for (size_t i = 0; i < out.size(); ++i) {
                if (sp.float64) {
                    std::memcpy(&out[i], p + 8 * i, 8);
                } else {
                    float f;
                    std::memcpy(&f, p + 4 * i, 4);
                    out[i] = f;
                }
                const size_t c = i % sp.components;
                out[i] = out[i] * (scale.empty() ? 1.0 : scale[c]) + (offset.empty() ? 0.0 : offset[c]);
                if (!std::isfinite(out[i]))
                    fail(file, pp,
                         "row " + std::to_string(i / sp.components) + ": value " + std::to_string(i % sp.components) +
                             " is not finite");
            }
            return out;
        };
        const std::pair<const std::optional<SemanticProperty>*, Subtree::Volume> volumes[] = {
            {&sem.box, Subtree::Volume::Box},
            {&sem.region, Subtree::Volume::Region},
            {&sem.sphere, Subtree::Volume::Sphere}};
        for (const auto& [prop, kind] : volumes) {  // the first given, as a box is the tightest
            if (!*prop || !props.contains((*prop)->name)) continue;
            s.volumes = values(**prop);
            s.volume = kind;
            const std::string pp = tp + ".properties." + (*prop)->name;
            const size_t c = (*prop)->components;
            for (uint64_t r = 0; r < rows; ++r) {
                const double* v = s.volumes.data() + r * c;
                if (kind == Subtree::Volume::Sphere && v[3] < 0.0)
                    fail(file, pp, "row " + std::to_string(r) + ": radius " + std::to_string(v[3]) + " is negative");
                if (kind == Subtree::Volume::Region && !badRegion(v).empty())
                    fail(file, pp, "row " + std::to_string(r) + ": " + badRegion(v));
            }
            break;
        }
        if (sem.error) {
            s.errors = values(*sem.error);
            for (uint64_t r = 0; r < s.errors.size(); ++r)
                if (s.errors[r] < 0.0)
                    fail(file, tp + ".properties." + sem.error->name,
                         "row " + std::to_string(r) + ": geometric error " + std::to_string(s.errors[r]) +
                             " is negative");
        }
    }
};

// The root of the subtree holding implicit tile d: its level and coordinates in that level, and d's depth in it.
struct SubtreeRoot {
    uint32_t level, depth, x, y, z;

    explicit SubtreeRoot(const TileDesc& d)
        : level(d.level / d.implicit->subtreeLevels * d.implicit->subtreeLevels),
          depth(d.level - level),
          x(d.x >> depth),
          y(d.y >> depth),
          z(d.z >> depth) {}

    // Tile d's bit in the subtree's tile availability: its level's offset + its Morton index within the level.
    uint64_t slot(const TileDesc& d, bool octree) const {
        return levelOffset(depth, octree) + morton(d.x - (x << depth), d.y - (y << depth), d.z - (z << depth), octree);
    }
};

// The tile's own volume and error where its subtree's metadata gives them (over the implied ones).
struct TileSemanticValues {
    std::optional<Sphere> sphere;
    std::optional<double> error;
};

TileSemanticValues semanticValues(const Subtree& sub, uint64_t at) {
    TileSemanticValues m;
    if ((sub.volume != Subtree::Volume::None || !sub.errors.empty()) && sub.tiles[at]) {
        const uint64_t row = sub.tiles.rank(at);
        const double* v = sub.volumes.data();
        switch (sub.volume) {
            case Subtree::Volume::None: break;
            case Subtree::Volume::Box: m.sphere = boxSphere(v + 12 * row); break;
            case Subtree::Volume::Region:
                m.sphere = regionSphere(std::vector<double>(v + 6 * row, v + 6 * row + 6));
                break;
            case Subtree::Volume::Sphere:
                m.sphere = Sphere{dvec3(v[4 * row], v[4 * row + 1], v[4 * row + 2]), v[4 * row + 3]};
                break;
        }
        if (!sub.errors.empty()) m.error = sub.errors[size_t(row)];
    }
    return m;
}

// "implicit tile 2/1/3" (level/x/y, and /z in an octree): how messages name an implicit tile.
std::string implicitName(const ImplicitTiling& t, uint32_t level, uint32_t x, uint32_t y, uint32_t z) {
    return "implicit tile " + std::to_string(level) + "/" + std::to_string(x) + "/" + std::to_string(y) +
           (t.octree ? "/" + std::to_string(z) : "");
}

// The URIs of the contents the subtree marks available for tile d (bit `at`), and their templates' JSON paths
// with the tile's coordinates into `paths`.
std::vector<std::string> availableContents(const TileDesc& d, const Subtree& sub, uint64_t at,
                                           std::vector<std::string>& paths) {
    const ImplicitTiling& t = *d.implicit;
    std::vector<std::string> contents;
    for (size_t c = 0; c < t.contents.size(); ++c) {
        if (!sub.contents[c][at]) continue;
        contents.push_back(expandTemplate(t.contents[c], d.level, d.x, d.y, d.z));
        const std::string path = c < t.contentPaths.size() ? t.contentPaths[c] : d.path;
        paths.push_back(path + " (" + implicitName(t, d.level, d.x, d.y, d.z) + ")");
    }
    return contents;
}

// Child (cx, cy, cz) of tile d (table index i), pending until it is resolved in turn.
TileDesc childTile(const TileDesc& d, uint32_t i, uint32_t cx, uint32_t cy, uint32_t cz) {
    const ImplicitTiling& t = *d.implicit;
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
    k.path = d.path.substr(0, d.path.find(" (implicit tile ")) + " (" + implicitName(t, k.level, cx, cy, cz) + ")";
    k.source = d.source;
    k.depth = d.depth + 1;
    k.implicit = d.implicit;
    k.pending = true;
    return k;
}

// The children of tile d (table index i) that its subtree marks available.
std::vector<TileDesc> availableChildren(const TileDesc& d, uint32_t i, const Subtree& sub, const SubtreeRoot& root) {
    const ImplicitTiling& t = *d.implicit;
    const uint32_t levels = t.subtreeLevels, r = root.depth, sx = root.x, sy = root.y, sz = root.z;
    std::vector<TileDesc> kids;
    for (uint32_t c = 0; d.level + 1 < t.availableLevels && c < (t.octree ? 8u : 4u); ++c) {
        const uint32_t cx = 2 * d.x + (c & 1), cy = 2 * d.y + (c >> 1 & 1), cz = t.octree ? 2 * d.z + (c >> 2 & 1) : 0;
        // In this subtree, or the root of one below it.
        const uint32_t below = r + 1;
        const uint64_t m = morton(cx - (sx << below), cy - (sy << below), cz - (sz << below), t.octree);
        if (!(below < levels ? sub.tiles[levelOffset(below, t.octree) + m] : sub.children[m])) continue;
        kids.push_back(childTile(d, i, cx, cy, cz));
    }
    return kids;
}

}  // namespace

uint64_t Availability::countBits(uint64_t n) {
    if (constant) return value ? n : 0;
    before.assign(bits.size() + 1, 0);
    for (size_t i = 0; i < bits.size(); ++i) {
        // The last byte's bits past n are not the subtree's.
        const unsigned mask = (uint64_t(i + 1) * 8 <= n) ? 0xffu : (1u << (n - i * 8)) - 1u;
        before[i + 1] = before[i] + uint64_t(__builtin_popcount(bits[i] & mask));
    }
    return before.back();
}

uint64_t Availability::rank(uint64_t i) const {
    if (constant) return value ? i : 0;
    return before[size_t(i >> 3)] + uint64_t(__builtin_popcount(bits[size_t(i >> 3)] & ((1u << (i & 7)) - 1u)));
}

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
            data = readBuffer(resolveReference(file, buffers[i]["uri"].get<std::string>(), path + ".uri"));
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
                                 : Availability{true, false, {}, {}});  // not given: none
    if (doc.contains("tileMetadata")) r.tileMetadata(tiling, s.tiles.countBits(tiles), s);
    readSubtreeMetadata(
        file, doc, tiling, tiles, [&r](const json& index, const std::string& at) { return r.viewAt(index, at); }, s);
    return s;
}

TileDesc TilesetState::resolve(uint32_t i) {
    TileDesc d = tile(i);
    if (!d.pending) return d;
    const ImplicitTiling& t = *d.implicit;
    const SubtreeRoot root(d);

    std::shared_ptr<const Subtree> sub;
    const auto key = std::make_tuple(d.implicit.get(), root.level, root.x, root.y, root.z);
    {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = subtrees_.find(key);
        if (it != subtrees_.end()) sub = it->second;
    }
    if (!sub) {  // read outside the lock: other loads go on meanwhile
        const std::string uri = expandTemplate(t.subtrees, root.level, root.x, root.y, root.z);
        auto read = [this](const std::string& u) { return readResource(u, options.resource); };
        sub = std::make_shared<const Subtree>(parseSubtree(uri, read(uri), t, read));
        for (const std::string& w : sub->warnings) warn(uri + ": " + w);
        std::lock_guard<std::mutex> lock(mutex_);
        subtrees_.emplace(key, sub);
    }

    const uint64_t at = root.slot(d, t.octree);
    const TileSemanticValues own = semanticValues(*sub, at);
    const ref_ptr<const TileMetadata> metadata = implicitTileMetadata(t, *sub, at, d.metadata.get());
    std::vector<std::string> paths;
    std::vector<std::string> contents = availableContents(d, *sub, at, paths);
    std::vector<TileDesc> kids = availableChildren(d, i, *sub, root);

    std::lock_guard<std::mutex> lock(mutex_);
    if (tiles_[i].pending) {  // another load may have resolved it meanwhile
        tiles_[i].contents = std::move(contents);
        tiles_[i].contentPaths = std::move(paths);
        tiles_[i].metadata = metadata;
        if (own.sphere) {
            tiles_[i].sphere = *own.sphere;
            tiles_[i].region = sub->volume == Subtree::Volume::Region;
        }
        if (own.error) tiles_[i].geometricError = *own.error;
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
