// sgframe: whole frames of the `city` orbit (docs/scenes.md) drawn in a 1280x720 window (GLFW; Xvfb where there is
// no display) by sg::Viewer with its default settings: each frame's events, update, cull, draw and buffer swap,
// timed from one frame's start to the next's. bench/compare_osg_frame.sh runs it alternating with the
// OpenSceneGraph peer's viewer on the same scene and path.
//   sgframe [--n N] [--passes K] [--back-faces auto|all] [--threading single|draw|cull-per-view|app-cull-draw]
// One JSON object on stdout: medians and p95 over K passes after a warm-up pass. --back-faces all draws every back
// face (Renderer::setBackFaceCulling(false)); auto, the default, skips those of closed meshes that cannot show.
#include "sg/gl/GlfwWindow.h"
#include "sg/viewer/Viewer.h"
#include "testbed/City.h"
#include "testbed/Stats.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

long argNumber(const char* s, const char* what, long lo, long hi) {
    char* end = nullptr;
    const long v = std::strtol(s, &end, 10);
    if (!end || *end || v < lo || v > hi)
        throw std::invalid_argument(std::string("--") + what + " needs a whole number in " + std::to_string(lo) + ".." +
                                    std::to_string(hi) + ", got '" + s + "'");
    return v;
}

}  // namespace

int main(int argc, char** argv) try {
    using namespace sg;
    using Clock = std::chrono::steady_clock;
    int n = 100, passes = 2;
    std::string backFaces = "auto";
    ThreadingModel threading = ThreadingModel::SingleThreaded;
    for (int i = 1; i < argc; i += 2) {
        const std::string k = argv[i];
        if (i + 1 >= argc) throw std::invalid_argument(k + " needs a value");
        if (k == "--n")
            n = int(argNumber(argv[i + 1], "n", 1, 4000));
        else if (k == "--passes")
            passes = int(argNumber(argv[i + 1], "passes", 1, 1000));
        else if (k == "--back-faces" && (std::string(argv[i + 1]) == "auto" || std::string(argv[i + 1]) == "all"))
            backFaces = argv[i + 1];
        else if (k == "--threading")
            threading = parseThreadingModel(argv[i + 1]);
        else
            throw std::invalid_argument("unknown option '" + k +
                                        "' (--n N, --passes K, --back-faces auto|all, --threading MODEL)");
    }
    const int w = 1280, h = 720;
    GlfwWindow window(w, h, "sgframe");
    window.setSwapInterval(0);  // as fast as it draws: no wait for a display's refresh
    const auto b0 = Clock::now();
    Scene scene(scenes::buildCity({n, false}));
    const double buildS = std::chrono::duration<double>(Clock::now() - b0).count();
    ViewerSettings vs;
    vs.threading = threading;  // a draw thread takes the window's context (GLFW: any thread may make it current)
    vs.bindContext = [&window](bool current) { current ? window.makeCurrent() : GlfwWindow::release(); };
    Viewer viewer(scene, vs);
    View& view = viewer.addView();
    viewer.renderer().setBackFaceCulling(backFaces == "auto");
    int f = 0;
    viewer.onApp([&](const FrameInfo& fi) {
        view.camera = scenes::cityOrbitCamera(n, int(fi.frame) % scenes::kOrbitFrames, w, h);
    });
    viewer.onPresent([&] { window.swapBuffers(); });

    std::vector<double> frameMs, cullMs, drawMs, gpuMs;
    double geometries = 0, triangles = 0, drawCalls = 0, skipped = 0;
    Clock::time_point last{};
    const int total = (passes + 1) * scenes::kOrbitFrames;
    // Pipelined, the stats read after frame() are those of the last frame drawn (the same count of frames).
    for (f = 0; f < total; ++f) {
        window.pollEvents();
        viewer.frame();
        const Clock::time_point now = Clock::now();
        if (f > scenes::kOrbitFrames) frameMs.push_back(std::chrono::duration<double, std::milli>(now - last).count());
        last = now;
        if (f >= scenes::kOrbitFrames && viewer.framesDrawn() > 0) {
            const StageTimes& t = viewer.lastFrame();
            cullMs.push_back(t.cullMs);
            drawMs.push_back(t.drawMs);
            gpuMs.push_back(t.gpuMs);
            geometries += double(view.cullStats().geometries);
            triangles += double(view.cullStats().triangles);
            drawCalls += double(view.renderStats().drawCalls);
            skipped += double(view.renderStats().backFacesSkipped);
        }
    }
    const double k = double(cullMs.size());
    std::printf(
        "{\"peer\": \"sgkit\", \"threading\": \"%s\", \"back_faces\": \"%s\", \"n\": %d, \"width\": %d, \"height\": "
        "%d, \"frames\": %zu, "
        "\"frame_ms_median\": %.3f, "
        "\"frame_ms_p95\": %.3f, \"cull_ms_median\": %.3f, \"draw_ms_median\": %.3f, \"gpu_ms_median\": %.3f, "
        "\"geometries_mean\": %.1f, \"triangles_mean\": %.1f, \"draw_calls_mean\": %.1f, \"back_faces_skipped_mean\": "
        "%.1f, \"build_s\": %.2f}\n",
        threadingModelName(threading), backFaces.c_str(), n, w, h, frameMs.size(), stats::median(frameMs),
        stats::percentile(frameMs, 0.95), stats::median(cullMs), stats::median(drawMs), stats::median(gpuMs),
        geometries / k, triangles / k, drawCalls / k, skipped / k, buildS);
    viewer.flush();
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "sgframe: %s\n", e.what());
    return 1;
}
