// The point tile builder's sample rule (a node's points taken from its children) and a leaf's spacing.
#include "loaders/points/internal/PointTilerDetail.h"

#include <algorithm>
#include <cmath>

namespace sg::pointtiles {
namespace {

// The cell of p in a grid of `cells` per edge over [min, min + cells * cellSize), clamped into it.
glm::u64vec3 gridCell(const dvec3& p, const dvec3& min, double cellSize, uint64_t cells) {
    glm::u64vec3 c;
    for (int a = 0; a < 3; ++a) {
        const double f = std::floor((p[a] - min[a]) / cellSize);
        c[a] = f > 0.0 ? uint64_t(std::min(f, double(cells - 1))) : 0u;  // NaN to 0 as well
    }
    return c;
}

struct Candidate {
    uint64_t key;  // the grid cell
    double distance2;
    uint64_t order;
    uint32_t child, index;
    bool operator<(const Candidate& o) const {
        if (key != o.key) return key < o.key;
        if (distance2 != o.distance2) return distance2 < o.distance2;
        return order < o.order;
    }
};

}  // namespace

std::vector<Point> takeSample(const Cube& cube, const NodeId& node, int gridCells,
                              std::vector<std::vector<Point>*> children) {
    const uint64_t g = uint64_t(gridCells);
    const double cellSize = node.edge(cube) / double(g);
    const dvec3 min = node.min(cube);
    std::vector<Candidate> candidates;
    for (uint32_t c = 0; c < children.size(); ++c) {
        const std::vector<Point>& pts = *children[c];
        for (uint32_t i = 0; i < pts.size(); ++i) {
            const glm::u64vec3 cell = gridCell(pts[i].position, min, cellSize, g);
            const dvec3 centre = min + (dvec3(cell) + 0.5) * cellSize;
            const dvec3 d = pts[i].position - centre;
            candidates.push_back({cell.x + g * (cell.y + g * cell.z), glm::dot(d, d), pts[i].order, c, i});
        }
    }
    std::sort(candidates.begin(), candidates.end());
    std::vector<std::vector<char>> chosen(children.size());
    for (uint32_t c = 0; c < children.size(); ++c) chosen[c].assign(children[c]->size(), 0);
    std::vector<Point> sample;
    for (size_t i = 0; i < candidates.size(); ++i) {
        if (i > 0 && candidates[i].key == candidates[i - 1].key) continue;  // the cell's first is its nearest
        const Candidate& k = candidates[i];
        chosen[k.child][k.index] = 1;
        sample.push_back((*children[k.child])[k.index]);
    }
    for (uint32_t c = 0; c < children.size(); ++c) {
        std::vector<Point>& pts = *children[c];
        size_t kept = 0;
        for (size_t i = 0; i < pts.size(); ++i)
            if (!chosen[c][i]) pts[kept++] = pts[i];
        pts.resize(kept);
    }
    std::sort(sample.begin(), sample.end(), [](const Point& a, const Point& b) { return a.order < b.order; });
    return sample;
}

// The bits of v spread to every third bit (20 bits in, 60 out): a Morton code's one axis.
uint64_t spread(uint64_t v) {
    v &= 0xfffff;
    v = (v | (v << 32)) & 0x1f00000000ffffULL;
    v = (v | (v << 16)) & 0x1f0000ff0000ffULL;
    v = (v | (v << 8)) & 0x100f00f00f00f00fULL;
    v = (v | (v << 4)) & 0x10c30c30c30c30c3ULL;
    v = (v | (v << 2)) & 0x1249249249249249ULL;
    return v;
}

double leafSpacing(const Cube& cube, const NodeId& node, int gridCells, const std::vector<Point>& points) {
    // Each point's cell in the finest grid tried (10 halvings of the sample grid: at most 2^20 cells an edge) as a
    // Morton code, sorted once: points that share a cell at some halving share the code's leading bits there, so
    // they sit side by side, and the deepest prefix two neighbours share names the halving that parts every point.
    constexpr int kHalvings = 10;
    const uint64_t finest = uint64_t(gridCells) << kHalvings;
    const double cellSize = node.edge(cube) / double(gridCells);
    const dvec3 min = node.min(cube);
    std::vector<uint64_t> codes(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
        const glm::u64vec3 c = gridCell(points[i].position, min, cellSize / double(1 << kHalvings), finest);
        codes[i] = spread(c.x) | (spread(c.y) << 1) | (spread(c.z) << 2);
    }
    std::sort(codes.begin(), codes.end());
    int needed = 0;  // halvings
    for (size_t i = 1; i < codes.size() && needed < kHalvings; ++i) {
        const uint64_t differ = codes[i] ^ codes[i - 1];
        if (differ == 0) return cellSize / double(1 << kHalvings);  // duplicates stop at the finest tried
        const int highest = 63 - __builtin_clzll(differ);
        // They share the cell of halving h while all their coordinates' bits from (10 - h) up agree.
        needed = std::max(needed, kHalvings - highest / 3);
    }
    return cellSize / double(1 << std::max(needed, 0));
}

}  // namespace sg::pointtiles
