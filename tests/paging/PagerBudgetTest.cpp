// Pager: the byte budget (the least recently needed detail leaves, a needed one never), tracked nodes inside released
// and evicted details, the back-off after a failed load, prepare functions that attach details within each update's
// budget, and details' images built on the loader thread.
#include "paging/PagerTestUtil.h"
#include "sg/cull/CullTraversal.h"
#include "sg/paging/Pager.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <map>

using namespace sg;
using namespace pagertest;

TEST(Pager, OverTheByteBudgetTheLeastRecentlyNeededDetailLeavesAndANeededOneNever) {
    // Three tiles 50 m apart side by side, each seen alone from in front of it; details of known bytes, a budget
    // of two of them.
    auto root = make<Group>();
    auto a = addTile(*root, dvec3(-25, 20, 0), "a.glb", 100.0f);
    auto b = addTile(*root, dvec3(0, 20, 0), "b.glb", 100.0f);
    auto c = addTile(*root, dvec3(25, 20, 0), "c.glb", 100.0f);
    Scene scene(root);
    const size_t B = pageBytes(makeDetail().get());
    PagerSettings ps;
    ps.maxResidentBytes = 2 * B;
    Pager pager(
        scene, [](const std::string&) { return makeDetail(); }, ps);
    Frames f(scene, pager);
    auto lookAt = [&](double x) { f.cam.setLookAt(dvec3(x, 0, 0), dvec3(x, 20, 0), dvec3(0, 0, 1)); };
    auto loadIn = [&] {
        f.run();
        f.run();
        pager.waitIdle();
        f.run();
    };
    lookAt(-25);
    loadIn();
    lookAt(0);
    loadIn();
    EXPECT_EQ(pager.stats().bytesResident, 2 * B);
    EXPECT_FALSE(pager.stats().overBudget);
    lookAt(25);
    loadIn();  // c attached: three over the budget, a (the least recently needed) leaves in the same update
    EXPECT_EQ(pager.stats().frame.attached, 1u);
    EXPECT_EQ(pager.stats().frame.evicted, 1u);
    EXPECT_EQ(a->state(), PagedLOD::State::Unloaded);
    EXPECT_EQ(b->state(), PagedLOD::State::Loaded);
    EXPECT_EQ(c->state(), PagedLOD::State::Loaded);
    EXPECT_EQ(pager.stats().evicted, 1u);
    EXPECT_EQ(pager.stats().bytesResident, 2 * B);
    EXPECT_FALSE(pager.stats().overBudget);

    // All three in view: a loads again, nothing can leave (all needed): over the budget, and said so.
    f.cam.setLookAt(dvec3(0, -30, 0), dvec3(0, 20, 0), dvec3(0, 0, 1));
    loadIn();
    for (int k = 0; k < 3; ++k) f.run();
    EXPECT_EQ(a->state(), PagedLOD::State::Loaded);
    EXPECT_EQ(b->state(), PagedLOD::State::Loaded);
    EXPECT_EQ(c->state(), PagedLOD::State::Loaded);
    EXPECT_EQ(pager.stats().bytesResident, 3 * B);
    EXPECT_TRUE(pager.stats().overBudget);
    EXPECT_EQ(pager.stats().evicted, 1u);
    // A new tile in view is queued and not started while over the budget...
    auto d = addTile(*root, dvec3(-25, 40, 0), "d.glb", 100.0f);
    f.run();
    f.run();
    pager.waitIdle();  // nothing that may start
    f.run();
    EXPECT_EQ(d->state(), PagedLOD::State::Requested);
    EXPECT_EQ(pager.stats().queued, 1u);
    EXPECT_EQ(pager.stats().loading, 0u);
    // ...but a commanded load is.
    auto e = make<PagedLOD>();
    e->setFile("e.glb");
    e->setTrigger(PagedLOD::Trigger::Command);
    root->addChild(e);
    f.run();
    pager.load(*e);
    pager.waitIdle();
    f.run();
    EXPECT_EQ(e->state(), PagedLOD::State::Loaded);
    // Looking at c alone: a and b (no longer needed) leave; the commanded e stays; d's request is dropped.
    lookAt(25);
    f.run();
    f.run();
    EXPECT_EQ(a->state(), PagedLOD::State::Unloaded);
    EXPECT_EQ(b->state(), PagedLOD::State::Unloaded);
    EXPECT_EQ(c->state(), PagedLOD::State::Loaded);
    EXPECT_EQ(e->state(), PagedLOD::State::Loaded);
    EXPECT_EQ(d->state(), PagedLOD::State::Unloaded);
    EXPECT_EQ(pager.stats().bytesResident, 2 * B);
    EXPECT_FALSE(pager.stats().overBudget);
    EXPECT_EQ(pager.stats().evicted, 3u);
    EXPECT_GE(pager.stats().maxQueued, 1u);  // d (and others, had the loaders not taken them by the update)
}

// A parent tile 10 m ahead whose detail holds a child tile at its place (ranges of 100 m).
struct Nested {
    ref_ptr<Group> root = make<Group>();
    ref_ptr<PagedLOD> parent, child;
    Nested() { parent = addTile(*root, dvec3(0, 10, 0), "parent.glb", 100.0f); }
    ref_ptr<Node> load(const std::string& file, PagedLOD::Trigger childTrigger) {
        if (file != "parent.glb") return makeDetail();
        auto g = make<CountedGroup>();
        child = addTile(*g, dvec3(0), "child.glb", 100.0f);
        child->setTrigger(childTrigger);
        return g;
    }
};

TEST(Pager, ATrackedNodeInsideAReleasedDetailIsReleasedFirstAndItsBytesLeaveTheTotal) {
    Nested w;
    Scene scene(w.root);
    const int before = gAlive.load();
    {
        Pager pager(scene, [&](const std::string& file) { return w.load(file, PagedLOD::Trigger::Range); });
        Frames f(scene, pager);
        for (int level = 0; level < 2; ++level) {
            f.run();
            f.run();
            pager.waitIdle();
            f.run();
        }
        ASSERT_EQ(w.parent->state(), PagedLOD::State::Loaded);
        ASSERT_EQ(w.child->state(), PagedLOD::State::Loaded);
        EXPECT_EQ(pager.tracked(), 2u);
        EXPECT_EQ(pager.stats().resident, 2u);
        EXPECT_EQ(pager.stats().bytesResident, w.parent->detailBytes() + w.child->detailBytes());
        const ref_ptr<PagedLOD> child = w.child;
        pager.release(*w.parent);
        EXPECT_EQ(child->state(), PagedLOD::State::Unloaded);
        EXPECT_EQ(child->detail(), nullptr);
        EXPECT_EQ(w.parent->state(), PagedLOD::State::Unloaded);
        EXPECT_EQ(pager.tracked(), 0u);
        EXPECT_EQ(pager.stats().resident, 0u);
        EXPECT_EQ(pager.stats().bytesResident, 0u);
        EXPECT_EQ(pager.stats().unloads, 2u);
        w.child = nullptr;
    }
    EXPECT_EQ(gAlive.load(), before);  // both details freed
}

TEST(Pager, ATrackedNodeInsideAnEvictedDetailIsReleasedAndItsBytesLeaveTheTotal) {
    // The child is commanded (never evicted itself); the parent, no longer needed, is evicted for a third tile.
    Nested w;
    auto other = addTile(*w.root, dvec3(60, 10, 0), "other.glb", 100.0f);
    Scene scene(w.root);
    const size_t B = pageBytes(makeDetail().get());
    PagerSettings ps;
    ps.maxResidentBytes = 2 * B + 500;  // the parent's detail (a coarse box) and the child's, not the third
    Pager pager(
        scene, [&](const std::string& file) { return w.load(file, PagedLOD::Trigger::Command); }, ps);
    Frames f(scene, pager);
    f.run();
    f.run();
    pager.waitIdle();
    f.run();
    ASSERT_EQ(w.parent->state(), PagedLOD::State::Loaded);
    pager.load(*w.child);
    pager.waitIdle();
    f.run();
    ASSERT_EQ(w.child->state(), PagedLOD::State::Loaded);
    EXPECT_EQ(pager.stats().bytesResident, w.parent->detailBytes() + w.child->detailBytes());
    EXPECT_LE(pager.stats().bytesResident, ps.maxResidentBytes);
    const ref_ptr<PagedLOD> child = w.child;
    f.cam.setLookAt(dvec3(60, 0, 0), dvec3(60, 10, 0), dvec3(0, 0, 1));  // the other tile alone
    f.run();
    f.run();
    pager.waitIdle();
    f.run();
    EXPECT_EQ(other->state(), PagedLOD::State::Loaded);
    EXPECT_EQ(w.parent->state(), PagedLOD::State::Unloaded);
    EXPECT_EQ(child->state(), PagedLOD::State::Unloaded);
    EXPECT_EQ(pager.stats().evicted, 1u);
    EXPECT_EQ(pager.tracked(), 1u);
    EXPECT_EQ(pager.stats().resident, 1u);
    EXPECT_EQ(pager.stats().bytesResident, other->detailBytes());
}

TEST(Pager, AFailedLoadIsAskedForAgainAfterABackOffThatDoublesAndTheErrorStaysMeanwhile) {
    World w;
    Scene scene(w.root);
    std::atomic<int> calls{0};
    PagerSettings ps;
    ps.retrySeconds = 1.0;
    ps.maxRetrySeconds = 10.0;
    Pager pager(
        scene,
        [&](const std::string&) -> ref_ptr<Node> {
            if (++calls <= 2) throw std::runtime_error("server busy");
            return makeDetail();
        },
        ps);
    CullTraversal cull;
    const Camera cam = testutil::lookingAlongY();
    uint64_t n = 0;
    auto frame = [&](double t) {
        ++n;
        pager.update({n, t});
        scene.update({n, t});
        DrawList list;
        CullStats st;
        cull.cull(scene, cam, CullSettings{}, list, st);
    };
    frame(0.00);  // posted
    frame(0.01);  // queued
    pager.waitIdle();
    frame(0.02);  // failed: asked again from 1.02 on
    EXPECT_EQ(pager.stats().frame.failed, 1u);
    ASSERT_EQ(w.tile->state(), PagedLOD::State::Failed);
    EXPECT_EQ(w.tile->failures(), 1u);
    EXPECT_DOUBLE_EQ(w.tile->retryTime(), 1.02);
    for (double t : {0.5, 1.0, 1.01}) {
        frame(t);
        pager.waitIdle();
    }
    EXPECT_EQ(calls.load(), 1);
    EXPECT_EQ(w.tile->error(), "tile.glb: server busy");  // kept on the node meanwhile
    frame(1.03);                                          // posted again
    frame(1.04);                                          // queued
    pager.waitIdle();
    EXPECT_EQ(calls.load(), 2);
    frame(1.05);  // failed again: asked again 2 s later, from 3.05 on
    ASSERT_EQ(w.tile->state(), PagedLOD::State::Failed);
    EXPECT_EQ(w.tile->failures(), 2u);
    EXPECT_DOUBLE_EQ(w.tile->retryTime(), 3.05);
    for (double t : {2.0, 3.0, 3.04}) {
        frame(t);
        pager.waitIdle();
    }
    EXPECT_EQ(calls.load(), 2);
    frame(3.1);
    frame(3.11);
    pager.waitIdle();
    frame(3.12);
    EXPECT_EQ(calls.load(), 3);
    EXPECT_EQ(w.tile->state(), PagedLOD::State::Loaded);
    EXPECT_EQ(w.tile->failures(), 0u);
    EXPECT_EQ(pager.stats().failures, 2u);
    EXPECT_EQ(pager.stats().frame.attached, 1u);
}

TEST(Pager, WithAPrepareFunctionDetailsAttachWithinTheBudgetOfEachUpdateMostNeededFirst) {
    // Four tiles loaded at once; a prepare function that counts its calls and spends an object each; a budget of
    // one object an update: one attaches per update, the nearest first.
    auto root = make<Group>();
    std::vector<ref_ptr<PagedLOD>> tiles;
    for (int k = 0; k < 4; ++k)
        tiles.push_back(addTile(*root, dvec3(0, 10.0 + 8.0 * (3 - k), 0), "t" + std::to_string(k) + ".glb"));
    Scene scene(root);
    PagerSettings ps;
    ps.prepareObjectsPerFrame = 1;
    ps.prepareMsPerFrame = 1e9;  // objects alone decide: no test depends on time
    Pager pager(
        scene, [](const std::string&) { return makeDetail(); }, ps);
    int calls = 0;
    std::vector<const PagedLOD*> attachedOrder;
    pager.setPrepare([&](Node&, PrepareBudget& budget) {
        calls++;
        budget.spend(1, 100);
        return true;
    });
    Frames f(scene, pager);
    f.run();
    f.run();
    pager.waitIdle();
    for (int update = 1; update <= 4; ++update) {
        f.run();
        EXPECT_EQ(calls, update);
        EXPECT_EQ(pager.stats().frame.attached, 1u) << "update " << update;
        EXPECT_EQ(pager.stats().frame.uploadedObjects, 1u);
        EXPECT_EQ(pager.stats().frame.uploadedBytes, 100u);
        EXPECT_EQ(pager.stats().pending, size_t(4 - update));
        for (const auto& t : tiles)
            if (t->state() == PagedLOD::State::Loaded &&
                std::find(attachedOrder.begin(), attachedOrder.end(), t.get()) == attachedOrder.end())
                attachedOrder.push_back(t.get());
    }
    f.run();
    EXPECT_EQ(calls, 4);
    EXPECT_EQ(pager.stats().frame.attached, 0u);
    EXPECT_EQ(pager.stats().resident, 4u);
    // tiles[3] is the nearest.
    EXPECT_EQ(attachedOrder,
              (std::vector<const PagedLOD*>{tiles[3].get(), tiles[2].get(), tiles[1].get(), tiles[0].get()}));
}

TEST(Pager, APrepareFunctionMayTakeSeveralUpdatesAndItsFailureIsTheLoads) {
    World w;
    World other("other.glb");
    Scene scene(w.root);
    Pager pager(scene, [](const std::string&) { return makeDetail(); });
    int calls = 0;
    pager.setPrepare([&](Node&, PrepareBudget&) { return ++calls == 3; });  // done at the third call
    Frames f(scene, pager);
    f.run();
    f.run();
    pager.waitIdle();
    f.run();
    f.run();
    EXPECT_EQ(w.tile->state(), PagedLOD::State::Requested);  // drawn coarse meanwhile
    f.run();
    EXPECT_EQ(calls, 3);
    EXPECT_EQ(w.tile->state(), PagedLOD::State::Loaded);
    pager.release(*w.tile);
    pager.setPrepare([](Node&, PrepareBudget&) -> bool { throw std::runtime_error("out of video memory"); });
    pager.load(*w.tile);
    pager.waitIdle();
    f.run();
    EXPECT_EQ(w.tile->state(), PagedLOD::State::Failed);
    EXPECT_EQ(w.tile->error(), "tile.glb: out of video memory");
    EXPECT_EQ(pager.tracked(), 0u);
}

// A prepare function that keeps what it works on (as a renderer's upload list holds its detail) is told when a
// detail it has not finished is dropped, and lets go of it: the detail is then freed where the pager frees details.
TEST(Pager, ADetailDroppedWhilePreparedIsLetGoByThePrepareFunction) {
    const int alive = gAlive;
    World w;
    Scene scene(w.root);
    PagerSettings ps;
    ps.freeOnLoaderThread = true;
    Pager pager(
        scene, [](const std::string&) { return makeDetail(); }, ps);
    std::map<const Node*, ref_ptr<Node>> held;  // what the prepare function keeps, by detail
    std::vector<const Node*> dropped;
    pager.setPrepare(
        [&](Node& d, PrepareBudget&) {
            held[&d] = ref_ptr<Node>(&d);
            return false;  // never done
        },
        [&](const Node& d) {
            dropped.push_back(&d);
            held.erase(&d);
        });
    Frames f(scene, pager);
    f.run();
    f.run();
    pager.waitIdle();
    f.run();
    ASSERT_EQ(held.size(), 1u);
    EXPECT_EQ(gAlive, alive + 1);
    const Node* detail = held.begin()->first;
    pager.release(*w.tile);
    EXPECT_EQ(dropped, std::vector<const Node*>{detail});
    EXPECT_TRUE(held.empty());
    f.run();
    pager.waitIdle();
    EXPECT_EQ(gAlive, alive);  // freed by the pager's loader thread
}

TEST(Pager, BuildsADetailsImageOnTheLoaderThreadAndTheUpdateTakesIt) {
    // A detail of 400 boxes: the update that attaches it writes its entries itself only without buildImages.
    auto bigDetail = [](const std::string&) -> ref_ptr<Node> {
        auto g = make<Group>();
        for (int k = 0; k < 400; ++k) {
            auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(0.01 * k, 0, 0)));
            t->addChild(make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), make<Material>()));
            g->addChild(t);
        }
        return g;
    };
    for (const bool ahead : {true, false}) {
        World w;
        Scene scene(w.root);
        PagerSettings ps;
        ps.buildImages = ahead;
        Pager pager(scene, bigDetail, ps);
        Frames f(scene, pager);
        f.run();  // the cull posts the request, with its frame
        f.run();  // the pager queues it
        pager.waitIdle();
        const size_t drawn = f.run().size();  // attaches: the update takes the image or builds it
        ASSERT_NE(w.tile->detail(), nullptr);
        EXPECT_EQ(drawn, 400u);
        if (ahead)
            EXPECT_LT(scene.lastUpdate().entriesWritten, 10u);
        else
            EXPECT_GT(scene.lastUpdate().entriesWritten, 800u);
        // What the cull sees equals a scene built from scratch.
        const CullStats stats = culledFromScratch(w.root, f.cam);
        EXPECT_EQ(stats.geometries, 400u);
        EXPECT_EQ(stats.triangles, f.stats.triangles);
    }
}
