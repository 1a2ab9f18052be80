#include "nodes/Geometry.h"
#include "nodes/LOD.h"
#include "sg/build/LodGenerator.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <tuple>

using namespace sg;

namespace {

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

// A UV sphere of radius r: `seg` meridians, `rings` parallels. The seam meridian and the pole rows are
// duplicated vertices (same position, different UV), as a textured sphere has them; outward normals.
ref_ptr<Mesh> makeSphere(float r, int seg, int rings) {
    std::vector<vec3> pos, nrm;
    std::vector<vec2> uv;
    std::vector<uint32_t> idx;
    const double pi = 3.14159265358979323846;
    for (int j = 0; j <= rings; ++j)
        for (int i = 0; i <= seg; ++i) {
            const double u = double(i) / seg, v = double(j) / rings;
            const double th = u * 2 * pi, ph = v * pi;
            const vec3 n(float(std::sin(ph) * std::cos(th)), float(std::cos(ph)), float(std::sin(ph) * std::sin(th)));
            pos.push_back(n * r);
            nrm.push_back(n);
            uv.push_back(vec2(float(u), float(v)));
        }
    for (int j = 0; j < rings; ++j)
        for (int i = 0; i < seg; ++i) {
            const uint32_t a = uint32_t(j * (seg + 1) + i), b = a + 1, c = a + uint32_t(seg + 1), d = c + 1;
            if (j > 0) idx.insert(idx.end(), {a, d, b});  // none at the poles: they would be degenerate
            if (j < rings - 1) idx.insert(idx.end(), {a, c, d});
        }
    auto m = make<Mesh>();
    m->set(std::move(pos), std::move(nrm), std::move(idx), std::move(uv));
    return m;
}

using Vertex = std::tuple<float, float, float, float, float, float, float, float>;
Vertex vertexOf(const Mesh& m, uint32_t v) {
    const vec3 p = m.positions()[v], n = m.normals()[v];
    const vec2 t = m.uvs()[v];
    return {p.x, p.y, p.z, n.x, n.y, n.z, t.x, t.y};
}

// The largest distance between the sphere of radius r and the level's flat triangles: the sagitta at the
// point of each triangle nearest the centre (its centroid is near enough for this comparison).
double sphereDeviation(const Mesh& m, double r) {
    double worst = 0.0;
    for (uint32_t t = 0; t < m.triangleCount(); ++t) {
        const dvec3 c = (dvec3(m.positions()[m.index(3 * t)]) + dvec3(m.positions()[m.index(3 * t + 1)]) +
                         dvec3(m.positions()[m.index(3 * t + 2)])) /
                        3.0;
        worst = std::max(worst, r - glm::length(c));
    }
    return worst;
}

const std::vector<float> kRatios = {0.5f, 0.25f, 0.1f};

}  // namespace

TEST(LodGenerator, SphereLevelsReachTheirTargetsWithGrowingErrors) {
    const float radius = 10.0f;
    auto sphere = makeSphere(radius, 64, 32);
    const uint32_t full = sphere->triangleCount();
    ASSERT_EQ(full, 64u * 30u * 2u + 2u * 64u);
    const auto levels = generateLevels(sphere, kRatios);
    ASSERT_EQ(levels.size(), 4u);

    EXPECT_EQ(levels[0].mesh.get(), sphere.get());  // the original itself, not a copy
    EXPECT_EQ(levels[0].error, 0.0f);
    EXPECT_EQ(levels[0].triangles, full);

    std::set<Vertex> original;
    for (uint32_t v = 0; v < sphere->positions().size(); ++v) original.insert(vertexOf(*sphere, v));
    for (size_t i = 1; i < levels.size(); ++i) {
        const LodLevel& l = levels[i];
        SCOPED_TRACE("level " + std::to_string(i));
        const double target = double(kRatios[i - 1]) * full;
        EXPECT_EQ(l.triangles, l.mesh->triangleCount());
        EXPECT_LT(l.triangles, levels[i - 1].triangles);
        EXPECT_LE(l.triangles, target * 1.02 + 1);  // the topology-keeping simplifier gets there on a sphere
        EXPECT_GE(l.triangles, target * 0.8);
        EXPECT_TRUE(std::isfinite(l.error));
        EXPECT_GT(l.error, levels[i - 1].error);  // a sphere has no flat part: each reduction costs
        // Absolute, in the mesh's units: within a factor of 3 of how far the flat triangles lie inside the
        // sphere (a relative error would be 20 times smaller here: the sphere is 20 units across).
        const double dev = sphereDeviation(*l.mesh, radius);
        EXPECT_GT(l.error, dev / 3.0) << "measured deviation " << dev;
        EXPECT_LT(l.error, dev * 3.0) << "measured deviation " << dev;
        EXPECT_LT(l.error, 0.1f * radius);

        // Compacted to the vertices used, each an original vertex with its own normal and UV.
        ASSERT_EQ(l.mesh->normals().size(), l.mesh->positions().size());
        ASSERT_EQ(l.mesh->uvs().size(), l.mesh->positions().size());
        EXPECT_TRUE(l.mesh->colors().empty());
        EXPECT_LT(l.mesh->positions().size(), levels[i - 1].mesh->positions().size());
        std::vector<bool> used(l.mesh->positions().size(), false);
        for (uint32_t k = 0; k < l.mesh->indexCount(); ++k) used[l.mesh->index(k)] = true;
        EXPECT_EQ(std::count(used.begin(), used.end(), false), 0);
        size_t foreign = 0;
        for (uint32_t v = 0; v < l.mesh->positions().size(); ++v) foreign += original.count(vertexOf(*l.mesh, v)) == 0;
        EXPECT_EQ(foreign, 0u);
        // So every level lies within the original's bound.
        EXPECT_TRUE(l.mesh->validBound());
        for (int a = 0; a < 3; ++a) {
            EXPECT_GE(l.mesh->box().min[a], sphere->box().min[a]);
            EXPECT_LE(l.mesh->box().max[a], sphere->box().max[a]);
        }
    }
}

TEST(LodGenerator, BoxFacesKeepTheirNormalsAndOutline) {
    // Each face has its own vertices (normals differ at the edges): the edges are seams and must hold.
    const dvec3 lo(-2, -1, -3), hi(2, 1, 3);
    auto box = makeBoxMesh(lo, hi, 16);
    ASSERT_EQ(box->triangleCount(), 6u * 16u * 16u * 2u);
    const auto levels = generateLevels(box, {0.3f, 0.05f});
    ASSERT_EQ(levels.size(), 3u);
    const dvec3 size = hi - lo;
    for (size_t i = 1; i < levels.size(); ++i) {
        const Mesh& m = *levels[i].mesh;
        SCOPED_TRACE("level " + std::to_string(i));
        EXPECT_LT(levels[i].triangles, levels[i - 1].triangles);
        EXPECT_LE(levels[i].triangles, (i == 1 ? 0.3 : 0.05) * box->triangleCount() * 1.02 + 1);
        EXPECT_LT(levels[i].error, 1e-3f * 6.0f);  // flat faces: next to nothing of the box's 6 units
        ASSERT_EQ(m.normals().size(), m.positions().size());
        ASSERT_EQ(m.uvs().size(), m.positions().size());
        // Every triangle stays in one face: its three normals are that face's. Summed per face, the signed
        // areas are the face's area: the faces are still covered up to their edges (no hole, no overlap
        // left over; meshoptimizer 0.18 may fold a sliver here and there, which this sum tolerates).
        std::map<std::tuple<float, float, float>, double> area;
        for (uint32_t t = 0; t < m.triangleCount(); ++t) {
            const uint32_t a = m.index(3 * t), b = m.index(3 * t + 1), c = m.index(3 * t + 2);
            const vec3 n = m.normals()[a];
            ASSERT_EQ(m.normals()[b], n) << "triangle " << t;
            ASSERT_EQ(m.normals()[c], n) << "triangle " << t;
            const dvec3 pa(m.positions()[a]), pb(m.positions()[b]), pc(m.positions()[c]);
            area[{n.x, n.y, n.z}] += 0.5 * glm::dot(glm::cross(pb - pa, pc - pa), dvec3(n));
        }
        ASSERT_EQ(area.size(), 6u);
        for (const auto& [n, a] : area) {
            const double expected = std::abs(std::get<0>(n)) > 0.5f   ? size.y * size.z
                                    : std::abs(std::get<1>(n)) > 0.5f ? size.x * size.z
                                                                      : size.x * size.y;
            EXPECT_NEAR(a, expected, 1e-4 * expected);
        }
        EXPECT_EQ(m.box().min, box->box().min);
        EXPECT_EQ(m.box().max, box->box().max);
    }
}

TEST(LodGenerator, SeamsEverywhereFallBackToClustering) {
    // 125 separate cubes, each with a seam at every vertex: the topology-keeping simplifier can remove
    // nothing, so the levels come from clustering, and counts never grow from one level to the next.
    auto soup = make<Mesh>();
    {
        std::vector<vec3> pos, nrm;
        std::vector<vec2> uv;
        std::vector<uint32_t> idx;
        for (int x = 0; x < 5; ++x)
            for (int y = 0; y < 5; ++y)
                for (int z = 0; z < 5; ++z) {
                    auto c = makeBoxMesh(dvec3(x, y, z) * 3.0, dvec3(x, y, z) * 3.0 + dvec3(1), 1);
                    const uint32_t base = uint32_t(pos.size());
                    pos.insert(pos.end(), c->positions().begin(), c->positions().end());
                    nrm.insert(nrm.end(), c->normals().begin(), c->normals().end());
                    uv.insert(uv.end(), c->uvs().begin(), c->uvs().end());
                    for (uint32_t k = 0; k < c->indexCount(); ++k) idx.push_back(base + c->index(k));
                }
        soup->set(std::move(pos), std::move(nrm), std::move(idx), std::move(uv));
    }
    std::set<Vertex> original;
    for (uint32_t v = 0; v < soup->positions().size(); ++v) original.insert(vertexOf(*soup, v));
    const auto levels = generateLevels(soup, {0.5f, 0.2f, 0.01f});
    ASSERT_EQ(levels.size(), 4u);
    EXPECT_LT(levels[1].triangles, soup->triangleCount() * 0.55);
    EXPECT_GT(levels[1].error, 0.0f);
    for (size_t i = 1; i < levels.size(); ++i) {
        SCOPED_TRACE("level " + std::to_string(i));
        EXPECT_EQ(levels[i].triangles, levels[i].mesh->triangleCount());
        EXPECT_GE(levels[i].triangles, 1u);
        EXPECT_LE(levels[i].triangles, levels[i - 1].triangles);
        EXPECT_GE(levels[i].error, levels[i - 1].error);
        EXPECT_LT(levels[i].error, 15.0f);  // less than the soup's size
        ASSERT_EQ(levels[i].mesh->normals().size(), levels[i].mesh->positions().size());
        ASSERT_EQ(levels[i].mesh->uvs().size(), levels[i].mesh->positions().size());
        for (uint32_t v = 0; v < levels[i].mesh->positions().size(); ++v)
            ASSERT_EQ(original.count(vertexOf(*levels[i].mesh, v)), 1u) << "vertex " << v;
    }
}

TEST(LodGenerator, ThirtyTwoBitInputGivesCompactLevels) {
    auto box = makeBoxMesh(dvec3(-1), dvec3(1), 106);  // 6 * 107^2 vertices: past 16-bit indices
    ASSERT_FALSE(box->indices32().empty());
    const auto levels = generateLevels(box, {0.01f});
    ASSERT_EQ(levels.size(), 2u);
    const Mesh& m = *levels[1].mesh;
    EXPECT_LE(m.triangleCount(), box->triangleCount() / 100 + 1);
    EXPECT_GT(m.triangleCount(), 0u);
    EXPECT_FALSE(m.indices16().empty());  // the few vertices left fit 16-bit indices again
    EXPECT_EQ(m.box().min, box->box().min);
    EXPECT_EQ(m.box().max, box->box().max);
}

TEST(LodGenerator, TinyMeshReportsWhatWasReached) {
    // 12 triangles whose every vertex is a seam corner: the topology-keeping simplifier cannot collapse
    // anything. Whatever is used, the count reported is the level's, with at least one triangle.
    auto cube = makeBoxMesh(dvec3(-1), dvec3(1), 1);
    const auto levels = generateLevels(cube, {0.5f, 0.1f});
    ASSERT_EQ(levels.size(), 3u);
    for (size_t i = 1; i < levels.size(); ++i) {
        SCOPED_TRACE("level " + std::to_string(i));
        EXPECT_EQ(levels[i].triangles, levels[i].mesh->triangleCount());
        EXPECT_GE(levels[i].triangles, 1u);
        EXPECT_LE(levels[i].triangles, levels[i - 1].triangles);
        EXPECT_TRUE(std::isfinite(levels[i].error));
        EXPECT_GE(levels[i].error, levels[i - 1].error);
    }
}

TEST(LodGenerator, MaxErrorHoldsTheSimplifierBack) {
    auto sphere = makeSphere(10.0f, 64, 32);
    const auto free = generateLevels(sphere, {0.1f});
    const float limit = free[1].error * 0.25f;
    const auto held = generateLevels(sphere, {0.1f}, limit);
    EXPECT_LE(held[1].error, limit * 1.001f);
    EXPECT_GT(held[1].triangles, free[1].triangles * 2);
}

TEST(LodGenerator, BadInputIsRefusedByName) {
    auto sphere = makeSphere(1.0f, 16, 8);
    auto msg = [&](std::vector<float> r, float maxError = INFINITY) {
        return errorOf([&] { generateLevels(sphere, r, maxError); });
    };
    EXPECT_EQ(msg({1.0f}), "generateLevels(): ratios[0] = 1.000000 is not in (0, 1)");
    EXPECT_EQ(msg({0.5f, 0.0f}), "generateLevels(): ratios[1] = 0.000000 is not in (0, 1)");
    EXPECT_EQ(msg({-0.5f}), "generateLevels(): ratios[0] = -0.500000 is not in (0, 1)");
    EXPECT_EQ(msg({NAN}), "generateLevels(): ratios[0] = nan is not in (0, 1)");
    EXPECT_EQ(msg({0.5f, 0.5f}),
              "generateLevels(): ratios[1] = 0.500000 is not below ratios[0] = 0.500000 (ratios must decrease)");
    EXPECT_EQ(msg({0.25f, 0.5f}),
              "generateLevels(): ratios[1] = 0.500000 is not below ratios[0] = 0.250000 (ratios must decrease)");
    EXPECT_EQ(msg({0.5f}, -1.0f), "generateLevels(): maxError -1.000000 is negative or NaN");
    EXPECT_EQ(msg({0.5f}, NAN), "generateLevels(): maxError nan is negative or NaN");
    EXPECT_EQ(errorOf([&] { generateLevels(nullptr, {0.5f}); }), "generateLevels(): mesh is null");
    auto empty = make<Mesh>();
    empty->set({vec3(0), vec3(1), vec3(2)}, {}, {});
    EXPECT_EQ(errorOf([&] { generateLevels(empty, {0.5f}); }), "generateLevels(): mesh has no triangles");
    auto bad = make<Mesh>();
    bad->set({vec3(0), vec3(1, 0, 0), vec3(0, NAN, 0)}, {}, {0, 1, 2});
    EXPECT_EQ(errorOf([&] { generateLevels(bad, {0.5f}); }),
              "generateLevels(): positions[2] = (0.000000, nan, 0.000000) is not finite");
    // makeLod names itself, for its own parameters and for the levels'.
    auto mat = make<Material>();
    EXPECT_EQ(errorOf([&] { makeLod(sphere, mat, {0.5f}, 0.0); }),
              "makeLod(): pixelError 0.000000 is not positive and finite");
    EXPECT_EQ(errorOf([&] { makeLod(sphere, mat, {0.5f}, 1.0, -5.0); }),
              "makeLod(): pixelsPerRadian -5.000000 is not positive and finite");
    EXPECT_EQ(errorOf([&] { makeLod(sphere, mat, {0.5f}, 1.0, INFINITY); }),
              "makeLod(): pixelsPerRadian inf is not positive and finite");
    EXPECT_EQ(errorOf([&] { makeLod(sphere, mat, {2.0f}); }), "makeLod(): ratios[0] = 2.000000 is not in (0, 1)");
    EXPECT_EQ(errorOf([&] { makeLod(bad, mat, {0.5f}); }),
              "makeLod(): positions[2] = (0.000000, nan, 0.000000) is not finite");
}

TEST(LodGenerator, MakeLodShowsEachLevelWhereItsErrorIsBelowThePixelError) {
    auto sphere = makeSphere(10.0f, 64, 32);
    auto mat = make<Material>();
    const double pixelError = 2.0, ppr = 1000.0;
    auto lod = makeLod(sphere, mat, kRatios, pixelError, ppr);
    const auto levels = generateLevels(sphere, kRatios);  // deterministic: the same levels again
    ASSERT_EQ(lod->numChildren(), 4u);
    EXPECT_EQ(lod->mode(), LOD::Mode::Distance);
    EXPECT_EQ(lod->range(0).min, 0.0f);
    EXPECT_EQ(lod->range(3).max, FLT_MAX);
    for (size_t i = 0; i < lod->numChildren(); ++i) {
        SCOPED_TRACE("child " + std::to_string(i));
        ASSERT_EQ(lod->child(i)->kind(), NodeKind::Geometry);
        auto* g = static_cast<Geometry*>(lod->child(i));
        EXPECT_EQ(g->material(), mat.get());
        EXPECT_EQ(g->mesh()->triangleCount(), levels[i].triangles);
        EXPECT_EQ(lod->error(i), levels[i].error);
        if (i == 0) {
            EXPECT_EQ(g->mesh(), sphere.get());
            continue;
        }
        EXPECT_LT(g->mesh()->triangleCount(), static_cast<Geometry*>(lod->child(i - 1))->mesh()->triangleCount());
        EXPECT_GT(lod->error(i), lod->error(i - 1));
        // Contiguous and increasing: one level at every distance.
        EXPECT_EQ(lod->range(i).min, lod->range(i - 1).max);
        EXPECT_GT(lod->range(i).min, lod->range(i - 1).min);
        // The rule: from where level i starts, its error projects to at most pixelError pixels, and it
        // starts no farther than that requires (one float step).
        const double d = lod->range(i).min;
        EXPECT_LE(lod->error(i) * ppr / d, pixelError);
        EXPECT_GT(lod->error(i) * ppr / std::nextafter(float(d), 0.0f), pixelError);
        // The finer level before it is never kept beyond that distance.
        EXPECT_LE(lod->range(i - 1).max, d);
    }
    // Twice the pixel error allowed: every switch twice as near.
    auto coarse = makeLod(sphere, mat, kRatios, 2.0 * pixelError, ppr);
    for (size_t i = 1; i < 4; ++i) EXPECT_NEAR(coarse->range(i).min, lod->range(i).min / 2, lod->range(i).min * 1e-6);
    // No ratios: the mesh alone, at every distance.
    auto single = makeLod(sphere, mat, {});
    ASSERT_EQ(single->numChildren(), 1u);
    EXPECT_EQ(single->range(0).min, 0.0f);
    EXPECT_EQ(single->range(0).max, FLT_MAX);
}

TEST(LodGenerator, FlatLevelsThatCostNothingAreShownFromTheStart) {
    // A flat-faced box loses nothing by simplifying: the coarse level's error is 0, so the full one gets
    // an empty range and the coarse one is shown from distance 0.
    auto box = makeBoxMesh(dvec3(-1), dvec3(1), 8);
    auto lod = makeLod(box, nullptr, {0.2f});
    ASSERT_EQ(lod->numChildren(), 2u);
    EXPECT_LT(lod->error(1), 1e-5f);
    EXPECT_LE(lod->range(1).min, 1e-5f * float(kDefaultPixelsPerRadian));
    EXPECT_EQ(lod->range(0).max, lod->range(1).min);
}

TEST(LOD, ErrorsFollowTheirChildrenLikeRanges) {
    auto lod = make<LOD>();
    std::vector<ref_ptr<Node>> kids;
    for (int i = 0; i < 4; ++i) kids.push_back(make<Group>());
    lod->addChild(kids[0], 0, 10);
    lod->addChild(kids[1], 10, 20);
    EXPECT_EQ(lod->error(0), 0.0f);  // never set: 0
    EXPECT_EQ(lod->error(1), 0.0f);
    lod->setError(1, 0.5f);  // set while the ranges are all inline
    lod->addChild(kids[2], 20, 30);
    lod->setError(2, 1.5f);
    EXPECT_EQ(lod->error(0), 0.0f);
    EXPECT_EQ(lod->error(1), 0.5f);
    EXPECT_EQ(lod->error(2), 1.5f);

    // Inserted: the new child has range [0, far) and error 0; the others move with their children.
    lod->insertChild(1, kids[3]);
    ASSERT_EQ(lod->numChildren(), 4u);
    EXPECT_EQ(lod->child(1), kids[3].get());
    EXPECT_EQ(lod->error(1), 0.0f);
    EXPECT_EQ(lod->error(2), 0.5f);
    EXPECT_EQ(lod->range(2).min, 10.0f);
    EXPECT_EQ(lod->error(3), 1.5f);
    EXPECT_EQ(lod->range(3).min, 20.0f);

    // Removed: the ones after it move back.
    lod->removeChild(size_t(0));
    EXPECT_EQ(lod->error(0), 0.0f);
    EXPECT_EQ(lod->error(1), 0.5f);
    EXPECT_EQ(lod->range(1).min, 10.0f);
    EXPECT_EQ(lod->error(2), 1.5f);
    EXPECT_EQ(lod->range(2).min, 20.0f);
    lod->removeChild(kids[1].get());
    EXPECT_EQ(lod->error(0), 0.0f);
    EXPECT_EQ(lod->error(1), 1.5f);
    EXPECT_EQ(lod->range(1).min, 20.0f);

    // Emptied and refilled: nothing left over.
    lod->removeAllChildren();
    lod->addChild(kids[0], 0, 10);
    EXPECT_EQ(lod->error(0), 0.0f);

    // Refused like the ranges.
    EXPECT_NE(errorOf([&] { lod->setError(1, 1.0f); }).find("LOD::setError(): child 1"), std::string::npos);
    EXPECT_THROW(lod->setError(1, 1.0f), std::out_of_range);
    EXPECT_THROW(lod->error(1), std::out_of_range);
    EXPECT_NE(errorOf([&] { lod->setError(0, -1.0f); }).find("LOD::setError(): LOD child 0: error -1.000000"),
              std::string::npos);
    EXPECT_THROW(lod->setError(0, NAN), std::invalid_argument);
    EXPECT_THROW(lod->setError(0, INFINITY), std::invalid_argument);
    EXPECT_EQ(lod->error(0), 0.0f);
}

TEST(LOD, ErrorsCostNoMemoryUntilSet) {
    // One LOD per city cell: storing errors must not make the node bigger than its ranges made it.
    EXPECT_LE(sizeof(LOD), sizeof(Group) + sizeof(dvec3) + 2 * sizeof(LOD::Range) + sizeof(void*) + 8);
}
