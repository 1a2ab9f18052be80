// tileset.json read into the tile table: every field the graph relies on checked, each error naming the file,
// the JSON path and the reason.
#include "loaders/gltf/internal/GltfDetail.h"
#include "loaders/metadata/internal/MetadataJson.h"
#include "loaders/tiles/internal/TilesetTable.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace sg::tiles {
namespace {

using json = nlohmann::json;

// Extensions a tileset may require that change nothing the reader does (3D Tiles 1.0's glTF content).
const char* const kKnownExtensions[] = {"3DTILES_content_gltf"};

[[noreturn]] void fail(const std::string& file, const std::string& path, const std::string& reason) {
    throw LoadError(file, path, reason);
}

double number(const std::string& file, const json& v, const std::string& path) {
    if (!v.is_number()) fail(file, path, std::string("must be a number, not ") + v.type_name());
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(file, path, "is not finite");
    return d;
}

std::vector<double> numbers(const std::string& file, const json& v, const std::string& path, size_t n) {
    if (!v.is_array() || v.size() != n) fail(file, path, "must be an array of " + std::to_string(n) + " numbers");
    std::vector<double> out;
    for (size_t i = 0; i < n; ++i) out.push_back(number(file, v[i], path + "[" + std::to_string(i) + "]"));
    return out;
}

// WGS84, in metres: a point of longitude, latitude (radians) and height in the Earth-centred frame.
dvec3 wgs84(double lon, double lat, double h) {
    constexpr double a = 6378137.0, e2 = 6.69437999014e-3;
    const double n = a / std::sqrt(1.0 - e2 * std::sin(lat) * std::sin(lat));
    return {(n + h) * std::cos(lat) * std::cos(lon), (n + h) * std::cos(lat) * std::sin(lon),
            (n * (1.0 - e2) + h) * std::sin(lat)};
}

}  // namespace

// A sphere holding a region: a 17 x 17 grid at both heights bounds it, grown by the most the surface can bulge
// between grid points (the arc across a grid cell at the largest radius), so that it holds the whole region.
Sphere regionSphere(const std::vector<double>& r) {
    constexpr int n = 16;
    std::vector<dvec3> pts;
    double east = r[2] < r[0] ? r[2] + 2.0 * M_PI : r[2];  // a region may cross the antimeridian
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j)
            for (double h : {r[4], r[5]})
                pts.push_back(wgs84(r[0] + (east - r[0]) * i / n, r[1] + (r[3] - r[1]) * j / n, h));
    Box box;
    for (const dvec3& p : pts) box.expand(p);
    Sphere s{box.center(), 0.0};
    for (const dvec3& p : pts) s.radius = std::max(s.radius, glm::length(p - s.center));
    const double step = std::max((east - r[0]) / n, (r[3] - r[1]) / n);
    s.radius += (6378137.0 + std::max(r[5], 0.0)) * step;
    return s;
}

Sphere boxSphere(const double* b) {
    Sphere s{{b[0], b[1], b[2]}, 0.0};
    const dvec3 x(b[3], b[4], b[5]), y(b[6], b[7], b[8]), z(b[9], b[10], b[11]);
    for (double i : {-1.0, 1.0})
        for (double j : {-1.0, 1.0})
            for (double k : {-1.0, 1.0}) s.radius = std::max(s.radius, glm::length(i * x + j * y + k * z));
    return s;
}

std::string badRegion(const double* r) {
    if (r[0] < -M_PI || r[0] > M_PI || r[2] < -M_PI || r[2] > M_PI)
        return "west and east must be longitudes in radians, in [-pi, pi]";
    if (r[1] < -M_PI / 2 || r[3] > M_PI / 2 || r[1] > r[3])
        return "south and north must be latitudes in radians, -pi/2 <= south <= north <= pi/2";
    if (r[4] > r[5]) return "minimum height is above the maximum";
    return "";
}

bool transformComponents(const json& v, uint32_t n, std::vector<double>& out) {
    out.clear();
    if (n == 1 && v.is_number()) out.push_back(v.get<double>());
    if (n > 1 && v.is_array() && v.size() == n)
        for (const json& e : v)
            if (e.is_number()) out.push_back(e.get<double>());
    if (out.size() != n) out.clear();
    for (double x : out)
        if (!std::isfinite(x)) out.clear();
    return out.size() == n;
}

namespace {
std::string transformShape(uint32_t n) {
    return n == 1 ? "a finite number" : "an array of " + std::to_string(n) + " finite numbers";
}
}  // namespace

MetadataSchema readSchema(const std::string& file, const json& tileset, const ResourceOptions& options,
                          std::shared_ptr<const Schema>* full, std::vector<std::string>* warnings) {
    std::string from = file, path = "schema";
    json schema;
    if (tileset.contains("schema")) {
        schema = tileset["schema"];
    } else if (tileset.contains("schemaUri")) {
        if (!tileset["schemaUri"].is_string()) fail(file, "schemaUri", "must be a string");
        from = resolveReference(file, tileset["schemaUri"].get<std::string>(), "schemaUri");
        path = "";
        const std::vector<unsigned char> bytes = readResource(from, options);
        gltf::checkJsonDepth(from, bytes.data(), bytes.size());
        try {
            schema = json::parse(bytes.begin(), bytes.end());
        } catch (const json::exception& e) {
            fail(from, "", std::string("JSON: ") + e.what());
        }
    } else {
        return {};
    }
    auto at = [&](const std::string& p) { return path.empty() ? p : path + "." + p; };
    if (!schema.is_object()) fail(from, path, "a schema must be an object");
    if (full) {
        std::vector<std::string> w;
        *full = std::make_shared<const Schema>(
            metadata::parseSchema(nlohmann::ordered_json(schema), metadata::Context{from, &w}, path));
        if (warnings)
            for (const std::string& x : w) warnings->push_back(from + ": " + x);
    }
    const json classes = schema.value("classes", json::object());
    if (!classes.is_object()) fail(from, at("classes"), "must be an object");
    // The semantics the reader applies, with their components; any other property is ignored.
    const std::pair<const char*, uint32_t> known[] = {{"TILE_BOUNDING_BOX", 12},
                                                      {"TILE_BOUNDING_REGION", 6},
                                                      {"TILE_BOUNDING_SPHERE", 4},
                                                      {"TILE_GEOMETRIC_ERROR", 1}};
    MetadataSchema out;
    std::vector<double> unused;
    for (const auto& [name, cls] : classes.items()) {
        TileSemantics& sem = out[name];
        const json props = cls.is_object() ? cls.value("properties", json::object()) : json::object();
        if (!props.is_object()) continue;
        for (const auto& [key, p] : props.items()) {
            const json semantic = p.is_object() ? p.value("semantic", json()) : json();
            if (!semantic.is_string()) continue;
            const auto k =
                std::find_if(std::begin(known), std::end(known), [&](const auto& e) { return semantic == e.first; });
            if (k == std::end(known)) continue;
            const std::string pp = at("classes." + name + ".properties." + key);
            // A bad declaration fails the subtrees that use its class only.
            auto problem = [&](const std::string& where, const std::string& why) {
                if (!sem.problem) sem.problem = std::make_tuple(from, where, why);
            };
            const std::string what = k->first;
            const json type = p.value("type", json()), component = p.value("componentType", json());
            const bool array = p.value("array", json(false)) == true;
            const json count = p.value("count", json());
            if (type != "SCALAR") {
                problem(pp + ".type", what + " must be SCALAR, not " + type.dump());
            } else if (component != "FLOAT32" && component != "FLOAT64") {
                problem(pp + ".componentType", what + " must be FLOAT32 or FLOAT64, not " + component.dump());
            } else if (k->second == 1 && array) {
                problem(pp + ".array", what + " is a single number, not an array");
            } else if (k->second > 1 && (!array || count != k->second)) {
                problem(pp + ".count", what + " must be an array of " + std::to_string(k->second) + " numbers");
            } else if (p.value("normalized", json(false)) == true) {
                problem(pp + ".normalized", what + " is a float: normalized applies to integer types only");
            } else if (p.contains("offset") && !transformComponents(p["offset"], k->second, unused)) {
                problem(pp + ".offset", what + "'s offset must be " + transformShape(k->second));
            } else if (p.contains("scale") && !transformComponents(p["scale"], k->second, unused)) {
                problem(pp + ".scale", what + "'s scale must be " + transformShape(k->second));
            } else {
                SemanticProperty sp{key, component == "FLOAT64", k->second};
                if (p.contains("offset")) transformComponents(p["offset"], k->second, sp.offset);
                if (p.contains("scale")) transformComponents(p["scale"], k->second, sp.scale);
                (k->second == 12  ? sem.box
                 : k->second == 6 ? sem.region
                 : k->second == 4 ? sem.sphere
                                  : sem.error) = sp;
            }
        }
    }
    return out;
}

namespace {

// A tile's bounding volume (or its viewerRequestVolume: `key`) as a sphere; `raw`: the box's or region's numbers
// (implicit tiling divides them).
Sphere volume(const std::string& file, const json& tile, const std::string& tilePath, bool& region,
              std::vector<double>& raw, const char* key = "boundingVolume") {
    const std::string path = tilePath + "." + key;
    if (!tile.contains(key)) fail(file, path, "missing");
    const json& v = tile[key];
    if (!v.is_object()) fail(file, path, "must be an object");
    region = false;
    if (v.contains("box")) {
        raw = numbers(file, v["box"], path + ".box", 12);
        return boxSphere(raw.data());
    }
    if (v.contains("sphere")) {
        const auto b = numbers(file, v["sphere"], path + ".sphere", 4);
        if (b[3] < 0.0) fail(file, path + ".sphere[3]", "radius " + std::to_string(b[3]) + " is negative");
        raw.clear();
        return {{b[0], b[1], b[2]}, b[3]};
    }
    if (v.contains("region")) {
        const auto r = raw = numbers(file, v["region"], path + ".region", 6);
        const std::string bad = badRegion(r.data());
        if (!bad.empty()) fail(file, path + ".region", bad);
        region = true;
        return regionSphere(r);
    }
    fail(file, path, "has no box, sphere or region");
}

class Reader {
public:
    Reader(const std::string& file, std::deque<TileDesc>& tiles, std::vector<std::string>& warnings, uint32_t source,
           const MetadataSchema& schema, const FileMetadata& meta)
        : file_(file), tiles_(tiles), warnings_(warnings), source_(source), schema_(schema), meta_(meta) {}

    uint32_t tile(const json& j, const std::string& path, int64_t parent, bool inheritedAdd, uint32_t depth) {
        if (!j.is_object()) fail(file_, path, "a tile must be an object");
        TileDesc d;
        d.parent = parent;
        d.file = file_;
        d.path = path;
        d.source = source_;
        d.depth = depth;
        std::vector<double> raw;
        d.sphere = volume(file_, j, path, d.region, raw);
        if (!j.contains("geometricError")) fail(file_, path + ".geometricError", "missing");
        d.geometricError = number(file_, j["geometricError"], path + ".geometricError");
        if (d.geometricError < 0.0) fail(file_, path + ".geometricError", "is negative");
        d.add = inheritedAdd;
        if (j.contains("refine")) {
            const json& r = j["refine"];
            std::string v = r.is_string() ? r.get<std::string>() : "";
            std::transform(v.begin(), v.end(), v.begin(), ::toupper);  // 1.0 tilesets wrote "add" too
            if (v != "ADD" && v != "REPLACE") fail(file_, path + ".refine", "must be \"ADD\" or \"REPLACE\"");
            d.add = v == "ADD";
        } else if (parent < 0 && depth == 0) {
            warnings_.push_back(file_ + ": " + path + ".refine: missing on the root; REPLACE assumed");
        }
        if (j.contains("transform")) {
            const auto m = numbers(file_, j["transform"], path + ".transform", 16);
            dmat4 t;
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r) t[c][r] = m[size_t(c * 4 + r)];  // column-major, as glTF
            const std::string why = nonInvertibleAffine(t);
            if (!why.empty()) fail(file_, path + ".transform", why);
            d.transform = t;
            d.hasTransform = t != dmat4(1.0);
        }
        if (j.contains("viewerRequestVolume")) {
            std::vector<double> unused;
            d.request = volume(file_, j, path, d.requestRegion, unused, "viewerRequestVolume");
        }
        auto meta = make<TileMetadata>();  // kept when the tile or a content has metadata or a group
        if (j.contains("metadata"))
            meta->tile = readEntity(file_, j["metadata"], meta_.schema.get(), path + ".metadata", warnings_);
        if (j.contains("content")) content(j["content"], path + ".content", d, *meta);
        if (j.contains("contents")) {
            const json& cs = j["contents"];
            if (!cs.is_array()) fail(file_, path + ".contents", "must be an array");
            for (size_t i = 0; i < cs.size(); ++i)
                content(cs[i], path + ".contents[" + std::to_string(i) + "]", d, *meta);
        }
        if (meta->tile || std::any_of(meta->contents.begin(), meta->contents.end(),
                                      [](const TileMetadata::Content& c) { return c.metadata || c.group >= 0; })) {
            meta->schema = meta_.schema;
            meta->groups = meta_.groups;
            d.metadata = meta;
        }
        if (j.contains("implicitTiling")) implicit(j, path, raw, d);
        const uint32_t index = uint32_t(tiles_.size());
        tiles_.push_back(std::move(d));
        if (j.contains("children")) {
            const json& cs = j["children"];
            if (!cs.is_array()) fail(file_, path + ".children", "must be an array");
            for (size_t i = 0; i < cs.size(); ++i) {
                const uint32_t c =
                    tile(cs[i], path + ".children[" + std::to_string(i) + "]", index, tiles_[index].add, depth + 1);
                tiles_[index].children.push_back(c);
            }
        }
        return index;
    }

private:
    // The root of an implicit tree: its contents' URIs are templates, read per tile with its subtree.
    void implicit(const json& j, const std::string& path, const std::vector<double>& raw, TileDesc& d) {
        const std::string at = path + ".implicitTiling";
        const json& it = j["implicitTiling"];
        if (!it.is_object()) fail(file_, at, "must be an object");
        if (j.contains("children")) fail(file_, path + ".children", "a tile with implicit tiling has no children");
        if (raw.empty())
            fail(file_, path + ".boundingVolume", "implicit tiling divides a box or a region, not a sphere");
        auto t = std::make_shared<ImplicitTiling>();
        const json scheme = it.value("subdivisionScheme", json());
        if (scheme != "QUADTREE" && scheme != "OCTREE")
            fail(file_, at + ".subdivisionScheme", "must be \"QUADTREE\" or \"OCTREE\"");
        t->octree = scheme == "OCTREE";
        for (auto [key, out, most] : {std::make_tuple("subtreeLevels", &t->subtreeLevels, t->octree ? 8u : 12u),
                                      std::make_tuple("availableLevels", &t->availableLevels, 31u)}) {
            const json v = it.value(key, json());
            if (!v.is_number_integer() || v.get<int64_t>() < 1 || v.get<int64_t>() > int64_t(most))
                fail(file_, at + "." + key, "must be an integer from 1 to " + std::to_string(most));
            *out = v.get<uint32_t>();
        }
        const json sub = it.value("subtrees", json());
        if (!sub.is_object() || !sub.contains("uri") || !sub["uri"].is_string())
            fail(file_, at + ".subtrees.uri", "missing or not a string");
        t->subtrees = resolveReference(file_, sub["uri"].get<std::string>(), at + ".subtrees.uri");
        t->contents = std::move(d.contents);
        t->contentPaths = std::move(d.contentPaths);
        d.contents.clear();
        d.contentPaths.clear();
        t->region = d.region;
        t->volume = raw;
        t->geometricError = d.geometricError;
        t->schema = schema_;
        t->fullSchema = meta_.schema;
        t->groups = meta_.groups;
        t->contentGroups.assign(t->contents.size(), -1);
        for (size_t c = 0; d.metadata && c < d.metadata->contents.size() && c < t->contentGroups.size(); ++c)
            t->contentGroups[c] = d.metadata->contents[c].group;
        d.implicit = std::move(t);
        d.pending = true;
    }

    void content(const json& c, const std::string& path, TileDesc& d, TileMetadata& meta) {
        if (!c.is_object()) fail(file_, path, "must be an object");
        const char* key = c.contains("uri") ? "uri" : "url";  // "url": 3D Tiles 1.0 before its release
        if (!c.contains(key) || !c[key].is_string() || c[key].get<std::string>().empty())
            fail(file_, path + ".uri", "missing or not a non-empty string");
        d.contents.push_back(resolveReference(file_, c[key].get<std::string>(), path + "." + key));
        d.contentPaths.push_back(path + "." + key);
        TileMetadata::Content m;
        if (c.contains("metadata"))
            m.metadata = readEntity(file_, c["metadata"], meta_.schema.get(), path + ".metadata", warnings_);
        if (c.contains("group")) {
            const json& g = c["group"];
            if (!g.is_number_unsigned() || g.get<uint64_t>() >= meta_.groups->size())
                fail(file_, path + ".group",
                     "must be an index into the tileset's " + std::to_string(meta_.groups->size()) + " groups");
            m.group = int(g.get<uint64_t>());
        }
        meta.contents.push_back(std::move(m));
    }

    const std::string& file_;
    std::deque<TileDesc>& tiles_;
    std::vector<std::string>& warnings_;
    uint32_t source_;
    const MetadataSchema& schema_;
    const FileMetadata& meta_;
};

}  // namespace

uint32_t TilesetState::addTileset(const std::string& file, const std::vector<unsigned char>& bytes,
                                  int64_t parentSource, int64_t parentTile) {
    gltf::checkJsonDepth(file, bytes.data(), bytes.size());
    json j;
    try {
        j = json::parse(bytes.begin(), bytes.end());
    } catch (const json::exception& e) {
        fail(file, "", std::string("JSON: ") + e.what());
    }
    if (!j.is_object() || !j.contains("asset") || !j["asset"].is_object())
        fail(file, "asset", "missing: not a 3D Tiles tileset");
    if (!j.contains("root")) fail(file, "root", "missing: not a 3D Tiles tileset");
    const json& asset = j["asset"];
    if (!asset.contains("version") || !asset["version"].is_string()) fail(file, "asset.version", "missing");
    const std::string version = asset["version"].get<std::string>();
    std::vector<std::string> warnings;
    if (version != "1.0" && version != "1.1" && version != "0.0")
        warnings.push_back(file + ": asset.version: " + version + " is newer than 1.1; read as 1.1");
    if (j.contains("extensionsRequired")) {
        const json& ext = j["extensionsRequired"];
        if (!ext.is_array()) fail(file, "extensionsRequired", "must be an array");
        for (size_t i = 0; i < ext.size(); ++i) {
            const std::string name = ext[i].is_string() ? ext[i].get<std::string>() : ext[i].dump();
            if (std::find(std::begin(kKnownExtensions), std::end(kKnownExtensions), name) == std::end(kKnownExtensions))
                fail(file, "extensionsRequired[" + std::to_string(i) + "]", "extension " + name + " is not supported");
        }
    }

    std::shared_ptr<const Schema> full;
    const MetadataSchema schema = readSchema(file, j, options.resource, &full, &warnings);
    FileMetadata meta = readFileMetadata(file, j, std::move(full), warnings);

    std::lock_guard<std::mutex> lock(mutex_);
    // An external tileset naming one of the files that lead to it would be read forever.
    std::string chain = file;
    for (int64_t s = parentSource; s >= 0; s = sources_[size_t(s)].parent) {
        chain = sources_[size_t(s)].file + " -> " + chain;
        if (sources_[size_t(s)].file == file) fail(file, "", "the tileset refers back to itself (" + chain + ")");
    }
    const uint32_t source = uint32_t(sources_.size());
    sources_.push_back({file, parentSource});
    const size_t before = tiles_.size();
    bool add = false;
    uint32_t depth = 0;
    if (parentTile >= 0) {
        add = tiles_[size_t(parentTile)].add;
        depth = tiles_[size_t(parentTile)].depth + 1;
    }
    try {
        Reader reader(file, tiles_, warnings, source, schema, meta);
        const uint32_t root = reader.tile(j["root"], "root", -1, add, depth);
        if (parentSource < 0) top = std::move(meta);
        counts_.tiles += tiles_.size() - before;
        if (parentTile >= 0) counts_.externalTilesets++;
        warnings_.insert(warnings_.end(), warnings.begin(), warnings.end());
        return root;
    } catch (...) {
        tiles_.resize(before);  // a tileset is read whole or not at all
        sources_.pop_back();
        throw;
    }
}

Sphere implicitSphere(const ImplicitTiling& t, uint32_t level, uint32_t x, uint32_t y, uint32_t z) {
    const double n = std::ldexp(1.0, int(level));
    std::vector<double> v = t.volume;
    if (t.region) {  // west, south, east, north, heights: divided in longitude and latitude (and height)
        const double dw = (t.volume[2] - t.volume[0]) / n, ds = (t.volume[3] - t.volume[1]) / n;
        v[0] = t.volume[0] + dw * x;
        v[2] = v[0] + dw;
        v[1] = t.volume[1] + ds * y;
        v[3] = v[1] + ds;
        if (t.octree) {
            const double dh = (t.volume[5] - t.volume[4]) / n;
            v[4] = t.volume[4] + dh * z;
            v[5] = v[4] + dh;
        }
        return regionSphere(v);
    }
    // A box: halved along its first two half axes (and the third for an octree) per level.
    const dvec3 c(v[0], v[1], v[2]);
    const dvec3 ax[3] = {{v[3], v[4], v[5]}, {v[6], v[7], v[8]}, {v[9], v[10], v[11]}};
    const uint32_t at[3] = {x, y, z};
    dvec3 centre = c;
    for (int i = 0; i < (t.octree ? 3 : 2); ++i) {
        centre += ax[i] * ((2.0 * at[i] + 1.0) / n - 1.0);
        for (int k = 0; k < 3; ++k) v[size_t(3 + 3 * i + k)] /= n;
    }
    v[0] = centre.x;
    v[1] = centre.y;
    v[2] = centre.z;
    return boxSphere(v.data());
}

TileDesc TilesetState::tile(uint32_t i) const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (i >= tiles_.size()) throw LoadError("", "", "tile " + std::to_string(i) + " is not in the tileset");
    return tiles_[i];
}

void TilesetState::setWorld(uint32_t i, const dmat4& world) {
    std::lock_guard<std::mutex> lock(mutex_);
    tiles_[i].world = world;
}

void TilesetState::warn(std::string w) {
    std::lock_guard<std::mutex> lock(mutex_);
    warnings_.push_back(std::move(w));
}

std::vector<std::string> TilesetState::warnings() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return warnings_;
}

TilesetCounts TilesetState::counts() const {
    TilesetCounts c;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        c = counts_;
        c.failed = failures_.size();
    }
    c.sharedMeshes = meshes.replaced();
    c.pooledMeshes = meshes.size();
    return c;
}

void TilesetState::countPoints(size_t points) {
    std::lock_guard<std::mutex> lock(mutex_);
    counts_.points += points;
}

}  // namespace sg::tiles
