// cityflight: the headless demo. Builds the `city` benchmark scene, flies its orbit path through sg::Viewer
// (update, cull, draw) rendered offscreen, writes the last frame to a PNG and prints a stats table.
//   cityflight [--n N] [--frames F] [--size WxH] [--out city.png] [--strategy S]
#include "nodes/Transform.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/viewer/Viewer.h"
#include "testbed/City.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

using namespace sg;

int main(int argc, char** argv) {
    int n = 100, frames = 24, w = 960, h = 540;
    std::string out = "city.png", strategy = "aabb";
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string k = argv[i], v = argv[i + 1];
        if (k == "--n")
            n = std::max(1, std::atoi(v.c_str()));
        else if (k == "--frames")
            frames = std::max(1, std::atoi(v.c_str()));
        else if (k == "--size" && std::sscanf(v.c_str(), "%dx%d", &w, &h) == 2) {
        } else if (k == "--out")
            out = v;
        else if (k == "--strategy")
            strategy = v;
        else {
            std::fprintf(stderr, "cityflight: unknown option %s\n", k.c_str());
            return 2;
        }
    }
    try {
        const auto t0 = std::chrono::steady_clock::now();
        Scene scene(scenes::buildCity({n, false}));
        scene.update();
        const double buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        OsmesaContext ctx(w, h);
        Viewer viewer(scene);
        View& view = viewer.addView();
        view.cull.strategy = parseStrategy(strategy);
        std::vector<double> cullMs, drawMs, geoms, tris, calls;
        for (int f = 0; f < frames; ++f) {
            // The city's orbit path (docs/scenes.md), sampled evenly over the frames shown.
            view.camera = scenes::cityOrbitCamera(n, f * scenes::kOrbitFrames / frames, w, h);
            viewer.frame();  // finished: the draw time is real
            cullMs.push_back(view.cullStats().ms);
            drawMs.push_back(view.renderStats().ms);
            geoms.push_back(double(view.cullStats().geometries));
            tris.push_back(double(view.cullStats().triangles));
            calls.push_back(double(view.renderStats().drawCalls));
        }
        // The picture: one more frame from above the city's corner, looking across it.
        const double size = 20.0 * n;
        view.camera.setPerspective(60, double(w) / h, 1, 3000);
        view.camera.setLookAt(dvec3(-0.05 * size, -0.05 * size, 120), dvec3(0.35 * size, 0.35 * size, 0),
                              dvec3(0, 0, 1));
        viewer.frame();
        savePng(out, viewer.renderer().readColor());
        auto mean = [](const std::vector<double>& v) {
            double s = 0;
            for (double x : v) s += x;
            return s / double(v.size());
        };
        std::printf("cityflight: city N=%d (%zu image entries), %d frames at %dx%d, strategy %s\n", n,
                    scene.image().size(), frames, w, h, strategy.c_str());
        std::printf("  %-28s %10.1f\n", "scene build + update (ms)", buildMs);
        std::printf("  %-28s %10.3f\n", "cull per frame (ms, mean)", mean(cullMs));
        std::printf("  %-28s %10.3f\n", "draw submit (ms, mean)", mean(drawMs));
        std::printf("  %-28s %10.0f\n", "geometries per frame", mean(geoms));
        std::printf("  %-28s %10.0f\n", "triangles per frame", mean(tris));
        std::printf("  %-28s %10.0f\n", "draw calls per frame", mean(calls));
        std::printf("  wrote %s\n", out.c_str());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "cityflight: %s\n", e.what());
        return 1;
    }
}
