// Picks on posed Geometries: a ray hits a skinned or morphed Geometry where its pose puts its triangles, not where its
// mesh has them, and reports the triangle of the Geometry's mesh.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Transform.h"
#include "sg/intersect/IntersectTraversal.h"
#include "sg/scene/Posing.h"

#include "SkinnedBar.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {
dmat4 move(const dvec3& t) { return glm::translate(dmat4(1.0), t); }

ref_ptr<Mesh> bar(bool blend = false) { return testutil::skinnedBar(blend); }
}  // namespace

TEST(PosedPick, RayHitsTheSkinnedPoseNotTheBindPose) {
    auto root = make<Group>();
    auto hip = make<Transform>(dmat4(1.0));
    auto knee = make<Transform>(move(dvec3(1, 0, 0)));
    hip->addChild(knee);
    auto g = make<Geometry>(bar(), make<Material>());
    g->setSkin(
        make<Skin>(std::vector<ref_ptr<Node>>{hip, knee}, std::vector<dmat4>{dmat4(1.0), move(dvec3(-1, 0, 0))}));
    auto far = make<Transform>(move(dvec3(100, 0, 0)));  // places nothing: the Geometry is skinned
    far->addChild(g);
    root->addChild(hip);
    root->addChild(far);
    // The knee turned a quarter about z: the bar's far half now runs from (1, 0) to (1, 1), 0.2 wide.
    knee->setMatrix(move(dvec3(1, 0, 0)) * glm::rotate(dmat4(1.0), glm::radians(90.0), dvec3(0, 0, 1)));
    Scene scene(root);
    scene.update();
    IntersectTraversal it;
    Hit h;
    ASSERT_TRUE(it.intersect(scene, Ray{dvec3(1.0, 0.6, 5.0), dvec3(0, 0, -1)}, {}, h));
    EXPECT_EQ(h.geometry, g.get());
    EXPECT_NEAR(glm::length(h.point - dvec3(1.0, 0.6, 0.1)), 0.0, 1e-5);
    EXPECT_NEAR(h.normal.z, 1.0, 1e-5);
    ASSERT_LT(h.primitive, g->mesh()->triangleCount());
    // The triangle named is the Geometry mesh's, as posed: its posed corners and the barycentrics give the point.
    ref_ptr<Mesh> posed = skinMesh(*g->mesh(), *makePose(*g));
    auto corner = [&](int k) { return dvec3(posed->positions()[g->mesh()->index(3 * size_t(h.primitive) + k)]); };
    const dvec3 p = (1 - h.u - h.v) * corner(0) + h.u * corner(1) + h.v * corner(2);
    EXPECT_NEAR(glm::length(p - h.point), 0.0, 1e-5);
    // Where the bind pose had the far half, nothing now.
    EXPECT_FALSE(it.intersect(scene, Ray{dvec3(1.6, 0.0, 5.0), dvec3(0, 0, -1)}, {}, h));
    // Turned back: the bind pose is hit again (the posed mesh kept for the last pose is not reused).
    knee->setMatrix(move(dvec3(1, 0, 0)));
    scene.update();
    ASSERT_TRUE(it.intersect(scene, Ray{dvec3(1.6, 0.0, 5.0), dvec3(0, 0, -1)}, {}, h));
    EXPECT_NEAR(glm::length(h.point - dvec3(1.6, 0.0, 0.1)), 0.0, 1e-5);
    EXPECT_FALSE(it.intersect(scene, Ray{dvec3(1.0, 0.6, 5.0), dvec3(0, 0, -1)}, {}, h));
}

TEST(PosedPick, RayHitsTheMorphedSurface) {
    // A square at z = 0, morphed up by 0.5 * 2, placed 10 down.
    auto m = make<Mesh>();
    m->set({vec3(-1, -1, 0), vec3(1, -1, 0), vec3(1, 1, 0), vec3(-1, 1, 0)},
           {vec3(0, 0, 1), vec3(0, 0, 1), vec3(0, 0, 1), vec3(0, 0, 1)}, {0, 1, 2, 0, 2, 3});
    MorphTarget up;
    up.positions.assign(4, vec3(0, 0, 2));
    m->setMorphTargets({up});
    auto g = make<Geometry>(m, make<Material>());
    g->setMorphWeights({0.5f});
    auto at = make<Transform>(move(dvec3(0, 0, -10)));
    at->addChild(g);
    Scene scene(at);
    scene.update();
    IntersectTraversal it;
    Hit h;
    ASSERT_TRUE(it.intersect(scene, Ray{dvec3(0.2, 0.3, 0.0), dvec3(0, 0, -1)}, {}, h));
    EXPECT_EQ(h.geometry, g.get());
    EXPECT_NEAR(h.t, 9.0, 1e-6);
    EXPECT_NEAR(glm::length(h.point - dvec3(0.2, 0.3, -9.0)), 0.0, 1e-6);
    EXPECT_LT(h.primitive, 2u);
    // The weight set to 0: the mesh as it is.
    g->setMorphWeights({0.0f});
    scene.update();
    ASSERT_TRUE(it.intersect(scene, Ray{dvec3(0.2, 0.3, 0.0), dvec3(0, 0, -1)}, {}, h));
    EXPECT_NEAR(h.t, 10.0, 1e-6);
}
