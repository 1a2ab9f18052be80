#include "TestUtil.h"
#include "nodes/BspGroup.h"
#include "sg/cull/CullTraversal.h"
#include "testbed/City.h"
#include "testbed/RandomScene.h"

#include <gtest/gtest.h>

#include <set>

using namespace sg;

namespace {
struct Culled {
    DrawList list;
    CullStats stats;
};
Culled cullWith(const Scene& s, const Camera& cam, CullStrategy strat, double smallFeature = 0.0) {
    Culled c;
    CullSettings set;
    set.strategy = strat;
    set.smallFeaturePixels = smallFeature;
    CullTraversal().cull(s, cam, set, c.list, c.stats);
    return c;
}
ref_ptr<Geometry> box(double h = 1.0) { return make<Geometry>(makeBoxMesh(dvec3(-h), dvec3(h)), make<Material>()); }
Camera lookingDownMinusZ(double fov = 60.0) {
    Camera cam;
    cam.setViewport(200, 200);
    cam.setPerspective(fov, 1.0, 1.0, 1000.0);
    cam.setLookAt(dvec3(0, 0, 0), dvec3(0, 0, -1), dvec3(0, 1, 0));
    return cam;
}
// (mesh, model translation) of what was drawn, comparable across strategies.
std::multiset<std::pair<const Mesh*, std::array<float, 3>>> drawn(const DrawList& l) {
    std::multiset<std::pair<const Mesh*, std::array<float, 3>>> s;
    for (const DrawItem& it : l.items) s.insert({it.mesh, {it.model[3].x, it.model[3].y, it.model[3].z}});
    return s;
}
}  // namespace

TEST(Cull, ConservativeStrategiesKeepEverythingWithAVertexInView) {
    // Random graphs (rotations, non-uniform scale, LOD, Switch, Billboard, Instance, BspGroup) and the
    // awkward cameras, near the origin and 10,000 km from it.
    int views = 0, checkedDrawn = 0;
    for (uint64_t seed = 1; seed <= 8; ++seed)
        for (double off : {0.0, 1e7}) {
            scenes::RandomSceneOptions o;
            o.offset = dvec3(off, off, 0);
            auto root = scenes::buildRandomScene(seed, o);
            Scene s(root);
            s.update();
            scenes::Rng rng(seed * 77);
            Box b{o.offset - dvec3(70), o.offset + dvec3(70)};
            for (int k = 0; k < 12; ++k, ++views) {
                const Camera cam = scenes::randomCamera(rng, b, k, 320, 240);
                const auto all = drawn(cullWith(s, cam, CullStrategy::None).list);
                for (auto strat : {CullStrategy::Sphere, CullStrategy::Aabb, CullStrategy::SphereSphere}) {
                    const auto got = drawn(cullWith(s, cam, strat).list);
                    // Never more than the unculled set...
                    for (auto& g : got) ASSERT_TRUE(all.count(g)) << "seed " << seed << " view " << k;
                    // ...and every geometry with a vertex well inside the frustum is there.
                    testutil::forEachActive(root.get(), dmat4(1.0), cam, [&](Geometry* g, const dmat4& m) {
                        if (!testutil::vertexInside(*g, m, cam, 1e-3 * (1.0 + glm::length(cam.eye()) * 1e-9))) return;
                        const dvec3 t = dvec3(m[3]) - cam.eye();
                        bool found = false;
                        for (auto& d : got)
                            found |= d.first == g->mesh() &&
                                     glm::length(dvec3(d.second[0], d.second[1], d.second[2]) - t) < 1e-2;
                        ++checkedDrawn;
                        ASSERT_TRUE(found) << strategyName(strat) << " dropped a visible geometry, seed " << seed
                                           << " view " << k << " offset " << off;
                    });
                }
            }
        }
    EXPECT_EQ(views, 192);
    EXPECT_GT(checkedDrawn, 500);
}

TEST(Cull, CityCountsAgreeAcrossConservativeStrategiesWithinTheirTightness) {
    Scene s(scenes::buildCity({64, false}));
    s.update();
    for (int f = 0; f < 120; f += 17) {
        const Camera cam = scenes::cityOrbitCamera(64, f, 320, 180);
        const auto none = cullWith(s, cam, CullStrategy::None);
        const auto sphere = cullWith(s, cam, CullStrategy::Sphere);
        const auto aabb = cullWith(s, cam, CullStrategy::Aabb);
        const auto ss = cullWith(s, cam, CullStrategy::SphereSphere);
        EXPECT_LT(sphere.stats.geometries, none.stats.geometries);
        EXPECT_LE(aabb.stats.geometries, sphere.stats.geometries + 2);  // boxes are tighter here (rounding aside)
        EXPECT_EQ(ss.stats.geometries, sphere.stats.geometries);        // the pre-test only saves plane tests
        EXPECT_GT(sphere.stats.culledFrustum, 0u);
    }
}

TEST(Cull, NothingOutsideIsDrawnAndTestsStopInsideTheFrustum) {
    auto root = make<Group>();
    auto near = make<Group>(), far = make<Group>();
    for (int k = 0; k < 10; ++k) {
        auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(k - 5.0, 0, -50)));
        t->addChild(box(0.2));
        near->addChild(t);
        auto t2 = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 0, 50 + k)));  // behind the eye
        t2->addChild(box(0.2));
        far->addChild(t2);
    }
    root->addChild(near);
    root->addChild(far);
    Scene s(root);
    s.update();
    // Force the scalar path with a tiny scene? The image is small: the whole root is one batch.
    const auto c = cullWith(s, lookingDownMinusZ(), CullStrategy::Sphere);
    EXPECT_EQ(c.stats.geometries, 10u);
    EXPECT_EQ(c.stats.culledFrustum, 1u);  // the group behind the eye, as a whole
    // Fully inside: the group `near` is accepted and its 20 entries below are not tested.
    EXPECT_EQ(c.stats.boundsTested, 3u);  // root, near, far
}

TEST(Cull, LodSelectsByDistanceAndByPixelSize) {
    auto lod = make<LOD>();
    auto hi = box(1), lo = box(1);
    lod->addChild(hi, 0, 20);
    lod->addChild(lo, 20, 100);
    lod->setCenter(dvec3(0));
    auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 0, -10)));
    t->addChild(lod);
    Scene s(t);
    s.update();
    auto c = cullWith(s, lookingDownMinusZ(), CullStrategy::Sphere);
    ASSERT_EQ(c.list.items.size(), 1u);
    EXPECT_EQ(c.list.items[0].mesh, hi->mesh());
    t->setTranslation(dvec3(0, 0, -50));
    s.update();
    c = cullWith(s, lookingDownMinusZ(), CullStrategy::Sphere);
    ASSERT_EQ(c.list.items.size(), 1u);
    EXPECT_EQ(c.list.items[0].mesh, lo->mesh());
    t->setTranslation(dvec3(0, 0, -150));
    s.update();
    EXPECT_EQ(cullWith(s, lookingDownMinusZ(), CullStrategy::Sphere).list.items.size(), 0u);
    // Pixel size: the sphere of radius sqrt(3) at 50 m, 200 px tall viewport at 60 degrees.
    lod->setMode(LOD::Mode::PixelSize);
    lod->setRange(0, 0, 20);    // small on screen: coarse... here child 0 is shown below 20 px
    lod->setRange(1, 20, 1e6);  // and child 1 above
    t->setTranslation(dvec3(0, 0, -50));
    s.update();
    const double px = 2 * std::sqrt(3.0) * (1.0 / std::tan(M_PI / 6)) * 0.5 * 200 / 50;  // about 12 px
    c = cullWith(s, lookingDownMinusZ(), CullStrategy::Sphere);
    ASSERT_EQ(c.list.items.size(), 1u);
    EXPECT_EQ(c.list.items[0].mesh, px < 20 ? hi->mesh() : lo->mesh());
}

TEST(Cull, SwitchMasksAndNodeMasks) {
    auto sw = make<Switch>();
    auto a = box(), b = box();
    sw->addChild(a);
    sw->addChild(b, false);
    auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 0, -10)));
    t->addChild(sw);
    Scene s(t);
    s.update();
    auto c = cullWith(s, lookingDownMinusZ(), CullStrategy::Sphere);
    ASSERT_EQ(c.list.items.size(), 1u);
    EXPECT_EQ(c.list.items[0].mesh, a->mesh());
    sw->setAll(true);  // the image holds the bits as of the last update: stale until the next
    EXPECT_THROW(cullWith(s, lookingDownMinusZ(), CullStrategy::Sphere), std::logic_error);
    s.update();
    EXPECT_EQ(cullWith(s, lookingDownMinusZ(), CullStrategy::Sphere).list.items.size(), 2u);
    a->setNodeMask(0x2);
    s.update();
    CullSettings set;
    set.traversalMask = 0x1;
    DrawList l;
    CullStats st;
    CullTraversal().cull(s, lookingDownMinusZ(), set, l, st);
    ASSERT_EQ(l.items.size(), 1u);
    EXPECT_EQ(l.items[0].mesh, b->mesh());
}

TEST(Cull, BillboardTurnsTowardTheEye) {
    auto bb = make<Billboard>();  // axial about +Z
    bb->addChild(make<Geometry>(makeBoxMesh(dvec3(-1, -0.01, 0), dvec3(1, 0.01, 2)), make<Material>()));
    auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(10, 0, 0)));
    t->addChild(bb);
    Scene s(t);
    s.update();
    for (double a : {0.0, 1.0, 2.5, 4.0}) {
        Camera cam;
        cam.setViewport(100, 100);
        cam.setPerspective(60, 1, 0.1, 100);
        const dvec3 eye = dvec3(10, 0, 1) + 20.0 * dvec3(std::cos(a), std::sin(a), 0.3);
        cam.setLookAt(eye, dvec3(10, 0, 1), dvec3(0, 0, 1));
        const auto c = cullWith(s, cam, CullStrategy::Sphere);
        ASSERT_EQ(c.list.items.size(), 1u);
        // The child's -Y axis, in the world, points at the eye (in the horizontal plane).
        const dvec3 minusY = -dvec3(dmat4(c.list.items[0].matrix()) * dvec4(0, 1, 0, 0));
        const dvec3 toEye = glm::normalize(dvec3(std::cos(a), std::sin(a), 0));
        EXPECT_NEAR(glm::dot(glm::normalize(minusY), toEye), 1.0, 1e-5) << a;
        EXPECT_NEAR(minusY.z, 0.0, 1e-6);
    }
}

TEST(Cull, EveryInstancePlacementIsCulledOnItsOwn) {
    auto proto = make<Group>();
    proto->addChild(box(1));
    auto root = make<Group>();
    for (int k = 0; k < 5; ++k)
        root->addChild(make<Instance>(proto, glm::translate(dmat4(1.0), dvec3(k * 15.0 - 30.0, 0, -40))));
    root->addChild(make<Instance>(proto, glm::scale(glm::translate(dmat4(1.0), dvec3(0, 0, 40)), dvec3(3))));  // behind
    Scene s(root);
    s.update();
    const auto c = cullWith(s, lookingDownMinusZ(), CullStrategy::Sphere);
    // At z = -40 the half-width of the view is 23.1 m: only x = -15, 0, 15 are inside.
    EXPECT_EQ(c.stats.geometries, 3u);
    EXPECT_EQ(c.stats.instancesVisited, 3u);
    for (const DrawItem& it : c.list.items) EXPECT_LE(std::abs(it.model[3].x), 15.0f + 1e-4f);
}

TEST(Cull, BspGroupEmitsFrontToBack) {
    auto g = make<BspGroup>();
    for (int k = 0; k < 8; ++k) {
        auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3((k * 5) % 8 * 3.0 - 12.0, 0, -20)));
        t->addChild(box(1));
        g->addChild(t);
    }
    Scene s(g);
    s.update();
    for (double x : {-40.0, 40.0}) {
        Camera cam;
        cam.setViewport(100, 100);
        cam.setPerspective(120, 1, 0.1, 1000);
        cam.setLookAt(dvec3(x, 0, -20), dvec3(0, 0, -20), dvec3(0, 0, 1));
        CullSettings set;
        set.sort = false;
        DrawList l;
        CullStats st;
        CullTraversal().cull(s, cam, set, l, st);
        ASSERT_EQ(l.items.size(), 8u);
        for (size_t k = 1; k < l.items.size(); ++k)
            EXPECT_LT(std::abs(l.items[k - 1].model[3].x), std::abs(l.items[k].model[3].x) + 1e-3) << "eye x " << x;
    }
}

TEST(Cull, NaNBoundIsDrawnAndCounted) {
    auto bad = make<Mesh>();
    bad->set({vec3(0), vec3(1, 0, 0), vec3(NAN, 0, 0)}, {}, {0, 1, 2});
    auto root = make<Group>();
    auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 0, 500)));  // behind the eye
    t->addChild(make<Geometry>(bad, make<Material>()));
    root->addChild(t);
    root->addChild(box());
    Scene s(root);
    s.update();
    for (auto strat : {CullStrategy::Sphere, CullStrategy::Aabb, CullStrategy::SphereSphere, CullStrategy::CenterBox}) {
        const auto c = cullWith(s, lookingDownMinusZ(), strat, 5.0);
        EXPECT_EQ(c.stats.invalidDrawn, 1u) << strategyName(strat);
    }
}

TEST(Cull, SmallFeatureCullingDropsWhatIsBelowThreshold) {
    auto root = make<Group>();
    for (int k = 1; k <= 10; ++k) {
        auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 0, -20.0 * k)));
        t->addChild(box(0.1));
        root->addChild(t);
    }
    Scene s(root);
    s.update();
    const auto all = cullWith(s, lookingDownMinusZ(), CullStrategy::Sphere);
    const auto some = cullWith(s, lookingDownMinusZ(), CullStrategy::Sphere, 3.0);
    EXPECT_EQ(all.stats.geometries, 10u);
    // Diameter 2*sqrt(0.03) = 0.35 m; at 200 px over 60 degrees, 3 px is reached closer than 20 m * 2.0.
    EXPECT_LT(some.stats.geometries, 10u);
    EXPECT_GT(some.stats.geometries, 0u);
    EXPECT_EQ(some.stats.culledSmallFeature, 10u - some.stats.geometries);
}

TEST(Cull, StaleSceneIsRefused) {
    auto root = make<Group>();
    root->addChild(box());
    Scene s(root);
    s.update();
    root->addChild(box());
    DrawList l;
    CullStats st;
    try {
        CullTraversal().cull(s, lookingDownMinusZ(), {}, l, st);
        FAIL() << "no error";
    } catch (const std::logic_error& e) {
        EXPECT_EQ(std::string(e.what()),
                  "CullTraversal::cull(): the scene changed since its last update(); call Scene::update() first");
    }
}

namespace {
// One LOD at the origin: a detailed box below 100 m, a coarse one from 100 m to 1000 m.
struct TwoLevels {
    ref_ptr<Geometry> detailed = box(1.0), coarse = box(1.0);
    ref_ptr<Group> root = make<Group>();
    TwoLevels() {
        auto lod = make<LOD>();
        lod->addChild(detailed, 0.0f, 100.0f);
        lod->addChild(coarse, 100.0f, 1000.0f);
        lod->setCenter(dvec3(0.0));
        root->addChild(lod);
    }
};
}  // namespace

TEST(Cull, LodChangesCountTheLevelsShownAtAnotherChildThanLastSeen) {
    // The boundary test's LOD: hovering at 100 m +- 1%, with a hysteresis too small to hold it (1e-6, yet the
    // history kept) every frame after the first is one change; with 2% none; past the widened boundary, one.
    TwoLevels two;
    Scene s(two.root);
    s.update();
    auto changes = [&](CullTraversal& t, double x, double h) {
        Camera cam;
        cam.setViewport(200, 200);
        cam.setPerspective(60.0, 1.0, 1.0, 2000.0);
        cam.setLookAt(dvec3(x, 0, 0), dvec3(0, 0, 0), dvec3(0, 0, 1));
        CullSettings set;
        set.lodHysteresis = h;
        DrawList l;
        CullStats st;
        t.cull(s, cam, set, l, st);
        return st.lodChanged;
    };
    CullTraversal loose, held, untracked;
    EXPECT_EQ(changes(loose, 99.0, 1e-6), 0u);  // first sight
    EXPECT_EQ(changes(held, 99.0, 0.02), 0u);
    for (int f = 1; f < 10; ++f) {
        const double x = f % 2 ? 101.0 : 99.0;
        EXPECT_EQ(changes(loose, x, 1e-6), 1u) << f;
        EXPECT_EQ(changes(held, x, 0.02), 0u) << f;
        EXPECT_EQ(changes(untracked, x, 0.0), 0u) << f;  // no history kept: nothing to compare with
    }
    EXPECT_EQ(changes(held, 103.0, 0.02), 1u);
    EXPECT_EQ(changes(held, 103.0, 0.02), 0u);
    // Out of range (past 1000 m: nothing shown) is a change from what was shown.
    EXPECT_EQ(changes(held, 1500.0, 0.02), 1u);
    EXPECT_EQ(changes(held, 1500.0, 0.02), 0u);
}

TEST(Cull, LodHysteresisHoldsTheLevelAtABoundary) {
    // Detailed below 100 m, coarse from 100 m; the eye hovers at 100 m +- 1% along x.
    TwoLevels two;
    auto &detailed = two.detailed, &coarse = two.coarse;
    auto& root = two.root;
    Scene s(root);
    s.update();
    auto cameraAt = [](double x) {
        Camera cam;
        cam.setViewport(200, 200);
        cam.setPerspective(60.0, 1.0, 1.0, 2000.0);
        cam.setLookAt(dvec3(x, 0, 0), dvec3(0, 0, 0), dvec3(0, 0, 1));
        return cam;
    };
    auto shows = [&](CullTraversal& t, double x, double h) {
        CullSettings set;
        set.lodHysteresis = h;
        DrawList l;
        CullStats st;
        t.cull(s, cameraAt(x), set, l, st);
        EXPECT_EQ(l.items.size(), 1u);
        return l.items.empty() ? nullptr : l.items[0].mesh;
    };
    // Without hysteresis the level flips every frame; with 2% it keeps the first one.
    CullTraversal plain, held;
    int flipsPlain = 0, flipsHeld = 0;
    const Mesh* lastPlain = shows(plain, 99.0, 0.0);
    const Mesh* lastHeld = shows(held, 99.0, 0.02);
    EXPECT_EQ(lastHeld, detailed->mesh());
    for (int f = 1; f < 40; ++f) {
        const double x = f % 2 ? 101.0 : 99.0;
        const Mesh* p = shows(plain, x, 0.0);
        const Mesh* q = shows(held, x, 0.02);
        flipsPlain += p != lastPlain;
        flipsHeld += q != lastHeld;
        lastPlain = p;
        lastHeld = q;
    }
    EXPECT_EQ(flipsPlain, 39);
    EXPECT_EQ(flipsHeld, 0);
    // Past the widened boundary it switches, and then holds the new level on the way back.
    EXPECT_EQ(shows(held, 103.0, 0.02), coarse->mesh());
    EXPECT_EQ(shows(held, 99.0, 0.02), coarse->mesh());
    EXPECT_EQ(shows(held, 97.0, 0.02), detailed->mesh());
    // A rebuilt image forgets what was shown (entries may have moved).
    root->addChild(make<Group>());
    s.update();
    EXPECT_EQ(shows(held, 99.0, 0.02), detailed->mesh());
    // Out of range: refused by name.
    CullSettings bad;
    bad.lodHysteresis = 1.5;
    DrawList l;
    CullStats st;
    EXPECT_THROW(held.cull(s, cameraAt(99.0), bad, l, st), std::invalid_argument);
}

TEST(Cull, LodScaleMakesEverythingLookFarther) {
    TwoLevels two;
    auto &detailed = two.detailed, &coarse = two.coarse;
    auto& root = two.root;
    Scene s(root);
    s.update();
    Camera cam;
    cam.setViewport(200, 200);
    cam.setPerspective(60.0, 1.0, 1.0, 2000.0);
    cam.setLookAt(dvec3(60, 0, 0), dvec3(0, 0, 0), dvec3(0, 0, 1));
    auto shown = [&](double scale) {
        CullSettings set;
        set.lodScale = scale;
        DrawList l;
        CullStats st;
        CullTraversal().cull(s, cam, set, l, st);
        return l.items.size() == 1 ? l.items[0].mesh : nullptr;
    };
    EXPECT_EQ(shown(1.0), detailed->mesh());  // 60 m
    EXPECT_EQ(shown(2.0), coarse->mesh());    // seen as 120 m
    EXPECT_EQ(shown(0.5), detailed->mesh());
    EXPECT_THROW(shown(0.0), std::invalid_argument);
    EXPECT_THROW(shown(std::nan("")), std::invalid_argument);
}

// Points and lines are culled by their bounds like triangles, and counted by kind.
TEST(Cull, PointsAndLinesAreCulledByTheirBoundsAndCounted) {
    auto points = make<Mesh>();
    points->setPoints({{-1, -1, -10}, {1, 1, -10}, {0, 0, -11}});
    auto lines = make<Mesh>();
    lines->setLines({{-1, 0, -10}, {1, 0, -10}, {1, 1, -10}}, {0, 1, 1, 2});
    auto behind = make<Mesh>();
    behind->setPoints({{0, 0, 10}, {1, 0, 10}});
    auto root = make<Group>();
    root->addChild(make<Geometry>(points, make<Material>()));
    root->addChild(make<Geometry>(lines, make<Material>()));
    root->addChild(make<Geometry>(behind, make<Material>()));
    Scene s(root);
    s.update();
    const Culled c = cullWith(s, lookingDownMinusZ(), CullStrategy::Aabb);
    EXPECT_EQ(c.list.items.size(), 2u);
    EXPECT_EQ(c.stats.points, 3u);
    EXPECT_EQ(c.stats.lines, 2u);
    EXPECT_EQ(c.stats.triangles, 0u);
}
