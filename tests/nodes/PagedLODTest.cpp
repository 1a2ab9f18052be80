#include "TestUtil.h"
#include "nodes/PagedLOD.h"
#include "sg/cull/CullTraversal.h"
#include "sg/intersect/IntersectTraversal.h"

#include <gtest/gtest.h>

#include <set>

using namespace sg;

namespace {

struct Tile {
    ref_ptr<Group> root = make<Group>();
    ref_ptr<PagedLOD> paged = make<PagedLOD>();
    ref_ptr<Mesh> coarse = makeBoxMesh(dvec3(-1), dvec3(1));
    ref_ptr<Mesh> fine = makeBoxMesh(dvec3(-1), dvec3(1), 3);
    // The tile 10 m ahead of a camera at the origin looking along +y; detail wanted within 50 m.
    Tile() {
        auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 10, 0)));
        paged->addChild(make<Geometry>(coarse, make<Material>()));
        paged->setFile("tile.glb");
        paged->setRange(0.0f, 50.0f);
        t->addChild(paged);
        root->addChild(t);
    }
    void attach() {
        auto g = make<Group>();
        g->addChild(make<Geometry>(fine, make<Material>()));
        paged->attachDetail(g, 123);
    }
};

std::set<const Mesh*> cull(const Scene& s, const Camera& cam, CullStats* stats = nullptr, CullTraversal* t = nullptr) {
    CullTraversal local;
    DrawList list;
    CullStats st;
    (t ? *t : local).cull(s, cam, CullSettings{}, list, st);
    if (stats) *stats = st;
    std::set<const Mesh*> drawn;
    for (const DrawItem& it : list.items) drawn.insert(it.mesh);
    return drawn;
}

}  // namespace

TEST(PagedLOD, SettersCheckTheirArguments) {
    auto p = make<PagedLOD>();
    EXPECT_THROW(p->setFile(""), std::invalid_argument);
    try {
        p->setRange(5.0f, 1.0f);
        FAIL();
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()).rfind("PagedLOD::setRange(): ", 0), 0u) << e.what();
    }
    EXPECT_THROW(p->setRange(-1.0f, 1.0f), std::invalid_argument);
    EXPECT_THROW(p->setRadius(-1.0), std::invalid_argument);
    EXPECT_THROW(p->setCenter(dvec3(NAN)), std::invalid_argument);
    EXPECT_THROW(p->attachDetail(nullptr, 0), std::invalid_argument);
    p->setFile("a.glb");
    p->attachDetail(make<Group>(), 0);
    EXPECT_THROW(p->attachDetail(make<Group>(), 0), std::logic_error);
    try {
        p->setFile("b.glb");
        FAIL();
    } catch (const std::logic_error& e) {
        EXPECT_NE(std::string(e.what()).find("a.glb"), std::string::npos) << e.what();
    }
    p->detachDetail();
    p->setFailed("a.glb: broken");
    p->setFile("b.glb");  // a failed node takes a new file and is Unloaded again
    EXPECT_EQ(p->state(), PagedLOD::State::Unloaded);
    EXPECT_TRUE(p->error().empty());
}

TEST(PagedLOD, TheCullDrawsTheCoarseLevelAndPostsTheNodeOncePerUpdateUntilTheDetailIsAttached) {
    Tile t;
    Scene s(t.root);
    s.update();
    const Camera cam = testutil::lookingAlongY();
    CullStats st;
    EXPECT_EQ(cull(s, cam, &st), std::set<const Mesh*>{t.coarse.get()});
    EXPECT_EQ(st.pagedWanted, 1u);
    EXPECT_EQ(st.pagedRequested, 1u);
    EXPECT_EQ(st.pagedCoarse, 1u);
    EXPECT_EQ(t.paged->lastNeeded(), s.updateCount());
    cull(s, cam, &st);  // a second view of the same update: marked, not posted again
    EXPECT_EQ(st.pagedRequested, 0u);
    std::vector<ref_ptr<Node>> posted;
    s.pageRequests().take(posted);
    ASSERT_EQ(posted.size(), 1u);
    EXPECT_EQ(posted[0].get(), t.paged.get());
    s.update();
    t.paged->setRequested();  // a requested node is the pager's: not posted again
    cull(s, cam, &st);
    EXPECT_EQ(st.pagedRequested, 0u);
    EXPECT_EQ(s.pageRequests().size(), 0u);

    t.attach();
    s.update();
    EXPECT_EQ(cull(s, cam, &st), std::set<const Mesh*>{t.fine.get()});
    EXPECT_EQ(st.pagedCoarse, 0u);
    // Out of range: the coarse level again, though the detail is attached; the mark stays where it was.
    const uint64_t marked = t.paged->lastNeeded();
    s.update();
    Camera far = testutil::lookingAlongY();
    far.setLookAt(dvec3(0, -60, 0), dvec3(0, 10, 0), dvec3(0, 0, 1));
    EXPECT_EQ(cull(s, far, &st), std::set<const Mesh*>{t.coarse.get()});
    EXPECT_EQ(st.pagedWanted, 0u);
    EXPECT_EQ(t.paged->lastNeeded(), marked);
    // Detached (by the pager, or by Group::removeChild): Unloaded, the coarse level.
    t.paged->detachDetail();
    EXPECT_EQ(t.paged->state(), PagedLOD::State::Unloaded);
    s.update();
    EXPECT_EQ(cull(s, cam, &st), std::set<const Mesh*>{t.coarse.get()});
    t.attach();
    t.paged->removeChild(t.paged->detailIndex());
    EXPECT_EQ(t.paged->detail(), nullptr);
    EXPECT_EQ(t.paged->state(), PagedLOD::State::Unloaded);
}

TEST(PagedLOD, ANodeWithoutCoarseLevelIsSeenWhereItsRadiusSays) {
    auto root = make<Group>();
    auto p = make<PagedLOD>();
    p->setFile("far.glb");
    root->addChild(p);
    {
        Scene s(root);
        s.update();
        EXPECT_TRUE(s.image().flags[1] & FlatImage::kEmpty);
        CullStats st;
        cull(s, testutil::lookingAlongY(), &st);
        EXPECT_EQ(st.pagedRequested, 0u);  // empty: never visited
    }
    p->setCenter(dvec3(0, 20, 0));
    p->setRadius(5.0);
    Scene s(root);
    s.update();
    EXPECT_FALSE(s.image().flags[1] & FlatImage::kEmpty);
    const Box b = s.image().box(1);
    EXPECT_LE(b.min.y, 15.0);
    EXPECT_GE(b.max.y, 25.0);
    CullStats st;
    cull(s, testutil::lookingAlongY(), &st);
    EXPECT_EQ(st.pagedRequested, 1u);
    // Behind the camera: not in view, not wanted.
    p->setCenter(dvec3(0, -20, 0));
    s.update();
    cull(s, testutil::lookingAlongY(), &st);
    EXPECT_EQ(st.pagedWanted, 0u);
}

TEST(PagedLOD, PicksSeeTheLevelThatIsDrawn) {
    Tile t;
    Scene s(t.root);
    s.update();
    IntersectTraversal it;
    const Camera cam = testutil::lookingAlongY();
    QueryOptions o;
    o.lod = LodChoice::AsDrawn;
    o.camera = &cam;
    auto hitMesh = [&]() -> const Mesh* {
        Hit hit;
        if (!it.intersect(s, Ray{dvec3(0.01, 0, 0.02), dvec3(0, 1, 0)}, o, hit)) return nullptr;
        return hit.geometry->mesh();
    };
    EXPECT_EQ(hitMesh(), t.coarse.get());
    t.attach();
    s.update();
    EXPECT_EQ(hitMesh(), t.fine.get());
    Camera far = cam;  // the detail out of range for this view: the pick sees the coarse level again
    far.setLookAt(dvec3(0, -60, 0), dvec3(0, 10, 0), dvec3(0, 0, 1));
    o.camera = &far;
    EXPECT_EQ(hitMesh(), t.coarse.get());
}

TEST(PagedLOD, AttachingOrDetachingTheDetailRewritesItsOwnImageNotTheScenes) {
    // A scene of 200 other tiles: attaching writes the detail's entries and the paged node's path only.
    Tile t;
    for (int k = 0; k < 200; ++k) {
        auto o = make<Transform>(glm::translate(dmat4(1.0), dvec3(k * 3.0, 40, 0)));
        o->addChild(make<Geometry>(t.coarse, make<Material>()));
        t.root->addChild(o);
    }
    Scene s(t.root);
    s.update();
    const uint64_t structure = s.structureVersion();
    const size_t entries = s.image().size();
    t.attach();
    s.update();
    EXPECT_EQ(s.structureVersion(), structure);
    EXPECT_EQ(s.lastUpdate().fullRebuilds, 0u);
    EXPECT_EQ(s.image().size(), entries);
    EXPECT_LE(s.lastUpdate().entriesWritten, 10u);
    EXPECT_EQ(cull(s, testutil::lookingAlongY()).count(t.fine.get()), 1u);
    t.paged->detachDetail();
    s.update();
    EXPECT_EQ(s.structureVersion(), structure);
    EXPECT_EQ(s.lastUpdate().fullRebuilds, 0u);
    EXPECT_EQ(cull(s, testutil::lookingAlongY()).count(t.fine.get()), 0u);
    // A coarse child added is a change of the scene's structure.
    t.paged->addChild(make<Geometry>(t.coarse, make<Material>()));
    s.update();
    EXPECT_GT(s.structureVersion(), structure);
}

TEST(PagedLOD, TheDetailIsDrawnAndPickedWhereItsFrameIsAndFollowsItWhenItMoves) {
    auto root = make<Group>();
    auto frame = make<Transform>(glm::scale(glm::translate(dmat4(1.0), dvec3(0, 10, 0)), dvec3(2.0)));
    auto p = make<PagedLOD>();
    p->setFile("tile.glb");
    frame->addChild(p);
    root->addChild(frame);
    auto fine = makeBoxMesh(dvec3(-1), dvec3(1));
    auto g = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 1, 0)));
    g->addChild(make<Geometry>(fine, make<Material>()));
    p->attachDetail(g, 0);
    Scene s(root);
    s.update();
    IntersectTraversal it;
    auto hitY = [&]() {
        Hit hit;
        return it.intersect(s, Ray{dvec3(0.01, 0, 0.02), dvec3(0, 1, 0)}, QueryOptions{}, hit) ? hit.point.y : -1.0;
    };
    // The box [-1, 1] moved by 1 in the detail, scaled by 2 and moved by 10: its near face at y = 10.
    EXPECT_NEAR(hitY(), 10.0, 1e-9);
    const Box b = s.image().box(1);
    EXPECT_LE(b.min.y, 10.0);
    EXPECT_GE(b.max.y, 14.0);
    DrawList list;
    CullStats st;
    CullTraversal().cull(s, testutil::lookingAlongY(), CullSettings{}, list, st);
    ASSERT_EQ(list.items.size(), 1u);
    EXPECT_FLOAT_EQ(list.items[0].model[3].y, 12.0f);
    EXPECT_FLOAT_EQ(list.items[0].model[0].x, 2.0f);
    frame->setMatrix(glm::translate(dmat4(1.0), dvec3(0, 20, 0)));
    s.update();
    EXPECT_NEAR(hitY(), 20.0, 1e-9);
    g->setTranslation(dvec3(0, 3, 0));  // a change inside the detail
    s.update();
    EXPECT_NEAR(hitY(), 22.0, 1e-9);
}
