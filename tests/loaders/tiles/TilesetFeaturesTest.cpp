// writeTileset's copies keep what nodes say of themselves: a feature's binding (Node::setFeatures) goes with the
// copy of its node into a tile's content, to the Instance that places a repeated leaf, and a feature is never split.
#include "loaders/tiles/internal/TilesetDetail.h"
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/Transform.h"
#include "sg/core/Features.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace sg;

namespace {

// Three rows' worth of ids, no store: the copies only carry the pointer and the index.
ref_ptr<MeshFeatures> threeFeatures() {
    auto f = make<MeshFeatures>();
    FeatureIdSet set;
    set.source = FeatureIdSet::Source::Instance;
    set.featureCount = 3;
    set.ids = {0, 1, 2};
    f->sets.push_back(set);
    return f;
}

// A building as the city makes it: a Transform at (x, 0, 0) over an LOD (user centre) of one box Geometry.
ref_ptr<Transform> building(const ref_ptr<Mesh>& mesh, const ref_ptr<Material>& mat, double x) {
    auto lod = make<LOD>();
    lod->setCenter(dvec3(0, 0, 5));
    lod->addChild(make<Geometry>(mesh, mat), 0.0f, 2500.0f);
    auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(x, 0, 0)));
    t->addChild(lod);
    return t;
}

}  // namespace

TEST(TilesetFeatures, ACopiedNodeKeepsItsBinding) {
    const auto f = threeFeatures();
    auto b = building(makeBoxMesh(dvec3(0), dvec3(1), 1), make<Material>(), 10.0);
    b->setFeatures(f, 2);
    auto content = make<Group>();
    tiles::addUnit(*content, *b, dmat4(1.0), glm::translate(dmat4(1.0), dvec3(-10, 0, 0)), tiles::kKeepAll);
    ASSERT_EQ(content->numChildren(), 1u);
    const Node* copy = content->child(0);
    ASSERT_NE(copy, b.get());
    EXPECT_EQ(copy->kind(), NodeKind::Transform);
    EXPECT_EQ(copy->features(), f.get());
    EXPECT_EQ(copy->featureIndex(), 2u);
    // The LOD below was copied too, and is no feature.
    ASSERT_EQ(copy->numChildren(), 1u);
    EXPECT_EQ(copy->child(0)->features(), nullptr);
}

TEST(TilesetFeatures, AnInstancePlacingARepeatedBuildingIsThatBuilding) {
    const auto f = threeFeatures();
    const auto mesh = makeBoxMesh(dvec3(0), dvec3(1), 1);
    const auto mat = make<Material>();
    auto content = make<Group>();
    for (uint32_t i = 0; i < 3; ++i) {
        auto b = building(mesh, mat, 20.0 * i);
        b->setFeatures(f, 2 - i);  // an index unlike the order, so that a mix-up shows
        content->addChild(b);
    }
    ASSERT_EQ(tiles::instanceRepeats(*content), 3u);
    ASSERT_EQ(content->numChildren(), 3u);
    for (size_t k = 0; k < 3; ++k) {
        const Node* n = content->child(k);
        ASSERT_EQ(n->kind(), NodeKind::Instance);
        const auto& in = static_cast<const Instance&>(*n);
        const uint32_t i = uint32_t(std::lround(in.matrix()[3].x / 20.0));
        EXPECT_EQ(in.features(), f.get());
        EXPECT_EQ(in.featureIndex(), 2 - i) << "the instance at x = " << 20.0 * i;
        // The shared prototype names no feature.
        EXPECT_EQ(in.prototype()->features(), nullptr);
    }
}

TEST(TilesetFeatures, AGroupThatIsOneFeatureStaysWhole) {
    const auto f = threeFeatures();
    const auto mesh = makeBoxMesh(dvec3(0), dvec3(1), 1);
    const auto mat = make<Material>();
    auto machine = make<Group>();  // one feature of two repeated parts
    machine->addChild(building(mesh, mat, 0.0));
    machine->addChild(building(mesh, mat, 5.0));
    machine->setFeatures(f, 1);
    auto content = make<Group>();
    content->addChild(machine);
    EXPECT_EQ(tiles::instanceRepeats(*content), 0u);
    ASSERT_EQ(content->numChildren(), 1u);
    EXPECT_EQ(content->child(0), machine.get());
    EXPECT_EQ(machine->numChildren(), 2u);
    EXPECT_EQ(machine->featureIndex(), 1u);
}

TEST(TilesetFeatures, AFeatureIsOneUnitHoweverManyTrianglesItHas) {
    const auto mesh = makeBoxMesh(dvec3(0), dvec3(1), 1);  // 12 triangles a box
    const auto mat = make<Material>();
    auto root = make<Group>();
    auto plain = make<Group>(), feature = make<Group>();
    for (int i = 0; i < 4; ++i) {
        plain->addChild(make<Geometry>(mesh, mat));
        feature->addChild(make<Geometry>(mesh, mat));
    }
    feature->setFeatures(threeFeatures(), 0);
    root->addChild(plain);
    root->addChild(feature);
    // 20 triangles a unit: the plain Group (48) is split into its four boxes, the feature (48) is not.
    const tiles::Units u = tiles::collectUnits(*root, 20);
    ASSERT_EQ(u.units.size(), 5u);
    size_t whole = 0;
    for (const tiles::Unit& unit : u.units) whole += unit.node == feature.get() ? 1 : 0;
    EXPECT_EQ(whole, 1u);
}
