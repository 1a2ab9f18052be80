// CullBench: the cull mode, OSG's cull of the orbit path with frustum culling only, on the city without
// occluders; with --with-sgkit, sgkit's cull of its own city right after OSG's on every frame.
#include <osg/FrameStamp>
#include <osg/Version>
#include <osgUtil/SceneView>

#include <chrono>
#include <cstdio>
#include <vector>

#include <unistd.h>

#ifdef SGBENCH_WITH_SGKIT
#include "sg/cull/CullTraversal.h"
#include "testbed/City.h"

#include <memory>
#endif

#include "Bench.h"

namespace osgbench {

namespace {

using namespace osgcity;

double rssBytes() {
    long pages = 0, resident = 0;
    FILE* f = std::fopen("/proc/self/statm", "r");
    if (!f) return 0.0;
    if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
    std::fclose(f);
    return double(resident) * double(sysconf(_SC_PAGESIZE));
}

#ifdef SGBENCH_WITH_SGKIT
// In-process comparison: sgkit's own city, culled right after OpenSceneGraph's on every frame, so
// that both see the same machine speed (this machine's speed drifts for seconds at a time).
struct SgkitCull {
    std::unique_ptr<sg::Scene> scene;
    sg::CullTraversal cull;
    sg::DrawList list;
    std::vector<double> ms, ratio;
    double geometries = 0.0;
};

// sgkit's cull of orbit frame f; osgMs is the time OSG's cull of the same frame took.
void cullSgkit(SgkitCull& peer, int n, int f, bool timed, double osgMs) {
    const sg::Camera cam = scenes::cityOrbitCamera(n, f);
    sg::CullStats st;
    const auto s0 = Clock::now();
    peer.cull.cull(*peer.scene, cam, sg::CullSettings{}, peer.list, st);
    const auto s1 = Clock::now();
    if (timed) {
        peer.ms.push_back(msBetween(s0, s1));
        peer.ratio.push_back(osgMs / msBetween(s0, s1));
        peer.geometries += double(st.geometries);
    }
}
#endif

// The scene, its cull and what the timed passes measured. Scene points at meshes: the run is never moved.
struct CullRun {
    int n = 0;
    Meshes meshes;
    Scene scene;
    double rssBefore = 0.0, rssAfter = 0.0, buildSeconds = 0.0;
    osg::ref_ptr<osg::FrameStamp> frameStamp;
    osg::ref_ptr<osgUtil::SceneView> sceneView;
    std::vector<double> frameMs;
    double geometriesSum = 0.0, trianglesSum = 0.0;
#ifdef SGBENCH_WITH_SGKIT
    SgkitCull sgkit;
#endif
};

void build(CullRun& run) {
    run.rssBefore = rssBytes();
    const auto buildStart = Clock::now();
    run.meshes = buildMeshes(OccluderKind::None);
    run.scene = buildCity(run.n, run.meshes, false);
    const auto buildEnd = Clock::now();
    run.rssAfter = rssBytes();
    run.buildSeconds = std::chrono::duration<double>(buildEnd - buildStart).count();
}

// The untimed warm-up pass over the orbit, then the timed ones. False when the cull settings did not hold.
bool cullFrames(CullRun& run, int passes) {
    run.frameMs.reserve(size_t(passes) * kFrames);
    unsigned frameNumber = 0;
    for (int pass = 0; pass <= passes; ++pass) {
        const bool timed = pass > 0;  // pass 0 is the untimed warm-up
        for (int f = 0; f < kFrames; ++f) {
            run.sceneView->setViewMatrix(orbitView(run.n, f));
            ++frameNumber;
            run.frameStamp->setFrameNumber(frameNumber);
            run.frameStamp->setReferenceTime(frameNumber / 60.0);
            run.frameStamp->setSimulationTime(frameNumber / 60.0);

            const auto t0 = Clock::now();
            run.sceneView->cull();
            const auto t1 = Clock::now();

            if (pass == 0 && f == 0 && !checkInherited(*run.sceneView, kFrustumCulling)) return false;

#ifdef SGBENCH_WITH_SGKIT
            if (run.sgkit.scene) cullSgkit(run.sgkit, run.n, f, timed, msBetween(t0, t1));
#endif
            if (timed) {
                run.frameMs.push_back(msBetween(t0, t1));
                const DrawCount dc = countStage(*run.sceneView->getRenderStage(), run.scene);
                run.geometriesSum += double(dc.leaves);
                run.trianglesSum += double(dc.triangles);
            }
        }
    }
    return true;
}

void printJson(const CullRun& run, double geometriesMean, double timedFrames) {
    std::printf(
        "{\"peer\":\"openscenegraph\",\"osg_version\":\"%s\",\"n\":%d,\"path\":\"orbit\","
        "\"frames\":%d,\"cull_ms_median\":%.4f,\"cull_ms_p95\":%.4f,"
        "\"geometries_mean\":%.2f,\"triangles_mean\":%.1f,\"build_s\":%.4f,"
        "\"rss_mb\":%.2f,\"nodes\":%llu,\"bytes_per_node\":%.2f",
        osgGetVersion(), run.n, kFrames, median(run.frameMs), percentile95(run.frameMs), geometriesMean,
        run.trianglesSum / timedFrames, run.buildSeconds, run.rssAfter / (1024.0 * 1024.0),
        (unsigned long long)run.scene.nodes, (run.rssAfter - run.rssBefore) / double(run.scene.nodes));
#ifdef SGBENCH_WITH_SGKIT
    const SgkitCull& peer = run.sgkit;
    if (peer.scene)
        std::printf(
            ",\"sgkit_cull_ms_median\":%.4f,\"sgkit_geometries_mean\":%.2f,\"osg_over_sgkit_per_frame_median\":%.3f",
            median(peer.ms), peer.geometries / double(peer.ms.size()), median(peer.ratio));
#endif
    std::printf("}\n");
}

}  // namespace

int runCull(int n, int passes, bool withSgkit) {
    CullRun run;
    run.n = n;
    build(run);

#ifdef SGBENCH_WITH_SGKIT
    if (withSgkit) {
        run.sgkit.scene = std::make_unique<sg::Scene>(scenes::buildCity({n, false}));
        run.sgkit.scene->update();
    }
#else
    if (withSgkit) usage("--with-sgkit: this build has no sgkit (configure it inside the sgkit project)");
#endif

    run.frameStamp = new osg::FrameStamp;
    run.sceneView = makeSceneView(run.scene.root.get(), run.frameStamp.get(), kNear, kFrustumCulling);
    if (!cullFrames(run, passes)) return 1;

    const double timedFrames = double(run.frameMs.size());
    const double geometriesMean = run.geometriesSum / timedFrames;
    if (geometriesMean <= 0.0) {
        std::fprintf(stderr, "error: the cull produced no draw leaves on the orbit path\n");
        return 1;
    }
    printJson(run, geometriesMean, timedFrames);
    std::fflush(stdout);
    return 0;
}

}  // namespace osgbench
