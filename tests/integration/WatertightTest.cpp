// Watertightness: 1,000,000 rays aimed exactly at the shared edges and vertices of closed meshes (a
// subdivided icosahedron, a bumpy one, a box with split faces whose edges repeat their vertices), placed
// with rotation and non-uniform scale, near the origin and 10,000 km from it: none passes through.
#include "nodes/Geometry.h"
#include "nodes/Transform.h"
#include "sg/intersect/IntersectTraversal.h"
#include "testbed/RandomScene.h"

#include <gtest/gtest.h>

#include <map>

using namespace sg;

namespace {
// Icosahedron subdivided `levels` times, vertices shared, radius scaled per vertex by `bump`.
ref_ptr<Mesh> icosphere(int levels, scenes::Rng* bump) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<dvec3> v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    std::vector<uint32_t> f = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                               4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
                               6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
    for (auto& p : v) p = glm::normalize(p);
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
        auto m = [&](uint32_t a, uint32_t b) {
            const auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            v.push_back(glm::normalize(v[a] + v[b]));
            return mid[key] = uint32_t(v.size() - 1);
        };
        std::vector<uint32_t> g;
        for (size_t k = 0; k < f.size(); k += 3) {
            const uint32_t a = f[k], b = f[k + 1], c = f[k + 2], ab = m(a, b), bc = m(b, c), ca = m(c, a);
            g.insert(g.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        f = g;
    }
    std::vector<vec3> pos, nrm;
    for (const auto& p : v) {
        const double s = bump ? bump->uniform(0.8, 1.2) : 1.0;
        pos.push_back(vec3(p * s));
        nrm.push_back(vec3(p));
    }
    auto mesh = make<Mesh>();
    mesh->set(pos, nrm, f);
    return mesh;
}

}  // namespace

TEST(Watertight, RaysThroughSharedEdgesAndVerticesNeverPassThrough) {
    scenes::Rng rng(20261122);
    // Convex, bumpy (star-shaped about its centre), and a box whose faces repeat the vertices of its edges.
    const std::vector<ref_ptr<Mesh>> cases = {icosphere(3, nullptr), icosphere(3, &rng),
                                              makeBoxMesh(dvec3(-1, -0.5, -2), dvec3(1, 0.5, 2), 4)};
    constexpr int kRays = 1000000;
    int rays = 0, escaped = 0;
    for (int far = 0; far < 2; ++far) {
        for (size_t ci = 0; ci < cases.size(); ++ci) {
            const Mesh& mesh = *cases[ci];
            const dvec3 offset = far ? dvec3(1e7, -4e6, 3e5) : dvec3(0.0);
            dmat4 m =
                glm::translate(dmat4(1.0), offset + dvec3(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-5, 5)));
            m = glm::rotate(m, rng.uniform(0, 6.283), glm::normalize(dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), 1)));
            m = glm::scale(m, dvec3(rng.uniform(0.5, 3), rng.uniform(0.5, 3), rng.uniform(0.5, 3)));
            auto root = make<Group>();
            auto xf = make<Transform>(m);
            xf->addChild(make<Geometry>(cases[ci], make<Material>()));
            root->addChild(xf);
            Scene scene(root);
            scene.update();
            IntersectTraversal it;
            const int n = kRays / 6 + (far == 1 && ci == 2 ? kRays % 6 : 0);
            for (int k = 0; k < n; ++k, ++rays) {
                // Target: a vertex, or a point on an edge, of a random triangle (edges of a closed mesh are shared).
                const uint32_t tri = uint32_t(rng.below(int(mesh.triangleCount())));
                const int e = rng.below(3);
                const dvec3 a(mesh.positions()[mesh.index(3 * tri + e)]),
                    b(mesh.positions()[mesh.index(3 * tri + (e + 1) % 3)]);
                const dvec3 local = rng.chance(0.25) ? a : a + (b - a) * rng.uniform(0, 1);
                const dvec3 target = dvec3(m * dvec4(local, 1.0));
                // Through the target and an interior point q: from q outward (the ray leaves the solid at
                // the target or before), or from beyond the target inward (it enters the solid there or
                // before). Rays that only graze a corner need not hit, so none are aimed that way.
                const bool convex = ci != 1;
                const dvec3 qLocal =
                    convex ? dvec3(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3)) : dvec3(0.0);
                const dvec3 q = dvec3(m * dvec4(qLocal, 1.0));
                const dvec3 origin = (k % 2 == 0 && convex) ? target + (target - q) * rng.uniform(0.5, 20) : q;
                Hit h;
                const bool hit = it.intersect(scene, Ray{origin, target - origin}, {}, h);
                // The target lies on the surface at t = 1: a hit at or before it, up to the rounding of
                // the target's and the origin's own coordinates (a few ulps of 10,000 km far out).
                const double coords = glm::length(glm::abs(target) + glm::abs(origin));
                const double slack = 8.0 * 2.220446049250313e-16 * coords / glm::length(target - origin);
                if (!hit || h.t > 1.0 + slack) {
                    if (++escaped <= 5)
                        ADD_FAILURE() << "ray passed through: case " << ci << (far ? " far" : " near") << " triangle "
                                      << tri << " edge " << e << " origin (" << origin.x << ", " << origin.y << ", "
                                      << origin.z << ") target (" << target.x << ", " << target.y << ", " << target.z
                                      << ")" << (hit ? " hit later at t = " + std::to_string(h.t) : " no hit");
                }
            }
        }
    }
    EXPECT_EQ(rays, kRays);
    EXPECT_EQ(escaped, 0);
}
