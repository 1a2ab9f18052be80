// writeTileset's implicit tiling (3D Tiles 1.1): the same quadtree of tiles as the explicit tileset.json, written
// as availability bitstreams in subtree files. The writer's boxes are tight around their contents (which overflow
// the quadtree's cells) and its errors are not halved per level, so each tile's box and error travel as tile
// metadata with the TILE_BOUNDING_BOX and TILE_GEOMETRIC_ERROR semantics, which readers apply over the implied
// ones: the tileset refines exactly as the explicit one does.
#include "loaders/tiles/internal/TilesetDetail.h"
#include "loaders/tiles/internal/TilesetTable.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <tuple>

namespace sg::tiles {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Key = std::tuple<uint32_t, uint64_t, uint64_t>;  // level, x, y

// A subtree file's binary chunk: buffer views 8-byte aligned (FLOAT64 values are read in place).
struct Binary {
    std::vector<unsigned char> bytes;
    json views = json::array();

    size_t view(const void* data, size_t size) {
        bytes.resize((bytes.size() + 7) / 8 * 8, 0);
        views.push_back({{"buffer", 0}, {"byteOffset", bytes.size()}, {"byteLength", size}});
        const auto* p = static_cast<const unsigned char*>(data);
        bytes.insert(bytes.end(), p, p + size);
        return views.size() - 1;
    }
};

// An availability: constant where every bit or none is set, else a bitstream.
json availability(Binary& bin, const std::vector<uint64_t>& set, uint64_t bits) {
    if (set.empty()) return {{"constant", 0}};
    if (set.size() == bits) return {{"constant", 1}};
    std::vector<unsigned char> stream(size_t((bits + 7) / 8), 0);
    for (uint64_t i : set) stream[size_t(i >> 3)] |= uint8_t(1u << (i & 7));
    return {{"bitstream", bin.view(stream.data(), stream.size())}, {"availableCount", set.size()}};
}

void writeFile(const std::string& path, const std::vector<unsigned char>& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    out.close();
    if (!out) throw std::runtime_error("writeTileset(): " + path + ": cannot be written");
}

// Tiles in the first `levels` levels of a quadtree.
uint64_t slotsAbove(uint32_t levels) { return ((uint64_t(1) << (2 * levels)) - 1) / 3; }

// The tiles by position, the levels they fill and the box holding them all.
struct TileIndex {
    std::map<Key, size_t> at;
    uint32_t levels = 0;
    Box all;
};

TileIndex indexTiles(const std::vector<ImplicitTile>& tiles) {
    TileIndex index;
    for (size_t i = 0; i < tiles.size(); ++i) {
        const ImplicitTile& t = tiles[i];
        index.at.emplace(Key{t.level, t.x, t.y}, i);
        index.levels = std::max(index.levels, t.level + 1);
        index.all.expand(Box{t.centre - t.half, t.centre + t.half});
    }
    return index;
}

// The subtree's tiles by slot (level offset + Morton index within the level), which orders their rows, and the
// Morton indices of the roots of the subtrees below it.
struct SubtreeTiles {
    std::vector<std::pair<uint64_t, size_t>> rows;
    std::vector<uint64_t> below;
};

// The subtree whose root is tiles[root], at `key`, `subtreeLevels` deep.
SubtreeTiles subtreeTiles(const std::vector<ImplicitTile>& tiles, const std::map<Key, size_t>& at, size_t root,
                          const Key& key, uint32_t subtreeLevels) {
    const auto [rootLevel, sx, sy] = key;
    SubtreeTiles out;
    std::vector<size_t> stack{root};
    while (!stack.empty()) {
        const size_t i = stack.back();
        const ImplicitTile& t = tiles[i];
        stack.pop_back();
        const uint32_t r = t.level - rootLevel;
        const uint64_t lx = t.x - (sx << r), ly = t.y - (sy << r);
        const uint64_t m = morton(uint32_t(lx), uint32_t(ly), 0, false);
        if (r == subtreeLevels) {  // the root of a subtree below
            out.below.push_back(m);
            continue;
        }
        out.rows.emplace_back(slotsAbove(r) + m, i);
        for (uint64_t q = 0; q < 4; ++q) {
            auto it = at.find(Key{t.level + 1, 2 * t.x + (q & 1), 2 * t.y + (q >> 1)});
            if (it != at.end()) stack.push_back(it->second);
        }
    }
    std::sort(out.rows.begin(), out.rows.end());
    return out;
}

// A subtree file's JSON: its availabilities and its tiles' metadata (boxes and errors), their bytes in `bin`.
// `slots`: the subtree's tiles; `childSlots`: the subtrees below it.
json subtreeJson(const std::vector<ImplicitTile>& tiles, const SubtreeTiles& st, const dvec3& rootCentre,
                 uint64_t slots, uint64_t childSlots, Binary& bin) {
    std::vector<uint64_t> available, contents;
    std::vector<double> boxes, errors;
    for (const auto& [slot, i] : st.rows) {
        const ImplicitTile& t = tiles[i];
        available.push_back(slot);
        if (t.content) contents.push_back(slot);
        const dvec3 c = t.centre - rootCentre;  // the root tile's frame, as implicit tiles share it
        boxes.insert(boxes.end(), {c.x, c.y, c.z, t.half.x, 0, 0, 0, t.half.y, 0, 0, 0, t.half.z});
        errors.push_back(t.error);
    }

    json sub;
    sub["tileAvailability"] = availability(bin, available, slots);
    sub["contentAvailability"] = json::array({availability(bin, contents, slots)});
    sub["childSubtreeAvailability"] = availability(bin, st.below, childSlots);
    const size_t boxView = bin.view(boxes.data(), boxes.size() * sizeof(double));
    const size_t errorView = bin.view(errors.data(), errors.size() * sizeof(double));
    sub["propertyTables"] = json::array(
        {{{"class", "tile"},
          {"count", st.rows.size()},
          {"properties", {{"boundingBox", {{"values", boxView}}}, {"geometricError", {{"values", errorView}}}}}}});
    sub["tileMetadata"] = 0;
    bin.bytes.resize((bin.bytes.size() + 7) / 8 * 8, 0);
    sub["buffers"] = json::array({{{"byteLength", bin.bytes.size()}}});
    sub["bufferViews"] = std::move(bin.views);
    return sub;
}

// The binary subtree format: "subt", version 1, the JSON's and the binary chunk's lengths (both padded
// to 8 bytes), the JSON, the binary chunk.
std::vector<unsigned char> subtreeFile(const json& sub, const std::vector<unsigned char>& binary) {
    std::string text = sub.dump();
    text.resize((text.size() + 7) / 8 * 8, ' ');
    std::vector<unsigned char> file = {'s', 'u', 'b', 't', 1, 0, 0, 0};
    for (uint64_t v : {uint64_t(text.size()), uint64_t(binary.size())})
        for (int k = 0; k < 8; ++k) file.push_back(uint8_t(v >> (8 * k)));
    file.insert(file.end(), text.begin(), text.end());
    file.insert(file.end(), binary.begin(), binary.end());
    return file;
}

// Saves the subtree rooted at `key` as dir/subtrees/{level}/{x}/{y}.subtree.
void saveSubtree(const std::string& dir, const Key& key, const std::vector<unsigned char>& file) {
    const auto [rootLevel, sx, sy] = key;
    const fs::path folder = fs::path(dir) / "subtrees" / std::to_string(rootLevel) / std::to_string(sx);
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (ec) throw std::runtime_error("writeTileset(): " + folder.string() + ": cannot be created: " + ec.message());
    writeFile((folder / (std::to_string(sy) + ".subtree")).string(), file);
}

// The metadata class of every tile: its box and geometric error, with the semantics readers apply.
json tileSchema() {
    const json number = {{"type", "SCALAR"}, {"componentType", "FLOAT64"}};
    json box = number, error = number;
    box["array"] = true;
    box["count"] = 12;
    box["semantic"] = "TILE_BOUNDING_BOX";
    error["semantic"] = "TILE_GEOMETRIC_ERROR";
    return {{"id", "sgkit_tiles"},
            {"classes", {{"tile", {{"properties", {{"boundingBox", box}, {"geometricError", error}}}}}}}};
}

// The root tile's JSON, whose implicitTiling names the subtrees and contents.
json implicitRoot(const std::vector<ImplicitTile>& tiles, const TileIndex& index, const dvec3& rootCentre,
                  uint32_t subtreeLevels) {
    const ImplicitTile& r = tiles[index.at.at(Key{0, 0, 0})];
    json root;
    root["transform"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, rootCentre.x, rootCentre.y, rootCentre.z, 1};
    // The implied volumes divide this box; every tile's own (in its metadata) is inside it.
    const dvec3 c = index.all.center() - rootCentre, h = index.all.halfExtent();
    root["boundingVolume"]["box"] = {c.x, c.y, c.z, h.x, 0, 0, 0, h.y, 0, 0, 0, h.z};
    root["geometricError"] = r.error;
    root["refine"] = "REPLACE";
    if (std::any_of(tiles.begin(), tiles.end(), [](const ImplicitTile& t) { return t.content; }))
        root["content"]["uri"] = "tiles/{level}/{x}/{y}.glb";
    root["implicitTiling"] = {{"subdivisionScheme", "QUADTREE"},
                              {"subtreeLevels", subtreeLevels},
                              {"availableLevels", index.levels},
                              {"subtrees", {{"uri", "subtrees/{level}/{x}/{y}.subtree"}}}};
    return root;
}

}  // namespace

json writeImplicitTiles(const std::vector<ImplicitTile>& tiles, const dvec3& rootCentre, const std::string& dir,
                        json& schema, size_t& bytes) {
    const TileIndex index = indexTiles(tiles);
    // Opening reads the root's subtree only: with half the levels in each, no subtree holds much more than the
    // square root of a full tree's tiles.
    const uint32_t subtreeLevels = std::min(12u, std::max(1u, (index.levels + 1) / 2));
    const uint64_t slots = slotsAbove(subtreeLevels), childSlots = uint64_t(1) << (2 * subtreeLevels);

    for (const auto& [key, root] : index.at) {
        if (std::get<0>(key) % subtreeLevels) continue;  // subtrees start every subtreeLevels levels
        const SubtreeTiles st = subtreeTiles(tiles, index.at, root, key, subtreeLevels);
        Binary bin;
        const json sub = subtreeJson(tiles, st, rootCentre, slots, childSlots, bin);
        const std::vector<unsigned char> file = subtreeFile(sub, bin.bytes);
        saveSubtree(dir, key, file);
        bytes += file.size();
    }

    schema = tileSchema();
    return implicitRoot(tiles, index, rootCentre, subtreeLevels);
}

}  // namespace sg::tiles
