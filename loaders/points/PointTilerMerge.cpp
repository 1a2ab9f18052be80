// The point tile builder's merge: the levels above the chunks sampled from the chunk roots' points (outDir/.parts),
// every chunk root's tile written, and tileset.json.
#include "loaders/points/internal/PointTilerDetail.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>

namespace sg::pointtiles {
namespace {

namespace fs = std::filesystem;

struct Merge {
    std::string outDir, parts;
    const PointTileOptions& options;
    Cube cube;
    bool intensity = false;
    std::set<std::string> chunks, upper;   // upper: the nodes above the chunks
    std::map<std::string, TileMeta> meta;  // every chunk root's and upper node's, once final
    std::set<std::string> dropped;         // leaves the level above took every point of
    PointTileStats& stats;

    std::string part(const std::string& path) const { return parts + "/" + path + ".pts"; }
    bool isNode(const std::string& path) const { return chunks.count(path) || upper.count(path); }

    void readIndex();
    void readChunks(const std::string& file, const nlohmann::json& list);
    std::vector<std::string> splitParts(const std::string& file, const std::string& at, const std::string& path) const;
    void sample(const std::string& path);
    void writeTiles(const std::string& path, std::vector<Point>& points);
    void writeTile(std::ostream& out, const std::string& path);
};

// LoadError(file, JSON path, reason) for a part of the index that is not what the shards write.
[[noreturn]] void badIndex(const std::string& file, const std::string& path, const std::string& reason) {
    throw LoadError(file, path, reason);
}

void Merge::readIndex() {
    const std::string file = parts + "/index.json";
    if (!fs::exists(file)) throw std::runtime_error(file + ": missing: run the shards (--shard I/N) before the merge");
    const nlohmann::json j = nlohmann::json::parse(readFile(file), nullptr, false);
    if (!j.is_object()) badIndex(file, "", "not a JSON object");
    try {
        const auto& c = j.value("cube", nlohmann::json());
        if (!c.is_array() || c.size() != 4 || !std::all_of(c.begin(), c.end(), [](auto& v) { return v.is_number(); }))
            badIndex(file, "cube", "not four numbers");
        cube.min = dvec3(c[0].get<double>(), c[1].get<double>(), c[2].get<double>());
        cube.size = c[3].get<double>();
        if (!isFinite(cube.min) || !(cube.size > 0.0) || !std::isfinite(cube.size))
            badIndex(file, "cube", "not finite");
        if (j.value("gridCells", -1) != options.gridCells)
            badIndex(file, "gridCells", "the shards were built with another gridCells than the merge's");
        if (j.value("pnts", !options.pnts) != options.pnts)
            badIndex(file, "pnts", "the shards were built with another tile format than the merge's");
        intensity = j.value("intensity", false);
        stats.points = j.value("points", uint64_t(0));
        readChunks(file, j.value("chunks", nlohmann::json()));
    } catch (const nlohmann::json::exception& e) {  // a value of the wrong type
        badIndex(file, "", e.what());
    }
}

void Merge::readChunks(const std::string& file, const nlohmann::json& list) {
    if (!list.is_array() || list.empty()) badIndex(file, "chunks", "not a list of chunks");
    for (size_t i = 0; i < list.size(); ++i) {
        const std::string at = "chunks[" + std::to_string(i) + "].path";
        if (!list[i].is_object() || !list[i].value("path", nlohmann::json()).is_string()) badIndex(file, at, "missing");
        const std::string path = list[i]["path"].get<std::string>();
        try {
            NodeId::fromPath(path);
        } catch (const std::runtime_error& e) {
            badIndex(file, at, e.what());
        }
        // A chunk split out of core (too dense for memory): its parts are the chunks, it is a level above them.
        std::vector<std::string> built{path};
        if (fs::exists(parts + "/" + path + ".split")) built = splitParts(file, at, path);
        for (const std::string& b : built) {
            if (!fs::exists(part(b)))
                throw std::runtime_error(part(b) + ": missing: chunk " + std::to_string(i) +
                                         " has not been built (has every shard finished?)");
            chunks.insert(b);
            for (size_t n = 1; n < b.size(); ++n) upper.insert(b.substr(0, n));
        }
    }
    for (const std::string& u : upper)
        if (chunks.count(u)) badIndex(file, "chunks", "chunk " + u + " is above another chunk");
}

// The parts a shard split chunk `path` into (outDir/.parts/<path>.split: a path a line), each below it.
std::vector<std::string> Merge::splitParts(const std::string& file, const std::string& at,
                                           const std::string& path) const {
    std::vector<std::string> out;
    const std::string text = readFile(parts + "/" + path + ".split");
    for (size_t b = 0, e; b < text.size(); b = e + 1) {
        e = text.find('\n', b);
        if (e == std::string::npos) e = text.size();
        const std::string sub = text.substr(b, e - b);
        if (sub.empty()) continue;
        try {
            NodeId::fromPath(sub);
        } catch (const std::runtime_error& err) {
            badIndex(file, at, path + ".split: " + err.what());
        }
        if (sub.compare(0, path.size(), path) != 0) badIndex(file, at, path + ".split: " + sub + " is not below it");
        out.push_back(sub);
    }
    if (out.empty()) badIndex(file, at, path + ".split: no parts");
    return out;
}

// Bottom-up: the node's sample taken from its children's points, their tiles written, its own points kept in its part.
void Merge::sample(const std::string& path) {
    const NodeId node = NodeId::fromPath(path);
    std::vector<std::string> kids;
    for (int i = 0; i < 8; ++i)
        if (isNode(path + char('0' + i))) kids.push_back(path + char('0' + i));
    for (const std::string& k : kids)
        if (upper.count(k)) sample(k);
    std::vector<std::vector<Point>> points(kids.size());
    std::vector<std::vector<Point>*> held;
    TileMeta own;
    own.error = node.edge(cube) / double(options.gridCells);
    for (size_t i = 0; i < kids.size(); ++i) {
        points[i] = readPart(part(kids[i]), meta[kids[i]]);
        held.push_back(&points[i]);
        own.box.expand(meta[kids[i]].box);
        own.levels = std::max(own.levels, meta[kids[i]].levels + 1);
    }
    std::vector<Point> mine = takeSample(cube, node, options.gridCells, held);
    for (size_t i = 0; i < kids.size(); ++i) writeTiles(kids[i], points[i]);
    own.content = !mine.empty();
    writePart(part(path), own, mine);
}

// A node's final points: its tile (none when the level above took them all; a leaf is then dropped).
void Merge::writeTiles(const std::string& path, std::vector<Point>& points) {
    TileMeta& m = meta[path];
    m.content = !points.empty();
    if (m.content) {
        stats.bytes += pointtiles::writeTile(outDir, cube, NodeId::fromPath(path), points, intensity, options.pnts);
        ++stats.tiles;
    } else if (chunks.count(path) && fs::file_size(parts + "/" + path + ".children") == 0) {
        dropped.insert(path);
    }
    std::vector<Point>().swap(points);
}

// Streamed: the chunks' subtrees are copied from their .children text, never held together.
void Merge::writeTile(std::ostream& out, const std::string& path) {
    const NodeId node = NodeId::fromPath(path);
    out << openTile(path, meta[path], node.edge(cube), options.pnts, path == "r");
    if (chunks.count(path)) {
        out << closeTile(readFile(parts + "/" + path + ".children"));
        return;
    }
    std::vector<std::string> kept;
    for (int i = 0; i < 8; ++i)
        if (isNode(path + char('0' + i)) && !dropped.count(path + char('0' + i))) kept.push_back(path + char('0' + i));
    if (kept.empty()) {  // a tileset's children list is never empty
        out << '}';
        return;
    }
    out << ",\"children\":[";
    for (size_t i = 0; i < kept.size(); ++i) {
        if (i > 0) out << ',';
        writeTile(out, kept[i]);
    }
    out << "]}";
}

}  // namespace

void mergePointTiles(const std::string& outDir, const PointTileOptions& options, PointTileStats& stats) {
    Merge m{outDir, outDir + "/.parts", options, {}, false, {}, {}, {}, {}, stats};
    m.readIndex();
    fs::create_directories(outDir + "/tiles");
    if (m.upper.count("r")) m.sample("r");
    std::vector<Point> root = readPart(m.part("r"), m.meta["r"]);
    m.writeTiles("r", root);
    m.dropped.erase("r");  // the root stays, whatever it holds
    stats.levels = m.meta["r"].levels;

    const std::string file = outDir + "/tileset.json";
    {
        std::ofstream out(file, std::ios::binary | std::ios::trunc);
        if (!out) throw std::runtime_error(file + ": cannot be opened for writing");
        const nlohmann::json asset = {{"version", options.pnts ? "1.0" : "1.1"}};
        // The error of drawing nothing: the whole cube.
        out << "{\"asset\":" << asset.dump() << ",\"geometricError\":" << nlohmann::json(m.cube.size).dump()
            << ",\"root\":";
        m.writeTile(out, "r");
        out << "}\n";
        out.close();
        if (!out) throw std::runtime_error(file + ": cannot be written");
    }
    stats.bytes += fs::file_size(file);
    fs::remove_all(m.parts);
}

}  // namespace sg::pointtiles
