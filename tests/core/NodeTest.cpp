#include "nodes/BspGroup.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/Occluder.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"
#include "sg/scene/internal/BspBuilder.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {
template <class F>
std::string errorOf(F f) {
    try {
        f();
    } catch (const std::exception& e) {
        return e.what();
    }
    return "no error";
}
}  // namespace

TEST(Group, ACycleNeverEntersTheGraph) {
    auto a = make<Group>(), b = make<Group>(), c = make<Group>();
    a->setName("a");
    c->setName("c");
    a->addChild(b);
    b->addChild(c);
    EXPECT_EQ(errorOf([&] { c->addChild(a); }),
              "Group::addChild(): adding Group 'a' below Group 'c' would make a cycle (the group is the child or one "
              "of its descendants)");
    EXPECT_NE(errorOf([&] { a->addChild(a); }).find("cycle"), std::string::npos);
    EXPECT_EQ(c->numChildren(), 0u);
    EXPECT_EQ(a->numParents(), 0u);
    // Through a second parent (DAG) and through an Instance.
    auto d = make<Group>();
    d->addChild(c);
    EXPECT_NE(errorOf([&] { c->addChild(d); }).find("cycle"), std::string::npos);
    // A placement of `a` below c, which is itself below a.
    auto in = make<Instance>(a, dmat4(1.0));
    EXPECT_NE(errorOf([&] { c->addChild(in); }).find("cycle"), std::string::npos);
    EXPECT_NE(errorOf([&] {
                  make<Instance>(c, dmat4(1.0));
                  auto self = make<Instance>();
                  self->setPrototype(self);
              }).find("cycle"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { a->addChild(nullptr); }).find("Group::addChild(): child is null"), std::string::npos);
}

TEST(Node, PlainNodesStaySmall) {
    // A name, a callback or a second parent costs a block of its own; a node without them carries none.
    if (sizeof(void*) != 8) GTEST_SKIP() << "sizes stated for 64-bit targets";
    EXPECT_EQ(sizeof(Group), 40u);
    EXPECT_EQ(sizeof(Transform), 72u);
    auto g = make<Group>(), p1 = make<Group>(), p2 = make<Group>();
    p1->addChild(g);
    g->setName("g");  // the only parent moves into the node's Extras with the name
    p2->addChild(g);
    EXPECT_EQ(g->numParents(), 2u);
    EXPECT_EQ(g->parent(0), p1.get());
    EXPECT_EQ(g->parent(1), p2.get());
    p1->removeChild(g.get());
    EXPECT_EQ(g->numParents(), 1u);
    EXPECT_EQ(g->parent(0), p2.get());
    EXPECT_EQ(g->name(), "g");
}

TEST(Group, ErrorsNameTheFunctionCalled) {
    auto a = make<Group>(), b = make<Group>();
    a->setName("a");
    a->addChild(b);
    EXPECT_EQ(errorOf([&] { a->insertChild(0, nullptr); }),
              "Group::insertChild(): child is null (adding to Group 'a')");
    EXPECT_EQ(errorOf([&] { a->addChild(nullptr); }), "Group::addChild(): child is null (adding to Group 'a')");
    EXPECT_EQ(errorOf([&] { b->insertChild(0, a); }),
              "Group::insertChild(): adding Group 'a' below Group would make a cycle (the group is the child or one "
              "of its descendants)");
    EXPECT_EQ(a->numChildren(), 1u);
}

TEST(Group, ParentsAreTrackedForDagsAndRemoval) {
    auto shared = make<Group>();
    auto p1 = make<Group>(), p2 = make<Group>();
    p1->addChild(shared);
    p2->addChild(shared);
    EXPECT_EQ(shared->numParents(), 2u);
    EXPECT_TRUE(p2->removeChild(shared.get()));
    EXPECT_EQ(shared->numParents(), 1u);
    EXPECT_EQ(shared->parent(0), p1.get());
    EXPECT_EQ(errorOf([&] { p2->removeChild(size_t(3)); }),
              "Group::removeChild(): index 3 past the 0 children of Group");
    p1 = nullptr;  // destroying a parent detaches it
    EXPECT_EQ(shared->numParents(), 0u);
}

TEST(Transform, InstanceAndTransformRefuseTheSameNearlySingularMatrix) {
    dmat4 m(1.0);
    m[1] = dvec4(1.0, 1e-13, 0.0, 0.0);  // the second axis almost along the first: |det| 1e-13
    auto t = make<Transform>();
    auto in = make<Instance>();
    const std::string why = nonInvertibleAffine(m);
    EXPECT_EQ(why.rfind("matrix is singular (det ", 0), 0u) << why;
    EXPECT_EQ(errorOf([&] { t->setMatrix(m); }), "Transform::setMatrix(): Transform: " + why);
    EXPECT_EQ(errorOf([&] { in->setMatrix(m); }), "Instance::setMatrix(): Instance: " + why);
    EXPECT_EQ(in->matrix(), dmat4(1.0));
    m[1] = dvec4(1.0, 1e-9, 0.0, 0.0);  // thin but invertible: both take it
    EXPECT_EQ(errorOf([&] { t->setMatrix(m); }), "no error");
    EXPECT_EQ(errorOf([&] { in->setMatrix(m); }), "no error");
    m[2][3] = 0.5;
    EXPECT_EQ(errorOf([&] { in->setMatrix(m); }),
              "Instance::setMatrix(): Instance: last row is (0 0 0.5 1), not (0 0 0 1): only affine transforms are "
              "drawn");
}

TEST(Transform, BadMatricesAreRefusedWithTheElement) {
    auto t = make<Transform>();
    t->setName("crane");
    dmat4 m(1.0);
    m[1][2] = std::nan("");
    EXPECT_EQ(errorOf([&] { t->setMatrix(m); }), "Transform::setMatrix(): Transform 'crane': element [1][2] is nan");
    EXPECT_NE(errorOf([&] { t->setMatrix(glm::scale(dmat4(1.0), dvec3(1, 0, 1))); }).find("singular"),
              std::string::npos);
    EXPECT_TRUE(t->isTranslation());
    t->setMatrix(glm::translate(dmat4(1.0), dvec3(1, 2, 3)));
    EXPECT_TRUE(t->isTranslation());
    EXPECT_EQ(t->matrix()[3], dvec4(1, 2, 3, 1));
    const dmat4 r = glm::rotate(dmat4(1.0), 0.5, dvec3(0, 0, 1));
    t->setMatrix(r);
    EXPECT_FALSE(t->isTranslation());
    EXPECT_EQ(t->matrix(), r);
    EXPECT_EQ(t->apply(dmat4(2.0)), dmat4(2.0) * r);
}

TEST(LOD, RangesOutOfOrderAreRefused) {
    auto lod = make<LOD>();
    lod->addChild(make<Group>(), 0, 100);
    EXPECT_NE(errorOf([&] { lod->addChild(make<Group>(), 50, 40); }).find("min > max"), std::string::npos);
    EXPECT_NE(errorOf([&] { lod->addChild(make<Group>(), -1, 40); }).find("below 0"), std::string::npos);
    EXPECT_NE(errorOf([&] { lod->addChild(make<Group>(), NAN, 40); }).find("NaN"), std::string::npos);
    lod->addChild(make<Group>(), 100, 200);
    auto lod2 = make<LOD>();
    lod2->addChild(make<Group>(), 100, 200);
    EXPECT_EQ(errorOf([&] { lod2->addChild(make<Group>(), 0, 100); }),
              "LOD::addChild(): LOD child 1: range [0.000000, 100.000000) starts before the previous child's range "
              "(ranges out of order)");
    EXPECT_EQ(lod->numChildren(), 2u);
    EXPECT_EQ(lod->range(1).min, 100.0f);
    EXPECT_NE(errorOf([&] { lod->setRange(7, 0, 1); }).find("LOD::setRange(): child 7"), std::string::npos);
}

TEST(Switch, ChildrenFollowTheirBits) {
    auto sw = make<Switch>();
    sw->addChild(make<Group>());
    sw->addChild(make<Group>(), false);
    EXPECT_TRUE(sw->isOn(0));
    EXPECT_FALSE(sw->isOn(1));
    sw->setOnly(1);
    EXPECT_FALSE(sw->isOn(0));
    EXPECT_TRUE(sw->isOn(1));
    sw->removeChild(size_t(0));
    EXPECT_TRUE(sw->isOn(0));
    EXPECT_NE(errorOf([&] { sw->setOn(4, true); }).find("Switch::setOn(): child 4"), std::string::npos);
}

TEST(Mesh, BadIndicesAreRefusedAndNaNMakesTheBoundInvalid) {
    auto m = make<Mesh>();
    EXPECT_EQ(errorOf([&] {
                  m->set({vec3(0), vec3(1), vec3(2)}, {}, {0, 1, 3});
              }),
              "Mesh::set(): indices[2] = 3 is out of range (3 positions)");
    EXPECT_NE(errorOf([&] { m->set({vec3(0), vec3(1)}, {vec3(0)}, {}); }).find("normals has 1"), std::string::npos);
    m->set({vec3(0), vec3(1, 0, 0), vec3(0, NAN, 0)}, {}, {0, 1, 2});
    EXPECT_FALSE(m->validBound());
    auto box = makeBoxMesh(dvec3(0), dvec3(1), 10);
    EXPECT_EQ(box->triangleCount(), 1200u);
    EXPECT_FALSE(box->indices16().empty());
}

TEST(Occluder, ShapesAreChecked) {
    auto o = make<Occluder>();
    EXPECT_NE(errorOf([&] { o->setBox(Box{}); }).find("Occluder::setBox()"), std::string::npos);
    EXPECT_NE(errorOf([&] { o->setPolygon({dvec3(0), dvec3(1, 0, 0)}); }).find("at least 3"), std::string::npos);
    EXPECT_NE(errorOf([&] {
                  o->setPolygon({dvec3(0), dvec3(1, 0, 0), dvec3(1, 1, 1), dvec3(0, 1, 0)});
              }).find("off the polygon's plane"),
              std::string::npos);
    EXPECT_NE(errorOf([&] {
                  o->setPolygon({dvec3(0), dvec3(2, 0, 0), dvec3(1, 0.2, 0), dvec3(2, 2, 0), dvec3(0, 2, 0)});
              }).find("not convex"),
              std::string::npos);
    o->setPolygon({dvec3(0), dvec3(2, 0, 0), dvec3(2, 2, 0), dvec3(0, 2, 0)});
    EXPECT_EQ(o->shape(), Occluder::Shape::Polygon);
    EXPECT_EQ(o->box().max, dvec3(2, 2, 0));
}

TEST(BspGroup, OrderIsFrontToBack) {
    auto g = make<BspGroup>();
    for (int k = 0; k < 5; ++k) g->addChild(make<Group>());
    std::vector<Box> boxes;
    for (int k = 0; k < 5; ++k) boxes.push_back(Box{dvec3(10.0 * k, 0, 0), dvec3(10.0 * k + 5, 5, 5)});
    // A BSP over boxes along x: from an eye at x = -100 the order is 0..4, from x = +100 it is 4..0.
    buildBsp(*g, boxes);
    std::vector<uint32_t> ord;
    g->order(dvec3(-100, 2, 2), ord);
    EXPECT_EQ(ord, (std::vector<uint32_t>{0, 1, 2, 3, 4}));
    g->order(dvec3(100, 2, 2), ord);
    EXPECT_EQ(ord, (std::vector<uint32_t>{4, 3, 2, 1, 0}));
    // From every gap between boxes: a box never comes after one that is farther on its side of the eye.
    for (double x : {7.5, 17.5, 27.5, 37.5}) {
        g->order(dvec3(x, 2, 2), ord);
        ASSERT_EQ(ord.size(), 5u);
        for (size_t a = 0; a < 5; ++a)
            for (size_t b = a + 1; b < 5; ++b) {
                const double da = boxes[ord[a]].center().x - x, db = boxes[ord[b]].center().x - x;
                if ((da > 0) == (db > 0)) {
                    EXPECT_LT(std::abs(da), std::abs(db)) << "eye x " << x;
                }
            }
    }
}
