// The point tile builder's first pass: the root cube, the points counted into a 128^3 grid, and the grid's count
// pyramid cut into chunks.
#include "loaders/points/internal/PointTilerDetail.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sg::pointtiles {
namespace {

constexpr uint32_t kCells = 1u << kCountLevel;  // per edge
constexpr size_t kReadPoints = 1 << 16;

Cube cubeOf(const Box& b) {
    Cube c;
    const dvec3 extent = b.max - b.min;
    c.size = std::max({extent.x, extent.y, extent.z});
    // A single point (or one plane's worth of a header) still gets a cube to split.
    if (!(c.size > 0.0) || !std::isfinite(c.size)) c.size = 1.0;
    c.min = b.center() - dvec3(c.size * 0.5);
    return c;
}

Box readBounds(ScanReader& scan) {
    Box b;
    std::vector<ScanPoint> buf;
    scan.rewind();
    while (scan.read(buf, kReadPoints) > 0)
        for (const ScanPoint& p : buf) b.expand(p.position);
    return b;
}

// Counts per cell of the count grid; `bounds` gets the points' bounds.
std::vector<uint64_t> countCells(ScanReader& scan, const Cube& cube, uint64_t& total, Box& bounds) {
    std::vector<uint64_t> counts(size_t(kCells) * kCells * kCells, 0);
    std::vector<ScanPoint> buf;
    total = 0;
    scan.rewind();
    const int shift = kMaxLevel - kCountLevel;
    while (scan.read(buf, kReadPoints) > 0) {
        for (const ScanPoint& p : buf) {
            const glm::u32vec3 q = cube.cell(p.position) >> uint32_t(shift);
            ++counts[q.x + kCells * (q.y + size_t(kCells) * q.z)];
            bounds.expand(p.position);
        }
        total += buf.size();
    }
    return counts;
}

struct Pyramid {
    std::vector<std::vector<uint64_t>> levels;  // levels[j]: 8^j cells, x + (y << j) + (z << 2j)
    static size_t at(int j, uint32_t x, uint32_t y, uint32_t z) {
        return x + (size_t(y) << j) + (size_t(z) << (2 * j));
    }
};

Pyramid pyramidOf(std::vector<uint64_t> finest) {
    Pyramid p;
    p.levels.resize(kCountLevel + 1);
    p.levels[kCountLevel] = std::move(finest);
    for (int j = kCountLevel - 1; j >= 0; --j) {
        const uint32_t n = 1u << j;
        p.levels[size_t(j)].assign(size_t(n) * n * n, 0);
        for (uint32_t z = 0; z < 2 * n; ++z)
            for (uint32_t y = 0; y < 2 * n; ++y)
                for (uint32_t x = 0; x < 2 * n; ++x)
                    p.levels[size_t(j)][Pyramid::at(j, x / 2, y / 2, z / 2)] +=
                        p.levels[size_t(j) + 1][Pyramid::at(j + 1, x, y, z)];
    }
    return p;
}

// Depth first from the root: a cell of at most chunkPoints (or of the count grid) is a chunk.
void cut(const Pyramid& p, size_t chunkPoints, const NodeId& node, ChunkPlan& plan) {
    const uint32_t x = uint32_t(node.index.x), y = uint32_t(node.index.y), z = uint32_t(node.index.z);
    const uint64_t count = p.levels[size_t(node.level)][Pyramid::at(node.level, x, y, z)];
    if (count == 0) return;
    if (count > chunkPoints && node.level < kCountLevel) {
        for (int i = 0; i < 8; ++i) cut(p, chunkPoints, node.child(i), plan);
        return;
    }
    const uint32_t id = uint32_t(plan.chunks.size());
    plan.chunks.push_back({node.path, count});
    const uint32_t span = 1u << (kCountLevel - node.level);  // count-grid cells per chunk edge
    for (uint32_t k = 0; k < span; ++k)
        for (uint32_t j = 0; j < span; ++j)
            for (uint32_t i = 0; i < span; ++i)
                plan.owner[(x * span + i) + kCells * ((y * span + j) + size_t(kCells) * (z * span + k))] = id;
}

}  // namespace

ChunkPlan planChunks(ScanReader& scan, size_t chunkPoints) {
    ChunkPlan plan;
    Box header = scan.info().bounds;
    if (header.empty() || !isFinite(header.min) || !isFinite(header.max)) header = readBounds(scan);
    plan.cube = cubeOf(header);
    Box bounds;
    std::vector<uint64_t> counts = countCells(scan, plan.cube, plan.points, bounds);
    if (plan.points == 0) throw std::runtime_error("buildPointTiles(): the scan has no points");
    if (!header.contains(bounds.min) || !header.contains(bounds.max)) {  // the header's bounds were wrong
        plan.cube = cubeOf(bounds);
        counts = countCells(scan, plan.cube, plan.points, bounds);
    }
    plan.owner.assign(counts.size(), UINT32_MAX);
    cut(pyramidOf(std::move(counts)), chunkPoints, NodeId{}, plan);
    return plan;
}

}  // namespace sg::pointtiles
