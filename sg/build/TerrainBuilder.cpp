#include "sg/build/TerrainBuilder.h"

#include "nodes/Geometry.h"
#include "nodes/Occluder.h"
#include "nodes/Transform.h"
#include "sg/core/Mesh.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

namespace sg {

namespace {

bool powerOfTwoPlusOne(long n) { return n >= 3 && (((n - 1) & (n - 2)) == 0); }

void fail(const std::string& what) { throw std::invalid_argument("sg::buildTerrain(): " + what); }

}  // namespace

std::vector<int> terrainLevelCells(int per, int levels) {
    std::vector<int> cells{per};
    for (int l = 1, step = 2; l < levels && step <= (1 << 24); ++l, step *= 2) {
        const int c = std::max(2, (per + step - 1) / step);
        if (c < cells.back()) cells.push_back(c);
    }
    return cells;
}

TerrainTileGrid terrainTileGrid(int per, int cells) {
    if (!(cells >= 2 && cells <= per))
        throw std::invalid_argument("sg::terrainTileGrid(): cells " + std::to_string(cells) + " is not in 2.." +
                                    std::to_string(per));
    TerrainTileGrid g;
    g.per = per;
    const int side = per + 1;
    // The sample points inside the tile: per / cells apart, rounded to the grid.
    std::vector<int> at(size_t(cells) + 1);
    for (int k = 0; k <= cells; ++k) at[size_t(k)] = int(std::lround(double(k) * per / cells));
    std::vector<char> used(size_t(side) * size_t(side), 0);
    auto use = [&](int li, int lj) { used[size_t(lj) * size_t(side) + size_t(li)] = 1; };
    if (cells == per) {
        std::fill(used.begin(), used.end(), 1);
    } else {
        for (int k = 0; k <= per; ++k) use(k, 0), use(k, per), use(0, k), use(per, k);
        for (int b = 1; b < cells; ++b)
            for (int a = 1; a < cells; ++a) use(at[size_t(a)], at[size_t(b)]);
    }
    std::vector<uint32_t> id(used.size(), 0);
    for (int lj = 0; lj <= per; ++lj)
        for (int li = 0; li <= per; ++li) {
            if (!used[size_t(lj) * size_t(side) + size_t(li)]) continue;
            id[size_t(lj) * size_t(side) + size_t(li)] = uint32_t(g.points.size());
            g.points.emplace_back(li, lj);
        }
    std::vector<uint32_t>& idx = g.indices;
    // A triangle of grid points, wound to face up.
    auto tri = [&](glm::ivec2 p, glm::ivec2 q, glm::ivec2 r) {
        if ((q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x) < 0) std::swap(q, r);
        for (const glm::ivec2& v : {p, q, r}) idx.push_back(id[size_t(v.y) * size_t(side) + size_t(v.x)]);
    };
    auto quad = [&](int ia, int ib, int ja, int jb) {  // split along the (ia, ja)-(ib, jb) diagonal
        tri({ia, ja}, {ib, ja}, {ib, jb});
        tri({ia, ja}, {ib, jb}, {ia, jb});
    };
    if (cells == per) {
        idx.reserve(size_t(per) * size_t(per) * 6);
        for (int j = 0; j < per; ++j)
            for (int i = 0; i < per; ++i) quad(i, i + 1, j, j + 1);
        return g;
    }
    for (int b = 1; b + 1 < cells; ++b)
        for (int a = 1; a + 1 < cells; ++a) quad(at[size_t(a)], at[size_t(a + 1)], at[size_t(b)], at[size_t(b + 1)]);
    // The ring between the inner grid's outline and the border, one side at a time (counter-clockwise):
    // both chains run along the side; the one whose next edge ends nearer the start advances.
    const int lo = at[1], hi = at[size_t(cells - 1)], m = cells - 2;
    for (int s = 0; s < 4; ++s) {
        // Point k of the border (0..per) and of the inner chain (0..m) on side s, and their position along it.
        auto outer = [&](int k) -> glm::ivec2 {
            const glm::ivec2 v[4] = {{k, 0}, {per, k}, {per - k, per}, {0, per - k}};
            return v[s];
        };
        auto inner = [&](int k) -> glm::ivec2 {
            const int c = at[size_t(k + 1)], r = at[size_t(cells - 1 - k)];
            const glm::ivec2 v[4] = {{c, lo}, {hi, c}, {r, hi}, {lo, r}};
            return v[s];
        };
        auto innerAlong = [&](int k) { return double(at[size_t(k + 1)]); };
        int a = 0, b = 0;
        while (a < per || b < m) {
            const bool advanceOuter = b == m || (a < per && a + 0.5 <= 0.5 * (innerAlong(b) + innerAlong(b + 1)));
            if (advanceOuter) {
                tri(outer(a), outer(a + 1), inner(b));
                ++a;
            } else {
                tri(outer(a), inner(b + 1), inner(b));
                ++b;
            }
        }
    }
    return g;
}

namespace {

// Templated on the sample accessor: the build calls it for every level of every tile.
template <class Height>
double levelError(const TerrainTileGrid& level, const Height& height) {
    const int per = level.per;
    // The full-resolution surface at tile-local grid coordinates (gx, gy) in [0, per]^2: the plane of the
    // cell's triangle that holds the point.
    auto surface = [&](double gx, double gy) {
        const int i = std::min(int(gx), per - 1), j = std::min(int(gy), per - 1);
        const double u = gx - i, v = gy - j;
        const double h00 = height(i, j), h10 = height(i + 1, j), h01 = height(i, j + 1), h11 = height(i + 1, j + 1);
        return u >= v ? h00 + u * (h10 - h00) + v * (h11 - h10) : h00 + v * (h01 - h00) + u * (h11 - h01);
    };
    double err = 0.0;
    const std::vector<glm::ivec2>& p = level.points;
    for (size_t t = 0; t + 2 < level.indices.size(); t += 3) {
        const glm::ivec2 c[3] = {p[level.indices[t]], p[level.indices[t + 1]], p[level.indices[t + 2]]};
        const double hc[3] = {height(c[0].x, c[0].y), height(c[1].x, c[1].y), height(c[2].x, c[2].y)};
        const double area = double((c[1].x - c[0].x) * (c[2].y - c[0].y) - (c[1].y - c[0].y) * (c[2].x - c[0].x));
        if (area == 0.0) continue;
        const glm::ivec2 mn = glm::min(c[0], glm::min(c[1], c[2])), mx = glm::max(c[0], glm::max(c[1], c[2]));
        const long sgn = area > 0.0 ? 1 : -1;
        for (int j = mn.y; j <= mx.y; ++j) {
            // The row's points inside: each edge's (integer) numerator C - D i keeps the area's sign, solved for i
            // exactly; the thin fan triangles of the border would otherwise scan their whole boxes.
            long lo = mn.x, hi = mx.x;
            for (int e = 0; e < 3; ++e) {
                const glm::ivec2 a = c[(e + 1) % 3], b = c[(e + 2) % 3];
                const long D = sgn * (b.y - a.y), C = sgn * (long(b.x - a.x) * (j - a.y) + long(b.y - a.y) * a.x);
                if (D == 0) {
                    if (C < 0) hi = lo - 1;
                } else if (D > 0) {  // i <= C / D
                    hi = std::min(hi, C >= 0 ? C / D : -((-C + D - 1) / D));
                } else {                          // i >= C / D, D < 0
                    const long nc = -C, nd = -D;  // i >= nc / nd
                    lo = std::max(lo, nc >= 0 ? (nc + nd - 1) / nd : -((-nc) / nd));
                }
            }
            for (int i = int(lo); i <= int(hi); ++i) {
                auto edge = [&](const glm::ivec2& a, const glm::ivec2& b) {
                    return double((b.x - a.x) * (j - a.y) - (b.y - a.y) * (i - a.x)) / area;
                };
                const double w0 = edge(c[1], c[2]), w1 = edge(c[2], c[0]), w2 = edge(c[0], c[1]);
                if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) continue;
                err = std::max(err, std::abs(height(i, j) - (w0 * hc[0] + w1 * hc[1] + w2 * hc[2])));
            }
        }
        for (int e = 0; e < 3; ++e) {
            const glm::ivec2 a = c[e], b = c[(e + 1) % 3];
            const double ha = hc[e], hb = hc[(e + 1) % 3];
            auto crossings = [&](int va, int vb) {  // where a linear function of the edge passes an integer
                for (int k = std::min(va, vb) + 1; k < std::max(va, vb); ++k) {
                    const double s = double(k - va) / double(vb - va);
                    const double x = a.x + s * (b.x - a.x), y = a.y + s * (b.y - a.y);
                    err = std::max(err, std::abs(surface(x, y) - (ha + s * (hb - ha))));
                }
            };
            crossings(a.x, b.x);
            crossings(a.y, b.y);
            crossings(a.x - a.y, b.x - b.y);
        }
    }
    return err;
}

}  // namespace

double terrainLevelError(const TerrainTileGrid& level, const std::function<double(int, int)>& height) {
    return levelError(level, height);
}

namespace {

template <class T>
struct Builder {
    const std::vector<T>& h;
    int n = 0, per = 0;
    double spacing = 1.0, pixelsPerRadian = 1.0, pixelError = 1.0;
    std::vector<TerrainTileGrid> grids;  // one per level, shared by every tile
    ref_ptr<Material> material;
    Terrain& out;
    const TerrainParams& prm;
    dvec3 origin{0.0};

    double at(int i, int j) const { return double(h[size_t(j) * size_t(n) + size_t(i)]); }
    // A vertex's height as drawn (rounded once to float, as tileMesh rounds it).
    double drawnZ(int i, int j) const { return double(float(prm.originInVertices ? origin.z + at(i, j) : at(i, j))); }

    // Occluders (TerrainParams::occluders). A tile split into k x k parts: their edges in tile-local grid
    // coordinates, and for each part (row-major) the grid points of every triangle of every level whose bounding
    // rectangle meets the part's (closed): every point of a level's surface over the part lies in one of those
    // triangles, where the surface is linear between its corners, so no lower than the lowest of those points and no
    // higher than the highest. The vertices' xy rounding to float moves them far less than the cell that separates a
    // triangle that misses the part from it.
    struct Parts {
        std::vector<int> edge;
        std::vector<std::vector<glm::ivec2>> points;
        int count() const { return int(edge.size()) - 1; }
        // The parts whose closed interval [edge[b], edge[b + 1]] meets [lo, hi].
        std::pair<int, int> span(int lo, int hi) const {
            const int first = int(std::lower_bound(edge.begin() + 1, edge.end(), lo) - edge.begin()) - 1;
            const int last = int(std::upper_bound(edge.begin(), edge.end() - 1, hi) - edge.begin()) - 1;
            return {first, last};
        }
    };

    Parts parts(int k) const {
        Parts p;
        for (int e = 0; e <= k; ++e) p.edge.push_back(int(std::lround(double(e) * per / k)));
        p.points.assign(size_t(k) * size_t(k), {});
        for (const TerrainTileGrid& g : grids)
            for (size_t t = 0; t + 2 < g.indices.size(); t += 3) {
                const glm::ivec2 c[3] = {g.points[g.indices[t]], g.points[g.indices[t + 1]],
                                         g.points[g.indices[t + 2]]};
                const glm::ivec2 mn = glm::min(c[0], glm::min(c[1], c[2])), mx = glm::max(c[0], glm::max(c[1], c[2]));
                const auto sx = p.span(mn.x, mx.x), sy = p.span(mn.y, mx.y);
                for (int by = sy.first; by <= sy.second; ++by)
                    for (int bx = sx.first; bx <= sx.second; ++bx)
                        for (const glm::ivec2& q : c) p.points[size_t(by) * size_t(k) + size_t(bx)].push_back(q);
            }
        for (std::vector<glm::ivec2>& v : p.points) {
            std::sort(v.begin(), v.end(),
                      [](glm::ivec2 a, glm::ivec2 b) { return a.y < b.y || (a.y == b.y && a.x < b.x); });
            v.erase(std::unique(v.begin(), v.end()), v.end());
        }
        return p;
    }

    void prepareParts() {
        blocks = parts(prm.occluderBlocks);
        cells = per % 4 == 0 && per > 4 ? parts(per / 4) : blocks;
    }

    void tileMesh(const TerrainTileGrid& g, int i0, int j0, Mesh& mesh) const {
        std::vector<vec3> pos, nrm;
        std::vector<vec2> uvs;
        std::vector<vec4> col;
        pos.reserve(g.points.size());
        nrm.reserve(g.points.size());
        for (const glm::ivec2& q : g.points) {
            const int i = i0 + q.x, j = j0 + q.y;
            // From the global grid index: tiles that share a border compute the same floats there.
            const dvec3 p = prm.originInVertices ? origin + dvec3(i * spacing, j * spacing, at(i, j))
                                                 : dvec3(i * spacing, j * spacing, at(i, j));
            pos.emplace_back(p);
            const double dzx = at(std::min(i + 1, n - 1), j) - at(std::max(i - 1, 0), j);
            const double dzy = at(i, std::min(j + 1, n - 1)) - at(i, std::max(j - 1, 0));
            nrm.emplace_back(glm::normalize(dvec3(-dzx, -dzy, 2.0 * spacing)));
            if (prm.uv || prm.color) {
                const dvec3 world = prm.originInVertices ? p : origin + p;
                if (prm.uv) uvs.push_back(prm.uv(world));
                if (prm.color) col.push_back(prm.color(world));
            }
        }
        mesh.set(std::move(pos), std::move(nrm), g.indices, std::move(uvs), std::move(col));
    }

    // A tile's levels and their ranges: plain data, filled on worker threads (no shared reference counts; the
    // meshes are made beforehand in tile and level order, so that their ids do not depend on the threads).
    struct TileData {
        std::vector<ref_ptr<Mesh>> levels;
        std::vector<double> errors;
        std::vector<float> from;
        dvec3 center{0.0};
        // Occluders: each block's lowest drawn vertex, each height cell's highest, and the tile's lowest.
        std::vector<double> blockLow, cellHigh;
        double low = 0.0;
    };
    std::vector<TileData> tiles;  // by tj * tilesPerSide + ti
    // Occluders (Parts above).
    Parts blocks{};  // the boxes'
    Parts cells{};   // the surface's height cells: 4 grid cells a side when that divides the tile, else the blocks
    std::shared_ptr<OccluderSurface> surface{};
    double lowest = 0.0;  // the lowest drawn vertex (prepareSurface)

    void tileData(int ti, int tj, TileData& t) const {
        const int i0 = ti * per, j0 = tj * per;
        auto height = [&](int li, int lj) { return at(i0 + li, j0 + lj); };
        for (size_t l = 0; l < grids.size(); ++l) {
            tileMesh(grids[l], i0, j0, *t.levels[l]);
            // Never more accurate than a finer level: distances stay in order.
            t.errors.push_back(l == 0 ? 0.0 : std::max(t.errors.back(), levelError(grids[l], height)));
        }
        if (prm.occluders) {
            t.low = std::numeric_limits<double>::infinity();
            for (int lj = 0; lj <= per; ++lj)
                for (int li = 0; li <= per; ++li) t.low = std::min(t.low, drawnZ(i0 + li, j0 + lj));
            for (const std::vector<glm::ivec2>& pts : blocks.points) {
                double low = std::numeric_limits<double>::infinity();
                for (const glm::ivec2& q : pts) low = std::min(low, drawnZ(i0 + q.x, j0 + q.y));
                t.blockLow.push_back(low);
            }
            for (const std::vector<glm::ivec2>& pts : cells.points) {
                double high = -std::numeric_limits<double>::infinity();
                for (const glm::ivec2& q : pts) high = std::max(high, drawnZ(i0 + q.x, j0 + q.y));
                t.cellHigh.push_back(high);
            }
        }
        const Box box = t.levels[0]->box();
        t.center = box.center();
        const double radius = 0.5 * glm::length(box.max - box.min);
        // Level l is shown from the distance where its error projects to pixelError pixels from the tile's
        // nearest point: the LOD measures from the tile's centre, so its radius is added.
        t.from.assign(t.levels.size(), 0.0f);
        for (size_t l = 1; l < t.levels.size(); ++l) {
            const double d = t.errors[l] * pixelsPerRadian / pixelError + radius;
            float v = float(d);
            if (double(v) < d) v = std::nextafter(v, std::numeric_limits<float>::max());  // at most pixelError
            t.from[l] = v;
        }
    }

    void buildTiles(int perSide) {
        tiles.resize(size_t(perSide) * size_t(perSide));
        for (TileData& t : tiles)
            for (size_t l = 0; l < grids.size(); ++l) t.levels.push_back(make<Mesh>());
        std::atomic<size_t> next{0};
        std::exception_ptr error;
        std::mutex errorLock;
        auto work = [&] {
            try {
                for (size_t k; (k = next++) < tiles.size();)
                    tileData(int(k % size_t(perSide)), int(k / size_t(perSide)), tiles[k]);
            } catch (...) {
                std::lock_guard<std::mutex> lock(errorLock);
                error = std::current_exception();
                next = tiles.size();
            }
        };
        const unsigned threads = std::min<unsigned>(std::max(1u, std::thread::hardware_concurrency()), 8u);
        std::vector<std::thread> pool;
        for (unsigned t = 1; t < threads && tiles.size() > 16; ++t) pool.emplace_back(work);
        work();
        for (std::thread& t : pool) t.join();
        if (error) std::rethrow_exception(error);
    }

    // What the occluders share: the terrain's rectangle as drawn (its corners rounded to float, then one float
    // inward) and the highest vertex over each height cell (Parts: no level's surface over it rises higher), one
    // float up. The cells divide the tiles evenly, so they make an even grid over the terrain.
    void prepareSurface() {
        auto s = std::make_shared<OccluderSurface>();
        const double ox = prm.originInVertices ? origin.x : 0.0, oy = prm.originInVertices ? origin.y : 0.0;
        const double side = double(n - 1) * spacing;
        const float inf = std::numeric_limits<float>::infinity();
        s->min = dvec2(std::nextafter(float(ox), inf), std::nextafter(float(oy), inf));
        s->max = dvec2(std::nextafter(float(ox + side), -inf), std::nextafter(float(oy + side), -inf));
        const int sub = per % cells.count() == 0 ? cells.count() : 1, tps = out.tilesPerSide;
        s->cellsX = s->cellsY = tps * sub;
        s->highest.assign(size_t(s->cellsX) * size_t(s->cellsY), -std::numeric_limits<double>::infinity());
        lowest = std::numeric_limits<double>::infinity();
        for (int tj = 0; tj < tps; ++tj)
            for (int ti = 0; ti < tps; ++ti) {
                const TileData& t = tiles[size_t(tj) * size_t(tps) + size_t(ti)];
                lowest = std::min(lowest, t.low);
                for (int cy = 0; cy < cells.count(); ++cy)
                    for (int cx = 0; cx < cells.count(); ++cx) {
                        // Uneven blocks (sub 1): the tile's cell takes the highest of them all.
                        double& h = sub == 1
                                        ? s->highest[size_t(tj) * size_t(s->cellsX) + size_t(ti)]
                                        : s->highest[size_t(tj * sub + cy) * size_t(s->cellsX) + size_t(ti * sub + cx)];
                        h = std::max(h, double(std::nextafter(
                                            float(t.cellHigh[size_t(cy) * size_t(cells.count()) + size_t(cx)]), inf)));
                    }
            }
        surface = s;
    }

    // A tile's occluders: one box per block, from a quarter of a tile's width below the terrain's lowest vertex (boxes
    // over hills are taller, so the pass, which takes near and large occluders first, prefers them to those of the
    // plain) up to one float under the block's lowest vertex (Parts), its xy the block's as drawn (inside the tile's
    // float vertices: over the tile's own triangles) and inside the surface's rectangle. None where rounding leaves
    // no room.
    void tileOccluders(const TileData& t, int ti, int tj, const LOD* lod, std::vector<ref_ptr<Node>>& add) const {
        const int k = blocks.count();
        const double ox = prm.originInVertices ? origin.x : 0.0, oy = prm.originInVertices ? origin.y : 0.0;
        const float inf = std::numeric_limits<float>::infinity();
        for (int by = 0; by < k; ++by)
            for (int bx = 0; bx < k; ++bx) {
                const double low = t.blockLow[size_t(by) * size_t(k) + size_t(bx)];
                const double top = double(std::nextafter(float(low), -inf));
                double bottom = std::min(lowest, top) - 0.25 * double(per) * spacing;
                if (!(bottom < top)) bottom = top - 1e-6 * std::abs(top);  // a tile's width lost in rounding
                // The block's edges where the tile's vertices are drawn (as tileMesh computes and rounds them).
                auto drawn = [&](double o, int g) { return double(float(o + g * spacing)); };
                const dvec2 lo(std::max(surface->min.x, drawn(ox, ti * per + blocks.edge[size_t(bx)])),
                               std::max(surface->min.y, drawn(oy, tj * per + blocks.edge[size_t(by)])));
                const dvec2 hi(std::min(surface->max.x, drawn(ox, ti * per + blocks.edge[size_t(bx) + 1])),
                               std::min(surface->max.y, drawn(oy, tj * per + blocks.edge[size_t(by) + 1])));
                if (!(std::isfinite(top) && std::isfinite(bottom) && bottom < top && lo.x < hi.x && lo.y < hi.y))
                    continue;
                auto o = make<Occluder>();
                o->setBox(Box{dvec3(lo, bottom), dvec3(hi, top)});
                o->setGenerated(true);
                o->setShownWith(lod);
                o->setBelowSurface(surface);
                add.push_back(o);
            }
    }

    // The tile's occluders, by tile, for its parent to add after it.
    std::vector<std::vector<ref_ptr<Node>>> occluders{};

    ref_ptr<Group> tile(int ti, int tj) {
        TileData& t = tiles[size_t(tj) * size_t(out.tilesPerSide) + size_t(ti)];
        auto lod = make<LOD>();
        lod->setCenter(t.center);
        const float kFar = std::numeric_limits<float>::max();
        for (size_t l = 0; l < t.levels.size(); ++l) {
            // A level as accurate as the next coarser one is never needed: an empty range.
            const float to = l + 1 < t.levels.size() ? t.from[l + 1] : kFar;
            lod->addChild(make<Geometry>(t.levels[l], material), t.from[l], to);
            lod->setError(l, float(t.errors[l]));
        }
        out.finestTriangles += t.levels.front()->triangleCount();
        out.coarsestTriangles += t.levels.back()->triangleCount();
        if (prm.occluders)
            tileOccluders(t, ti, tj, lod.get(), occluders[size_t(tj) * size_t(out.tilesPerSide) + size_t(ti)]);
        t = TileData{};
        return lod;
    }

    // The quadtree node over size x size tiles from tile (ti, tj), and everything below it.
    ref_ptr<Group> node(int ti, int tj, int size, int parent, int depth) {
        const int self = int(out.quad.size());
        out.quad.push_back({nullptr, parent, depth, size == 1});
        ref_ptr<Group> g;
        if (size == 1) {
            g = tile(ti, tj);
        } else {
            g = make<Group>();
            const int s = size / 2;
            for (int k = 0; k < 4; ++k) {
                const int ci = ti + (k & 1) * s, cj = tj + (k >> 1) * s;
                g->addChild(node(ci, cj, s, self, depth + 1));
                if (s == 1) addOccluders(*g, ci, cj);
            }
        }
        out.quad[size_t(self)].node = g;
        return g;
    }

    // One Group of every tile, in row order.
    ref_ptr<Group> flatNode(int perSide) {
        auto g = make<Group>();
        out.quad.push_back({g, -1, 0, false});
        for (int tj = 0; tj < perSide; ++tj)
            for (int ti = 0; ti < perSide; ++ti) {
                out.quad.push_back({nullptr, 0, 1, true});
                out.quad.back().node = tile(ti, tj);
                g->addChild(out.quad.back().node);
                addOccluders(*g, ti, tj);
            }
        return g;
    }

    void addOccluders(Group& parent, int ti, int tj) {
        if (!prm.occluders) return;
        std::vector<ref_ptr<Node>>& add = occluders[size_t(tj) * size_t(out.tilesPerSide) + size_t(ti)];
        for (ref_ptr<Node>& o : add) parent.addChild(o);
        add.clear();
    }
};

bool isMultiple(long a, long b) { return b > 0 && a % b == 0; }

template <class T>
Terrain build(const std::vector<T>& heights, int samplesPerSide, double spacing, const dvec3& origin,
              const TerrainParams& prm) {
    const int n = samplesPerSide;
    if (prm.flat ? !(n >= 3 && n <= (1 << 16) + 1) : (!powerOfTwoPlusOne(n) || n > (1 << 16) + 1))
        fail("samplesPerSide " + std::to_string(n) +
             (prm.flat ? " is not in 3..65537" : " is not 2^k + 1 (3 to 65537)"));
    if (heights.size() != size_t(n) * size_t(n))
        fail(std::to_string(heights.size()) + " heights for " + std::to_string(n) + " x " + std::to_string(n) +
             " samples");
    for (size_t k = 0; k < heights.size(); ++k)
        if (!std::isfinite(heights[k]))
            fail("height " + std::to_string(k) + " (i " + std::to_string(k % size_t(n)) + ", j " +
                 std::to_string(k / size_t(n)) + ") is not finite");
    if (!(spacing > 0.0 && std::isfinite(spacing))) fail("spacing " + std::to_string(spacing) + " is not positive");
    if (!isFinite(origin)) fail("the origin is not finite");
    if (prm.flat) {
        if (!(prm.tileSamples >= 3 && prm.tileSamples <= n && isMultiple(n - 1, prm.tileSamples - 1)))
            fail("tileSamples " + std::to_string(prm.tileSamples) + " is not in 3.." + std::to_string(n) +
                 " with samplesPerSide - 1 a multiple of tileSamples - 1");
    } else if (!powerOfTwoPlusOne(prm.tileSamples) || prm.tileSamples > n) {
        fail("tileSamples " + std::to_string(prm.tileSamples) + " is not 2^m + 1 in 3.." + std::to_string(n));
    }
    if (prm.levels < 1) fail("levels " + std::to_string(prm.levels) + " is below 1");
    if (prm.occluders && !(prm.occluderBlocks >= 1 && prm.occluderBlocks <= prm.tileSamples - 1))
        fail("occluderBlocks " + std::to_string(prm.occluderBlocks) + " is not in 1.." +
             std::to_string(prm.tileSamples - 1));
    if (!(prm.pixelError > 0.0 && std::isfinite(prm.pixelError)))
        fail("pixelError " + std::to_string(prm.pixelError) + " is not positive and finite");
    if (!(prm.fovyDegrees > 0.0 && prm.fovyDegrees < 180.0))
        fail("fovyDegrees " + std::to_string(prm.fovyDegrees) + " is not in (0, 180)");
    if (prm.viewportHeight < 1) fail("viewportHeight " + std::to_string(prm.viewportHeight) + " is below 1");
    if (!(prm.pixelsPerRadian >= 0.0 && std::isfinite(prm.pixelsPerRadian)))
        fail("pixelsPerRadian " + std::to_string(prm.pixelsPerRadian) + " is negative or not finite");

    Terrain t;
    const int per = prm.tileSamples - 1;
    t.tilesPerSide = (n - 1) / per;
    Builder<T> b{heights, n, per, spacing, 0.0, prm.pixelError, {}, prm.material, t, prm, origin, {}};
    b.pixelsPerRadian = prm.pixelsPerRadian > 0.0
                            ? prm.pixelsPerRadian
                            : prm.viewportHeight / (2.0 * std::tan(glm::radians(prm.fovyDegrees) / 2.0));
    if (!b.material) b.material = make<Material>(vec4(0.55f, 0.50f, 0.38f, 1.0f));
    for (int cells : terrainLevelCells(per, prm.levels)) b.grids.push_back(terrainTileGrid(per, cells));
    if (prm.occluders) {
        b.prepareParts();
        b.occluders.resize(size_t(t.tilesPerSide) * size_t(t.tilesPerSide));
    }
    b.buildTiles(t.tilesPerSide);
    if (prm.occluders) b.prepareSurface();
    ref_ptr<Group> top = prm.flat ? b.flatNode(t.tilesPerSide) : b.node(0, 0, t.tilesPerSide, -1, 0);
    if (prm.occluders && !prm.flat && t.tilesPerSide == 1) {
        // The tile's occluders are its siblings: one tile gets a parent to hold them.
        auto g = make<Group>();
        g->addChild(top);
        b.addOccluders(*g, 0, 0);
        top = g;
    }
    if (prm.originInVertices) {
        top->setName("terrain");
        t.root = top;
        return t;
    }
    // Vertices relative to the origin, in float; the origin itself in the root's double transform.
    auto root = make<Transform>();
    root->setTranslation(origin);
    root->setName("terrain");
    root->addChild(top);
    t.root = root;
    return t;
}

}  // namespace

Terrain buildTerrain(const std::vector<float>& heights, int samplesPerSide, double spacing, const dvec3& origin,
                     const TerrainParams& params) {
    return build(heights, samplesPerSide, spacing, origin, params);
}

Terrain buildTerrain(const std::vector<double>& heights, int samplesPerSide, double spacing, const dvec3& origin,
                     const TerrainParams& params) {
    return build(heights, samplesPerSide, spacing, origin, params);
}

}  // namespace sg
