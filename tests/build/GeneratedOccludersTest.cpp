// generateOccluders: the occluder nodes it adds to a graph beside the geometry (boxes checked against the solid they
// stand for), what it leaves out, and the settings it refuses.
#include "sg/build/GeneratedOccluders.h"

#include "build/OccluderChecks.h"
#include "nodes/Billboard.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "nodes/Occluder.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"
#include "sg/scene/Scene.h"
#include "testbed/Rng.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

using namespace sg;
using namespace occtest;

namespace {

// --- Graphs.

void collectOccluders(Node* n, std::vector<Occluder*>& out) {
    if (n->kind() == NodeKind::Occluder) out.push_back(static_cast<Occluder*>(n));
    for (size_t i = 0; i < n->numChildren(); ++i) collectOccluders(n->child(i), out);
}
std::vector<Occluder*> occludersUnder(Node* n) {
    std::vector<Occluder*> out;
    collectOccluders(n, out);
    return out;
}

ref_ptr<Geometry> geometryOf(ref_ptr<Mesh> m, ref_ptr<Material> mat = make<Material>()) {
    return make<Geometry>(std::move(m), std::move(mat));
}

}  // namespace

// --- 1. Occluder nodes in a graph.

TEST(GeneratedOccluders, AGeometryGetsABoxBesideIt) {
    scenes::Rng rng(11);
    auto root = make<Group>();
    auto g = geometryOf(makeBoxMesh(dvec3(-1, -2, -3), dvec3(2, 1, 0)));
    root->addChild(g);
    const OccluderGenStats st = generateOccluders(*root);
    ASSERT_EQ(root->numChildren(), 2u);
    const std::vector<Occluder*> occ = occludersUnder(root.get());
    ASSERT_EQ(occ.size(), 1u);
    EXPECT_LT(root->indexOf(occ[0]), 2u) << "not beside the geometry";
    EXPECT_TRUE(occ[0]->generated());
    EXPECT_EQ(occ[0]->shape(), Occluder::Shape::Box);
    EXPECT_EQ(occ[0]->shownWith(), nullptr);
    expectInsideSolid(*g->mesh(), {occ[0]->box()}, rng, "beside a geometry");
    // An eye inside the solid must not use it: the box it is used outside of covers the whole mesh.
    ASSERT_FALSE(occ[0]->eyeOutside().empty());
    EXPECT_TRUE(occ[0]->eyeOutside().contains(g->mesh()->box().min) &&
                occ[0]->eyeOutside().contains(g->mesh()->box().max))
        << str(occ[0]->eyeOutside());
    EXPECT_EQ(st.geometries, 1u);
    EXPECT_EQ(st.meshes, 1u);
    EXPECT_EQ(st.meshTriangles, 12u);
    EXPECT_EQ(st.sceneTriangles, 12u);
    EXPECT_EQ(st.boxes, 1u);
    EXPECT_EQ(st.polygons, 0u);
    EXPECT_EQ(st.lods, 0u);
    EXPECT_EQ(st.skipped, 0u);
}

TEST(GeneratedOccluders, AnOpenGeometryGetsPolygons) {
    auto root = make<Group>();
    auto single = make<Material>();
    single->doubleSided = false;
    root->addChild(geometryOf(quadMesh(), single));
    const OccluderGenStats st = generateOccluders(*root);
    const std::vector<Occluder*> occ = occludersUnder(root.get());
    ASSERT_EQ(occ.size(), 1u);
    EXPECT_TRUE(occ[0]->generated());
    EXPECT_EQ(occ[0]->shape(), Occluder::Shape::Polygon);
    EXPECT_NEAR(area(occ[0]->polygon()), 4.0, 1e-5);
    EXPECT_TRUE(occ[0]->oneSided()) << "back faces are not drawn: the polygon hides nothing seen from behind";
    EXPECT_EQ(st.polygons, 1u);
    EXPECT_EQ(st.boxes, 0u);
}

TEST(GeneratedOccluders, APolygonWithinABoxedMeshBesideItIsLeftOut) {
    // A floor inside a building (a closed box), a roof slab on top of it (within the bound's tolerance), and a wall
    // beside it reaching out of the bound: the first two are left out, the wall is kept.
    auto root = make<Group>();
    root->addChild(geometryOf(makeBoxMesh(dvec3(-4, -4, 0), dvec3(4, 4, 6))));
    auto floorAt = [](double z) {
        return meshOf({{-3, -3, z}, {3, -3, z}, {3, 3, z}, {-3, 3, z}}, {0, 1, 2, 0, 2, 3});
    };
    root->addChild(geometryOf(floorAt(3.0)));
    root->addChild(geometryOf(floorAt(6.0)));
    root->addChild(geometryOf(meshOf({{5, -4, 0}, {5, 4, 0}, {5, 4, 6}, {5, -4, 6}}, {0, 1, 2, 0, 2, 3})));
    const OccluderGenStats st = generateOccluders(*root);
    EXPECT_EQ(st.boxes, 1u);
    EXPECT_EQ(st.polygons, 1u);
    EXPECT_EQ(st.enclosed, 2u);
    const std::vector<Occluder*> occ = occludersUnder(root.get());
    size_t polygons = 0;
    for (const Occluder* o : occ)
        if (o->shape() == Occluder::Shape::Polygon) {
            ++polygons;
            for (const dvec3& v : o->polygon()) EXPECT_NEAR(v.x, 5.0, 1e-6) << "the wall outside the bound is kept";
        }
    EXPECT_EQ(polygons, 1u);

    // In another group the box's bound does not count: the floor is kept.
    auto other = make<Group>();
    auto inner = make<Group>();
    other->addChild(geometryOf(makeBoxMesh(dvec3(-4, -4, 0), dvec3(4, 4, 6))));
    inner->addChild(geometryOf(floorAt(3.0)));
    other->addChild(inner);
    const OccluderGenStats st2 = generateOccluders(*other);
    EXPECT_EQ(st2.polygons, 1u);
    EXPECT_EQ(st2.enclosed, 0u);
}

TEST(GeneratedOccluders, BlendedOrMaskedMaterialsGetNone) {
    auto blended = make<Material>();
    blended->blend = true;
    auto cutout = make<Material>();
    cutout->alphaCutoff = 0.5f;
    for (const auto& mat : {blended, cutout}) {
        auto root = make<Group>();
        root->addChild(geometryOf(unitBoxMesh(), mat));
        root->addChild(geometryOf(quadMesh(), mat));
        const OccluderGenStats st = generateOccluders(*root);
        EXPECT_TRUE(occludersUnder(root.get()).empty());
        EXPECT_EQ(root->numChildren(), 2u);
        EXPECT_EQ(st.geometries, 0u);
        EXPECT_EQ(st.skipped, 2u);
    }
}

TEST(GeneratedOccluders, GeometryThePassWouldNotUseGetsNone) {
    {
        auto root = make<Group>();
        auto sw = make<Switch>();
        sw->addChild(geometryOf(unitBoxMesh()), true);
        root->addChild(sw);
        const OccluderGenStats st = generateOccluders(*root);
        EXPECT_TRUE(occludersUnder(root.get()).empty()) << "under a Switch";
        EXPECT_EQ(st.skipped, 1u);
    }
    {
        auto root = make<Group>();
        auto bb = make<Billboard>();
        bb->addChild(geometryOf(unitBoxMesh()));
        root->addChild(bb);
        generateOccluders(*root);
        EXPECT_TRUE(occludersUnder(root.get()).empty()) << "under a Billboard";
    }
    {
        auto root = make<Group>();
        // A masked Geometry gets none (the occluder beside it would not carry its mask); below a masked Group, the
        // occluder carries the Group's mask as the pass's condition, so it is made.
        auto masked = make<Group>();
        masked->setNodeMask(0x1);
        auto g = geometryOf(unitBoxMesh());
        g->setNodeMask(0x1);
        masked->addChild(g);
        root->addChild(masked);
        generateOccluders(*root);
        EXPECT_TRUE(occludersUnder(root.get()).empty()) << "a masked Geometry";
        g->setNodeMask(0xffffffffu);
        generateOccluders(*root);
        EXPECT_EQ(occludersUnder(root.get()).size(), 1u) << "below a masked Group";
    }
    {
        auto root = make<Group>();
        auto proto = make<Group>();
        proto->addChild(geometryOf(unitBoxMesh()));
        root->addChild(make<Instance>(proto, glm::translate(dmat4(1.0), dvec3(5, 0, 0))));
        generateOccluders(*root);
        EXPECT_TRUE(occludersUnder(root.get()).empty()) << "in an Instance's prototype";
        EXPECT_EQ(proto->numChildren(), 1u);
    }
}

TEST(GeneratedOccluders, AnAuthoredOccluderIsKeptAndNoneAdded) {
    auto root = make<Group>();
    auto authored = make<Occluder>();
    authored->setBox(Box{dvec3(-0.5), dvec3(0.5)});
    root->addChild(authored);
    root->addChild(geometryOf(unitBoxMesh()));
    auto other = make<Group>();  // a parent without one still gets its own
    other->addChild(geometryOf(unitBoxMesh()));
    root->addChild(other);
    const OccluderGenStats st = generateOccluders(*root);
    EXPECT_EQ(root->numChildren(), 3u);
    EXPECT_EQ(root->child(0), authored.get());
    EXPECT_FALSE(authored->generated());
    EXPECT_EQ(other->numChildren(), 2u);
    EXPECT_EQ(occludersUnder(root.get()).size(), 2u);
    EXPECT_EQ(st.skipped, 1u);
    EXPECT_EQ(st.geometries, 1u);
}

TEST(GeneratedOccluders, AnLodGetsABoxInsideEveryLevel) {
    scenes::Rng rng(12);
    auto root = make<Group>();
    auto lod = make<LOD>();
    const ref_ptr<Mesh> fine = makeBoxMesh(dvec3(-2, -2, -2), dvec3(2, 2, 2), 2);
    const ref_ptr<Mesh> coarse = makeBoxMesh(dvec3(-1.5, -1, -2.5), dvec3(1, 2.5, 1.2));
    lod->addChild(geometryOf(fine), 0.0f, 50.0f);
    lod->addChild(geometryOf(coarse), 50.0f, 500.0f);
    root->addChild(geometryOf(quadMesh()));
    root->addChild(lod);
    root->addChild(geometryOf(makeBoxMesh(dvec3(10), dvec3(11))));
    const OccluderGenStats st = generateOccluders(*root);
    EXPECT_EQ(lod->numChildren(), 2u) << "the LOD's levels are its children: nothing may be added among them";
    const size_t at = root->indexOf(lod.get());
    ASSERT_LT(at + 1, root->numChildren());
    ASSERT_EQ(root->child(at + 1)->kind(), NodeKind::Occluder) << "the pass finds the LOD as the sibling before";
    std::vector<Occluder*> withLod;
    for (Occluder* o : occludersUnder(root.get()))
        if (o->shownWith() == lod.get()) withLod.push_back(o);
    ASSERT_FALSE(withLod.empty());
    for (Occluder* o : withLod) {
        EXPECT_TRUE(o->generated());
        ASSERT_EQ(o->shape(), Occluder::Shape::Box);
        EXPECT_EQ(root->indexOf(o), at + 1) << "only the sibling right after the LOD is used with it";
        expectInsideSolid(*fine, {o->box()}, rng, "fine level");
        expectInsideSolid(*coarse, {o->box()}, rng, "coarse level");
        // An eye inside the level shown must not use it: the box it is used outside of covers every level.
        const Box& eye = o->eyeOutside();
        ASSERT_FALSE(eye.empty());
        for (const Mesh* m : {fine.get(), coarse.get()})
            EXPECT_TRUE(eye.contains(m->box().min) && eye.contains(m->box().max)) << str(eye);
    }
    EXPECT_EQ(st.lods, withLod.size());
}

TEST(GeneratedOccluders, EveryBoxOfAnLodStandsRightAfterIt) {
    // Levels shaped as an L give a box in each arm: each box must follow the LOD (other occluders between) to be used
    // with it (Occluder::setShownWith), which the image records as the LOD's entry.
    scenes::Rng rng(15);
    auto root = make<Group>();
    auto lod = make<LOD>();
    const ref_ptr<Mesh> fine = lPrism();
    const ref_ptr<Mesh> coarse =
        transformed(*lPrism(), glm::translate(dmat4(1.0), dvec3(3, 3, 1)) * glm::scale(dmat4(1.0), dvec3(1.05)) *
                                   glm::translate(dmat4(1.0), dvec3(-3, -3, -1)));
    lod->addChild(geometryOf(fine), 0.0f, 50.0f);
    lod->addChild(geometryOf(coarse), 50.0f, 500.0f);
    root->addChild(lod);
    OccluderGenSettings s;
    s.maxBoxes = 4;
    generateOccluders(*root, s);
    std::vector<Occluder*> withLod;
    for (Occluder* o : occludersUnder(root.get()))
        if (o->shownWith() == lod.get()) withLod.push_back(o);
    ASSERT_FALSE(withLod.empty());
    for (Occluder* o : withLod) {
        expectInsideSolid(*fine, {o->box()}, rng, "fine L");
        expectInsideSolid(*coarse, {o->box()}, rng, "coarse L");
        // After the LOD, with only occluders between them: the image finds the LOD for each.
        for (size_t k = root->indexOf(lod.get()) + 1; k < root->indexOf(o); ++k)
            EXPECT_EQ(root->child(k)->kind(), NodeKind::Occluder) << "something other than an occluder between";
        EXPECT_GT(root->indexOf(o), root->indexOf(lod.get()));
    }
    Scene scene(root);
    scene.update();
    for (const FlatImage::OccluderRef& ref : scene.image().occluders) {
        if (static_cast<const Occluder*>(ref.node)->shownWith() != lod.get()) continue;
        EXPECT_TRUE(ref.active && ref.lod != ~0u) << "an occluder of the LOD the pass never uses";
    }
}

TEST(GeneratedOccluders, AnLodWithAnOpenLevelOrLevelsApartGetsNoBox) {
    for (int k = 0; k < 2; ++k) {
        auto root = make<Group>();
        auto lod = make<LOD>();
        lod->addChild(geometryOf(unitBoxMesh()), 0.0f, 50.0f);
        lod->addChild(geometryOf(k == 0 ? quadMesh() : makeBoxMesh(dvec3(5), dvec3(7))), 50.0f, 500.0f);
        root->addChild(lod);
        const OccluderGenStats st = generateOccluders(*root);
        for (Occluder* o : occludersUnder(root.get())) EXPECT_NE(o->shownWith(), lod.get()) << "case " << k;
        EXPECT_EQ(st.lods, 0u);
        EXPECT_EQ(lod->numChildren(), 2u);
    }
}

TEST(GeneratedOccluders, RunningAgainAddsNoDuplicatesAndRemoveTakesOnlyGenerated) {
    auto root = make<Group>();
    for (int i = 0; i < 5; ++i) {
        auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(4.0 * i, 0, 0)));
        t->addChild(geometryOf(unitBoxMesh()));
        t->addChild(geometryOf(quadMesh()));
        root->addChild(t);
    }
    auto withAuthored = make<Group>();
    auto authored = make<Occluder>();
    authored->setBox(Box{dvec3(20), dvec3(21)});
    withAuthored->addChild(authored);
    withAuthored->addChild(geometryOf(unitBoxMesh()));
    root->addChild(withAuthored);

    const OccluderGenStats first = generateOccluders(*root);
    const size_t count = occludersUnder(root.get()).size();
    ASSERT_GT(count, 5u);
    EXPECT_EQ(first.boxes + first.polygons + 1, count);
    const OccluderGenStats second = generateOccluders(*root);
    EXPECT_EQ(occludersUnder(root.get()).size(), count);
    EXPECT_EQ(second.boxes, first.boxes);
    EXPECT_EQ(second.polygons, first.polygons);

    EXPECT_EQ(removeOccluders(*root, true), count - 1);
    const std::vector<Occluder*> left = occludersUnder(root.get());
    ASSERT_EQ(left.size(), 1u);
    EXPECT_EQ(left[0], authored.get());
    for (size_t i = 0; i < 5; ++i) EXPECT_EQ(root->child(i)->numChildren(), 2u);

    generateOccluders(*root);
    EXPECT_EQ(occludersUnder(root.get()).size(), count);
    EXPECT_EQ(removeOccluders(*root, false), count);
    EXPECT_TRUE(occludersUnder(root.get()).empty());
}

TEST(GeneratedOccluders, TheOccluderIsInTheGeometrysFrame) {
    scenes::Rng rng(13);
    for (int i = 0; i < 4; ++i) {
        const dmat4 xf = randomPlacement(rng) * glm::scale(dmat4(1.0), dvec3(1.0, 2.0, 0.5));
        const ref_ptr<Mesh> mesh = lPrism();
        auto root = make<Group>();
        auto t = make<Transform>(xf);
        t->addChild(geometryOf(mesh));
        root->addChild(t);
        generateOccluders(*root);
        const std::vector<Occluder*> occ = occludersUnder(root.get());
        ASSERT_FALSE(occ.empty());
        for (Occluder* o : occ) EXPECT_EQ(t->indexOf(o) < t->numChildren(), true) << "not beside the geometry";

        Box world;  // the transformed mesh's bound, exactly
        for (const vec3& p : mesh->positions()) world.expand(dvec3(xf * dvec4(dvec3(p), 1.0)));
        const std::vector<Tri> worldTris = trianglesOf(*transformed(*mesh, xf));
        Scene scene(root);
        scene.update();
        const FlatImage& img = scene.image();
        ASSERT_EQ(img.occluders.size(), occ.size());
        const double slack = 1e-5 * (glm::length(world.max) + glm::length(world.max - world.min));
        for (const FlatImage::OccluderRef& ref : img.occluders) {
            EXPECT_TRUE(ref.active);
            const Box b = img.box(ref.entry);
            EXPECT_TRUE(glm::all(glm::greaterThanEqual(b.min, world.min - slack)) &&
                        glm::all(glm::lessThanEqual(b.max, world.max + slack)))
                << "world box " << str(b) << " outside the mesh's world bound " << str(world);
            const Box local = static_cast<const Occluder*>(ref.node)->box();
            for (int c = 0; c < 8; ++c) {
                const dvec3 corner(c & 1 ? local.max.x : local.min.x, c & 2 ? local.max.y : local.min.y,
                                   c & 4 ? local.max.z : local.min.z);
                EXPECT_GT(windingNumber(worldTris, dvec3(xf * dvec4(corner, 1.0))), 0.5) << "corner " << c;
            }
        }
    }
}

TEST(GeneratedOccluders, AMeshSharedByManyGeometriesIsAnalysedOnce) {
    auto root = make<Group>();
    const ref_ptr<Mesh> mesh = makeBoxMesh(dvec3(-1), dvec3(1), 2);
    auto mat = make<Material>();
    for (int i = 0; i < 100; ++i) {
        auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(3.0 * (i % 10), 3.0 * (i / 10), 0)));
        t->addChild(geometryOf(mesh, mat));
        root->addChild(t);
    }
    const OccluderGenStats st = generateOccluders(*root);
    EXPECT_EQ(st.meshes, 1u);
    EXPECT_EQ(st.meshTriangles, uint64_t(mesh->triangleCount()));
    EXPECT_EQ(st.sceneTriangles, 100u * mesh->triangleCount());
    EXPECT_EQ(st.geometries, 100u);
    EXPECT_EQ(st.boxes, 100u);
    EXPECT_EQ(st.skipped, 0u);
    EXPECT_GE(st.ms, 0.0);
    EXPECT_EQ(occludersUnder(root.get()).size(), 100u);
    Box first;
    for (size_t i = 0; i < 100; ++i) {
        const Node* t = root->child(i);
        ASSERT_EQ(t->numChildren(), 2u);
        const Node* o = t->child(0)->kind() == NodeKind::Occluder ? t->child(0) : t->child(1);
        ASSERT_EQ(o->kind(), NodeKind::Occluder);
        const Box b = static_cast<const Occluder*>(o)->box();
        if (i == 0) first = b;
        EXPECT_EQ(b.min, first.min);
        EXPECT_EQ(b.max, first.max);
    }
}

TEST(GeneratedOccluders, StatsCountGeometryNodes) {
    // Three geometries under a Switch are three left without; a small box beside a large one is left out as minor,
    // and its geometry did not get an occluder.
    auto root = make<Group>();
    auto sw = make<Switch>();
    for (int i = 0; i < 3; ++i) sw->addChild(geometryOf(unitBoxMesh()), true);
    root->addChild(sw);
    root->addChild(make<Switch>());  // no geometry: nothing left without
    auto big = make<Group>();
    big->addChild(geometryOf(makeBoxMesh(dvec3(0), dvec3(100))));
    root->addChild(big);
    auto small = make<Group>();
    small->addChild(geometryOf(makeBoxMesh(dvec3(200), dvec3(201))));
    root->addChild(small);
    OccluderGenSettings s;
    s.minMajorShare = 0.1;
    const OccluderGenStats st = generateOccluders(*root, s);
    EXPECT_EQ(small->numChildren(), 1u) << "a 1-unit box beside a 100-unit one is minor";
    EXPECT_EQ(big->numChildren(), 2u);
    EXPECT_EQ(st.minor, 1u);
    EXPECT_EQ(st.boxes, 1u);
    EXPECT_EQ(st.skipped, 3u) << "Geometry nodes left without";
    EXPECT_EQ(st.geometries, 1u) << "Geometry nodes that got occluders";
}

// --- 2. Bad settings.

namespace {
void expectRejected(const OccluderGenSettings& s, const std::string& setting) {
    try {
        s.validate("sg::generateOccluders()");
        ADD_FAILURE() << setting << ": accepted";
    } catch (const std::invalid_argument& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("sg::generateOccluders()"), std::string::npos) << msg;
        EXPECT_NE(msg.find(setting), std::string::npos) << msg;
    }
}
}  // namespace

TEST(GeneratedOccluders, BadSettingsAreRejectedByName) {
    OccluderGenSettings s;
    EXPECT_NO_THROW(s.validate("f"));
    s.voxels = 0;
    expectRejected(s, "voxels");
    s.voxels = 1000;
    expectRejected(s, "voxels");
    s.voxels = 257;
    expectRejected(s, "voxels");
    s = {};
    s.voxels = 256;
    EXPECT_NO_THROW(s.validate("f"));
    s = {};
    s.minBoxShare = 1.5;
    expectRejected(s, "minBoxShare");
    s.minBoxShare = kNaN;
    expectRejected(s, "minBoxShare");
    s.minBoxShare = -0.1;
    expectRejected(s, "minBoxShare");
    s = {};
    s.minPolygonShare = 1.5;
    expectRejected(s, "minPolygonShare");
    s.minPolygonShare = kNaN;
    expectRejected(s, "minPolygonShare");
    s = {};
    s.minMajorShare = 2.0;
    expectRejected(s, "minMajorShare");
    s.minMajorShare = kNaN;
    expectRejected(s, "minMajorShare");
    s = {};
    s.maxBoxes = 65;
    expectRejected(s, "maxBoxes");
    s = {};
    s.maxPolygons = 65;
    expectRejected(s, "maxPolygons");
    s = {};
    s.maxOpenings = 65;
    expectRejected(s, "maxOpenings");
    s = {};
    s.openingDepth = -0.01;
    expectRejected(s, "openingDepth");
    s.openingDepth = kNaN;
    expectRejected(s, "openingDepth");
    s.openingDepth = 1.5;
    expectRejected(s, "openingDepth");
    s = {};
    s.minBoxShare = 1.0;
    s.minPolygonShare = 0.0;
    s.maxOpenings = 64;
    s.openingDepth = 1.0;
    s.maxBoxes = 64;
    s.maxPolygons = 0;
    EXPECT_NO_THROW(s.validate("f"));
}

TEST(GeneratedOccluders, GenerateRejectsBadSettingsBeforeChangingTheGraph) {
    auto root = make<Group>();
    root->addChild(geometryOf(unitBoxMesh()));
    OccluderGenSettings s;
    s.voxels = 0;
    EXPECT_THROW(generateOccluders(*root, s), std::invalid_argument);
    EXPECT_EQ(root->numChildren(), 1u);
    EXPECT_THROW(meshOccluders(*unitBoxMesh(), s), std::invalid_argument);
}
