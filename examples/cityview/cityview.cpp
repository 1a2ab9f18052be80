// cityview: the `city` scene in a real window (GLFW): the orbit path (docs/scenes.md) plays until the window is
// closed or Escape is pressed; space pauses; the cull and draw figures go to the terminal once a second.
//   cityview [--n N] [--frames F]   (F > 0: stop after F frames, for scripted runs under xvfb-run)
#include "sg/cull/CullTraversal.h"
#include "sg/gl/GlfwWindow.h"
#include "sg/gl/Renderer.h"
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
    Renderer renderer;
    Scene scene(scenes::buildCity({n, false}));
    CullTraversal cull;
    DrawList list;
    bool paused = false;
    window.setKeyCallback([&](int key, int action, int) {
        if (action != 1) return;          // GLFW_PRESS
        if (key == 256) window.close();   // GLFW_KEY_ESCAPE
        if (key == 32) paused = !paused;  // GLFW_KEY_SPACE
    });
    int shown = 0, path = 0;
    double lastReport = window.time(), cullMs = 0, drawMs = 0;
    while (!window.shouldClose() && (frames == 0 || shown < frames)) {
        if (!paused) path = (path + 1) % scenes::kOrbitFrames;
        const Camera cam = scenes::cityOrbitCamera(n, path, window.width(), window.height());
        scene.update({uint64_t(shown), window.time()});
        CullStats st;
        cull.cull(scene, cam, CullSettings{}, list, st);
        renderer.draw(list, cam);
        window.swapBuffers();
        window.pollEvents();
        cullMs += st.ms;
        drawMs += renderer.lastStats().ms;
        ++shown;
        if (window.time() - lastReport > 1.0 || (frames && shown == frames)) {
            std::printf("frame %d: %llu geometries, %llu triangles, cull %.2f ms, draw submit %.2f ms\n", shown,
                        (unsigned long long)st.geometries, (unsigned long long)st.triangles, cullMs / shown,
                        drawMs / shown);
            lastReport = window.time();
        }
    }
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "cityview: %s\n", e.what());
    return 1;
}
