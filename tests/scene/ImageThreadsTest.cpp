// The cull of one update's image beside the application changing the graph for the next (Performer's
// APP_CULL_DRAW): the image holds copies of what the application changes per frame (switch bits, node masks,
// general matrices), and nodes it removes are freed only once the cull is done (sg::DeferredRelease). CI runs
// these under ThreadSanitizer: a cull that read a node the application writes, or a node freed under the cull,
// is reported there.
#include "nodes/Geometry.h"
#include "nodes/Instance.h"
#include "nodes/PagedLOD.h"
#include "nodes/Switch.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"
#include "sg/scene/Scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <limits>
#include <mutex>
#include <random>
#include <thread>
#include <vector>

using namespace sg;

namespace {

Camera viewOfTheRow() {
    Camera cam;
    cam.setViewport(200, 100);
    cam.setPerspective(50, 2.0, 0.5, 500);
    cam.setLookAt(dvec3(0, -60, 25), dvec3(0, 0, 0), dvec3(0, 0, 1));
    return cam;
}

dmat4 turned(const dvec3& at, double angle, double scale = 1.0) {
    return glm::scale(glm::rotate(glm::translate(dmat4(1.0), at), angle, dvec3(0, 0, 1)), dvec3(scale));
}

// One cell of the row: a general Transform over a Switch (a box, or a group of two boxes, the second of which
// gets masked) and an Instance of the shared prototype placed with a turn. Each cell has meshes of its own, so
// that a cell removed frees what the cull's draw items point at.
struct Cell {
    ref_ptr<Transform> t;
    Switch* sw = nullptr;
    Geometry* maskable = nullptr;
    Instance* placed = nullptr;
};

Cell makeCell(int k, Node* prototype, const ref_ptr<Material>& mat) {
    const dvec3 at(double(k % 12) * 8.0 - 44.0, double(k / 12) * 10.0, 0.0);
    Cell c;
    c.t = make<Transform>(turned(at, 0.1 * k));
    auto sw = make<Switch>();
    const double h = 1.0 + 0.1 * (k % 5);
    sw->addChild(make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1, 1, h)), mat));
    auto g = make<Group>();
    g->addChild(make<Geometry>(makeBoxMesh(dvec3(-2, -1, 0), dvec3(0, 1, h)), mat));
    auto masked = make<Geometry>(makeBoxMesh(dvec3(0, -1, 0), dvec3(2, 1, 2 * h)), mat);
    g->addChild(masked);
    sw->addChild(g, false);
    c.t->addChild(sw);
    auto in = make<Instance>(ref_ptr<Node>(prototype), turned(dvec3(0, 3, 0), 0.3, 0.5));
    c.t->addChild(in);
    c.sw = sw.get();
    c.maskable = masked.get();
    c.placed = in.get();
    return c;
}

struct Row {
    ref_ptr<Material> mat = make<Material>();
    ref_ptr<Switch> proto = make<Switch>();  // the prototype: a Switch of two boxes, placed by every cell
    ref_ptr<Group> root = make<Group>();
    std::vector<Cell> cells;
    int made = 0;

    explicit Row(int n) {
        proto->addChild(make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), mat));
        proto->addChild(make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1, 1, 3)), mat), false);
        for (int k = 0; k < n; ++k) add();
    }
    void add() {
        cells.push_back(makeCell(made++ % 36, proto.get(), mat));
        root->addChild(cells.back().t);
    }
};

CullSettings settingsBeside() {
    CullSettings set;
    set.traversalMask = 0x1;
    return set;
}

DrawList cullOnce(CullTraversal& cull, const Scene& s, const CullSettings& set) {
    DrawList l;
    CullStats st;
    CullControls beside;
    beside.imageOfLastUpdate = true;  // the graph may be changing while it runs
    cull.cull(s, viewOfTheRow(), set, l, st, beside);
    return l;
}

// Same items (mesh, material, matrix) in the same order, and the same sorted order.
::testing::AssertionResult sameList(const DrawList& a, const DrawList& b) {
    if (a.items.size() != b.items.size())
        return ::testing::AssertionFailure() << a.items.size() << " items, " << b.items.size() << " expected";
    for (size_t i = 0; i < a.items.size(); ++i) {
        const DrawItem &x = a.items[i], &y = b.items[i];
        if (x.mesh != y.mesh || x.material != y.material || std::memcmp(&x.model, &y.model, sizeof(x.model)) != 0)
            return ::testing::AssertionFailure() << "item " << i << " differs" << (x.mesh != y.mesh ? " mesh" : "")
                                                 << (std::memcmp(&x.model, &y.model, sizeof(x.model)) ? " model" : "");
    }
    if (a.order != b.order) return ::testing::AssertionFailure() << "the sorted order differs";
    return ::testing::AssertionSuccess();
}

// The same meshes drawn with the same matrices up to float rounding, in any order: a scene refitted and one built
// afresh may round their bounds and batch their walks differently.
::testing::AssertionResult sameDrawing(const DrawList& a, const DrawList& b) {
    if (a.items.size() != b.items.size())
        return ::testing::AssertionFailure() << a.items.size() << " items, " << b.items.size() << " expected";
    std::vector<bool> used(b.items.size());
    for (size_t i = 0; i < a.items.size(); ++i) {
        bool found = false;
        for (size_t j = 0; j < b.items.size() && !found; ++j) {
            if (used[j] || a.items[i].mesh != b.items[j].mesh) continue;
            const mat4 d = a.items[i].matrix() - b.items[j].matrix();
            float err = 0.0f;
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r) err = std::max(err, std::abs(d[c][r]));
            if (err < 1e-4f) used[j] = found = true;
        }
        if (!found) return ::testing::AssertionFailure() << "item " << i << " is not drawn so";
    }
    return ::testing::AssertionSuccess();
}

// A cull of a scene built afresh from the graph as it is now: what the scene's image must give after update().
DrawList freshCull(Node* root) {
    Scene s{ref_ptr<Node>(root)};
    s.update();
    CullTraversal cull;
    return cullOnce(cull, s, settingsBeside());
}

}  // namespace

TEST(ImageThreads, CullReadsTheUpdatesCopiesNotTheNodes) {
    Row row(12);
    Scene s(row.root);
    s.update();
    CullTraversal cull;
    const DrawList before = cullOnce(cull, s, settingsBeside());
    ASSERT_GT(before.items.size(), 6u);
    ASSERT_LT(before.items.size(), 3 * row.cells.size());  // some cells are out of view
    const auto unchangedUntilUpdate = [&](const char* what) {
        EXPECT_TRUE(sameList(cullOnce(cull, s, settingsBeside()), before)) << what << ", before the update";
        s.update();
        const DrawList after = cullOnce(cull, s, settingsBeside());
        EXPECT_FALSE(sameDrawing(after, before)) << what << " changes nothing drawn: no test";
        // (a second Scene on the same graph clears its marks: only after this scene's update)
        EXPECT_TRUE(sameDrawing(after, freshCull(row.root.get()))) << what << ", after the update";
    };
    const auto back = [&] {
        row.cells[3].sw->setOnly(0);
        row.cells[3].t->setMatrix(turned(dvec3(-20, 0, 0), 0.3));
        row.cells[4].maskable->setNodeMask(0xffffffffu);
        row.cells[4].sw->setOnly(0);
        row.cells[5].placed->setMatrix(turned(dvec3(0, 3, 0), 0.3, 0.5));
        row.proto->setOnly(0);
        s.update();
        ASSERT_TRUE(sameList(cullOnce(cull, s, settingsBeside()), before));
    };

    row.cells[3].sw->setOnly(1);
    unchangedUntilUpdate("a Switch turned");
    back();
    row.cells[3].t->setMatrix(turned(dvec3(-19, 1, 0), 1.3));  // still general: its matrix is rewritten in place
    unchangedUntilUpdate("a general Transform moved");
    back();
    row.cells[4].sw->setOnly(1);
    s.update();
    const DrawList shown = cullOnce(cull, s, settingsBeside());
    row.cells[4].maskable->setNodeMask(0x2);  // outside the traversal mask
    EXPECT_TRUE(sameList(cullOnce(cull, s, settingsBeside()), shown)) << "a node masked, before the update";
    s.update();
    EXPECT_EQ(cullOnce(cull, s, settingsBeside()).items.size(), shown.items.size() - 1);
    EXPECT_TRUE(sameDrawing(cullOnce(cull, s, settingsBeside()), freshCull(row.root.get())));
    back();
    row.cells[5].placed->setMatrix(turned(dvec3(1, 2, 0), 2.0, 0.7));
    unchangedUntilUpdate("an Instance turned");
    back();
    row.proto->setOnly(1);
    unchangedUntilUpdate("a Switch in the prototype turned");
    back();
}

// Thread C culls each update's image (kCullsPerFrame times) while thread A changes the graph for the next frame:
// switches, general matrices, masks, the prototype's switch, and cells removed and replaced inside a
// DeferredRelease scope. At each hand-off (C idle) A updates the scene, frees what the last frame's edits released,
// and culls the new image itself: C's culls must give exactly that list.
TEST(ImageThreads, CullBesideTheApplicationEqualsTheCullOfTheSameUpdate) {
    constexpr int kFrames = 240, kCullsPerFrame = 3;
    Row row(36);
    Scene s(row.root);
    std::mutex mu;
    std::condition_variable cv;
    int ready = -1, done = -1;  // the frame whose image C may cull; the last frame C finished
    bool stop = false;
    std::vector<DrawList> culled(kCullsPerFrame);

    std::thread c([&] {
        CullTraversal cull;  // one per view, kept from frame to frame
        const CullSettings set = settingsBeside();
        for (int f = 0;; ++f) {
            {
                std::unique_lock<std::mutex> lock(mu);
                cv.wait(lock, [&] { return stop || ready >= f; });
                if (stop) return;
            }
            for (DrawList& l : culled) l = cullOnce(cull, s, set);
            {
                std::lock_guard<std::mutex> lock(mu);
                done = f;
            }
            cv.notify_all();
        }
    });

    std::mt19937 rng(7);
    const auto pick = [&](size_t n) { return size_t(rng() % n); };
    CullTraversal reference;
    std::vector<const Referenced*> released;
    size_t freed = 0, compared = 0;
    for (int f = 0; f < kFrames; ++f) {
        // The hand-off: C is idle.
        s.update();
        freed += released.size();
        releaseNow(released);
        const DrawList expected = cullOnce(reference, s, settingsBeside());
        {
            std::lock_guard<std::mutex> lock(mu);
            ready = f;
        }
        cv.notify_all();

        // The application's frame, beside C's cull of frame f.
        {
            DeferredRelease scope;
            for (int k = 0; k < 3; ++k) row.cells[pick(row.cells.size())].sw->setOnly(pick(2));
            for (int k = 0; k < 3; ++k) {
                Cell& cell = row.cells[pick(row.cells.size())];
                const dvec3 at(cell.t->matrix()[3]);
                cell.t->setMatrix(turned(at, 0.01 * double(pick(628)), 0.8 + 0.1 * double(pick(4))));
            }
            for (int k = 0; k < 2; ++k) row.cells[pick(row.cells.size())].maskable->setNodeMask(pick(2) ? 0x1 : 0x2);
            row.cells[pick(row.cells.size())].placed->setMatrix(turned(dvec3(0, 3, 0), 0.01 * double(pick(628)), 0.5));
            if (f % 4 == 0) row.proto->setOnly(pick(2));
            if (f % 3 == 0) {  // a cell removed: its nodes and meshes are queued, not freed, while C may read them
                const size_t k = pick(row.cells.size());
                row.root->removeChild(row.cells[k].t.get());
                row.cells.erase(row.cells.begin() + std::ptrdiff_t(k));
                row.add();
                EXPECT_GT(scope.size(), 0u);
            }
            released = scope.take();
        }

        {
            std::unique_lock<std::mutex> lock(mu);
            cv.wait(lock, [&] { return done >= f; });
        }
        for (int k = 0; k < kCullsPerFrame; ++k) {
            EXPECT_TRUE(sameList(culled[size_t(k)], expected)) << "frame " << f << ", cull " << k;
            ++compared;
        }
        if (::testing::Test::HasFailure()) break;
    }
    {
        std::lock_guard<std::mutex> lock(mu);
        stop = true;
    }
    cv.notify_all();
    c.join();
    releaseNow(released);
    EXPECT_EQ(compared, size_t(kFrames * kCullsPerFrame));
    EXPECT_GT(freed, size_t(kFrames / 3 - 1));
}

namespace {

// Counts its deletions; holds its children as a node does.
struct Counted : Referenced {
    explicit Counted(int& deaths) : deaths(deaths) {}
    ~Counted() override { ++deaths; }
    int& deaths;
    std::vector<ref_ptr<Counted>> kids;
};

}  // namespace

TEST(ImageThreads, DeferredReleaseQueuesTheLastUnrefUntilReleaseNow) {
    int deaths = 0;
    std::vector<const Referenced*> queued;
    {
        DeferredRelease scope;
        ref_ptr<Counted> a = new Counted(deaths), b = a;
        a = nullptr;  // not the last reference: nothing queued
        EXPECT_EQ(scope.size(), 0u);
        b = nullptr;
        EXPECT_EQ(deaths, 0);
        EXPECT_EQ(scope.size(), 1u);
        queued = scope.take();
        EXPECT_EQ(scope.size(), 0u);
    }
    EXPECT_EQ(deaths, 0);  // taken out of the scope: its end frees nothing
    ASSERT_EQ(queued.size(), 1u);
    releaseNow(queued);
    EXPECT_EQ(deaths, 1);
    EXPECT_TRUE(queued.empty());
    // Without a scope, the last unref deletes at once, as always.
    { ref_ptr<Counted> c = new Counted(deaths); }
    EXPECT_EQ(deaths, 2);
}

TEST(ImageThreads, DeferredReleaseOfATreeFreesTheChildrenWithTheRoot) {
    int deaths = 0;
    std::vector<const Referenced*> queued;
    {
        DeferredRelease scope;
        ref_ptr<Counted> root = new Counted(deaths);
        root->kids = {new Counted(deaths), new Counted(deaths)};
        root->kids[0]->kids = {new Counted(deaths)};
        root = nullptr;
        EXPECT_EQ(scope.size(), 1u);  // the root only: its children are still held by it
        queued = scope.take();
    }
    releaseNow(queued);  // no scope now: the children go with it
    EXPECT_EQ(deaths, 4);

    // Released inside a scope, the children are queued there in turn.
    deaths = 0;
    ref_ptr<Counted> root = new Counted(deaths);
    root->kids = {new Counted(deaths)};
    {
        DeferredRelease scope;
        root = nullptr;
        queued = scope.take();
        releaseNow(queued);
        EXPECT_EQ(deaths, 1);
        EXPECT_EQ(scope.size(), 1u);
    }
    EXPECT_EQ(deaths, 2);  // the outermost scope's end frees what it still holds
}

TEST(ImageThreads, DeferredReleaseOfNodesKeepsTheirMeshesUntilReleased) {
    ref_ptr<Mesh> mesh = makeBoxMesh(dvec3(0), dvec3(1));
    auto root = make<Group>();
    auto t = make<Transform>(turned(dvec3(1, 0, 0), 0.5));
    t->addChild(make<Geometry>(mesh, make<Material>()));
    root->addChild(t);
    std::vector<const Referenced*> queued;
    {
        DeferredRelease scope;
        root->removeChild(t.get());
        t = nullptr;
        EXPECT_EQ(mesh->refCount(), 2u);  // the Geometry, below the queued Transform, still holds it
        queued = scope.take();
    }
    EXPECT_EQ(mesh->refCount(), 2u);
    releaseNow(queued);
    EXPECT_EQ(mesh->refCount(), 1u);
}

TEST(ImageThreads, DeferredReleaseScopesNest) {
    int deaths = 0;
    DeferredRelease outer;
    {
        DeferredRelease inner;
        ref_ptr<Counted> a = new Counted(deaths);
        a = nullptr;
        EXPECT_EQ(inner.size(), 1u);  // the innermost scope queues
        EXPECT_EQ(outer.size(), 0u);
    }
    EXPECT_EQ(deaths, 0);  // an inner scope's end hands what it holds to the outer one
    EXPECT_EQ(outer.size(), 1u);
    // Another thread's last unref is its own: deleted there at once.
    ref_ptr<Counted> b = new Counted(deaths);
    std::thread([&] { b = nullptr; }).join();
    EXPECT_EQ(deaths, 1);
    EXPECT_EQ(outer.size(), 1u);
    std::vector<const Referenced*> q = outer.take();
    releaseNow(q);
    EXPECT_EQ(deaths, 2);
}

TEST(ImageThreads, ASwitchInAnAttachedDetailIsCopiedAtTheUpdate) {
    auto mat = make<Material>();
    auto paged = make<PagedLOD>();
    paged->setRange(0.0f, std::numeric_limits<float>::infinity());  // the detail wanted from anywhere
    paged->addChild(make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), mat));
    auto sw = make<Switch>();
    auto a = make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1, 1, 2)), mat);
    auto b = make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1, 1, 3)), mat);
    sw->addChild(a);
    sw->addChild(b, false);
    paged->attachDetail(sw, 0);
    auto root = make<Group>();
    root->addChild(paged);
    Scene s(root);
    s.update();
    CullTraversal cull;
    const auto meshes = [&] {
        std::vector<const Mesh*> v;
        for (const DrawItem& it : cullOnce(cull, s, settingsBeside()).items) v.push_back(it.mesh);
        return v;
    };
    ASSERT_EQ(meshes(), std::vector<const Mesh*>{a->mesh()});
    sw->setOnly(1);
    EXPECT_EQ(meshes(), std::vector<const Mesh*>{a->mesh()});
    s.update();
    EXPECT_EQ(s.lastUpdate().entriesWritten, 0u);  // copied without a refit
    EXPECT_EQ(meshes(), std::vector<const Mesh*>{b->mesh()});
}
