// Posing: skin matrices, morphing, the pose's box and its reuse of the morphed mesh; the update's posed entries, what a
// moved joint costs it, and a joint that holds its own skinned Geometry refused.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Transform.h"
#include "sg/scene/Posing.h"
#include "sg/scene/Scene.h"

#include "SkinnedBar.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <string>

using namespace sg;

namespace {
void expectNearMatrix(const dmat4& a, const dmat4& b, double tol) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) EXPECT_NEAR(a[c][r], b[c][r], tol) << "element [" << c << "][" << r << "]";
}

dmat4 rotZ(double degrees) { return glm::rotate(dmat4(1.0), glm::radians(degrees), dvec3(0, 0, 1)); }
dmat4 move(const dvec3& t) { return glm::translate(dmat4(1.0), t); }

ref_ptr<Mesh> bar(bool blend = false) { return testutil::skinnedBar(blend); }

// A skeleton (hip at `where`, knee 1 along x below it) and beside it a bar skinned by it, under `root`.
struct Figure {
    ref_ptr<Group> root = make<Group>();
    ref_ptr<Transform> hip, knee;
    ref_ptr<Geometry> geometry;
};

Figure figure(const dvec3& where = dvec3(0.0), bool blend = false) {
    Figure f;
    f.hip = make<Transform>(move(where));
    f.hip->setName("hip");
    f.knee = make<Transform>(move(dvec3(1, 0, 0)));
    f.hip->addChild(f.knee);
    f.geometry = make<Geometry>(bar(blend), make<Material>());
    f.geometry->setSkin(make<Skin>(std::vector<ref_ptr<Node>>{f.hip, f.knee},
                                   std::vector<dmat4>{move(-where), move(-where - dvec3(1, 0, 0))}));
    f.root->addChild(f.hip);
    f.root->addChild(f.geometry);
    return f;
}
}  // namespace

TEST(Posing, SkinMatricesAreTheJointsPathsTimesTheirInverseBinds) {
    auto above = make<Transform>(move(dvec3(5, 0, 0)));  // not a joint: still on the joints' paths
    auto j0 = make<Transform>(move(dvec3(0, 2, 0)) * rotZ(90));
    auto j1 = make<Transform>(move(dvec3(1, 0, 0)));
    above->addChild(j0);
    j0->addChild(j1);
    const dmat4 ib0 = move(dvec3(0, 0, -1)), ib1 = glm::scale(dmat4(1.0), dvec3(2.0));
    Skin skin({j0, j1}, {ib0, ib1});
    const std::vector<dmat4> m = skinMatrices(skin);
    ASSERT_EQ(m.size(), 2u);
    const dmat4 w0 = move(dvec3(5, 0, 0)) * move(dvec3(0, 2, 0)) * rotZ(90), w1 = w0 * move(dvec3(1, 0, 0));
    expectNearMatrix(m[0], w0 * ib0, 1e-12);
    expectNearMatrix(m[1], w1 * ib1, 1e-12);
    expectNearMatrix(worldMatrix(*j1), w1, 1e-12);
    // The knee's world origin: (5, 2, 0) plus x turned to y.
    EXPECT_NEAR(glm::length(dvec3(worldMatrix(*j1)[3]) - dvec3(5, 3, 0)), 0.0, 1e-12);
}

TEST(Posing, MorphMeshAddsWeightedTargetsAndRenormalisesNormals) {
    auto m = make<Mesh>();
    m->set({vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0)}, {vec3(0, 0, 1), vec3(0, 0, 1), vec3(0, 0, 1)}, {0, 1, 2},
           {vec2(0, 0), vec2(1, 0), vec2(0, 1)});
    MorphTarget up, tilt;
    up.positions = {vec3(0, 0, 1), vec3(0, 0, 0), vec3(0, 0, 0)};
    tilt.normals = {vec3(1, 0, 0), vec3(1, 0, 0), vec3(1, 0, 0)};
    m->setMorphTargets({up, tilt});
    EXPECT_EQ(morphMesh(*m, {0.0f, 0.0f}), nullptr);
    EXPECT_EQ(morphMesh(*m, {}), nullptr);
    ref_ptr<Mesh> out = morphMesh(*m, {0.5f, 1.0f});
    ASSERT_NE(out, nullptr);
    EXPECT_TRUE(out->morphTargets().empty());
    EXPECT_EQ(out->positions()[0], vec3(0, 0, 0.5f));
    EXPECT_EQ(out->positions()[1], vec3(1, 0, 0));
    const float h = std::sqrt(0.5f);
    EXPECT_NEAR(glm::length(out->normals()[2] - vec3(h, 0, h)), 0.0f, 1e-6f);
    EXPECT_EQ(out->uvs(), m->uvs());
    EXPECT_EQ(out->indexCount(), 3u);
    EXPECT_NEAR(out->box().max.z, 0.5, 1e-7);
    // Weights past the targets' count are not there; the tilt alone keeps the positions.
    ref_ptr<Mesh> only = morphMesh(*m, {0.0f, 1.0f});
    ASSERT_NE(only, nullptr);
    EXPECT_EQ(only->positions(), m->positions());
    // Skin weights come along.
    ref_ptr<Mesh> skinned = bar();
    MorphTarget longer;
    longer.positions.assign(skinned->positions().size(), vec3(1, 0, 0));
    skinned->setMorphTargets({longer});
    ref_ptr<Mesh> morphed = morphMesh(*skinned, {1.0f});
    ASSERT_NE(morphed, nullptr);
    EXPECT_EQ(morphed->influences(), 4);
    EXPECT_EQ(morphed->joints(), skinned->joints());
    EXPECT_EQ(morphed->weights(), skinned->weights());
}

TEST(Posing, SkinnedBoxHoldsEveryPosedVertexAndFitsTheBindPose) {
    Figure f = figure(dvec3(3, -2, 1), true);
    // Bind pose: the box is the mesh's, moved by nothing.
    ref_ptr<const Pose> bind = makePose(*f.geometry);
    ASSERT_TRUE(bind->skinned());
    const Box mb = f.geometry->mesh()->box();
    EXPECT_NEAR(glm::length(bind->box.min - mb.min), 0.0, 1e-9);
    EXPECT_NEAR(glm::length(bind->box.max - mb.max), 0.0, 1e-9);
    EXPECT_NEAR(glm::length(bind->anchor - dvec3(3, -2, 1)), 0.0, 1e-12);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto turn = [&] {
        dvec3 axis(u(rng), u(rng), u(rng));
        if (glm::length(axis) < 1e-3) axis = dvec3(0, 0, 1);
        return glm::rotate(dmat4(1.0), 3.2 * u(rng), glm::normalize(axis));
    };
    for (int k = 0; k < 200; ++k) {
        f.hip->setMatrix(move(dvec3(3, -2, 1)) * turn());
        f.knee->setMatrix(move(dvec3(1, 0, 0)) * turn());
        ref_ptr<const Pose> pose = makePose(*f.geometry);
        ref_ptr<Mesh> posed = skinMesh(*f.geometry->mesh(), *pose);
        const dvec3 slack(1e-5);
        const Box grown{pose->box.min - slack, pose->box.max + slack};
        for (const vec3& p : posed->positions()) ASSERT_TRUE(grown.contains(dvec3(p))) << "pose " << k;
    }
}

TEST(Posing, MakePoseReusesTheMorphedMeshForTheSameWeights) {
    ref_ptr<Mesh> m = makeBoxMesh(dvec3(-1), dvec3(1));
    MorphTarget t;
    t.positions.assign(m->positions().size(), vec3(0, 0, 1));
    m->setMorphTargets({t});
    auto g = make<Geometry>(m, make<Material>());
    g->setMorphWeights({0.5f});
    ref_ptr<const Pose> a = makePose(*g);
    ASSERT_NE(a->mesh, nullptr);
    EXPECT_FALSE(a->skinned());
    EXPECT_NEAR(a->box.max.z, 1.5, 1e-7);  // morphed only: the Geometry's frame
    ref_ptr<const Pose> b = makePose(*g, a.get());
    EXPECT_EQ(b->mesh, a->mesh);
    g->setMorphWeights({0.25f});
    ref_ptr<const Pose> c = makePose(*g, b.get());
    EXPECT_NE(c->mesh, b->mesh);
    EXPECT_NEAR(c->box.max.z, 1.25, 1e-7);
}

TEST(Posing, UpdatePosesSkinnedGeometryAndItsBoundFollowsTheJoint) {
    Figure f = figure();
    // Where a skinned Geometry sits places nothing: far off under a transform, its bound stays the skeleton's.
    auto far = make<Transform>(move(dvec3(100, 0, 0)));
    f.root->removeChild(f.geometry.get());
    far->addChild(f.geometry);
    f.root->addChild(far);
    Scene s(f.root);
    s.update();
    const FlatImage& img = s.image();
    // Entries: root 0, hip 1, knee 2, far 3, geometry 4.
    ASSERT_EQ(img.size(), 5u);
    ASSERT_EQ(img.kind[4], NodeKind::Geometry);
    EXPECT_TRUE(img.flags[4] & FlatImage::kPosed);
    ASSERT_EQ(img.posed.size(), 1u);
    EXPECT_EQ(img.posed[0].first, 4u);
    const Pose* pose = img.poseOf(4);
    ASSERT_NE(pose, nullptr);
    EXPECT_TRUE(pose->skinned());
    EXPECT_NEAR(img.box(4).max.x, 2.0, 1e-5);
    EXPECT_NEAR(img.box(4).max.y, 0.1, 1e-5);
    // The knee turned a quarter about z: the bar's far end goes to (1, 1).
    f.knee->setMatrix(move(dvec3(1, 0, 0)) * rotZ(90));
    s.update();
    EXPECT_LE(s.lastUpdate().entriesWritten, 3u);
    EXPECT_NE(img.poseOf(4), nullptr);
    EXPECT_NEAR(img.box(4).max.x, 1.1, 1e-5);
    EXPECT_NEAR(img.box(4).max.y, 1.0, 1e-5);
    EXPECT_NEAR(img.box(0).max.y, 1.0, 1e-5);  // the root's bound follows
    // Moved above the first joint: re-posed too.
    f.hip->setMatrix(move(dvec3(0, 0, 5)));
    s.update();
    EXPECT_NEAR(img.box(4).min.z, 4.9, 1e-5);
}

TEST(Posing, MovingOneJointCostsTheSameWithManyStillFigures) {
    auto written = [](int figures) {
        auto root = make<Group>();
        std::vector<Figure> all;
        for (int k = 0; k < figures; ++k) {
            all.push_back(figure(dvec3(3.0 * k, 0, 0)));
            root->addChild(all.back().root);
        }
        Scene s(root);
        s.update();
        all[0].knee->setMatrix(move(dvec3(1, 0, 0)) * rotZ(45));
        s.update();
        EXPECT_EQ(s.lastUpdate().fullRebuilds, 0u);
        return s.lastUpdate().entriesWritten;
    };
    const uint64_t one = written(1), fifty = written(50);
    EXPECT_EQ(one, fifty);
    EXPECT_GE(one, 2u);  // the knee and its Geometry
    EXPECT_LE(one, 3u);
}

TEST(Posing, JointAboveItsOwnSkinnedGeometryIsRefused) {
    Figure f = figure();
    f.geometry->setName("leg");
    f.root->removeChild(f.geometry.get());
    f.hip->addChild(f.geometry);
    Scene s(f.root);
    try {
        s.update();
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("Transform 'hip'"), std::string::npos) << what;
        EXPECT_NE(what.find("Geometry 'leg'"), std::string::npos) << what;
    }
    f.geometry->setSkin(nullptr);  // the references this graph makes a cycle of: broken, so that it is freed
}
