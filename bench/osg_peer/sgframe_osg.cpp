// sgframe_osg: whole frames of the `city` orbit (shared/bench city.md) drawn by OpenSceneGraph's osgViewer::Viewer in
// a 1280x720 window (GLX; Xvfb where there is no display), each frame's update, cull, draw and buffer swap, timed
// from one frame's end to the next's: the OpenSceneGraph side of bench/compare_osg_frame.sh (sgkit's is
// bench/frame/sgframe).
//
// What makes it fair
//   * The scene is the cull peer's (OsgCity.h), with a material per shared mesh in sgkit's city's colours, lit by
//     the viewer's headlight (OSG's default lighting, as sgkit's default): what a user of each gets by default.
//   * Culling as the cull peer's: the six frustum planes, no small-feature culling, no near/far computation.
//   * No swap interval (vsync off) in either program, one warm-up pass of the path before the timed passes.
//
//   sgframe_osg [--n N] [--passes K] [--threading single|draw|cull-draw] [--cull-face 0|1]
//     single     SingleThreaded
//     draw       DrawThreadPerContext (the cull of frame f+1 overlaps the draw of frame f)
//     cull-draw  CullDrawThreadPerContext
//   --cull-face 1: an osg::CullFace (back) on both materials, what an OSG user sets by hand on solids (sgkit skips
//   back faces it can prove hidden by default; bench/frame/sgframe --back-faces all draws them).
// Output: one JSON object on stdout.
#include "OsgCity.h"

#include <osg/CullFace>
#include <osg/Material>
#include <osg/Version>
#include <osgUtil/RenderBin>
#include <osgUtil/RenderStage>
#include <osgUtil/SceneView>
#include <osgUtil/StateGraph>
#include <osgViewer/Renderer>
#include <osgViewer/Viewer>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace {

using namespace osgcity;

// testbed/Stats.h's formulas (this program is built without the testbed): a median is the mean of the two middle
// values, other percentiles nearest-rank.
double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t m = v.size() / 2;
    return (v.size() % 2) ? v[m] : 0.5 * (v[m - 1] + v[m]);
}
double percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t rank = size_t(std::ceil(p * double(v.size())));
    return v[std::min(std::max<size_t>(rank, 1), v.size()) - 1];
}

long argNumber(const char* s, const char* what, long lo, long hi) {
    char* end = nullptr;
    const long v = std::strtol(s, &end, 10);
    if (!end || *end || v < lo || v > hi)
        throw std::invalid_argument(std::string("--") + what + " needs a whole number in " + std::to_string(lo) + ".." +
                                    std::to_string(hi) + ", got '" + s + "'");
    return v;
}

osg::ref_ptr<osg::StateSet> materialState(const osg::Vec4& colour, bool cullFace) {
    osg::ref_ptr<osg::Material> m = new osg::Material;
    m->setDiffuse(osg::Material::FRONT_AND_BACK, colour);
    m->setAmbient(osg::Material::FRONT_AND_BACK, colour * 0.25f);
    osg::ref_ptr<osg::StateSet> s = new osg::StateSet;
    s->setAttribute(m.get());
    if (cullFace) s->setAttributeAndModes(new osg::CullFace(osg::CullFace::BACK), osg::StateAttribute::ON);
    return s;
}

// Draw leaves the last cull left in a scene view's render stage (its state graphs), counted outside the timing.
size_t leaves(const osgUtil::RenderBin& bin) {
    size_t n = bin.getRenderLeafList().size();
    for (const osgUtil::StateGraph* sg : bin.getStateGraphList()) n += sg->_leaves.size();
    for (const auto& child : bin.getRenderBinList()) n += leaves(*child.second);
    return n;
}

}  // namespace

int main(int argc, char** argv) try {
    using Clock = std::chrono::steady_clock;
    int n = 100, passes = 2;
    std::string threading = "single";
    bool cullFace = false;
    for (int i = 1; i < argc; i += 2) {
        const std::string k = argv[i];
        if (i + 1 >= argc) throw std::invalid_argument(k + " needs a value");
        if (k == "--n")
            n = int(argNumber(argv[i + 1], "n", 1, 4000));
        else if (k == "--passes")
            passes = int(argNumber(argv[i + 1], "passes", 1, 1000));
        else if (k == "--threading")
            threading = argv[i + 1];
        else if (k == "--cull-face")
            cullFace = argNumber(argv[i + 1], "cull-face", 0, 1) == 1;
        else
            throw std::invalid_argument("unknown option '" + k +
                                        "' (--n N, --passes K, --threading T, --cull-face 0|1)");
    }
    osgViewer::ViewerBase::ThreadingModel model;
    if (threading == "single")
        model = osgViewer::ViewerBase::SingleThreaded;
    else if (threading == "draw")
        model = osgViewer::ViewerBase::DrawThreadPerContext;
    else if (threading == "cull-draw")
        model = osgViewer::ViewerBase::CullDrawThreadPerContext;
    else
        throw std::invalid_argument("--threading must be single, draw or cull-draw, got '" + threading + "'");

    const auto b0 = Clock::now();
    Meshes meshes = buildMeshes(OccluderKind::None);
    const osg::ref_ptr<osg::StateSet> building = materialState({0.72f, 0.70f, 0.66f, 1.0f}, cullFace);
    for (auto& g : meshes.detailed) g->setStateSet(building.get());
    for (auto& g : meshes.coarse) g->setStateSet(building.get());
    meshes.car->setStateSet(materialState({0.8f, 0.15f, 0.1f, 1.0f}, cullFace).get());
    Scene scene = buildCity(n, meshes, false);
    const double buildS = std::chrono::duration<double>(Clock::now() - b0).count();

    osg::ref_ptr<osg::GraphicsContext::Traits> traits = new osg::GraphicsContext::Traits;
    traits->readDISPLAY();  // $DISPLAY (Xvfb's under xvfb-run), not :0
    traits->x = traits->y = 0;
    traits->width = kViewportW;
    traits->height = kViewportH;
    traits->windowDecoration = false;
    traits->doubleBuffer = true;
    traits->vsync = false;
    traits->depth = 24;
    osg::ref_ptr<osg::GraphicsContext> gc = osg::GraphicsContext::createGraphicsContext(traits.get());
    if (!gc) throw std::runtime_error("cannot create a 1280x720 GLX window (is there a display? run under xvfb-run)");

    osgViewer::Viewer viewer;
    viewer.setThreadingModel(model);
    viewer.setKeyEventSetsDone(0);
    osg::Camera* camera = viewer.getCamera();
    camera->setGraphicsContext(gc.get());
    camera->setViewport(0, 0, kViewportW, kViewportH);
    camera->setProjectionMatrixAsPerspective(kFovY, kAspect, kNear, kFar);
    camera->setCullingMode(osg::CullSettings::VIEW_FRUSTUM_SIDES_CULLING | osg::CullSettings::NEAR_PLANE_CULLING |
                           osg::CullSettings::FAR_PLANE_CULLING);
    camera->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
    camera->setClearColor({0.6f, 0.7f, 0.8f, 1.0f});
    viewer.setSceneData(scene.root.get());
    viewer.realize();
    if (!viewer.isRealized()) throw std::runtime_error("the viewer's window could not be realized");

    auto* renderer = dynamic_cast<osgViewer::Renderer*>(camera->getRenderer());
    std::vector<double> frameMs;
    double geometries = 0;
    Clock::time_point last{};
    const int total = (passes + 1) * kFrames;
    for (int f = 0; f < total; ++f) {
        camera->setViewMatrix(orbitView(n, f % kFrames));
        viewer.frame();
        const Clock::time_point now = Clock::now();
        if (f > kFrames) frameMs.push_back(std::chrono::duration<double, std::milli>(now - last).count());
        last = now;
        // The untimed warm-up pass counts what each frame drew (single-threaded: one scene view culls and draws).
        if (f < kFrames && renderer && model == osgViewer::ViewerBase::SingleThreaded)
            geometries += double(leaves(*renderer->getSceneView(0)->getRenderStage()));
    }
    // Counted only single-threaded (where one scene view culls and draws): null otherwise.
    const std::string counted =
        model == osgViewer::ViewerBase::SingleThreaded ? std::to_string(geometries / kFrames) : "null";
    std::printf(
        "{\"peer\": \"openscenegraph\", \"osg_version\": \"%s\", \"threading\": \"%s%s\", \"n\": %d, \"width\": %d, "
        "\"height\": %d, \"frames\": %zu, \"frame_ms_median\": %.3f, \"frame_ms_p95\": %.3f, \"geometries_mean\": "
        "%s, \"build_s\": %.2f}\n",
        osgGetVersion(), threading.c_str(), cullFace ? "+cullface" : "", n, kViewportW, kViewportH, frameMs.size(),
        median(frameMs), percentile(frameMs, 0.95), counted.c_str(), buildS);
    std::fflush(stdout);
    std::_Exit(0);  // the graph's teardown is quadratic in shared Geometry parents (see sgbench_osg); nothing follows
} catch (const std::exception& e) {
    std::fprintf(stderr, "sgframe_osg: %s\n", e.what());
    return 1;
}
