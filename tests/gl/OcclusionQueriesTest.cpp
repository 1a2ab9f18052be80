// OcclusionQueries: an item behind a wall drawn in the first frame (no answer yet) and left out from the second on,
// back a frame after it shows again; a repeated view, from its second frame on, the pixels of the unculled render.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OcclusionQueries.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/io/ImageIO.h"
#include "testbed/City.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace sg;

namespace {

constexpr int kW = 96, kH = 72;

CullSettings frustumOnly() {
    CullSettings c;
    c.strategy = CullStrategy::Aabb;
    c.occlusion.mode = OcclusionMode::Off;
    return c;
}

bool draws(const DrawList& l, const Mesh* m) {
    return std::any_of(l.items.begin(), l.items.end(), [&](const DrawItem& it) { return it.mesh == m; });
}

// A wall across the view at z = -10, a box behind it at z = -20, a box in front of it at z = -5.
struct WallScene {
    ref_ptr<Mesh> wall = makeBoxMesh(dvec3(-20, -20, -10.5), dvec3(20, 20, -10));
    ref_ptr<Mesh> behind = makeBoxMesh(dvec3(-1), dvec3(1));
    ref_ptr<Mesh> front = makeBoxMesh(dvec3(-0.5), dvec3(0.5));
    ref_ptr<Group> root = make<Group>();
    WallScene() {
        root->addChild(make<Geometry>(wall, make<Material>(vec4(0.8f, 0.8f, 0.8f, 1.0f))));
        auto far = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 0, -20)));
        far->addChild(make<Geometry>(behind, make<Material>(vec4(1, 0, 0, 1))));
        root->addChild(far);
        auto near = make<Transform>(glm::translate(dmat4(1.0), dvec3(2, 0, -5)));
        near->addChild(make<Geometry>(front, make<Material>(vec4(0, 1, 0, 1))));
        root->addChild(near);
    }
};

Camera lookingDown(const dvec3& eye) {
    Camera cam;
    cam.setPerspective(60, double(kW) / kH, 0.5, 100);
    cam.setLookAt(eye, eye + dvec3(0, 0, -1), dvec3(0, 1, 0));
    cam.setViewport(kW, kH);
    return cam;
}

TEST(OcclusionQueries, HiddenFromTheSecondFrameAndBackWhenSeen) {
    OsmesaContext ctx(kW, kH);
    Renderer renderer;
    WallScene w;
    Scene scene(w.root);
    scene.update();
    OcclusionQueries queries;
    CullTraversal cull;
    DrawList list;
    CullStats st;
    const Camera cam = lookingDown(dvec3(0));
    cull.cull(scene, cam, frustumOnly(), list, st);
    ASSERT_EQ(list.items.size(), 3u);

    queries.draw(renderer, list, cam);  // frame 1: no answer yet, all drawn
    EXPECT_EQ(queries.drawn().items.size(), 3u);
    EXPECT_TRUE(draws(queries.drawn(), w.behind.get()));
    EXPECT_EQ(queries.lastStats().queries, 3u);
    EXPECT_EQ(queries.lastStats().hidden, 0u);
    renderer.finish();
    for (int frame = 2; frame <= 3; ++frame) {  // frame 2 on: the box behind the wall is out, and still queried
        cull.cull(scene, cam, frustumOnly(), list, st);
        queries.draw(renderer, list, cam);
        EXPECT_FALSE(draws(queries.drawn(), w.behind.get())) << frame;
        EXPECT_TRUE(draws(queries.drawn(), w.front.get())) << frame;
        EXPECT_TRUE(draws(queries.drawn(), w.wall.get())) << frame;
        EXPECT_EQ(queries.lastStats().hidden, 1u) << frame;
        EXPECT_EQ(queries.lastStats().hiddenTriangles, 12u) << frame;
        EXPECT_EQ(queries.lastStats().queries, 3u) << frame;
        renderer.finish();
    }

    // Past the wall (now behind the eye): the box is still out for a frame (the answer is the last frame's), then in.
    const Camera past = lookingDown(dvec3(0, 0, -15));
    cull.cull(scene, past, frustumOnly(), list, st);
    ASSERT_TRUE(draws(list, w.behind.get()));
    queries.draw(renderer, list, past);
    EXPECT_FALSE(draws(queries.drawn(), w.behind.get()));
    renderer.finish();
    queries.draw(renderer, list, past);
    EXPECT_TRUE(draws(queries.drawn(), w.behind.get()));

    // reset() forgets: everything drawn.
    queries.reset();
    cull.cull(scene, cam, frustumOnly(), list, st);
    queries.draw(renderer, list, cam);
    EXPECT_EQ(queries.drawn().items.size(), 3u);
}

// A view drawn again and again: from the second frame on, exactly the pixels of the render without queries, with
// items hidden, in either depth mode (LEQUAL, or GEQUAL with reversed depth).
// A small city along its street, and the large one from its orbit at a larger viewport (box faces on building faces
// hundreds of metres away, where the depth buffer's steps are centimetres).
TEST(OcclusionQueries, RepeatedViewMatchesTheUnculledRender) {
    const int w = 320, h = 180;
    OsmesaContext ctx(w, h);
    Renderer renderer;
    Scene small(scenes::buildCity({6, false})), large(scenes::buildCity({100, false}));
    small.update();
    large.update();
    std::vector<std::pair<const Scene*, Camera>> views;
    for (int f : {0, 60, 150}) views.push_back({&small, scenes::cityStreetCamera(6, f, kW, kH)});
    for (int f : {10, 50, 90}) views.push_back({&large, scenes::cityOrbitCamera(100, f, w, h)});
    std::vector<Renderer::DepthMode> modes = {Renderer::DepthMode::Classic};
    if (renderer.reverseZSupported()) modes.push_back(Renderer::DepthMode::ReverseZ);
    for (Renderer::DepthMode mode : modes) {
        renderer.setDepthMode(mode);
        for (size_t f = 0; f < views.size(); ++f) {
            const Scene& scene = *views[f].first;
            const Camera& cam = views[f].second;
            CullTraversal cull;
            DrawList list;
            CullStats st;
            cull.cull(scene, cam, frustumOnly(), list, st);
            renderer.draw(list, cam);
            const Image reference = renderer.readColor();
            OcclusionQueries queries;
            for (int frame = 1; frame <= 3; ++frame) {
                cull.cull(scene, cam, frustumOnly(), list, st);
                queries.draw(renderer, list, cam);
                const Image got = renderer.readColor();
                EXPECT_EQ(countDifferingPixels(reference, got), 0u)
                    << "view " << f << " frame " << frame << " reverse " << renderer.lastDepthReversed();
                if (frame > 1) {
                    EXPECT_GT(queries.lastStats().hidden, 0u) << "view " << f << " frame " << frame;
                }
            }
        }
    }
}

}  // namespace
