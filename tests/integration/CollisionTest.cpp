// ViewpointCollider: random walks at up to 100 m/s at 60 Hz through `city` and `office`, near the origin and
// 10,000 km from it: the eye sphere never ends a step intersecting collidable geometry (checked against
// every nearby triangle with an exact distance computed here, independently of the library).
#include "nodes/Geometry.h"
#include "nodes/LOD.h"
#include "nodes/Transform.h"
#include "sg/intersect/ViewpointCollider.h"
#include "testbed/City.h"
#include "testbed/Office.h"
#include "testbed/RandomScene.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {
struct WorldGeometry {
    Box box;
    std::vector<dvec3> tris;  // three per triangle, world
};

// Every collidable geometry as the collider should see it (LOD: the most detailed child), in world space.
void collect(Node* n, const dmat4& m, std::vector<WorldGeometry>& out) {
    if (!(n->nodeMask() & kCollidable)) return;
    if (n->kind() == NodeKind::Geometry) {
        const Mesh* mesh = static_cast<Geometry*>(n)->mesh();
        WorldGeometry g;
        for (uint32_t i = 0; i < mesh->indexCount(); ++i) {
            g.tris.push_back(dvec3(m * dvec4(dvec3(mesh->positions()[mesh->index(i)]), 1.0)));
            g.box.expand(g.tris.back());
        }
        out.push_back(std::move(g));
        return;
    }
    const dmat4 mm = n->kind() == NodeKind::Transform ? static_cast<Transform*>(n)->apply(m) : m;
    const size_t k = n->kind() == NodeKind::LOD ? std::min<size_t>(1, n->numChildren()) : n->numChildren();
    for (size_t i = 0; i < k; ++i) collect(n->child(i), mm, out);
}

double segmentDistance(const dvec3& p, const dvec3& a, const dvec3& b) {
    const dvec3 ab = b - a;
    const double l2 = glm::dot(ab, ab);
    const double s = l2 > 0 ? std::min(1.0, std::max(0.0, glm::dot(p - a, ab) / l2)) : 0.0;
    return glm::length(p - (a + ab * s));
}

// Distance from p to triangle abc: to its plane when the foot falls inside, else to the nearest edge.
double triangleDistance(const dvec3& p, const dvec3& a, const dvec3& b, const dvec3& c) {
    const dvec3 n = glm::cross(b - a, c - a);
    const double n2 = glm::dot(n, n);
    if (n2 > 0) {
        const dvec3 foot = p - n * (glm::dot(p - a, n) / n2);
        const double s1 = glm::dot(glm::cross(b - a, foot - a), n), s2 = glm::dot(glm::cross(c - b, foot - b), n),
                     s3 = glm::dot(glm::cross(a - c, foot - c), n);
        if (s1 >= 0 && s2 >= 0 && s3 >= 0) return std::abs(glm::dot(p - a, n)) / std::sqrt(n2);
    }
    return std::min({segmentDistance(p, a, b), segmentDistance(p, b, c), segmentDistance(p, c, a)});
}

double nearestDistance(const std::vector<WorldGeometry>& geoms, const dvec3& p, double reach) {
    double best = kInf;
    for (const auto& g : geoms) {
        const dvec3 q = glm::clamp(p, g.box.min, g.box.max);
        if (glm::length(p - q) > reach) continue;
        for (size_t k = 0; k < g.tris.size(); k += 3)
            best = std::min(best, triangleDistance(p, g.tris[k], g.tris[k + 1], g.tris[k + 2]));
    }
    return best;
}

struct WalkResult {
    int steps = 0, failures = 0, contactSteps = 0, groundedSteps = 0;
    double travelled = 0.0;
};

// Random walk in `region`: a new heading toward a random point and a speed in [0, 100] m/s every 30 steps.
WalkResult randomWalk(const Scene& scene, const std::vector<WorldGeometry>& geoms, const Box& region,
                      const ViewpointSettings& vs, uint64_t seed, int steps) {
    scenes::Rng rng(seed);
    ViewpointCollider col(vs);
    auto randomPoint = [&] {
        return dvec3(rng.uniform(region.min.x, region.max.x), rng.uniform(region.min.y, region.max.y),
                     rng.uniform(region.min.z, region.max.z));
    };
    dvec3 pos = randomPoint();
    while (nearestDistance(geoms, pos, vs.radius + 0.1) < vs.radius + 0.1) pos = randomPoint();
    dvec3 target = pos;
    double speed = 0.0;
    WalkResult r;
    for (int s = 0; s < steps; ++s) {
        if (s % 30 == 0) {
            target = randomPoint();
            speed = rng.uniform(0, 100);
        }
        dvec3 dir = target - pos + dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
        if (vs.groundFollow) dir.z = 0;
        const double len = glm::length(dir);
        const dvec3 step = len > 0 ? dir / len * (speed / 60.0) : dvec3(0.0);
        const dvec3 to = col.move(scene, pos, step);
        r.steps++;
        const double d = nearestDistance(geoms, to, vs.radius);
        if (d < vs.radius) {
            if (++r.failures <= 3)
                ADD_FAILURE() << "step " << s << " (seed " << seed << ") ends intersecting: distance " << d
                              << " < radius " << vs.radius << "; from (" << pos.x << ", " << pos.y << ", " << pos.z
                              << ") step (" << step.x << ", " << step.y << ", " << step.z << ") to (" << to.x << ", "
                              << to.y << ", " << to.z << ")";
        }
        if (col.lastStats().contacts) r.contactSteps++;
        if (col.lastStats().grounded) r.groundedSteps++;
        r.travelled += glm::length(to - pos);
        pos = to;
    }
    return r;
}

ref_ptr<Node> moved(ref_ptr<Node> root, const dvec3& offset) {
    auto t = make<Transform>(glm::translate(dmat4(1.0), offset));
    t->addChild(std::move(root));
    return t;
}

void walkScene(ref_ptr<Node> content, const Box& localRegion, double radius, const dvec3& offset, uint64_t seed,
               bool ground = false) {
    ref_ptr<Node> root = moved(std::move(content), offset);
    Scene scene(root);
    scene.update();
    std::vector<WorldGeometry> geoms;
    collect(root.get(), dmat4(1.0), geoms);
    ViewpointSettings vs;
    vs.radius = radius;
    vs.groundFollow = ground;
    vs.eyeHeight = 1.6;
    const Box region{localRegion.min + offset, localRegion.max + offset};
    const int steps = ground ? 3000 : 10000;
    const WalkResult r = randomWalk(scene, geoms, region, vs, seed, steps);
    std::printf("[ collision ] %d steps, %d with contacts, %d grounded, %.0f m travelled, %d ending inside geometry\n",
                r.steps, r.contactSteps, r.groundedSteps, r.travelled, r.failures);
    EXPECT_EQ(r.failures, 0);
    // Not vacuous: the walk met geometry often and still moved.
    EXPECT_GT(r.contactSteps, steps / 20);
    EXPECT_GT(r.travelled, steps * 0.05);
    if (ground) {
        EXPECT_GT(r.groundedSteps, steps * 9 / 10);
    }
}

const dvec3 kFar(1e7, -4e6, 3e5);
}  // namespace

TEST(Collision, CityRandomWalk) {
    walkScene(scenes::buildCity({12, false}), Box{dvec3(-20, -20, 0.3), dvec3(260, 260, 70)}, 0.3, dvec3(0.0), 1);
}
TEST(Collision, CityRandomWalkFarFromOrigin) {
    walkScene(scenes::buildCity({12, false}), Box{dvec3(-20, -20, 0.3), dvec3(260, 260, 70)}, 0.3, kFar, 2);
}
TEST(Collision, OfficeRandomWalk) {
    walkScene(scenes::buildOffice(4), Box{dvec3(0.3, 0.3, 0.4), dvec3(23.7, 23.7, 2.6)}, 0.25, dvec3(0.0), 3);
}
TEST(Collision, OfficeRandomWalkFarFromOrigin) {
    walkScene(scenes::buildOffice(4), Box{dvec3(0.3, 0.3, 0.4), dvec3(23.7, 23.7, 2.6)}, 0.25, kFar, 4);
}
TEST(Collision, OfficeGroundFollowing) {
    walkScene(scenes::buildOffice(4), Box{dvec3(0.3, 0.3, 1.6), dvec3(23.7, 23.7, 1.6)}, 0.25, dvec3(0.0), 5, true);
}

TEST(Collision, GroundFollowingClimbsStairs) {
    // Ten 0.15 m steps, 0.3 m deep: the eye rises with them and keeps its height above each.
    auto root = make<Group>();
    for (int k = 0; k < 10; ++k)
        root->addChild(make<Geometry>(makeBoxMesh(dvec3(0.3 * k, -1, -1), dvec3(0.3 * k + 0.3, 1, 0.15 * (k + 1))),
                                      make<Material>()));
    root->addChild(make<Geometry>(makeBoxMesh(dvec3(-5, -1, -1), dvec3(0, 1, 0)), make<Material>()));
    Scene scene(root);
    scene.update();
    ViewpointSettings vs;
    vs.groundFollow = true;
    vs.eyeHeight = 1.6;
    vs.radius = 0.3;
    ViewpointCollider col(vs);
    dvec3 p(-3, 0, 1.6);
    for (int s = 0; s < 250; ++s) {
        p = col.move(scene, p, dvec3(0.02, 0, 0));
        EXPECT_TRUE(col.lastStats().grounded);
    }
    EXPECT_NEAR(p.x, 2.0, 1e-6);
    EXPECT_NEAR(p.z, 0.15 * 7 + 1.6, 1e-6);  // on the seventh step, x in [1.8, 2.1]
}

TEST(Collision, SlidesAlongAWall) {
    auto root = make<Group>();
    root->addChild(make<Geometry>(makeBoxMesh(dvec3(0, -50, -50), dvec3(1, 50, 50)), make<Material>()));
    Scene scene(root);
    scene.update();
    ViewpointCollider col;  // radius 0.3
    const dvec3 p = col.move(scene, dvec3(-0.5, 0, 0), dvec3(1, 1, 0));
    EXPECT_NEAR(p.x, -0.3 - 1.5 * col.settings().skin, 1e-9);  // stopped at radius + skin, then half a skin away
    EXPECT_NEAR(p.y, 1.0, 1e-9);                               // the part along the wall is kept whole
    EXPECT_EQ(col.lastStats().contacts, 1);
    // However fast, never through: 0.2 m thick at 1000 m per step.
    auto thin = make<Group>();
    thin->addChild(make<Geometry>(makeBoxMesh(dvec3(0, -5, -5), dvec3(0.2, 5, 5)), make<Material>()));
    Scene s2(thin);
    s2.update();
    EXPECT_LT(col.move(s2, dvec3(-1, 0, 0), dvec3(1000, 0, 0)).x, -0.3);
}

TEST(Collision, BadSettingsRefused) {
    ViewpointSettings vs;
    vs.radius = -1;
    try {
        ViewpointCollider c(vs);
        FAIL();
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "ViewpointCollider::ViewpointCollider(): radius -1.000000 is negative or not finite");
    }
    ViewpointCollider c;
    Scene scene(make<Group>());
    scene.update();
    EXPECT_THROW(c.move(scene, dvec3(kNaN), dvec3(0)), std::invalid_argument);
}
