// The cull's conservative predicates on random inputs (fixed seeds, 100,000 cases and more per property),
// each against a reference computed here independently, in long double or by sampling points: spheres and
// boxes against one plane and against a frustum (the float kernels and their masked scalar twins, the image
// origin up to 10,000 km away), boxes against an occlusion tree of one occluder, and boxes against an
// occlusion map of one occluder (their screen rectangles, near-plane crossings included). A predicate may
// keep what the reference rejects, never reject what it keeps; each property also counts the rejections, so
// that it is not satisfied by rejecting nothing.
#include "sg/core/Camera.h"
#include "sg/cull/OcclusionMap.h"
#include "sg/cull/OcclusionTree.h"
#include "sg/cull/internal/FrustumKernel.h"
#include "testbed/Rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

using namespace sg;

namespace {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_UNDEFINED__)
#define SG_STRESS_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(undefined_behavior_sanitizer)
#define SG_STRESS_SANITIZED 1
#endif
#endif
// Cases per property: 100,000 and more in optimized builds; a tenth under the sanitizers, which run it ~20x slower.
#if defined(SG_STRESS_SANITIZED)
constexpr int kScale = 10;
#else
constexpr int kScale = 1;
#endif

using LD = long double;

using Rng = scenes::Rng;

// A random unit vector (rejection sampling in the unit ball).
dvec3 dir(Rng& r) {
    for (;;) {
        const dvec3 v(r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1));
        const double l = glm::length(v);
        if (l > 0.1 && l <= 1.0) return v / l;
    }
}

// A random perspective camera at `eye`: any field of view from 0.5 to 179 degrees, aspect, near and far.
Camera randomCamera(Rng& r, const dvec3& eye) {
    Camera cam;
    const double nearD = r.logUniform(1e-3, 10.0);
    cam.setPerspective(r.uniform(0.5, 179.0), r.logUniform(0.2, 5.0), nearD, nearD * r.logUniform(10.0, 1e6));
    dvec3 f = dir(r), up = dir(r);
    if (glm::length(glm::cross(f, up)) < 0.1) up = glm::normalize(glm::cross(f, dvec3(0.3, 0.5, 0.8)));
    cam.setLookAt(eye, eye + f, up);
    return cam;
}

// ---- Frustum planes: the float kernels against the planes evaluated in long double.

// The bounds of one batch, float, relative to the image origin, and the planes (double) in that frame.
struct Batch {
    std::array<Plane, 6> planes;
    std::vector<float> cx, cy, cz, r, ex, ey, ez;
    double extent = 0.0;
};

// Bounds around the camera at every distance and size, a third of them placed on a plane's boundary (its
// distance equal to minus the radius or the box's reach, within a relative 1e-6), where rounding decides.
Batch makeBatch(Rng& r, const Camera& cam, const dvec3& eyeRel, size_t n) {
    Batch b;
    for (size_t k = 0; k < 6; ++k) {
        const Plane& e = cam.eyePlanes()[k];
        b.planes[k] = Plane{e.n, e.d - glm::dot(e.n, eyeRel)};
    }
    const double farD = cam.eyePlanes()[5].d;  // the far plane faces the eye: d is its distance
    for (size_t i = 0; i < n; ++i) {
        const double dist = r.logUniform(cam.nearDistance() * 0.1, farD * 2.0);
        const double rad = dist * r.logUniform(1e-5, 1.0);
        dvec3 c = eyeRel + dir(r) * dist;
        dvec3 e = dvec3(r.uniform(0, 1), r.uniform(0, 1), r.uniform(0, 1)) * rad;
        if (r.below(3) == 0) {
            // On plane k's boundary: the sphere (or box) touches it from outside, give or take 1e-6.
            const Plane& p = b.planes[size_t(r.below(6))];
            const double reach = std::abs(p.n.x) * e.x + std::abs(p.n.y) * e.y + std::abs(p.n.z) * e.z;
            const double want = -(r.below(2) ? rad : reach) * (1.0 + r.uniform(-1e-6, 1e-6));
            c += p.n * (want - p.distance(c));
        }
        b.cx.push_back(float(c.x));
        b.cy.push_back(float(c.y));
        b.cz.push_back(float(c.z));
        b.r.push_back(float(rad));
        b.ex.push_back(float(e.x));
        b.ey.push_back(float(e.y));
        b.ez.push_back(float(e.z));
        // As FlatImage: the largest |centre| + radius (radius of the float box, at least the sphere's).
        const double boxR = glm::length(dvec3(b.ex.back(), b.ey.back(), b.ez.back()));
        b.extent = std::max(
            b.extent, glm::length(dvec3(b.cx.back(), b.cy.back(), b.cz.back())) + std::max(double(b.r.back()), boxR));
    }
    return b;
}

// Signed distances of the farthest-inside and farthest-outside points of the bound from plane p, in long
// double: for a sphere centre +- r; for a box the largest and smallest over its 8 corners.
void sphereRange(const Plane& p, const Batch& b, size_t i, LD& lo, LD& hi) {
    const LD d = LD(p.n.x) * b.cx[i] + LD(p.n.y) * b.cy[i] + LD(p.n.z) * b.cz[i] + LD(p.d);
    lo = d - b.r[i];
    hi = d + b.r[i];
}
void boxRange(const Plane& p, const Batch& b, size_t i, LD& lo, LD& hi) {
    lo = HUGE_VALL;
    hi = -HUGE_VALL;
    for (int k = 0; k < 8; ++k) {
        const LD x = LD(b.cx[i]) + ((k & 1) ? LD(b.ex[i]) : -LD(b.ex[i]));
        const LD y = LD(b.cy[i]) + ((k & 2) ? LD(b.ey[i]) : -LD(b.ey[i]));
        const LD z = LD(b.cz[i]) + ((k & 4) ? LD(b.ez[i]) : -LD(b.ez[i]));
        const LD d = LD(p.n.x) * x + LD(p.n.y) * y + LD(p.n.z) * z + LD(p.d);
        lo = std::min(lo, d);
        hi = std::max(hi, d);
    }
}

struct Tally {
    uint64_t cases = 0, culled = 0, inside = 0, refCulled = 0, wrongCull = 0, insideInSlack = 0;
    void print(const char* what) const {
        std::printf(
            "[ stress ] %-26s cases %llu  culled %llu (reference %llu, wrongly %llu)  inside %llu (of them "
            "within the slack of a plane %llu)\n",
            what, (unsigned long long)cases, (unsigned long long)culled, (unsigned long long)refCulled,
            (unsigned long long)wrongCull, (unsigned long long)inside, (unsigned long long)insideInSlack);
    }
    void expectSound(const char* what, double minCulledShare) const {
        print(what);
        EXPECT_GE(cases, uint64_t(100000 / kScale)) << what;
        EXPECT_EQ(wrongCull, 0u) << what << ": culled where the reference sees part of it inside";
        EXPECT_GE(double(culled), minCulledShare * double(cases)) << what << ": too few culled to mean anything";
        EXPECT_GT(inside, cases / 50) << what << ": too few inside to mean anything";
        // "Inside" within the slack of a plane is the safe answer too (the bound is drawn, its children
        // untested): counted, not an error. The slack, 8 float ulps of the batch's extent, costs the
        // boundary cases (a third of them sit on one) and no more.
        EXPECT_GE(double(culled), 0.8 * double(refCulled)) << what;
    }
};

// One property: the batch kernel or the masked scalar test, spheres or boxes, one plane or all six.
void frustumProperty(bool boxes, bool masked, bool onePlane, uint64_t seed, Tally& t) {
    Rng r(seed);
    const int cameras = 1000 / kScale;
    const size_t n = 131;  // not a multiple of the vector width
    for (int cam = 0; cam < cameras; ++cam) {
        // The image origin 0 to 10,000 km away from the world's, the eye up to 1 km from the image origin.
        const double far = cam % 4 == 0 ? 0.0 : r.logUniform(1.0, 1e7);
        const dvec3 origin = dir(r) * far;
        const dvec3 eyeRel = dir(r) * r.logUniform(1e-3, 1e3);
        const Camera c = randomCamera(r, origin + eyeRel);
        const Batch b = makeBatch(r, c, eyeRel, n);
        const uint32_t mask = onePlane ? (1u << r.below(6)) : 0x3fu;
        const kernel::Planes kp = kernel::Planes::make(b.planes, dvec3(0.0), b.extent, mask);
        std::vector<uint8_t> out(n);
        if (!masked) {
            if (boxes)
                kernel::classifyBoxes(kp, b.cx.data(), b.cy.data(), b.cz.data(), b.ex.data(), b.ey.data(), b.ez.data(),
                                      uint32_t(n), out.data());
            else
                kernel::classifySpheres(kp, b.cx.data(), b.cy.data(), b.cz.data(), b.r.data(), uint32_t(n), out.data());
        }
        for (size_t i = 0; i < n; ++i) {
            bool culled, inside;
            if (masked) {
                const uint32_t m =
                    boxes ? kernel::boxMasked(kp, mask, b.cx[i], b.cy[i], b.cz[i], b.ex[i], b.ey[i], b.ez[i])
                          : kernel::sphereMasked(kp, mask, b.cx[i], b.cy[i], b.cz[i], b.r[i]);
                culled = m == kernel::kCulledMask;
                inside = m == 0;
            } else {
                culled = out[i] & kernel::kOutside;
                inside = out[i] & kernel::kInside;
                EXPECT_FALSE(culled && inside);
            }
            bool refOut = false, refIn = true;
            for (int k = 0; k < 6; ++k) {
                if (!(mask & (1u << k))) continue;
                LD lo, hi;
                (boxes ? boxRange : sphereRange)(b.planes[size_t(k)], b, i, lo, hi);
                refOut |= hi < 0;  // every point on the outer side
                refIn &= lo > 0;
            }
            ++t.cases;
            t.culled += culled;
            t.inside += inside;
            t.refCulled += refOut;
            t.wrongCull += culled && !refOut;
            t.insideInSlack += inside && !refIn;
        }
    }
}

// ---- Occlusion: brute force rays from the eye (the origin: everything here is eye-relative).

// True when the segment from the eye to s enters the open box [lo, hi] strictly before s.
bool rayBlockedByBox(const dvec3& lo, const dvec3& hi, const dvec3& s) {
    LD t0 = 0, t1 = 1;
    for (int a = 0; a < 3; ++a) {
        const LD d = s[a];
        if (d == 0) {
            if (!(0 > lo[a] && 0 < hi[a])) return false;
            continue;
        }
        LD ta = LD(lo[a]) / d, tb = LD(hi[a]) / d;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    // Entering at t0 < 1 with an interior (t0 < t1): a point of the open box strictly before s.
    return t0 < t1 && t0 < 1 - 1e-12L;
}

// A convex polygon; true when the segment from the eye to s crosses its interior strictly before s.
bool rayBlockedByPolygon(const std::vector<dvec3>& poly, const dvec3& s) {
    const dvec3 n = glm::cross(poly[1] - poly[0], poly[2] - poly[0]);
    const LD w = LD(n.x) * poly[0].x + LD(n.y) * poly[0].y + LD(n.z) * poly[0].z;
    const LD ns = LD(n.x) * s.x + LD(n.y) * s.y + LD(n.z) * s.z;
    if (ns == 0) return false;
    const LD t = w / ns;
    if (!(t > 0 && t < 1 - 1e-12L)) return false;
    LD q[3] = {t * s.x, t * s.y, t * s.z};
    int sign = 0;
    for (size_t k = 0; k < poly.size(); ++k) {
        const dvec3& a = poly[k];
        const dvec3& b = poly[(k + 1) % poly.size()];
        // (b - a) x (q - a) . n: the same sign for every edge inside.
        const LD e[3] = {LD(b.x) - a.x, LD(b.y) - a.y, LD(b.z) - a.z};
        const LD v[3] = {q[0] - a.x, q[1] - a.y, q[2] - a.z};
        const LD c =
            (e[1] * v[2] - e[2] * v[1]) * n.x + (e[2] * v[0] - e[0] * v[2]) * n.y + (e[0] * v[1] - e[1] * v[0]) * n.z;
        const int sg = c > 0 ? 1 : (c < 0 ? -1 : 0);
        if (sg == 0 || (sign != 0 && sg != sign)) return false;
        sign = sg;
    }
    return true;
}

// Points of the box [lo, hi]: its corners, edge midpoints, face centres and a 4 x 4 x 4 grid through it.
void samples(const dvec3& lo, const dvec3& hi, std::vector<dvec3>& out) {
    out.clear();
    for (int i = 0; i <= 2; ++i)
        for (int j = 0; j <= 2; ++j)
            for (int k = 0; k <= 2; ++k) out.push_back(lo + (hi - lo) * dvec3(i, j, k) * 0.5);
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            for (int k = 0; k < 4; ++k) out.push_back(lo + (hi - lo) * (dvec3(i, j, k) + 0.5) * 0.25);
}

// A box somewhere behind the point `at` (eye-relative), of a size up to `size`.
void boxBehind(Rng& r, const dvec3& at, double size, dvec3& lo, dvec3& hi) {
    const dvec3 c = at * r.uniform(0.9, 3.0) + dir(r) * size * r.uniform(0.0, 1.0);
    const dvec3 e = dvec3(r.uniform(0, 1), r.uniform(0, 1), r.uniform(0, 1)) * size * r.logUniform(1e-3, 1.0);
    lo = c - e;
    hi = c + e;
}

// A small box near a point of the occluder (towards one of its `corners`, eye-relative): 1e-6 to 3% of
// the distance beyond it or in front of it, where a depth test is decided.
void boxNearOccluder(Rng& r, const dvec3& at, const dvec3* corners, int count, dvec3& lo, dvec3& hi) {
    const dvec3 p = at + (corners[r.below(count)] - at) * r.uniform(0.5, 1.0);
    const double len = glm::length(p), eps = r.logUniform(1e-6, 0.03) * (r.below(2) ? 1.0 : -1.0);
    const dvec3 e = dvec3(r.uniform(0.1, 1), r.uniform(0.1, 1), r.uniform(0.1, 1)) * len * r.logUniform(1e-5, 1e-2);
    const dvec3 c = p * (1.0 + eps) + p / len * glm::length(e) * (eps > 0 ? 1.0 : -1.0);
    lo = c - e;
    hi = c + e;
}

}  // namespace

TEST(PredicateStress, SpheresAgainstOnePlane) {
    Tally batch, masked;
    frustumProperty(false, false, true, 101, batch);
    frustumProperty(false, true, true, 102, masked);
    batch.expectSound("classifySpheres, one plane", 0.2);
    masked.expectSound("sphereMasked, one plane", 0.2);
}

TEST(PredicateStress, SpheresAgainstAFrustum) {
    Tally batch, masked;
    frustumProperty(false, false, false, 103, batch);
    frustumProperty(false, true, false, 104, masked);
    batch.expectSound("classifySpheres, frustum", 0.2);
    masked.expectSound("sphereMasked, frustum", 0.2);
}

TEST(PredicateStress, BoxesAgainstOnePlane) {
    Tally batch, masked;
    frustumProperty(true, false, true, 105, batch);
    frustumProperty(true, true, true, 106, masked);
    batch.expectSound("classifyBoxes, one plane", 0.2);
    masked.expectSound("boxMasked, one plane", 0.2);
}

TEST(PredicateStress, BoxesAgainstAFrustum) {
    Tally batch, masked;
    frustumProperty(true, false, false, 107, batch);
    frustumProperty(true, true, false, 108, masked);
    batch.expectSound("classifyBoxes, frustum", 0.2);
    masked.expectSound("boxMasked, frustum", 0.2);
}

TEST(PredicateStress, OcclusionTreeOfOneOccluderCullsOnlyHiddenBoxes) {
    // One box or polygon occluder in front of an eye 0 to 10,000 km from the origin; boxes behind it, beside
    // it, straddling its shadow's edges, and crossing it. A box the tree (its hierarchical test, which splits
    // boxes by the chain's planes, and isOccluded) calls occluded has every sample hidden from the eye.
    Rng r(201);
    std::vector<dvec3> pts;
    uint64_t cases = 0, occluded = 0, wrong = 0, hierarchicalDiffers = 0;
    OcclusionTree tree;
    const int trees = 2000 / kScale, perTree = 60;
    for (int t = 0; t < trees; ++t) {
        // The eye on a 2^-20 grid near a whole offset: world - eye is exact, the tree sees our geometry.
        const double off = t % 3 == 0 ? 0.0 : std::round(r.uniform(-1, 1) * 1e7);
        const dvec3 eye(off, -off, std::round(r.uniform(-100, 100)));
        auto q = [](double v) { return std::ldexp(std::round(std::ldexp(v, 20)), -20); };
        auto qv = [&](const dvec3& v) { return dvec3(q(v.x), q(v.y), q(v.z)); };
        OcclusionTree::Options o;
        tree.reset(eye, o);
        const double dist = r.logUniform(0.01, 1000.0);
        const dvec3 at = qv(dir(r) * dist);
        const bool poly = t % 2 == 1;
        dvec3 corners[8];  // the occluder's corners, eye-relative
        int nCorners = 0;
        dvec3 olo, ohi;
        std::vector<dvec3> polygon;
        if (poly) {
            // A quad facing the eye roughly, tilted at random.
            const dvec3 n = glm::normalize(-at + dir(r) * dist * 0.5);
            dvec3 u = glm::normalize(glm::cross(n, dir(r))), v = glm::cross(n, u);
            const double a = dist * r.uniform(0.1, 2.0), b = dist * r.uniform(0.1, 2.0);
            polygon = std::vector<dvec3>{qv(at - u * a - v * b), qv(at + u * a - v * b), qv(at + u * a + v * b),
                                         qv(at - u * a + v * b)};
            // Quantizing may bend it out of its plane: the fourth vertex completes the parallelogram (exact).
            polygon[3] = polygon[0] + polygon[2] - polygon[1];
            for (const dvec3& p : polygon) corners[nCorners++] = p;
            std::vector<dvec3> world;
            for (const dvec3& p : polygon) world.push_back(eye + p);
            if (!tree.insertPolygon(world.data(), world.size())) continue;
        } else {
            const dvec3 e = dvec3(r.uniform(0.05, 1), r.uniform(0.05, 1), r.uniform(0.05, 1)) * dist;
            olo = qv(at - e);
            ohi = qv(at + e);
            for (int k = 0; k < 8; ++k)
                corners[nCorners++] = dvec3((k & 1) ? ohi.x : olo.x, (k & 2) ? ohi.y : olo.y, (k & 4) ? ohi.z : olo.z);
            if (!tree.insertBox(Box{eye + olo, eye + ohi})) continue;
        }
        for (int k = 0; k < perTree; ++k) {
            dvec3 lo, hi;
            if (k % 2)
                boxBehind(r, at, dist, lo, hi);
            else
                boxNearOccluder(r, at, corners, nCorners, lo, hi);
            lo = qv(lo);
            hi = qv(hi);
            const Box world{eye + lo, eye + hi};
            int32_t resume = tree.root();
            const bool hier = tree.test(world, resume) == OcclusionTree::Result::Occluded;
            const bool occ = tree.isOccluded(world);
            hierarchicalDiffers += hier != occ;
            ++cases;
            if (!(hier || occ)) continue;
            ++occluded;
            samples(lo, hi, pts);
            bool allHidden = true;
            for (const dvec3& s : pts)
                allHidden &= poly ? rayBlockedByPolygon(polygon, s) : rayBlockedByBox(olo, ohi, s);
            if (!allHidden && wrong++ < 5)
                ADD_FAILURE() << "occluded but a sample is visible: eye " << eye.x << " " << eye.y << " " << eye.z
                              << (poly ? " polygon" : " box") << " box " << lo.x << " " << lo.y << " " << lo.z << " .. "
                              << hi.x << " " << hi.y << " " << hi.z;
        }
    }
    std::printf(
        "[ stress ] occlusion tree, one occluder      cases %llu  occluded %llu  wrong %llu  "
        "hierarchical != isOccluded %llu\n",
        (unsigned long long)cases, (unsigned long long)occluded, (unsigned long long)wrong,
        (unsigned long long)hierarchicalDiffers);
    EXPECT_GE(cases, uint64_t(100000 / kScale));
    EXPECT_EQ(wrong, 0u);
    EXPECT_GE(double(occluded), 0.2 * double(cases));
}

TEST(PredicateStress, OcclusionMapOfOneOccluderCullsOnlyHiddenBoxes) {
    // One polygon or box occluder covering part of the screen; boxes behind it, beside it, in front of it and
    // across the near plane. A box called Occluded has every sample inside the view hidden behind the
    // occluder (its ray crosses it first, so it lies inside the occluder's projection and beyond it); a box
    // with a corner nearer than the near plane is never Occluded.
    Rng r(301);
    std::vector<dvec3> pts;
    uint64_t cases = 0, occluded = 0, wrong = 0, nearCases = 0, nearOccluded = 0;
    OcclusionMap map;
    const int maps = 2000 / kScale, perMap = 60;
    for (int t = 0; t < maps; ++t) {
        Camera cam = randomCamera(r, dvec3(0.0));
        cam.setPerspective(r.uniform(1.0, 170.0), r.logUniform(0.3, 3.0), r.logUniform(1e-3, 1.0), 1e5);
        cam.setViewport(16 << r.below(7), 16 << r.below(7));
        OcclusionSettings s;
        s.method = OcclusionMethod::Hom;
        map.reset(cam, OcclusionMap::optionsFor(cam, s));
        const dvec3 fwd = cam.viewDirection();
        const double nearD = cam.nearDistance();
        const double dist = nearD * r.logUniform(1.5, 1e3);
        const dvec3 at = fwd * dist + dir(r) * dist * r.uniform(0.0, 0.3);
        const bool poly = t % 2 == 1;
        dvec3 corners[8];  // the occluder's corners, eye-relative
        int nCorners = 0;
        std::vector<dvec3> polygon;
        dvec3 olo, ohi;
        if (poly) {
            const dvec3 n = glm::normalize(-at + dir(r) * dist * 0.5);
            const dvec3 u = glm::normalize(glm::cross(n, dir(r))), v = glm::cross(n, u);
            const double a = dist * r.uniform(0.1, 3.0), b = dist * r.uniform(0.1, 3.0);
            polygon =
                std::vector<dvec3>{at - u * a - v * b, at + u * a - v * b, at + u * a + v * b, at - u * a + v * b};
            map.addPolygon(polygon.data(), polygon.size());
            for (const dvec3& p : polygon) corners[nCorners++] = p;
        } else {
            const dvec3 e = dvec3(r.uniform(0.05, 1), r.uniform(0.05, 1), r.uniform(0.05, 1)) * dist;
            olo = at - e;
            ohi = at + e;
            dvec3 c[8];
            for (int k = 0; k < 8; ++k)
                c[k] = dvec3((k & 1) ? ohi.x : olo.x, (k & 2) ? ohi.y : olo.y, (k & 4) ? ohi.z : olo.z);
            map.addBox(c);
            for (const dvec3& p : c) corners[nCorners++] = p;
        }
        map.finish();
        const auto& planes = cam.eyePlanes();
        for (int k = 0; k < perMap; ++k) {
            dvec3 lo, hi;
            const bool acrossNear = k % 8 == 0;
            if (acrossNear) {
                // Straddling the near plane: one corner nearer than it, the rest anywhere up to far behind.
                const dvec3 p = fwd * nearD * r.uniform(0.0, 0.999) + dir(r) * nearD * r.uniform(0.0, 0.5);
                const dvec3 q = at * r.uniform(0.5, 3.0) + dir(r) * dist * r.uniform(0.0, 0.5);
                lo = glm::min(p, q);
                hi = glm::max(p, q);
            } else if (k % 2) {
                boxBehind(r, at, dist, lo, hi);
            } else {
                boxNearOccluder(r, at, corners, nCorners, lo, hi);
            }
            const OcclusionMap::Result res = map.test(lo, hi);
            ++cases;
            bool cutByNear = false;
            for (int c = 0; c < 8; ++c) {
                const dvec3 p((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
                cutByNear |= planes[4].distance(p) < 0;
            }
            if (cutByNear) {
                ++nearCases;
                nearOccluded += res == OcclusionMap::Result::Occluded;
            }
            if (res != OcclusionMap::Result::Occluded) continue;
            ++occluded;
            samples(lo, hi, pts);
            bool allHidden = true;
            for (const dvec3& p : pts) {
                // Off the screen (outside a side plane, by more than rounding): not drawn, need not be hidden.
                bool onScreen = true;
                for (int pl = 0; pl < 4; ++pl) onScreen &= planes[size_t(pl)].distance(p) >= -1e-9 * glm::length(p);
                if (!onScreen) continue;
                allHidden &= poly ? rayBlockedByPolygon(polygon, p) : rayBlockedByBox(olo, ohi, p);
            }
            if (!allHidden && wrong++ < 5)
                ADD_FAILURE() << "Occluded but a sample on screen is visible: map " << t << " box " << lo.x << " "
                              << lo.y << " " << lo.z << " .. " << hi.x << " " << hi.y << " " << hi.z;
        }
    }
    std::printf(
        "[ stress ] occlusion map, one occluder       cases %llu  occluded %llu  wrong %llu  "
        "across the near plane %llu (occluded %llu)\n",
        (unsigned long long)cases, (unsigned long long)occluded, (unsigned long long)wrong,
        (unsigned long long)nearCases, (unsigned long long)nearOccluded);
    EXPECT_GE(cases, uint64_t(100000 / kScale));
    EXPECT_EQ(wrong, 0u);
    EXPECT_EQ(nearOccluded, 0u);
    EXPECT_GT(nearCases, cases / 20);
    EXPECT_GE(double(occluded), 0.2 * double(cases));
}
