// The pager under load on several threads (sg_thread_tests, which CI also runs under ThreadSanitizer): loader
// threads loading at once, enter and leave cycles while loads are in flight, nested tiles under a byte budget, a
// detail of instances built on the loader thread.
#include "TestUtil.h"
#include "loaders/tiles/internal/SharedMeshes.h"
#include "paging/PagerTestUtil.h"
#include "sg/cull/CullTraversal.h"
#include "sg/paging/Pager.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

using namespace sg;
using namespace pagertest;

TEST(PagerThreads, SeveralLoaderThreadsLoadAtOnceAndTheFiguresAddUp) {
    // Four loader threads, each held at a gate: four loads run at once; released, all attach.
    auto root = make<Group>();
    std::vector<ref_ptr<PagedLOD>> tiles;
    for (int k = 0; k < 8; ++k) tiles.push_back(addTile(*root, dvec3(4.0 * k - 14.0, 20, 0), "t" + std::to_string(k)));
    Scene scene(root);
    Latch gate;
    std::mutex m;
    std::condition_variable cv;
    int inside = 0;
    PagerSettings ps;
    ps.loaderThreads = 4;
    Pager pager(
        scene,
        [&](const std::string&) {
            {
                std::lock_guard<std::mutex> lock(m);
                inside++;
            }
            cv.notify_all();
            gate.wait();
            return makeDetail();
        },
        ps);
    Frames f(scene, pager);
    f.run();
    f.run();
    {
        std::unique_lock<std::mutex> lock(m);
        cv.wait(lock, [&] { return inside == 4; });  // four at once: one per thread
    }
    f.run();
    EXPECT_EQ(pager.stats().loading, 4u);
    EXPECT_EQ(pager.stats().queued, 4u);
    gate.release();
    pager.waitIdle();
    f.run();
    EXPECT_EQ(pager.stats().loads, 8u);
    EXPECT_EQ(pager.stats().resident, 8u);
    size_t bytes = 0;
    for (const auto& t : tiles) bytes += t->detailBytes();
    EXPECT_EQ(pager.stats().bytesResident, bytes);
}

// Many enter and leave cycles, in random order (fixed seed), while loads are in flight: two views culled on
// two threads at once each frame, commands given between frames. Nothing leaks (every detail is freed once
// the pager and the scene are gone), the pager's figures match the graph every frame. Run under
// ThreadSanitizer in CI.
// How many loads end within a frame is the machine's (the loader runs below the frame thread, nice 10, and a
// busy machine may give it nothing for many frames): every fourth frame waits for the loader to be idle, so
// that the queued loads are attached at its update whatever the speed, and the frames go on until the cycles
// asked for have happened. A pager that stops attaching, unloading or failing runs into the frame cap and fails.
TEST(PagerThreads, EnterAndLeaveCyclesWhileLoadsAreInFlight) {
    const int before = gAlive.load();
    {
        auto root = make<Group>();
        std::vector<ref_ptr<PagedLOD>> tiles;
        for (int k = 0; k < 16; ++k) {
            auto p = make<PagedLOD>();
            p->setFile("tile" + std::to_string(k) + ".glb");
            p->setRange(0.0f, 30.0f);
            p->setRadius(2.0);
            if (k % 4 == 3) p->setTrigger(PagedLOD::Trigger::Command);
            auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(20.0 * (k % 4), 20.0 * (k / 4), 0)));
            p->addChild(make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), make<Material>()));
            t->addChild(p);
            root->addChild(t);
            tiles.push_back(p);
        }
        Scene scene(root);
        PagerSettings ps;
        ps.expiryFrames = 3;
        ps.expirySeconds = 0.0;
        ps.freeOnLoaderThread = true;  // nothing else holds the details' nodes here
        std::atomic<uint64_t> seq{0};
        // Every detail's mesh is equal: the loads share one, as a tileset's do, so that one mesh is referenced
        // and released by several loader threads at once (its count is atomic).
        tiles::SharedMeshes meshes;
        Pager pager(
            scene,
            [&](const std::string& file) -> ref_ptr<Node> {
                const uint64_t s = seq++;
                std::this_thread::sleep_for(std::chrono::microseconds(s * 7919 % 300));
                if (s % 13 == 5) throw std::runtime_error("bad luck on " + file);
                ref_ptr<Node> d = makeDetail();
                meshes.share(*d);
                return d;
            },
            ps);
        std::mt19937 rng(12345);
        std::uniform_real_distribution<double> pos(-10.0, 70.0);
        CullTraversal cullA, cullB;
        const auto enough = [&] {
            const PagerStats& s = pager.stats();
            return s.loads > 50 && s.unloads > 50 && s.failures > 0;
        };
        constexpr uint64_t kFrames = 1500, kCap = 20000;  // the cap ends a broken pager's run, never a slow one's
        uint64_t n = 1;
        for (; n <= kCap && (n <= kFrames || !enough()); ++n) {
            if (n % 4 == 0) pager.waitIdle();
            const FrameInfo f{n, n / 60.0};
            pager.update(f);
            scene.update(f);
            Camera a = testutil::lookingAlongY(), b = testutil::lookingAlongY();
            a.setLookAt(dvec3(pos(rng), pos(rng), 10), dvec3(pos(rng), pos(rng), 0), dvec3(0, 0, 1));
            b.setLookAt(dvec3(pos(rng), pos(rng), 10), dvec3(pos(rng), pos(rng), 0), dvec3(0, 0, 1));
            DrawList la, lb;
            CullStats sa, sb;
            std::thread other([&] { cullB.cull(scene, b, CullSettings{}, lb, sb); });
            cullA.cull(scene, a, CullSettings{}, la, sa);
            other.join();
            // Commands between frames: enter or leave a random tile.
            const size_t k = rng() % tiles.size();
            switch (rng() % 4) {
                case 0: pager.load(*tiles[k]); break;
                case 1: pager.release(*tiles[k]); break;
                default: break;
            }
            size_t attached = 0, bytes = 0;
            for (const auto& t : tiles)
                if (t->detail()) attached++, bytes += t->detailBytes();
            ASSERT_EQ(pager.stats().resident, attached) << "frame " << n;
            ASSERT_EQ(pager.stats().bytesResident, bytes) << "frame " << n;
        }
        const PagerStats& s = pager.stats();
        EXPECT_GT(s.loads, 50u) << n - 1 << " frames";
        EXPECT_GT(s.unloads, 50u) << n - 1 << " frames";
        EXPECT_GT(s.failures, 0u) << n - 1 << " frames";
        EXPECT_GT(meshes.replaced(), 50u);
        std::printf(
            "paging cycles: %llu frames, %llu requests, %llu loads, %llu unloads, %llu failures, %llu cancelled, "
            "%llu discarded\n",
            (unsigned long long)(n - 1), (unsigned long long)s.requests, (unsigned long long)s.loads,
            (unsigned long long)s.unloads, (unsigned long long)s.failures, (unsigned long long)s.cancelled,
            (unsigned long long)s.discarded);
    }
    EXPECT_EQ(gAlive.load(), before);
}

// A quadtree of tiles three levels deep, each tile's detail the group of its four children (built on the loader
// threads), leaves a counted detail; a byte budget that holds a fraction of them, failures now and then (retried
// after a back-off), a prepare function that takes several updates, two views culled on two threads at once,
// wandering. Every frame the pager's figures match the graph it can reach; nothing leaks. Run under
// ThreadSanitizer in CI.
TEST(PagerThreads, NestedTilesUnderAByteBudgetWithFailuresAndPrepare) {
    const int before = gAlive.load();
    {
        constexpr int kLevels = 3;
        constexpr double kSize = 64.0;
        auto tileAt = [](int level, int x, int y) {
            const double size = kSize / double(1 << level);
            auto p = make<PagedLOD>();
            p->setFile(std::to_string(level) + "/" + std::to_string(x) + "/" + std::to_string(y));
            p->setRange(0.0f, float(2.5 * size));
            p->setCenter(dvec3((x + 0.5) * size, (y + 0.5) * size, 0.0));
            p->setRadius(0.75 * size);
            const dvec3 lo((x + 0.1) * size, (y + 0.1) * size, 0.0), hi((x + 0.9) * size, (y + 0.9) * size, 1.0);
            p->addChild(make<Geometry>(makeBoxMesh(lo, hi), make<Material>()));
            return p;
        };
        auto root = make<Group>();
        root->addChild(tileAt(0, 0, 0));
        Scene scene(root);
        std::atomic<uint64_t> seq{0};
        PagerSettings ps;
        ps.loaderThreads = 3;
        ps.expiryFrames = 20;
        ps.expirySeconds = 0.0;
        ps.maxResidentBytes = 12 * pageBytes(makeDetail().get());
        ps.retrySeconds = 0.05;
        ps.maxRetrySeconds = 0.2;
        ps.prepareObjectsPerFrame = 3;
        ps.prepareMsPerFrame = 1e9;
        Pager pager(
            scene,
            [&](const std::string& file) -> ref_ptr<Node> {
                const uint64_t s = seq++;
                if (s % 11 == 7) throw std::runtime_error("bad luck");
                int level = 0, x = 0, y = 0;
                std::sscanf(file.c_str(), "%d/%d/%d", &level, &x, &y);
                if (level + 1 >= kLevels) return makeDetail();
                auto g = make<CountedGroup>();
                for (int k = 0; k < 4; ++k) g->addChild(tileAt(level + 1, 2 * x + (k & 1), 2 * y + (k >> 1)));
                return g;
            },
            ps);
        std::unordered_map<const Node*, int> prepareCalls;
        pager.setPrepare([&](Node& d, PrepareBudget& b) {
            b.spend(1, 0);
            return ++prepareCalls[&d] % 2 == 0;  // a detail's second call finishes it
        });
        // What the graph holds: every PagedLOD reachable from the root with a detail attached.
        auto reachable = [&](size_t& count, size_t& bytes) {
            count = bytes = 0;
            std::vector<const Node*> stack{root.get()};
            while (!stack.empty()) {
                const Node* n = stack.back();
                stack.pop_back();
                if (n->kind() == NodeKind::PagedLOD)
                    if (const auto* p = static_cast<const PagedLOD*>(n); p->detail())
                        count++, bytes += p->detailBytes();
                for (size_t i = 0; i < n->numChildren(); ++i) stack.push_back(n->child(i));
            }
        };
        std::mt19937 rng(777);
        std::uniform_real_distribution<double> pos(-20.0, 84.0), height(5.0, 80.0);
        CullTraversal cullA, cullB;
        Camera a = testutil::lookingAlongY(), b = testutil::lookingAlongY();
        uint64_t attached = 0;
        for (uint64_t n = 1; n <= 1200; ++n) {
            if (n % 5 == 0) pager.waitIdle();
            const FrameInfo f{n, n / 60.0};
            pager.update(f);
            scene.update(f);
            if (n % 40 == 1) {
                a.setLookAt(dvec3(pos(rng), pos(rng), height(rng)), dvec3(pos(rng), pos(rng), 0), dvec3(0, 0, 1));
                b.setLookAt(dvec3(pos(rng), pos(rng), height(rng)), dvec3(pos(rng), pos(rng), 0), dvec3(0, 0, 1));
            }
            DrawList la, lb;
            CullStats sa, sb;
            std::thread other([&] { cullB.cull(scene, b, CullSettings{}, lb, sb); });
            cullA.cull(scene, a, CullSettings{}, la, sa);
            other.join();
            size_t count = 0, bytes = 0;
            reachable(count, bytes);
            ASSERT_EQ(pager.stats().resident, count) << "frame " << n;
            ASSERT_EQ(pager.stats().bytesResident, bytes) << "frame " << n;
            ASSERT_LE(pager.stats().frame.attached, 3u) << "frame " << n;  // three objects an update
            attached += pager.stats().frame.attached;
        }
        const PagerStats& s = pager.stats();
        EXPECT_GT(attached, 20u);
        EXPECT_GT(s.failures, 0u);
        std::printf(
            "nested paging: %llu requests, %llu loads, %llu unloads, %llu evicted, %llu failures, %llu "
            "cancelled, %llu discarded, most queued %zu\n",
            (unsigned long long)s.requests, (unsigned long long)s.loads, (unsigned long long)s.unloads,
            (unsigned long long)s.evicted, (unsigned long long)s.failures, (unsigned long long)s.cancelled,
            (unsigned long long)s.discarded, s.maxQueued);
    }
    EXPECT_EQ(gAlive.load(), before);
}

// A tile of instanced models (an i3dm's): its image, with its prototypes' images, is built on the loader thread and
// taken by the update; released, it takes them with it.
TEST(PagerThreads, ADetailHoldingInstancesIsBuiltOnTheLoaderThreadAndFreedWithItsPrototypesImages) {
    std::atomic<const Node*> lastPrototype{nullptr};  // an address to look up, never read through
    auto instanced = [&](const std::string&) -> ref_ptr<Node> {
        auto lod = make<LOD>();
        lod->addChild(make<Geometry>(makeBoxMesh(dvec3(-0.5), dvec3(0.5)), make<Material>()), 0.0f, 500.0f);
        auto outer = make<Group>();  // a prototype placing another
        outer->addChild(make<Instance>(lod, glm::translate(dmat4(1.0), dvec3(0, 0, 1))));
        auto g = make<Group>();
        for (int k = 0; k < 20; ++k)
            g->addChild(make<Instance>(lod, glm::translate(dmat4(1.0), dvec3(k - 9.5, 10, 0))));
        g->addChild(make<Instance>(outer, glm::translate(dmat4(1.0), dvec3(0, 12, 0))));
        lastPrototype = lod.get();
        return g;
    };
    World w;
    Scene scene(w.root);
    Pager pager(scene, instanced);
    Frames f(scene, pager);
    f.run();  // the cull posts the request, with its frame
    f.run();  // the pager queues it
    const size_t bytes = scene.bytes();
    pager.waitIdle();
    f.run();  // attaches: the update takes the image
    ASSERT_NE(w.tile->detail(), nullptr);
    EXPECT_LT(scene.lastUpdate().entriesWritten, 10u);
    EXPECT_EQ(f.stats.geometries, 21u);
    EXPECT_EQ(scene.prototypeImage(lastPrototype.load()), nullptr);  // the detail's image holds it
    const CullStats stats = culledFromScratch(w.root, f.cam);
    EXPECT_EQ(stats.geometries, 21u);
    EXPECT_EQ(stats.triangles, f.stats.triangles);

    pager.release(*w.tile);
    scene.update(FrameInfo{f.n + 1, double(f.n + 1) / 60.0});
    EXPECT_EQ(scene.prototypeImage(lastPrototype.load()), nullptr);
    EXPECT_EQ(scene.bytes(), bytes);
}
