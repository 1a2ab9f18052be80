// The factory scene (docs/scenes.md): its size, buildings, instanced machines, models with coarse levels (coloured
// from the detailed one), occluders, switches, terrain height function and determinism, and that it culls as an
// application uses it.
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "sg/build/LodGenerator.h"
#include "sg/cull/CullTraversal.h"
#include "sg/intersect/IntersectTraversal.h"
#include "sg/scene/Scene.h"
#include "testbed/Factory.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

using namespace sg;

namespace {
// The Instances under `n` (not entering their prototypes).
void instancesUnder(Node& n, std::vector<Instance*>& out) {
    if (n.kind() == NodeKind::Instance) {
        out.push_back(static_cast<Instance*>(&n));
        return;
    }
    for (size_t i = 0; i < n.numChildren(); ++i) instancesUnder(*n.child(i), out);
}
Mesh* levelMesh(const LOD& lod, size_t level) {
    EXPECT_EQ(lod.child(level)->kind(), NodeKind::Geometry);
    return static_cast<Geometry*>(lod.child(level))->mesh();
}
// Terrain tile t: an LOD of its levels.
LOD& tile(const scenes::Factory& f, size_t t) {
    EXPECT_EQ(f.terrain->child(t)->kind(), NodeKind::LOD);
    return static_cast<LOD&>(*f.terrain->child(t));
}
Box translated(const Box& b, const dvec3& t) { return Box{b.min + t, b.max + t}; }
bool inside(const Box& inner, const Box& outer) { return outer.contains(inner.min) && outer.contains(inner.max); }

const scenes::Factory& factory() {
    static const scenes::Factory f = scenes::buildFactory();
    return f;
}
}  // namespace

TEST(Factory, TriangleCountsAroundThePapersFigure) {
    const auto& f = factory();
    // The paper's site has 183,747 triangles, its instanced machines stored once: this one is within 5%.
    EXPECT_GE(f.storedTriangles, 174560u);
    EXPECT_LE(f.storedTriangles, 192934u);
    EXPECT_EQ(f.machineMesh->triangleCount(), 2886u);
    // Drawn at full detail, every machine placement counts: 68 of them.
    EXPECT_GE(f.drawnTriangles, f.storedTriangles + 67u * 2886u);
}

TEST(Factory, ElevenBuildingsAndFourWorkshopsOfSeventeenInstancedMachines) {
    const auto& f = factory();
    ASSERT_EQ(f.buildings.size(), 11u);
    std::multiset<std::string> kinds;
    for (const auto& b : f.buildings) kinds.insert(b.kind);
    EXPECT_EQ(kinds.count("workshop"), 4u);
    EXPECT_EQ(kinds.count("auxiliary"), 5u);
    EXPECT_EQ(kinds.count("technology"), 1u);
    EXPECT_EQ(kinds.count("office"), 1u);
    ASSERT_EQ(f.workshops.size(), 4u);
    EXPECT_EQ(f.machines, 68);
    for (const auto& w : f.workshops) {
        EXPECT_EQ(f.buildings[size_t(w.building)].kind, "workshop");
        std::vector<Instance*> inst;
        instancesUnder(*w.interior, inst);
        ASSERT_EQ(inst.size(), 17u);
        for (Instance* i : inst) EXPECT_EQ(i->prototype(), f.machine.get());
    }
    // The prototype's image is built once, and every placement stands in the workshop's box.
    Scene scene(f.root);
    scene.update();
    EXPECT_NE(scene.prototypeImage(f.machine.get()), nullptr);
    std::set<const Mesh*> machineMeshes;
    for (size_t k = 0; k < f.machine->numChildren(); ++k) machineMeshes.insert(levelMesh(*f.machine, k));
    EXPECT_EQ(machineMeshes.size(), 2u);
    for (const auto& w : f.workshops) {
        std::vector<Instance*> inst;
        instancesUnder(*w.interior, inst);
        const dvec3 origin = f.buildings[size_t(w.building)].place->matrix()[3];
        for (Instance* i : inst) {
            const dvec3 p = origin + dvec3(i->matrix()[3]);
            EXPECT_TRUE(f.buildings[size_t(w.building)].box.contains(p));
        }
    }
}

TEST(Factory, BuildingsAndMachinesHaveCoarseLevelsDownToAnOrderOfMagnitudeFewer) {
    const auto& f = factory();
    std::vector<const LOD*> lods{f.machine.get()};
    for (const auto& b : f.buildings) lods.push_back(b.lod.get());
    for (const LOD* lod : lods) {
        // The machine: its detailed and simple model; a building also a middle one, so that the circle round
        // the site does not draw every building at full detail until the simple one is a pixel off.
        ASSERT_EQ(lod->numChildren(), lod == f.machine.get() ? 2u : 3u);
        const size_t last = lod->numChildren() - 1;
        const uint32_t fine = levelMesh(*lod, 0)->triangleCount();
        EXPECT_LE(levelMesh(*lod, last)->triangleCount() * 10u, fine);
        for (size_t i = 1; i <= last; ++i) {
            const uint32_t coarse = levelMesh(*lod, i)->triangleCount();
            EXPECT_LT(coarse * 2u, levelMesh(*lod, i - 1)->triangleCount()) << "level " << i;
            EXPECT_GT(coarse, 0u);
            // Switched where the level's error projects to one pixel: coarser levels further away.
            EXPECT_GT(lod->error(i), lod->error(i - 1));
            EXPECT_NEAR(lod->range(i).min, lod->error(i) * kDefaultPixelsPerRadian, 1e-3 * lod->range(i).min);
            EXPECT_EQ(lod->range(i - 1).max, lod->range(i).min);
        }
        // A fade band at every switch.
        EXPECT_NEAR(lod->transition(), 0.1f * lod->range(1).min, 1e-3f * lod->range(1).min);
    }
}

TEST(Factory, OccludersStayInsideTheirBuildings) {
    const auto& f = factory();
    for (const auto& b : f.buildings) {
        const dvec3 t = b.place->matrix()[3];
        const Box& occ = b.occluder->box();
        // Inside both models (the simplified one may pull in its outline) and the building's box.
        for (size_t i = 0; i < b.lod->numChildren(); ++i)
            EXPECT_TRUE(inside(occ, translated(levelMesh(*b.lod, i)->box(), t))) << b.kind << " level " << i;
        EXPECT_TRUE(inside(occ, b.box)) << b.kind;
        EXPECT_LT(occ.max.z, b.box.max.z);
    }
}

TEST(Factory, SwitchesDefaultToTheOutsideAndFlipForAWorkshop) {
    auto f = scenes::buildFactory();
    EXPECT_TRUE(f.outside->isOn(0));
    for (const auto& w : f.workshops) EXPECT_FALSE(w.interior->isOn(0));
    const Box& b1 = f.buildings[size_t(f.workshops[1].building)].box;
    EXPECT_EQ(scenes::factoryWorkshopAt(f, b1.center()), 1);
    EXPECT_EQ(scenes::factoryWorkshopAt(f, dvec3(300, 300, 50)), -1);
    scenes::setFactoryEye(f, 1);
    EXPECT_FALSE(f.outside->isOn(0));
    for (size_t k = 0; k < 4; ++k) EXPECT_EQ(f.workshops[k].interior->isOn(0), k == 1);
    scenes::setFactoryEye(f, -1);
    EXPECT_TRUE(f.outside->isOn(0));
    for (const auto& w : f.workshops) EXPECT_FALSE(w.interior->isOn(0));
    EXPECT_THROW(scenes::setFactoryEye(f, 4), std::out_of_range);
}

TEST(Factory, TwoBuildsAreIdentical) {
    const auto& a = factory();
    const auto b = scenes::buildFactory();
    EXPECT_EQ(a.storedTriangles, b.storedTriangles);
    EXPECT_EQ(a.drawnTriangles, b.drawnTriangles);
    EXPECT_EQ(a.trees, b.trees);
    EXPECT_EQ(a.cars, b.cars);
    Scene sa(a.root), sb(b.root);
    sa.update();
    sb.update();
    ASSERT_EQ(sa.image().size(), sb.image().size());
    for (size_t i = 0; i < sa.image().size(); ++i) {
        const Box ba = sa.image().box(i), bb = sb.image().box(i);
        ASSERT_EQ(ba.min, bb.min) << i;
        ASSERT_EQ(ba.max, bb.max) << i;
    }
    // Another seed moves the hills and the trees.
    scenes::FactoryParams p;
    p.seed = 7;
    const auto c = scenes::buildFactory(p);
    EXPECT_NE(c.terrainHeight(300, 300), a.terrainHeight(300, 300));
}

TEST(Factory, TerrainHeightAgreesWithTheTerrainMesh) {
    const auto& f = factory();
    // Every vertex of every tile.
    size_t vertices = 0;
    double lo = kInf, hi = -kInf;
    for (size_t t = 0; t < f.terrain->numChildren(); ++t)
        for (size_t level = 0; level < tile(f, t).numChildren(); ++level)  // coarse levels stand on it too
            for (const vec3& p : levelMesh(tile(f, t), level)->positions()) {
                ASSERT_NEAR(f.terrainHeight(p.x, p.y), p.z, 1e-4) << p.x << " " << p.y;
                lo = std::min(lo, double(p.z));
                hi = std::max(hi, double(p.z));
                vertices += level == 0;
            }
    EXPECT_EQ(vertices, 8u * 8u * 32u * 32u);
    EXPECT_GT(hi - lo, 20.0);                          // hills, not a plane
    EXPECT_NEAR(f.terrainHeight(-25, 25), 0.0, 1e-9);  // the yard is flat
    // Between the vertices: vertical rays against the terrain alone.
    Scene terrain(f.terrain);
    terrain.update();
    IntersectTraversal it;
    QueryOptions q;
    q.traversalMask = ~0u;
    for (int k = 0; k < 200; ++k) {
        const double x = -390.0 + 780.0 * std::fmod(k * 0.618034, 1.0),
                     y = -390.0 + 780.0 * std::fmod(k * 0.414214, 1.0);
        Hit hit;
        ASSERT_TRUE(it.intersect(terrain, Ray{dvec3(x, y, 500.0), dvec3(0, 0, -1), 1000.0}, q, hit));
        EXPECT_NEAR(hit.point.z, f.terrainHeight(x, y), 1e-3) << x << " " << y;
    }
}

TEST(Factory, BadParamsThrowNamingTheValue) {
    auto expectThrow = [](scenes::FactoryParams p, const std::string& what) {
        try {
            scenes::buildFactory(p);
            ADD_FAILURE() << "no throw for " << what;
        } catch (const std::invalid_argument& e) {
            const std::string msg = e.what();
            EXPECT_EQ(msg.rfind("scenes::buildFactory(): ", 0), 0u) << msg;
            EXPECT_NE(msg.find(what), std::string::npos) << msg;
        }
    };
    scenes::FactoryParams p;
    p.siteSize = -800.0;
    expectThrow(p, "siteSize -800");
    p = {};
    p.siteSize = std::nan("");
    expectThrow(p, "siteSize nan");
    p = {};
    p.terrainCells = 100;
    expectThrow(p, "terrainCells 100");
    p = {};
    p.trees = -1;
    expectThrow(p, "trees -1");
    p = {};
    p.cars = 65;
    expectThrow(p, "cars 65");
    p = {};
    p.machinesPerWorkshop = -3;
    expectThrow(p, "machinesPerWorkshop -3");
    p = {};
    p.pixelError = 0.0;
    expectThrow(p, "pixelError 0");
    p = {};
    p.fadeFraction = std::nan("");
    expectThrow(p, "fadeFraction nan");
}

TEST(Factory, CullsFromOutsideAndFromInsideAWorkshop) {
    auto f = scenes::buildFactory();
    Scene scene(f.root);
    scene.update();
    std::set<const Mesh*> terrain, machine;
    for (size_t t = 0; t < f.terrain->numChildren(); ++t)
        for (size_t level = 0; level < tile(f, t).numChildren(); ++level) terrain.insert(levelMesh(tile(f, t), level));
    for (size_t k = 0; k < f.machine->numChildren(); ++k) machine.insert(levelMesh(*f.machine, k));
    auto count = [](const DrawList& l, const std::set<const Mesh*>& s) {
        size_t n = 0;
        for (const DrawItem& it : l.items) n += s.count(it.mesh);
        return n;
    };
    CullTraversal cull;
    DrawList list;
    CullStats st;
    CullSettings set;
    set.occlusion.mode = OcclusionMode::EveryFrame;
    set.occlusion.method = OcclusionMethod::Tree;
    // Outside: hills in view, the closed workshops hide their machines.
    for (int frame : {0, 30, 60, 90}) {
        cull.cull(scene, scenes::factoryOrbitCamera(frame), set, list, st);
        EXPECT_GT(count(list, terrain), 10u) << frame;
        EXPECT_EQ(count(list, machine), 0u) << frame;
        EXPECT_LT(st.triangles, f.drawnTriangles);
    }
    // Inside workshop 2 with the switches flipped: its machines, no hills.
    const Camera in = scenes::factoryWorkshopCamera(f, 2);
    ASSERT_EQ(scenes::factoryWorkshopAt(f, in.eye()), 2);
    scenes::setFactoryEye(f, 2);
    scene.update();
    cull.cull(scene, in, set, list, st);
    EXPECT_GE(count(list, machine), 10u);
    EXPECT_EQ(count(list, terrain), 0u);
    EXPECT_LT(st.triangles, 17u * 2886u + 5000u);
}

TEST(Factory, TerrainTilesHaveCoarseLevelsSwitchedWhereTheirErrorIsAPixel) {
    const auto& f = factory();
    ASSERT_EQ(f.terrain->numChildren(), 64u);
    int hilly = 0, flat = 0;
    for (size_t t = 0; t < 64; ++t) {
        const LOD& lod = tile(f, t);
        ASSERT_EQ(lod.numChildren(), 4u);
        const uint32_t fine = levelMesh(lod, 0)->triangleCount();
        EXPECT_EQ(fine, 31u * 31u * 2u);
        for (size_t i = 1; i < 4; ++i) {
            EXPECT_LT(levelMesh(lod, i)->triangleCount(), levelMesh(lod, i - 1)->triangleCount()) << t;
            // Same per-vertex arrays as the full grid.
            EXPECT_EQ(levelMesh(lod, i)->normals().size(), levelMesh(lod, i)->positions().size());
            EXPECT_EQ(levelMesh(lod, i)->uvs().size(), levelMesh(lod, i)->positions().size());
            EXPECT_EQ(levelMesh(lod, i)->colors().size(), levelMesh(lod, i)->positions().size());
        }
        EXPECT_LE(levelMesh(lod, 3)->triangleCount() * 10u, fine) << t;  // an order of magnitude
        // Level i from where its error projects to one pixel from the tile's nearest point: the centre's
        // distance less the tile's radius.
        const Box b = levelMesh(lod, 0)->box();
        const double radius = 0.5 * glm::length(b.max - b.min);
        EXPECT_EQ(lod.center(), b.center());
        EXPECT_EQ(lod.range(0).min, 0.0f);
        for (size_t i = 1; i < 4; ++i) {
            EXPECT_GE(lod.error(i), lod.error(i - 1));
            EXPECT_NEAR(lod.range(i).min, lod.error(i) * kDefaultPixelsPerRadian + radius, 1e-3 * lod.range(i).min);
            EXPECT_GE((lod.range(i).min - radius) / kDefaultPixelsPerRadian, lod.error(i) * (1.0 - 1e-6));
            EXPECT_EQ(lod.range(i - 1).max, lod.range(i).min);
        }
        EXPECT_EQ(lod.range(3).max, std::numeric_limits<float>::max());
        EXPECT_NEAR(lod.transition(), 0.1f * lod.range(0).max, 1e-3f * lod.range(0).max);
        hilly += lod.error(1) > 0.05f;
        flat += lod.error(3) == 0.0f;  // the yard: every level exact
    }
    EXPECT_GE(hilly, 40);
    EXPECT_GE(flat, 4);
}

TEST(Factory, TerrainLevelErrorsBoundTheirDistanceToTheFullGrid) {
    const auto& f = factory();
    IntersectTraversal it;
    QueryOptions q;
    q.traversalMask = ~0u;
    for (size_t t : {0u, 7u, 21u, 45u, 63u}) {  // hills, the stream (21, 45), the yard's edge
        const LOD& lod = tile(f, t);
        const Box b = levelMesh(lod, 0)->box();
        for (size_t level = 1; level < lod.numChildren(); ++level) {
            auto root = make<Group>();
            root->addChild(make<Geometry>(ref_ptr<Mesh>(levelMesh(lod, level)), make<Material>(vec4(1.0f))));
            Scene scene(root);
            scene.update();
            double worst = 0.0;
            for (int k = 0; k < 1500; ++k) {
                const double x = b.min.x + (b.max.x - b.min.x) * std::fmod(0.5 + k * 0.618034, 1.0),
                             y = b.min.y + (b.max.y - b.min.y) * std::fmod(0.5 + k * 0.7548777, 1.0);
                Hit hit;
                ASSERT_TRUE(it.intersect(scene, Ray{dvec3(x, y, 500.0), dvec3(0, 0, -1), 1000.0}, q, hit));
                worst = std::max(worst, std::abs(hit.point.z - f.terrainHeight(x, y)));
            }
            EXPECT_LE(worst, lod.error(level) + 1e-3) << t << " level " << level;
            // Not a loose bound either: samples come near it.
            EXPECT_GE(worst, 0.5 * lod.error(level)) << t << " level " << level;
        }
    }
}

TEST(Factory, TerrainTilesSwitchLevelAtTheirRanges) {
    const auto& f = factory();
    Scene scene(f.terrain);
    scene.update();
    const size_t t = 7;  // a corner tile in the hills
    const LOD& lod = tile(f, t);
    ASSERT_GT(lod.range(1).max, lod.range(1).min + lod.transition());
    CullTraversal cull;
    DrawList list;
    CullStats st;
    // Straight above the tile's centre, looking down: which of its levels is drawn.
    auto drawn = [&](double height) {
        Camera cam;
        cam.setViewport(640, 480);
        cam.setPerspective(60.0, 640.0 / 480.0, 1.0, 5000.0);
        const dvec3 c = lod.center();
        cam.setLookAt(c + dvec3(0, 0, height), c, dvec3(0, 1, 0));
        cull.cull(scene, cam, CullSettings{}, list, st);
        std::set<size_t> levels;
        for (const DrawItem& item : list.items)
            for (size_t i = 0; i < lod.numChildren(); ++i)
                if (item.mesh == levelMesh(lod, i)) levels.insert(i);
        return levels;
    };
    const double d = lod.range(1).min, w = lod.transition();
    EXPECT_EQ(drawn(d - w / 2 - 1.0), std::set<size_t>{0});
    EXPECT_EQ(drawn(d), (std::set<size_t>{0, 1}));  // fading across
    EXPECT_EQ(drawn(d + w / 2 + 1.0), std::set<size_t>{1});
}

TEST(Factory, NoCracksBetweenTerrainTilesAtDifferentLevels) {
    auto f = scenes::buildFactory();
    // East of x = 200 every tile at its coarsest level, west of it at its finest.
    for (size_t t = 0; t < f.terrain->numChildren(); ++t) {
        LOD& lod = tile(f, t);
        const bool coarse = lod.center().x > 200.0;
        const size_t shown = coarse ? lod.numChildren() - 1 : 0;
        lod.setTransition(0.0f);
        for (size_t i = 0; i < lod.numChildren(); ++i)
            lod.setRange(i, 0.0f, i == shown ? std::numeric_limits<float>::max() : 0.0f);
    }
    Scene scene(f.terrain);
    scene.update();
    // Looking across the border between tiles 5 and 6 of a row in the hills, from either side, down at 25
    // degrees: every ray must meet the ground (a crack would let one through, to the sky).
    IntersectTraversal it;
    int misses = 0, east = 0, west = 0;
    for (const double side : {-1.0, 1.0}) {
        const dvec3 eye(200.0 + 40.0 * side, 230.0, f.terrainHeight(200.0 + 40.0 * side, 230.0) + 20.0);
        const dvec3 fwd = glm::normalize(dvec3(-side * std::cos(0.44), 0.0, -std::sin(0.44)));
        const dvec3 right = glm::normalize(glm::cross(fwd, dvec3(0, 0, 1))), up = glm::cross(right, fwd);
        Camera cam;
        cam.setViewport(300, 200);
        cam.setPerspective(40.0, 1.5, 0.5, 3000.0);
        cam.setLookAt(eye, eye + fwd, dvec3(0, 0, 1));
        QueryOptions q;
        q.traversalMask = ~0u;
        q.lod = LodChoice::AsDrawn;
        q.camera = &cam;
        const double th = std::tan(20.0 * M_PI / 180.0);
        for (int py = 0; py < 200; ++py)
            for (int px = 0; px < 300; ++px) {
                const double sx = (2.0 * (px + 0.5) / 300 - 1.0) * th * 1.5, sy = (1.0 - 2.0 * (py + 0.5) / 200) * th;
                Hit hit;
                if (!it.intersect(scene, Ray{eye, glm::normalize(fwd + sx * right + sy * up), 3000.0}, q, hit)) {
                    ++misses;
                    continue;
                }
                (hit.point.x > 200.0 ? east : west) += 1;
            }
    }
    EXPECT_EQ(misses, 0);
    // Both levels are in view, each over a good share of it.
    EXPECT_GT(east, 2 * 300 * 200 / 5);
    EXPECT_GT(west, 2 * 300 * 200 / 5);
}

TEST(Factory, CoarseTerrainLevelsTakeTheirColoursFromTheFinest) {
    auto f = scenes::buildFactory();
    // Finest colours: red a checkerboard of the grid points, green rising along x.
    for (size_t t = 0; t < f.terrain->numChildren(); ++t) {
        Mesh& m = *levelMesh(tile(f, t), 0);
        std::vector<vec4> col;
        for (const vec3& p : m.positions()) {
            const long i = std::lround((p.x + 400.0) / 3.2258064516), j = std::lround((p.y + 400.0) / 3.2258064516);
            col.emplace_back(float((i + j) % 2), float((p.x + 400.0) / 800.0), 0.0f, 1.0f);
        }
        std::vector<uint32_t> idx(m.indexCount());
        for (size_t i = 0; i < idx.size(); ++i) idx[i] = m.index(i);
        m.set(m.positions(), m.normals(), std::move(idx), m.uvs(), std::move(col));
    }
    scenes::shareTerrainColors(f);
    for (size_t t = 0; t < f.terrain->numChildren(); ++t) {
        const LOD& lod = tile(f, t);
        const Box b = levelMesh(lod, 0)->box();
        for (size_t level = 1; level < lod.numChildren(); ++level) {
            const Mesh& m = *levelMesh(lod, level);
            ASSERT_EQ(m.colors().size(), m.positions().size());
            for (size_t v = 0; v < m.positions().size(); ++v) {
                const vec3 p = m.positions()[v];
                const vec4 c = m.colors()[v];
                // Green is linear in x: a mean over a window centred on the vertex keeps the vertex's value.
                EXPECT_NEAR(c.g, (p.x + 400.0) / 800.0, 1e-5);
                const bool border = p.x == b.min.x || p.x == b.max.x || p.y == b.min.y || p.y == b.max.y;
                const long i = std::lround((p.x + 400.0) / 3.2258064516), j = std::lround((p.y + 400.0) / 3.2258064516);
                if (border)
                    ASSERT_EQ(c.r, float((i + j) % 2)) << t << " level " << level;  // the neighbours' colour
                else
                    ASSERT_TRUE(c.r > 0.3f && c.r < 0.7f) << c.r;  // the checkerboard averaged out
            }
        }
    }
}

// A coarse terrain level's error counts the light it loses: uniform colours leave the geometric errors as
// they were; a checkerboard of light and shadow, which every coarse level averages out, makes each error at
// least half a coarse cell (2 fine cells of 3.2 m at the least, the colour 0.5 off).
TEST(Factory, ACoarseTerrainLevelsErrorCountsTheLightItLoses) {
    auto paint = [](scenes::Factory& f, bool checker) {
        std::vector<std::vector<float>> before;
        for (size_t t = 0; t < f.terrain->numChildren(); ++t) {
            const LOD& lod = tile(f, t);
            before.emplace_back();
            for (size_t level = 0; level < lod.numChildren(); ++level) before.back().push_back(lod.error(level));
            Mesh& m = *levelMesh(lod, 0);
            std::vector<vec4> col;
            for (const vec3& p : m.positions()) {
                const long i = std::lround((p.x + 400.0) / 3.2258064516), j = std::lround((p.y + 400.0) / 3.2258064516);
                col.emplace_back(checker ? float((i + j) % 2) : 0.5f, 0.5f, 0.5f, 1.0f);
            }
            std::vector<uint32_t> idx(m.indexCount());
            for (size_t i = 0; i < idx.size(); ++i) idx[i] = m.index(i);
            m.set(m.positions(), m.normals(), std::move(idx), m.uvs(), std::move(col));
        }
        scenes::shareTerrainColors(f);
        return before;
    };
    auto even = scenes::buildFactory();
    const auto geometric = paint(even, false);
    auto checker = scenes::buildFactory();
    paint(checker, true);
    for (size_t t = 0; t < even.terrain->numChildren(); ++t)
        for (size_t level = 1; level < tile(even, t).numChildren(); ++level) {
            EXPECT_EQ(tile(even, t).error(level), geometric[t][level]) << "tile " << t << " level " << level;
            EXPECT_GE(tile(checker, t).error(level), std::max(geometric[t][level], 0.5f * 2.0f * 3.2258f))
                << "tile " << t << " level " << level;
        }
}

TEST(Factory, CoarseBuildingLevelsTakeTheirColoursFromTheDetailedSurfaceFacingTheSameWay) {
    auto f = scenes::buildFactory();
    // Detailed colours that tell the way a face looks: a coarse outer wall must take its own side's.
    auto colorOf = [](const vec3& n) { return vec4(0.5f + 0.5f * n.x, 0.5f + 0.5f * n.y, 0.5f + 0.5f * n.z, 1.0f); };
    for (const auto& b : f.buildings) {
        Mesh& m = *levelMesh(*b.lod, 0);
        std::vector<vec4> col;
        for (const vec3& n : m.normals()) col.push_back(colorOf(n));
        std::vector<uint32_t> idx(m.indexCount());
        for (size_t i = 0; i < idx.size(); ++i) idx[i] = m.index(i);
        m.set(m.positions(), m.normals(), std::move(idx), m.uvs(), std::move(col));
    }
    scenes::shareBuildingColors(f);
    for (const auto& b : f.buildings) {
        const Box box = levelMesh(*b.lod, 0)->box();
        for (size_t level = 1; level < b.lod->numChildren(); ++level) {
            const Mesh& m = *levelMesh(*b.lod, level);
            ASSERT_EQ(m.colors().size(), m.positions().size());
            // The way each vertex's triangles face, when they all face the same way along x or y out of the
            // model's box (an outer wall); the simplifier may give a vertex triangles that face other ways.
            std::vector<vec3> facing(m.positions().size(), vec3(0.0f));
            std::vector<bool> mixed(m.positions().size(), false);
            for (uint32_t t = 0; t < m.triangleCount(); ++t) {
                const uint32_t v[3] = {m.index(3 * t), m.index(3 * t + 1), m.index(3 * t + 2)};
                const vec3 p0 = m.positions()[v[0]], p1 = m.positions()[v[1]], p2 = m.positions()[v[2]];
                const vec3 c = glm::cross(p1 - p0, p2 - p0), mid = (p0 + p1 + p2) / 3.0f;
                if (glm::length(c) == 0.0f) continue;
                const vec3 n = glm::normalize(c);
                const bool outer =
                    (n.x < -0.999f && mid.x < box.min.x + 0.4) || (n.x > 0.999f && mid.x > box.max.x - 0.4) ||
                    (n.y < -0.999f && mid.y < box.min.y + 0.4) || (n.y > 0.999f && mid.y > box.max.y - 0.4);
                const vec3 axis = outer ? glm::round(n) : vec3(9.0f);
                for (uint32_t k : v) {
                    mixed[k] = mixed[k] || (facing[k] != vec3(0.0f) && facing[k] != axis) || !outer;
                    facing[k] = axis;
                }
            }
            int walls = 0;
            for (size_t v = 0; v < m.positions().size(); ++v) {
                if (mixed[v] || facing[v] == vec3(0.0f)) continue;
                ++walls;
                const vec4 c = m.colors()[v], want = colorOf(facing[v]);
                for (int k = 0; k < 4; ++k) ASSERT_NEAR(c[k], want[k], 1e-4f) << b.kind << " level " << level;
            }
            EXPECT_GT(walls, 3) << b.kind << " level " << level;
        }
    }
}
TEST(Factory, CoarseBuildingLevelsAreShadedByTheirFacesNormals) {
    const auto& f = factory();
    for (const auto& b : f.buildings)
        for (size_t level = 1; level < b.lod->numChildren(); ++level) {
            const Mesh& m = *levelMesh(*b.lod, level);
            ASSERT_EQ(m.normals().size(), m.positions().size());
            ASSERT_EQ(m.uvs().size(), m.positions().size());
            // Every corner's normal is its face's (the simplifier's shared vertices kept some other face's): the sun
            // lights the walls that face it.
            for (uint32_t t = 0; t < m.triangleCount(); ++t) {
                const uint32_t v[3] = {m.index(3 * t), m.index(3 * t + 1), m.index(3 * t + 2)};
                const vec3 c =
                    glm::cross(m.positions()[v[1]] - m.positions()[v[0]], m.positions()[v[2]] - m.positions()[v[0]]);
                ASSERT_GT(glm::length(c), 0.0f) << b.kind << " level " << level;
                for (uint32_t k : v)
                    ASSERT_GT(glm::dot(glm::normalize(c), m.normals()[k]), 0.99f) << b.kind << " level " << level;
            }
            ASSERT_EQ(b.coarseColors.size(), b.lod->numChildren() - 1);
        }
}
