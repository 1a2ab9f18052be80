// The factory scene (docs/scenes.md): its size, buildings, instanced machines, two-level models, occluders,
// switches, terrain height function and determinism, and that it culls as an application uses it.
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "sg/cull/CullTraversal.h"
#include "sg/intersect/IntersectTraversal.h"
#include "sg/lod/LodGenerator.h"
#include "sg/scene/Scene.h"
#include "testbed/Factory.h"

#include <gtest/gtest.h>

#include <cmath>
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

TEST(Factory, BuildingsAndMachinesHaveACoarseLevelAFifthOfTheFineOne) {
    const auto& f = factory();
    std::vector<const LOD*> lods{f.machine.get()};
    for (const auto& b : f.buildings) lods.push_back(b.lod.get());
    for (const LOD* lod : lods) {
        ASSERT_EQ(lod->numChildren(), 2u);
        const uint32_t fine = levelMesh(*lod, 0)->triangleCount(), coarse = levelMesh(*lod, 1)->triangleCount();
        EXPECT_LE(coarse * 5u, fine) << fine << " -> " << coarse;
        EXPECT_GT(coarse, 0u);
        // Switched where the coarse level's error projects to one pixel, with a fade band there.
        EXPECT_GT(lod->error(1), 0.0f);
        EXPECT_NEAR(lod->range(1).min, lod->error(1) * kDefaultPixelsPerRadian, 1e-3 * lod->range(1).min);
        EXPECT_EQ(lod->range(0).max, lod->range(1).min);
        EXPECT_NEAR(lod->transition(), 0.1f * lod->range(1).min, 1e-3f * lod->range(1).min);
    }
}

TEST(Factory, OccludersStayInsideTheirBuildings) {
    const auto& f = factory();
    for (const auto& b : f.buildings) {
        const dvec3 t = b.place->matrix()[3];
        const Box& occ = b.occluder->box();
        // Inside both models (the simplified one may pull in its outline) and the building's box.
        EXPECT_TRUE(inside(occ, translated(levelMesh(*b.lod, 0)->box(), t))) << b.kind;
        EXPECT_TRUE(inside(occ, translated(levelMesh(*b.lod, 1)->box(), t))) << b.kind;
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
    for (size_t t = 0; t < f.terrain->numChildren(); ++t) {
        const Mesh* m = static_cast<Geometry*>(f.terrain->child(t))->mesh();
        for (const vec3& p : m->positions()) {
            ASSERT_NEAR(f.terrainHeight(p.x, p.y), p.z, 1e-4) << p.x << " " << p.y;
            lo = std::min(lo, double(p.z));
            hi = std::max(hi, double(p.z));
            ++vertices;
        }
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
        terrain.insert(static_cast<Geometry*>(f.terrain->child(t))->mesh());
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
    set.occlusion.mode = OcclusionMode::Tree;
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
