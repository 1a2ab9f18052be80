// PickBench: the pick mode. The rays of `sgbench pick` (random pixels of the orbit
// frames, from the near to the far plane), each picked by OSG (LineSegmentIntersector, nearest, k-d trees built
// by osg::KdTreeBuilder) and right after by sgkit (IntersectTraversal, nearest), both with the most detailed LOD
// level (OSG's intersection default). Part of the program only when it is built inside the sgkit project.
#include <osg/KdTree>
#include <osg/Version>
#include <osgUtil/IntersectionVisitor>
#include <osgUtil/LineSegmentIntersector>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "sg/intersect/IntersectTraversal.h"
#include "sg/intersect/PickSet.h"
#include "testbed/City.h"
#include "testbed/RandomScene.h"

#include "Bench.h"

namespace osgbench {

using namespace osgcity;

int runPick(int n, int raysPerFrame) {
    const Meshes meshes = buildMeshes(OccluderKind::None);
    Scene scene = buildCity(n, meshes, false);
    osg::ref_ptr<osg::KdTreeBuilder> kd = new osg::KdTreeBuilder;
    scene.root->accept(*kd);
    sg::Scene sgScene(scenes::buildCity({n, false}));
    sgScene.update();

    scenes::Rng rng(1);
    std::vector<sg::Ray> rays;
    for (int f = 0; f < kFrames; ++f) {
        const sg::Camera cam = scenes::cityOrbitCamera(n, f);
        for (int k = 0; k < raysPerFrame; ++k)
            rays.push_back(sg::pixelRay(cam, rng.uniform(0, 1280), rng.uniform(0, 720)));
    }
    sg::IntersectTraversal sgPick;
    sg::QueryOptions opt;
    opt.lod = sg::LodChoice::Highest;
    auto osgPick = [&](const sg::Ray& r, double& dist) {
        const osg::Vec3d a(r.origin.x, r.origin.y, r.origin.z);
        const sg::dvec3 e = r.origin + r.direction * r.tMax;
        osg::ref_ptr<osgUtil::LineSegmentIntersector> lsi =
            new osgUtil::LineSegmentIntersector(a, osg::Vec3d(e.x, e.y, e.z));
        lsi->setIntersectionLimit(osgUtil::Intersector::LIMIT_NEAREST);
        osgUtil::IntersectionVisitor iv(lsi.get());
        iv.setUseKdTreeWhenAvailable(true);
        scene.root->accept(iv);
        if (!lsi->containsIntersections()) return false;
        dist = (lsi->getFirstIntersection().getWorldIntersectPoint() - a).length();
        return true;
    };
    std::vector<double> osgUs, sgUs, ratio;
    uint64_t same = 0, hits = 0;
    for (int pass = 0; pass < 2; ++pass) {  // pass 0: warm-up (sgkit builds its BVHs on first use)
        for (const sg::Ray& r : rays) {
            double od = 0.0;
            const auto t0 = Clock::now();
            const bool oh = osgPick(r, od);
            const auto t1 = Clock::now();
            sg::Hit h;
            const bool sh = sgPick.intersect(sgScene, r, opt, h);
            const auto t2 = Clock::now();
            if (pass == 0) continue;
            osgUs.push_back(msBetween(t0, t1) * 1000.0);
            sgUs.push_back(msBetween(t1, t2) * 1000.0);
            ratio.push_back(msBetween(t0, t1) / msBetween(t1, t2));
            hits += sh;
            same += oh == sh && (!sh || std::abs(od - h.distance) < 1e-3);
        }
    }
    std::printf(
        "{\"peer\":\"openscenegraph\",\"osg_version\":\"%s\",\"n\":%d,\"rays\":%zu,\"hit_fraction\":%.4f,"
        "\"osg_pick_us_median\":%.3f,\"osg_pick_us_p95\":%.3f,\"sgkit_pick_us_median\":%.3f,\"sgkit_pick_us_p95\":%.3f,"
        "\"osg_over_sgkit_per_ray_median\":%.3f,\"same_hit_fraction\":%.5f}\n",
        osgGetVersion(), n, sgUs.size(), double(hits) / double(sgUs.size()), median(osgUs), percentile95(osgUs),
        median(sgUs), percentile95(sgUs), median(ratio), double(same) / double(sgUs.size()));
    return 0;
}

}  // namespace osgbench
