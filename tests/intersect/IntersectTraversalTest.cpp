// IntersectTraversal: hits, paths and results; masks, Switch, LOD, Billboard and Instance as the cull sees
// them; all hits in order; spheres and swept spheres; bad input refused; far from the origin.
#include "nodes/Billboard.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/PagedLOD.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"
#include "sg/intersect/IntersectTraversal.h"
#include "sg/intersect/PickSet.h"
#include "sg/intersect/internal/IntersectPrimitives.h"

#include <gtest/gtest.h>

#include <functional>
#include <set>

using namespace sg;

namespace {
ref_ptr<Geometry> unitBox() { return make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1), 2), make<Material>()); }

ref_ptr<Transform> at(const dvec3& p, ref_ptr<Node> child) {
    auto t = make<Transform>(glm::translate(dmat4(1.0), p));
    t->addChild(std::move(child));
    return t;
}

void expectThrowsWith(const std::function<void()>& f, const std::string& start) {
    try {
        f();
        FAIL() << "no exception, expected one starting with " << start;
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()).rfind(start, 0), 0u) << e.what();
    }
}
}  // namespace

TEST(Intersect, NearestHitPointNormalPathBarycentrics) {
    auto root = make<Group>();
    auto near = unitBox(), far = unitBox();
    auto tNear = at(dvec3(0, 0, -5), near);
    root->addChild(tNear);
    root->addChild(at(dvec3(0, 0, -10), far));
    Scene scene(root);
    scene.update();
    IntersectTraversal it;
    Hit h;
    ASSERT_TRUE(it.intersect(scene, Ray{dvec3(0.25, 0.5, 0), dvec3(0, 0, -1)}, {}, h));
    EXPECT_NEAR(h.t, 4.0, 1e-12);
    EXPECT_NEAR(h.distance, 4.0, 1e-12);
    EXPECT_NEAR(glm::length(h.point - dvec3(0.25, 0.5, -4)), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(h.normal - dvec3(0, 0, 1)), 0.0, 1e-12);
    EXPECT_EQ(h.geometry, near.get());
    ASSERT_EQ(h.path.size(), 3u);
    EXPECT_EQ(h.path[0], root.get());
    EXPECT_EQ(h.path[1], tNear.get());
    EXPECT_EQ(h.path[2], near.get());
    EXPECT_EQ(h.instance, nullptr);
    // The barycentrics rebuild the hit point from the triangle.
    const Mesh& m = *near->mesh();
    const dvec3 p0(m.positions()[m.index(3 * h.primitive)]), p1(m.positions()[m.index(3 * h.primitive + 1)]),
        p2(m.positions()[m.index(3 * h.primitive + 2)]);
    const dvec3 local = (1 - h.u - h.v) * p0 + h.u * p1 + h.v * p2 + dvec3(0, 0, -5);
    EXPECT_NEAR(glm::length(local - h.point), 0.0, 1e-9);
    // A segment that stops short misses.
    EXPECT_FALSE(it.intersect(scene, segment(dvec3(0.25, 0.5, 0), dvec3(0.25, 0.5, -3.9)), {}, h));
}

TEST(Intersect, AllHitsInOrder) {
    auto root = make<Group>();
    for (int k = 0; k < 5; ++k) root->addChild(at(dvec3(0, 0, -5.0 * (5 - k)), unitBox()));
    Scene scene(root);
    scene.update();
    IntersectTraversal it;
    std::vector<Hit> hits;
    it.intersectAll(scene, Ray{dvec3(0.3, 0.1, 0), dvec3(0, 0, -1)}, {}, hits);
    ASSERT_EQ(hits.size(), 10u);  // in and out of each box
    for (size_t k = 1; k < hits.size(); ++k) EXPECT_LE(hits[k - 1].t, hits[k].t);
    EXPECT_NEAR(hits[0].t, 4.0, 1e-12);
    EXPECT_NEAR(hits[9].t, 26.0, 1e-12);
}

TEST(Intersect, MasksSwitchAndLod) {
    auto root = make<Group>();
    auto hidden = unitBox();
    hidden->setNodeMask(kCollidable);  // collidable, not pickable
    root->addChild(at(dvec3(0, 0, -5), hidden));
    auto sw = make<Switch>();
    auto off = unitBox(), on = unitBox();
    sw->addChild(at(dvec3(0, 0, -10), off), false);
    sw->addChild(at(dvec3(0, 0, -15), on), true);
    root->addChild(sw);
    Scene scene(root);
    scene.update();
    IntersectTraversal it;
    Hit h;
    ASSERT_TRUE(it.intersect(scene, Ray{dvec3(0), dvec3(0, 0, -1)}, {}, h));
    EXPECT_EQ(h.geometry, on.get());
    QueryOptions col;
    col.traversalMask = kCollidable;
    ASSERT_TRUE(it.intersect(scene, Ray{dvec3(0), dvec3(0, 0, -1)}, col, h));
    EXPECT_EQ(h.geometry, hidden.get());

    // LOD: the highest level by default, the drawn one for a camera.
    auto lodRoot = make<Group>();
    auto lod = make<LOD>();
    auto detailed = unitBox(), coarse = unitBox();
    lod->addChild(detailed, 0.0f, 20.0f);
    lod->addChild(coarse, 20.0f, 1000.0f);
    lod->setCenter(dvec3(0));
    lodRoot->addChild(at(dvec3(0, 0, -50), lod));
    Scene s2(lodRoot);
    s2.update();
    ASSERT_TRUE(it.intersect(s2, Ray{dvec3(0), dvec3(0, 0, -1)}, {}, h));
    EXPECT_EQ(h.geometry, detailed.get());
    Camera cam;
    cam.setLookAt(dvec3(0), dvec3(0, 0, -1), dvec3(0, 1, 0));
    QueryOptions drawn;
    drawn.camera = &cam;
    drawn.lod = LodChoice::AsDrawn;
    ASSERT_TRUE(it.intersect(s2, Ray{dvec3(0), dvec3(0, 0, -1)}, drawn, h));
    EXPECT_EQ(h.geometry, coarse.get());
    cam.setLookAt(dvec3(0, 0, -40), dvec3(0, 0, -41), dvec3(0, 1, 0));
    ASSERT_TRUE(it.intersect(s2, Ray{dvec3(0, 0, -40), dvec3(0, 0, -1)}, drawn, h));
    EXPECT_EQ(h.geometry, detailed.get());
}

TEST(Intersect, AsDrawnWithoutCameraMeasuresFromTheQueryOrigin) {
    // A distance LOD 50 m down -z: seen from the origin the coarse child (20 m and beyond), from 10 m away
    // the detailed one; a pixel-size LOD has no pixels without a camera: its finest child.
    auto root = make<Group>();
    auto lod = make<LOD>();
    auto detailed = unitBox(), coarse = unitBox();
    lod->addChild(detailed, 0.0f, 20.0f);
    lod->addChild(coarse, 20.0f, 1000.0f);
    lod->setCenter(dvec3(0));
    root->addChild(at(dvec3(0, 0, -50), lod));
    auto pixels = make<LOD>();
    auto big = unitBox(), small = unitBox();
    pixels->setMode(LOD::Mode::PixelSize);
    pixels->addChild(small, 0.0f, 100.0f);
    pixels->addChild(big, 100.0f, 1e6f);
    root->addChild(at(dvec3(10, 0, -500), pixels));
    Scene scene(root);
    scene.update();
    IntersectTraversal it;
    QueryOptions drawn;
    drawn.lod = LodChoice::AsDrawn;
    Hit h;
    ASSERT_TRUE(it.intersect(scene, Ray{dvec3(0), dvec3(0, 0, -1)}, drawn, h));
    EXPECT_EQ(h.geometry, coarse.get());
    ASSERT_TRUE(it.intersect(scene, Ray{dvec3(0, 0, -40), dvec3(0, 0, -1)}, drawn, h));
    EXPECT_EQ(h.geometry, detailed.get());
    drawn.lodScale = 3.0;  // 30 m look like 90: coarse again
    ASSERT_TRUE(it.intersect(scene, Ray{dvec3(0, 0, -20), dvec3(0, 0, -1)}, drawn, h));
    EXPECT_EQ(h.geometry, coarse.get());
    std::vector<Hit> hits;
    it.intersectSphere(scene, dvec3(0, 0, -44), 6.0, drawn, hits);  // 6 m away, scaled to 18: detailed
    ASSERT_FALSE(hits.empty());
    for (const Hit& s : hits) EXPECT_EQ(s.geometry, detailed.get());
    ASSERT_TRUE(it.intersect(scene, Ray{dvec3(10, 0, 0), dvec3(0, 0, -1)}, drawn, h));
    EXPECT_EQ(h.geometry, big.get());
}

TEST(Intersect, BillboardFacesTheEye) {
    // A thin panel facing -Y; turned toward an eye on +X it blocks a ray along -X.
    auto root = make<Group>();
    auto bb = make<Billboard>();
    bb->addChild(make<Geometry>(makeBoxMesh(dvec3(-2, -0.01, -2), dvec3(2, 0.01, 2)), make<Material>()));
    root->addChild(bb);
    Scene scene(root);
    scene.update();
    IntersectTraversal it;
    Hit h;
    ASSERT_TRUE(it.intersect(scene, Ray{dvec3(10, 0, 0), dvec3(-1, 0, 0)}, {}, h));
    EXPECT_NEAR(h.t, 10.0 - 0.01, 1e-9);
    // Seen from +X by a camera, a ray from the side along -Y meets its edge only (0.02 thick at x = 0).
    Camera cam;
    cam.setLookAt(dvec3(10, 0, 0), dvec3(0), dvec3(0, 0, 1));
    QueryOptions o;
    o.camera = &cam;
    EXPECT_FALSE(it.intersect(scene, Ray{dvec3(1, 10, 0), dvec3(0, -1, 0)}, o, h));
    EXPECT_TRUE(it.intersect(scene, Ray{dvec3(0, 10, 0), dvec3(0, -1, 0)}, o, h));
}

TEST(Intersect, EveryInstancePlacement) {
    auto proto = make<Group>();
    auto g = unitBox();
    proto->addChild(at(dvec3(0, 0, 1), g));
    auto root = make<Group>();
    std::vector<ref_ptr<Instance>> placed;
    for (int k = 0; k < 4; ++k) {
        placed.push_back(
            make<Instance>(proto, glm::scale(glm::translate(dmat4(1.0), dvec3(10.0 * k, 0, 0)), dvec3(1, 1, 2))));
        root->addChild(placed.back());
    }
    Scene scene(root);
    scene.update();
    IntersectTraversal it;
    std::set<uint32_t> placements;
    for (int k = 0; k < 4; ++k) {
        Hit h;
        ASSERT_TRUE(it.intersect(scene, Ray{dvec3(10.0 * k, 0, 20), dvec3(0, 0, -1)}, {}, h));
        EXPECT_NEAR(h.point.z, 4.0, 1e-12);  // (1 + 1) * 2
        EXPECT_EQ(h.instance, placed[size_t(k)].get());
        EXPECT_EQ(h.geometry, g.get());
        ASSERT_GE(h.path.size(), 3u);
        EXPECT_EQ(h.path[1], placed[size_t(k)].get());
        EXPECT_EQ(h.path[2], proto.get());
        placements.insert(h.placement);
    }
    EXPECT_EQ(placements.size(), 4u);
}

// The images of the prototypes placed in a paged detail are the detail image's own (built with it, on a loader
// thread too): a pick finds them there, for a placement and a nested one.
TEST(Intersect, InstancesInsideAPagedDetailAreHitWhetherItsImageWasBuiltAheadOrByTheUpdate) {
    for (const bool ahead : {false, true}) {
        SCOPED_TRACE(ahead ? "built ahead" : "built by the update");
        auto g = unitBox();
        auto lod = make<LOD>();
        lod->addChild(g, 0.0f, 1e9f);
        auto outer = make<Group>();  // a prototype placing another
        auto inner = make<Instance>(lod, glm::translate(dmat4(1.0), dvec3(0, 0, 1)));
        outer->addChild(inner);
        auto detail = make<Group>();
        auto placed = make<Instance>(lod, glm::translate(dmat4(1.0), dvec3(0, 0, -10)));
        detail->addChild(placed);
        detail->addChild(make<Instance>(outer, glm::translate(dmat4(1.0), dvec3(5, 0, -10))));
        auto paged = make<PagedLOD>();
        paged->setFile("tile");
        paged->setRange(0.0f, 1e9f);
        paged->addChild(at(dvec3(0, 50, 0), unitBox()));  // the coarse level, off the rays
        const dmat4 frame = glm::translate(dmat4(1.0), dvec3(100, 0, 0));
        auto placedPaged = make<Transform>(frame);
        placedPaged->addChild(paged);
        auto root = make<Group>();
        root->addChild(placedPaged);
        Scene scene(root);
        scene.update();
        if (ahead) {
            std::shared_ptr<FlatImage> image = Scene::buildDetailImage(*detail, frame);
            ASSERT_TRUE(image);
            scene.offerDetailImage(paged.get(), detail.get(), frame, std::move(image));
        }
        paged->attachDetail(detail, 0);
        scene.update();

        IntersectTraversal it;
        Hit h;
        ASSERT_TRUE(it.intersect(scene, Ray{dvec3(100.25, 0.5, 0), dvec3(0, 0, -1)}, {}, h));
        EXPECT_NEAR(h.point.z, -9.0, 1e-12);
        EXPECT_EQ(h.geometry, g.get());
        EXPECT_EQ(h.instance, placed.get());
        ASSERT_TRUE(it.intersect(scene, Ray{dvec3(105.25, 0.5, 0), dvec3(0, 0, -1)}, {}, h));
        EXPECT_NEAR(h.point.z, -8.0, 1e-12);
        EXPECT_EQ(h.geometry, g.get());
        EXPECT_EQ(h.instance, inner.get());
    }
}

TEST(Intersect, SpheresAndSweeps) {
    auto root = make<Group>();
    root->addChild(at(dvec3(0), unitBox()));
    Scene scene(root);
    scene.update();
    IntersectTraversal it;
    std::vector<Hit> hits;
    it.intersectSphere(scene, dvec3(0, 0, 1.5), 0.6, {}, hits);
    ASSERT_FALSE(hits.empty());
    EXPECT_NEAR(hits[0].distance, 0.5, 1e-12);
    it.intersectSphere(scene, dvec3(0, 0, 1.5), 0.4, {}, hits);
    EXPECT_TRUE(hits.empty());
    // A fast sphere across the box: stopped at its face, however far it would have gone.
    SweepHit s;
    ASSERT_TRUE(it.sweepSphere(scene, dvec3(-10, 0.2, 0.1), 0.5, dvec3(1000, 0, 0), {}, s));
    EXPECT_NEAR(-10 + 1000 * s.t, -1.5, 1e-9);
    EXPECT_NEAR(glm::length(s.normal - dvec3(-1, 0, 0)), 0.0, 1e-9);
    // Past an edge: contact on the edge, the normal toward the centre.
    ASSERT_TRUE(it.sweepSphere(scene, dvec3(-10, 0, 1.3), 0.5, dvec3(20, 0, 0), {}, s));
    EXPECT_NEAR(glm::length(s.point - dvec3(-1, s.point.y, 1)), 0.0, 1e-9);
    EXPECT_FALSE(it.sweepSphere(scene, dvec3(-10, 0, 1.6), 0.5, dvec3(20, 0, 0), {}, s));
}

TEST(Intersect, FarFromOrigin) {
    const dvec3 far(1e7, -3e6, 2e5);
    auto root = make<Group>();
    auto inner = make<Transform>(glm::rotate(glm::translate(dmat4(1.0), far), 0.3, dvec3(0, 0, 1)));
    inner->addChild(unitBox());
    root->addChild(inner);
    Scene scene(root);
    scene.update();
    IntersectTraversal it;
    Hit h;
    ASSERT_TRUE(it.intersect(scene, Ray{far + dvec3(0.123, 0.2, 50), dvec3(0, 0, -1)}, {}, h));
    EXPECT_NEAR(h.point.z - far.z, 1.0, 1e-8);
    EXPECT_NEAR(h.point.x - far.x, 0.123, 1e-8);
    SweepHit s;
    ASSERT_TRUE(it.sweepSphere(scene, far + dvec3(0.1, 0.1, 3), 0.5, dvec3(0, 0, -10), {}, s));
    EXPECT_NEAR(3 - 10 * s.t, 1.5, 1e-7);
}

TEST(Intersect, BadInputRefused) {
    Scene scene(make<Group>());
    scene.update();
    IntersectTraversal it;
    Hit h;
    expectThrowsWith(
        [&] {
            it.intersect(scene, Ray{dvec3(kNaN, 0, 0), dvec3(0, 0, 1)}, {}, h);
        },
        "IntersectTraversal::intersect(): ray origin");
    expectThrowsWith(
        [&] {
            it.intersect(scene, Ray{dvec3(0), dvec3(0)}, {}, h);
        },
        "IntersectTraversal::intersect(): ray direction (0.000000, 0.000000, 0.000000) has zero length");
    expectThrowsWith(
        [&] {
            it.intersect(scene, Ray{dvec3(0), dvec3(1, 0, 0), -1.0}, {}, h);
        },
        "IntersectTraversal::intersect(): ray tMax -1");
    std::vector<Hit> hits;
    expectThrowsWith([&] { it.intersectSphere(scene, dvec3(0), -1.0, {}, hits); },
                     "IntersectTraversal::intersectSphere(): radius -1");
    SweepHit s;
    expectThrowsWith([&] { it.sweepSphere(scene, dvec3(0), 1.0, dvec3(kNaN), {}, s); },
                     "IntersectTraversal::sweepSphere(): motion");
    expectThrowsWith([&] { pixelRay(Camera(), kNaN, 0); }, "pixelRay(): pixel");
    PickSet ps;
    expectThrowsWith([&] { ps.add(nullptr); }, "PickSet::add(): node is null");
}

TEST(Intersect, PickSetReturnsTheRegisteredAncestor) {
    auto root = make<Group>();
    auto region = make<Group>();
    auto part = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 0, -10)));
    part->addChild(unitBox());
    region->addChild(part);
    root->addChild(region);
    Scene scene(root);
    scene.update();
    Camera cam;
    cam.setViewport(100, 100);
    cam.setPerspective(60, 1, 1, 100);
    cam.setLookAt(dvec3(0), dvec3(0, 0, -1), dvec3(0, 1, 0));
    PickSet ps;
    IntersectTraversal it;
    EXPECT_EQ(ps.pick(it, scene, cam, 50, 50).object, nullptr);
    ps.add(region.get());
    const auto r = ps.pick(it, scene, cam, 50, 50);
    EXPECT_TRUE(r.hit);
    EXPECT_EQ(r.object, region.get());
    EXPECT_NEAR(r.nearest.point.z, -9.0, 1e-9);
    ps.add(part.get());
    EXPECT_EQ(ps.pick(it, scene, cam, 50, 50).object, part.get());
    region->setName("region 7");
    EXPECT_EQ(pathString(r.nearest.path), "Group / Group 'region 7' / Transform / Geometry");
    EXPECT_FALSE(ps.pick(it, scene, cam, 2, 2).hit);  // the corner pixel sees past the box
}

TEST(Intersect, BvhFollowsAMeshThatWasSetAgain) {
    auto g = unitBox();
    auto root = make<Group>();
    root->addChild(g);
    Scene scene(root);
    scene.update();
    IntersectTraversal it;
    Hit h;
    ASSERT_TRUE(it.intersect(scene, Ray{dvec3(0, 0, 10), dvec3(0, 0, -1)}, {}, h));
    EXPECT_NEAR(h.point.z, 1.0, 1e-12);
    auto bigger = makeBoxMesh(dvec3(-3), dvec3(3));
    g->mesh()->set(bigger->positions(), bigger->normals(),
                   std::vector<uint32_t>(bigger->indices16().begin(), bigger->indices16().end()));
    g->setMesh(g->mesh());  // marks the bound dirty
    scene.update();
    ASSERT_TRUE(it.intersect(scene, Ray{dvec3(0, 0, 10), dvec3(0, 0, -1)}, {}, h));
    EXPECT_NEAR(h.point.z, 3.0, 1e-12);
    EXPECT_EQ(it.bvhCache().size(), 1u);
}
