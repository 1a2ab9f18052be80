// OcclusionMap: the pyramid's values, the overlap and depth tests on hand-made occluders, the approximate
// threshold, the near plane, and the rasterizer's coverage against the polygons it rasterizes.
#include "sg/core/Camera.h"
#include "sg/cull/OcclusionMap.h"

#include <gtest/gtest.h>

#include <random>

using namespace sg;

namespace {
// The eye at the origin looking down -Z, 90 degrees, square: a map pixel is a screen pixel at 256 x 256, and
// the point (x, y, -d) lands on map pixel ((x / d + 1) * 128, (y / d + 1) * 128).
Camera straightAhead(int size = 256) {
    Camera cam;
    cam.setLookAt(dvec3(0.0), dvec3(0, 0, -1), dvec3(0, 1, 0));
    cam.setPerspective(90.0, 1.0, 0.5, 1000.0);
    cam.setViewport(size, size);
    return cam;
}

OcclusionSettings homSettings(double opacity = 1.0) {
    OcclusionSettings s;
    s.method = OcclusionMethod::Hom;
    s.homOpacity = opacity;
    return s;
}

// The square [x0, x1] x [y0, y1] at depth d, as a polygon.
void addSquare(OcclusionMap& m, double x0, double x1, double y0, double y1, double d) {
    const dvec3 q[4] = {{x0, y0, -d}, {x1, y0, -d}, {x1, y1, -d}, {x0, y1, -d}};
    ASSERT_TRUE(m.addPolygon(q, 4));
}

OcclusionMap::Result testBox(const OcclusionMap& m, double x0, double x1, double y0, double y1, double z0, double z1) {
    return m.test(dvec3(x0, y0, -z1), dvec3(x1, y1, -z0));
}
}  // namespace

TEST(OcclusionMap, PyramidHoldsCoverageAndTheNearestOccludersFarDepth) {
    const Camera cam = straightAhead();
    OcclusionMap m;
    m.reset(cam, OcclusionMap::optionsFor(cam, homSettings()));
    // [-5, 5]^2 at depth 10: map pixels 64 to 192 along both axes. Pixels 64 and 191 touch the edges and
    // are only covered up to the margin: not counted.
    addSquare(m, -5, 5, -5, 5, 10);
    m.finish();
    EXPECT_EQ(m.levels(), 9);
    EXPECT_EQ(m.opacity(0, 65, 65), 1.0f);
    EXPECT_EQ(m.opacity(0, 190, 100), 1.0f);
    EXPECT_EQ(m.opacity(0, 64, 100), 0.0f);
    EXPECT_EQ(m.opacity(0, 191, 100), 0.0f);
    EXPECT_EQ(m.opacity(0, 10, 10), 0.0f);
    EXPECT_EQ(m.coveredPixels(), 126u * 126u);
    // Level 1 pixel (32, 32) holds level-0 pixels 64..65 x 64..65: one of four covered.
    EXPECT_EQ(m.opacity(1, 32, 32), 0.25f);
    EXPECT_EQ(m.opacity(1, 33, 33), 1.0f);
    EXPECT_EQ(m.opacity(8, 0, 0), float(126 * 126) / float(256 * 256));
    // Depth: the square's 10, moved away by the depth buffer's resolution only; none where uncovered.
    EXPECT_GE(m.depth(0, 100, 100), 10.0f);
    EXPECT_LT(m.depth(0, 100, 100), 10.01f);
    EXPECT_EQ(m.depth(0, 10, 10), 0.0f);
    EXPECT_EQ(m.depth(8, 0, 0), m.depth(0, 100, 100));

    // A nearer square over part of it: there the nearest occluder's depth.
    addSquare(m, -1, 1, -1, 1, 4);
    m.finish();
    EXPECT_LT(m.depth(0, 128, 128), 4.01f);
    EXPECT_GE(m.depth(0, 70, 70), 10.0f);
}

TEST(OcclusionMap, BoxBehindIsOccludedInFrontOrBesideIsNot) {
    const Camera cam = straightAhead();
    OcclusionMap m;
    m.reset(cam, OcclusionMap::optionsFor(cam, homSettings()));
    addSquare(m, -5, 5, -5, 5, 10);
    m.finish();
    EXPECT_EQ(testBox(m, -3, 3, -3, 3, 18, 20), OcclusionMap::Result::Occluded);
    EXPECT_EQ(testBox(m, -0.1, 0.1, -0.1, 0.1, 10.1, 10.2), OcclusionMap::Result::Occluded);  // a small one
    EXPECT_EQ(testBox(m, -3, 3, -3, 3, 6, 8), OcclusionMap::Result::NotOccluded);             // in front
    EXPECT_EQ(testBox(m, -3, 3, -3, 3, 9, 20), OcclusionMap::Result::NotOccluded);            // through the occluder
    EXPECT_EQ(testBox(m, -3, 11, -3, 3, 18, 20), OcclusionMap::Result::NotOccluded);  // sticking out at the side
    // Entirely beside it: no coverage under it at all, so neither is anything inside it.
    EXPECT_EQ(testBox(m, 12, 14, -1, 1, 18, 20), OcclusionMap::Result::Visible);
    // Cut by the near plane, or behind the eye: never occluded.
    EXPECT_EQ(m.test(dvec3(-1, -1, -20), dvec3(1, 1, -0.1)), OcclusionMap::Result::NotOccluded);
    EXPECT_EQ(m.test(dvec3(-1, -1, 1), dvec3(1, 1, 3)), OcclusionMap::Result::NotOccluded);
}

TEST(OcclusionMap, TwoOccludersTogetherHideWhatNeitherHidesAlone) {
    const Camera cam = straightAhead();
    OcclusionMap left, right, both;
    for (OcclusionMap* m : {&left, &right, &both}) m->reset(cam, OcclusionMap::optionsFor(cam, homSettings()));
    addSquare(left, -5, 0.5, -5, 5, 10);
    addSquare(right, -0.5, 5, -5, 5, 12);
    addSquare(both, -5, 0.5, -5, 5, 10);
    addSquare(both, -0.5, 5, -5, 5, 12);
    for (OcclusionMap* m : {&left, &right, &both}) m->finish();
    EXPECT_EQ(testBox(left, -3, 3, -3, 3, 18, 20), OcclusionMap::Result::NotOccluded);
    EXPECT_EQ(testBox(right, -3, 3, -3, 3, 18, 20), OcclusionMap::Result::NotOccluded);
    EXPECT_EQ(testBox(both, -3, 3, -3, 3, 18, 20), OcclusionMap::Result::Occluded);
    // Between the two depths: hidden on the left where the nearer one is, not on the right.
    EXPECT_EQ(testBox(both, -3, -1, -3, 3, 11, 11.5), OcclusionMap::Result::Occluded);
    EXPECT_EQ(testBox(both, 1, 3, -3, 3, 11, 11.5), OcclusionMap::Result::NotOccluded);
}

TEST(OcclusionMap, ApproximateThresholdCullsBehindASmallGapTheConservativeOneDoesNot) {
    const Camera cam = straightAhead();
    OcclusionMap exact, approx;
    exact.reset(cam, OcclusionMap::optionsFor(cam, homSettings(1.0)));
    approx.reset(cam, OcclusionMap::optionsFor(cam, homSettings(0.9)));
    for (OcclusionMap* m : {&exact, &approx}) {
        // A slit 0.02 wide at depth 10 (a fifth of a pixel): the two columns it crosses are not covered.
        addSquare(*m, -5, -0.01, -5, 5, 10);
        addSquare(*m, 0.01, 5, -5, 5, 10);
        m->finish();
    }
    EXPECT_EQ(exact.opacity(0, 127, 100), 0.0f);
    EXPECT_EQ(exact.opacity(0, 128, 100), 0.0f);
    EXPECT_EQ(exact.opacity(0, 126, 100), 1.0f);
    EXPECT_EQ(testBox(exact, -3, 3, -3, 3, 18, 20), OcclusionMap::Result::NotOccluded);
    EXPECT_EQ(testBox(approx, -3, 3, -3, 3, 18, 20), OcclusionMap::Result::Occluded);
    // What is seen only through the slit is culled by the approximate test: that is its error.
    // Seen only through the slit's own pixels, it is not culled by either.
    EXPECT_EQ(testBox(approx, -0.01, 0.01, -0.5, 0.5, 18, 20), OcclusionMap::Result::NotOccluded);
}

TEST(OcclusionMap, BoxOccluderHidesBehindItsFrontFaceNotItsBackFace) {
    const Camera cam = straightAhead();
    OcclusionMap m;
    m.reset(cam, OcclusionMap::optionsFor(cam, homSettings()));
    // A thick wall x, y in [-5, 5], z in [-12, -10]: only its face at z = -10 faces the eye.
    dvec3 c[8];
    for (int k = 0; k < 8; ++k) c[k] = dvec3((k & 1) ? 5 : -5, (k & 2) ? 5 : -5, (k & 4) ? -10 : -12);
    ASSERT_TRUE(m.addBox(c));
    m.finish();
    EXPECT_LT(m.depth(0, 128, 128), 10.01f);
    // Inside the wall, behind its front face: hidden.
    EXPECT_EQ(testBox(m, -1, 1, -1, 1, 11, 11.5), OcclusionMap::Result::Occluded);
    // The eye inside a box: it covers nothing.
    OcclusionMap inside;
    inside.reset(cam, OcclusionMap::optionsFor(cam, homSettings()));
    for (int k = 0; k < 8; ++k) c[k] = dvec3((k & 1) ? 5 : -5, (k & 2) ? 5 : -5, (k & 4) ? 5 : -5);
    EXPECT_FALSE(inside.addBox(c));
    inside.finish();
    EXPECT_TRUE(inside.empty());
}

TEST(OcclusionMap, BoxCutByTheNearPlaneCoversOnlyItsFacesBeyondIt) {
    const Camera cam = straightAhead();
    OcclusionMap m;
    m.reset(cam, OcclusionMap::optionsFor(cam, homSettings()));
    // A box to the right whose left face (x = 1) runs from in front of the near plane to depth 20: the GPU
    // shows the inside of the box where the near plane cuts its front faces away. The cut is at depth 0.5,
    // where x = 1 is beyond the right edge of the view: the face covers the right half beyond x / z = 1 / 20.
    dvec3 c[8];
    for (int k = 0; k < 8; ++k) c[k] = dvec3((k & 1) ? 3 : 1, (k & 2) ? 5 : -5, (k & 4) ? 1 : -20);
    ASSERT_TRUE(m.addBox(c));
    m.finish();
    // Nothing left of the face's far edge is covered (pixel 134 is x / z = 1 / 20 across at 256).
    for (int x = 0; x < 134; ++x) ASSERT_EQ(m.opacity(0, x, 128), 0.0f) << x;
    EXPECT_EQ(m.opacity(0, 200, 128), 1.0f);
}

TEST(OcclusionMap, CoveredPixelsLieInsideTheirTriangleAndInteriorPixelsAreCovered) {
    // Random triangles at random depths: every covered map pixel lies inside the triangle's projection
    // (its four corners, by exact orientation tests), and a pixel whose square lies inside by more than
    // a margin's worth is covered.
    const Camera cam = straightAhead();
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.3, 1.3), dz(1.0, 50.0);
    uint64_t covered = 0;
    for (int t = 0; t < 300; ++t) {
        OcclusionMap m;
        m.reset(cam, OcclusionMap::optionsFor(cam, homSettings()));
        dvec3 v[3];
        double px[3], py[3];
        for (int k = 0; k < 3; ++k) {
            const double d = dz(rng);
            v[k] = dvec3(u(rng) * d, u(rng) * d, -d);
            px[k] = (v[k].x / d + 1.0) * 128.0;
            py[k] = (v[k].y / d + 1.0) * 128.0;
        }
        const double area = (px[1] - px[0]) * (py[2] - py[0]) - (py[1] - py[0]) * (px[2] - px[0]);
        if (std::abs(area) < 1.0) continue;
        m.addPolygon(v, 3);
        m.finish();
        const double sgn = area > 0 ? 1.0 : -1.0;
        // Signed distance (in pixels) of a point inside the triangle from its nearest edge.
        auto inside = [&](double x, double y) {
            double worst = 1e300;
            for (int k = 0; k < 3; ++k) {
                const int j = (k + 1) % 3;
                const double ex = px[j] - px[k], ey = py[j] - py[k];
                worst = std::min(worst, sgn * (ex * (y - py[k]) - ey * (x - px[k])) / std::hypot(ex, ey));
            }
            return worst;
        };
        for (int y = 0; y < 256; ++y)
            for (int x = 0; x < 256; ++x) {
                const double worst = std::min({inside(x, y), inside(x + 1, y), inside(x, y + 1), inside(x + 1, y + 1)});
                if (m.opacity(0, x, y) == 1.0f) {
                    ++covered;
                    ASSERT_GT(worst, 0.0) << "triangle " << t << " pixel " << x << "," << y;
                } else if (worst > 0.05) {
                    ADD_FAILURE() << "triangle " << t << " pixel " << x << "," << y << " inside by " << worst;
                    return;
                }
            }
    }
    EXPECT_GT(covered, 100000u);
}

TEST(OcclusionMap, BadSizeOrThresholdIsRefusedByName) {
    const Camera cam = straightAhead();
    OcclusionSettings s = homSettings();
    s.homWidth = 300;
    EXPECT_THROW(
        {
            try {
                OcclusionMap::optionsFor(cam, s);
            } catch (const std::invalid_argument& e) {
                EXPECT_NE(std::string(e.what()).find("OcclusionMap::optionsFor()"), std::string::npos);
                throw;
            }
        },
        std::invalid_argument);
    s = homSettings(0.0);
    EXPECT_THROW(OcclusionMap::optionsFor(cam, s), std::invalid_argument);
    s = homSettings(std::nan(""));
    EXPECT_THROW(OcclusionMap::optionsFor(cam, s), std::invalid_argument);
}
