// Picking points and lines: hits within the cone about a ray (its width and slope, the nearest along the ray), a
// segment's nearest point, a scaled Transform, the PointBvh against brute force, featuresAt on a point and a segment,
// pickCone's numbers for a perspective and an orthographic camera.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Transform.h"
#include "sg/core/Camera.h"
#include "sg/intersect/HitFeatures.h"
#include "sg/intersect/IntersectTraversal.h"
#include "sg/intersect/PickCone.h"
#include "sg/intersect/PointBvh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

using namespace sg;

namespace {

ref_ptr<Geometry> points(std::vector<vec3> p) {
    auto m = make<Mesh>();
    m->setPoints(std::move(p));
    return make<Geometry>(m, make<Material>());
}

ref_ptr<Geometry> lines(std::vector<vec3> p, std::vector<uint32_t> indices) {
    auto m = make<Mesh>();
    m->setLines(std::move(p), std::move(indices));
    return make<Geometry>(m, make<Material>());
}

QueryOptions cone(double width, double slope) {
    QueryOptions o;
    o.coneWidth = width;
    o.coneSlope = slope;
    return o;
}

// The nearest hit of the ray on a scene of one node.
bool pick(ref_ptr<Node> node, const Ray& ray, const QueryOptions& o, Hit& h) {
    auto root = make<Group>();
    root->addChild(std::move(node));
    Scene scene(root);
    scene.update();
    IntersectTraversal it;
    const bool hit = it.intersect(scene, ray, o, h);
    if (hit && !h.path.empty() && h.path.front() == root.get()) h.path.erase(h.path.begin());  // dies on return
    return hit;
}

}  // namespace

TEST(PointPick, ARayThroughAPointHitsIt) {
    auto g = points({{3, 0, -5}, {0, 0, -5}});
    Hit h;
    ASSERT_TRUE(pick(g, Ray{dvec3(0), dvec3(0, 0, -1)}, cone(0.01, 0.0), h));
    EXPECT_EQ(h.primitive, 1u);
    EXPECT_EQ(h.geometry, g.get());
    EXPECT_NEAR(h.t, 5.0, 1e-12);
    EXPECT_NEAR(h.distance, 5.0, 1e-12);
    EXPECT_NEAR(glm::length(h.point - dvec3(0, 0, -5)), 0.0, 1e-12);
    EXPECT_EQ(h.normal, dvec3(0.0));
    EXPECT_EQ(h.u, 0.0);
    // Without a cone (the default) points are not hit.
    EXPECT_FALSE(pick(g, Ray{dvec3(0), dvec3(0, 0, -1)}, {}, h));
}

TEST(PointPick, WithinTheConesRadiusAtItsDistanceHitsBeyondMisses) {
    // Direction of length 2: the point at t = 5 is 10 along the ray, where the radius is 0.1 + 10 * 0.05 = 0.6.
    const Ray ray{dvec3(0), dvec3(0, 0, -2)};
    const QueryOptions o = cone(0.1, 0.05);
    Hit h;
    ASSERT_TRUE(pick(points({{0.9f * 0.6f, 0, -10}}), ray, o, h));
    EXPECT_NEAR(h.t, 5.0, 1e-12);
    EXPECT_NEAR(h.distance, std::sqrt(100.0 + 0.54 * 0.54), 1e-6);
    EXPECT_FALSE(pick(points({{1.1f * 0.6f, 0, -10}}), ray, o, h));
    // On the other side and along y likewise.
    EXPECT_TRUE(pick(points({{0, -0.9f * 0.6f, -10}}), ray, o, h));
    EXPECT_FALSE(pick(points({{0, -1.1f * 0.6f, -10}}), ray, o, h));
}

TEST(PointPick, TheNearerAlongTheRayWinsNotTheNearerToItsAxis) {
    // Point 0 on the axis at 10, point 1 off it by 0.3 at 6: both in a cone of width 0.5.
    auto g = points({{0, 0, -10}, {0.3f, 0, -6}});
    Hit h;
    ASSERT_TRUE(pick(g, Ray{dvec3(0), dvec3(0, 0, -1)}, cone(0.5, 0.0), h));
    EXPECT_EQ(h.primitive, 1u);
    EXPECT_NEAR(h.t, 6.0, 1e-12);
    // intersectAll: both, nearest first.
    auto root = make<Group>();
    root->addChild(g);
    Scene scene(root);
    scene.update();
    IntersectTraversal it;
    std::vector<Hit> all;
    it.intersectAll(scene, Ray{dvec3(0), dvec3(0, 0, -1)}, cone(0.5, 0.0), all);
    ASSERT_EQ(all.size(), 2u);
    EXPECT_EQ(all[0].primitive, 1u);
    EXPECT_EQ(all[1].primitive, 0u);
}

TEST(PointPick, ALineSegmentCrossedAtADistance) {
    // Segment 1 runs along x at y = 0.2, z = -8, from x = -1 to 3: the ray down -z passes it 0.2 away at x = 0.
    auto g = lines({{5, 5, -3}, {6, 5, -3}, {-1, 0.2f, -8}, {3, 0.2f, -8}}, {0, 1, 2, 3});
    Hit h;
    ASSERT_TRUE(pick(g, Ray{dvec3(0), dvec3(0, 0, -1)}, cone(0.25, 0.0), h));
    EXPECT_EQ(h.primitive, 1u);
    EXPECT_NEAR(h.t, 8.0, 1e-6);
    EXPECT_NEAR(h.u, 0.25, 1e-6);
    EXPECT_NEAR(glm::length(h.point - dvec3(0, 0.2, -8)), 0.0, 1e-6);
    EXPECT_EQ(h.normal, dvec3(0.0));
    EXPECT_FALSE(pick(g, Ray{dvec3(0), dvec3(0, 0, -1)}, cone(0.15, 0.0), h));
}

TEST(PointPick, ALineMeshUnderAScaledTransform) {
    // Local segment (-1, 0.1, 0)-(1, 0.1, 0), scaled by 2 and moved to z = -10: world y = 0.2, x in [-2, 2].
    auto t = make<Transform>(glm::scale(glm::translate(dmat4(1.0), dvec3(0, 0, -10)), dvec3(2.0)));
    t->addChild(lines({{-1, 0.1f, 0}, {1, 0.1f, 0}}, {0, 1}));
    Hit h;
    const Ray ray{dvec3(0.5, 0, 0), dvec3(0, 0, -1)};
    ASSERT_TRUE(pick(t, ray, cone(0.25, 0.0), h));
    EXPECT_NEAR(h.t, 10.0, 1e-6);
    EXPECT_NEAR(h.u, 0.625, 1e-6);  // local x 0.25 of [-1, 1]
    EXPECT_NEAR(glm::length(h.point - dvec3(0.5, 0.2, -10)), 0.0, 1e-6);
    // The cone is in world units: 0.2 away in the world (0.1 in the segment's frame) is outside a width of 0.15.
    EXPECT_FALSE(pick(t, ray, cone(0.15, 0.0), h));
}

TEST(PointPick, SpheresPassThroughPointsAndABadConeIsRefused) {
    auto root = make<Group>();
    root->addChild(points({{0, 0, -5}}));
    Scene scene(root);
    scene.update();
    IntersectTraversal it;
    std::vector<Hit> hits;
    it.intersectSphere(scene, dvec3(0, 0, -5), 1.0, cone(0.5, 0.0), hits);
    EXPECT_TRUE(hits.empty());
    Hit h;
    EXPECT_THROW(it.intersect(scene, Ray{dvec3(0), dvec3(0, 0, -1)}, cone(-0.1, 0.0), h), std::invalid_argument);
    EXPECT_THROW(it.intersect(scene, Ray{dvec3(0), dvec3(0, 0, -1)}, cone(0.1, kNaN), h), std::invalid_argument);
}

// The hierarchy's answer is brute force's (every primitive given the same exact test), for points and segments seen
// through a rotated, unevenly scaled frame, on 1000 random rays with random cones.
TEST(PointPick, TheBvhAgreesWithBruteForce) {
    std::mt19937_64 g(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::uniform_real_distribution<double> pos(0.0, 1.0);
    std::vector<vec3> p;
    for (int k = 0; k < 1000; ++k) p.emplace_back(float(10 * u(g)), float(10 * u(g)), float(10 * u(g)));
    std::vector<uint32_t> idx;
    for (uint32_t k = 0; k + 1 < 1000; k += 2) idx.insert(idx.end(), {k, (k * 7 + 3) % 1000});
    auto pm = make<Mesh>(), lm = make<Mesh>();
    pm->setPoints(p);
    lm->setLines(p, idx);
    const PointBvh pb(*pm), lb(*lm);
    const glm::dmat3 a = glm::dmat3(glm::rotate(dmat4(1.0), 0.7, glm::normalize(dvec3(1, 2, 3)))) *
                         glm::dmat3(glm::scale(dmat4(1.0), dvec3(1.0, 2.0, 0.5)));
    for (int r = 0; r < 1000; ++r) {
        PointBvh::Cone c;
        c.a = a;
        c.offset = dvec3(3, -2, 1);
        c.origin = dvec3(30 * u(g), 30 * u(g), 30 * u(g));
        c.direction = (dvec3(8 * u(g), 8 * u(g), 8 * u(g)) - c.origin) * (0.5 + pos(g));
        c.tMax = r % 3 == 0 ? kInf : 0.5 + 2.0 * pos(g);
        c.width = 0.5 * pos(g);
        c.slope = 0.05 * pos(g);
        for (const Mesh* m : {pm.get(), lm.get()}) {
            const bool isLines = m == lm.get();
            PointBvh::ConeHit best, h;
            bool found = false;
            size_t count = 0;
            for (uint32_t k = 0; k < (isLines ? m->lineCount() : m->pointCount()); ++k) {
                const dvec3 p0 = a * dvec3(p[isLines ? idx[2 * k] : k]) + c.offset;
                const bool hit = isLines
                                     ? PointBvh::hitSegment(c, c.tMax, p0, a * dvec3(p[idx[2 * k + 1]]) + c.offset, h)
                                     : PointBvh::hitPoint(c, c.tMax, p0, h);
                if (!hit) continue;
                ++count;
                if (!found || h.t < best.t) best = h, best.primitive = k, found = true;
            }
            const PointBvh& bvh = isLines ? lb : pb;
            PointBvh::ConeHit got;
            ASSERT_EQ(bvh.nearest(c, got), found) << "ray " << r << (isLines ? " lines" : " points");
            if (found) {
                // Segments that share an end tie when the ray passes nearest that end: either is the answer.
                EXPECT_EQ(got.t, best.t) << "ray " << r;
                if (got.primitive != best.primitive) {
                    const uint32_t k = got.primitive;
                    ASSERT_TRUE(isLines) << "ray " << r;
                    ASSERT_TRUE(PointBvh::hitSegment(c, c.tMax, a * dvec3(p[idx[2 * k]]) + c.offset,
                                                     a * dvec3(p[idx[2 * k + 1]]) + c.offset, h));
                    EXPECT_EQ(h.t, best.t) << "ray " << r;
                }
            }
            std::vector<PointBvh::ConeHit> all;
            bvh.all(c, all);
            EXPECT_EQ(all.size(), count) << "ray " << r;
        }
    }
}

TEST(PointPick, FeaturesAtAPointAndASegmentsNearerEnd) {
    auto f = make<MeshFeatures>();
    FeatureIdSet ids;
    ids.featureCount = 10;
    ids.ids = {7, 8, 9};
    f->sets.push_back(ids);
    auto pm = make<Mesh>();
    pm->setPoints({{0, 0, -5}, {1, 0, -5}, {2, 0, -5}});
    pm->setFeatures(f);
    auto g = make<Geometry>(pm, make<Material>());
    Hit h;
    ASSERT_TRUE(pick(g, Ray{dvec3(2, 0, 0), dvec3(0, 0, -1)}, cone(0.1, 0.0), h));
    ASSERT_EQ(h.primitive, 2u);
    HitFeatures at = featuresAt(h);
    ASSERT_EQ(at.features.size(), 1u);
    EXPECT_EQ(at.features[0].featureId, 9);
    // Segment 0 runs from vertex 2 to vertex 1: at u = 0.75 the nearer end is vertex 1 (id 8), at 0.25 vertex 2.
    auto lm = make<Mesh>();
    lm->setLines({{0, 0, -5}, {1, 0, -5}, {2, 0, -5}}, {2, 1});
    lm->setFeatures(f);
    auto lg = make<Geometry>(lm, make<Material>());
    Hit s;
    s.geometry = lg.get();
    s.path = {lg.get()};
    s.primitive = 0;
    s.u = 0.75;
    at = featuresAt(s);
    ASSERT_EQ(at.features.size(), 1u);
    EXPECT_EQ(at.features[0].featureId, 8);
    s.u = 0.25;
    EXPECT_EQ(featuresAt(s).features[0].featureId, 9);
    s.primitive = 1;  // no such segment
    EXPECT_TRUE(featuresAt(s).empty());
}

TEST(PointPick, PickConeForPerspectiveAndOrthographicCameras) {
    Camera persp;
    persp.setPerspective(60.0, 2.0, 0.5, 100.0);
    persp.setViewport(200, 100);
    // 3 pixels of 100 over 2 tan(30 deg) = 1.1547: slope 0.034641, width at the near plane 0.5 * slope.
    const PickCone p = pickCone(persp, 3.0);
    EXPECT_NEAR(p.coneSlope, 3.0 * 2.0 * std::tan(glm::radians(30.0)) / 100.0, 1e-12);
    EXPECT_NEAR(p.coneSlope, 0.0346410, 1e-6);
    EXPECT_NEAR(p.coneWidth, 0.5 * p.coneSlope, 1e-12);
    Camera ortho;
    ortho.setProjection(glm::ortho(-4.0, 4.0, -2.0, 2.0, 0.1, 10.0));
    ortho.setViewport(200, 100);
    // 4 units over 100 pixels: 3 pixels are 0.12 at any distance.
    const PickCone o = pickCone(ortho, 3.0);
    EXPECT_NEAR(o.coneWidth, 0.12, 1e-12);
    EXPECT_EQ(o.coneSlope, 0.0);
    EXPECT_EQ(pickCone(ortho, 0.0).coneWidth, 0.0);
    EXPECT_THROW(pickCone(persp, -1.0), std::invalid_argument);
    EXPECT_THROW(pickCone(persp, kInf), std::invalid_argument);
    EXPECT_THROW(pickCone(persp, kNaN), std::invalid_argument);
}
