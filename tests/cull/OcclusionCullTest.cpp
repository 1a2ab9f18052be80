// The occlusion pass inside the cull: which occluders it uses, what it culls, when it runs at all.
#include "TestUtil.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/Occluder.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>

using namespace sg;

namespace {
ref_ptr<Geometry> boxGeom(const dvec3& lo, const dvec3& hi) {
    return make<Geometry>(makeBoxMesh(lo, hi), make<Material>());
}

// A wall (geometry + box occluder) across the view at y = 20..21, x and z in [-w, w].
ref_ptr<Transform> wall(double w = 10.0) {
    auto t = make<Transform>();
    const Box b{dvec3(-w, 20, -w), dvec3(w, 21, w)};
    t->addChild(make<Geometry>(makeBoxMesh(b.min, b.max), make<Material>()));
    auto o = make<Occluder>();
    o->setBox(b);
    t->addChild(o);
    return t;
}

struct Culled {
    DrawList list;
    CullStats stats;
    bool drew(const Mesh* m) const {
        for (auto& it : list.items)
            if (it.mesh == m) return true;
        return false;
    }
};

Culled cull(const Scene& s, const Camera& cam, OcclusionMode mode = OcclusionMode::EveryFrame,
            CullTraversal* t = nullptr) {
    Culled r;
    CullSettings set;
    set.occlusion.mode = mode;
    set.occlusion.method = OcclusionMethod::Tree;
    CullTraversal local;
    (t ? *t : local).cull(s, cam, set, r.list, r.stats);
    return r;
}
}  // namespace

TEST(OcclusionCull, WallHidesWhatIsBehindItOnly) {
    auto root = make<Group>();
    root->addChild(wall());
    auto behind = boxGeom(dvec3(-1, 40, -1), dvec3(1, 42, 1));
    auto beside = boxGeom(dvec3(30, 40, -1), dvec3(32, 42, 1));
    auto front = boxGeom(dvec3(-1, 10, -1), dvec3(1, 12, 1));
    root->addChild(behind);
    root->addChild(beside);
    root->addChild(front);
    Scene s(root);
    s.update();
    const Culled r = cull(s, testutil::lookingAlongY(500.0));
    EXPECT_TRUE(r.stats.occlusionRan);
    EXPECT_EQ(r.stats.occludersUsed, 1u);
    EXPECT_FALSE(r.drew(behind->mesh()));
    EXPECT_TRUE(r.drew(beside->mesh()));
    EXPECT_TRUE(r.drew(front->mesh()));
    EXPECT_TRUE(
        r.drew(static_cast<Geometry*>(static_cast<Transform*>(root->child(0))->child(0))->mesh()));  // the wall itself
    EXPECT_GE(r.stats.culledOcclusion, 1u);
    // Off, or the reference (no culling): the box behind is drawn.
    EXPECT_TRUE(cull(s, testutil::lookingAlongY(500.0), OcclusionMode::Off).drew(behind->mesh()));
    Culled none;
    CullSettings ref;
    ref.strategy = CullStrategy::None;
    CullTraversal().cull(s, testutil::lookingAlongY(500.0), ref, none.list, none.stats);
    EXPECT_TRUE(none.drew(behind->mesh()));
    EXPECT_FALSE(none.stats.occlusionRan);
}

TEST(OcclusionCull, TwoNeighboursTogetherHideWhatNeitherHidesAlone) {
    // Two half walls overlap a little at x = 0; the box behind straddles the seam. (Occluders that only
    // touch leave a crack of the shadows' safety margin, a 64th of a pixel, at the seam.)
    auto root = make<Group>();
    for (double x0 : {-10.0, -0.05}) {
        auto o = make<Occluder>();
        o->setBox(Box{dvec3(x0, 20, -10), dvec3(x0 + 10.05, 21, 10)});
        root->addChild(o);
    }
    auto behind = boxGeom(dvec3(-2, 40, -1), dvec3(2, 42, 1));
    root->addChild(behind);
    Scene s(root);
    s.update();
    const Culled r = cull(s, testutil::lookingAlongY(500.0));
    EXPECT_EQ(r.stats.occludersUsed, 2u);
    EXPECT_FALSE(r.drew(behind->mesh()));
    static_cast<Occluder*>(root->child(1))->setBox(Box{dvec3(0, 20, -10), dvec3(10, 21, 0)});  // now a gap above
    s.update();
    EXPECT_TRUE(cull(s, testutil::lookingAlongY(500.0)).drew(behind->mesh()));
}

TEST(OcclusionCull, NoOccludersNoPass) {
    auto root = make<Group>();
    root->addChild(boxGeom(dvec3(-1, 40, -1), dvec3(1, 42, 1)));
    Scene s(root);
    s.update();
    const Culled r = cull(s, testutil::lookingAlongY(500.0));
    EXPECT_FALSE(r.stats.occlusionRan);
    EXPECT_EQ(r.stats.occlusionTests, 0u);
    // Occluders behind the eye: in the scene, not in view; no tree, no tests.
    auto t = wall();
    t->setTranslation(dvec3(0, -60, 0));
    root->addChild(t);
    s.update();
    const Culled r2 = cull(s, testutil::lookingAlongY(500.0));
    EXPECT_EQ(r2.stats.occluderCandidates, 0u);
    EXPECT_EQ(r2.stats.occlusionTests, 0u);
}

TEST(OcclusionCull, OccludersAreUsedWhileWhatIsAboveThemIsDrawn) {
    // Below a Switch: used while the Switch shows it (the image's copy of its bits), not once it is turned off.
    auto root = make<Group>();
    auto sw = make<Switch>();
    sw->addChild(wall(), true);
    root->addChild(sw);
    auto behind = boxGeom(dvec3(-1, 40, -1), dvec3(1, 42, 1));
    root->addChild(behind);
    Scene s(root);
    s.update();
    EXPECT_FALSE(cull(s, testutil::lookingAlongY(500.0)).drew(behind->mesh()));
    sw->setAll(false);
    s.update();
    Culled r = cull(s, testutil::lookingAlongY(500.0));
    EXPECT_EQ(r.stats.occluderCandidates, 0u);
    EXPECT_TRUE(r.drew(behind->mesh()));
    sw->setAll(true);
    s.update();
    EXPECT_FALSE(cull(s, testutil::lookingAlongY(500.0)).drew(behind->mesh()));
    // Moved out of the Switch: used.
    auto w = ref_ptr<Node>(sw->child(0));
    sw->removeChild(size_t(0));
    root->addChild(w);
    s.update();
    EXPECT_FALSE(cull(s, testutil::lookingAlongY(500.0)).drew(behind->mesh()));
    // Below a masked node: used while the traversal mask sees the node (the wall is drawn then), not otherwise.
    w->setNodeMask(0x1);
    s.update();
    EXPECT_FALSE(cull(s, testutil::lookingAlongY(500.0)).drew(behind->mesh()));
    CullSettings set;
    set.occlusion.mode = OcclusionMode::EveryFrame;
    set.occlusion.method = OcclusionMethod::Tree;
    set.traversalMask = 0x2;
    CullTraversal t;
    r = Culled{};
    t.cull(s, testutil::lookingAlongY(500.0), set, r.list, r.stats);
    EXPECT_TRUE(r.drew(behind->mesh()));
    EXPECT_EQ(r.stats.occluderCandidates, 0u);
    // Masked itself: not used (its own mask is not among the conditions an occluder carries).
    w->setNodeMask(0xffffffffu);
    w->child(1)->setNodeMask(0x1);
    s.update();
    r = cull(s, testutil::lookingAlongY(500.0));
    EXPECT_TRUE(r.drew(behind->mesh()));
}

TEST(OcclusionCull, MovedOccluderIsFollowedByTheRefit) {
    auto root = make<Group>();
    auto w = wall();
    root->addChild(w);
    auto behind = boxGeom(dvec3(-1, 40, -1), dvec3(1, 42, 1));
    root->addChild(behind);
    Scene s(root);
    s.update();
    EXPECT_FALSE(cull(s, testutil::lookingAlongY(500.0)).drew(behind->mesh()));
    w->setTranslation(dvec3(25, 0, 0));  // slides aside
    s.update();
    EXPECT_EQ(s.lastUpdate().fullRebuilds, 0u);
    EXPECT_TRUE(cull(s, testutil::lookingAlongY(500.0)).drew(behind->mesh()));
    // Back in front, turned half a turn about its own centre: the same box through a general matrix.
    w->setMatrix(glm::translate(dmat4(1.0), dvec3(0, 20.5, 0)) *
                 glm::rotate(dmat4(1.0), glm::pi<double>(), dvec3(0, 0, 1)) *
                 glm::translate(dmat4(1.0), dvec3(0, -20.5, 0)));
    s.update();
    EXPECT_FALSE(cull(s, testutil::lookingAlongY(500.0)).drew(behind->mesh()));
}

TEST(OcclusionCull, PolygonOccluderUnderARotation) {
    auto root = make<Group>();
    auto t = make<Transform>();
    // A square in the local xz plane, turned 30 degrees about z (seen at a slant), 20 m ahead.
    t->setMatrix(glm::translate(dmat4(1.0), dvec3(0, 20, 0)) *
                 glm::rotate(dmat4(1.0), glm::radians(30.0), dvec3(0, 0, 1)));
    auto o = make<Occluder>();
    o->setPolygon({dvec3(-10, 0, -10), dvec3(10, 0, -10), dvec3(10, 0, 10), dvec3(-10, 0, 10)});
    t->addChild(o);
    root->addChild(t);
    auto behind = boxGeom(dvec3(-1, 40, -1), dvec3(1, 42, 1));
    auto beside = boxGeom(dvec3(26, 40, -1), dvec3(28, 42, 1));
    root->addChild(behind);
    root->addChild(beside);
    Scene s(root);
    s.update();
    const Culled r = cull(s, testutil::lookingAlongY(500.0));
    EXPECT_EQ(r.stats.occludersUsed, 1u);
    EXPECT_FALSE(r.drew(behind->mesh()));
    EXPECT_TRUE(r.drew(beside->mesh()));
}

TEST(OcclusionCull, HiddenInstancePlacementIsCulled) {
    auto proto = make<Group>();
    auto geom = boxGeom(dvec3(-1), dvec3(1));
    proto->addChild(geom);
    auto root = make<Group>();
    root->addChild(wall());
    auto hidden = make<Instance>();
    hidden->setPrototype(proto);
    hidden->setMatrix(glm::translate(dmat4(1.0), dvec3(0, 50, 0)));
    auto shown = make<Instance>();
    shown->setPrototype(proto);
    shown->setMatrix(glm::translate(dmat4(1.0), dvec3(0, 10, 0)));
    root->addChild(hidden);
    root->addChild(shown);
    Scene s(root);
    s.update();
    const Culled r = cull(s, testutil::lookingAlongY(500.0));
    size_t n = 0;
    for (auto& it : r.list.items) n += it.mesh == geom->mesh();
    EXPECT_EQ(n, 1u);
}

TEST(OcclusionCull, AdaptiveModeBacksOffWhenThePassDoesNotPay) {
    // A wall with nothing behind it: the pass runs, culls nothing, and Adaptive skips the next frames.
    auto root = make<Group>();
    root->addChild(wall());
    for (int k = 0; k < 20; ++k) root->addChild(boxGeom(dvec3(-30 + 3 * k, 5, -1), dvec3(-29 + 3 * k, 6, 1)));
    Scene s(root);
    s.update();
    CullTraversal t;
    const Camera cam = testutil::lookingAlongY(500.0);
    Culled r = cull(s, cam, OcclusionMode::Adaptive, &t);
    EXPECT_TRUE(r.stats.occlusionRan);
    int skipped = 0;
    for (int f = 0; f < 4; ++f) skipped += cull(s, cam, OcclusionMode::Adaptive, &t).stats.occlusionSkipped;
    EXPECT_EQ(skipped, 4);
    EXPECT_TRUE(cull(s, cam, OcclusionMode::Adaptive, &t).stats.occlusionRan);  // tries again
    // Twice in a row without pay: it waits longer (8 frames).
    skipped = 0;
    for (int f = 0; f < 8; ++f) skipped += cull(s, cam, OcclusionMode::Adaptive, &t).stats.occlusionSkipped;
    EXPECT_EQ(skipped, 8);

    // Behind the wall, a crowd: the pass pays and runs every frame.
    auto crowd = make<Group>();
    for (int k = 0; k < 50; ++k) crowd->addChild(boxGeom(dvec3(-5 + 0.2 * k, 40, -1), dvec3(-4.9 + 0.2 * k, 41, 1)));
    root->addChild(crowd);
    s.update();
    CullTraversal t2;
    for (int f = 0; f < 10; ++f) {
        r = cull(s, cam, OcclusionMode::Adaptive, &t2);
        EXPECT_TRUE(r.stats.occlusionRan) << "frame " << f;
        EXPECT_GE(r.stats.culledOcclusion, 1u);
    }
}

TEST(OcclusionCull, OrthographicCameraRunsNoPass) {
    auto root = make<Group>();
    root->addChild(wall());
    auto behind = boxGeom(dvec3(-1, 40, -1), dvec3(1, 42, 1));
    root->addChild(behind);
    Scene s(root);
    s.update();
    Camera cam = testutil::lookingAlongY(500.0);
    cam.setProjection(glm::ortho(-50.0, 50.0, -40.0, 40.0, 0.5, 500.0));
    const Culled r = cull(s, cam);
    EXPECT_FALSE(r.stats.occlusionRan);
    EXPECT_TRUE(r.drew(behind->mesh()));
}

// A generated occluder's conditions (Occluder::eyeOutside, shownWith, oneSided), checked by the pass each frame.
namespace {
// The wall at y = 20..21 as geometry, with a generated-style box occluder beside it.
ref_ptr<Occluder> boxOccluder(const Box& b) {
    auto o = make<Occluder>();
    o->setBox(b);
    o->setGenerated(true);
    return o;
}
const Box kWall{dvec3(-10, 20, -10), dvec3(10, 21, 10)};
}  // namespace

TEST(OcclusionCull, AnEyeInsideTheOccludersEyeOutsideBoxIsNotServed) {
    auto root = make<Group>();
    root->addChild(make<Geometry>(makeBoxMesh(kWall.min, kWall.max), make<Material>()));
    auto o = boxOccluder(kWall);
    root->addChild(o);
    auto behind = boxGeom(dvec3(-1, 40, -1), dvec3(1, 42, 1));
    root->addChild(behind);
    Scene s(root);
    s.update();
    EXPECT_FALSE(cull(s, testutil::lookingAlongY()).drew(behind->mesh()));
    // The eye (the origin) inside the box the occluder must be seen from outside of: not used.
    o->setEyeOutside(Box{dvec3(-1, -1, -1), dvec3(1, 30, 1)});
    s.update();
    Culled r = cull(s, testutil::lookingAlongY());
    EXPECT_TRUE(r.drew(behind->mesh()));
    EXPECT_EQ(r.stats.occluderCandidates, 0u);
    // A box that ends 0.2 short of the eye: the near plane (0.5 here) could clip the surface in it, so still not used.
    o->setEyeOutside(Box{dvec3(-1, 0.2, -1), dvec3(1, 30, 1)});
    s.update();
    EXPECT_TRUE(cull(s, testutil::lookingAlongY()).drew(behind->mesh()));
    // Well clear of the eye: used.
    o->setEyeOutside(Box{dvec3(-10, 15, -10), dvec3(10, 30, 10)});
    s.update();
    EXPECT_FALSE(cull(s, testutil::lookingAlongY()).drew(behind->mesh()));
}

TEST(OcclusionCull, AnOccluderWithOpeningsIsUsedOnlyWithTheEyeBeyondTheirPlanes) {
    // In a turned and moved frame, as the generator leaves them: the wall at y = 10..11 in its frame, turned about the
    // view axis and moved 10 along it (y = 20..21 in the world, still across the view); the eye at (0, -10, 0) there.
    auto root = make<Group>();
    auto place = make<Transform>();
    place->setMatrix(glm::translate(dmat4(1.0), dvec3(0, 10, 0)) * glm::rotate(dmat4(1.0), 0.7, dvec3(0, 1, 0)));
    root->addChild(place);
    const Box wall{kWall.min - dvec3(0, 10, 0), kWall.max - dvec3(0, 10, 0)};
    place->addChild(make<Geometry>(makeBoxMesh(wall.min, wall.max), make<Material>()));
    auto o = boxOccluder(wall);
    place->addChild(o);
    auto behind = boxGeom(dvec3(-1, 40, -1), dvec3(1, 42, 1));
    root->addChild(behind);
    Scene s(root);
    s.update();
    ASSERT_FALSE(cull(s, testutil::lookingAlongY()).drew(behind->mesh()));
    // The eye on the positive side of y < 8: used.
    o->setOpenings({Plane{dvec3(0, -1, 0), 8.0}});
    s.update();
    EXPECT_FALSE(cull(s, testutil::lookingAlongY()).drew(behind->mesh()));
    // And of a second plane, z > 1, on its negative side: not used.
    o->setOpenings({Plane{dvec3(0, -1, 0), 8.0}, Plane{dvec3(0, 0, 1), -1.0}});
    s.update();
    Culled r = cull(s, testutil::lookingAlongY());
    EXPECT_TRUE(r.drew(behind->mesh()));
    EXPECT_EQ(r.stats.occluderCandidates, 0u);
    // On the plane z = 0, up to the rounding of its way into the frame: not beyond it, not used; 1 mm beyond: used.
    o->setOpenings({Plane{dvec3(0, 0, 1), 0.0}});
    s.update();
    EXPECT_TRUE(cull(s, testutil::lookingAlongY()).drew(behind->mesh()));
    o->setOpenings({Plane{dvec3(0, 0, 1), 1e-3}});
    s.update();
    EXPECT_FALSE(cull(s, testutil::lookingAlongY()).drew(behind->mesh()));
    // Cleared: used anywhere.
    o->setOpenings({});
    s.update();
    EXPECT_FALSE(cull(s, testutil::lookingAlongY()).drew(behind->mesh()));
}

TEST(OcclusionCull, OpeningsThatAreNotPlanesAreRefusedByName) {
    auto o = boxOccluder(kWall);
    o->setName("lidless");
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (const Plane& p : {Plane{dvec3(0, 0, 2), 0.0}, Plane{dvec3(nan, 0, 1), 0.0}, Plane{dvec3(0, 0, 1), kInf}}) {
        try {
            o->setOpenings({Plane{dvec3(1, 0, 0), 0.0}, p});
            ADD_FAILURE() << "accepted";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find("Occluder::setOpenings()"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("lidless"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("plane 1"), std::string::npos) << e.what();
        }
        EXPECT_TRUE(o->openings().empty()) << "kept a refused plane";
    }
}

TEST(OcclusionCull, AnOccluderShownWithAnLodIsUsedWhileTheLodShowsALevel) {
    // The LOD shows the wall up to 60 (eye at the origin, centre at y = 20.5): used; beyond its last range the LOD
    // shows nothing and the occluder must not hide what is behind.
    auto root = make<Group>();
    auto lod = make<LOD>();
    lod->addChild(make<Geometry>(makeBoxMesh(kWall.min, kWall.max), make<Material>()), 0.0f, 60.0f);
    root->addChild(lod);
    auto o = boxOccluder(kWall);
    o->setShownWith(lod.get());
    root->addChild(o);
    auto behind = boxGeom(dvec3(-1, 40, -1), dvec3(1, 42, 1));
    root->addChild(behind);
    Scene s(root);
    s.update();
    EXPECT_FALSE(cull(s, testutil::lookingAlongY()).drew(behind->mesh()));
    lod->setRange(0, 0.0f, 15.0f);  // the wall is past its range: not drawn
    s.update();
    EXPECT_TRUE(cull(s, testutil::lookingAlongY()).drew(behind->mesh()));
    // A fade band about the end of the range: dissolving to nothing from 19 (the value is 20.5, the wall's centre).
    lod->setRange(0, 0.0f, 23.0f);
    lod->setTransition(8.0f);
    s.update();
    EXPECT_TRUE(cull(s, testutil::lookingAlongY()).drew(behind->mesh()));
    lod->setTransition(0.0f);
    s.update();
    EXPECT_FALSE(cull(s, testutil::lookingAlongY()).drew(behind->mesh()));
    // Not right after its LOD (a Geometry between): never used.
    root->insertChild(1, boxGeom(dvec3(100, 100, 100), dvec3(101, 101, 101)));
    s.update();
    EXPECT_TRUE(cull(s, testutil::lookingAlongY()).drew(behind->mesh()));
}

TEST(OcclusionCull, AOneSidedPolygonHidesOnlyFromItsFront) {
    auto root = make<Group>();
    auto o = make<Occluder>();
    // Counter-clockwise seen from -y (the eye's side): its front faces the eye.
    o->setPolygon({dvec3(-10, 20, -10), dvec3(10, 20, -10), dvec3(10, 20, 10), dvec3(-10, 20, 10)});
    o->setGenerated(true);
    o->setOneSided(true);
    root->addChild(o);
    auto behind = boxGeom(dvec3(-1, 40, -1), dvec3(1, 42, 1));
    root->addChild(behind);
    Scene s(root);
    s.update();
    EXPECT_FALSE(cull(s, testutil::lookingAlongY()).drew(behind->mesh()));
    o->setPolygon({dvec3(-10, 20, 10), dvec3(10, 20, 10), dvec3(10, 20, -10), dvec3(-10, 20, -10)});  // turned round
    s.update();
    EXPECT_TRUE(cull(s, testutil::lookingAlongY()).drew(behind->mesh()));
}
