// The simulated laser scan of the factory (testbed/FactoryScan.h): the same points whatever the number of workers,
// every point on a surface to within its noise, about as many points as asked for, colours and intensities that vary.
#include "testbed/FactoryScan.h"

#include "sg/core/Camera.h"
#include "sg/intersect/IntersectTraversal.h"

#include <gtest/gtest.h>

#include <set>
#include <vector>

using sg::dvec3;

namespace {

constexpr uint64_t kPoints = 20000;
constexpr double kNoise = 0.005;

struct Site {
    scenes::Factory f = scenes::buildFactory();
    sg::Scene scene{f.root};
    Site() { scene.update(); }
};
Site& site() {
    static Site s;
    return s;
}

struct Scanned {
    scenes::FactoryScan scan;
    std::vector<scenes::ScannedPoint> points;
};

Scanned scan(int threads) {
    scenes::FactoryScanParams p;
    p.points = kPoints;
    p.walkStations = 3;
    p.siteStations = 3;
    p.rangeNoise = kNoise;
    p.seed = 7;
    p.threads = threads;
    Scanned r;
    r.scan = scenes::scanFactory(site().f, site().scene, p, [&](const std::vector<scenes::ScannedPoint>& batch) {
        r.points.insert(r.points.end(), batch.begin(), batch.end());
    });
    return r;
}

const Scanned& oneWorker() {
    static const Scanned s = scan(1);
    return s;
}

// Whether a triangle is within `radius` of p. A tree is a billboard turned toward the eye that sees it: a point on one
// is on it as seen from its station, so each station is tried as the eye too.
bool onASurface(sg::IntersectTraversal& probe, const std::vector<dvec3>& stations, const dvec3& p, double radius) {
    std::vector<sg::Hit> hits;
    sg::QueryOptions options;
    probe.intersectSphere(site().scene, p, radius, options, hits);
    if (!hits.empty()) return true;
    for (const dvec3& s : stations) {
        sg::Camera eye;
        eye.setViewport(100, 100);
        eye.setPerspective(60.0, 1.0, 0.1, 1000.0);
        eye.setLookAt(s, s + dvec3(1.0, 0.0, 0.0), dvec3(0.0, 0.0, 1.0));
        options.camera = &eye;
        probe.intersectSphere(site().scene, p, radius, options, hits);
        if (!hits.empty()) return true;
    }
    return false;
}

}  // namespace

TEST(FactoryScan, TheSamePointsWithOneAndTwoWorkers) {
    const Scanned& a = oneWorker();
    const Scanned b = scan(2);
    EXPECT_EQ(a.scan.rays, b.scan.rays);
    ASSERT_EQ(a.points.size(), b.points.size());
    for (size_t k = 0; k < a.points.size(); ++k) {
        ASSERT_EQ(a.points[k].position, b.points[k].position) << "point " << k;
        ASSERT_EQ(a.points[k].color, b.points[k].color) << "point " << k;
        ASSERT_EQ(a.points[k].intensity, b.points[k].intensity) << "point " << k;
    }
}

TEST(FactoryScan, AboutThePointsAskedFor) {
    const Scanned& a = oneWorker();
    EXPECT_EQ(a.scan.stations.size(), 6u);
    EXPECT_EQ(a.scan.points, uint64_t(a.points.size()));
    EXPECT_EQ(a.scan.rays, uint64_t(a.scan.azimuthSteps) * uint64_t(a.scan.elevationSteps) * 6u);
    EXPECT_LT(a.scan.points, a.scan.rays);  // the sky returns nothing
    EXPECT_GE(double(a.points.size()), 0.8 * kPoints);
    EXPECT_LE(double(a.points.size()), 1.2 * kPoints);
}

TEST(FactoryScan, EveryPointLiesOnASurfaceWithinItsNoise) {
    const Scanned& a = oneWorker();
    ASSERT_FALSE(a.points.empty());
    sg::IntersectTraversal probe;
    int off = 0, checked = 0;
    for (size_t k = 0; k < a.points.size(); k += 7) {  // a seventh of them: the test stays fast
        ++checked;
        if (!onASurface(probe, a.scan.stations, a.points[k].position, 5.0 * kNoise)) {
            if (off++ == 0) ADD_FAILURE() << "point " << k << " is off every surface";
        }
    }
    EXPECT_EQ(off, 0) << "of " << checked;
}

TEST(FactoryScan, ColoursAndIntensitiesVary) {
    const Scanned& a = oneWorker();
    std::set<uint32_t> colors;
    std::set<uint16_t> intensities;
    size_t translucent = 0;
    for (const scenes::ScannedPoint& p : a.points) {
        colors.insert((uint32_t(p.color.r) << 16) | (uint32_t(p.color.g) << 8) | uint32_t(p.color.b));
        intensities.insert(p.intensity);
        translucent += p.color.a != 255;
    }
    EXPECT_EQ(translucent, 0u);
    EXPECT_GT(colors.size(), 10u);
    EXPECT_GT(intensities.size(), 100u);
}
