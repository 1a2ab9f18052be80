// TriangleClusters: cluster boxes hold their triangles; the screen-rectangle rejection keeps what reaches the
// viewport (hand-made cases, boxes across the near plane and behind the eye, against the paper's per-triangle test);
// the cache; and the cull's use of it (CullSettings::screenRect): counts and DrawList ranges.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"
#include "sg/cull/TriangleClusters.h"
#include "testbed/RandomScene.h"

#include <gtest/gtest.h>

#include <stdexcept>

using namespace sg;

namespace {

// A flat strip along x from x0 to x1 at z = 0 (facing +z), `quads` quads in a row: triangle t covers
// [x0 + (t / 2) * step, x0 + (t / 2 + 1) * step].
ref_ptr<Mesh> strip(double x0, double x1, uint32_t quads) {
    std::vector<vec3> pos, nrm;
    std::vector<uint32_t> idx;
    for (uint32_t i = 0; i <= quads; ++i)
        for (int j = 0; j < 2; ++j) {
            pos.push_back(vec3(float(x0 + (x1 - x0) * i / quads), float(j) - 0.5f, 0.0f));
            nrm.push_back(vec3(0, 0, 1));
        }
    for (uint32_t i = 0; i < quads; ++i) {
        const uint32_t a = 2 * i, b = a + 1, c = a + 2, d = a + 3;
        idx.insert(idx.end(), {a, c, d, a, d, b});
    }
    auto m = make<Mesh>();
    m->set(pos, nrm, idx);
    return m;
}

// Looking down -z at the origin from z = 10, 90 degrees vertically, square: the viewport spans x, y in [-10, 10]
// at z = 0.
Camera topDown() {
    Camera cam;
    cam.setViewport(100, 100);
    cam.setPerspective(90.0, 1.0, 0.5, 100.0);
    cam.setLookAt(dvec3(0, 0, 10), dvec3(0, 0, 0), dvec3(0, 1, 0));
    return cam;
}

dmat4 viewProj(const Camera& c) { return c.projection() * c.viewRotation(); }
// Local -> eye-relative world for a mesh at `at`.
dmat4 model(const Camera& c, const dvec3& at) { return glm::translate(dmat4(1.0), at - c.eye()); }

}  // namespace

TEST(TriangleClusters, EveryClusterBoxHoldsItsTriangles) {
    scenes::Rng rng(7);
    for (int m = 0; m < 20; ++m) {
        std::vector<vec3> pos, nrm;
        std::vector<uint32_t> idx;
        const double scale = std::pow(10.0, rng.uniform(-3, 5));
        for (int v = 0; v < 200; ++v) {
            pos.push_back(vec3(float(rng.uniform(-1, 1) * scale), float(rng.uniform(-1, 1) * scale + scale * 3),
                               float(rng.uniform(-1, 1) * scale)));
            nrm.push_back(vec3(0, 0, 1));
        }
        for (int t = 0; t < 301; ++t)
            for (int k = 0; k < 3; ++k) idx.push_back(uint32_t(rng.below(200)));
        auto mesh = make<Mesh>();
        mesh->set(pos, nrm, idx);
        for (uint32_t per : {1u, 7u, 32u, 1000u}) {
            const TriangleClusters tc(*mesh, per);
            ASSERT_EQ(tc.size(), (301 + per - 1) / per);
            for (uint32_t t = 0; t < 301; ++t) {
                const TriangleClusters::Bounds& b = tc[t / per];
                for (int k = 0; k < 3; ++k) {
                    const vec3 p = pos[idx[t * 3 + uint32_t(k)]];
                    for (int a = 0; a < 3; ++a) {
                        EXPECT_GE(p[a], b.centre[a] - b.half[a]) << "mesh " << m << " per " << per << " tri " << t;
                        EXPECT_LE(p[a], b.centre[a] + b.half[a]) << "mesh " << m << " per " << per << " tri " << t;
                    }
                }
            }
        }
    }
}

TEST(TriangleClusters, RefusesClusterSizesOutOfRangeAndHasNoClustersForNonFiniteMeshes) {
    const ref_ptr<Mesh> m = strip(0, 1, 4);
    EXPECT_THROW(TriangleClusters(*m, 0), std::invalid_argument);
    EXPECT_THROW(TriangleClusters(*m, 65537), std::invalid_argument);
    auto bad = make<Mesh>();
    bad->set({vec3(0), vec3(1, 0, 0), vec3(NAN, 0, 0)}, {}, {0, 1, 2});
    const TriangleClusters tc(*bad, 1);
    EXPECT_TRUE(tc.empty());
    std::vector<IndexRange> out;
    uint64_t tested = 0, rejected = 0;
    EXPECT_EQ(tc.keepInViewport(dmat4(1.0), dmat4(1.0), out, tested, rejected), 1u);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].first, 0u);
    EXPECT_EQ(out[0].count, 3u);
}

TEST(TriangleClusters, AStripHalfOffScreenKeepsTheClustersThatReachTheViewport) {
    // 40 quads of 1 m from x = -30.5 to 9.5; the viewport reaches x = -10, so quads 20..39 are on screen and
    // quad 19 ([-11.5, -10.5]) is not.
    const Camera cam = topDown();
    const ref_ptr<Mesh> m = strip(-30.5, 9.5, 40);
    for (uint32_t per : {1u, 2u, 8u, 80u}) {
        const TriangleClusters tc(*m, per);
        std::vector<IndexRange> out;
        uint64_t tested = 0, rejected = 0;
        const uint32_t kept = tc.keepInViewport(viewProj(cam), model(cam, dvec3(0)), out, tested, rejected);
        // Whole clusters: the first kept one is the one holding triangle 40 (quad 20's first).
        const uint32_t firstKept = (40 / per) * per;
        EXPECT_EQ(kept, 80 - firstKept) << per;
        EXPECT_EQ(tested, tc.size());
        EXPECT_EQ(rejected, firstKept / per);
        ASSERT_EQ(out.size(), 1u) << "adjacent clusters make one range";
        EXPECT_EQ(out[0].first, firstKept * 3);
        EXPECT_EQ(out[0].count, (80 - firstKept) * 3);
    }
    // Per triangle, the paper's test agrees: 40 triangles reach the viewport.
    EXPECT_EQ(TriangleClusters::keepTrianglesNaive(*m, viewProj(cam), model(cam, dvec3(0))), 40u);
    // Moved off screen altogether (beyond the right edge, the top, the bottom): nothing kept.
    for (const dvec3& at : {dvec3(41, 0, 0), dvec3(10, 11, 0), dvec3(10, -11, 0)}) {
        const TriangleClusters tc(*m, 4);
        std::vector<IndexRange> out;
        uint64_t tested = 0, rejected = 0;
        EXPECT_EQ(tc.keepInViewport(viewProj(cam), model(cam, at), out, tested, rejected), 0u);
        EXPECT_TRUE(out.empty());
    }
}

TEST(TriangleClusters, BoxesAcrossTheNearPlaneAreKeptAndThoseBehindTheEyeBeyondASideAreNot) {
    // A strip standing along the view axis, from behind the eye (z = 20) to in front of it (z = 0), at x = 0:
    // it crosses the near plane and the eye's plane, and is in view: kept, in one cluster or per triangle.
    const Camera cam = topDown();
    auto vertical = make<Mesh>();
    vertical->set({vec3(-1, 0, 0), vec3(1, 0, 0), vec3(-1, 0, 20), vec3(1, 0, 20)}, {}, {0, 1, 3, 0, 3, 2});
    for (uint32_t per : {1u, 2u}) {
        const TriangleClusters tc(*vertical, per);
        std::vector<IndexRange> out;
        uint64_t tested = 0, rejected = 0;
        EXPECT_EQ(tc.keepInViewport(viewProj(cam), model(cam, dvec3(0)), out, tested, rejected), 2u);
        EXPECT_EQ(rejected, 0u);
    }
    // The same crossing the near plane but 30 m to the side: outside the left plane everywhere in front of the
    // eye and behind it too (x < -w holds for w < 0 where x < -w): dropped, as nothing of it is seen.
    {
        const TriangleClusters tc(*vertical, 2);
        std::vector<IndexRange> out;
        uint64_t tested = 0, rejected = 0;
        EXPECT_EQ(tc.keepInViewport(viewProj(cam), model(cam, dvec3(-30, 0, 0)), out, tested, rejected), 0u);
    }
    // Wholly behind the eye, straight behind it (z = 12..30): x + w < 0 for every point since w < 0 and
    // |x| is small: dropped.
    {
        const TriangleClusters tc(*vertical, 2);
        std::vector<IndexRange> out;
        uint64_t tested = 0, rejected = 0;
        EXPECT_EQ(tc.keepInViewport(viewProj(cam), model(cam, dvec3(0, 0, 12)), out, tested, rejected), 0u);
    }
}

TEST(TriangleClusters, NeverDropsATriangleThePerTriangleTestKeeps) {
    // Random triangles in front of random cameras (every vertex in front of the eye): per-cluster rejection of
    // size 1 drops a triangle only when the paper's projected rectangle misses the viewport.
    scenes::Rng rng(11);
    const Box bounds{dvec3(-50), dvec3(50)};
    uint64_t dropped = 0, checked = 0;
    for (int k = 0; k < 200; ++k) {
        const Camera cam = scenes::randomCamera(rng, bounds, k, 320, 240);
        std::vector<vec3> pos;
        std::vector<uint32_t> idx;
        for (int t = 0; t < 100; ++t) {
            const dvec3 c(rng.uniform(-60, 60), rng.uniform(-60, 60), rng.uniform(-60, 60));
            for (int v = 0; v < 3; ++v) {
                idx.push_back(uint32_t(pos.size()));
                pos.push_back(vec3(c + dvec3(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-5, 5))));
            }
        }
        auto mesh = make<Mesh>();
        mesh->set(pos, {}, idx);
        const TriangleClusters tc(*mesh, 1);
        const dmat4 vp = viewProj(cam), mm = model(cam, dvec3(0));
        std::vector<IndexRange> out;
        uint64_t tested = 0, rejected = 0;
        tc.keepInViewport(vp, mm, out, tested, rejected);
        std::vector<bool> kept(100, false);
        for (const IndexRange& r : out)
            for (uint32_t i = r.first / 3; i < (r.first + r.count) / 3; ++i) kept[i] = true;
        for (uint32_t t = 0; t < 100; ++t) {
            const dmat4 clip = vp * mm;
            bool front = true;
            for (uint32_t v = 0; v < 3; ++v) front = front && (clip * dvec4(dvec3(pos[t * 3 + v]), 1.0)).w > 0.0;
            if (!front) continue;  // the paper's test keeps these whatever they are
            auto one = make<Mesh>();
            one->set({pos[t * 3], pos[t * 3 + 1], pos[t * 3 + 2]}, {}, {0, 1, 2});
            if (TriangleClusters::keepTrianglesNaive(*one, vp, mm) == 1 && !kept[t])
                ADD_FAILURE() << "view " << k << " triangle " << t << " dropped but its rectangle meets the viewport";
            dropped += !kept[t];
            ++checked;
        }
    }
    EXPECT_GT(checked, 5000u);
    EXPECT_GT(dropped, 1000u) << "the test must reject something to mean anything";
}

TEST(TriangleClusters, CacheRebuildsWhenTheMeshOrTheClusterSizeChanges) {
    TriangleClusters::Cache cache;
    ref_ptr<Mesh> m = strip(0, 10, 10);
    EXPECT_EQ(cache.get(*m, 4).size(), 5u);
    EXPECT_EQ(cache.get(*m, 10).size(), 2u);
    const ref_ptr<Mesh> other = strip(0, 10, 40);
    m->set(other->positions(), other->normals(), [&] {
        std::vector<uint32_t> idx;
        for (uint32_t i = 0; i < other->indexCount(); ++i) idx.push_back(other->index(i));
        return idx;
    }());
    EXPECT_EQ(cache.get(*m, 10).size(), 8u);
    EXPECT_EQ(cache.size(), 1u);
    for (int f = 0; f < 600; ++f) cache.nextFrame();
    EXPECT_EQ(cache.size(), 0u);
}

namespace {
struct Culled {
    DrawList list;
    CullStats stats;
};
Culled cullStrip(const ref_ptr<Mesh>& mesh, const CullSettings& set) {
    auto root = make<Group>();
    auto t = make<Transform>();
    t->setTranslation(dvec3(0));
    t->addChild(make<Geometry>(mesh, make<Material>()));
    root->addChild(t);
    // A second geometry fully on screen: drawn whole, no part.
    auto t2 = make<Transform>();
    t2->setTranslation(dvec3(0, 5, 0));
    t2->addChild(make<Geometry>(strip(-1, 1, 2), make<Material>()));
    root->addChild(t2);
    Scene scene(root);
    scene.update();
    Culled c;
    CullTraversal().cull(scene, topDown(), set, c.list, c.stats);
    return c;
}
}  // namespace

TEST(ScreenRectCull, DrawsAStripHalfOffScreenAsOneRangeAndCountsWhatItLeftOut) {
    const ref_ptr<Mesh> mesh = strip(-30.5, 9.5, 40);
    CullSettings set;
    set.screenRect = true;
    set.screenRectTriangles = 8;
    const Culled c = cullStrip(mesh, set);
    ASSERT_EQ(c.list.items.size(), 2u);
    ASSERT_EQ(c.list.parts.size(), 1u);
    const DrawList::Part& p = c.list.parts[0];
    EXPECT_EQ(c.list.items[p.item].mesh, mesh.get());
    ASSERT_EQ(p.count, 1u);
    EXPECT_EQ(c.list.ranges[p.first].first, 40u * 3);
    EXPECT_EQ(c.list.ranges[p.first].count, 40u * 3);
    EXPECT_EQ(c.stats.culledScreenRectTriangles, 40u);
    EXPECT_EQ(c.stats.culledScreenRectClusters, 5u);
    EXPECT_EQ(c.stats.triangles, 40u + 4u);
    // Off, or the reference strategy: whole meshes.
    set.screenRect = false;
    const Culled off = cullStrip(mesh, set);
    EXPECT_TRUE(off.list.parts.empty());
    EXPECT_EQ(off.stats.triangles, 84u);
    set.screenRect = true;
    set.strategy = CullStrategy::None;
    const Culled none = cullStrip(mesh, set);
    EXPECT_TRUE(none.list.parts.empty());
    EXPECT_EQ(none.stats.screenRectClusters, 0u);
}

TEST(ScreenRectCull, AGeometryWhoseClustersAreAllOffScreenIsNotDrawn) {
    // Centre-box keeps the strip (its centre is in the frustum's box) though every triangle is off screen: the
    // strip runs from x = -60 to 60 at y = 15, above the top edge (the viewport reaches y = 10 at z = 0).
    auto mesh = make<Mesh>();
    const ref_ptr<Mesh> s = strip(-60, 60, 12);
    std::vector<vec3> pos = s->positions();
    for (vec3& p : pos) p.y += 15.0f;
    std::vector<uint32_t> idx;
    for (uint32_t i = 0; i < s->indexCount(); ++i) idx.push_back(s->index(i));
    mesh->set(pos, s->normals(), idx);
    CullSettings set;
    set.strategy = CullStrategy::CenterBox;
    set.screenRect = true;
    set.screenRectTriangles = 4;
    const Culled c = cullStrip(mesh, set);
    EXPECT_EQ(c.stats.culledCenterBox, 0u);
    EXPECT_EQ(c.stats.culledScreenRectGeometries, 1u);
    EXPECT_EQ(c.stats.culledScreenRectTriangles, 24u);
    ASSERT_EQ(c.list.items.size(), 1u);
    EXPECT_NE(c.list.items[0].mesh, mesh.get());
    EXPECT_TRUE(c.list.parts.empty());
}

TEST(ScreenRectCull, RefusesClusterSizesOutOfRange) {
    CullSettings set;
    set.screenRect = true;
    set.screenRectTriangles = 0;
    try {
        cullStrip(strip(0, 1, 1), set);
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()), "CullTraversal::cull(): screenRectTriangles 0 is not in 1..65536");
    }
}

TEST(TriangleClusters, PropertyARejectedBoxHasNoPointInTheViewAndABoxSeenAtItsCentreIsKept) {
    // 100,000 cases: 1,000 boxes (one 12-triangle cluster each, up to 40 m across, many across the near plane or
    // around the eye) under 100 random cameras of every kind. A rejected box: none of its corners nor 8 random
    // points of it is inside the clip volume (-w <= x, y <= w, w > 0). A box whose centre is inside it: kept.
    scenes::Rng rng(2026);
    const Box bounds{dvec3(-60), dvec3(60)};
    std::vector<vec3> pos;
    std::vector<uint32_t> idx;
    std::vector<dvec3> lo, hi;
    for (int b = 0; b < 1000; ++b) {
        const dvec3 c(rng.uniform(-80, 80), rng.uniform(-80, 80), rng.uniform(-80, 80));
        const dvec3 h(rng.uniform(0.01, 20), rng.uniform(0.01, 20), rng.uniform(0.01, 20));
        const ref_ptr<Mesh> box = makeBoxMesh(c - h, c + h, 1);
        const uint32_t base = uint32_t(pos.size());
        pos.insert(pos.end(), box->positions().begin(), box->positions().end());
        for (uint32_t i = 0; i < box->indexCount(); ++i) idx.push_back(base + box->index(i));
        lo.push_back(dvec3(box->box().min));
        hi.push_back(dvec3(box->box().max));
    }
    auto mesh = make<Mesh>();
    mesh->set(pos, {}, idx);
    const TriangleClusters tc(*mesh, 12);
    ASSERT_EQ(tc.size(), 1000u);
    uint64_t rejectedTotal = 0, keptSeen = 0;
    for (int k = 0; k < 100; ++k) {
        const Camera cam = scenes::randomCamera(rng, bounds, k, 320, 240);
        const dmat4 vp = viewProj(cam), mm = model(cam, dvec3(0)), clip = vp * mm;
        std::vector<IndexRange> out;
        uint64_t tested = 0, rejected = 0;
        tc.keepInViewport(vp, mm, out, tested, rejected);
        std::vector<bool> kept(1000, false);
        for (const IndexRange& r : out)
            for (uint32_t t = r.first / 3; t < (r.first + r.count) / 3; ++t) kept[t / 12] = true;
        auto inView = [&](const dvec3& p) {
            const dvec4 q = clip * dvec4(p, 1.0);
            return q.w > 0.0 && std::abs(q.x) <= q.w && std::abs(q.y) <= q.w;
        };
        for (uint32_t b = 0; b < 1000; ++b) {
            if (kept[b]) {
                keptSeen += inView(0.5 * (lo[b] + hi[b]));
                continue;
            }
            ++rejectedTotal;
            ASSERT_FALSE(inView(0.5 * (lo[b] + hi[b]))) << "view " << k << " box " << b << " centre";
            for (int c = 0; c < 8; ++c) {
                const dvec3 corner((c & 1) ? hi[b].x : lo[b].x, (c & 2) ? hi[b].y : lo[b].y,
                                   (c & 4) ? hi[b].z : lo[b].z);
                ASSERT_FALSE(inView(corner)) << "view " << k << " box " << b << " corner " << c;
            }
            for (int s = 0; s < 8; ++s) {
                const dvec3 p(rng.uniform(lo[b].x, hi[b].x), rng.uniform(lo[b].y, hi[b].y),
                              rng.uniform(lo[b].z, hi[b].z));
                ASSERT_FALSE(inView(p)) << "view " << k << " box " << b << " point " << s;
            }
        }
    }
    // Not vacuous: both outcomes are common.
    EXPECT_GT(rejectedTotal, 20000u);
    EXPECT_GT(keptSeen, 10000u);
}
