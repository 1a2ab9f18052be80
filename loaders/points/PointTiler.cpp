// buildPointTiles: the options checked, a shard's chunks distributed (pass 2) and built, then the merge.
#include "loaders/points/PointTiler.h"

#include "loaders/points/internal/PointTilerDetail.h"

#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace sg {
namespace {

namespace fs = std::filesystem;
using namespace pointtiles;

// Pass 2 keeps at most this many points in its buffers before appending them to the chunks' files (~40 MiB).
constexpr size_t kBufferedPoints = size_t(1) << 20;

void check(const PointTileOptions& o) {
    const auto bad = [](const std::string& why) { throw std::invalid_argument("buildPointTiles(): " + why); };
    if (o.maxPointsPerTile == 0) bad("maxPointsPerTile must be at least 1");
    if (o.chunkPoints < o.maxPointsPerTile) bad("chunkPoints must be at least maxPointsPerTile");
    if (o.gridCells < 1 || o.gridCells > 1024) bad("gridCells must be from 1 to 1024");
    if (o.shards < 1) bad("shards must be at least 1, not " + std::to_string(o.shards));
    if (o.shard < 0 || o.shard >= o.shards)
        bad("shard must be from 0 to shards - 1 (" + std::to_string(o.shards - 1) + "), not " +
            std::to_string(o.shard));
    if (o.stage == PointTileOptions::All && o.shards != 1) bad("the All stage builds every chunk: shards must be 1");
}

std::string chunkFile(const std::string& tempDir, size_t chunk) {
    return tempDir + "/chunk-" + std::to_string(chunk) + ".bin";
}

// Pass 2: this shard's points appended to their chunks' files, in scan order.
void distribute(ScanReader& scan, const ChunkPlan& plan, const PointTileOptions& o, const std::string& tempDir) {
    const auto mine = [&](size_t chunk) { return chunk % size_t(o.shards) == size_t(o.shard); };
    for (size_t c = 0; c < plan.chunks.size(); ++c)
        if (mine(c)) fs::remove(chunkFile(tempDir, c));  // files of an interrupted run would be appended to
    std::vector<std::vector<Point>> buffers(plan.chunks.size());
    size_t buffered = 0;
    const auto flush = [&] {
        for (size_t c = 0; c < buffers.size(); ++c)
            if (!buffers[c].empty()) {
                appendRecords(chunkFile(tempDir, c), buffers[c]);
                // Freed, not cleared: a buffer that once held most of the points would keep its capacity, and the
                // capacities of many chunks' buffers add up far past the points buffered at any one time.
                std::vector<Point>().swap(buffers[c]);
            }
        buffered = 0;
    };
    const uint32_t cells = 1u << kCountLevel, shift = kMaxLevel - kCountLevel;
    std::vector<ScanPoint> buf;
    uint64_t order = 0;
    scan.rewind();
    while (scan.read(buf, 1 << 16) > 0) {
        for (const ScanPoint& p : buf) {
            const glm::u32vec3 q = plan.cube.cell(p.position) >> shift;
            const uint32_t chunk = plan.owner[q.x + cells * (q.y + size_t(cells) * q.z)];
            if (chunk < plan.chunks.size() && mine(chunk)) {
                buffers[chunk].push_back({p.position, order, p.color, p.intensity});
                if (++buffered == kBufferedPoints) flush();
            }
            ++order;
        }
    }
    flush();
    if (order != plan.points)
        throw std::runtime_error("buildPointTiles(): the scan gave " + std::to_string(order) +
                                 " points on its second reading, " + std::to_string(plan.points) + " on its first");
}

// Written under a temporary name, then renamed: shards writing it at once each leave a whole file.
void writeIndex(const std::string& outDir, const ChunkPlan& plan, const PointTileOptions& o, bool intensity) {
    nlohmann::json chunks = nlohmann::json::array();
    for (const ChunkPlan::Chunk& c : plan.chunks) chunks.push_back({{"path", c.path}, {"points", c.points}});
    const nlohmann::json index = {{"cube", {plan.cube.min.x, plan.cube.min.y, plan.cube.min.z, plan.cube.size}},
                                  {"gridCells", o.gridCells},
                                  {"pnts", o.pnts},
                                  {"intensity", intensity},
                                  {"points", plan.points},
                                  {"chunks", chunks}};
    const std::string tmp = outDir + "/.parts/index.json." + std::to_string(o.shard);
    writeFile(tmp, index.dump());
    fs::rename(tmp, outDir + "/.parts/index.json");
}

// One chunk (or part of a chunk split out of core) built in memory: its tiles, and its root's part for the merge.
void buildOne(const SubChunk& sc, const std::string& outDir, const PointTileOptions& o, bool intensity,
              const Cube& cube, PointTileStats& stats) {
    std::vector<Point> points = readRecords(sc.file);
    fs::remove(sc.file);
    if (points.size() != sc.points)
        throw std::runtime_error(sc.file + ": " + std::to_string(points.size()) + " points, " +
                                 std::to_string(sc.points) + " counted");
    stats.largestChunk = std::max(stats.largestChunk, uint64_t(points.size()));
    ChunkResult r = buildChunk(cube, sc.node, std::move(points), o, intensity, outDir);
    const std::string part = outDir + "/.parts/" + sc.node.path;
    writePart(part + ".pts", r.meta, r.points);
    writeFile(part + ".children", r.childrenText);
    stats.tiles += r.tiles;
    stats.bytes += r.bytes + r.points.size() * kRecordBytes + r.childrenText.size();
    stats.levels = std::max(stats.levels, r.meta.levels);
}

void buildShard(ScanReader& scan, const std::string& outDir, const PointTileOptions& o, PointTileStats& stats) {
    const ChunkPlan plan = planChunks(scan, o.chunkPoints);
    stats.points = plan.points;
    const bool intensity = scan.info().hasIntensity;
    const std::string tempDir = o.tempDir.empty() ? outDir + "/.tmp-" + std::to_string(o.shard) : o.tempDir;
    fs::create_directories(outDir + "/tiles");
    fs::create_directories(outDir + "/.parts");
    fs::create_directories(tempDir);
    distribute(scan, plan, o, tempDir);
    for (size_t c = size_t(o.shard); c < plan.chunks.size(); c += size_t(o.shards)) {
        const NodeId root = NodeId::fromPath(plan.chunks[c].path);
        const std::vector<SubChunk> subs =
            splitChunk(plan.cube, root, chunkFile(tempDir, c), plan.chunks[c].points, o.chunkPoints);
        if (subs.size() > 1 || subs[0].node.path != root.path) {  // the merge builds the levels above them
            std::string list;
            for (const SubChunk& sc : subs) list += sc.node.path + "\n";
            writeFile(outDir + "/.parts/" + root.path + ".split", list);
        }
        for (const SubChunk& sc : subs) buildOne(sc, outDir, o, intensity, plan.cube, stats);
    }
    writeIndex(outDir, plan, o, intensity);
    if (o.tempDir.empty()) fs::remove_all(tempDir);
}

}  // namespace

PointTileStats buildPointTiles(ScanReader& scan, const std::string& outDir, const PointTileOptions& options) {
    check(options);
    const auto start = std::chrono::steady_clock::now();
    PointTileStats stats;
    try {
        if (options.stage != PointTileOptions::Merge) buildShard(scan, outDir, options, stats);
        if (options.stage != PointTileOptions::Shard) mergePointTiles(outDir, options, stats);
    } catch (const fs::filesystem_error& e) {
        throw std::runtime_error(std::string("buildPointTiles(): ") + e.what());
    }
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return stats;
}

}  // namespace sg
