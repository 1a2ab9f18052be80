// buildPointTiles: the tiles read back (GLB chunks parsed here, tileset.json with nlohmann-json) against the scan:
// every point once, the sample rule, errors down the tree, the same bytes whatever the number of shards, and the
// options and scans refused.
#include "loaders/points/PointTiler.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

using namespace sg;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// A scan held in a vector, read in pieces of at most 100 points (several reads per pass).
class VectorScan : public ScanReader {
public:
    VectorScan(std::vector<ScanPoint> points, const Box& bounds) : points_(std::move(points)) {
        info_.format = "vector";
        info_.count = points_.size();
        info_.bounds = bounds;
        info_.hasColor = info_.hasIntensity = true;
    }
    size_t read(std::vector<ScanPoint>& out, size_t max) override {
        const size_t n = std::min({max, size_t(100), points_.size() - next_});
        out.assign(points_.begin() + long(next_), points_.begin() + long(next_ + n));
        next_ += n;
        return n;
    }
    void rewind() override { next_ = 0; }

private:
    std::vector<ScanPoint> points_;
    size_t next_ = 0;
};

// 3000 points in the cube [0, 64]^3: half spread over it on a grid of 1, half in a cluster in [0, 8)^3 on a grid of
// 0.5 (deeper chunks), every coordinate 0.3 past a grid line (never on a sample cell's edge). The colour is the
// point's index (r + 256 g + 65536 b), the intensity its index too.
std::vector<ScanPoint> makePoints() {
    std::vector<ScanPoint> points(3000);
    uint32_t state = 12345;
    const auto next = [&state](uint32_t n) {
        state = state * 1664525u + 1013904223u;
        return (state >> 8) % n;
    };
    for (uint32_t i = 0; i < points.size(); ++i) {
        ScanPoint& p = points[i];
        for (int a = 0; a < 3; ++a) p.position[a] = i % 2 ? next(16) * 0.5 + 0.3 : next(64) + 0.3;
        p.color = glm::u8vec4(i & 255, (i >> 8) & 255, (i >> 16) & 255, 255);
        p.intensity = uint16_t(i);
    }
    return points;
}

const Box kBounds{dvec3(0.0), dvec3(64.0)};

PointTileOptions smallOptions() {
    PointTileOptions o;
    o.maxPointsPerTile = 100;
    o.chunkPoints = 1000;
    o.gridCells = 4;
    return o;
}

struct TempDir {
    fs::path path;
    explicit TempDir(const std::string& name)
        : path(fs::temp_directory_path() / ("sgkit_pointtiler_" + name + "_" + std::to_string(::getpid()))) {
        fs::remove_all(path);
    }
    ~TempDir() { fs::remove_all(path); }
    std::string str() const { return path.string(); }
};

std::string readBytes(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

struct TilePoint {
    dvec3 position;  // in the tileset's axes (+Z up)
    uint32_t id;
    uint16_t intensity;
};

// A GLB of points as buildPointTiles writes it: one node (translated), one primitive, in glTF's +Y up axes.
std::vector<TilePoint> readGlb(const fs::path& file, dvec3& centre) {
    const std::string bytes = readBytes(file);
    EXPECT_EQ(bytes.substr(0, 4), "glTF") << file;
    uint32_t jsonLength = 0;
    std::memcpy(&jsonLength, bytes.data() + 12, 4);
    const json j = json::parse(bytes.substr(20, jsonLength));
    const char* bin = bytes.data() + 20 + jsonLength + 8;
    const json& t = j["nodes"][0]["translation"];
    centre = dvec3(t[0].get<double>(), -t[2].get<double>(), t[1].get<double>());
    const json& prim = j["meshes"][0]["primitives"][0];
    EXPECT_EQ(prim["mode"].get<int>(), 0);  // POINTS
    const auto view = [&](const char* attribute, size_t& stride) {
        const json& a = j["accessors"][prim["attributes"][attribute].get<int>()];
        const json& v = j["bufferViews"][a["bufferView"].get<int>()];
        stride = v["byteStride"].get<size_t>();
        return bin + v.value("byteOffset", size_t(0)) + a.value("byteOffset", size_t(0));
    };
    const size_t count = j["accessors"][prim["attributes"]["POSITION"].get<int>()]["count"].get<size_t>();
    size_t ps = 0, cs = 0, is = 0;
    const char* pos = view("POSITION", ps);
    const char* col = view("COLOR_0", cs);
    const char* ints = view("_INTENSITY", is);
    std::vector<TilePoint> points(count);
    for (size_t i = 0; i < count; ++i) {
        float g[3];
        std::memcpy(g, pos + i * ps, 12);
        points[i].position = centre + dvec3(g[0], -g[2], g[1]);
        const auto* c = reinterpret_cast<const uint8_t*>(col + i * cs);
        points[i].id = c[0] + 256u * c[1] + 65536u * c[2];
        std::memcpy(&points[i].intensity, ints + i * is, 2);
    }
    return points;
}

json readTileset(const fs::path& dir) { return json::parse(readBytes(dir / "tileset.json")); }

// Every tile depth first, with its parent (null for the root).
void forEachTile(const json& tile, const json* parent, const std::function<void(const json&, const json*)>& f) {
    f(tile, parent);
    for (const json& c : tile.value("children", json::array())) forEachTile(c, &tile, f);
}

std::map<std::string, std::string> filesOf(const fs::path& dir) {
    std::map<std::string, std::string> files;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file()) files[fs::relative(e.path(), dir).string()] = readBytes(e.path());
    return files;
}

}  // namespace

TEST(PointTiler, EveryPointIsInExactlyOneTile) {
    const std::vector<ScanPoint> input = makePoints();
    VectorScan scan(input, kBounds);
    TempDir dir("once");
    const PointTileStats stats = buildPointTiles(scan, dir.str(), smallOptions());
    EXPECT_EQ(stats.points, 3000u);
    EXPECT_GT(stats.levels, 3);
    const json tileset = readTileset(dir.path);
    EXPECT_EQ(tileset["asset"]["version"], "1.1");
    EXPECT_EQ(tileset["root"]["refine"], "ADD");
    std::vector<int> seen(input.size(), 0);
    size_t tiles = 0;
    forEachTile(tileset["root"], nullptr, [&](const json& tile, const json*) {
        if (!tile.contains("content")) return;
        ++tiles;
        dvec3 centre;
        for (const TilePoint& p : readGlb(dir.path / tile["content"]["uri"].get<std::string>(), centre)) {
            ASSERT_LT(p.id, input.size());
            ++seen[p.id];
            EXPECT_NEAR(glm::length(p.position - input[p.id].position), 0.0, 1e-4) << "point " << p.id;
            EXPECT_EQ(p.intensity, input[p.id].intensity);
        }
    });
    EXPECT_EQ(tiles, stats.tiles);
    for (size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], 1) << "point " << i;
}

TEST(PointTiler, ParentsHoldAtMostOnePointPerSampleCell) {
    VectorScan scan(makePoints(), kBounds);
    TempDir dir("sample");
    const PointTileOptions o = smallOptions();
    buildPointTiles(scan, dir.str(), o);
    size_t parents = 0;
    forEachTile(readTileset(dir.path)["root"], nullptr, [&](const json& tile, const json*) {
        if (!tile.contains("content") || !tile.contains("children")) return;
        ++parents;
        // The sample grid: gridCells cells of geometricError over the cube centred on the tile's translation.
        const double cell = tile["geometricError"].get<double>();
        dvec3 centre;
        const std::vector<TilePoint> points = readGlb(dir.path / tile["content"]["uri"].get<std::string>(), centre);
        const dvec3 min = centre - dvec3(cell * o.gridCells * 0.5);
        std::set<std::array<int, 3>> cells;
        for (const TilePoint& p : points) {
            std::array<int, 3> c;
            for (int a = 0; a < 3; ++a)
                c[size_t(a)] = std::clamp(int(std::floor((p.position[a] - min[a]) / cell)), 0, 3);
            EXPECT_TRUE(cells.insert(c).second) << tile["content"]["uri"] << ": two points in one cell";
        }
    });
    EXPECT_GT(parents, 3u);
}

TEST(PointTiler, GeometricErrorDecreasesDownTheTree) {
    VectorScan scan(makePoints(), kBounds);
    TempDir dir("errors");
    buildPointTiles(scan, dir.str(), smallOptions());
    const json tileset = readTileset(dir.path);
    // The root's sample grid: 4 cells over the 64 m cube.
    EXPECT_DOUBLE_EQ(tileset["root"]["geometricError"].get<double>(), 16.0);
    EXPECT_GT(tileset["geometricError"].get<double>(), 16.0);
    forEachTile(tileset["root"], nullptr, [&](const json& tile, const json* parent) {
        EXPECT_GT(tile["geometricError"].get<double>(), 0.0);
        if (parent) {
            EXPECT_LT(tile["geometricError"].get<double>(), (*parent)["geometricError"].get<double>());
        }
    });
}

TEST(PointTiler, ShardedBuildsWriteTheSameBytes) {
    VectorScan scan(makePoints(), kBounds);
    TempDir whole("whole");
    buildPointTiles(scan, whole.str(), smallOptions());
    const std::map<std::string, std::string> expected = filesOf(whole.path);
    ASSERT_TRUE(expected.count("tileset.json"));
    for (int shards : {1, 3, 8}) {
        TempDir dir("shards" + std::to_string(shards));
        PointTileOptions o = smallOptions();
        o.stage = PointTileOptions::Shard;
        o.shards = shards;
        for (o.shard = 0; o.shard < shards; ++o.shard) buildPointTiles(scan, dir.str(), o);
        o.stage = PointTileOptions::Merge;
        o.shard = 0;
        buildPointTiles(scan, dir.str(), o);
        const std::map<std::string, std::string> files = filesOf(dir.path);
        EXPECT_EQ(files.size(), expected.size()) << shards << " shards";
        for (const auto& [name, bytes] : expected) {
            ASSERT_TRUE(files.count(name)) << name << " missing with " << shards << " shards";
            EXPECT_TRUE(files.at(name) == bytes) << name << " differs with " << shards << " shards";
        }
    }
}

TEST(PointTiler, PntsTilesHoldEveryPoint) {
    VectorScan scan(makePoints(), kBounds);
    TempDir dir("pnts");
    PointTileOptions o = smallOptions();
    o.pnts = true;
    buildPointTiles(scan, dir.str(), o);
    const json tileset = readTileset(dir.path);
    EXPECT_EQ(tileset["asset"]["version"], "1.0");
    uint64_t points = 0;
    forEachTile(tileset["root"], nullptr, [&](const json& tile, const json*) {
        if (!tile.contains("content")) return;
        const std::string bytes = readBytes(dir.path / tile["content"]["uri"].get<std::string>());
        ASSERT_EQ(bytes.substr(0, 4), "pnts");
        uint32_t header[7];
        std::memcpy(header, bytes.data(), 28);
        EXPECT_EQ(header[2], bytes.size());
        EXPECT_EQ((28 + header[3]) % 8, 0u);
        points += json::parse(bytes.substr(28, header[3]))["POINTS_LENGTH"].get<uint64_t>();
    });
    EXPECT_EQ(points, 3000u);
}

TEST(PointTiler, BadOptionsAreRefused) {
    VectorScan scan(makePoints(), kBounds);
    TempDir dir("bad");
    PointTileOptions o = smallOptions();
    o.stage = PointTileOptions::Shard;
    o.shard = 3;
    o.shards = 3;
    EXPECT_THROW(buildPointTiles(scan, dir.str(), o), std::invalid_argument);
    o.shard = 0;
    o.shards = 0;
    EXPECT_THROW(buildPointTiles(scan, dir.str(), o), std::invalid_argument);
    o = smallOptions();
    o.maxPointsPerTile = 0;
    EXPECT_THROW(buildPointTiles(scan, dir.str(), o), std::invalid_argument);
    EXPECT_FALSE(fs::exists(dir.path));  // refused before anything is written
}

TEST(PointTiler, AnEmptyScanIsRefused) {
    VectorScan scan({}, Box{});
    TempDir dir("empty");
    EXPECT_THROW(buildPointTiles(scan, dir.str(), smallOptions()), std::runtime_error);
}

// A count-grid cell (64 / 128 = 0.5 an edge here) holding more than chunkPoints, as the ground at a scanner's station
// does: it is split on disk into parts that fit, every point still in one tile, the same bytes whatever the shards.
TEST(PointTiler, AChunkDenserThanMemoryIsSplitOnDisk) {
    std::vector<ScanPoint> input = makePoints();
    const size_t spread = input.size();
    for (uint32_t i = 0; i < 2500; ++i) {
        ScanPoint p;
        p.position = dvec3(0.01 + 0.48 * ((i * 37) % 101) / 101.0, 0.01 + 0.48 * ((i * 53) % 97) / 97.0,
                           0.01 + 0.48 * ((i * 71) % 89) / 89.0);
        const uint32_t id = uint32_t(spread + i);
        p.color = glm::u8vec4(id & 255, (id >> 8) & 255, (id >> 16) & 255, 255);
        input.push_back(p);
    }
    VectorScan scan(input, kBounds);
    TempDir whole("dense");
    const PointTileStats stats = buildPointTiles(scan, whole.str(), smallOptions());
    EXPECT_EQ(stats.points, input.size());
    EXPECT_GT(stats.largestChunk, 0u);
    EXPECT_LE(stats.largestChunk, smallOptions().chunkPoints);  // 2500 in one count cell, held 1000 at most
    std::vector<int> seen(input.size(), 0);
    forEachTile(readTileset(whole.path)["root"], nullptr, [&](const json& tile, const json*) {
        if (!tile.contains("content")) return;
        dvec3 centre;
        for (const TilePoint& p : readGlb(whole.path / tile["content"]["uri"].get<std::string>(), centre)) {
            ASSERT_LT(p.id, input.size());
            ++seen[p.id];
        }
    });
    for (size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], 1) << "point " << i;

    const std::map<std::string, std::string> expected = filesOf(whole.path);
    TempDir dir("dense3");
    PointTileOptions o = smallOptions();
    o.stage = PointTileOptions::Shard;
    o.shards = 3;
    for (o.shard = 0; o.shard < o.shards; ++o.shard) buildPointTiles(scan, dir.str(), o);
    o.stage = PointTileOptions::Merge;
    o.shard = 0;
    buildPointTiles(scan, dir.str(), o);
    EXPECT_TRUE(filesOf(dir.path) == expected);
}
