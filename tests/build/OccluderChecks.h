// Checks shared by the generated-occluder tests, computed independently of the implementation in double precision.
#pragma once
#include "build/OccluderTestShapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace occtest {

// Every box lies wholly inside the solid of `mesh`: no triangle meets it; at its corners, face and edge centres and
// random points the winding number is 1 or more, and the signed crossings along three random rays (ray parity, the
// sign kept) agree with it; and every ray from outside the mesh's bound into the box crosses the surface first.
inline void expectInsideSolid(const Mesh& mesh, const std::vector<Box>& boxes, scenes::Rng& rng,
                              const std::string& what, int points = 40, int rays = 60) {
    const std::vector<Tri> tris = trianglesOf(mesh);
    const Box bound = mesh.box();
    const double size = glm::length(bound.max - bound.min);
    for (size_t k = 0; k < boxes.size(); ++k) {
        const Box& b = boxes[k];
        SCOPED_TRACE(what + ": box " + std::to_string(k) + " " + str(b));
        ASSERT_FALSE(b.empty());
        ASSERT_TRUE(isFinite(b.min) && isFinite(b.max));
        EXPECT_GT(volume(b), 0.0);
        for (size_t t = 0; t < tris.size(); ++t)
            ASSERT_FALSE(triangleMeetsBox(tris[t], b)) << "triangle " << t << " meets the box";
        for (const dvec3& p : samplesOf(b, rng, points)) {
            const double w = windingNumber(tris, p);
            ASSERT_GT(w, 0.5) << "point (" << p.x << " " << p.y << " " << p.z << ") winding number " << w;
            ASSERT_NEAR(w, std::round(w), 1e-6) << "point off the surface but a winding number not whole";
            for (int r = 0; r < 3; ++r) {
                const dvec3 d = randomDirection(rng);
                ASSERT_EQ(signedCrossings(tris, p, d), int(std::round(w)))
                    << "point (" << p.x << " " << p.y << " " << p.z << "): crossings along (" << d.x << " " << d.y
                    << " " << d.z << ") disagree with the winding number";
            }
        }
        for (int r = 0; r < rays; ++r) {
            const dvec3 o = bound.center() + randomDirection(rng) * (size * 2.0 + 1.0);
            const dvec3 target(rng.uniform(b.min.x, b.max.x), rng.uniform(b.min.y, b.max.y),
                               rng.uniform(b.min.z, b.max.z));
            const dvec3 d = target - o;
            const double enter = entryInto(b, o, d), hit = firstHit(tris, o, d);
            ASSERT_LE(enter, 1.0);
            ASSERT_LE(hit, enter) << "ray " << r << " from (" << o.x << " " << o.y << " " << o.z
                                  << ") reaches the box before any surface";
        }
    }
}

// A polygon's normal by Newell's method, and its area.
inline dvec3 newellNormal(const std::vector<dvec3>& poly) {  // length: twice the area
    dvec3 n(0.0);
    const dvec3 o = poly[0];
    for (size_t i = 1; i + 1 < poly.size(); ++i) n += glm::cross(poly[i] - o, poly[i + 1] - o);
    return n;
}
inline double area(const std::vector<dvec3>& poly) { return 0.5 * glm::length(newellNormal(poly)); }

}  // namespace occtest
