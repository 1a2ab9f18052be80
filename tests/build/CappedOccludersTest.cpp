// Boxes inside open meshes whose openings are closed by caps in their planes (MeshOccluders::cappedBoxes): a
// building without a floor, a lidless box, a dome, shapes with random holes. What must hold is checked here in double
// precision, independently of the implementation: every box is clear of the mesh's triangles and lies on the positive
// side of every opening plane, and a segment from any eye outside the bound and on the positive side of every plane
// to any point of the box crosses a drawn triangle first.
#include "sg/build/GeneratedOccluders.h"

#include "build/OccluderTestShapes.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/LOD.h"
#include "nodes/Occluder.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace sg;
using namespace occtest;

namespace {

bool beyondAll(const std::vector<Plane>& planes, const dvec3& p) {
    for (const Plane& pl : planes)
        if (!(pl.distance(p) > 0.0)) return false;
    return true;
}

// The property the pass relies on (Occluder::setOpenings), for every capped box; `used` counts the eyes tried from
// the positive side of every plane.
void expectBehindDrawn(const Mesh& mesh, const MeshOccluders& occ, scenes::Rng& rng, const std::string& what, int& used,
                       int eyes = 120) {
    const std::vector<Tri> tris = trianglesOf(mesh);
    const Box bound = mesh.box();
    const double size = glm::length(bound.max - bound.min);
    used = 0;
    for (size_t k = 0; k < occ.cappedBoxes.size(); ++k) {
        const Box& b = occ.cappedBoxes[k];
        SCOPED_TRACE(what + ": capped box " + std::to_string(k) + " " + str(b));
        EXPECT_GT(volume(b), 0.0);
        for (size_t t = 0; t < tris.size(); ++t)
            ASSERT_FALSE(triangleMeetsBox(tris[t], b)) << "triangle " << t << " meets the box";
        for (int c = 0; c < 8; ++c)
            ASSERT_TRUE(beyondAll(
                occ.openings, dvec3(c & 1 ? b.max.x : b.min.x, c & 2 ? b.max.y : b.min.y, c & 4 ? b.max.z : b.min.z)))
                << "corner " << c << " not on the positive side of every opening's plane";
        for (int e = 0; e < eyes; ++e) {
            // Far eyes, and eyes just outside the bound (within half its size).
            dvec3 eye;
            if (e % 2) {
                eye = bound.center() + randomDirection(rng) * (size * 2.0 + 1.0);
            } else {
                const dvec3 h = bound.halfExtent() * 1.5 + 1e-3 * size;
                do eye = bound.center() + dvec3(rng.uniform(-h.x, h.x), rng.uniform(-h.y, h.y), rng.uniform(-h.z, h.z));
                while (bound.contains(eye));
            }
            if (!beyondAll(occ.openings, eye)) continue;
            ++used;
            for (const dvec3& target : samplesOf(b, rng, 2)) {
                const dvec3 d = target - eye;
                const double enter = entryInto(b, eye, d), hit = firstHit(tris, eye, d);
                ASSERT_LE(enter, 1.0 + 1e-12);
                ASSERT_LE(hit, enter) << "from (" << eye.x << " " << eye.y << " " << eye.z << ") to (" << target.x
                                      << " " << target.y << " " << target.z
                                      << "): the box is reached before any triangle";
            }
        }
    }
}

// Walls of a w x d x h building as four quads (outward, corners shared), no floor and no top; a roof slab (a closed
// box) across the top inside the walls, and a door leaf: a quad 5 cm in front of the south wall (a flat part).
ref_ptr<Mesh> buildingWithoutFloor(double w, double d, double h) {
    const double x = w / 2, y = d / 2;
    std::vector<dvec3> pos{{-x, -y, 0}, {x, -y, 0}, {x, y, 0}, {-x, y, 0},
                           {-x, -y, h}, {x, -y, h}, {x, y, h}, {-x, y, h}};
    std::vector<uint32_t> idx;
    for (uint32_t k = 0; k < 4; ++k) {
        const uint32_t a = k, b = (k + 1) % 4, c = b + 4, e = a + 4;  // counter-clockwise seen from outside
        idx.insert(idx.end(), {a, b, c, a, c, e});
    }
    const ref_ptr<Mesh> walls = meshOf(pos, idx);
    const ref_ptr<Mesh> slab = makeBoxMesh(dvec3(-x, -y, h - 0.3), dvec3(x, y, h - 0.05));
    const ref_ptr<Mesh> door = meshOf(
        {{-0.6, -y - 0.05, 0}, {0.6, -y - 0.05, 0}, {0.6, -y - 0.05, 2.1}, {-0.6, -y - 0.05, 2.1}}, {0, 1, 2, 0, 2, 3});
    return merged(*merged(*walls, *slab), *door);
}

// The six faces of makeBoxMesh(..., 1) are triangles 2f, 2f + 1: -z, +z, -y, +y, -x, +x.
ref_ptr<Mesh> boxWithout(std::initializer_list<int> faces) {
    const ref_ptr<Mesh> box = makeBoxMesh(dvec3(-1), dvec3(1), 1);
    std::vector<uint32_t> idx = indicesOf(*box), keep;
    for (size_t t = 0; t < idx.size() / 3; ++t)
        if (std::find(faces.begin(), faces.end(), int(t / 2)) == faces.end())
            keep.insert(keep.end(), idx.begin() + ptrdiff_t(3 * t), idx.begin() + ptrdiff_t(3 * t + 3));
    std::vector<dvec3> pos;
    for (const vec3& p : box->positions()) pos.push_back(dvec3(p));
    return meshOf(pos, std::move(keep));
}

}  // namespace

TEST(CappedOccluders, ALidlessBoxGetsABoxBelowItsOpening) {
    scenes::Rng rng(31);
    for (int i = 0; i < 4; ++i) {
        SCOPED_TRACE(i == 0 ? "in place" : "placement " + std::to_string(i));
        const dmat4 xf = i == 0 ? dmat4(1.0) : randomPlacement(rng);
        const ref_ptr<Mesh> lidless = transformed(*withoutTriangles(*makeBoxMesh(dvec3(-1), dvec3(1), 2), 8, 8), xf);
        ASSERT_FALSE(lidless->closed());
        OccluderGenSettings s;
        s.minBoxShare = 0.001;  // a turned box's bound is larger than the box found inside it
        const MeshOccluders occ = meshOccluders(*lidless, s);
        EXPECT_FALSE(occ.closed);
        EXPECT_TRUE(occ.boxes.empty()) << "not inside a closed mesh's solid";
        EXPECT_TRUE(occ.polygons.empty()) << "a mesh that gets capped boxes gets no polygons";
        ASSERT_FALSE(occ.cappedBoxes.empty());
        ASSERT_EQ(occ.openings.size(), 1u);
        const dvec3 up = glm::normalize(dvec3(xf * dvec4(0, 0, 1, 0)));
        EXPECT_NEAR(glm::dot(occ.openings[0].n, up), -1.0, 1e-6) << "positive below the opening";
        if (i == 0) {
            EXPECT_GT(volume(occ.cappedBoxes[0]), 0.9 * 8.0) << str(occ.cappedBoxes[0]);
        }
        int used = 0;
        expectBehindDrawn(*lidless, occ, rng, "lidless", used);
        EXPECT_GT(used, 40);
        // From above the opening the box is in plain sight: the plane is what keeps such an eye from using it.
        const dvec3 above = dvec3(xf * dvec4(0, 0, 3, 1)), centre = occ.cappedBoxes[0].center();
        EXPECT_LT(occ.openings[0].distance(above), 0.0);
        EXPECT_GT(firstHit(trianglesOf(*lidless), above, centre - above), 1.0) << "something hides it from above";
    }
}

TEST(CappedOccluders, ABuildingWithoutAFloorGetsABoxAndItsDoorLeafIsLeftOut) {
    scenes::Rng rng(32);
    const ref_ptr<Mesh> b = buildingWithoutFloor(20.0, 12.0, 8.0);
    ASSERT_FALSE(b->closed());
    const MeshOccluders occ = meshOccluders(*b);
    ASSERT_FALSE(occ.cappedBoxes.empty());
    // The floor's and the top's loops; the door leaf is flat and bounds nothing, so it adds no plane.
    ASSERT_EQ(occ.openings.size(), 2u);
    for (const Plane& p : occ.openings) EXPECT_NEAR(std::abs(p.n.z), 1.0, 1e-9) << "a plane that is not a floor or top";
    EXPECT_TRUE(beyondAll(occ.openings, dvec3(0, -20, 1.7))) << "an eye on the street in front of the door";
    EXPECT_FALSE(beyondAll(occ.openings, dvec3(0, -20, 9.0))) << "an eye above the walls' top";
    EXPECT_GT(volume(occ.cappedBoxes[0]), 0.5 * 20.0 * 12.0 * 8.0) << str(occ.cappedBoxes[0]);
    int used = 0;
    expectBehindDrawn(*b, occ, rng, "building", used, 200);
    EXPECT_GT(used, 50);
}

TEST(CappedOccluders, ADomeGetsBoxesAboveItsRim) {
    scenes::Rng rng(33);
    const ref_ptr<Mesh> dome = uvSphere(2.0, 16, 32, true);
    const MeshOccluders occ = meshOccluders(*dome);
    ASSERT_FALSE(occ.cappedBoxes.empty());
    ASSERT_EQ(occ.openings.size(), 1u);
    EXPECT_NEAR(occ.openings[0].n.z, 1.0, 1e-9);
    int used = 0;
    expectBehindDrawn(*dome, occ, rng, "dome", used);
    EXPECT_GT(used, 50);
}

TEST(CappedOccluders, RandomHolesKeepTheBoxesBehindDrawnTriangles) {
    scenes::Rng rng(34);
    const std::vector<std::pair<std::string, ref_ptr<Mesh>>> shapes{{"torus", torus(3.0, 1.2, 24, 12)},
                                                                    {"sphere", uvSphere(2.0, 12, 24)},
                                                                    {"L prism", lPrism()},
                                                                    {"U", uShape()},
                                                                    {"notched box", notchedBox()},
                                                                    {"two boxes", twoBoxes()},
                                                                    {"box", makeBoxMesh(dvec3(-1), dvec3(1), 3)}};
    int capped = 0, eyes = 0;
    for (const auto& [name, shape] : shapes)
        for (int trial = 0; trial < 6; ++trial) {
            const uint32_t n = shape->triangleCount(), count = 1 + uint32_t(rng.uniform(0, 4));
            const uint32_t first = uint32_t(rng.uniform(0, double(n - count)));
            const ref_ptr<Mesh> m = transformed(*withoutTriangles(*shape, first, count), randomPlacement(rng));
            const std::string what = name + " without triangles " + std::to_string(first) + ".." +
                                     std::to_string(first + count - 1) + " (trial " + std::to_string(trial) + ")";
            for (double depth : {0.02, 1.0}) {  // 1: any loop, the plane moved past its cap's slab
                OccluderGenSettings s;
                s.openingDepth = depth;
                const MeshOccluders occ = meshOccluders(*m, s);
                if (!occ.cappedBoxes.empty()) ++capped;
                int used = 0;
                expectBehindDrawn(*m, occ, rng, what, used, 40);
                eyes += used;
                if (HasFatalFailure()) return;
            }
        }
    EXPECT_GT(capped, 15) << "few shapes with holes got boxes: the property was hardly tried";
    EXPECT_GT(eyes, 500);
}

TEST(CappedOccluders, AnOpeningFarOffItsPlaneLeavesItsPartOut) {
    scenes::Rng rng(35);
    // The +z and -y faces gone: one opening bent over the edge between them.
    const ref_ptr<Mesh> m = boxWithout({1, 2});
    MeshOccluders occ = meshOccluders(*m);
    EXPECT_TRUE(occ.cappedBoxes.empty());
    EXPECT_FALSE(occ.polygons.empty()) << "left with its faces as polygons";
    // Allowed any depth, the plane lies past the whole bent loop: boxes, still behind the drawn faces.
    OccluderGenSettings deep;
    deep.openingDepth = 1.0;
    occ = meshOccluders(*m, deep);
    ASSERT_FALSE(occ.cappedBoxes.empty());
    ASSERT_EQ(occ.openings.size(), 1u);
    int used = 0;
    expectBehindDrawn(*m, occ, rng, "bent opening", used, 300);
    EXPECT_GT(used, 10);
}

TEST(CappedOccluders, TooManyOpeningsOrCappingOffGiveNoBoxes) {
    const ref_ptr<Mesh> tube = boxWithout({0, 1});  // open at both ends
    MeshOccluders occ = meshOccluders(*tube);
    ASSERT_FALSE(occ.cappedBoxes.empty());
    EXPECT_EQ(occ.openings.size(), 2u);
    OccluderGenSettings one;
    one.maxOpenings = 1;
    occ = meshOccluders(*tube, one);
    EXPECT_TRUE(occ.cappedBoxes.empty());
    EXPECT_TRUE(occ.openings.empty());
    EXPECT_EQ(occ.polygons.size(), 4u) << "its walls as polygons instead";
    OccluderGenSettings off;
    off.capOpenings = false;
    EXPECT_TRUE(meshOccluders(*tube, off).cappedBoxes.empty());
}

TEST(CappedOccluders, AClosedPartBesideAFlatOneGetsBoxesWithNoPlanes) {
    scenes::Rng rng(36);
    const ref_ptr<Mesh> quad = meshOf({{5, 5, 0}, {7, 5, 0}, {7, 7, 0}, {5, 7, 0}}, {0, 1, 2, 0, 2, 3});
    const ref_ptr<Mesh> m = merged(*makeBoxMesh(dvec3(-1), dvec3(1), 2), *quad);
    ASSERT_FALSE(m->closed());
    OccluderGenSettings any;
    any.minBoxShare = 0.0;  // the box is 4% of the bound the quad stretches
    const MeshOccluders occ = meshOccluders(*m, any);
    ASSERT_FALSE(occ.cappedBoxes.empty());
    EXPECT_TRUE(occ.openings.empty());
    EXPECT_GT(volume(occ.cappedBoxes[0]), 0.5 * 8.0);
    int used = 0;
    expectBehindDrawn(*m, occ, rng, "box beside a quad", used);
    EXPECT_GT(used, 100);
}

TEST(CappedOccluders, AnInsideOutLidlessBoxGetsNone) {
    const ref_ptr<Mesh> lidless = boxWithout({1});
    std::vector<uint32_t> idx = indicesOf(*lidless);
    for (size_t i = 0; i < idx.size(); i += 3) std::swap(idx[i + 1], idx[i + 2]);
    std::vector<dvec3> pos;
    for (const vec3& p : lidless->positions()) pos.push_back(dvec3(p));
    EXPECT_TRUE(meshOccluders(*meshOf(pos, idx)).cappedBoxes.empty());
}

TEST(CappedOccluders, AGeometryAndAnLodGetBoxesThatCarryTheirOpenings) {
    auto root = make<Group>();
    const ref_ptr<Mesh> lidless = boxWithout({1});
    root->addChild(make<Geometry>(lidless, make<Material>()));
    OccluderGenStats st = generateOccluders(*root);
    std::vector<const Occluder*> occ;
    for (size_t c = 0; c < root->numChildren(); ++c)
        if (root->child(c)->kind() == NodeKind::Occluder) occ.push_back(static_cast<const Occluder*>(root->child(c)));
    ASSERT_EQ(occ.size(), 1u) << "one box and no polygons";
    EXPECT_EQ(occ[0]->shape(), Occluder::Shape::Box);
    EXPECT_EQ(occ[0]->openings().size(), 1u);
    EXPECT_EQ(occ[0]->eyeOutside().min, lidless->box().min);
    EXPECT_EQ(st.boxes, 1u);
    EXPECT_EQ(st.polygons, 0u);

    // An LOD of a lidless and a floorless level: a box inside both, used beyond both openings.
    auto lodRoot = make<Group>();
    auto lod = make<LOD>();
    lod->addChild(make<Geometry>(lidless, make<Material>()), 0.0f, 50.0f);
    lod->addChild(make<Geometry>(boxWithout({0}), make<Material>()), 50.0f, 500.0f);
    lodRoot->addChild(lod);
    st = generateOccluders(*lodRoot);
    ASSERT_EQ(lodRoot->numChildren(), 2u);
    ASSERT_EQ(lodRoot->child(1)->kind(), NodeKind::Occluder);
    const auto& o = static_cast<const Occluder&>(*lodRoot->child(1));
    EXPECT_EQ(o.shownWith(), lod.get());
    ASSERT_EQ(o.openings().size(), 2u);
    EXPECT_NEAR(o.openings()[0].n.z * o.openings()[1].n.z, -1.0, 1e-9) << "the lid's plane and the floor's";
    EXPECT_TRUE(beyondAll(o.openings(), o.box().center()));
}
