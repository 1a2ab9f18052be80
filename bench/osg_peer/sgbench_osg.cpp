// sgbench_osg: OpenSceneGraph 3.6 peer for sgkit's cull and occlusion benchmarks.
//
// What it measures
//   Wall-clock time of OpenSceneGraph's cull traversal (osgUtil::SceneView::cull)
//   for the canonical benchmark scene `city` (N x N cells). No graphics context
//   exists and nothing is drawn: only the CPU work a viewer's cull thread
//   performs per frame is timed. SceneView::cull is the same call
//   osgViewer::Renderer makes each frame: it collects the occluders in view
//   (when the scene has any), resets the CullVisitor, RenderStage and
//   StateGraph, traverses the scene (frustum and occluder tests, LOD selection,
//   matrix stack, RenderLeaf/StateGraph construction), sorts the render bins
//   and prunes the state graph.
//
//   Two modes:
//   * cull (default): the `orbit` camera path (120 frames), frustum culling only,
//     the scene without occluders. Output: one JSON object.
//   * --occlusion: the `street` camera path (240 frames; or --path orbit) on
//     the city with occluders (docs/scenes.md), OSG's
//     shadow-volume occlusion culling on, alternating every frame with the same
//     city without occluders and frustum culling only (and with the occluder
//     city with SHADOW_OCCLUSION_CULLING cleared, which shows what collecting
//     the occluders costs on its own). With --with-sgkit, sgkit's cull of its
//     own occluder city alternates with them: frustum only and frustum +
//     occlusion tree (settings as `sgbench occlusion`: mode On, the defaults
//     otherwise). Output: a table, or one JSON object with --json.
//
// What makes it fair
//   * The scene graph follows the shared scene definition exactly: root ->
//     8x8-cell tiles -> cell Group -> {MatrixTransform -> LOD -> 2 Geodes,
//     MatrixTransform -> Geode}, with one shared osg::Geometry per distinct
//     building height and level of detail plus one shared car Geometry.
//   * Culling mode is VIEW_FRUSTUM_SIDES_CULLING | NEAR_PLANE_CULLING |
//     FAR_PLANE_CULLING. OSG's default (DEFAULT_CULLING) tests only the four
//     side planes and additionally enables small-feature, shadow-occlusion and
//     cluster culling; the peer must reject the same things our toolkit rejects
//     (all six frustum planes, nothing else). The occlusion mode adds
//     SHADOW_OCCLUSION_CULLING to exactly these bits.
//   * Compute-near-far is DO_NOT_COMPUTE_NEAR_FAR: the paths use fixed near and
//     far planes, so OSG must not spend time computing (or clamping to)
//     per-drawable depth ranges that our toolkit does not compute.
//   * Bounding spheres are computed during the build (as part of build_s), so
//     neither timed pass pays for lazy bound computation; a full untimed
//     warm-up pass additionally warms caches and OSG's RenderLeaf/StateGraph
//     pools, just as they would be warm in a running viewer.
//   * Verification of the result (counting RenderLeafs and triangles) is done
//     outside the timed region.
//
// Occluders (--occlusion)
//   An osg::OccluderNode holds one osg::ConvexPlanarOccluder (one convex
//   polygon), and OSG tests each occluder's shadow volume on its own: a bound is
//   culled only when it lies entirely inside the shadow of a single polygon.
//   Each building's box Occluder becomes OccluderNodes beside the building's LOD
//   under its MatrixTransform (where sgkit places its Occluder), one per polygon,
//   the polygons shared per building height like the meshes. --osg-occluders
//   picks the polygons:
//     box        the 4 vertical side faces and the roof (5 per building),
//     sides      the 4 vertical side faces,
//     diagonals  the 2 vertical diagonal cross-sections of the box (the default).
//   The diagonals lie inside the box, so they are conservative. They give OSG
//   its best result: from the street a building shows two faces and OSG cannot
//   join two polygons' shadows, while the diagonal facing the eye spans most of
//   the building's outline (12*sqrt(2) m); half the polygons to set up per
//   frame, too. The roof never helps from the street (the eye is below every
//   roof, whose shadow lies above it), so box culls exactly what sides culls.
//   OSG keeps at most --osg-max-occluders active occluders per frame (the
//   largest shadow volumes, after dropping occluders hidden by a larger one;
//   OSG's default 10) and ignores occluders whose shadow volume is below
//   --osg-min-volume of the view frustum's (OSG's default 0.005).
//   OSG computes the shadow volume of every occluder polygon in the view
//   frustum each frame, out to the far plane; --osg-occluder-range R puts a
//   building's OccluderNodes under an osg::LOD active in [0, R) (the
//   collection honours LOD ranges), so only the polygons of nearby buildings
//   are computed. Off (0) by default: the scene is then the built-in city exactly.
//
// Usage
//   sgbench_osg [--n N] [--frames-passes K] [--with-sgkit]
//   sgbench_osg --pick [--n N] [--rays-per-frame K]   (needs a build inside sgkit: the same rays as `sgbench pick`)
//   sgbench_osg --occlusion [--n N] [--path street|orbit] [--frames-passes K] [--with-sgkit] [--json]
//               [--osg-occluders box|sides|diagonals] [--osg-max-occluders M] [--osg-min-volume V]
//               [--osg-occluder-range R]
// --with-sgkit (when built inside the sgkit project) also builds sgkit's city and culls it in the same
// process on every frame: the per-frame time ratios are then free of this machine's speed drift.
//   N: city size (default 316; 100 with --occlusion). K: number of timed passes over the path after the
//   warm-up pass (default 1); statistics are taken over all K*frames frames.
// Output: JSON on stdout (the cull mode always, the occlusion mode with --json); diagnostics on stderr.

#include <osg/CollectOccludersVisitor>
#include <osg/ConvexPlanarOccluder>
#include <osg/FrameStamp>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/Group>
#include <osg/KdTree>
#include <osg/LOD>
#include <osg/MatrixTransform>
#include <osg/Notify>
#include <osg/OccluderNode>
#include <osg/PrimitiveSet>
#include <osg/Version>
#include <osgUtil/CullVisitor>
#include <osgUtil/IntersectionVisitor>
#include <osgUtil/LineSegmentIntersector>
#include <osgUtil/RenderBin>
#include <osgUtil/RenderLeaf>
#include <osgUtil/RenderStage>
#include <osgUtil/SceneView>
#include <osgUtil/StateGraph>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

#include <unistd.h>

#ifdef SGBENCH_WITH_SGKIT
#include "sg/cull/CullTraversal.h"
#include "sg/intersect/IntersectTraversal.h"
#include "sg/intersect/PickSet.h"
#include "testbed/City.h"
#include "testbed/RandomScene.h"

#include <memory>
#endif

#include "OsgCity.h"

namespace {

using namespace osgcity;

// ---------------------------------------------------------------------------
// Verification: walk the render graph the cull produced and count the draw
// leaves (one RenderLeaf per selected Geometry instance) and their triangles.

struct DrawCount {
    uint64_t leaves = 0;
    uint64_t triangles = 0;
};

template <class F>
void forEachLeafInBin(const osgUtil::RenderBin& bin, const F& f) {
    // State-sorted bins keep leaves in their StateGraphs; depth-sorted bins
    // move them to the RenderLeafList. A leaf is in exactly one of the two.
    for (const osgUtil::StateGraph* sg : bin.getStateGraphList())
        for (const auto& leaf : sg->_leaves) f(leaf.get());
    for (const osgUtil::RenderLeaf* leaf : bin.getRenderLeafList()) f(leaf);
    for (const auto& child : bin.getRenderBinList()) forEachLeafInBin(*child.second, f);
}

template <class F>
void forEachLeaf(const osgUtil::RenderStage& stage, const F& f) {
    for (const auto& pre : stage.getPreRenderList()) forEachLeafInBin(*pre.second, f);
    forEachLeafInBin(stage, f);
    for (const auto& post : stage.getPostRenderList()) forEachLeafInBin(*post.second, f);
}

DrawCount countStage(const osgUtil::RenderStage& stage, const Scene& scene) {
    DrawCount out;
    forEachLeaf(stage, [&](const osgUtil::RenderLeaf* leaf) {
        ++out.leaves;
        auto it = scene.meshes->triangles.find(leaf->getDrawable());
        if (it != scene.meshes->triangles.end()) out.triangles += it->second;
    });
    return out;
}

// A draw leaf's identity across two culls of the same frame: the drawable and
// where it is drawn (the translation of its model-view matrix, which both culls
// compute the same way from the same view matrix and transforms).
using LeafKey = std::tuple<const osg::Drawable*, double, double, double>;

std::vector<LeafKey> leafKeys(const osgUtil::RenderStage& stage) {
    std::vector<LeafKey> keys;
    forEachLeaf(stage, [&](const osgUtil::RenderLeaf* leaf) {
        const osg::RefMatrix* mv = leaf->_modelview.get();
        keys.emplace_back(leaf->getDrawable(), mv ? (*mv)(3, 0) : 0.0, mv ? (*mv)(3, 1) : 0.0, mv ? (*mv)(3, 2) : 0.0);
    });
    std::sort(keys.begin(), keys.end());
    return keys;
}

// ---------------------------------------------------------------------------
// Utilities.

double rssBytes() {
    long pages = 0, resident = 0;
    FILE* f = std::fopen("/proc/self/statm", "r");
    if (!f) return 0.0;
    if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
    std::fclose(f);
    return double(resident) * double(sysconf(_SC_PAGESIZE));
}

// Route all OSG notifications to stderr so stdout carries only the results.
class StderrNotifyHandler : public osg::NotifyHandler {
public:
    void notify(osg::NotifySeverity, const char* message) override { std::fputs(message, stderr); }
};

// The same definitions as sgbench's (compare_osg.sh divides one program's median by the other's): the
// median is the mean of the two middle elements for an even count, other percentiles are nearest-rank.
double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t m = v.size() / 2;
    return (v.size() % 2) ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

double percentile95(std::vector<double> v) {
    if (v.empty()) return 0.0;
    // Nearest-rank percentile.
    std::sort(v.begin(), v.end());
    size_t rank = size_t(std::ceil(0.95 * double(v.size())));
    return v[std::max<size_t>(rank, 1) - 1];
}

constexpr const char* kUsage =
    "usage: sgbench_osg [--n N] [--frames-passes K] [--with-sgkit]\n"
    "       sgbench_osg --pick [--n N] [--rays-per-frame K]\n"
    "       sgbench_osg --occlusion [--n N] [--path street|orbit] [--frames-passes K] [--with-sgkit] [--json]\n"
    "                   [--osg-occluders box|sides|diagonals] [--osg-max-occluders M] [--osg-min-volume V]\n"
    "                   [--osg-occluder-range R]\n";

[[noreturn]] void usage(const char* msg) {
    std::fprintf(stderr, "error: %s\n%s", msg, kUsage);
    std::exit(2);
}

long parsePositive(const char* s, const char* what) {
    char* end = nullptr;
    long v = std::strtol(s, &end, 10);
    if (!end || *end != '\0' || v <= 0) usage((std::string("invalid value for ") + what).c_str());
    return v;
}

double parseNonNegative(const char* s, const char* what) {
    char* end = nullptr;
    double v = std::strtod(s, &end);
    if (!end || *end != '\0' || !(v >= 0.0)) usage((std::string("invalid value for ") + what).c_str());
    return v;
}

// One flat JSON object, keys in insertion order, or the same fields as a table.
class Json {
public:
    Json& add(const std::string& k, double v, int decimals = 4) {
        char buf[64];
        if (!std::isfinite(v))
            std::snprintf(buf, sizeof buf, "null");
        else
            std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
        kv_.emplace_back(k, buf);
        return *this;
    }
    Json& addInt(const std::string& k, long long v) {
        kv_.emplace_back(k, std::to_string(v));
        return *this;
    }
    Json& addBool(const std::string& k, bool v) {
        kv_.emplace_back(k, v ? "true" : "false");
        return *this;
    }
    Json& addStr(const std::string& k, const std::string& v) {
        kv_.emplace_back(k, "\"" + v + "\"");
        return *this;
    }
    std::string str() const {
        std::string s = "{";
        for (size_t i = 0; i < kv_.size(); ++i) s += (i ? ",\"" : "\"") + kv_[i].first + "\":" + kv_[i].second;
        return s + "}";
    }
    const std::vector<std::pair<std::string, std::string>>& fields() const { return kv_; }

private:
    std::vector<std::pair<std::string, std::string>> kv_;
};

// SceneView set up as osgViewer::Renderer would drive it for one camera.
osg::ref_ptr<osgUtil::SceneView> makeSceneView(osg::Node* scene, osg::FrameStamp* frameStamp, double zNear,
                                               unsigned cullingMode) {
    // setDefaults() creates the osg::State (no GL context is touched during
    // cull), the CullVisitor, the StateGraph and the RenderStage, plus the
    // standard global state set and headlight a viewer would also have.
    osg::ref_ptr<osgUtil::SceneView> sv = new osgUtil::SceneView;
    sv->setDefaults();
    sv->setFrameStamp(frameStamp);
    sv->setViewport(0, 0, kViewportW, kViewportH);
    sv->setProjectionMatrix(osg::Matrixd::perspective(kFovY, kAspect, zNear, kFar));
    sv->setSceneData(scene);
    // Cull settings must be set after setDefaults() (which resets them). The
    // SceneView is itself the CullSettings that cull() copies into its
    // CullVisitor (and CollectOccludersVisitor) every frame
    // (inheritCullSettings).
    sv->setCullingMode(cullingMode);
    sv->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
    return sv;
}

// Guard against the settings being silently overridden.
bool checkInherited(const osgUtil::SceneView& sv, unsigned cullingMode) {
    const osgUtil::CullVisitor* cv = sv.getCullVisitor();
    if (unsigned(cv->getCullingMode()) != cullingMode ||
        cv->getComputeNearFarMode() != osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR) {
        std::fprintf(stderr,
                     "error: CullVisitor did not inherit the cull settings "
                     "(mode 0x%x, near/far mode %d)\n",
                     cv->getCullingMode(), int(cv->getComputeNearFarMode()));
        return false;
    }
    return true;
}

constexpr unsigned kFrustumCulling = osg::CullSettings::VIEW_FRUSTUM_SIDES_CULLING |
                                     osg::CullSettings::NEAR_PLANE_CULLING | osg::CullSettings::FAR_PLANE_CULLING;

using Clock = std::chrono::steady_clock;
double msBetween(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

// ---------------------------------------------------------------------------
// Cull mode: the orbit path, frustum culling, the scene without occluders.

int runCull(int n, int passes, bool withSgkit) {
    // --- Build ---------------------------------------------------------------
    const double rssBefore = rssBytes();
    const auto buildStart = Clock::now();
    const Meshes meshes = buildMeshes(OccluderKind::None);
    Scene scene = buildCity(n, meshes, false);
    const auto buildEnd = Clock::now();
    const double rssAfter = rssBytes();
    const double buildSeconds = std::chrono::duration<double>(buildEnd - buildStart).count();

#ifdef SGBENCH_WITH_SGKIT
    // In-process comparison: sgkit's own city, culled right after OpenSceneGraph's on every frame, so
    // that both see the same machine speed (this machine's speed drifts for seconds at a time).
    std::unique_ptr<sg::Scene> sgScene;
    sg::CullTraversal sgCull;
    sg::DrawList sgList;
    std::vector<double> sgMs, ratio;
    double sgGeometries = 0.0;
    if (withSgkit) {
        sgScene = std::make_unique<sg::Scene>(scenes::buildCity({n, false}));
        sgScene->update();
    }
#else
    if (withSgkit) usage("--with-sgkit: this build has no sgkit (configure it inside the sgkit project)");
#endif

    // --- Cull setup ------------------------------------------------------------
    osg::ref_ptr<osg::FrameStamp> frameStamp = new osg::FrameStamp;
    osg::ref_ptr<osgUtil::SceneView> sceneView =
        makeSceneView(scene.root.get(), frameStamp.get(), kNear, kFrustumCulling);

    // --- Warm-up + timed passes -----------------------------------------------
    std::vector<double> frameMs;
    frameMs.reserve(size_t(passes) * kFrames);
    double geometriesSum = 0.0, trianglesSum = 0.0;
    unsigned frameNumber = 0;

    for (int pass = 0; pass <= passes; ++pass) {
        const bool timed = pass > 0;  // pass 0 is the untimed warm-up
        for (int f = 0; f < kFrames; ++f) {
            sceneView->setViewMatrix(orbitView(n, f));
            ++frameNumber;
            frameStamp->setFrameNumber(frameNumber);
            frameStamp->setReferenceTime(frameNumber / 60.0);
            frameStamp->setSimulationTime(frameNumber / 60.0);

            const auto t0 = Clock::now();
            sceneView->cull();
            const auto t1 = Clock::now();

            if (pass == 0 && f == 0 && !checkInherited(*sceneView, kFrustumCulling)) return 1;

#ifdef SGBENCH_WITH_SGKIT
            if (sgScene) {
                const sg::Camera cam = scenes::cityOrbitCamera(n, f);
                sg::CullStats st;
                const auto s0 = Clock::now();
                sgCull.cull(*sgScene, cam, sg::CullSettings{}, sgList, st);
                const auto s1 = Clock::now();
                if (timed) {
                    sgMs.push_back(msBetween(s0, s1));
                    ratio.push_back(msBetween(t0, t1) / msBetween(s0, s1));
                    sgGeometries += double(st.geometries);
                }
            }
#endif
            if (timed) {
                frameMs.push_back(msBetween(t0, t1));
                const DrawCount dc = countStage(*sceneView->getRenderStage(), scene);
                geometriesSum += double(dc.leaves);
                trianglesSum += double(dc.triangles);
            }
        }
    }

    const double timedFrames = double(frameMs.size());
    const double geometriesMean = geometriesSum / timedFrames;
    if (geometriesMean <= 0.0) {
        std::fprintf(stderr, "error: the cull produced no draw leaves on the orbit path\n");
        return 1;
    }

    std::printf(
        "{\"peer\":\"openscenegraph\",\"osg_version\":\"%s\",\"n\":%d,\"path\":\"orbit\","
        "\"frames\":%d,\"cull_ms_median\":%.4f,\"cull_ms_p95\":%.4f,"
        "\"geometries_mean\":%.2f,\"triangles_mean\":%.1f,\"build_s\":%.4f,"
        "\"rss_mb\":%.2f,\"nodes\":%llu,\"bytes_per_node\":%.2f",
        osgGetVersion(), n, kFrames, median(frameMs), percentile95(frameMs), geometriesMean, trianglesSum / timedFrames,
        buildSeconds, rssAfter / (1024.0 * 1024.0), (unsigned long long)scene.nodes,
        (rssAfter - rssBefore) / double(scene.nodes));
#ifdef SGBENCH_WITH_SGKIT
    if (sgScene)
        std::printf(
            ",\"sgkit_cull_ms_median\":%.4f,\"sgkit_geometries_mean\":%.2f,\"osg_over_sgkit_per_frame_median\":%.3f",
            median(sgMs), sgGeometries / double(sgMs.size()), median(ratio));
#endif
    std::printf("}\n");
    std::fflush(stdout);
    return 0;
}

// ---------------------------------------------------------------------------
// Occlusion mode.

struct OcclusionOptions {
    int n = 100;
    int passes = 1;
    bool street = true;
    bool withSgkit = false;
    bool json = false;
    OccluderKind occluders = OccluderKind::Diagonals;
    unsigned maxOccluders = 10;  // OSG's default (CollectOccludersVisitor)
    double minVolume = 0.005;    // OSG's default (CollectOccludersVisitor)
    double occluderRange = 0.0;  // > 0: occluders only within this distance (an LOD around them)
};

// Time stamps that split SceneView::cull: its occluder collection starts with
// CollectOccludersVisitor::reset() and ends right before CullVisitor::reset()
// (removeOccludedOccluders and the hand-over to the CullVisitor included).
struct CullMarks {
    Clock::time_point collectStart, cullStart;
    bool collected = false;
};

class MarkingCollector : public osg::CollectOccludersVisitor {
public:
    explicit MarkingCollector(CullMarks* marks) : marks_(marks) {}
    void reset() override {
        marks_->collectStart = Clock::now();
        marks_->collected = true;
        osg::CollectOccludersVisitor::reset();
    }

private:
    CullMarks* marks_;
};

class MarkingCullVisitor : public osgUtil::CullVisitor {
public:
    MarkingCullVisitor(const osgUtil::CullVisitor& cv, CullMarks* marks) : osgUtil::CullVisitor(cv), marks_(marks) {}
    void reset() override {
        marks_->cullStart = Clock::now();
        osgUtil::CullVisitor::reset();
    }

private:
    CullMarks* marks_;
};

// What one cull configuration produced over the timed frames.
struct Series {
    std::vector<double> ms;
    std::vector<double> collectMs;  // OSG: the occluder collection part of ms
    double geometries = 0.0, triangles = 0.0, occluders = 0.0;
};

int runOcclusion(const OcclusionOptions& o) {
    const int n = o.n;
    const int frames = o.street ? kStreetFrames : kFrames;
    const double zNear = o.street ? kStreetNear : kNear;
    auto view = [&](int f) { return o.street ? streetView(n, f) : orbitView(n, f); };

    // --- Build: the city with occluders, and the same city without them (sharing every mesh) -------
    const auto buildStart = Clock::now();
    const Meshes meshes = buildMeshes(o.occluders);
    Scene occScene = buildCity(n, meshes, true, float(o.occluderRange));
    const auto buildEnd = Clock::now();
    Scene plainScene = buildCity(n, meshes, false);
    const double buildSeconds = std::chrono::duration<double>(buildEnd - buildStart).count();

    // --- Cull setup: one SceneView per configuration, each with its own (warm) render graph pools ---
    osg::ref_ptr<osg::FrameStamp> frameStamp = new osg::FrameStamp;
    const unsigned occlusionMode = kFrustumCulling | osg::CullSettings::SHADOW_OCCLUSION_CULLING;
    struct OsgConfig {
        const char* name;
        Scene* scene;
        unsigned mode;
        osg::ref_ptr<osgUtil::SceneView> sv;
        Series s;
        CullMarks marks;
        std::vector<LeafKey> keys;  // this frame's draw leaves (occlusion and frustum-only configs)
    };
    std::vector<OsgConfig> osgConfigs = {
        {"occlusion", &occScene, occlusionMode, nullptr, {}, {}, {}},
        {"frustum", &plainScene, kFrustumCulling, nullptr, {}, {}, {}},
        {"occluders_ignored", &occScene, kFrustumCulling, nullptr, {}, {}, {}},
    };
    for (OsgConfig& c : osgConfigs) {
        c.sv = makeSceneView(c.scene->root.get(), frameStamp.get(), zNear, c.mode);
        // SceneView::cull collects the occluders in view with this visitor whenever the scene holds
        // OccluderNodes (whatever the culling mode), then hands them to the CullVisitor.
        osg::ref_ptr<osg::CollectOccludersVisitor> cov = new MarkingCollector(&c.marks);
        cov->setMaximumNumberOfActiveOccluders(o.maxOccluders);
        cov->setMinimumShadowOccluderVolume(float(o.minVolume));
        c.sv->setCollectOccludersVisitor(cov.get());
        c.sv->setCullVisitor(new MarkingCullVisitor(*c.sv->getCullVisitor(), &c.marks));
    }
    OsgConfig& osgOcc = osgConfigs[0];
    OsgConfig& osgOff = osgConfigs[1];

#ifdef SGBENCH_WITH_SGKIT
    std::unique_ptr<sg::Scene> sgScene;
    sg::CullSettings sgFrustum;
    sgFrustum.occlusion.mode = sg::OcclusionMode::Off;
    sg::CullSettings sgOcclusion = sgFrustum;
    sgOcclusion.occlusion.mode = sg::OcclusionMode::EveryFrame;
    sgOcclusion.occlusion.method = sg::OcclusionMethod::Tree;
    sg::CullTraversal sgCullFrustum, sgCullOcclusion;  // one per setting, as each keeps per-view state
    sg::DrawList sgList;
    Series sgF, sgO;
    if (o.withSgkit) {
        sgScene = std::make_unique<sg::Scene>(scenes::buildCity({n, true}));
        sgScene->update();
    }
#else
    if (o.withSgkit) usage("--with-sgkit: this build has no sgkit (configure it inside the sgkit project)");
#endif

    // The configurations culled each frame, in an order that rotates from frame to frame so that none
    // always runs first (or right after another one) in a frame.
    std::vector<std::function<void(int, bool)>> steps;
    for (OsgConfig& c : osgConfigs) {
        OsgConfig* cp = &c;
        steps.push_back([cp, &view](int f, bool timed) {
            cp->sv->setViewMatrix(view(f));
            cp->marks.collected = false;
            const auto t0 = Clock::now();
            cp->sv->cull();
            const auto t1 = Clock::now();
            if (!timed) return;
            cp->s.ms.push_back(msBetween(t0, t1));
            if (cp->marks.collected) cp->s.collectMs.push_back(msBetween(cp->marks.collectStart, cp->marks.cullStart));
            const DrawCount dc = countStage(*cp->sv->getRenderStage(), *cp->scene);
            cp->s.geometries += double(dc.leaves);
            cp->s.triangles += double(dc.triangles);
            cp->s.occluders += double(cp->sv->getCullVisitor()->getOccluderList().size());
            cp->keys = leafKeys(*cp->sv->getRenderStage());
        });
    }
#ifdef SGBENCH_WITH_SGKIT
    if (sgScene) {
        const sg::Scene* scene = sgScene.get();
        sg::DrawList* list = &sgList;
        const bool street = o.street;
        auto sgStep = [=](sg::CullTraversal* t, const sg::CullSettings* set, Series* s) {
            return [=](int f, bool timed) {
                const sg::Camera cam = street ? scenes::cityStreetCamera(n, f) : scenes::cityOrbitCamera(n, f);
                sg::CullStats st;
                const auto t0 = Clock::now();
                t->cull(*scene, cam, *set, *list, st);
                const auto t1 = Clock::now();
                if (!timed) return;
                s->ms.push_back(msBetween(t0, t1));
                s->geometries += double(st.geometries);
                s->triangles += double(st.triangles);
                s->occluders += double(st.occludersUsed);
            };
        };
        steps.push_back(sgStep(&sgCullFrustum, &sgFrustum, &sgF));
        steps.push_back(sgStep(&sgCullOcclusion, &sgOcclusion, &sgO));
    }
#endif

    // --- Warm-up + timed passes -----------------------------------------------
    uint64_t notSubset = 0;  // draw leaves of the occlusion cull that the frustum-only cull did not draw
    unsigned frameNumber = 0;
    for (int pass = 0; pass <= o.passes; ++pass) {
        const bool timed = pass > 0;  // pass 0 is the untimed warm-up
        for (int f = 0; f < frames; ++f) {
            ++frameNumber;
            frameStamp->setFrameNumber(frameNumber);
            frameStamp->setReferenceTime(frameNumber / 60.0);
            frameStamp->setSimulationTime(frameNumber / 60.0);
            const size_t first = size_t(frameNumber) % steps.size();
            for (size_t k = 0; k < steps.size(); ++k) steps[(first + k) % steps.size()](f, timed);

            if (pass == 0 && f == 0)
                for (const OsgConfig& c : osgConfigs)
                    if (!checkInherited(*c.sv, c.mode)) return 1;
            if (timed) {
                std::vector<LeafKey> extra;
                std::set_difference(osgOcc.keys.begin(), osgOcc.keys.end(), osgOff.keys.begin(), osgOff.keys.end(),
                                    std::back_inserter(extra));
                notSubset += extra.size();
            }
        }
    }

    const double k = double(osgOcc.s.ms.size());
    if (osgOff.s.geometries <= 0.0) {
        std::fprintf(stderr, "error: the cull produced no draw leaves on the path\n");
        return 1;
    }
    auto perFrame = [](const Series& a, const Series& b) {  // median over frames of a's time / b's time
        std::vector<double> r;
        for (size_t i = 0; i < a.ms.size() && i < b.ms.size(); ++i) r.push_back(a.ms[i] / b.ms[i]);
        return median(r);
    };

    const OsgConfig& osgIgn = osgConfigs[2];
    Json j;
    j.addStr("peer", "openscenegraph").addStr("osg_version", osgGetVersion()).addInt("n", n);
    j.addStr("path", o.street ? "street" : "orbit").addBool("occlusion", true);
    j.addStr("osg_occluders", occluderKindName(o.occluders));
    j.addInt("occluder_polygons_per_building", long(meshes.occluders[0].size()));
    j.addInt("osg_max_active_occluders", o.maxOccluders).add("osg_min_occluder_volume", o.minVolume, 5);
    j.add("osg_occluder_range", o.occluderRange, 1);
    j.addInt("frames", frames).addInt("passes", o.passes);
    j.add("cull_ms_median", median(osgOcc.s.ms)).add("cull_ms_p95", percentile95(osgOcc.s.ms));
    j.add("geometries_mean", osgOcc.s.geometries / k, 2).add("triangles_mean", osgOcc.s.triangles / k, 1);
    j.add("active_occluders_mean", osgOcc.s.occluders / k, 2);
    j.add("occluder_collect_ms_median", median(osgOcc.s.collectMs));
    j.add("occluder_collect_ms_p95", percentile95(osgOcc.s.collectMs));
    j.add("cull_ms_median_no_occlusion", median(osgOff.s.ms))
        .add("cull_ms_p95_no_occlusion", percentile95(osgOff.s.ms));
    j.add("geometries_mean_no_occlusion", osgOff.s.geometries / k, 2);
    j.add("triangles_mean_no_occlusion", osgOff.s.triangles / k, 1);
    j.add("cull_ms_median_occluders_ignored", median(osgIgn.s.ms));
    j.add("cull_ms_p95_occluders_ignored", percentile95(osgIgn.s.ms));
    j.add("triangles_mean_occluders_ignored", osgIgn.s.triangles / k, 1);
    j.add("occlusion_over_frustum_triangles", osgOcc.s.triangles / osgOff.s.triangles);
    j.add("occlusion_over_frustum_cull_per_frame_median", perFrame(osgOcc.s, osgOff.s), 3);
    j.add("occluders_ignored_over_frustum_cull_per_frame_median", perFrame(osgIgn.s, osgOff.s), 3);
    j.addInt("occlusion_leaves_not_in_frustum_set", (long long)notSubset);
    j.add("build_s", buildSeconds).addInt("nodes", (long long)occScene.nodes);
    j.addInt("nodes_no_occlusion", (long long)plainScene.nodes);
#ifdef SGBENCH_WITH_SGKIT
    if (sgScene) {
        j.add("sgkit_cull_ms_median", median(sgO.ms)).add("sgkit_cull_ms_p95", percentile95(sgO.ms));
        j.add("sgkit_geometries_mean", sgO.geometries / k, 2).add("sgkit_triangles_mean", sgO.triangles / k, 1);
        j.add("sgkit_occluders_used_mean", sgO.occluders / k, 2);
        j.add("sgkit_cull_ms_median_no_occlusion", median(sgF.ms));
        j.add("sgkit_cull_ms_p95_no_occlusion", percentile95(sgF.ms));
        j.add("sgkit_geometries_mean_no_occlusion", sgF.geometries / k, 2);
        j.add("sgkit_triangles_mean_no_occlusion", sgF.triangles / k, 1);
        j.add("sgkit_occlusion_over_frustum_triangles", sgO.triangles / sgF.triangles);
        j.add("sgkit_occlusion_over_frustum_cull_per_frame_median", perFrame(sgO, sgF), 3);
        j.add("osg_over_sgkit_per_frame_median", perFrame(osgOcc.s, sgO), 3);
        j.add("osg_over_sgkit_per_frame_median_no_occlusion", perFrame(osgOff.s, sgF), 3);
        j.add("osg_over_sgkit_triangles", osgOcc.s.triangles / sgO.triangles);
    }
#endif

    if (o.json) {
        std::printf("%s\n", j.str().c_str());
    } else {
        std::printf("sgbench_osg --occlusion: city N=%d, %s path, %d frames x %d pass(es), OpenSceneGraph %s\n", n,
                    o.street ? "street" : "orbit", frames, o.passes, osgGetVersion());
        std::printf(
            "OSG occluders: %s (%zu ConvexPlanarOccluder polygons per building), at most %u active, "
            "minimum volume %g, ",
            occluderKindName(o.occluders), meshes.occluders[0].size(), o.maxOccluders, o.minVolume);
        if (o.occluderRange > 0.0)
            std::printf("within %g m (LOD)\n\n", o.occluderRange);
        else
            std::printf("no range limit\n\n");
        std::printf("%-38s %10s %10s %12s %12s %10s\n", "", "cull ms", "p95 ms", "geometries", "triangles",
                    "occluders");
        auto row = [&](const char* name, const Series& s, bool occl) {
            std::printf("%-38s %10.3f %10.3f %12.1f %12.1f", name, median(s.ms), percentile95(s.ms), s.geometries / k,
                        s.triangles / k);
            if (occl) std::printf(" %10.2f", s.occluders / k);
            std::printf("\n");
        };
        row("OSG frustum only (no occluders)", osgOff.s, false);
        row("OSG + shadow-volume occlusion", osgOcc.s, true);
        row("OSG occluders, SHADOW_OCCLUSION off", osgIgn.s, false);
#ifdef SGBENCH_WITH_SGKIT
        if (sgScene) {
            row("sgkit frustum only", sgF, false);
            row("sgkit + occlusion tree", sgO, true);
        }
#endif
        std::printf("\nOSG occluder collection (part of the cull time above): median %.3f ms, p95 %.3f ms\n",
                    median(osgOcc.s.collectMs), percentile95(osgOcc.s.collectMs));
        std::printf("\nper-frame medians of time ratios (same frame, same process):\n");
        std::printf("  OSG occlusion / OSG frustum only            %.3f   (triangles %.3f)\n",
                    perFrame(osgOcc.s, osgOff.s), osgOcc.s.triangles / osgOff.s.triangles);
        std::printf("  OSG occluders ignored / OSG frustum only    %.3f\n", perFrame(osgIgn.s, osgOff.s));
#ifdef SGBENCH_WITH_SGKIT
        if (sgScene) {
            std::printf("  sgkit occlusion / sgkit frustum only        %.3f   (triangles %.3f)\n", perFrame(sgO, sgF),
                        sgO.triangles / sgF.triangles);
            std::printf("  OSG / sgkit, frustum only                   %.3f\n", perFrame(osgOff.s, sgF));
            std::printf("  OSG / sgkit, with occlusion                 %.3f   (triangles %.3f)\n",
                        perFrame(osgOcc.s, sgO), osgOcc.s.triangles / sgO.triangles);
        }
#endif
        std::printf("\nOSG occlusion draw leaves not drawn by OSG frustum only: %llu (expected 0)\n",
                    (unsigned long long)notSubset);
    }
    std::fflush(stdout);
    return 0;
}

#ifdef SGBENCH_WITH_SGKIT
// ---------------------------------------------------------------------------
// Pick mode: the rays of `sgbench pick` (random pixels of the orbit frames, from the near to the far plane),
// each picked by OSG (LineSegmentIntersector, nearest, k-d trees built by osg::KdTreeBuilder) and right after
// by sgkit (IntersectTraversal, nearest), both with the most detailed LOD level (OSG's intersection default).

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
#endif

}  // namespace

int main(int argc, char** argv) {
    int n = 0;
    int passes = 1;
    bool withSgkit = false, occlusion = false, json = false, pick = false;
    int raysPerFrame = 100;
    std::string path;
    OcclusionOptions occ;
    bool occOnly = false;  // an occlusion-only option was given
    for (int a = 1; a < argc; ++a) {
        const bool hasValue = a + 1 < argc;
        if (!std::strcmp(argv[a], "--n") && hasValue)
            n = int(parsePositive(argv[++a], "--n"));
        else if (!std::strcmp(argv[a], "--with-sgkit"))
            withSgkit = true;
        else if (!std::strcmp(argv[a], "--frames-passes") && hasValue)
            passes = int(parsePositive(argv[++a], "--frames-passes"));
        else if (!std::strcmp(argv[a], "--occlusion"))
            occlusion = true;
        else if (!std::strcmp(argv[a], "--pick"))
            pick = true;
        else if (!std::strcmp(argv[a], "--rays-per-frame") && hasValue)
            raysPerFrame = int(parsePositive(argv[++a], "--rays-per-frame"));
        else if (!std::strcmp(argv[a], "--json"))
            json = true;
        else if (!std::strcmp(argv[a], "--path") && hasValue)
            path = argv[++a];
        else if (!std::strcmp(argv[a], "--osg-occluders") && hasValue) {
            const std::string k = argv[++a];
            if (k == "box")
                occ.occluders = OccluderKind::Box;
            else if (k == "sides")
                occ.occluders = OccluderKind::Sides;
            else if (k == "diagonals")
                occ.occluders = OccluderKind::Diagonals;
            else
                usage("--osg-occluders must be box, sides or diagonals");
            occOnly = true;
        } else if (!std::strcmp(argv[a], "--osg-max-occluders") && hasValue) {
            occ.maxOccluders = unsigned(parsePositive(argv[++a], "--osg-max-occluders"));
            occOnly = true;
        } else if (!std::strcmp(argv[a], "--osg-occluder-range") && hasValue) {
            occ.occluderRange = parseNonNegative(argv[++a], "--osg-occluder-range");
            occOnly = true;
        } else if (!std::strcmp(argv[a], "--osg-min-volume") && hasValue) {
            occ.minVolume = parseNonNegative(argv[++a], "--osg-min-volume");
            occOnly = true;
        } else
            usage((std::string("unknown or incomplete argument: ") + argv[a]).c_str());
    }

    osg::setNotifyHandler(new StderrNotifyHandler);

    int rc = 0;
    if (pick) {
#ifdef SGBENCH_WITH_SGKIT
        rc = runPick(n ? n : 316, raysPerFrame);
#else
        usage("--pick: this build has no sgkit (configure it inside the sgkit project)");
#endif
    } else if (occlusion) {
        if (!path.empty() && path != "street" && path != "orbit") usage("--path must be street or orbit");
        occ.n = n ? n : 100;
        occ.passes = passes;
        occ.street = path != "orbit";
        occ.withSgkit = withSgkit;
        occ.json = json;
        rc = runOcclusion(occ);
    } else {
        // The cull mode always prints JSON (--json is accepted for symmetry).
        if (!path.empty() && path != "orbit") usage("--path street needs --occlusion");
        if (occOnly)
            usage("--osg-occluders, --osg-max-occluders, --osg-min-volume and --osg-occluder-range need --occlusion");
        rc = runCull(n ? n : 316, passes, withSgkit);
    }

    // Skip tearing the scene down. Each shared Geometry keeps its parent Geodes
    // in a std::vector and osg::Node::removeParent erases from it one entry at a
    // time, so destroying the graph is quadratic in the number of instances
    // (minutes at N=1000, where the car Geometry has a million parents). Nothing
    // is measured after this point, so let the OS reclaim the memory.
    std::fflush(stdout);
    std::_Exit(rc);
}
