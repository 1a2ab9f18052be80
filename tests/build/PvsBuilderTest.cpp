// PvsBuilder: hand-made cases where the answer is known: a wall hides a box behind it from a cell, but not
// through a gap, not from a cell that sees around the wall's end, not from a cell inside the wall; two
// overlapping walls hide together what neither hides alone; with either choice of projection plane.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Occluder.h"
#include "nodes/Transform.h"
#include "sg/build/PvsBuilder.h"
#include "sg/scene/Scene.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {
ref_ptr<Geometry> boxGeom(const Box& b) { return make<Geometry>(makeBoxMesh(b.min, b.max), make<Material>()); }

// A wall: geometry and a box occluder over the same box, under one group.
ref_ptr<Group> wall(const Box& b) {
    auto g = make<Group>();
    g->addChild(boxGeom(b));
    auto o = make<Occluder>();
    o->setBox(b);
    g->addChild(o);
    return g;
}
// A wall across +y at y = 20..21 over x in [x0, x1], z in [-10, 10].
ref_ptr<Group> wallX(double x0, double x1) { return wall(Box{dvec3(x0, 20, -10), dvec3(x1, 21, 10)}); }

const Box kTarget{dvec3(-1, 40, -1), dvec3(1, 42, 1)};

struct Built {
    PvsTable table;
    PvsBuilder::Stats stats;
};
// One cell, the box [centre - 1, centre + 1].
Built buildOneCell(const Scene& s, const dvec3& centre, PvsBuilder::Plane plane = PvsBuilder::Plane::Both) {
    PvsBuilder::Options o;
    o.plane = plane;
    o.region = Box{centre - 1.0, centre + 1.0};
    o.cellSize = dvec3(2.0);
    Built b;
    b.table = PvsBuilder::build(s, o, &b.stats);
    EXPECT_EQ(b.table.cellCount(), 1u);
    return b;
}

// The entry index of a node's image entry (the image is pre-order: root 0, then its children's subtrees).
uint32_t entryOfChild(const Scene& s, size_t child) {
    uint32_t j = 1;
    for (size_t k = 0; k < child; ++k) j = s.image().end[j];
    return j;
}
}  // namespace

TEST(PvsBuilder, WallHidesTheBoxBehindIt) {
    auto root = make<Group>();
    root->addChild(wallX(-10, 10));
    root->addChild(boxGeom(kTarget));                                   // 1: behind the wall
    root->addChild(boxGeom(Box{dvec3(-1, 10, -1), dvec3(1, 12, 1)}));   // 2: in front of it
    root->addChild(boxGeom(Box{dvec3(40, 40, -1), dvec3(42, 42, 1)}));  // 3: far off to the side
    Scene s(root);
    s.update();
    const Built b = buildOneCell(s, dvec3(0.0));
    EXPECT_TRUE(b.table.isHidden(0, entryOfChild(s, 1)));
    EXPECT_FALSE(b.table.isHidden(0, entryOfChild(s, 2)));
    EXPECT_FALSE(b.table.isHidden(0, entryOfChild(s, 3)));
    EXPECT_FALSE(b.table.isHidden(0, 0));
    for (uint32_t e = entryOfChild(s, 0); e < s.image().end[entryOfChild(s, 0)]; ++e)
        EXPECT_FALSE(b.table.isHidden(0, e)) << "the wall's own entries, " << e;
    EXPECT_EQ(b.table.hiddenCount(0), 1u);
    EXPECT_EQ(b.stats.cellsComputed, 1u);
    EXPECT_GE(b.stats.occluders, 1u);
}

TEST(PvsBuilder, HiddenParentHidesItsSubtreeWithOneBit) {
    auto root = make<Group>();
    root->addChild(wallX(-10, 10));
    auto group = make<Group>();
    group->addChild(boxGeom(kTarget));
    auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 3, 0)));
    t->addChild(boxGeom(kTarget));
    group->addChild(t);
    root->addChild(group);
    Scene s(root);
    s.update();
    const Built b = buildOneCell(s, dvec3(0.0));
    const uint32_t g = entryOfChild(s, 1);
    EXPECT_TRUE(b.table.isHidden(0, g));
    EXPECT_EQ(b.table.hiddenCount(0), 1u);  // the entries below are not even tested
}

TEST(PvsBuilder, GapBetweenWallsLetsTheBoxBeSeen) {
    auto root = make<Group>();
    root->addChild(wallX(-10, -0.5));
    root->addChild(wallX(0.5, 10));
    root->addChild(boxGeom(Box{dvec3(-0.2, 40, -0.2), dvec3(0.2, 42, 0.2)}));
    Scene s(root);
    s.update();
    for (auto plane : {PvsBuilder::Plane::BeyondAll, PvsBuilder::Plane::BeyondLargest}) {
        const Built b = buildOneCell(s, dvec3(0.0), plane);
        EXPECT_FALSE(b.table.isHidden(0, entryOfChild(s, 2)));
        EXPECT_EQ(b.table.hiddenCount(0), 0u);
    }
}

TEST(PvsBuilder, CellBesideTheWallSeesAroundItsEnd) {
    auto root = make<Group>();
    root->addChild(wallX(-10, 10));
    root->addChild(boxGeom(kTarget));
    Scene s(root);
    s.update();
    // From x = 30 the line to the box crosses the wall's plane at x ~ 15, past its end at 10.
    EXPECT_FALSE(buildOneCell(s, dvec3(30, 0, 0)).table.isHidden(0, entryOfChild(s, 1)));
    // From x = 5 it crosses at ~2.5: hidden.
    EXPECT_TRUE(buildOneCell(s, dvec3(5, 0, 0)).table.isHidden(0, entryOfChild(s, 1)));
}

TEST(PvsBuilder, TwoWallsHideTogetherWhatNeitherHidesAlone) {
    // Overlapping by a metre over the box's line of sight: from the cell's corners at x = -1 and x = 1
    // each wall alone leaves part of the box in view.
    for (int walls : {1, 2, 3}) {
        auto root = make<Group>();
        root->addChild(boxGeom(kTarget));
        if (walls & 1) root->addChild(wallX(-10, 0.5));
        if (walls & 2) root->addChild(wallX(-0.5, 10));
        Scene s(root);
        s.update();
        for (auto plane : {PvsBuilder::Plane::BeyondAll, PvsBuilder::Plane::BeyondLargest})
            EXPECT_EQ(buildOneCell(s, dvec3(0.0), plane).table.isHidden(0, entryOfChild(s, 0)), walls == 3)
                << "walls " << walls << ", plane " << int(plane);
    }
}

TEST(PvsBuilder, NoOccludersNothingHidden) {
    auto root = make<Group>();
    root->addChild(wallX(-10, 10));
    root->addChild(boxGeom(kTarget));
    Scene s(root);
    s.update();
    PvsBuilder::Options o;
    o.region = Box{dvec3(-1), dvec3(1)};
    o.maxOccluders = 0;
    PvsBuilder::Stats st;
    EXPECT_EQ(PvsBuilder::build(s, o, &st).hiddenCount(0), 0u);
    EXPECT_EQ(st.occluders, 0u);
    o.maxOccluders = 1;
    EXPECT_EQ(PvsBuilder::build(s, o, &st).hiddenCount(0), 1u);
}

TEST(PvsBuilder, OccluderTouchingTheCellOrTooNearIsNotUsed) {
    auto root = make<Group>();
    root->addChild(wallX(-10, 10));
    root->addChild(boxGeom(kTarget));
    Scene s(root);
    s.update();
    // The cell reaching into the wall (y 19.5..21.5): the eye may be inside it.
    EXPECT_FALSE(buildOneCell(s, dvec3(0, 20.5, 0)).table.isHidden(0, entryOfChild(s, 1)));
    // The cell's face 0.5 m from the wall, nearer than the farthest near plane (1 m): not used.
    EXPECT_FALSE(buildOneCell(s, dvec3(0, 18.5, 0)).table.isHidden(0, entryOfChild(s, 1)));
    // 2 m away: used.
    EXPECT_TRUE(buildOneCell(s, dvec3(0, 17, 0)).table.isHidden(0, entryOfChild(s, 1)));
}

TEST(PvsBuilder, BoxStraddlingTheWallsDepthIsNotHidden) {
    // The box reaches in front of the wall's far face: the depth test must keep it.
    auto root = make<Group>();
    root->addChild(wallX(-10, 10));
    root->addChild(boxGeom(Box{dvec3(-1, 20.5, -1), dvec3(1, 30, 1)}));
    Scene s(root);
    s.update();
    EXPECT_FALSE(buildOneCell(s, dvec3(0.0)).table.isHidden(0, entryOfChild(s, 1)));
}

TEST(PvsBuilder, EveryDirection) {
    // The same wall and box turned to face each axis direction: hidden in all six.
    for (int dir = 0; dir < 6; ++dir) {
        const int a = dir / 2;
        const double sgn = dir & 1 ? -1.0 : 1.0;
        auto place = [&](const Box& b) {  // y becomes axis a, times sgn; x and z the other two
            Box r;
            for (const dvec3& p : {b.min, b.max}) {
                dvec3 q;
                q[a] = sgn * p.y;
                q[(a + 1) % 3] = p.x;
                q[(a + 2) % 3] = p.z;
                r.expand(q);
            }
            return r;
        };
        auto root = make<Group>();
        root->addChild(wall(place(Box{dvec3(-10, 20, -10), dvec3(10, 21, 10)})));
        root->addChild(boxGeom(place(kTarget)));
        Scene s(root);
        s.update();
        EXPECT_TRUE(buildOneCell(s, dvec3(0.0)).table.isHidden(0, entryOfChild(s, 1))) << "direction " << dir;
    }
}

TEST(PvsBuilder, OnlyTheCellsAskedForAreComputed) {
    auto root = make<Group>();
    root->addChild(wallX(-10, 10));
    root->addChild(boxGeom(kTarget));
    Scene s(root);
    s.update();
    PvsBuilder::Options o;
    o.region = Box{dvec3(-5, -1, -1), dvec3(5, 1, 1)};
    o.cellSize = dvec3(2.0);
    o.only = {dvec3(-4, 0, 0)};
    PvsBuilder::Stats st;
    const PvsTable t = PvsBuilder::build(s, o, &st);
    EXPECT_EQ(t.cellCount(), 5u);
    EXPECT_EQ(st.cellsComputed, 1u);
    EXPECT_EQ(t.hiddenCount(0), 1u);
    for (size_t c = 1; c < 5; ++c) EXPECT_EQ(t.hiddenCount(c), 0u) << c;
}

TEST(PvsBuilder, GridAndBadOptions) {
    PvsBuilder::Options o;
    o.region = Box{dvec3(0, 0, 1), dvec3(10, 4, 1)};  // flat along z
    o.cellSize = dvec3(3, 5, 1);
    const PvsTable::Grid g = PvsBuilder::gridFor(o);
    EXPECT_EQ(g.nx, 4u);
    EXPECT_EQ(g.ny, 1u);
    EXPECT_EQ(g.nz, 1u);
    EXPECT_DOUBLE_EQ(g.cellSize.x, 2.5);
    EXPECT_DOUBLE_EQ(g.cellSize.y, 4.0);
    Scene s(make<Group>());
    s.update();
    o.resolution = 8;
    EXPECT_THROW(PvsBuilder::build(s, o), std::invalid_argument);
    o.resolution = 64;
    o.cellSize.x = 0;
    EXPECT_THROW(PvsBuilder::build(s, o), std::invalid_argument);
    o.cellSize.x = 1;
    o.region = Box{};
    EXPECT_THROW(PvsBuilder::build(s, o), std::invalid_argument);
}
