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

double leafSpacing(const Cube& cube, const NodeId& node, int gridCells, const std::vector<Point>& points) {
    const dvec3 min = node.min(cube);
    uint64_t cells = uint64_t(gridCells);
    double cellSize = node.edge(cube) / double(cells);
    std::vector<uint64_t> keys(points.size());
    for (int halvings = 0;; ++halvings, cells *= 2, cellSize *= 0.5) {
        for (size_t i = 0; i < points.size(); ++i) {
            const glm::u64vec3 c = gridCell(points[i].position, min, cellSize, cells);
            keys[i] = c.x + cells * (c.y + cells * c.z);  // cells <= 2^20: 60 bits
        }
        std::sort(keys.begin(), keys.end());
        // Duplicates, or points closer than 2^-10 of a cell, stop at the finest tried.
        if (halvings == 10 || std::adjacent_find(keys.begin(), keys.end()) == keys.end()) return cellSize;
    }
}

}  // namespace sg::pointtiles
