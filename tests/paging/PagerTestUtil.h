// The pager's tests' helpers, shared by PagerTest.cpp (sg_loader_tests) and PagerThreadsTest.cpp (sg_thread_tests,
// which CI also runs under ThreadSanitizer): counted details, a tile ahead of the camera, frames as an application
// runs them, a gate for the load functions.
#pragma once
#include "TestUtil.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/PagedLOD.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"
#include "sg/paging/Pager.h"
#include "sg/scene/Scene.h"

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <set>
#include <string>

namespace pagertest {

using namespace sg;

// A Group that counts the live instances of itself: a detail freed is one fewer.
inline std::atomic<int> gAlive{0};
struct CountedGroup : Group {
    CountedGroup() { gAlive++; }
    ~CountedGroup() override { gAlive--; }
};

// What the load functions build: a counted group over a box mesh of its own.
inline ref_ptr<Node> makeDetail() {
    auto g = make<CountedGroup>();
    g->addChild(make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1), 2), make<Material>()));
    return g;
}

// One paged tile 10 m ahead of a camera at the origin looking along +y: coarse box, detail from `file`,
// wanted within 50 m.
struct World {
    ref_ptr<Group> root = make<Group>();
    ref_ptr<PagedLOD> tile = make<PagedLOD>();
    ref_ptr<Mesh> coarse = makeBoxMesh(dvec3(-1), dvec3(1));
    explicit World(const std::string& file = "tile.glb") {
        auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 10, 0)));
        tile->addChild(make<Geometry>(coarse, make<Material>()));
        tile->setFile(file);
        tile->setRange(0.0f, 50.0f);
        t->addChild(tile);
        root->addChild(t);
    }
};

// What a scene built from scratch over `root` draws from `cam`.
inline CullStats culledFromScratch(const ref_ptr<Node>& root, const Camera& cam) {
    Scene fresh(root);
    fresh.update();
    CullTraversal cull;
    DrawList list;
    CullStats stats;
    cull.cull(fresh, cam, CullSettings{}, list, stats);
    return stats;
}

// A frame as an application runs it: the pager's merge, the update, the cull. Returns what was drawn.
struct Frames {
    Frames(Scene& s, Pager& p) : scene(s), pager(p) {}
    Scene& scene;
    Pager& pager;
    CullTraversal cull;
    Camera cam = testutil::lookingAlongY();
    uint64_t n = 0;
    CullStats stats;
    std::set<const Mesh*> run() {
        ++n;
        const FrameInfo f{n, double(n) / 60.0};
        pager.update(f);
        scene.update(f);
        DrawList list;
        cull.cull(scene, cam, CullSettings{}, list, stats);
        std::set<const Mesh*> drawn;
        for (const DrawItem& it : list.items) drawn.insert(it.mesh);
        return drawn;
    }
};

// A gate the load functions wait at until the test opens it.
struct Latch {
    std::mutex m;
    std::condition_variable cv;
    bool open = false;
    void wait() {
        std::unique_lock<std::mutex> lock(m);
        cv.wait(lock, [&] { return open; });
    }
    void release() {
        {
            std::lock_guard<std::mutex> lock(m);
            open = true;
        }
        cv.notify_all();
    }
};

// A Range tile at `at` under `parent`: coarse box, detail from `file`, wanted within `range` m.
inline ref_ptr<PagedLOD> addTile(Group& parent, const dvec3& at, const std::string& file, float range = 50.0f) {
    auto p = make<PagedLOD>();
    p->setFile(file);
    p->setRange(0.0f, range);
    p->addChild(make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), make<Material>()));
    auto t = make<Transform>(glm::translate(dmat4(1.0), at));
    t->addChild(p);
    parent.addChild(t);
    return p;
}

}  // namespace pagertest
