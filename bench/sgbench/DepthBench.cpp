// sgbench depth: what reverse-Z costs against the classic depth buffer. The same city orbit views are drawn in
// both modes, alternating in blocks in one process (the machine's drift hits both), at 1280x720: whole-frame
// draw time, the time of an empty frame (clear, and for reverse-Z the colour blit to the context's
// framebuffer), and the pixels that differ between the two modes' images.
#include "sg/cull/CullTraversal.h"
#include "sg/gl/KeepFreedMemory.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sgbench/Bench.h"
#include "testbed/City.h"

#include <chrono>
#include <stdexcept>

namespace bench {

int runDepth(const Args& a) {
    const int n = int(a.num("n", 100)), rounds = int(a.num("rounds", 6));
    if (n < 1 || n > 1000)
        throw std::invalid_argument("sgbench depth: --n " + std::to_string(n) + " is not in 1..1000");
    if (rounds < 1) throw std::invalid_argument("sgbench depth: --rounds must be at least 1");
    using Mode = sg::Renderer::DepthMode;
    sg::OsmesaContext ctx(1280, 720);
    sg::Renderer renderer;
    if (renderer.softwareRasterizer()) sg::keepFreedMemory();  // as a frame loop does (sg/gl/KeepFreedMemory.h)
    if (!renderer.reverseZSupported())
        throw std::runtime_error("sgbench depth: the context has no glClipControl: reverse-Z is not available");
    scenes::CityOptions opt;
    opt.n = n;
    sg::Scene scene(scenes::buildCity(opt));
    scene.update();
    sg::CullTraversal cull;
    std::vector<sg::DrawList> lists;
    std::vector<sg::Camera> cams;
    for (int v = 0; v < scenes::kOrbitFrames; v += scenes::kOrbitFrames / 6) {
        cams.push_back(scenes::cityOrbitCamera(n, v));
        lists.emplace_back();
        sg::CullStats st;
        cull.cull(scene, cams.back(), sg::CullSettings{}, lists.back(), st);
    }
    auto timed = [&](const sg::DrawList& list, const sg::Camera& cam) {
        const auto t0 = std::chrono::steady_clock::now();
        renderer.draw(list, cam);
        renderer.finish();
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    };
    std::vector<double> frame[2], empty[2];
    uint64_t differing = 0;
    for (int r = 0; r < rounds; ++r)
        for (int m = 0; m < 2; ++m) {
            renderer.setDepthMode(m ? Mode::ReverseZ : Mode::Classic);
            for (size_t v = 0; v < cams.size(); ++v) {
                timed(lists[v], cams[v]);  // the mode's first frame after a switch is not timed
                frame[m].push_back(timed(lists[v], cams[v]));
                empty[m].push_back(timed(sg::DrawList{}, cams[v]));
            }
        }
    for (size_t v = 0; v < cams.size(); ++v) {
        renderer.setDepthMode(Mode::Classic);
        renderer.draw(lists[v], cams[v]);
        const sg::Image classic = renderer.readColor();
        renderer.setDepthMode(Mode::ReverseZ);
        renderer.draw(lists[v], cams[v]);
        differing += sg::countDifferingPixels(classic, renderer.readColor(), 0);
    }
    Json j;
    j.add("command", "depth").addInt("n", n).addInt("views", long(cams.size())).addInt("rounds", rounds);
    j.add("frame_ms_median_classic", median(frame[0])).add("frame_ms_median_reverse_z", median(frame[1]));
    j.add("frame_ratio_reverse_z", median(frame[1]) / median(frame[0]));
    j.add("empty_frame_ms_median_classic", median(empty[0])).add("empty_frame_ms_median_reverse_z", median(empty[1]));
    j.addInt("pixels_differing", long(differing))
        .add("pixels_differing_pct", 100.0 * double(differing) / (1280.0 * 720.0 * double(cams.size())));
    j.print(a);
    return 0;
}

}  // namespace bench
