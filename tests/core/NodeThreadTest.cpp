// Graphs built, named, re-parented and destroyed on several threads at once, as a loader thread does
// next to the application's: nodes of different graphs share no state (CI runs this under TSan too).
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/Transform.h"

#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

using namespace sg;

namespace {

constexpr int kThreads = 4, kRounds = 25, kChildren = 64;

// One graph's life on one thread; returns how many of its checks failed (gtest's own counters are
// not what is under test here).
int buildEditAndDestroy(int thread, int round) {
    int failed = 0;
    auto check = [&](bool ok) { failed += ok ? 0 : 1; };
    const std::string tag = std::to_string(thread) + "." + std::to_string(round) + ".";

    auto root = make<Group>();
    root->setName(tag + "root");
    auto shared = make<Group>();  // below every transform: a DAG join with kChildren parents
    shared->setName(tag + "shared");
    int calls = 0;
    std::vector<ref_ptr<Transform>> xs;
    for (int i = 0; i < kChildren; ++i) {
        auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(i, thread, round)));
        t->setName(tag + std::to_string(i));
        t->setUpdateCallback([&calls](Node&, const FrameInfo&) { ++calls; });
        t->addChild(shared);
        t->addChild(make<Geometry>());
        root->addChild(t);
        xs.push_back(t);
    }
    check(root->numChildren() == size_t(kChildren));
    check(shared->numParents() == size_t(kChildren));
    check(shared->name() == tag + "shared");

    // Re-parent every odd transform below the even one before it, and place `shared` once more.
    for (int i = 1; i < kChildren; i += 2) {
        check(root->removeChild(xs[size_t(i)].get()));
        xs[size_t(i) - 1]->addChild(xs[size_t(i)]);
    }
    auto placed = make<Instance>(shared, glm::translate(dmat4(1.0), dvec3(0, 0, 1)));
    root->addChild(placed);
    check(root->numChildren() == size_t(kChildren / 2 + 1));
    check(shared->numParents() == size_t(kChildren + 1));
    for (int i = 0; i < kChildren; ++i) {
        const Transform& t = *xs[size_t(i)];
        check(t.name() == tag + std::to_string(i));
        check(t.numParents() == 1);
        check(t.parent(0) == (i % 2 ? static_cast<const Node*>(xs[size_t(i) - 1].get()) : root.get()));
        check(t.matrix()[3] == dvec4(i, thread, round, 1));
        const UpdateCallback* cb = t.updateCallback();
        check(cb != nullptr);
        if (cb) (*cb)(*xs[size_t(i)], FrameInfo{});
    }
    check(calls == kChildren);

    // Renaming after the parents moved into the node's Extras keeps them; then the graph goes away.
    for (auto& t : xs) t->setName(t->name() + "'");
    check(xs[5]->name() == tag + "5'" && xs[5]->parent(0) == xs[4].get());
    for (int i = 0; i < kChildren; i += 2) xs[size_t(i)]->removeChild(shared.get());
    check(shared->numParents() == size_t(kChildren / 2 + 1));
    xs.clear();
    root = nullptr;
    check(placed->refCount() == 1 && shared->numParents() == 1);  // only the Instance holds it now
    placed = nullptr;
    check(shared->numParents() == 0 && shared->refCount() == 1);
    return failed;
}

}  // namespace

TEST(NodeThreads, GraphsOnDifferentThreadsDoNotInterfere) {
    std::vector<int> failed(kThreads, 0);
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
        threads.emplace_back([&failed, t] {
            for (int r = 0; r < kRounds; ++r) failed[size_t(t)] += buildEditAndDestroy(t, r);
        });
    for (auto& th : threads) th.join();
    for (int t = 0; t < kThreads; ++t) EXPECT_EQ(failed[size_t(t)], 0) << "thread " << t;
}
