// Renderer::prepare: a paged detail's meshes uploaded ahead of its first draw, within the budget of each call.
#include "TestUtil.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"

#include <gtest/gtest.h>

#include <chrono>

using namespace sg;

// The time limit, without a clock's luck: a budget whose frame began an hour ago is spent before it starts (nothing
// is listed nor uploaded, and the call says the detail is not ready), however many objects it allows; one that
// began now with time to spare uploads the whole detail.
TEST(RendererPrepare, ABudgetWhoseTimeIsSpentUploadsNothing) {
    OsmesaContext context(200, 150);
    Renderer renderer;
    auto detail = make<Group>();
    for (int k = 0; k < 4; ++k) detail->addChild(make<Geometry>(makeBoxMesh(dvec3(k), dvec3(k + 1)), make<Material>()));
    PrepareBudget late(5.0, 1000);
    late.start -= std::chrono::hours(1);
    EXPECT_TRUE(late.exhausted());
    EXPECT_FALSE(renderer.prepare(*detail, late));
    EXPECT_EQ(renderer.cachedMeshes(), 0u);
    EXPECT_EQ(late.objectsUsed, 0u);
    PrepareBudget ample(60000.0, 1000);  // a minute: the time is not what stops it
    EXPECT_TRUE(renderer.prepare(*detail, ample));
    EXPECT_EQ(renderer.cachedMeshes(), 4u);
    EXPECT_EQ(ample.objectsUsed, 4u);
}

TEST(RendererPrepare, UploadsWithinTheObjectBudgetAndTheFirstDrawUploadsNothingMore) {
    OsmesaContext context(200, 150);
    Renderer renderer;
    // A detail of five boxes side by side, each a mesh of its own, and a textured one (a mesh and a texture).
    auto detail = make<Group>();
    for (int k = 0; k < 5; ++k) {
        auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(3.0 * k - 6.0, 0, 0)));
        t->addChild(make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), make<Material>()));
        detail->addChild(t);
    }
    auto textured = make<Material>();
    textured->texture = make<Texture>(2, 2, std::vector<uint8_t>(16, 200));
    auto tt = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 0, 3)));
    tt->addChild(make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), textured));
    detail->addChild(tt);
    // Seven objects, two a call.
    int calls = 0;
    size_t bytes = 0;
    for (bool done = false; !done; ++calls) {
        ASSERT_LT(calls, 10);
        PrepareBudget budget(1e9, 2);  // objects alone decide
        const size_t meshes = renderer.cachedMeshes(), textures = renderer.cachedTextures();
        done = renderer.prepare(*detail, budget);
        EXPECT_LE(budget.objectsUsed, 2u);
        EXPECT_EQ(renderer.cachedMeshes() + renderer.cachedTextures(), meshes + textures + budget.objectsUsed);
        bytes += budget.bytesUsed;
    }
    EXPECT_EQ(calls, 4);
    EXPECT_EQ(renderer.cachedMeshes(), 6u);
    EXPECT_EQ(renderer.cachedTextures(), 1u);
    EXPECT_GT(bytes, 6u * makeBoxMesh(dvec3(-1), dvec3(1))->bytes());
    // A spent budget uploads nothing, and says whether something is left.
    PrepareBudget none(1e9, 0);
    EXPECT_TRUE(renderer.prepare(*detail, none));  // everything is there already
    // Kept by releaseUnused() before their first draw, for a few frames.
    renderer.releaseUnused();
    EXPECT_EQ(renderer.cachedMeshes(), 6u);
    // The first draw of the detail uploads nothing more.
    Scene scene(detail);
    scene.update();
    Camera cam = testutil::lookingAlongY();
    cam.setViewport(200, 150);
    cam.setLookAt(dvec3(0, -20, 2), dvec3(0, 0, 0), dvec3(0, 0, 1));
    CullTraversal cull;
    DrawList list;
    CullStats st;
    cull.cull(scene, cam, CullSettings{}, list, st);
    ASSERT_EQ(list.items.size(), 6u);
    renderer.draw(list, cam);
    EXPECT_EQ(renderer.cachedMeshes(), 6u);
    EXPECT_EQ(renderer.cachedTextures(), 1u);
}

TEST(RendererPrepare, ADetailPreparedButNeverDrawnIsReleasedAfterTheGrace) {
    OsmesaContext context(64, 64);
    Renderer renderer;
    auto detail = make<Group>();
    detail->addChild(make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), make<Material>()));
    PrepareBudget budget(1e9, 20);  // objects alone decide: the default's millisecond is missed on a loaded machine
    ASSERT_TRUE(renderer.prepare(*detail, budget));
    EXPECT_EQ(budget.objectsUsed, 1u);
    Camera cam = testutil::lookingAlongY();
    cam.setViewport(64, 64);
    for (int k = 0; k < 20; ++k) {
        renderer.draw(DrawList{}, cam);
        renderer.releaseUnused();
    }
    EXPECT_EQ(renderer.cachedMeshes(), 0u);
}

// A dropped detail's copies go (nothing else can draw them), those of meshes the program still holds stay, drawn or
// not: what keeps a paged flight's memory to its pager's budget.
TEST(RendererPrepare, OrphansAreReleasedAndHeldMeshesKept) {
    OsmesaContext context(64, 64);
    Renderer renderer;
    ref_ptr<Mesh> kept = makeBoxMesh(dvec3(-1), dvec3(1));
    auto dropped = make<Group>();
    dropped->addChild(make<Geometry>(makeBoxMesh(dvec3(2), dvec3(3)), make<Material>()));
    auto held = make<Group>();
    held->addChild(make<Geometry>(kept, make<Material>()));
    PrepareBudget budget(1e9, 20);
    ASSERT_TRUE(renderer.prepare(*dropped, budget));
    ASSERT_TRUE(renderer.prepare(*held, budget));
    EXPECT_EQ(renderer.cachedMeshes(), 2u);
    renderer.forgetPrepare(*dropped);
    renderer.forgetPrepare(*held);
    dropped = nullptr;
    held = nullptr;  // `kept` still holds its mesh
    renderer.releaseOrphans();
    EXPECT_EQ(renderer.cachedMeshes(), 1u);
    kept = nullptr;
    renderer.releaseOrphans();
    EXPECT_EQ(renderer.cachedMeshes(), 0u);
}

// A detail's shader variants are compiled by prepare(), before it is attached: its first draw compiles none. Four:
// the lit box's, the unlit textured box's, the points', and the dissolving one of the box below an LOD with a
// transition (its whole one is the first box's). A spent budget compiles none.
TEST(RendererPrepare, ADetailsShaderVariantsAreCompiledBeforeItIsAttached) {
    OsmesaContext context(200, 150);
    Renderer renderer;
    auto detail = make<Group>();
    detail->addChild(make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), make<Material>()));
    auto unlit = make<Material>();
    unlit->unlit = true;
    unlit->texture = make<Texture>(2, 2, std::vector<uint8_t>(16, 200));
    auto square = make<Mesh>();
    square->set({{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}}, std::vector<vec3>(4, vec3(0, -1, 0)),
                {0, 1, 2, 0, 2, 3}, {{0, 0}, {1, 0}, {1, 1}, {0, 1}});
    detail->addChild(make<Geometry>(square, unlit));
    auto points = make<Mesh>();
    points->setPoints({{0.0f, 0.0f, 0.0f}, {0.5f, 0.0f, 0.0f}});
    detail->addChild(make<Geometry>(points, make<Material>()));
    auto lod = make<LOD>();
    lod->addChild(make<Geometry>(makeBoxMesh(dvec3(2), dvec3(3)), make<Material>()), 0.0f, 50.0f);
    lod->setTransition(5.0f);
    detail->addChild(lod);

    PrepareBudget late(5.0, 1000);
    late.start -= std::chrono::hours(1);
    EXPECT_FALSE(renderer.prepare(*detail, late));
    EXPECT_EQ(renderer.variantCount(), 0u);
    PrepareBudget ample(60000.0, 1000);
    ASSERT_TRUE(renderer.prepare(*detail, ample));
    EXPECT_EQ(renderer.variantCount(), 4u);
    EXPECT_EQ(renderer.compiledInDraw(), 0u);

    Scene scene(detail);
    scene.update();
    Camera cam = testutil::lookingAlongY();
    cam.setViewport(200, 150);
    cam.setLookAt(dvec3(0, -8, 0), dvec3(0, 0, 0), dvec3(0, 0, 1));
    CullTraversal cull;
    DrawList list;
    CullStats st;
    cull.cull(scene, cam, CullSettings{}, list, st);
    ASSERT_EQ(list.items.size(), 4u);
    renderer.draw(list, cam);
    EXPECT_EQ(renderer.lastStats().programsCompiled, 0u);
    EXPECT_EQ(renderer.compiledInDraw(), 0u);
    EXPECT_EQ(renderer.variantCount(), 4u);
}
