// The built-in scenes (docs/scenes.md): their sizes, shared meshes, occluders and camera paths as documented.
#include "nodes/Occluder.h"
#include "nodes/Transform.h"
#include "sg/core/NodeVisitor.h"
#include "sg/cull/CullTraversal.h"
#include "testbed/City.h"
#include "testbed/Office.h"
#include "testbed/PcvrCity.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {
// World boxes of every Occluder, and the number of nodes (per path).
struct Census : NodeVisitor {
    std::vector<Box> occluders;
    uint64_t nodes = 0;
    std::vector<dmat4> stack{dmat4(1.0)};
    void apply(Node& n) override {
        ++nodes;
        traverse(n);
    }
    void apply(Transform& t) override {
        ++nodes;
        stack.push_back(t.apply(stack.back()));
        traverse(t);
        stack.pop_back();
    }
    void apply(Occluder& o) override {
        ++nodes;
        occluders.push_back(transformBox(stack.back(), o.box()));
    }
};
}  // namespace

TEST(Scenes, CityHasSevenNodesPerCellAndItsHeights) {
    for (int n : {1, 9, 20}) {
        auto root = scenes::buildCity({n, false});
        Census c;
        root->accept(c);
        EXPECT_EQ(c.nodes, scenes::cityNodeCount(n));
    }
    EXPECT_EQ(scenes::cityHeight(0, 0), 10u);
    EXPECT_EQ(scenes::cityHeight(1, 0), 10u + 73856093u % 51u);
    // With occluders: one box per building, equal to it.
    auto root = scenes::buildCity({3, true});
    Census c;
    root->accept(c);
    ASSERT_EQ(c.occluders.size(), 9u);
    EXPECT_EQ(c.occluders[0].min, dvec3(4, 4, 0));
    EXPECT_EQ(c.occluders[0].max, dvec3(16, 16, scenes::cityHeight(0, 0)));
}

TEST(Scenes, OfficeHasItsRoomsWallsAndFurniture) {
    const int r = 8;
    scenes::OfficeCounts counts;
    auto root = scenes::buildOffice(r, &counts);
    EXPECT_EQ(counts.rooms, r * r);
    // Inner walls: 2R(R-1), three boxes each (two beside the door, the lintel); outer walls: 4R, one box.
    EXPECT_EQ(counts.wallBoxes, 3 * 2 * r * (r - 1) + 4 * r);
    // Per room: 4 desks (top + 4 legs), 4 chairs (seat, back, post), 4 monitors (screen, foot), a shelf
    // with 4 boards.
    EXPECT_EQ(counts.furnitureBoxes, r * r * (4 * 5 + 4 * 3 + 4 * 2 + 5));
    Census c;
    root->accept(c);
    EXPECT_EQ(int(c.occluders.size()), counts.wallBoxes);
    // Every box has 12 triangles: culling off, everything is drawn.
    Scene s(root);
    s.update();
    CullSettings none;
    none.strategy = CullStrategy::None;
    DrawList list;
    CullStats st;
    CullTraversal().cull(s, scenes::officeWalkCamera(r, 0), none, list, st);
    EXPECT_EQ(st.triangles, uint64_t(12 * (r * r + counts.wallBoxes + counts.furnitureBoxes)));
    // The walk passes through the doors: the eye (and its near plane) never enters a wall.
    for (int f = 0; f < scenes::kWalkFrames; ++f) {
        const dvec3 eye = scenes::officeWalkCamera(r, f).eye();
        for (const Box& b : c.occluders) {
            const Box grown{b.min - dvec3(0.1), b.max + dvec3(0.1)};
            ASSERT_FALSE(grown.contains(eye)) << "frame " << f << " eye " << eye.x << " " << eye.y;
        }
    }
}

TEST(Scenes, PcvrCityHas25ObjectsAnd23400TrianglesForEverySeedAndAStreetLevelPath) {
    for (uint64_t seed : {1u, 2u, 3u, 99u}) {
        Scene scene(scenes::buildPcvrCity(seed));
        scene.update();
        // Everything in view of a camera far above, culling off: every object, every triangle.
        Camera above;
        above.setViewport(64, 64);
        above.setPerspective(90.0, 1.0, 1.0, 5000.0);
        above.setLookAt(dvec3(200, 200, 1000), dvec3(200, 200, 0), dvec3(0, 1, 0));
        CullSettings none;
        none.strategy = CullStrategy::None;
        DrawList list;
        CullStats st;
        CullTraversal().cull(scene, above, none, list, st);
        EXPECT_EQ(st.geometries, uint64_t(scenes::kPcvrObjects)) << seed;
        EXPECT_EQ(st.triangles, uint64_t(scenes::kPcvrTriangles)) << seed;
    }
    // The path: eye 1.5 m up, on the streets' inner square, level; it closes on itself.
    for (int f = 0; f < scenes::kPcvrFrames; f += 7) {
        const Camera c = scenes::pcvrCityCamera(f);
        EXPECT_DOUBLE_EQ(c.eye().z, 1.5);
        EXPECT_NEAR(c.viewDirection().z, 0.0, 1e-12);
        const bool onStreet = std::abs(c.eye().x - 100) < 1e-9 || std::abs(c.eye().x - 300) < 1e-9 ||
                              std::abs(c.eye().y - 100) < 1e-9 || std::abs(c.eye().y - 300) < 1e-9;
        EXPECT_TRUE(onStreet) << f;
        EXPECT_EQ(c.width(), 1024);
        EXPECT_EQ(c.height(), 768);
    }
    EXPECT_EQ(scenes::pcvrCityCamera(scenes::kPcvrFrames).eye(), scenes::pcvrCityCamera(0).eye());
}
