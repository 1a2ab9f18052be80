// The point tile builder's parts (loaders/points/PointTiler.h): the octree's addressing, the point records of its
// temporary and part files, the sample rule, the tile writers. Internal header (an internal/ folder): not installed.
#pragma once
#include "loaders/points/PointTiler.h"

#include <cstdint>
#include <string>
#include <vector>

namespace sg::pointtiles {

// A point as the builder keeps it; `order` is its index in the scan (what breaks ties: the bytes are deterministic).
struct Point {
    dvec3 position{0.0};
    uint64_t order = 0;
    glm::u8vec4 color{255};
    uint16_t intensity = 0;
};

// Octree levels at most: integer coordinates of 21 bits an axis (63 bits a point).
constexpr int kMaxLevel = 21;
// Levels of pass 1's count grid (128^3 cells).
constexpr int kCountLevel = 7;

// The octree's root cube.
struct Cube {
    dvec3 min{0.0};
    double size = 1.0;
    // The point's cell at the deepest level, clamped into the cube (a header's bounds may be rounded).
    glm::u32vec3 cell(const dvec3& p) const;
};

// An octree node: its path ("r", then a child digit a level) and integer position at its level.
struct NodeId {
    std::string path = "r";
    int level = 0;
    glm::u64vec3 index{0};
    NodeId child(int i) const;
    double edge(const Cube& c) const { return c.size / double(uint64_t(1) << level); }
    dvec3 min(const Cube& c) const { return c.min + dvec3(index) * edge(c); }
    // The node of the given path (digits 0-7 after "r"); throws std::runtime_error naming a bad path.
    static NodeId fromPath(const std::string& path);
};

// Which child of a node at `level` holds the deepest-level cell `q`.
inline int childOf(const glm::u32vec3& q, int level) {
    const int bit = kMaxLevel - 1 - level;
    return int((q.x >> bit) & 1u) | int(((q.y >> bit) & 1u) << 1) | int(((q.z >> bit) & 1u) << 2);
}

// What the tileset says of a tile besides its children.
struct TileMeta {
    Box box;             // the subtree's points
    double error = 0.0;  // geometricError
    bool content = false;
    int levels = 1;  // levels of its subtree
};

// Point records on disk: 40 bytes each, little-endian (the machines that build shards share a byte order).
constexpr size_t kRecordBytes = 40;
void appendRecords(const std::string& file, const std::vector<Point>& points);  // throws std::runtime_error
std::vector<Point> readRecords(const std::string& file);                        // throws std::runtime_error
std::vector<Point> decodeRecords(const char* bytes, size_t count);

// A chunk's file divided by octants into files (named file.0 ... file.7, recursively) of at most chunkPoints points,
// streamed a block at a time, each part's points in scan order; the parts in octree order, the input file removed.
// A chunk of at most chunkPoints comes back as it is. Throws std::runtime_error naming a file that cannot be read or
// written.
struct SubChunk {
    NodeId node;
    std::string file;
    uint64_t points = 0;
};
std::vector<SubChunk> splitChunk(const Cube& cube, const NodeId& root, const std::string& file, uint64_t count,
                                 size_t chunkPoints);

// A node's points and meta for the merge (outDir/.parts/<path>.pts); readPart checks the file's lengths.
void writePart(const std::string& file, const TileMeta& meta, const std::vector<Point>& points);
std::vector<Point> readPart(const std::string& file, TileMeta& meta);

// The sample rule: one point per cell of a gridCells^3 grid over the node's cube, the one nearest the cell's centre,
// ties to the lower `order`; the chosen points are moved out of `children` and returned in scan order.
std::vector<Point> takeSample(const Cube& cube, const NodeId& node, int gridCells,
                              std::vector<std::vector<Point>*> children);
// A leaf's geometric error: the cell size, from the node's sample grid's down by halvings (at most 10), at which
// every point has a cell of its own.
double leafSpacing(const Cube& cube, const NodeId& node, int gridCells, const std::vector<Point>& points);

// Writes outDir/tiles/<path>.glb (or .pnts) of the points, positions relative to the node's cube centre; returns
// the bytes written. Throws std::runtime_error naming the file when it cannot be written.
uint64_t writeTile(const std::string& outDir, const Cube& cube, const NodeId& node, const std::vector<Point>& points,
                   bool intensity, bool pnts);
// The bytes of a GLB of points (POSITION float relative to `centre` in glTF's +Y up axes, COLOR_0 normalized
// RGBA8, _INTENSITY uint16 when asked; the node translated to the centre) and of a .pnts (RTC_CENTER).
std::string glbBytes(const dvec3& centre, const std::vector<Point>& points, bool intensity);
std::string pntsBytes(const dvec3& centre, const std::vector<Point>& points);

// A tile's JSON object up to its children, left open ("{...,"): the caller writes `"children":[...]` or not, and the
// closing brace through closeTile().
std::string openTile(const std::string& path, const TileMeta& meta, double edge, bool pnts, bool root);
std::string closeTile(const std::string& childrenText);

// Builds one chunk in memory from its points: writes the tiles below its root and returns the root's points (its
// sample, or all of them for a leaf) with its meta; `childrenText` gets the JSON of the root's children.
struct ChunkResult {
    std::vector<Point> points;
    TileMeta meta;
    std::string childrenText;
    size_t tiles = 0;
    uint64_t bytes = 0;
};
ChunkResult buildChunk(const Cube& cube, const NodeId& root, std::vector<Point> points, const PointTileOptions& options,
                       bool intensity, const std::string& outDir);

// Pass 1: the root cube and each chunk's path and count. `owner` maps each cell of the count grid (x + y * 128 +
// z * 128^2) to its chunk's index. The cube is the scan's bounds made a cube (the header's, unless a point lies
// outside them: then the points'). Throws std::runtime_error for an empty scan.
struct ChunkPlan {
    Cube cube;
    uint64_t points = 0;
    struct Chunk {
        std::string path;
        uint64_t points = 0;
    };
    std::vector<Chunk> chunks;  // in octree order (depth first, children by digit)
    std::vector<uint32_t> owner;
};
ChunkPlan planChunks(ScanReader& scan, size_t chunkPoints);
// The merge (PointTileOptions::Merge): adds its tiles and bytes to `stats`.
void mergePointTiles(const std::string& outDir, const PointTileOptions& options, PointTileStats& stats);

// The whole file, or throws std::runtime_error naming it.
std::string readFile(const std::string& file);
void writeFile(const std::string& file, const std::string& bytes);

}  // namespace sg::pointtiles
