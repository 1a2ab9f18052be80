// A mesh's occluders (GeneratedOccluders.h, meshOccluders): boxes inside a closed mesh, boxes inside an open one with
// its openings capped, or else polygons on it.
//
// Boxes inside a closed mesh, and why each is inside its solid. A closed mesh (Mesh::closed()) runs every edge once
// each way, so its winding number w(p) is defined off the surface, is constant on each connected set the surface does
// not meet, is 0 far away, and changes only where a path crosses the surface: any segment from a point where w = 0 (an
// eye outside the solid) to a point where w > 0 crosses the surface, at a front face that is drawn. The grid spans the
// bound shrunk by a margin; a cell is *clear* when a separating-axis test finds every triangle farther than kClear of
// the cell grown by kClear (in double, from float positions, whose rounding is ~1e-16 of the mesh's size, far below
// kClear, so "separated" is never a rounding artefact). A clear cell, closed and grown a little, meets no triangle, so
// w is one value over it. That value is read on a vertical ray through the cell's column at a point inside the cell:
// w at a point is the signed count of the surface's crossings below it along the ray (down-facing triangles +1,
// up-facing -1). A triangle is counted only when the ray's point is surely inside its footprint (each edge function
// larger than its rounding bound) and skipped only when surely outside; any other case (the ray through an edge, a
// vertex, or in the plane of a vertical triangle) makes the column fail, retried once at another point, and a column
// that fails twice, or whose count does not end at 0, has no inside cells. (A count below 0 on the way is no error: a
// piece wound inside out, as simplification leaves some, has w < 0 in it; only cells with w > 0 are taken, and the
// crossing that raises w from 0 is at a face seen from its front.) A box is a union of inside cells: every point of it
// is within kClear of an inside cell, so w > 0 there too.
//
// Open meshes, boxes inside them with their openings capped and polygons on them: OpenMeshOccluders.cpp.
#include "sg/build/internal/MeshOccludersParts.h"
#include "sg/scene/internal/OccluderShapes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sg {

void OccluderGenSettings::validate(const char* fn) const {
    auto fail = [&](const std::string& what) { throw std::invalid_argument(std::string(fn) + ": " + what); };
    if (voxels < 1 || voxels > 256) fail("voxels " + std::to_string(voxels) + " is not in 1..256");
    if (maxBoxes > 64) fail("maxBoxes " + std::to_string(maxBoxes) + " is above 64");
    if (maxPolygons > 64) fail("maxPolygons " + std::to_string(maxPolygons) + " is above 64");
    if (maxOpenings > 64) fail("maxOpenings " + std::to_string(maxOpenings) + " is above 64");
    if (!(openingDepth >= 0.0 && openingDepth <= 1.0))
        fail("openingDepth " + std::to_string(openingDepth) + " is not in [0, 1]");
    if (!(minBoxShare >= 0.0 && minBoxShare <= 1.0))
        fail("minBoxShare " + std::to_string(minBoxShare) + " is not in [0, 1]");
    if (!(minPolygonShare >= 0.0 && minPolygonShare <= 1.0))
        fail("minPolygonShare " + std::to_string(minPolygonShare) + " is not in [0, 1]");
    if (!(minMajorShare >= 0.0 && minMajorShare <= 1.0))
        fail("minMajorShare " + std::to_string(minMajorShare) + " is not in [0, 1]");
}

namespace {

using meshocc::Tri;

std::vector<Tri> triangles(const Mesh& m) {
    std::vector<Tri> t(m.triangleCount());
    const auto& p = m.positions();
    for (size_t k = 0; k < t.size(); ++k)
        t[k] = Tri{dvec3(p[m.index(3 * k)]), dvec3(p[m.index(3 * k + 1)]), dvec3(p[m.index(3 * k + 2)])};
    return t;
}

// Separating-axis test of a triangle against the box [c - h, c + h] (Akenine-Moller): true when some axis separates
// them by more than `gap`.
bool separated(const Tri& t, const dvec3& c, const dvec3& h, double gap) {
    const dvec3 v0 = t.a - c, v1 = t.b - c, v2 = t.c - c;
    auto apart = [&](const dvec3& ax) {
        const double p0 = glm::dot(v0, ax), p1 = glm::dot(v1, ax), p2 = glm::dot(v2, ax);
        const double r = h.x * std::abs(ax.x) + h.y * std::abs(ax.y) + h.z * std::abs(ax.z);
        // The 1-norm bounds the length from above: a gap asked of it is at least the gap asked (no square root).
        const double len = std::abs(ax.x) + std::abs(ax.y) + std::abs(ax.z);
        return std::min({p0, p1, p2}) > r + gap * len || std::max({p0, p1, p2}) < -r - gap * len;
    };
    for (int a = 0; a < 3; ++a) {
        dvec3 ax(0.0);
        ax[a] = 1.0;
        if (apart(ax)) return true;
    }
    const dvec3 e[3] = {v1 - v0, v2 - v1, v0 - v2};
    const dvec3 n = glm::cross(e[0], e[1]);
    if (glm::dot(n, n) > 0.0 && apart(n)) return true;
    for (int a = 0; a < 3; ++a)
        for (const dvec3& ed : e) {
            dvec3 u(0.0);
            u[a] = 1.0;
            const dvec3 ax = glm::cross(u, ed);
            if (glm::dot(ax, ax) > 0.0 && apart(ax)) return true;
        }
    return false;
}

// Where the vertical line through (px, py) meets triangle t: +1 or -1 surely inside its footprint (the sign of its
// turn seen from above), 0 surely outside, 2 unsure.
int footprint(const Tri& t, double px, double py) {
    auto edge = [&](const dvec3& u, const dvec3& v, double& bound) {
        const double l = (v.x - u.x) * (py - u.y), r = (v.y - u.y) * (px - u.x);
        bound = 1e-12 * (std::abs(l) + std::abs(r)) + 1e-300;
        return l - r;
    };
    double b0, b1, b2;
    const double e0 = edge(t.a, t.b, b0), e1 = edge(t.b, t.c, b1), e2 = edge(t.c, t.a, b2);
    const bool pos = e0 > b0 && e1 > b1 && e2 > b2, neg = e0 < -b0 && e1 < -b1 && e2 < -b2;
    if (pos) return 1;
    if (neg) return -1;
    const bool somePos = e0 > b0 || e1 > b1 || e2 > b2, someNeg = e0 < -b0 || e1 < -b1 || e2 < -b2;
    return somePos && someNeg ? 0 : 2;
}

struct Grid {
    dvec3 lo, cell;
    int n[3];
    size_t size() const { return size_t(n[0]) * size_t(n[1]) * size_t(n[2]); }
    size_t at(int i, int j, int k) const { return (size_t(k) * size_t(n[1]) + size_t(j)) * size_t(n[0]) + size_t(i); }
    double corner(int axis, int i) const { return lo[axis] + double(i) * cell[axis]; }
};

// Cells that a triangle meets or comes within `clear` of (1: blocked); the others are clear.
std::vector<uint8_t> blockedCells(const std::vector<Tri>& tris, const Grid& g, double clear) {
    std::vector<uint8_t> blocked(g.size(), 0);
    for (const Tri& t : tris) {
        int lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            const double mn = std::min({t.a[a], t.b[a], t.c[a]}) - 2 * clear,
                         mx = std::max({t.a[a], t.b[a], t.c[a]}) + 2 * clear;
            // The cells the triangle's box (grown as the test grows it) reaches, and a little more for the division's
            // rounding: cells beyond are apart along an axis, as the test's first three axes would find.
            lo[a] = std::max(0, int(std::floor((mn - g.lo[a]) / g.cell[a] - 1e-6)));
            hi[a] = std::min(g.n[a] - 1, int(std::floor((mx - g.lo[a]) / g.cell[a] + 1e-6)));
        }
        for (int k = lo[2]; k <= hi[2]; ++k)
            for (int j = lo[1]; j <= hi[1]; ++j)
                for (int i = lo[0]; i <= hi[0]; ++i) {
                    const size_t c = g.at(i, j, k);
                    if (blocked[c]) continue;
                    const dvec3 mn(g.corner(0, i), g.corner(1, j), g.corner(2, k)),
                        mx(g.corner(0, i + 1), g.corner(1, j + 1), g.corner(2, k + 1));
                    if (!separated(t, (mn + mx) * 0.5, (mx - mn) * 0.5 + clear, clear)) blocked[c] = 1;
                }
    }
    return blocked;
}

// The crossings of each column's vertical ray through (ox, oy) of its cells: (height, +1 down-facing or -1 up-facing),
// into `hits`, for the columns not yet done; a column whose ray meets a triangle unsurely is marked in `unsure`.
void columnCrossings(const std::vector<Tri>& tris, const Grid& g, double ox, double oy,
                     const std::vector<uint8_t>& done, std::vector<uint8_t>& unsure,
                     std::vector<std::vector<std::pair<double, int>>>& hits) {
    for (const Tri& t : tris) {
        const double mnx = std::min({t.a.x, t.b.x, t.c.x}), mxx = std::max({t.a.x, t.b.x, t.c.x});
        const double mny = std::min({t.a.y, t.b.y, t.c.y}), mxy = std::max({t.a.y, t.b.y, t.c.y});
        const int i0 = std::max(0, int(std::floor((mnx - g.lo.x) / g.cell.x)) - 1),
                  i1 = std::min(g.n[0] - 1, int(std::floor((mxx - g.lo.x) / g.cell.x)) + 1);
        const int j0 = std::max(0, int(std::floor((mny - g.lo.y) / g.cell.y)) - 1),
                  j1 = std::min(g.n[1] - 1, int(std::floor((mxy - g.lo.y) / g.cell.y)) + 1);
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) {
                const size_t col = size_t(j) * size_t(g.n[0]) + size_t(i);
                if (done[col] || unsure[col]) continue;
                const double px = g.corner(0, i) + ox * g.cell.x, py = g.corner(1, j) + oy * g.cell.y;
                // Off the triangle's xy bound (compared exactly): surely outside it.
                if (px < mnx || px > mxx || py < mny || py > mxy) continue;
                const int f = footprint(t, px, py);
                if (f == 0) continue;
                if (f == 2) {
                    unsure[col] = 1;
                    continue;
                }
                // The plane's height at the point, from the barycentric weights.
                auto e = [&](const dvec3& u, const dvec3& v) {
                    return (v.x - u.x) * (py - u.y) - (v.y - u.y) * (px - u.x);
                };
                const double wa = e(t.b, t.c), wb = e(t.c, t.a), wc = e(t.a, t.b);
                const double z = (wa * t.a.z + wb * t.b.z + wc * t.c.z) / (wa + wb + wc);
                hits[col].push_back({z, f > 0 ? -1 : 1});  // facing up: leaving a solid going up
            }
    }
}

// The inside cells of column (i, j) from its crossings `h` (sorted here), marked in `inside`: none when the count
// does not end at 0 or a crossing lies within a clear cell.
void insideOfColumn(std::vector<std::pair<double, int>>& h, int i, int j, const Grid& g,
                    const std::vector<uint8_t>& blocked, double clear, std::vector<uint8_t>& inside) {
    std::sort(h.begin(), h.end());
    int w = 0;
    bool ok = true;
    for (const auto& x : h) w += x.second;
    if (!ok || w != 0) return;
    size_t next = 0;
    std::vector<size_t> found;
    for (int k = 0; k < g.n[2]; ++k) {
        const double z0 = g.corner(2, k), z1 = g.corner(2, k + 1), zc = 0.5 * (z0 + z1);
        while (next < h.size() && h[next].first < zc) w += h[next++].second;
        const size_t c = g.at(i, j, k);
        if (blocked[c]) continue;
        // A crossing within a clear cell would contradict its clearance: trust nothing in this column.
        for (const auto& x : h)
            if (x.first > z0 - clear && x.first < z1 + clear) ok = false;
        if (w > 0) found.push_back(c);
    }
    if (ok)
        for (size_t c : found) inside[c] = 1;
}

// Inside cells of a closed mesh's grid (1: inside).
std::vector<uint8_t> insideCells(const std::vector<Tri>& tris, const Grid& g, double clear) {
    const std::vector<uint8_t> blocked = blockedCells(tris, g, clear);
    // Winding numbers up each column, at two points inside its cells; a column unsure at both has no inside cells.
    std::vector<uint8_t> inside(g.size(), 0);
    const size_t columns = size_t(g.n[0]) * size_t(g.n[1]);
    std::vector<std::vector<std::pair<double, int>>> hits(columns);
    std::vector<uint8_t> done(columns, 0);
    for (int attempt = 0; attempt < 2; ++attempt) {
        const double ox = attempt == 0 ? 0.6234567 : 0.2281719, oy = attempt == 0 ? 0.4268941 : 0.6414213;
        std::vector<uint8_t> unsure(columns, 0);
        for (size_t c = 0; c < columns; ++c) hits[c].clear();
        columnCrossings(tris, g, ox, oy, done, unsure, hits);
        for (size_t col = 0; col < columns; ++col) {
            if (done[col] || unsure[col]) continue;  // an unsure column is tried again, then left with no cell
            done[col] = 1;
            const int i = int(col % size_t(g.n[0])), j = int(col / size_t(g.n[0]));
            insideOfColumn(hits[col], i, j, g, blocked, clear, inside);
        }
    }
    return inside;
}

struct CellBox {
    int lo[3], hi[3];  // cells [lo, hi)
    size_t volume() const { return size_t(hi[0] - lo[0]) * size_t(hi[1] - lo[1]) * size_t(hi[2] - lo[2]); }
};

// Depth of each inside cell: the fewest inside cells from it to the grid's edge or an outside cell along the three
// axes (seeds deep inside grow the largest boxes).
std::vector<uint16_t> cellDepths(const std::vector<uint8_t>& inside, const Grid& g) {
    std::vector<uint16_t> depth(inside.size(), 0);
    for (size_t c = 0; c < inside.size(); ++c) depth[c] = inside[c] ? uint16_t(0xffff) : 0;
    for (int a = 0; a < 3; ++a) {
        const int len = g.n[a], u = (a + 1) % 3, v = (a + 2) % 3;
        for (int p = 0; p < g.n[u]; ++p)
            for (int q = 0; q < g.n[v]; ++q) {
                auto cell = [&](int t) {
                    int x[3];
                    x[a] = t, x[u] = p, x[v] = q;
                    return g.at(x[0], x[1], x[2]);
                };
                std::vector<uint16_t> run(size_t(len), 0);
                for (int t = 0, r = 0; t < len; ++t) run[size_t(t)] = uint16_t(r = inside[cell(t)] ? r + 1 : 0);
                for (int t = len - 1, r = 0; t >= 0; --t) {
                    r = inside[cell(t)] ? r + 1 : 0;
                    const size_t c = cell(t);
                    depth[c] = std::min<uint16_t>(depth[c], std::min<uint16_t>(run[size_t(t)], uint16_t(r)));
                }
            }
    }
    return depth;
}

// Marked cells in any box in O(1): the prefix sums of a grid's marked cells.
struct CellCounts {
    int nx, ny, nz;
    std::vector<uint32_t> t;

    explicit CellCounts(const Grid& g)
        : nx(g.n[0]), ny(g.n[1]), nz(g.n[2]), t(size_t(nx + 1) * size_t(ny + 1) * size_t(nz + 1), 0) {}

    void sumOf(const std::vector<uint8_t>& cells, const Grid& g) {
        auto T = [&](int i, int j, int k) -> uint32_t& {
            return t[(size_t(k) * size_t(ny + 1) + size_t(j)) * size_t(nx + 1) + size_t(i)];
        };
        for (int k = 1; k <= nz; ++k)
            for (int j = 1; j <= ny; ++j)
                for (int i = 1; i <= nx; ++i)
                    T(i, j, k) = cells[g.at(i - 1, j - 1, k - 1)] + T(i - 1, j, k) + T(i, j - 1, k) + T(i, j, k - 1) -
                                 T(i - 1, j - 1, k) - T(i - 1, j, k - 1) - T(i, j - 1, k - 1) + T(i - 1, j - 1, k - 1);
    }

    size_t countIn(const CellBox& b) const {
        auto T = [&](int i, int j, int k) {
            return size_t(t[(size_t(k) * size_t(ny + 1) + size_t(j)) * size_t(nx + 1) + size_t(i)]);
        };
        return T(b.hi[0], b.hi[1], b.hi[2]) - T(b.lo[0], b.hi[1], b.hi[2]) - T(b.hi[0], b.lo[1], b.hi[2]) -
               T(b.hi[0], b.hi[1], b.lo[2]) + T(b.lo[0], b.lo[1], b.hi[2]) + T(b.lo[0], b.hi[1], b.lo[2]) +
               T(b.hi[0], b.lo[1], b.lo[2]) - T(b.lo[0], b.lo[1], b.lo[2]);
    }
};

// Seeds: the deepest uncovered inside cells, at most 24, as (-depth, cell), deepest first.
std::vector<std::pair<int, size_t>> deepestSeeds(const std::vector<uint8_t>& inside,
                                                 const std::vector<uint8_t>& covered,
                                                 const std::vector<uint16_t>& depth) {
    std::vector<std::pair<int, size_t>> seeds;
    for (size_t c = 0; c < inside.size(); ++c)
        if (inside[c] && !covered[c]) seeds.push_back({-int(depth[c]), c});
    const size_t keep = std::min<size_t>(seeds.size(), 24);
    std::partial_sort(seeds.begin(), seeds.begin() + ptrdiff_t(keep), seeds.end());
    seeds.resize(keep);
    return seeds;
}

// The box grown from cell `c` a face at a time while it holds inside cells only (`inside`, their counts).
CellBox grownBox(size_t c, const Grid& g, const CellCounts& inside) {
    const int nx = g.n[0], ny = g.n[1];
    const int i = int(c % size_t(nx)), j = int((c / size_t(nx)) % size_t(ny)), k = int(c / (size_t(nx) * ny));
    CellBox b{{i, j, k}, {i + 1, j + 1, k + 1}};
    for (bool grew = true; grew;) {
        grew = false;
        for (int face = 0; face < 6; ++face) {
            CellBox t = b;
            const int a = face / 2;
            if (face % 2 ? t.hi[a] >= g.n[a] : t.lo[a] <= 0) continue;
            (face % 2 ? t.hi[a] : t.lo[a]) += face % 2 ? 1 : -1;
            if (inside.countIn(t) == t.volume()) {
                b = t;
                grew = true;
            }
        }
    }
    return b;
}

void cover(const CellBox& b, const Grid& g, std::vector<uint8_t>& covered) {
    for (int z = b.lo[2]; z < b.hi[2]; ++z)
        for (int y = b.lo[1]; y < b.hi[1]; ++y)
            for (int x = b.lo[0]; x < b.hi[0]; ++x) covered[g.at(x, y, z)] = 1;
}

// Boxes grown over the inside cells, largest new volume first.
std::vector<CellBox> growBoxes(const std::vector<uint8_t>& inside, const Grid& g, uint32_t maxBoxes, size_t minCells) {
    const std::vector<uint16_t> depth = cellDepths(inside, g);
    std::vector<uint8_t> covered(inside.size(), 0);
    std::vector<CellBox> out;
    // Covered cells in any box in O(1): prefix sums of the covered cells, summed again after each box taken.
    CellCounts coveredCounts(g);
    CellCounts insideCounts(g);  // the same for the inside cells
    insideCounts.sumOf(inside, g);
    while (out.size() < maxBoxes) {
        const std::vector<std::pair<int, size_t>> seeds = deepestSeeds(inside, covered, depth);
        if (seeds.empty()) break;
        CellBox best{};
        size_t bestNew = 0;
        for (const auto& seed : seeds) {
            const CellBox b = grownBox(seed.second, g, insideCounts);
            const size_t fresh = b.volume() - coveredCounts.countIn(b);
            if (fresh > bestNew) bestNew = fresh, best = b;
        }
        if (bestNew == 0 || bestNew < minCells) break;
        cover(best, g, covered);
        out.push_back(best);
        coveredCounts.sumOf(covered, g);
    }
    return out;
}

}  // namespace

std::vector<Box> meshocc::boxesInside(const std::vector<Tri>& tris, const Box& b, size_t meshTriangles,
                                      const OccluderGenSettings& s, uint64_t& voxelsInside,
                                      const std::vector<Plane>& beyond) {
    std::vector<Box> boxes;
    const dvec3 ext = b.max - b.min;
    const double size = std::max({ext.x, ext.y, ext.z});
    if (!(size > 0.0) || s.maxBoxes == 0) return boxes;
    // The grid spans the bound shrunk by a margin far above kClear, so that faces on the bound (a box mesh's) leave
    // every cell clear; cells are about cubic, the longest axis cut in `voxels`.
    const double clear = 1e-9 * size;
    // Cells along the longest axis: a mesh of few triangles has few features to follow (a box mesh is found whole at
    // any size), so the grid grows with the cube root of its triangles, up to `voxels`: the cost then follows the
    // triangles, not the grid.
    const uint32_t cells =
        std::min(s.voxels, std::max<uint32_t>(8, uint32_t(std::lround(4.0 * std::cbrt(double(meshTriangles))))));
    Grid g;
    for (int a = 0; a < 3; ++a) {
        const double margin = std::max(1e-4 * ext[a], 1e-6 * size);
        if (ext[a] <= 4.0 * margin) return boxes;  // flat: no volume inside
        g.n[a] = std::clamp(int(std::ceil(double(cells) * ext[a] / size - 1e-9)), 1, int(cells));
        g.lo[a] = b.min[a] + margin;
        g.cell[a] = (ext[a] - 2.0 * margin) / double(g.n[a]);
    }
    std::vector<uint8_t> inside = insideCells(tris, g, clear);
    if (!beyond.empty())
        for (int k = 0; k < g.n[2]; ++k)
            for (int j = 0; j < g.n[1]; ++j)
                for (int i = 0; i < g.n[0]; ++i) {
                    uint8_t& in = inside[g.at(i, j, k)];
                    for (int c = 0; c < 8 && in; ++c) {
                        const dvec3 p(g.corner(0, i + (c & 1)), g.corner(1, j + (c >> 1 & 1)),
                                      g.corner(2, k + (c >> 2)));
                        for (const Plane& pl : beyond) in = in && pl.distance(p) > 0.0;
                    }
                }
    for (uint8_t v : inside) voxelsInside += v;
    const double cellVolume = g.cell.x * g.cell.y * g.cell.z, boundVolume = ext.x * ext.y * ext.z;
    const size_t minCells = size_t(std::ceil(s.minBoxShare * boundVolume / cellVolume - 1e-9));
    for (const CellBox& c : growBoxes(inside, g, s.maxBoxes, std::max<size_t>(minCells, 1)))
        boxes.push_back(Box{dvec3(g.corner(0, c.lo[0]), g.corner(1, c.lo[1]), g.corner(2, c.lo[2])),
                            dvec3(g.corner(0, c.hi[0]), g.corner(1, c.hi[1]), g.corner(2, c.hi[2]))});
    std::stable_sort(boxes.begin(), boxes.end(),
                     [](const Box& p, const Box& q) { return occluders::volume(p) > occluders::volume(q); });
    return boxes;
}

static void closedBoxes(const Mesh& mesh, const OccluderGenSettings& s, MeshOccluders& out) {
    out.boxes = meshocc::boxesInside(triangles(mesh), mesh.box(), mesh.triangleCount(), s, out.voxelsInside);
}

MeshOccluders meshOccluders(const Mesh& mesh, const OccluderGenSettings& s) {
    s.validate("sg::meshOccluders()");
    MeshOccluders out;
    if (mesh.triangleCount() == 0 || !mesh.validBound() || mesh.box().empty()) return out;
    out.closed = mesh.closed();
    if (out.closed) {
        closedBoxes(mesh, s, out);
        return out;
    }
    const meshocc::Welded welded(mesh);
    meshocc::cappedBoxes(mesh, welded, s, out);
    if (out.cappedBoxes.empty()) meshocc::openPolygons(mesh, welded, s, out);
    return out;
}

}  // namespace sg
