// The cull's PVS pre-pass (CullSettings::pvs): what it culls, when it is not used, and the table checks.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Occluder.h"
#include "sg/build/PvsBuilder.h"
#include "sg/cull/CullTraversal.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {
struct World {
    ref_ptr<Group> root = make<Group>();
    ref_ptr<Mesh> behind = makeBoxMesh(dvec3(-1, 40, -1), dvec3(1, 42, 1));
    ref_ptr<Mesh> wallMesh = makeBoxMesh(dvec3(-10, 20, -10), dvec3(10, 21, 10));
    World() {
        root->addChild(make<Geometry>(wallMesh, make<Material>()));
        auto o = make<Occluder>();
        o->setBox(Box{dvec3(-10, 20, -10), dvec3(10, 21, 10)});
        root->addChild(o);
        root->addChild(make<Geometry>(behind, make<Material>()));
    }
};

Camera camAt(const dvec3& eye, double zNear = 0.5) {
    Camera cam;
    cam.setViewport(400, 300);
    cam.setPerspective(60.0, 4.0 / 3.0, zNear, 1000.0);
    cam.setLookAt(eye, eye + dvec3(0, 1, 0), dvec3(0, 0, 1));
    return cam;
}

bool drew(const DrawList& l, const Mesh* m) {
    for (auto& it : l.items)
        if (it.mesh == m) return true;
    return false;
}

PvsTable tableFor(const Scene& s) {
    PvsBuilder::Options o;
    o.region = Box{dvec3(-1), dvec3(1)};
    o.cellSize = dvec3(2.0);
    return PvsBuilder::build(s, o);
}
}  // namespace

TEST(PvsCull, HiddenEntriesAreCulledFirst) {
    World w;
    Scene s(w.root);
    s.update();
    const PvsTable t = tableFor(s);
    ASSERT_EQ(t.hiddenCount(0), 1u);
    CullTraversal ct;
    CullSettings set;
    set.occlusion.mode = OcclusionMode::Off;
    DrawList l;
    CullStats st;
    ct.cull(s, camAt(dvec3(0.3, -0.5, 0.9)), set, l, st);
    EXPECT_TRUE(drew(l, w.behind.get()));
    EXPECT_EQ(st.culledPvs, 0u);
    set.pvs = &t;
    for (const dvec3& eye : {dvec3(0.3, -0.5, 0.9), dvec3(-1, -1, -1), dvec3(1, 1, 1), dvec3(1, 0, -1)}) {
        ct.cull(s, camAt(eye), set, l, st);
        EXPECT_FALSE(drew(l, w.behind.get())) << eye.x << " " << eye.y << " " << eye.z;
        EXPECT_TRUE(drew(l, w.wallMesh.get()));
        EXPECT_EQ(st.culledPvs, 1u);
    }
    // With the occlusion tree as well: the PVS has culled it first.
    set.occlusion.mode = OcclusionMode::EveryFrame;
    set.occlusion.method = OcclusionMethod::Tree;
    ct.cull(s, camAt(dvec3(0.3, -0.5, 0.9)), set, l, st);
    EXPECT_FALSE(drew(l, w.behind.get()));
    EXPECT_EQ(st.culledPvs, 1u);
    // Frustum culling off (no plane tests: the walk's fast path over entries inside the frustum).
    set.occlusion.mode = OcclusionMode::Off;
    set.strategy = CullStrategy::Sphere;
    ct.cull(s, camAt(dvec3(0, 0, 0)), set, l, st);
    EXPECT_FALSE(drew(l, w.behind.get()));
}

TEST(PvsCull, NotUsedOutsideTheGridNorByTheReference) {
    World w;
    Scene s(w.root);
    s.update();
    const PvsTable t = tableFor(s);
    CullTraversal ct;
    CullSettings set;
    set.pvs = &t;
    set.occlusion.mode = OcclusionMode::Off;
    DrawList l;
    CullStats st;
    ct.cull(s, camAt(dvec3(0, -3, 0)), set, l, st);  // outside every cell
    EXPECT_TRUE(drew(l, w.behind.get()));
    EXPECT_EQ(st.culledPvs, 0u);
    set.strategy = CullStrategy::None;
    ct.cull(s, camAt(dvec3(0, 0, 0)), set, l, st);
    EXPECT_TRUE(drew(l, w.behind.get()));
    EXPECT_EQ(st.culledPvs, 0u);
}

TEST(PvsCull, TableMustMatchTheSceneAndTheCamera) {
    World w;
    Scene s(w.root);
    s.update();
    const PvsTable t = tableFor(s);
    CullTraversal ct;
    CullSettings set;
    set.pvs = &t;
    DrawList l;
    CullStats st;
    try {
        ct.cull(s, camAt(dvec3(0.0), 2.0), set, l, st);
        FAIL() << "a near plane beyond the table's range was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("CullTraversal::cull(): the camera's near plane"), std::string::npos)
            << e.what();
    }
    ct.cull(s, camAt(dvec3(0.0)), set, l, st);  // fine
    // Another table in the same place, built for a scene with as many entries (one box moved): refused.
    {
        World other;
        other.root->removeChild(size_t(2));
        other.root->addChild(make<Geometry>(makeBoxMesh(dvec3(5, 40, -1), dvec3(7, 42, 1)), make<Material>()));
        Scene s2(other.root);
        s2.update();
        PvsTable moved = tableFor(s2);
        set.pvs = &moved;
        ct.cull(s2, camAt(dvec3(0.0)), set, l, st);
        moved = t;
        ct.cull(s, camAt(dvec3(0.0)), set, l, st);  // t's copy: fine
        moved = tableFor(s2);
        EXPECT_THROW(ct.cull(s, camAt(dvec3(0.0)), set, l, st), std::invalid_argument);
        set.pvs = &t;
    }
    w.root->addChild(make<Geometry>(makeBoxMesh(dvec3(0.0), dvec3(1.0)), make<Material>()));
    s.update();
    try {
        ct.cull(s, camAt(dvec3(0.0)), set, l, st);
        FAIL() << "a stale table was used";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("CullTraversal::cull(): the PVS table does not match: the table was built "
                                             "for 4 image entries, the scene has 5"),
                  std::string::npos)
            << e.what();
    }
}
