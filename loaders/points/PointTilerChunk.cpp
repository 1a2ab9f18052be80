// The point tile builder's in-memory step: one chunk split into an octree and sampled bottom-up.
#include "loaders/points/internal/PointTilerDetail.h"

#include <algorithm>
#include <array>

namespace sg::pointtiles {
namespace {

struct Builder {
    const Cube& cube;
    const PointTileOptions& options;
    const std::string& outDir;
    bool intensity;
    size_t tiles = 0;
    uint64_t bytes = 0;

    struct Subtree {
        std::vector<Point> points;  // what the node holds
        TileMeta meta;
        std::string childrenText;
    };

    Subtree build(const NodeId& node, std::vector<Point> points) {
        Subtree t;
        for (const Point& p : points) t.meta.box.expand(p.position);
        if (points.size() <= options.maxPointsPerTile || node.level == kMaxLevel) {
            t.meta.error = leafSpacing(cube, node, options.gridCells, points);
            t.meta.content = !points.empty();
            t.points = std::move(points);
            return t;
        }
        // Split in scan order (stable): the children's files come out the same whatever the input's chunking.
        std::array<std::vector<Point>, 8> parts;
        for (const Point& p : points) parts[size_t(childOf(cube.cell(p.position), node.level))].push_back(p);
        std::vector<Point>().swap(points);
        std::array<Subtree, 8> children;
        std::vector<std::vector<Point>*> held;
        for (int i = 0; i < 8; ++i) {
            if (parts[size_t(i)].empty()) continue;
            children[size_t(i)] = build(node.child(i), std::move(parts[size_t(i)]));
            held.push_back(&children[size_t(i)].points);
        }
        t.points = takeSample(cube, node, options.gridCells, held);
        t.meta.error = node.edge(cube) / double(options.gridCells);
        t.meta.content = !t.points.empty();
        for (int i = 0; i < 8; ++i) {
            Subtree& c = children[size_t(i)];
            if (c.meta.box.empty()) continue;  // no points in that octant
            t.meta.levels = std::max(t.meta.levels, c.meta.levels + 1);
            finish(node.child(i), c, t.childrenText);
        }
        return t;
    }

    // A child whose points are final (its parent has sampled): its tile is written and its JSON appended.
    void finish(const NodeId& node, Subtree& c, std::string& siblingsText) {
        c.meta.content = !c.points.empty();
        if (!c.meta.content && c.childrenText.empty()) return;  // a leaf the parent took every point of
        if (c.meta.content) {
            bytes += writeTile(outDir, cube, node, c.points, intensity, options.pnts);
            ++tiles;
        }
        if (!siblingsText.empty()) siblingsText += ',';
        siblingsText += openTile(node.path, c.meta, node.edge(cube), options.pnts, false) + closeTile(c.childrenText);
        std::vector<Point>().swap(c.points);
        std::string().swap(c.childrenText);
    }
};

}  // namespace

ChunkResult buildChunk(const Cube& cube, const NodeId& root, std::vector<Point> points, const PointTileOptions& options,
                       bool intensity, const std::string& outDir) {
    Builder b{cube, options, outDir, intensity};
    Builder::Subtree t = b.build(root, std::move(points));
    ChunkResult r;
    r.points = std::move(t.points);
    r.meta = t.meta;
    r.childrenText = std::move(t.childrenText);
    r.tiles = b.tiles;
    r.bytes = b.bytes;
    return r;
}

}  // namespace sg::pointtiles
