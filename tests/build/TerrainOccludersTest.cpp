// buildTerrain's occluders (TerrainParams::occluders): every box lies below every level's surface of its tile and
// inside the terrain's rectangle, on random terrains and awkward ones; the occlusion pass uses them only while the eye
// is over the terrain and well above the surface near it.
#include "nodes/Geometry.h"
#include "nodes/LOD.h"
#include "nodes/Occluder.h"
#include "nodes/Transform.h"
#include "sg/build/TerrainBuilder.h"
#include "sg/cull/OcclusionPass.h"
#include "sg/scene/Scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

using namespace sg;

namespace {

struct TileOccluders {
    const LOD* lod = nullptr;
    std::vector<const Occluder*> boxes;
};

// Each LOD below `n` with the occluders that follow it among its parent's children.
void collect(const Node& n, std::vector<TileOccluders>& out) {
    const LOD* last = nullptr;
    for (size_t k = 0; k < n.numChildren(); ++k) {
        const Node& c = *n.child(k);
        if (c.kind() == NodeKind::LOD) {
            last = static_cast<const LOD*>(&c);
            out.push_back({last, {}});
        } else if (c.kind() == NodeKind::Occluder) {
            const auto& o = static_cast<const Occluder&>(c);
            EXPECT_EQ(o.shownWith(), last);
            EXPECT_TRUE(o.generated());
            EXPECT_NE(o.belowSurface(), nullptr);
            if (last && !out.empty()) out.back().boxes.push_back(&o);
        } else {
            last = nullptr;
            collect(c, out);
        }
    }
}

// The lowest the level's surface (its float vertices, linear over each triangle) reaches at (x, y); NaN where no
// triangle holds the point.
double surfaceAt(const Mesh& m, double x, double y) {
    double best = std::numeric_limits<double>::quiet_NaN();
    const auto& p = m.positions();
    for (uint32_t t = 0; t < m.triangleCount(); ++t) {
        const dvec3 a(p[m.index(3 * t)]), b(p[m.index(3 * t + 1)]), c(p[m.index(3 * t + 2)]);
        const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
        if (area == 0.0) continue;
        const double w0 = ((b.x - x) * (c.y - y) - (b.y - y) * (c.x - x)) / area;
        const double w1 = ((c.x - x) * (a.y - y) - (c.y - y) * (a.x - x)) / area;
        const double w2 = 1.0 - w0 - w1;
        const double tol = -1e-9;
        if (w0 < tol || w1 < tol || w2 < tol) continue;
        const double z = w0 * a.z + w1 * b.z + w2 * c.z;
        if (!(z >= best)) best = z;
    }
    return best;
}

// The cells of `s` whose closed rectangles hold (x, y) (give or take 1e-6 of a cell), as [first, last] per axis.
struct CellRange {
    int i0, i1, j0, j1;
};
CellRange cellsAt(const OccluderSurface& s, double x, double y) {
    const double u = (x - s.min.x) / (s.max.x - s.min.x) * s.cellsX, v = (y - s.min.y) / (s.max.y - s.min.y) * s.cellsY;
    auto c = [](double w, int count) { return std::clamp(int(std::floor(w)), 0, count - 1); };
    return {c(u - 1e-6, s.cellsX), c(u + 1e-6, s.cellsX), c(v - 1e-6, s.cellsY), c(v + 1e-6, s.cellsY)};
}
double highestAt(const OccluderSurface& s, double x, double y) {
    const CellRange r = cellsAt(s, x, y);
    double h = std::numeric_limits<double>::infinity();
    for (int j = r.j0; j <= r.j1; ++j)
        for (int i = r.i0; i <= r.i1; ++i) h = std::min(h, s.highest[size_t(j) * size_t(s.cellsX) + size_t(i)]);
    return h;
}

// Every box below every level of its tile at `samples` random points, inside the rectangle; every level's surface
// there, and every vertex, below the surface description's highest over its cells. Returns the boxes checked.
size_t checkBelow(const Terrain& t, uint64_t seed, int samples = 24) {
    std::vector<TileOccluders> tiles;
    collect(*t.root, tiles);
    EXPECT_EQ(tiles.size(), size_t(t.tilesPerSide) * size_t(t.tilesPerSide));
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    size_t boxes = 0;
    for (const TileOccluders& to : tiles) {
        for (const Occluder* o : to.boxes) {
            const Box& b = o->box();
            const OccluderSurface& s = *o->belowSurface();
            EXPECT_GE(b.min.x, s.min.x);
            EXPECT_GE(b.min.y, s.min.y);
            EXPECT_LE(b.max.x, s.max.x);
            EXPECT_LE(b.max.y, s.max.y);
            ++boxes;
            for (int k = 0; k < samples; ++k) {
                // Corners and edges of the top face first, then anywhere in the box.
                dvec3 q = b.min + dvec3(u(rng), u(rng), u(rng)) * (b.max - b.min);
                if (k < 4) q = dvec3(k & 1 ? b.max.x : b.min.x, k & 2 ? b.max.y : b.min.y, b.max.z);
                for (size_t l = 0; l < to.lod->numChildren(); ++l) {
                    const Mesh& m = *static_cast<const Geometry&>(*to.lod->child(l)).mesh();
                    const double h = surfaceAt(m, q.x, q.y);
                    if (!(q.z < h)) {  // NaN: no triangle of the level over the point
                        ADD_FAILURE() << "level " << l << " at " << q.x << ", " << q.y << ", " << q.z << ": surface "
                                      << h;
                        return boxes;
                    }
                    if (!(h < highestAt(s, q.x, q.y))) {
                        ADD_FAILURE() << "level " << l << " at " << q.x << ", " << q.y << ": surface " << h
                                      << " above the highest " << highestAt(s, q.x, q.y);
                        return boxes;
                    }
                }
            }
        }
        if (to.boxes.empty()) continue;
        // Every vertex below the highest of every cell whose closed rectangle holds it.
        const OccluderSurface& s = *to.boxes.front()->belowSurface();
        for (size_t l = 0; l < to.lod->numChildren(); ++l)
            for (const vec3& p : static_cast<const Geometry&>(*to.lod->child(l)).mesh()->positions())
                EXPECT_LT(double(p.z), highestAt(s, p.x, p.y));
    }
    return boxes;
}

std::vector<double> randomHeights(int n, std::mt19937_64& rng, double relief) {
    std::uniform_real_distribution<double> u(-relief, relief);
    std::vector<double> h(size_t(n) * size_t(n));
    // A smooth part and noise: hills and spikes.
    const double f = u(rng) / relief * 0.3 + 0.5;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            h[size_t(j) * size_t(n) + size_t(i)] = relief * std::sin(f * i) * std::cos(0.7 * f * j) + 0.3 * u(rng);
    return h;
}

}  // namespace

TEST(TerrainOccluders, BoxesLieBelowEveryLevelOfRandomTerrains) {
    std::mt19937_64 rng(29);
    size_t total = 0;
    for (int trial = 0; trial < 12; ++trial) {
        const int n = (trial % 3 == 0) ? 17 : (trial % 3 == 1 ? 33 : 65);
        TerrainParams p;
        p.occluders = true;
        p.tileSamples = trial % 2 ? 9 : 17;
        p.levels = 2 + trial % 4;
        p.occluderBlocks = 1 + trial % 4;
        p.pixelError = 0.5 + trial;
        p.originInVertices = trial % 5 == 3;
        const dvec3 origin(1000.0 * trial - 3000.0, -250.0 * trial, 10.0 * trial);
        const Terrain t = buildTerrain(randomHeights(n, rng, 5.0 + 40.0 * trial), n, 1.0 + 0.7 * trial, origin, p);
        total += checkBelow(t, uint64_t(trial));
    }
    EXPECT_GT(total, 100u);
}

TEST(TerrainOccluders, FlatTilesAndOneTileAndExtremeHeights) {
    std::mt19937_64 rng(7);
    TerrainParams p;
    p.occluders = true;
    p.tileSamples = 9;
    p.occluderBlocks = 4;
    // One tile: its occluders need a parent, so the tile is put under a Group.
    {
        const Terrain t = buildTerrain(randomHeights(9, rng, 3.0), 9, 1.0, dvec3(0.0), p);
        EXPECT_EQ(checkBelow(t, 1), 16u);
        EXPECT_EQ(t.quad.size(), 1u);
        EXPECT_TRUE(t.quad[0].tile);
    }
    // Flat: the boxes stop just under the plane.
    {
        const Terrain t = buildTerrain(std::vector<double>(33 * 33, 12.5), 33, 2.0, dvec3(5.0), p);
        EXPECT_EQ(checkBelow(t, 2), 16u * 16u);
    }
    // Params::flat (tiles as the root's children) with 3 x 3 tiles.
    {
        TerrainParams f = p;
        f.flat = true;
        const Terrain t = buildTerrain(randomHeights(25, rng, 30.0), 25, 1.5, dvec3(0.0), f);
        EXPECT_EQ(checkBelow(t, 3), 9u * 16u);
    }
    // Extreme heights: far from zero, where a float's step is large, a cliff of 1e6, and 1e30.
    {
        std::vector<double> h = randomHeights(17, rng, 1.0);
        for (double& v : h) v += 1.0e7;
        h[40] = 1.0e7 + 1.0e6;
        h[41] = 1.0e7 - 1.0e6;
        EXPECT_GT(checkBelow(buildTerrain(h, 17, 1.0, dvec3(0.0), p), 4), 0u);
        std::vector<float> huge(17 * 17, 1.0e30f);
        huge[100] = -1.0e30f;
        checkBelow(buildTerrain(huge, 17, 1.0e-3, dvec3(0.0), p), 5);
    }
    // Blocks out of range.
    p.occluderBlocks = 9;
    EXPECT_THROW(buildTerrain(std::vector<double>(17 * 17, 0.0), 17, 1.0, dvec3(0.0), p), std::invalid_argument);
    p.occluderBlocks = 0;
    EXPECT_THROW(buildTerrain(std::vector<double>(17 * 17, 0.0), 17, 1.0, dvec3(0.0), p), std::invalid_argument);
}

namespace {

// A terrain 640 m square, flat at 0 but for a 60 m hill at its centre, with occluders.
Terrain hillTerrain(const dvec3& origin = dvec3(0.0)) {
    const int n = 65;
    std::vector<double> h(size_t(n) * size_t(n));
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double r = std::hypot(i - 32.0, j - 32.0);
            h[size_t(j) * size_t(n) + size_t(i)] = r < 12.0 ? 60.0 * (1.0 - r / 12.0) : 0.0;
        }
    TerrainParams p;
    p.occluders = true;
    p.tileSamples = 9;
    return buildTerrain(h, n, 10.0, origin, p);
}

Camera lookFrom(const dvec3& eye, const dvec3& at, double zNear = 1.0) {
    Camera c;
    c.setViewport(320, 240);
    c.setPerspective(60.0, 320.0 / 240.0, zNear, 1.0e5);
    c.setLookAt(eye, at, dvec3(0, 0, 1));
    return c;
}

uint64_t candidates(const Scene& s, const Camera& cam, const CullSettings& set) {
    OcclusionPass pass;
    CullStats st;
    pass.build(s.image(), cam, set, st);
    return st.occluderCandidates;
}

CullSettings everyFrame() {
    CullSettings set;
    set.occlusion.mode = OcclusionMode::EveryFrame;
    set.occlusion.method = OcclusionMethod::Tree;
    return set;
}

}  // namespace

TEST(TerrainOccluders, UsedOnlyWithTheEyeOverTheTerrainAndAboveTheSurfaceNearIt) {
    const dvec3 origin(-320.0, -320.0, 0.0);
    const Terrain t = hillTerrain(origin);
    Scene s(t.root);
    s.update();
    const CullSettings set = everyFrame();
    // Over the flat part, 2 m up, looking at the hill: used.
    EXPECT_GT(candidates(s, lookFrom(dvec3(-250.0, -250.0, 2.0), dvec3(0.0, 0.0, 20.0)), set), 0u);
    // Outside the rectangle (10 m beyond its edge), the same height and view: none.
    EXPECT_EQ(candidates(s, lookFrom(dvec3(-330.0, -250.0, 2.0), dvec3(0.0, 0.0, 20.0)), set), 0u);
    // Above the rectangle's edge but at the surface's height within the near plane's reach: none.
    EXPECT_EQ(candidates(s, lookFrom(dvec3(-250.0, -250.0, 0.5), dvec3(0.0, 0.0, 20.0)), set), 0u);
    // A near plane of 5 m reaches farther than the eye's 2 m height: none.
    EXPECT_EQ(candidates(s, lookFrom(dvec3(-250.0, -250.0, 2.0), dvec3(0.0, 0.0, 20.0), 5.0), set), 0u);
    // On the hill's slope, 2 m above the ground beneath, but the tile it stands over peaks higher nearby: none.
    EXPECT_EQ(candidates(s, lookFrom(dvec3(40.0, 0.0, 42.0), dvec3(300.0, 0.0, 0.0)), set), 0u);
    // Above the hill's top: used again.
    EXPECT_GT(candidates(s, lookFrom(dvec3(40.0, 0.0, 70.0), dvec3(300.0, 0.0, 0.0)), set), 0u);
    // Small-feature culling may drop a tile, the budget leave one out, hysteresis keep a level by last frame: none.
    const Camera good = lookFrom(dvec3(-250.0, -250.0, 2.0), dvec3(0.0, 0.0, 20.0));
    CullSettings small = set;
    small.smallFeaturePixels = 1.0;
    EXPECT_EQ(candidates(s, good, small), 0u);
    CullSettings hyst = set;
    hyst.lodHysteresis = 0.1;
    EXPECT_EQ(candidates(s, good, hyst), 0u);
}

TEST(TerrainOccluders, AFrameWithRotationAndScaleTakesTheEyeIntoIt) {
    // The terrain under a Transform that turns it a quarter about z and scales it by 2: the eye is taken into the
    // occluders' frame, and the reach scaled with it.
    const Terrain t = hillTerrain();
    auto x = make<Transform>();
    x->setMatrix(glm::scale(glm::rotate(dmat4(1.0), glm::radians(90.0), dvec3(0, 0, 1)), dvec3(2.0)));
    x->addChild(t.root);
    Scene s(x);
    s.update();
    const CullSettings set = everyFrame();
    // The terrain covers x in [-1280, 0], y in [0, 1280] in the world (local (0, 0) to (640, 640), turned).
    EXPECT_GT(candidates(s, lookFrom(dvec3(-100.0, 100.0, 4.0), dvec3(-640.0, 640.0, 40.0)), set), 0u);
    EXPECT_EQ(candidates(s, lookFrom(dvec3(100.0, 100.0, 4.0), dvec3(-640.0, 640.0, 40.0)), set), 0u);
    // 1 m up in the world is half a metre in the frame, within the near plane's reach there.
    EXPECT_EQ(candidates(s, lookFrom(dvec3(-100.0, 100.0, 1.0), dvec3(-640.0, 640.0, 40.0)), set), 0u);
}

TEST(TerrainOccluders, TheSurfaceConditionAloneMakesAnOccluderConditional) {
    // An occluder with no LOD beside it, only the surface: the image marks it conditional, so the pass checks it.
    auto s = std::make_shared<OccluderSurface>();
    s->min = dvec2(-100.0), s->max = dvec2(100.0);
    s->cellsX = s->cellsY = 1;
    s->highest = {1.0};
    auto o = make<Occluder>();
    o->setBox(Box{dvec3(-50.0, 40.0, -20.0), dvec3(50.0, 60.0, 0.0)});
    o->setBelowSurface(s);
    auto root = make<Group>();
    root->addChild(o);
    Scene sc(root);
    sc.update();
    EXPECT_EQ(candidates(sc, lookFrom(dvec3(0.0, 0.0, 10.0), dvec3(0.0, 50.0, -10.0)), everyFrame()), 1u);
    EXPECT_EQ(candidates(sc, lookFrom(dvec3(0.0, 0.0, 1.5), dvec3(0.0, 50.0, -10.0)), everyFrame()), 0u);
}

TEST(TerrainOccluders, ABadSurfaceIsRefusedNamingTheFunction) {
    auto o = make<Occluder>();
    auto message = [&](OccluderSurface s) {
        try {
            o->setBelowSurface(std::make_shared<OccluderSurface>(s));
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    OccluderSurface good;
    good.min = dvec2(0.0), good.max = dvec2(10.0);
    good.cellsX = 2, good.cellsY = 1;
    good.highest = {1.0, 2.0};
    EXPECT_EQ(message(good), "");
    OccluderSurface s = good;
    s.cellsY = 0;
    EXPECT_EQ(message(s).rfind("Occluder::setBelowSurface(): ", 0), 0u) << message(s);
    s = good;
    s.highest.pop_back();
    EXPECT_NE(message(s).find("1 heights for 2 x 1 cells"), std::string::npos) << message(s);
    s = good;
    s.highest[1] = std::nan("");
    EXPECT_NE(message(s).find("NaN"), std::string::npos) << message(s);
    s = good;
    s.max.y = 0.0;
    EXPECT_NE(message(s).find("empty or not finite"), std::string::npos) << message(s);
    o->setBelowSurface(nullptr);
    EXPECT_EQ(o->belowSurface(), nullptr);
}
