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

#include <osg/Notify>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "Bench.h"

namespace osgbench {

namespace {

constexpr const char* kUsage =
    "usage: sgbench_osg [--n N] [--frames-passes K] [--with-sgkit]\n"
    "       sgbench_osg --pick [--n N] [--rays-per-frame K]\n"
    "       sgbench_osg --occlusion [--n N] [--path street|orbit] [--frames-passes K] [--with-sgkit] [--json]\n"
    "                   [--osg-occluders box|sides|diagonals] [--osg-max-occluders M] [--osg-min-volume V]\n"
    "                   [--osg-occluder-range R]\n";

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

// Route all OSG notifications to stderr so stdout carries only the results.
class StderrNotifyHandler : public osg::NotifyHandler {
public:
    void notify(osg::NotifySeverity, const char* message) override { std::fputs(message, stderr); }
};

struct Options {
    int n = 0;  // 0: the mode's default
    int passes = 1;
    bool withSgkit = false, occlusion = false, json = false, pick = false;
    int raysPerFrame = 100;
    std::string path;
    OcclusionOptions occ;
    bool occOnly = false;  // an occlusion-only option was given
};

Options parseArgs(int argc, char** argv) {
    Options opt;
    OcclusionOptions& occ = opt.occ;
    for (int a = 1; a < argc; ++a) {
        const bool hasValue = a + 1 < argc;
        if (!std::strcmp(argv[a], "--n") && hasValue)
            opt.n = int(parsePositive(argv[++a], "--n"));
        else if (!std::strcmp(argv[a], "--with-sgkit"))
            opt.withSgkit = true;
        else if (!std::strcmp(argv[a], "--frames-passes") && hasValue)
            opt.passes = int(parsePositive(argv[++a], "--frames-passes"));
        else if (!std::strcmp(argv[a], "--occlusion"))
            opt.occlusion = true;
        else if (!std::strcmp(argv[a], "--pick"))
            opt.pick = true;
        else if (!std::strcmp(argv[a], "--rays-per-frame") && hasValue)
            opt.raysPerFrame = int(parsePositive(argv[++a], "--rays-per-frame"));
        else if (!std::strcmp(argv[a], "--json"))
            opt.json = true;
        else if (!std::strcmp(argv[a], "--path") && hasValue)
            opt.path = argv[++a];
        else if (!std::strcmp(argv[a], "--osg-occluders") && hasValue) {
            const std::string k = argv[++a];
            if (k == "box")
                occ.occluders = osgcity::OccluderKind::Box;
            else if (k == "sides")
                occ.occluders = osgcity::OccluderKind::Sides;
            else if (k == "diagonals")
                occ.occluders = osgcity::OccluderKind::Diagonals;
            else
                usage("--osg-occluders must be box, sides or diagonals");
            opt.occOnly = true;
        } else if (!std::strcmp(argv[a], "--osg-max-occluders") && hasValue) {
            occ.maxOccluders = unsigned(parsePositive(argv[++a], "--osg-max-occluders"));
            opt.occOnly = true;
        } else if (!std::strcmp(argv[a], "--osg-occluder-range") && hasValue) {
            occ.occluderRange = parseNonNegative(argv[++a], "--osg-occluder-range");
            opt.occOnly = true;
        } else if (!std::strcmp(argv[a], "--osg-min-volume") && hasValue) {
            occ.minVolume = parseNonNegative(argv[++a], "--osg-min-volume");
            opt.occOnly = true;
        } else
            usage((std::string("unknown or incomplete argument: ") + argv[a]).c_str());
    }
    return opt;
}

// Checks the options that depend on the mode, then runs the mode.
int runMode(Options& opt) {
    if (opt.pick) {
#ifdef SGBENCH_WITH_SGKIT
        return runPick(opt.n ? opt.n : 316, opt.raysPerFrame);
#else
        usage("--pick: this build has no sgkit (configure it inside the sgkit project)");
#endif
    }
    if (opt.occlusion) {
        const std::string& path = opt.path;
        if (!path.empty() && path != "street" && path != "orbit") usage("--path must be street or orbit");
        opt.occ.n = opt.n ? opt.n : 100;
        opt.occ.passes = opt.passes;
        opt.occ.street = path != "orbit";
        opt.occ.withSgkit = opt.withSgkit;
        opt.occ.json = opt.json;
        return runOcclusion(opt.occ);
    }
    // The cull mode always prints JSON (--json is accepted for symmetry).
    if (!opt.path.empty() && opt.path != "orbit") usage("--path street needs --occlusion");
    if (opt.occOnly)
        usage("--osg-occluders, --osg-max-occluders, --osg-min-volume and --osg-occluder-range need --occlusion");
    return runCull(opt.n ? opt.n : 316, opt.passes, opt.withSgkit);
}

}  // namespace

[[noreturn]] void usage(const char* msg) {
    std::fprintf(stderr, "error: %s\n%s", msg, kUsage);
    std::exit(2);
}

}  // namespace osgbench

int main(int argc, char** argv) {
    osgbench::Options opt = osgbench::parseArgs(argc, argv);

    osg::setNotifyHandler(new osgbench::StderrNotifyHandler);

    const int rc = osgbench::runMode(opt);

    // Skip tearing the scene down. Each shared Geometry keeps its parent Geodes
    // in a std::vector and osg::Node::removeParent erases from it one entry at a
    // time, so destroying the graph is quadratic in the number of instances
    // (minutes at N=1000, where the car Geometry has a million parents). Nothing
    // is measured after this point, so let the OS reclaim the memory.
    std::fflush(stdout);
    std::_Exit(rc);
}
