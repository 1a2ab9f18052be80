// sgbench motion: what moving content costs a frame. The city with a crowd of skinned, walking figures (the test
// figure: 20 joints, ~3k triangles) down the street the street camera walks, seen from that street. Frames in turn
// (A B A B ...): every figure moving (the animation player advanced a frame, the update refitting what moved and
// posing every skin, the cull, the draw) and the same frame frozen (nothing advanced: the update finds nothing to do).
// Reports each stage's median, the animation + update + cull per moving figure (--moving K: only K of them walk), and
// the frame ratios moving / frozen with and without llvmpipe's draw; and the pixels a moving frame's cull changes
// against drawing everything (conservative: 0).
#include "nodes/Group.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/KeepFreedMemory.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/io/ImageIO.h"
#include "sg/scene/AnimationPlayer.h"
#include "sg/scene/Scene.h"
#include "sgbench/Bench.h"
#include "testbed/City.h"
#include "testbed/Figure.h"

#include <chrono>
#include <stdexcept>
#include <string>
#include <vector>

namespace bench {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

struct Times {
    double anim = 0, update = 0, cull = 0, draw = 0;
    double noDraw() const { return anim + update + cull; }
    double frame() const { return noDraw() + draw; }
};

}  // namespace

int runMotion(const Args& a) {
    const long figures = a.num("figures", 1000), frames = a.num("frames", 10), n = a.num("n", 100);
    if (figures < 1 || figures > 100000)
        throw std::invalid_argument("sgbench motion: --figures " + std::to_string(figures) + " is not in 1..100000");
    if (frames < 1) throw std::invalid_argument("sgbench motion: --frames must be at least 1");
    if (n < 8 || n > 400) throw std::invalid_argument("sgbench motion: --n " + std::to_string(n) + " is not in 8..400");
    const int w = int(a.num("width", 1280)), h = int(a.num("height", 720));
    const bool drawing = a.num("draw", 1) != 0;  // --draw 0: the stages before the draw alone (for a profiler)
    if (w < 16 || h < 16) throw std::invalid_argument("sgbench motion: --width and --height must be at least 16");

    sg::OsmesaContext ctx(w, h);
    sg::Renderer renderer;
    if (renderer.softwareRasterizer()) sg::keepFreedMemory();
    auto root = sg::make<sg::Group>();
    root->addChild(scenes::buildCity(scenes::CityOptions{int(n)}));
    // Four abreast down the street the street camera walks (x = 20 floor(n / 2)), from 30 m ahead of its start.
    const double street = 20.0 * std::floor(double(n) / 2.0);
    std::vector<sg::ref_ptr<sg::Animation>> walks;
    root->addChild(scenes::makeCrowd(int(figures), sg::dvec3(street - 2.25, 30.0, 0.0), 4, 1.5, walks, {}, true));
    sg::Scene scene(root);
    sg::AnimationPlayer player;
    // --moving K: only the first K figures walk (the update's cost against what moves); default all.
    const long moving = a.num("moving", figures);
    if (moving < 0 || moving > figures)
        throw std::invalid_argument("sgbench motion: --moving " + std::to_string(moving) + " is not in 0..--figures");
    for (size_t i = 0; i < walks.size(); ++i) {
        const size_t k = player.add(walks[i]);
        if (long(i) < moving) player.play(k);
    }

    sg::Camera cam;
    cam.setViewport(w, h);
    cam.setPerspective(60.0, double(w) / double(h), 0.5, 3000.0);
    cam.setLookAt(sg::dvec3(street, 0.0, 1.7), sg::dvec3(street, 100.0, 1.0), sg::dvec3(0, 0, 1));
    sg::CullTraversal cull;
    sg::DrawList list;
    sg::CullStats stats;
    double clock = 0.0;
    uint64_t frameNo = 0;
    auto run = [&](bool moving) {
        Times t;
        auto t0 = Clock::now();
        if (moving) player.advance(1.0 / 30.0);
        t.anim = msSince(t0);
        t0 = Clock::now();
        clock += moving ? 1.0 / 30.0 : 0.0;
        scene.update(sg::FrameInfo{++frameNo, clock});
        t.update = msSince(t0);
        t0 = Clock::now();
        list.clear();
        stats = sg::CullStats{};
        cull.cull(scene, cam, sg::CullSettings{}, list, stats);
        t.cull = msSince(t0);
        t0 = Clock::now();
        if (drawing) {
            renderer.draw(list, cam);
            renderer.finish();
        }
        t.draw = msSince(t0);
        return t;
    };
    run(true);  // uploads and shader variants before the timing
    run(false);
    const sg::UpdateStats& us = scene.lastUpdate();
    std::vector<double> anim, update, cullMs, draw, frozenNoDraw, frozenFrame, ratioNoDraw, ratioFrame, perFigure;
    uint64_t written = 0;
    for (long f = 0; f < frames; ++f) {
        const Times m = run(true);
        written = us.entriesWritten;
        const Times z = run(false);
        anim.push_back(m.anim);
        update.push_back(m.update);
        cullMs.push_back(m.cull);
        draw.push_back(m.draw);
        frozenNoDraw.push_back(z.noDraw());
        frozenFrame.push_back(z.frame());
        ratioNoDraw.push_back(m.noDraw() / z.noDraw());
        ratioFrame.push_back(m.frame() / z.frame());
        perFigure.push_back(m.noDraw() * 1000.0 / double(std::max(1L, moving)));
    }
    // Conservative: a moving frame culled as usual against the same frame drawn with nothing culled.
    run(true);
    renderer.draw(list, cam);
    const sg::Image culled = renderer.readColor();
    sg::CullSettings none;
    none.strategy = sg::CullStrategy::None;
    sg::DrawList all;
    sg::CullStats allStats;
    cull.cull(scene, cam, none, all, allStats);
    renderer.draw(all, cam);
    const sg::Image reference = renderer.readColor();
    const long differing = long(sg::countDifferingPixels(culled, reference, 0));

    Json j;
    j.add("command", "motion").addInt("figures", figures).addInt("moving", moving);
    j.addInt("joints", figures * scenes::kFigureJoints);
    j.addInt("frames", frames).addInt("width", w).addInt("height", h);
    j.addInt("triangles_drawn", long(stats.triangles)).addInt("entries_written_per_update", long(written));
    j.add("anim_ms_median", median(anim)).add("update_ms_median", median(update)).add("cull_ms_median", median(cullMs));
    j.add("anim_update_cull_ms_median", median(anim) + median(update) + median(cullMs));
    j.add("anim_update_cull_us_per_moving_figure", median(perFigure));
    j.add("update_us_per_moving_figure", moving ? median(update) * 1000.0 / double(moving) : 0.0);
    j.add("draw_ms_median", median(draw));
    j.add("frozen_update_cull_ms_median", median(frozenNoDraw)).add("frozen_frame_ms_median", median(frozenFrame));
    j.add("moving_over_frozen_without_draw", median(ratioNoDraw));
    j.add("moving_over_frozen_frame", median(ratioFrame));
    j.addInt("pixels_differing_vs_no_cull", differing);
    j.print(a);
    return differing == 0 ? 0 : 1;
}

}  // namespace bench
