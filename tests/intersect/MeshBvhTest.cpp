// MeshBvh against a loop over every triangle: nearest and all hits of rays and segments, and the triangles
// a box overlaps, on random meshes (degenerate, flat, a single triangle, far from the origin).
#include "sg/intersect/MeshBvh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using namespace sg;

namespace {

using Rng = std::mt19937_64;

double uniform(Rng& g, double a, double b) { return std::uniform_real_distribution<double>(a, b)(g); }
size_t pick(Rng& g, size_t n) { return std::uniform_int_distribution<size_t>(0, n - 1)(g); }

dvec3 inBox(Rng& g, const dvec3& c, double h) {
    return c + dvec3(uniform(g, -h, h), uniform(g, -h, h), uniform(g, -h, h));
}

ref_ptr<Mesh> build(std::vector<vec3> pos, std::vector<uint32_t> idx) {
    auto m = make<Mesh>();
    m->set(std::move(pos), {}, std::move(idx));
    return m;
}

// `n` triangles of about `size` around `centre` within `spread`. One in three is degenerate in some way
// (a point, collinear, two vertices equal, a duplicate of an earlier triangle), one in six shares an edge
// with the previous one. Vertices are floats: far from the origin they fall on a coarse grid.
ref_ptr<Mesh> soup(uint64_t seed, int n, const dvec3& centre, double spread, double size) {
    Rng g(seed);
    std::vector<vec3> pos;
    std::vector<uint32_t> idx;
    auto add = [&](const dvec3& p) {
        pos.push_back(vec3(p));
        return uint32_t(pos.size() - 1);
    };
    for (int t = 0; t < n; ++t) {
        const dvec3 p = inBox(g, centre, spread);
        const dvec3 e = inBox(g, dvec3(0.0), size), f = inBox(g, dvec3(0.0), size);
        switch (pick(g, 12)) {
            case 0: idx.insert(idx.end(), {add(p), add(p), add(p)}); break;                // a point
            case 1: idx.insert(idx.end(), {add(p), add(p + e), add(p + 2.0 * e)}); break;  // collinear
            case 2: {
                const uint32_t a = add(p);
                idx.insert(idx.end(), {a, a, add(p + f)});  // two vertices equal
                break;
            }
            case 3:
                if (t > 0) {
                    const size_t s = 3 * pick(g, size_t(t));
                    idx.insert(idx.end(), {idx[s], idx[s + 1], idx[s + 2]});  // a duplicate
                    break;
                }
                [[fallthrough]];
            case 4:
            case 5:
                if (t > 0) {
                    const size_t s = idx.size() - 3;
                    const uint32_t a = idx[s + 1], b = idx[s];
                    idx.insert(idx.end(), {a, b, add(dvec3(pos[a]) + f)});  // the previous edge, reversed
                    break;
                }
                [[fallthrough]];
            default: idx.insert(idx.end(), {add(p), add(p + e), add(p + f)});
        }
    }
    return build(std::move(pos), std::move(idx));
}

// A k x k grid of quads at height z (flat), or with random heights: every interior edge and vertex shared.
ref_ptr<Mesh> grid(uint64_t seed, int k, double z, double bump) {
    Rng g(seed);
    std::vector<vec3> pos;
    std::vector<uint32_t> idx;
    for (int j = 0; j <= k; ++j)
        for (int i = 0; i <= k; ++i) pos.push_back(vec3(float(i), float(j), float(z + uniform(g, 0.0, bump))));
    for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) {
            const uint32_t a = uint32_t(j * (k + 1) + i), b = a + 1, c = a + uint32_t(k + 1), d = c + 1;
            idx.insert(idx.end(), {a, b, d, a, d, c});
        }
    return build(std::move(pos), std::move(idx));
}

struct Tri {
    dvec3 p[3];
    bool finite;
    Box box;
};

std::vector<Tri> triangles(const Mesh& m) {
    std::vector<Tri> out(m.triangleCount());
    for (uint32_t t = 0; t < m.triangleCount(); ++t) {
        Tri& tr = out[t];
        tr.finite = true;
        for (int k = 0; k < 3; ++k) {
            tr.p[k] = dvec3(m.positions()[m.index(3 * size_t(t) + k)]);
            tr.finite &= isFinite(tr.p[k]);
            tr.box.expand(tr.p[k]);
        }
    }
    return out;
}

bool overlaps(const Box& a, const Box& b) {
    for (int i = 0; i < 3; ++i)
        if (!(a.min[i] <= b.max[i] && a.max[i] >= b.min[i])) return false;
    return true;
}

bool close(double a, double b) { return std::abs(a - b) <= 1e-12 * std::max(1.0, std::abs(b)); }

struct Query {
    dvec3 o, d;
    double tMax;
};

std::string describe(const Query& q) {
    std::ostringstream s;
    s.precision(17);
    s << "o (" << q.o.x << ", " << q.o.y << ", " << q.o.z << ") d (" << q.d.x << ", " << q.d.y << ", " << q.d.z
      << ") tMax " << q.tMax;
    return s.str();
}

// Rays and segments at the mesh: aimed at points inside triangles, at vertices and edge midpoints (where
// neighbours meet), along the axes through a vertex (zero direction components), and at random.
std::vector<Query> queries(uint64_t seed, const std::vector<Tri>& tris, const Box& bound, int n) {
    Rng g(seed);
    const dvec3 c = bound.center();
    const double h = std::max(1e-3, glm::length(bound.halfExtent()));
    std::vector<Query> out;
    for (int k = 0; k < n; ++k) {
        const Tri& t = tris[pick(g, tris.size())];
        dvec3 target;
        switch (pick(g, 4)) {
            case 0: {
                const double u = uniform(g, 0, 1), v = uniform(g, 0, 1 - u);
                target = t.p[0] + u * (t.p[1] - t.p[0]) + v * (t.p[2] - t.p[0]);
                break;
            }
            case 1: target = t.p[pick(g, 3)]; break;
            case 2: target = 0.5 * (t.p[pick(g, 3)] + t.p[pick(g, 3)]); break;
            default: target = inBox(g, c, h);
        }
        if (!isFinite(target)) target = c;
        Query q;
        if (pick(g, 5) == 0) {  // along an axis through the target
            const int a = int(pick(g, 3));
            q.d = dvec3(0.0);
            q.d[a] = pick(g, 2) ? 1.0 : -1.0;
            q.o = target - q.d * uniform(g, 0.5, 2.0) * h;
        } else {
            q.o = inBox(g, c, 2.0 * h);
            q.d = target - q.o;
            if (pick(g, 2)) q.d *= uniform(g, 0.01, 100.0);  // any length
        }
        // Rays, segments ending before or past the target, and segments of length zero.
        const size_t kind = pick(g, 8);
        q.tMax = kind < 4 ? kInf : kind == 7 ? 0.0 : uniform(g, 0.0, 1.5);
        out.push_back(q);
    }
    return out;
}

// Runs every query through the BVH and the loop, counting disagreements; returns the first one described.
std::string compare(const Mesh& m, uint64_t seed, int nRays, int nBoxes) {
    const MeshBvh bvh(m);
    const std::vector<Tri> tris = triangles(m);
    Box bound;
    for (const Tri& t : tris)
        if (t.finite) bound.expand(t.box);
    if (bound.empty()) bound = Box{dvec3(-1.0), dvec3(1.0)};
    int bad = 0;
    std::string first;
    auto fail = [&](const std::string& what) {
        if (bad++ == 0) first = what;
    };
    size_t hits = 0;
    std::vector<MeshBvh::RayHit> all;
    for (const Query& q : queries(seed, tris, bound, nRays)) {
        // The loop: every hit, and the nearest t.
        std::map<uint32_t, MeshBvh::RayHit> expect;
        double tBest = kInf;
        for (uint32_t t = 0; t < tris.size(); ++t) {
            MeshBvh::RayHit h;
            if (!tris[t].finite || !MeshBvh::rayTriangle(q.o, q.d, q.tMax, tris[t].p[0], tris[t].p[1], tris[t].p[2], h))
                continue;
            h.primitive = t;
            expect[t] = h;
            tBest = std::min(tBest, h.t);
        }
        hits += expect.size();
        MeshBvh::RayHit h;
        const bool found = bvh.nearest(q.o, q.d, q.tMax, h);
        if (found != !expect.empty()) {
            fail("nearest: " + std::string(found ? "a hit the loop does not find" : "no hit, the loop finds one") +
                 ": " + describe(q));
        } else if (found) {
            // Triangles at the same t (shared edges, duplicates) are equally nearest: any of them will do.
            const auto it = expect.find(h.primitive);
            if (it == expect.end() || !close(h.t, tBest) || !close(it->second.t, tBest) || !close(h.u, it->second.u) ||
                !close(h.v, it->second.v))
                fail("nearest: triangle " + std::to_string(h.primitive) + " at t " + std::to_string(h.t) +
                     ", the loop's nearest t is " + std::to_string(tBest) + ": " + describe(q));
        }
        all.clear();
        bvh.all(q.o, q.d, q.tMax, all);
        std::map<uint32_t, MeshBvh::RayHit> got;
        bool twice = false;
        for (const auto& a : all) twice |= !got.emplace(a.primitive, a).second;
        bool same = !twice && got.size() == expect.size();
        for (auto g = got.begin(), e = expect.begin(); same && g != got.end(); ++g, ++e)
            same = g->first == e->first && close(g->second.t, e->second.t) && close(g->second.u, e->second.u) &&
                   close(g->second.v, e->second.v);
        if (!same)
            fail("all: " + std::to_string(all.size()) + " hits, the loop finds " + std::to_string(expect.size()) +
                 ": " + describe(q));
    }
    Rng g(seed + 1);
    const dvec3 c = bound.center();
    const double h = std::max(1e-3, glm::length(bound.halfExtent()));
    size_t overlapped = 0;
    for (int k = 0; k < nBoxes; ++k) {
        Box b;
        const dvec3 at = k % 4 == 0 ? tris[pick(g, tris.size())].p[0] : inBox(g, c, 1.2 * h);
        const dvec3 e = k % 8 == 0 ? dvec3(0.0) : dvec3(h * std::pow(10.0, uniform(g, -3.0, 0.3)));
        b.expand(isFinite(at) ? at - e : c);
        b.expand(isFinite(at) ? at + e : c);
        if (k % 50 == 1) b = Box{};  // empty: meets nothing
        std::multiset<uint32_t> got;
        bvh.overlapping(b, [&](uint32_t p) { got.insert(p); });
        std::set<uint32_t> expect;
        for (uint32_t t = 0; t < tris.size(); ++t)
            if (tris[t].finite && overlaps(tris[t].box, b)) expect.insert(t);
        overlapped += expect.size();
        // The BVH may add the rest of a leaf it meets; the caller's exact test drops them. Of what it reports,
        // the triangles whose boxes overlap are exactly the loop's, each once.
        std::set<uint32_t> kept;
        bool once = true, finite = true;
        for (uint32_t p : got) {
            once &= got.count(p) == 1;
            finite &= p < tris.size() && tris[p].finite;
            if (p < tris.size() && overlaps(tris[p].box, b)) kept.insert(p);
        }
        if (!once || !finite || kept != expect) {
            std::ostringstream s;
            s << "overlapping: " << kept.size() << " of " << got.size() << " reported overlap, the loop finds "
              << expect.size() << " (reported once: " << once << ", finite: " << finite << ") for box " << b.min.x
              << " " << b.min.y << " " << b.min.z << " .. " << b.max.x << " " << b.max.y << " " << b.max.z;
            fail(s.str());
        }
    }
    // The queries must exercise something: hits and overlaps on every mesh with a finite triangle.
    if (!bound.empty() && (hits == 0 || overlapped == 0))
        fail("the queries found " + std::to_string(hits) + " hits and " + std::to_string(overlapped) + " overlaps");
    return bad ? std::to_string(bad) + " disagreements; first: " + first : "";
}

}  // namespace

TEST(MeshBvh, AgreesWithEveryTriangleOnARandomSoup) {
    for (uint64_t seed : {1u, 2u, 3u}) {
        auto m = soup(seed, 1500, dvec3(0.0), 10.0, 1.5);
        EXPECT_EQ(compare(*m, seed * 100, 1000, 300), "") << "seed " << seed;
    }
}

TEST(MeshBvh, AgreesWithEveryTriangleOnSharedEdgesAndVertices) {
    auto m = grid(7, 24, 0.0, 2.0);
    EXPECT_EQ(compare(*m, 11, 1500, 300), "");
}

TEST(MeshBvh, AgreesWithEveryTriangleOnAFlatMesh) {
    // All centroids in one plane: the build splits on two axes only; rays in the plane see it edge-on.
    auto m = grid(8, 24, 3.0, 0.0);
    EXPECT_EQ(compare(*m, 12, 1500, 300), "");
}

TEST(MeshBvh, AgreesWithEveryTriangleOnASingleTriangle) {
    auto m = build({vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0)}, {0, 1, 2});
    EXPECT_EQ(compare(*m, 13, 1000, 200), "");
}

TEST(MeshBvh, AgreesWithEveryTriangleFarFromTheOrigin) {
    // Float vertices near 1e6 are 0.0625 apart: many triangles collapse, neighbours share rounded vertices.
    auto m = soup(4, 1500, dvec3(1.0e6, -2.0e6, 5.0e5), 200.0, 3.0);
    EXPECT_EQ(compare(*m, 14, 1000, 300), "");
    auto far = soup(5, 800, dvec3(3.0e7, 1.0e7, -2.0e7), 5000.0, 40.0);
    EXPECT_EQ(compare(*far, 15, 800, 200), "");
}

TEST(MeshBvh, AgreesWithEveryTriangleWhenCentroidsCoincide) {
    // Forty copies of one triangle and a few others: a leaf that no split can divide.
    std::vector<vec3> pos{vec3(0, 0, 0), vec3(2, 0, 0), vec3(0, 2, 0)};
    std::vector<uint32_t> idx;
    for (int k = 0; k < 40; ++k) idx.insert(idx.end(), {0, 1, 2});
    for (int k = 0; k < 6; ++k) {
        const uint32_t a = uint32_t(pos.size());
        pos.insert(pos.end(), {vec3(float(k), 5, 0), vec3(float(k) + 1, 5, 0), vec3(float(k), 6, 1)});
        idx.insert(idx.end(), {a, a + 1, a + 2});
    }
    auto m = build(std::move(pos), std::move(idx));
    EXPECT_EQ(compare(*m, 16, 1000, 200), "");
}

TEST(MeshBvh, AgreesWithEveryTriangleWhenSomeAreNotFinite) {
    // Triangles with a NaN or infinite vertex are left out of the BVH, and out of the loop.
    auto m = soup(6, 600, dvec3(0.0), 10.0, 1.5);
    std::vector<vec3> pos = m->positions();
    std::vector<uint32_t> idx(m->indexCount());
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = m->index(i);
    Rng g(6);
    for (int k = 0; k < 30; ++k) pos[pick(g, pos.size())][int(pick(g, 3))] = k % 2 ? NAN : -INFINITY;
    auto bad = build(std::move(pos), std::move(idx));
    EXPECT_EQ(compare(*bad, 17, 1000, 300), "");
}
