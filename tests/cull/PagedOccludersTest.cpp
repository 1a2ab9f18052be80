// Occluders held by paged levels (a tileset's tiles): the pass uses a PagedLOD's coarse level's occluders while the
// walk draws that level, its detail's while it draws the detail, and neither where the walk does not reach them.
#include "TestUtil.h"
#include "nodes/Geometry.h"
#include "nodes/Occluder.h"
#include "nodes/PagedLOD.h"
#include "nodes/Switch.h"
#include "sg/build/PvsBuilder.h"
#include "sg/cull/CullTraversal.h"
#include "sg/scene/Scene.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace sg;

namespace {
ref_ptr<Occluder> wall(double x0, double x1) {
    auto o = make<Occluder>();
    o->setBox(Box{dvec3(x0, 20, -4), dvec3(x1, 21, 4)});
    return o;
}

// The eye at the origin looking along +y. Two targets at y = 40, left (x = -5) and right (x = +5), outside the paged
// node. The PagedLOD's coarse level holds a wall in front of the left one, its detail a wall in front of the right
// one; each level also draws a small box of its own, near the eye, so that it is seen which level is drawn.
struct PagedWalls {
    ref_ptr<Group> root = make<Group>();
    ref_ptr<Switch> sw = make<Switch>();
    ref_ptr<PagedLOD> paged = make<PagedLOD>();
    ref_ptr<Mesh> left = makeBoxMesh(dvec3(-5.5, 40, -0.5), dvec3(-4.5, 41, 0.5));
    ref_ptr<Mesh> right = makeBoxMesh(dvec3(4.5, 40, -0.5), dvec3(5.5, 41, 0.5));
    ref_ptr<Mesh> coarseMark = makeBoxMesh(dvec3(-0.2, 5, -0.2), dvec3(0.2, 5.4, 0.2));
    ref_ptr<Mesh> detailMark = makeBoxMesh(dvec3(-0.2, 6, -0.2), dvec3(0.2, 6.4, 0.2));
    PagedWalls() {
        paged->setFile("detail");
        paged->setCenter(dvec3(0, 20, 0));
        paged->setRange(0.0f, 100.0f);  // wanted from within 100 of the centre (the eye is 20 away)
        auto coarse = make<Group>();
        coarse->addChild(wall(-8, -2));
        coarse->addChild(make<Geometry>(coarseMark, make<Material>()));
        paged->addChild(coarse);
        sw->addChild(paged);
        root->addChild(sw);
        root->addChild(make<Geometry>(left, make<Material>()));
        root->addChild(make<Geometry>(right, make<Material>()));
    }
    void attach() {
        auto d = make<Group>();
        d->addChild(wall(2, 8));
        d->addChild(make<Geometry>(detailMark, make<Material>()));
        paged->attachDetail(d, 1);
    }
};

Camera eyeCamera() {
    Camera cam;
    cam.setViewport(640, 480);
    cam.setPerspective(60.0, 640.0 / 480.0, 0.5, 500.0);
    cam.setLookAt(dvec3(0.0), dvec3(0, 1, 0), dvec3(0, 0, 1));
    return cam;
}

struct Drawn {
    bool left = false, right = false, coarse = false, detail = false;
    uint64_t candidates = 0;
};

Drawn cull(Scene& scene, const PagedWalls& s, double lodScale) {
    scene.update();
    CullSettings set;
    set.occlusion.mode = OcclusionMode::EveryFrame;
    set.occlusion.method = OcclusionMethod::Tree;
    set.lodScale = lodScale;
    CullTraversal t;
    DrawList list;
    CullStats st;
    t.cull(scene, eyeCamera(), set, list, st);
    auto has = [&](const Mesh* m) {
        return std::any_of(list.items.begin(), list.items.end(), [&](const DrawItem& it) { return it.mesh == m; });
    };
    return {has(s.left.get()), has(s.right.get()), has(s.coarseMark.get()), has(s.detailMark.get()),
            st.occluderCandidates};
}
}  // namespace

TEST(PagedOccluders, TheCoarseLevelsWallHidesWhileTheCoarseLevelIsDrawn) {
    PagedWalls s;
    Scene scene(s.root);
    // Wanted but not loaded yet: the coarse level is drawn, and its wall hides the left target.
    Drawn d = cull(scene, s, 1.0);
    EXPECT_TRUE(d.coarse);
    EXPECT_FALSE(d.left);
    EXPECT_TRUE(d.right);
    EXPECT_EQ(d.candidates, 1u);
    // Loaded but not wanted (the LOD scale puts the eye past the range): the coarse level still, the same.
    s.attach();
    d = cull(scene, s, 10.0);
    EXPECT_TRUE(d.coarse);
    EXPECT_FALSE(d.detail);
    EXPECT_FALSE(d.left);
    EXPECT_TRUE(d.right);
}

TEST(PagedOccluders, TheDetailsWallHidesWhileTheDetailIsDrawnAndTheCoarseOneNoLonger) {
    PagedWalls s;
    s.attach();
    Scene scene(s.root);
    const Drawn d = cull(scene, s, 1.0);
    EXPECT_TRUE(d.detail);
    EXPECT_FALSE(d.coarse);
    EXPECT_TRUE(d.left);  // the coarse level's wall is not drawn: it hides nothing
    EXPECT_FALSE(d.right);
    EXPECT_EQ(d.candidates, 1u);
}

TEST(PagedOccluders, NoWallOfAPagedNodeTheWalkDoesNotReach) {
    PagedWalls s;
    s.attach();
    Scene scene(s.root);
    s.sw->setAll(false);
    Drawn d = cull(scene, s, 1.0);
    EXPECT_FALSE(d.detail);
    EXPECT_FALSE(d.coarse);
    EXPECT_TRUE(d.left);
    EXPECT_TRUE(d.right);
    EXPECT_EQ(d.candidates, 0u);
    // The detail detached again: its image, and its wall, are gone.
    s.sw->setAll(true);
    s.paged->detachDetail();
    d = cull(scene, s, 1.0);
    EXPECT_TRUE(d.coarse);
    EXPECT_FALSE(d.left);
    EXPECT_TRUE(d.right);
}

TEST(PagedOccluders, APvsTableTakesNoWallOfAPagedLevel) {
    // A table is built for every frame to come; a coarse level's wall goes when its detail comes.
    PagedWalls s;
    Scene scene(s.root);
    scene.update();
    PvsBuilder::Options o;
    o.region = Box{dvec3(-1, -1, -1), dvec3(1, 1, 1)};
    o.cellSize = dvec3(2.0);
    PvsBuilder::Stats st;
    const PvsTable t = PvsBuilder::build(scene, o, &st);
    EXPECT_EQ(st.occluders, 0u);
}
