// sg::buildTerrain: input validation, the quadtree's bounds (tight prisms holding every sample), the exact
// level error against a brute-force twin, and no cracks between tiles at any mix of levels.
#include "nodes/Geometry.h"
#include "sg/build/TerrainBuilder.h"
#include "sg/intersect/IntersectTraversal.h"
#include "sg/scene/Scene.h"
#include "testbed/Terrain.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

using namespace sg;

namespace {

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

// The brute-force twin of terrainLevelError: every grid point of every triangle's box, and the full surface
// sampled finely along every edge.
double naiveLevelError(const TerrainTileGrid& g, const std::function<double(int, int)>& h) {
    auto surface = [&](double x, double y) {
        const int i = std::min(int(x), g.per - 1), j = std::min(int(y), g.per - 1);
        const double u = x - i, v = y - j;
        return u >= v ? h(i, j) + u * (h(i + 1, j) - h(i, j)) + v * (h(i + 1, j + 1) - h(i + 1, j))
                      : h(i, j) + v * (h(i, j + 1) - h(i, j)) + u * (h(i + 1, j + 1) - h(i, j + 1));
    };
    double err = 0.0;
    for (size_t t = 0; t < g.indices.size(); t += 3) {
        const glm::ivec2 c[3] = {g.points[g.indices[t]], g.points[g.indices[t + 1]], g.points[g.indices[t + 2]]};
        const double area = double((c[1].x - c[0].x) * (c[2].y - c[0].y) - (c[1].y - c[0].y) * (c[2].x - c[0].x));
        EXPECT_GT(area, 0.0) << "triangle " << t / 3 << " is not counter-clockwise from +Z";
        for (int s = 0; s <= 200; ++s) {  // inside, on a fine lattice of barycentrics, and along the edges
            for (int r = 0; r + s <= 200; r += (s % 20 == 0 ? 1 : 10)) {
                const double a = s / 200.0, b = r / 200.0, w = 1.0 - a - b;
                const double x = w * c[0].x + a * c[1].x + b * c[2].x, y = w * c[0].y + a * c[1].y + b * c[2].y;
                const double plane = w * h(c[0].x, c[0].y) + a * h(c[1].x, c[1].y) + b * h(c[2].x, c[2].y);
                err = std::max(err, std::abs(surface(x, y) - plane));
            }
        }
    }
    return err;
}

}  // namespace

TEST(TerrainBuilder, RejectsBadInputNamingIt) {
    const std::vector<float> h(17 * 17, 0.0f);
    auto build = [&](const std::vector<float>& hs, int n, double spacing, TerrainParams p = {}) {
        return errorOf([&] { buildTerrain(hs, n, spacing, dvec3(0.0), p); });
    };
    EXPECT_NE(build(h, 16, 1.0).find("samplesPerSide 16 is not 2^k + 1"), std::string::npos);
    EXPECT_NE(build(std::vector<float>(18 * 18), 18, 1.0).find("samplesPerSide 18"), std::string::npos);
    EXPECT_NE(build(h, 33, 1.0).find("289 heights for 33 x 33"), std::string::npos);
    std::vector<float> nan = h;
    nan[5 * 17 + 3] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_NE(build(nan, 17, 1.0).find("height 88 (i 3, j 5) is not finite"), std::string::npos);
    nan[5 * 17 + 3] = std::numeric_limits<float>::infinity();
    EXPECT_NE(build(nan, 17, 1.0).find("is not finite"), std::string::npos);
    EXPECT_NE(build(h, 17, 0.0).find("spacing 0"), std::string::npos);
    EXPECT_NE(build(h, 17, -2.0).find("spacing -2"), std::string::npos);
    EXPECT_NE(build(h, 17, std::nan("")).find("spacing"), std::string::npos);
    TerrainParams p;
    p.tileSamples = 20;
    EXPECT_NE(build(h, 17, 1.0, p).find("tileSamples 20"), std::string::npos);
    p.tileSamples = 33;
    EXPECT_NE(build(h, 17, 1.0, p).find("tileSamples 33 is not 2^m + 1 in 3..17"), std::string::npos);
    p = {};
    p.tileSamples = 9;
    p.pixelError = 0.0;
    EXPECT_NE(build(h, 17, 1.0, p).find("pixelError"), std::string::npos);
    p.pixelError = 1.0;
    p.levels = 0;
    EXPECT_NE(build(h, 17, 1.0, p).find("levels 0"), std::string::npos);
    p.levels = 3;
    p.fovyDegrees = 180.0;
    EXPECT_NE(build(h, 17, 1.0, p).find("fovyDegrees"), std::string::npos);
    EXPECT_EQ(build(h, 17, 1.0,
                    [] {
                        TerrainParams q;
                        q.tileSamples = 9;
                        return q;
                    }()),
              "");
    EXPECT_NE(errorOf([&] {
                  buildTerrain(h, 17, 1.0, dvec3(std::nan(""), 0, 0), [] {
                      TerrainParams q;
                      q.tileSamples = 9;
                      return q;
                  }());
              }).find("origin"),
              std::string::npos);
    EXPECT_THROW(terrainTileGrid(8, 1), std::invalid_argument);
    EXPECT_THROW(scenes::terrainHeights(100, 1, 10.0), std::invalid_argument);
    for (auto& msg : {build(h, 16, 1.0), build(h, 17, 0.0)}) EXPECT_EQ(msg.rfind("sg::buildTerrain(): ", 0), 0u) << msg;
}

TEST(TerrainBuilder, QuadtreeAndLevels) {
    const scenes::TerrainScene t = scenes::buildTerrainScene(129, 7, [] {
        scenes::TerrainSceneParams p;
        p.terrain.tileSamples = 17;
        return p;
    }());
    const Terrain& tr = t.terrain;
    EXPECT_EQ(tr.tilesPerSide, 8);
    EXPECT_EQ(tr.quad.size(), 1u + 4u + 16u + 64u);
    int tiles = 0;
    for (size_t q = 0; q < tr.quad.size(); ++q) {
        const Terrain::QuadNode& n = tr.quad[q];
        EXPECT_EQ(n.parent < 0, q == 0);
        if (n.parent >= 0) {
            EXPECT_LT(n.parent, int(q));  // pre-order
        }
        EXPECT_EQ(n.tile, n.depth == 3);
        if (!n.tile) {
            EXPECT_EQ(n.node->numChildren(), 4u);
            continue;
        }
        ++tiles;
        // 16 cells a side: levels of 16, 8, 4 and 2 cells, the finest first, ranges in order.
        const auto& lod = static_cast<const LOD&>(*n.node);
        ASSERT_EQ(lod.numChildren(), 4u);
        EXPECT_EQ(static_cast<const Geometry&>(*lod.child(0)).mesh()->triangleCount(), 16u * 16u * 2u);
        for (size_t l = 1; l < lod.numChildren(); ++l) {
            EXPECT_EQ(lod.range(l).min, lod.range(l - 1).max);
            EXPECT_GE(lod.error(l), lod.error(l - 1));
            EXPECT_LT(static_cast<const Geometry&>(*lod.child(l)).mesh()->triangleCount(),
                      static_cast<const Geometry&>(*lod.child(l - 1)).mesh()->triangleCount());
        }
    }
    EXPECT_EQ(tiles, 64);
    EXPECT_EQ(tr.finestTriangles, 64u * 512u);
}

// A level's error is exact: the fast row-interval scan finds what the brute-force twin finds, on rough fields.
TEST(TerrainBuilder, LevelErrorMatchesBruteForce) {
    const std::vector<float> h = scenes::terrainHeights(33, 3, 10.0, 0.3, 200.0);
    auto height = [&](int i, int j) { return double(h[size_t(j) * 33 + size_t(i)]); };
    for (int cells : terrainLevelCells(32, 5)) {
        const TerrainTileGrid g = terrainTileGrid(32, cells);
        const double fast = terrainLevelError(g, height);
        if (cells == 32) {
            EXPECT_EQ(fast, 0.0);
            continue;
        }
        const double slow = naiveLevelError(g, height);
        // The twin samples a lattice: it can only find less, and not much less.
        EXPECT_GE(fast, slow - 1e-9) << cells;
        EXPECT_LE(fast, slow * 1.05 + 1e-9) << cells;
    }
}

// Quadtree bounds: every node's box holds every sample below it, and is the prism (x, y of its tiles, z from
// their lowest to their highest sample): no looser.
TEST(TerrainBuilder, BoundsAreTheTilesPrisms) {
    scenes::TerrainSceneParams prm;
    prm.terrain.tileSamples = 9;
    const scenes::TerrainScene t = scenes::buildTerrainScene(65, 11, prm);
    Scene scene(t.terrain.root);
    scene.update();
    const FlatImage& img = scene.image();
    // Pre-order: the image's entries are the Transform, then the quadtree's nodes each followed by its subtree.
    const int n = t.samplesPerSide, per = 8;
    std::vector<uint32_t> entry;
    for (uint32_t i = 0; i < img.size(); ++i)
        if (img.kind[i] == NodeKind::Group || img.kind[i] == NodeKind::LOD) entry.push_back(i);
    ASSERT_EQ(entry.size(), t.terrain.quad.size());
    // Each quadtree node's tile range, from its place in the tree.
    struct Span {
        int i0, j0, size;
    };
    std::vector<Span> span(t.terrain.quad.size());
    span[0] = {0, 0, t.terrain.tilesPerSide};
    std::vector<int> seen(t.terrain.quad.size(), 0);
    for (size_t q = 1; q < span.size(); ++q) {
        const int p = t.terrain.quad[q].parent, k = seen[size_t(p)]++, s = span[size_t(p)].size / 2;
        span[q] = {span[size_t(p)].i0 + (k & 1) * s, span[size_t(p)].j0 + (k >> 1) * s, s};
    }
    for (size_t q = 0; q < span.size(); ++q) {
        const Span& s = span[q];
        double lo = 1e300, hi = -1e300;
        for (int j = s.j0 * per; j <= (s.j0 + s.size) * per; ++j)
            for (int i = s.i0 * per; i <= (s.i0 + s.size) * per; ++i) {
                lo = std::min(lo, double(t.heights[size_t(j) * size_t(n) + size_t(i)]));
                hi = std::max(hi, double(t.heights[size_t(j) * size_t(n) + size_t(i)]));
            }
        const Box prism{t.origin + dvec3(s.i0 * per * t.spacing, s.j0 * per * t.spacing, lo),
                        t.origin + dvec3((s.i0 + s.size) * per * t.spacing, (s.j0 + s.size) * per * t.spacing, hi)};
        const Box b = img.box(entry[q]);
        const double tol = 1e-3;  // float rounding of the stored bound, outward only
        for (int a = 0; a < 3; ++a) {
            EXPECT_LE(b.min[a], prism.min[a]) << q;
            EXPECT_GE(b.max[a], prism.max[a]) << q;
            EXPECT_GE(b.min[a], prism.min[a] - tol) << q;
            EXPECT_LE(b.max[a], prism.max[a] + tol) << q;
        }
        // The sphere: the box's half diagonal (the paper's radius), around the box's centre.
        EXPECT_NEAR(double(img.r[entry[q]]), 0.5 * glm::length(prism.max - prism.min), 1e-2) << q;
    }
}

// Tiles at every mix of levels meet without cracks: vertical rays down through a fine lattice that avoids no
// tile border all hit, with alternate tiles forced to their finest and their coarsest levels.
TEST(TerrainBuilder, NoCracksBetweenLevels) {
    scenes::TerrainSceneParams prm;
    prm.terrain.tileSamples = 17;
    prm.roughness = 0.3;
    prm.reliefMetres = 300.0;
    const scenes::TerrainScene t = scenes::buildTerrainScene(65, 5, prm);
    int k = 0;
    for (const Terrain::QuadNode& q : t.terrain.quad) {
        if (!q.tile) continue;
        auto& lod = static_cast<LOD&>(*q.node);
        const size_t shown = (k++ % 3 == 0) ? 0 : (k % 3 == 1 ? lod.numChildren() - 1 : 1);
        for (size_t l = 0; l < lod.numChildren(); ++l)
            lod.setRange(l, 0.0f, l == shown ? std::numeric_limits<float>::max() : 0.0f);
    }
    Scene scene(t.terrain.root);
    scene.update();
    IntersectTraversal it;
    QueryOptions qo;
    qo.traversalMask = ~0u;
    qo.lod = LodChoice::AsDrawn;
    const double side = 64 * t.spacing;
    int misses = 0, rays = 0;
    // 1/7 of a cell apart, and exactly on the tile borders and the sample lines.
    for (int b = 0; b <= 64 * 7; ++b)
        for (int a = 0; a <= 64 * 7; a += (b % 7 == 0 ? 1 : 7)) {
            const dvec3 o = t.origin + dvec3(a * side / (64 * 7), b * side / (64 * 7), 5000.0);
            Hit hit;
            ++rays;
            if (!it.intersect(scene, Ray{o, dvec3(0, 0, -1), 1e5}, qo, hit)) ++misses;
        }
    EXPECT_EQ(misses, 0) << "of " << rays << " rays";
    EXPECT_GT(rays, 20000);
}

// The options for a terrain that is one part of a larger scene: the tiles flat under one Group (any tile
// count), vertices in the scene's frame, per-vertex texture coordinates and colours, a given pixels per radian,
// and heights in double.
TEST(TerrainBuilder, FlatTilesInTheOriginsFrameWithVertexAttributes) {
    const int n = 3 * 6 + 1;  // three tiles of 6 cells a side: neither is a power of two
    std::vector<double> h(size_t(n) * size_t(n));
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) h[size_t(j * n + i)] = 0.1 + 3.0 * std::sin(0.7 * i) * std::cos(0.45 * j);
    const dvec3 origin(-90.25, 40.5, 2.0);
    const double spacing = 2.5;
    TerrainParams p;
    p.tileSamples = 7;
    p.levels = 3;
    p.flat = true;
    p.originInVertices = true;
    p.pixelsPerRadian = 1000.0;
    p.uv = [](const dvec3& q) { return vec2(float(q.x), float(q.y)) / 4.0f; };
    p.color = [](const dvec3& q) { return vec4(float(q.z), 0.5f, float(q.x), 1.0f); };
    const Terrain t = buildTerrain(h, n, spacing, origin, p);
    ASSERT_EQ(t.root->kind(), NodeKind::Group);  // no Transform: the origin is in the vertices
    ASSERT_EQ(t.root->numChildren(), 9u);
    ASSERT_EQ(t.quad.size(), 10u);
    EXPECT_EQ(t.quad[0].node.get(), t.root.get());
    EXPECT_EQ(t.tilesPerSide, 3);
    for (int tj = 0; tj < 3; ++tj)
        for (int ti = 0; ti < 3; ++ti) {
            const size_t k = size_t(tj * 3 + ti);
            EXPECT_EQ(t.quad[k + 1].node.get(), t.root->child(k));
            EXPECT_TRUE(t.quad[k + 1].tile);
            EXPECT_EQ(t.quad[k + 1].parent, 0);
            ASSERT_EQ(t.root->child(k)->kind(), NodeKind::LOD);
            const auto& lod = static_cast<const LOD&>(*t.root->child(k));
            ASSERT_EQ(lod.numChildren(), 3u);  // 6, then 3 and 2 cells a side
            for (size_t l = 0; l < lod.numChildren(); ++l) {
                const Mesh& m = *static_cast<const Geometry&>(*lod.child(l)).mesh();
                ASSERT_EQ(m.uvs().size(), m.positions().size());
                ASSERT_EQ(m.colors().size(), m.positions().size());
                for (size_t v = 0; v < m.positions().size(); ++v) {
                    const vec3 q = m.positions()[v];
                    const int i = int(std::lround((q.x - origin.x) / spacing)),
                              j = int(std::lround((q.y - origin.y) / spacing));
                    ASSERT_GE(i, ti * 6);
                    ASSERT_LE(i, ti * 6 + 6);
                    ASSERT_GE(j, tj * 6);
                    ASSERT_LE(j, tj * 6 + 6);
                    const dvec3 at = origin + dvec3(i * spacing, j * spacing, h[size_t(j * n + i)]);
                    EXPECT_EQ(q, vec3(at)) << k << " " << l << " " << v;  // rounded once, from double
                    EXPECT_EQ(m.uvs()[v], p.uv(at));
                    EXPECT_EQ(m.colors()[v], p.color(at));
                }
            }
            // Level 1 from where its error projects to a pixel at 1000 pixels per radian, plus the radius.
            const Box box = static_cast<const Geometry&>(*lod.child(0)).mesh()->box();
            const double d = lod.error(1) * 1000.0 + 0.5 * glm::length(box.max - box.min);
            EXPECT_NEAR(lod.range(1).min, d, 1e-5 * d);  // lod.error is the error rounded to float
        }
    // The default layout of the same field keeps the quadtree's rule: samples 2^k + 1.
    TerrainParams q = p;
    q.flat = false;
    EXPECT_NE(errorOf([&] { buildTerrain(h, n, spacing, origin, q); }).find("samplesPerSide 19 is not 2^k + 1"),
              std::string::npos);
    q = p;
    q.tileSamples = 8;
    EXPECT_NE(errorOf([&] {
                  buildTerrain(h, n, spacing, origin, q);
              }).find("tileSamples 8 is not in 3..19 with samplesPerSide - 1 a multiple of tileSamples - 1"),
              std::string::npos);
    q = p;
    q.pixelsPerRadian = -1.0;
    EXPECT_NE(errorOf([&] { buildTerrain(h, n, spacing, origin, q); }).find("pixelsPerRadian -1"), std::string::npos);
}
