// The cull and posed Geometries: a skinned item placed at its pose's anchor (not by its path) and listed with its pose
// in DrawList::poses, a morphed one by its path; a figure whose joints moved it out of the view is culled.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/LOD.h"
#include "nodes/Occluder.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"
#include "sg/scene/Scene.h"

#include "SkinnedBar.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {
dmat4 move(const dvec3& t) { return glm::translate(dmat4(1.0), t); }

// From (1, 1, 0) down -z.
Camera camera() {
    Camera cam;
    cam.setViewport(200, 200);
    cam.setPerspective(60.0, 1.0, 1.0, 1000.0);
    cam.setLookAt(dvec3(1, 1, 0), dvec3(1, 1, -1), dvec3(0, 1, 0));
    return cam;
}

DrawList cull(const Scene& s) {
    DrawList list;
    CullStats stats;
    CullTraversal().cull(s, camera(), CullSettings{}, list, stats);
    return list;
}

ref_ptr<Mesh> bar(bool blend = false) { return testutil::skinnedBar(blend); }

// root: [hip (at `where`) -> knee, far (x + 50, out of the view) -> the bar skinned by hip and knee].
struct Figure {
    ref_ptr<Group> root = make<Group>();
    ref_ptr<Transform> hip, knee;
    ref_ptr<Geometry> geometry;
};

Figure figure(const dvec3& where) {
    Figure f;
    f.hip = make<Transform>(move(where));
    f.knee = make<Transform>(move(dvec3(1, 0, 0)));
    f.hip->addChild(f.knee);
    f.geometry = make<Geometry>(bar(), make<Material>());
    f.geometry->setSkin(make<Skin>(std::vector<ref_ptr<Node>>{f.hip, f.knee},
                                   std::vector<dmat4>{dmat4(1.0), move(-dvec3(1, 0, 0))}));  // bound at the origin
    auto far = make<Transform>(move(dvec3(50, 0, 0)));
    far->addChild(f.geometry);
    f.root->addChild(f.hip);
    f.root->addChild(far);
    return f;
}
}  // namespace

TEST(PosedCull, SkinnedItemSitsAtItsAnchorWithItsPose) {
    Figure f = figure(dvec3(0, 0, -10));
    Scene s(f.root);
    s.update();
    const DrawList list = cull(s);
    // Its path would put it 50 to the right, out of the view: the pose's box is what the cull tests.
    ASSERT_EQ(list.items.size(), 1u);
    const DrawItem& it = list.items[0];
    EXPECT_EQ(it.mesh, f.geometry->mesh());  // the Geometry's own mesh: the draw state stays
    // The translation from the eye (1, 1, 0) to the anchor (the hip, at (0, 0, -10)).
    EXPECT_EQ(vec3(it.model[3]), vec3(-1, -1, -10));
    EXPECT_EQ(vec3(it.model[0]), vec3(1, 0, 0));
    EXPECT_EQ(vec3(it.model[1]), vec3(0, 1, 0));
    EXPECT_EQ(vec3(it.model[2]), vec3(0, 0, 1));
    ASSERT_EQ(list.poses.size(), 1u);
    EXPECT_EQ(list.poses[0].first, 0u);
    // Entries: root 0, hip 1, knee 2, far 3, the Geometry 4.
    ASSERT_NE(s.image().poseOf(4), nullptr);
    EXPECT_EQ(list.poses[0].second, s.image().poseOf(4));
    EXPECT_TRUE(list.poses[0].second->skinned());
}

TEST(PosedCull, MorphedItemKeepsItsPathsMatrix) {
    ref_ptr<Mesh> m = makeBoxMesh(dvec3(-1), dvec3(1));
    MorphTarget t;
    t.positions.assign(m->positions().size(), vec3(0, 0, 1));
    m->setMorphTargets({t});
    auto g = make<Geometry>(m, make<Material>());
    g->setMorphWeights({1.0f});
    auto at = make<Transform>(move(dvec3(2, 0, -10)));
    at->addChild(g);
    Scene s(at);
    s.update();
    const DrawList list = cull(s);
    ASSERT_EQ(list.items.size(), 1u);
    EXPECT_EQ(vec3(list.items[0].model[3]), vec3(1, -1, -10));
    ASSERT_EQ(list.poses.size(), 1u);
    EXPECT_EQ(list.poses[0].first, 0u);
    EXPECT_EQ(list.poses[0].second, s.image().poseOf(1));
    EXPECT_FALSE(list.poses[0].second->skinned());
    EXPECT_NE(list.poses[0].second->mesh, nullptr);
}

TEST(PosedCull, FigureMovedOutOfTheViewByItsJointsIsCulled) {
    Figure f = figure(dvec3(0, 0, -10));
    Scene s(f.root);
    s.update();
    EXPECT_EQ(cull(s).items.size(), 1u);
    f.hip->setMatrix(move(dvec3(0, 0, 10)));  // behind the eye; the Geometry's own path did not change
    s.update();
    const DrawList list = cull(s);
    EXPECT_TRUE(list.items.empty());
    EXPECT_TRUE(list.poses.empty());
    // Back into the view with the hip.
    f.hip->setMatrix(move(dvec3(0, 0, -10)));
    s.update();
    EXPECT_EQ(cull(s).items.size(), 1u);
}

// Occlusion and LOD on moving content: a skinned bar behind a wall is culled by the occlusion pass, and drawn again
// when its joints carry it out from behind; under an LOD, its level follows the distance of its pose's bound.
TEST(PosedCull, OcclusionAndLodFollowThePose) {
    auto root = make<Group>();
    auto wall = make<Occluder>();
    wall->setBox(Box{dvec3(-10, 20, -10), dvec3(10, 21, 10)});
    root->addChild(wall);
    Figure f = figure(dvec3(-1, 40, 0));  // bound at the origin, posed 40 along the view, behind the wall
    root->addChild(f.root);
    Scene s(root);
    s.update();
    Camera cam;
    cam.setViewport(400, 300);
    cam.setPerspective(60.0, 4.0 / 3.0, 0.5, 1000.0);
    cam.setLookAt(dvec3(0, 0, 0), dvec3(0, 1, 0), dvec3(0, 0, 1));
    CullSettings set;
    set.occlusion.mode = OcclusionMode::EveryFrame;
    set.occlusion.method = OcclusionMethod::Tree;
    CullTraversal cull;
    auto drawn = [&] {
        DrawList list;
        CullStats stats;
        cull.cull(s, cam, set, list, stats);
        return list.items.size();
    };
    EXPECT_EQ(drawn(), 0u);                    // hidden by the wall
    f.hip->setMatrix(move(dvec3(30, 40, 0)));  // walked out to the right, still 40 ahead, in the view
    s.update();
    EXPECT_EQ(drawn(), 1u);
    f.hip->setMatrix(move(dvec3(-1, 40, 0)));
    s.update();
    EXPECT_EQ(drawn(), 0u);

    // An LOD over the skinned bar (near: the bar; far: nothing): its range is tested at the pose's bound.
    Figure g = figure(dvec3(0, 50, 0));
    auto lod = make<LOD>();
    lod->addChild(g.root, 0.0f, 100.0f);
    Scene t(lod);
    t.update();
    auto drawnT = [&] {
        DrawList list;
        CullStats stats;
        cull.cull(t, cam, CullSettings{}, list, stats);
        return list.items.size();
    };
    EXPECT_EQ(drawnT(), 1u);
    g.hip->setMatrix(move(dvec3(0, 400, 0)));  // carried beyond the LOD's range by its joints
    t.update();
    EXPECT_EQ(drawnT(), 0u);
}
