// cityview: the `city` scene in a real window (GLFW) through sg::Viewer: the orbit path (docs/scenes.md) plays until
// the window is closed or Escape is pressed; space pauses; the stage times go to the terminal once a second.
//   cityview [--n N] [--frames F]   (F > 0: stop after F frames, for scripted runs under xvfb-run)
#include "sg/gl/GlfwWindow.h"
#include "sg/viewer/Viewer.h"
#include "testbed/City.h"

#include <cstdio>
#include <cstdlib>
#include <string>

int main(int argc, char** argv) try {
    using namespace sg;
    int n = 100, frames = 0;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string k = argv[i];
        if (k == "--n")
            n = std::max(1, std::atoi(argv[i + 1]));
        else if (k == "--frames")
            frames = std::max(0, std::atoi(argv[i + 1]));
    }
    GlfwWindow window(1280, 720, "sgkit cityview");
    Scene scene(scenes::buildCity({n, false}));
    ViewerSettings vs;
    vs.clock = [&] { return window.time(); };
    Viewer viewer(scene, vs);
    View& view = viewer.addView();
    bool paused = false;
    window.setKeyCallback([&](int key, int action, int) {
        if (action != 1) return;          // GLFW_PRESS
        if (key == 256) window.close();   // GLFW_KEY_ESCAPE
        if (key == 32) paused = !paused;  // GLFW_KEY_SPACE
    });
    int path = 0;
    double lastReport = window.time();
    viewer.onEvents([&] {
        window.pollEvents();
        if (window.shouldClose()) viewer.setDone();
    });
    viewer.onApp([&](const FrameInfo&) {
        if (!paused) path = (path + 1) % scenes::kOrbitFrames;
        view.camera = scenes::cityOrbitCamera(n, path, window.width(), window.height());
    });
    viewer.onPresent([&] {
        window.swapBuffers();
        const int shown = int(viewer.frameNumber()) + 1;
        if (window.time() - lastReport > 1.0 || (frames && shown == frames)) {
            const StageTimes m = viewer.history().mean();
            std::printf("frame %d: %llu geometries, %llu triangles, cull %.2f ms, draw %.2f ms, %.1f fps\n", shown,
                        (unsigned long long)view.cullStats().geometries, (unsigned long long)view.cullStats().triangles,
                        m.cullMs, m.drawMs, viewer.history().rate());
            lastReport = window.time();
        }
        if (frames && shown >= frames) viewer.setDone();
    });
    viewer.run();
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "cityview: %s\n", e.what());
    return 1;
}
