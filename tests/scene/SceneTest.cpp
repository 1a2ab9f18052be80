#include "TestUtil.h"
#include "nodes/PagedLOD.h"
#include "sg/cull/CullTraversal.h"
#include "sg/scene/Scene.h"
#include "sg/scene/internal/DistinctGeometries.h"
#include "testbed/City.h"
#include "testbed/RandomScene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

using namespace sg;

namespace {
ref_ptr<Geometry> unitBox(const ref_ptr<Material>& m = make<Material>()) {
    return make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), m);
}

// Every vertex of every geometry lies inside the box and the sphere of its entry and of all its ancestors.
void expectBoundsEnclose(const Scene& s) {
    const FlatImage& img = s.image();
    std::vector<uint32_t> stack;
    std::function<void(Node*, const dmat4&, uint32_t)> walk = [&](Node* n, const dmat4& m, uint32_t i) {
        ASSERT_EQ(img.kind[i], n->kind());
        if (n->kind() == NodeKind::Geometry && !(img.flags[i] & FlatImage::kNoTest)) {
            for (const vec3& p : static_cast<Geometry*>(n)->mesh()->positions()) {
                const dvec3 w(m * dvec4(dvec3(p), 1.0));
                for (uint32_t a : stack) {
                    const Box b = img.box(a);
                    ASSERT_TRUE(b.contains(w))
                        << "entry " << a << " (" << kindName(img.kind[a]) << ") box misses a vertex of entry " << i
                        << " by " << glm::length(glm::max(b.min - w, dvec3(0)) + glm::max(w - b.max, dvec3(0)));
                    ASSERT_LE(glm::length(w - img.center(a)), double(img.r[a]))
                        << "entry " << a << " sphere misses a vertex";
                }
            }
        }
        if (n->kind() == NodeKind::Instance) return;  // its prototype has an image of its own
        const dmat4 cm = n->kind() == NodeKind::Transform ? static_cast<Transform*>(n)->apply(m) : m;
        uint32_t j = i + 1;
        for (size_t k = 0; k < n->numChildren(); ++k, j = img.end[j]) {
            stack.push_back(j);
            walk(n->child(k), cm, j);
            stack.pop_back();
        }
        ASSERT_EQ(j, img.end[i]);
    };
    stack.push_back(0);
    walk(s.root(), dmat4(1.0), 0);
}
}  // namespace

TEST(Scene, ImageIsPreOrderWithSkipIndices) {
    auto root = make<Group>();
    auto a = make<Transform>(glm::translate(dmat4(1.0), dvec3(10, 0, 0)));
    a->addChild(unitBox());
    a->addChild(unitBox());
    root->addChild(a);
    root->addChild(unitBox());
    Scene s(root);
    s.update();
    const FlatImage& img = s.image();
    ASSERT_EQ(img.size(), 5u);
    EXPECT_EQ(img.end[0], 5u);
    EXPECT_EQ(img.end[1], 4u);
    EXPECT_EQ(img.end[2], 3u);
    EXPECT_EQ(img.kind[1], NodeKind::Transform);
    EXPECT_NEAR(img.center(2).x, 10.0, 1e-6);
    EXPECT_NEAR(img.box(0).min.x, -1.0, 1e-5);
    EXPECT_NEAR(img.box(0).max.x, 11.0, 1e-5);
    expectBoundsEnclose(s);
}

TEST(Scene, UnchangedSceneCostsNothingAndChangesRefitOnlyTheirPath) {
    Scene s(scenes::buildCity({16, false}));
    s.update();
    EXPECT_EQ(s.lastUpdate().fullRebuilds, 1u);
    s.update();
    EXPECT_EQ(s.lastUpdate().fullRebuilds, 0u);
    EXPECT_EQ(s.lastUpdate().entriesWritten, 0u);
    // Move one building's transform: its subtree (transform, LOD, 2 geometries) is rewritten, nothing else.
    auto* tile = s.root()->child(0);
    auto* cell = tile->child(3);
    auto* place = static_cast<Transform*>(cell->child(0));
    const size_t before = s.image().size();
    place->setTranslation(place->translation() + dvec3(0, 0, 100));
    s.update();
    EXPECT_EQ(s.lastUpdate().fullRebuilds, 0u);
    EXPECT_EQ(s.lastUpdate().entriesWritten, 4u);
    EXPECT_EQ(s.image().size(), before);
    EXPECT_GT(s.image().box(0).max.z, 100.0);  // the root's bound followed
    expectBoundsEnclose(s);
    // A structural change rebuilds.
    static_cast<Group*>(cell)->addChild(unitBox());
    s.update();
    EXPECT_EQ(s.lastUpdate().fullRebuilds, 1u);
    EXPECT_EQ(s.image().size(), before + 1);
    expectBoundsEnclose(s);
}

TEST(Scene, SwitchTurningMovesTheVersionWithoutARefit) {
    auto sw = make<Switch>();
    sw->addChild(unitBox());
    sw->addChild(unitBox(), false);
    auto inner = make<Switch>();  // one inside an Instance prototype too
    inner->addChild(unitBox());
    auto root = make<Group>();
    root->addChild(sw);
    root->addChild(make<Instance>(inner, dmat4(1.0)));
    Scene s(root);
    s.update();
    const uint64_t structure = s.structureVersion();
    uint64_t v = s.version();
    const auto turnsOnce = [&](const std::function<void()>& turn, const char* what) {
        turn();
        s.update();
        EXPECT_EQ(s.version(), v + 1) << what;
        EXPECT_EQ(s.lastUpdate().entriesWritten, 0u) << what;
        v = s.version();
        s.update();  // the mark is cleared: the next update is free again
        EXPECT_EQ(s.version(), v) << what;
    };
    turnsOnce([&] { sw->setOn(1, true); }, "setOn");
    turnsOnce([&] { sw->setAll(false); }, "setAll");
    turnsOnce([&] { sw->setOnly(0); }, "setOnly");
    turnsOnce([&] { inner->setOn(0, false); }, "setOn in a prototype");
    EXPECT_EQ(s.structureVersion(), structure);
    // Setting what is already set is no change.
    sw->setOnly(0);
    sw->setOn(1, false);
    inner->setAll(false);
    s.update();
    EXPECT_EQ(s.version(), v);
}

TEST(Scene, SharedChildIsUpdatedOnEveryPath) {
    auto shared = make<Transform>();
    shared->addChild(unitBox());
    auto root = make<Group>();
    for (int k = 0; k < 2; ++k) {
        auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(100.0 * k, 0, 0)));
        t->addChild(shared);
        root->addChild(t);
    }
    Scene s(root);
    s.update();
    shared->setTranslation(dvec3(0, 50, 0));
    s.update();
    EXPECT_NEAR(s.image().center(3).y, 50.0, 1e-5);
    EXPECT_NEAR(s.image().center(6).y, 50.0, 1e-5);
    EXPECT_NEAR(s.image().center(6).x, 100.0, 1e-5);
    expectBoundsEnclose(s);
}

TEST(Scene, UpdateCallbacksRunEachFrameAndTheirChangesShow) {
    auto root = make<Group>();
    auto t = make<Transform>();
    t->addChild(unitBox());
    t->setUpdateCallback(
        [](Node& n, const FrameInfo& f) { static_cast<Transform&>(n).setTranslation(dvec3(double(f.frame), 0, 0)); });
    root->addChild(t);
    Scene s(root);
    for (uint64_t f = 1; f <= 3; ++f) {
        s.update({f, 0.0});
        EXPECT_EQ(s.lastUpdate().callbacksRun, 1u);
        EXPECT_NEAR(s.image().center(2).x, double(f), 1e-6);
    }
}

TEST(Scene, RandomScenesHaveEnclosingBoundsNearAndFarFromTheOrigin) {
    for (uint64_t seed = 1; seed <= 6; ++seed)
        for (double off : {0.0, 1e7}) {
            scenes::RandomSceneOptions o;
            o.offset = dvec3(off, -off, off * 0.1);
            Scene s(scenes::buildRandomScene(seed, o));
            s.update();
            expectBoundsEnclose(s);
            // Float offsets stay small: the image origin is inside the scene.
            EXPECT_LT(s.image().extent, 1e3) << "seed " << seed;
        }
}

TEST(Scene, NaNPositionsMakeAnInvalidEntryThatPoisonsNoSibling) {
    auto root = make<Group>();
    auto bad = make<Mesh>();
    bad->set({vec3(0), vec3(1, 0, 0), vec3(NAN, 0, 0)}, {}, {0, 1, 2});
    root->addChild(make<Geometry>(bad, make<Material>()));
    root->addChild(unitBox());
    Scene s(root);
    s.update();
    EXPECT_TRUE(s.image().flags[1] & FlatImage::kInvalid);
    EXPECT_FALSE(s.image().flags[2] & FlatImage::kInvalid);
    EXPECT_TRUE(s.image().flags[0] & FlatImage::kInvalid);  // the parent can never be culled either
}

TEST(Scene, PrototypeImageIsBuiltOnceForManyInstances) {
    auto proto = make<Group>();
    proto->addChild(unitBox());
    auto root = make<Group>();
    for (int k = 0; k < 50; ++k)
        root->addChild(make<Instance>(proto, glm::translate(dmat4(1.0), dvec3(10.0 * k, 0, 0))));
    Scene s(root);
    s.update();
    EXPECT_EQ(s.image().size(), 51u);
    ASSERT_NE(s.prototypeImage(proto.get()), nullptr);
    EXPECT_EQ(s.prototypeImage(proto.get())->size(), 2u);
    EXPECT_NEAR(s.image().center(50).x, 490.0, 1e-5);
    EXPECT_NEAR(s.image().r[50], std::sqrt(3.0), 1e-5);
}

TEST(Scene, RefitGivesTheImageAFullBuildGives) {
    // Large enough for the root's children to be kept side by side (a wide group).
    auto root = scenes::buildCity({48, false});
    Scene s(root);
    s.update();
    ASSERT_FALSE(s.image().wides.empty());
    scenes::Rng rng(3);
    for (int round = 0; round < 3; ++round) {
        for (int k = 0; k < 20; ++k) {
            Node* tile = root->child(size_t(rng.below(int(root->numChildren()))));
            Node* cell = tile->child(size_t(rng.below(int(tile->numChildren()))));
            auto* t = static_cast<Transform*>(cell->child(size_t(rng.below(2))));
            t->setMatrix(glm::rotate(
                glm::translate(dmat4(1.0), t->translation() + dvec3(rng.uniform(-50, 50), 0, rng.uniform(0, 30))),
                rng.uniform(0, 3), dvec3(0, 0, 1)));
        }
        s.update();
        EXPECT_EQ(s.lastUpdate().fullRebuilds, 0u);
        Scene fresh(root);
        fresh.update();
        const FlatImage &a = s.image(), &b = fresh.image();
        ASSERT_EQ(a.size(), b.size());
        ASSERT_EQ(a.origin, b.origin);
        for (size_t i = 0; i < a.size(); ++i) {
            ASSERT_EQ(a.cx[i], b.cx[i]) << i;
            ASSERT_EQ(a.r[i], b.r[i]) << i;
            ASSERT_EQ(a.ez[i], b.ez[i]) << i;
            ASSERT_EQ(a.end[i], b.end[i]) << i;
        }
        ASSERT_EQ(a.wr, b.wr);
        ASSERT_EQ(a.wcx, b.wcx);
        for (size_t i = 0; i < a.size(); ++i) {
            if (a.kind[i] != NodeKind::Transform) continue;
            ASSERT_EQ(a.flags[i], b.flags[i]) << i;
            if (a.flags[i] & FlatImage::kGeneral)
                ASSERT_EQ(a.matrices[a.aux[i]], b.matrices[b.aux[i]]) << i;
            else
                ASSERT_EQ(a.translations[a.aux[i]], b.translations[b.aux[i]]) << i;
        }
        expectBoundsEnclose(s);
    }
}

namespace {
// Whether `to` is `from` or lies below it, through children and instances' prototypes: adding `from` below `to`
// would make a cycle. The test's own walk, each node once.
bool reaches(const Node* from, const Node* to, std::set<const Node*>& seen) {
    if (from == to) return true;
    if (!seen.insert(from).second) return false;
    for (size_t k = 0; k < from->numChildren(); ++k)
        if (reaches(from->child(k), to, seen)) return true;
    const Node* proto = from->kind() == NodeKind::Instance ? static_cast<const Instance*>(from)->prototype() : nullptr;
    return proto && reaches(proto, to, seen);
}
bool reaches(const Node* from, const Node* to) {
    std::set<const Node*> seen;
    return reaches(from, to, seen);
}
}  // namespace

// Random edits, good and bad, between updates and culls: bad ones are refused with an error and change
// nothing; after every update the image equals a fresh build of the same graph, and a cull runs.
TEST(Scene, RandomEditsKeepTheImageExactAndBadOnesAreRefused) {
    scenes::Rng rng(12345);
    auto root = scenes::buildRandomScene(5, {30, 40.0, dvec3(0.0)});
    Scene s(root);
    s.update();
    std::vector<ref_ptr<Node>> all;  // references: a node removed by one edit stays valid for the next
    std::function<void(Node*)> collect = [&](Node* n) {
        all.push_back(n);
        for (size_t k = 0; k < n->numChildren(); ++k) collect(n->child(k));
    };
    Camera cam;
    cam.setViewport(64, 64);
    cam.setLookAt(dvec3(0, -150, 40), dvec3(0), dvec3(0, 0, 1));
    CullTraversal cull;
    DrawList list;
    CullStats stats;
    int refused = 0, mustRefused = 0;
    for (int round = 0; round < 60; ++round) {
        all.clear();
        collect(root.get());
        for (int e = 0; e < 8; ++e) {
            Node* n = all[size_t(rng.below(int(all.size())))].get();
            Node* other = all[size_t(rng.below(int(all.size())))].get();
            bool mustRefuse = false, threw = false;  // the edits known to be bad must be refused
            try {
                switch (rng.below(7)) {
                    case 0:
                        if (n->kind() == NodeKind::Transform) {
                            // Each draw its own statement: the stream is the same whatever order a compiler
                            // evaluates arguments in.
                            const double angle = rng.uniform(0, 3), x = rng.uniform(-20, 20);
                            dmat4 m = glm::rotate(glm::translate(dmat4(1.0), dvec3(x, 0, 0)), angle, dvec3(0, 0, 1));
                            if (rng.chance(0.3)) m[1][1] = std::nan("");
                            if (rng.chance(0.2)) m = glm::translate(dmat4(1.0), dvec3(rng.uniform(-5, 5)));
                            mustRefuse = std::isnan(m[1][1]);
                            static_cast<Transform*>(n)->setMatrix(m);
                        }
                        break;
                    case 1:  // may be a cycle: must be refused
                        if (auto* g = dynamic_cast<Group*>(n); g && n->kind() != NodeKind::LOD) {
                            mustRefuse = reaches(other, n);
                            g->addChild(other);
                        }
                        break;
                    case 2:
                        if (auto* g = dynamic_cast<Group*>(n); g && g->numChildren() > 1 && n->kind() != NodeKind::LOD)
                            g->removeChild(size_t(rng.below(int(g->numChildren()))));
                        break;
                    case 3: n->setNodeMask(rng.chance(0.5) ? 0x1u : 0xffffffffu); break;
                    case 4:
                        if (n->kind() == NodeKind::LOD) {
                            const float far = float(rng.uniform(5, 80));
                            mustRefuse = rng.chance(0.3);
                            static_cast<LOD*>(n)->setRange(0, mustRefuse ? -1.0f : 0.0f, far);
                        }
                        break;
                    case 5:
                        if (n->kind() == NodeKind::Instance) {
                            Node* prototype = rng.chance(0.5) ? other : n;
                            mustRefuse = reaches(prototype, n);
                            static_cast<Instance*>(n)->setPrototype(ref_ptr<Node>(prototype));
                        }
                        break;
                    default:
                        if (n->kind() == NodeKind::Switch) static_cast<Switch*>(n)->setAll(rng.chance(0.5));
                        break;
                }
            } catch (const std::invalid_argument& err) {
                threw = true;
                ++refused;
                const std::string what = err.what();
                ASSERT_NE(what.find("()"), std::string::npos) << what;  // names the function
            }
            EXPECT_TRUE(threw || !mustRefuse) << "round " << round << " edit " << e << ": a bad edit was taken";
            mustRefused += mustRefuse;
        }
        s.update();
        cull.cull(s, cam, CullSettings{}, list, stats);
        Scene fresh(root);
        fresh.update();
        const FlatImage &a = s.image(), &b = fresh.image();
        ASSERT_EQ(a.size(), b.size()) << "round " << round;
        for (size_t i = 0; i < a.size(); ++i) {
            ASSERT_EQ(a.kind[i], b.kind[i]);
            ASSERT_EQ(a.end[i], b.end[i]);
            ASSERT_EQ(a.flags[i] & ~FlatImage::kGeneral, b.flags[i] & ~FlatImage::kGeneral)
                << "round " << round << " entry " << i;
            if (!(a.flags[i] & FlatImage::kInvalid)) {
                // The two images may have different origins (a refit keeps the old one): equal up to
                // the float rounding of the stored offsets.
                const double tol = 1e-5 * (1.0 + a.extent);
                ASSERT_LE(glm::length(a.center(i) - b.center(i)), tol) << "round " << round << " entry " << i;
                ASSERT_NEAR(a.r[i], b.r[i], tol);
            }
        }
        expectBoundsEnclose(s);
    }
    EXPECT_GT(mustRefused, 5);        // bad edits were tried (and refused, above)
    EXPECT_EQ(refused, mustRefused);  // and no good one was refused
}

namespace {
// Two images equal entry by entry (kinds, subtree ends, bounds up to float rounding), their paged details and the
// prototypes' images they own too.
void expectSameImages(const FlatImage& a, const FlatImage& b, const std::string& where) {
    ASSERT_EQ(a.size(), b.size()) << where;
    ASSERT_EQ(a.prototypes.size(), b.prototypes.size()) << where;
    for (const auto& [proto, pa] : a.prototypes) {
        auto pb = b.prototypes.find(proto);
        ASSERT_NE(pb, b.prototypes.end()) << where << ": no image of prototype " << proto->describe();
        expectSameImages(*pa, *pb->second, where + "/" + proto->describe());
    }
    for (uint32_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(a.kind[i], b.kind[i]) << where << " entry " << i;
        ASSERT_EQ(a.end[i], b.end[i]) << where << " entry " << i;
        ASSERT_LE(glm::length(a.center(i) - b.center(i)), 1e-4) << where << " entry " << i;
        ASSERT_NEAR(a.r[i], b.r[i], 1e-4) << where << " entry " << i;
        if (a.kind[i] != NodeKind::PagedLOD) continue;
        const auto &da = a.paged[a.aux[i]].detail, &db = b.paged[b.aux[i]].detail;
        ASSERT_EQ(bool(da), bool(db)) << where << " entry " << i;
        if (da) expectSameImages(*da, *db, where + "/" + std::to_string(i));
    }
}

ref_ptr<Group> boxes(int count, double x) {
    auto g = make<Group>();
    for (int i = 0; i < count; ++i) {
        auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(x + 3.0 * i, 0, 0)));
        t->addChild(unitBox());
        g->addChild(t);
    }
    return g;
}

ref_ptr<PagedLOD> paged(const std::string& file, double x) {
    auto p = make<PagedLOD>();
    p->setFile(file);
    p->setRange(0.0f, 1e9f);
    p->addChild(boxes(1, x));  // the coarse level
    return p;
}

// A detail of Instances, as a tile of instanced models: 50 placements of an LOD over a box in a row along x at
// y = 100, and one of a group that places the LOD once more inside (a nested Instance), at y = 120.
struct InstancedDetail {
    ref_ptr<LOD> lod;
    ref_ptr<Group> outer;  // the prototype holding an Instance
    ref_ptr<Group> root;
};
InstancedDetail instancedDetail() {
    InstancedDetail d;
    d.lod = make<LOD>();
    d.lod->addChild(unitBox(), 0.0f, 500.0f);
    d.outer = make<Group>();
    d.outer->addChild(make<Instance>(d.lod, glm::translate(dmat4(1.0), dvec3(0, 0, 5))));
    d.root = make<Group>();
    for (int k = 0; k < 50; ++k)
        d.root->addChild(make<Instance>(d.lod, glm::translate(dmat4(1.0), dvec3(-49.0 + 2.0 * k, 100, 0))));
    d.root->addChild(make<Instance>(d.outer, glm::translate(dmat4(1.0), dvec3(0, 120, 0))));
    return d;
}

// A PagedLOD below a translation, and the frame its detail's image is built in (what the cull posts).
struct PlacedPaged {
    ref_ptr<PagedLOD> node = paged("a", 0.0);
    ref_ptr<Group> root = make<Group>();
    dmat4 frame = glm::translate(dmat4(1.0), dvec3(5, 7, 0));
    PlacedPaged() {
        auto placed = make<Transform>(frame);
        placed->addChild(node);
        root->addChild(placed);
    }
    const FlatImage::Paged& entry(const Scene& s) const {
        for (const FlatImage::Paged& pg : s.image().paged)
            if (pg.node == node.get()) return pg;
        throw std::logic_error("no entry for the PagedLOD");
    }
};

// What a cull from `cam` gives the renderer: each item's mesh, translation and draw state (its sort key's).
std::multiset<std::tuple<const Mesh*, float, float, float, uint32_t>> drawnFrom(const Scene& s, const Camera& cam) {
    DrawList list;
    CullStats stats;
    CullTraversal().cull(s, cam, {}, list, stats);
    std::multiset<std::tuple<const Mesh*, float, float, float, uint32_t>> items;
    for (size_t i = 0; i < list.items.size(); ++i) {
        const DrawItem& it = list.items[i];
        items.insert({it.mesh, it.model[3].x, it.model[3].y, it.model[3].z, list.key(i) >> 12});
    }
    return items;
}
}  // namespace

TEST(Scene, AttachingADetailDeepDownRefitsTheDetailsAboveItAndRebuildsNoOther) {
    auto a = paged("a", 0.0);
    auto root = make<Group>();
    root->addChild(a);
    auto da = make<Group>();
    std::vector<ref_ptr<PagedLOD>> b;
    for (int i = 0; i < 4; ++i) {
        b.push_back(paged("b" + std::to_string(i), 400.0 * i));
        da->addChild(b.back());
    }
    a->attachDetail(da, 0);
    auto c = paged("c", 10.0);
    for (int i = 0; i < 4; ++i) {
        auto d = boxes(100, 400.0 * i);
        if (i == 0) d->addChild(c);
        b[size_t(i)]->attachDetail(d, 0);
    }
    Scene s(root);
    s.update();
    const uint64_t rebuilds = s.structureVersion();

    // A detail attached three levels down: its own entries are built, the details above it refitted along the
    // path; the 100-box details beside it (and below them) are not written again.
    c->attachDetail(boxes(5, 1000.0), 0);
    s.update();
    EXPECT_EQ(s.structureVersion(), rebuilds);
    EXPECT_LT(s.lastUpdate().entriesWritten, 60u);
    Scene fresh(root);
    fresh.update();
    expectSameImages(s.image(), fresh.image(), "after attach");

    // And detached again.
    c->detachDetail();
    s.update();
    EXPECT_LT(s.lastUpdate().entriesWritten, 60u);
    Scene fresh2(root);
    fresh2.update();
    expectSameImages(s.image(), fresh2.image(), "after detach");
}

TEST(DistinctGeometryWalk, StopsWhenAskedAndGoesOnToMeetEachGeometryOnce) {
    // 1,000 geometries under transforms, a shared subgraph placed twice, one mesh shared by all.
    auto mesh = makeBoxMesh(dvec3(-1), dvec3(1));
    auto root = make<Group>();
    for (int i = 0; i < 1000; ++i) {
        auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(double(i), 0, 0)));
        t->addChild(make<Geometry>(mesh, nullptr));
        root->addChild(t);
    }
    auto shared = make<Group>();
    shared->addChild(make<Geometry>(mesh, nullptr));
    root->addChild(shared);
    root->addChild(shared);

    std::set<const Geometry*> met;
    size_t calls = 0, repeats = 0;
    DistinctGeometryWalk walk(*root);
    while (!walk.run([&](const Geometry& g) { repeats += !met.insert(&g).second; }, [] { return true; }, 64)) {
        ++calls;
        ASSERT_LT(calls, 1000u);
    }
    EXPECT_TRUE(walk.done());
    EXPECT_EQ(met.size(), 1001u);
    EXPECT_EQ(repeats, 0u);
    EXPECT_GE(calls, 2003u / 64);  // stopped every 63 nodes: 2,003 nodes in all
    size_t once = 0;
    forEachDistinctGeometry(*root, [&](const Geometry&) { ++once; });
    EXPECT_EQ(once, 1001u);
}

TEST(Scene, ADetailImageBuiltAheadIsTakenWhenItsFrameMatchesAndRebuiltWhenNot) {
    for (const bool sameFrame : {true, false}) {
        auto a = paged("a", 0.0);
        auto placed = make<Transform>(glm::translate(dmat4(1.0), dvec3(5, 7, 0)));
        placed->addChild(a);
        auto root = make<Group>();
        root->addChild(placed);
        Scene s(root);
        s.update();
        // The frame the cull posts with the request is the one the image is built in.
        const FlatImage::Paged* entry = nullptr;
        for (const FlatImage::Paged& pg : s.image().paged)
            if (pg.node == a.get()) entry = &pg;
        ASSERT_NE(entry, nullptr);
        const dmat4 frame = entry->frame;
        EXPECT_EQ(frame, placed->matrix());

        auto detail = boxes(300, 20.0);
        std::shared_ptr<FlatImage> ahead = Scene::buildDetailImage(*detail, sameFrame ? frame : dmat4(1.0));
        ASSERT_TRUE(ahead);
        EXPECT_EQ(ahead->size(), 1u + 2u * 300u);
        s.offerDetailImage(a.get(), detail.get(), sameFrame ? frame : dmat4(1.0), ahead);
        a->attachDetail(detail, 0);
        s.update();
        // Taken: the update writes the paged node's own entries only; in another frame, it builds the detail.
        if (sameFrame)
            EXPECT_LT(s.lastUpdate().entriesWritten, 20u);
        else
            EXPECT_GT(s.lastUpdate().entriesWritten, 600u);
        Scene fresh(root);
        fresh.update();
        expectSameImages(s.image(), fresh.image(), sameFrame ? "taken" : "rebuilt");
    }
}

TEST(Scene, ADetailHoldingInstancesIsBuiltAheadWithItsPrototypesImagesAndDrawnAsAFreshSceneDrawsIt) {
    PlacedPaged p;
    Scene s(p.root);
    s.update();
    ASSERT_EQ(p.entry(s).frame, p.frame);
    const InstancedDetail d = instancedDetail();
    std::shared_ptr<FlatImage> ahead = Scene::buildDetailImage(*d.root, p.frame);
    ASSERT_TRUE(ahead);
    EXPECT_EQ(ahead->size(), 1u + 51u);
    s.offerDetailImage(p.node.get(), d.root.get(), p.frame, ahead);
    p.node->attachDetail(d.root, 0);
    s.update();
    // Taken, prototypes' images and all: the update writes the paged node's own entries only.
    EXPECT_EQ(p.entry(s).detail, ahead);
    EXPECT_LT(s.lastUpdate().entriesWritten, 20u);
    Scene fresh(p.root);
    fresh.update();
    expectSameImages(s.image(), fresh.image(), "taken");

    // Every placement drawn, the nested one too, with the scene's draw states (the image was built with others).
    const Camera cam = testutil::lookingAlongY();
    const auto drawn = drawnFrom(s, cam);
    EXPECT_EQ(drawn.size(), 51u);
    EXPECT_EQ(drawn, drawnFrom(fresh, cam));
}

TEST(Scene, ADetailBuiltAheadWithADetailAttachedInsideDrawsWithTheScenesStates) {
    PlacedPaged p;
    Scene s(p.root);
    s.update();
    auto inner = paged("inner", 0.0);
    inner->attachDetail(boxes(5, -6.0), 0);  // five materials: five states of the image built alone
    auto ahead = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 100, 0)));
    ahead->addChild(inner);
    auto detail = make<Group>();
    detail->addChild(ahead);
    s.offerDetailImage(p.node.get(), detail.get(), p.frame, Scene::buildDetailImage(*detail, p.frame));
    p.node->attachDetail(detail, 0);
    s.update();
    EXPECT_LT(s.lastUpdate().entriesWritten, 20u);  // taken
    Scene fresh(p.root);
    fresh.update();
    const Camera cam = testutil::lookingAlongY();
    const auto drawn = drawnFrom(s, cam);
    EXPECT_EQ(drawn.size(), 5u);
    EXPECT_EQ(drawn, drawnFrom(fresh, cam));
}

TEST(Scene, ADetachedDetailTakesItsPrototypesImagesWithIt) {
    for (const bool ahead : {false, true}) {
        SCOPED_TRACE(ahead ? "built ahead" : "built by the update");
        PlacedPaged p;
        Scene s(p.root);
        s.update();
        const size_t bytes = s.bytes();
        for (int load = 0; load < 3; ++load) {  // tiles loaded and evicted in turn: nothing is left behind
            const InstancedDetail d = instancedDetail();
            if (ahead) {
                std::shared_ptr<FlatImage> image = Scene::buildDetailImage(*d.root, p.frame);
                ASSERT_TRUE(image);
                s.offerDetailImage(p.node.get(), d.root.get(), p.frame, std::move(image));
            }
            p.node->attachDetail(d.root, 0);
            s.update();
            ASSERT_TRUE(p.entry(s).detail);
            EXPECT_GT(s.bytes(), bytes);
            p.node->detachDetail();
            s.update();
            // No image left keyed by the detail's nodes (freed with it), no bytes left counted.
            EXPECT_EQ(s.prototypeImage(d.lod.get()), nullptr);
            EXPECT_EQ(s.prototypeImage(d.outer.get()), nullptr);
            EXPECT_EQ(s.bytes(), bytes);
        }
    }
}

TEST(Scene, ADetailsPrototypesImagesFollowItsStructureAndTheirPrototypes) {
    PlacedPaged p;
    const InstancedDetail d = instancedDetail();
    p.node->attachDetail(d.root, 0);
    p.root->addChild(make<Instance>(d.lod, glm::translate(dmat4(1.0), dvec3(0, 0, 50))));  // placed outside too
    Scene s(p.root);
    s.update();
    const FlatImage& detail = *p.entry(s).detail;
    ASSERT_EQ(detail.prototypes.size(), 2u);
    const FlatImage* lod = s.prototypeImage(detail, d.lod.get());
    ASSERT_NE(lod, nullptr);
    EXPECT_EQ(lod, detail.prototypes.at(d.lod.get()).get());
    const FlatImage* scenes = s.prototypeImage(d.lod.get());
    ASSERT_NE(scenes, nullptr);
    EXPECT_NE(scenes, lod);  // the detail's own
    EXPECT_EQ(s.prototypeImage(s.image(), d.lod.get()), scenes);
    // The nested Instance's prototype's image is its placing prototype's.
    const FlatImage& outer = *detail.prototypes.at(d.outer.get());
    ASSERT_EQ(outer.prototypes.size(), 1u);
    EXPECT_EQ(s.prototypeImage(outer, d.lod.get()), outer.prototypes.at(d.lod.get()).get());

    // A prototype changed: the detail refitted, its images of the prototype rebuilt in place, where it is placed
    // and nested, and the scene's too (each table rebuilds it once in an update).
    const uint64_t structure = s.structureVersion();
    static_cast<Geometry*>(d.lod->child(0))->setMesh(makeBoxMesh(dvec3(-2), dvec3(2)));
    s.update();
    ASSERT_EQ(s.structureVersion(), structure);
    EXPECT_EQ(s.prototypeImage(detail, d.lod.get()), lod);
    EXPECT_NEAR(lod->r[0], std::sqrt(12.0), 1e-4);
    EXPECT_NEAR(outer.prototypes.at(d.lod.get())->r[0], std::sqrt(12.0), 1e-4);
    EXPECT_NEAR(s.prototypeImage(d.lod.get())->r[0], std::sqrt(12.0), 1e-4);
    Scene fresh(p.root);
    fresh.update();
    expectSameImages(s.image(), fresh.image(), "prototype changed");

    // The nested placement removed (a change of structure: the scene's image rebuilt): the outer prototype's image
    // is freed with the detail's.
    std::weak_ptr<FlatImage> outerImage = detail.prototypes.at(d.outer.get());
    d.root->removeChild(d.root->numChildren() - 1);
    s.update();
    EXPECT_TRUE(outerImage.expired());
    ASSERT_EQ(p.entry(s).detail->prototypes.size(), 1u);
    Scene fresh2(p.root);
    fresh2.update();
    expectSameImages(s.image(), fresh2.image(), "nested placement removed");
}
