// sgbench frame: whole frames through sg::Viewer with a threading model, interleaved pass by pass with
// SingleThreaded in one run (A B A B ...), headless at 1280x720: per model the frame period (the time between
// frame() calls), each stage's median, the slowest stage (what a pipeline's period is made of) and the latency.
// The city orbit or street path, or the factory's walk with its Switch turning; one view, or two side by side
// (--views 2: the second on the street path); the time budget (--lod budget) or static ranges; a viewpoint
// collider stepping along the path each frame (--collide sync: in the app stage; async: on the ISECT thread).
// --cull-only times two orbit views' culls alone (the second across the city), one after the other and on two threads.
// --app-ms keeps the app stage busy that long each frame (the application's own work). LP_NUM_THREADS=1 in the
// environment gives llvmpipe one rasterizer thread (the other core runs the cull).
#include "sg/gl/KeepFreedMemory.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/viewer/Viewer.h"
#include "sg/viewer/internal/StageThread.h"
#include "sgbench/Bench.h"
#include "testbed/City.h"
#include "testbed/Factory.h"
#include "testbed/FactoryWalk.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace bench {

namespace {

using Clock = std::chrono::steady_clock;

struct Pass {
    std::vector<double> period, app, cull, draw, sync, isect, work;
};

// The medians of one pass, and the stage a pipeline waits on.
struct Figures {
    double period = 0, app = 0, cull = 0, draw = 0, sync = 0, isect = 0, slowest = 0;
};

Figures figures(const Pass& p, sg::ThreadingModel m) {
    Figures f;
    f.period = median(p.period), f.app = median(p.app), f.cull = median(p.cull), f.draw = median(p.draw);
    f.sync = median(p.sync), f.isect = median(p.isect);
    switch (m) {
        case sg::ThreadingModel::SingleThreaded: f.slowest = f.app + f.cull + f.draw; break;
        case sg::ThreadingModel::DrawThread:
        case sg::ThreadingModel::CullThreadPerView: f.slowest = std::max(f.app + f.cull, f.draw); break;
        case sg::ThreadingModel::AppCullDraw: f.slowest = std::max({f.app, f.cull, f.draw}); break;
    }
    return f;
}

// Two views' culls alone, with no draw beside them to compete for the cores: one after the other on one thread, and
// each on a thread of its own as CullThreadPerView runs them (a StageThread for the second), alternating frame by
// frame. The wall time of each way, medians and the median of the per-frame ratios.
void cullPair(const Args& a, const sg::Scene& scene, const std::function<sg::Camera(int)>& first,
              const std::function<sg::Camera(int)>& second, int frames) {
    sg::CullTraversal t0, t1;
    sg::DrawList l0, l1;
    sg::CullStats s0, s1;
    const sg::CullSettings set;
    sg::StageThread worker;
    std::vector<double> seq, par, ratio;
    auto ms = [](Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); };
    for (int i = 0; i < frames + 20; ++i) {
        const sg::Camera c0 = first(i), c1 = second(i);
        auto t = Clock::now();
        t0.cull(scene, c0, set, l0, s0);
        t1.cull(scene, c1, set, l1, s1);
        const double one = ms(t);
        t = Clock::now();
        worker.run([&] { t1.cull(scene, c1, set, l1, s1); });
        t0.cull(scene, c0, set, l0, s0);
        worker.wait();
        const double two = ms(t);
        if (i < 20) continue;  // warm-up
        seq.push_back(one), par.push_back(two), ratio.push_back(two / one);
    }
    Json j;
    j.add("measure", "cull-pair").addInt("frames", frames);
    j.add("sequential_cull_ms", median(seq)).add("parallel_cull_ms", median(par));
    j.add("parallel_over_sequential", median(ratio));
    j.print(a);
}

}  // namespace

int runFrame(const Args& a) {
    const std::string sceneName = a.str("scene", "city");
    if (sceneName != "city" && sceneName != "factory")
        throw std::invalid_argument("sgbench frame: --scene must be city or factory (got '" + sceneName + "')");
    const bool factory = sceneName == "factory";
    const int n = int(a.num("n", 316));
    if (n < 1 || n > 3162)
        throw std::invalid_argument("sgbench frame: --n " + std::to_string(n) + " is not in 1..3162");
    const std::string path = a.str("path", factory ? "walk" : "orbit");
    if (factory ? path != "walk" : path != "orbit" && path != "street")
        throw std::invalid_argument("sgbench frame: --path must be orbit or street for the city, walk for the factory");
    const sg::ThreadingModel model = sg::parseThreadingModel(a.str("threading", "draw"));
    const int frames = int(a.num("frames", 120)), rounds = int(a.num("rounds", 3)), views = int(a.num("views", 1));
    if (frames < 20) throw std::invalid_argument("sgbench frame: --frames must be at least 20");
    if (rounds < 1) throw std::invalid_argument("sgbench frame: --rounds must be at least 1");
    if (views != 1 && views != 2) throw std::invalid_argument("sgbench frame: --views must be 1 or 2");
    const sg::LodPolicy lod = sg::parseLodPolicy(a.str("lod", "static"));
    const double budgetMs = double(a.num("budget-ms", 33));
    const std::string collide = a.str("collide", "none");
    if (collide != "none" && collide != "sync" && collide != "async")
        throw std::invalid_argument("sgbench frame: --collide must be none, sync or async (got '" + collide + "')");
    const int w = int(a.num("width", 1280)), h = int(a.num("height", 720));
    // An application's own work each frame (a simulation, input, networking): the app stage kept busy this long,
    // so that a pipeline has something to overlap with the draw where the cull alone is a small share of it.
    const double appWorkMs = double(a.num("app-ms", 0));
    if (appWorkMs < 0) throw std::invalid_argument("sgbench frame: --app-ms must not be negative");

    // The scene and its path.
    std::unique_ptr<scenes::Factory> site;
    sg::ref_ptr<sg::Node> root;
    if (factory) {
        site = std::make_unique<scenes::Factory>(scenes::buildFactory());
        root = site->root;
    } else {
        root = scenes::buildCity({n, false});
        setLevelErrorsToZero(*root);  // the city's two levels are the same box (sgbench lod)
    }
    sg::Scene scene(root);
    scene.update();
    scenes::WalkPath walk;
    if (factory) walk = scenes::buildWalkPath(*site, scene, frames);
    const int vw = views == 2 ? w / 2 : w;
    auto camera = [&](int i) {
        if (factory) return scenes::pathCamera(walk.frames[size_t(i % frames)], vw, h);
        return path == "orbit" ? scenes::cityOrbitCamera(n, i % scenes::kOrbitFrames, vw, h)
                               : scenes::cityStreetCamera(n, i % scenes::kStreetFrames, vw, h);
    };

    if (a.flag("cull-only")) {  // two views' culls without a draw: the cull's own parallelism
        if (factory) throw std::invalid_argument("sgbench frame: --cull-only is for the city");
        // The second view the orbit's opposite side: two culls of the same size, as two viewers of one city have.
        cullPair(
            a, scene, camera,
            [&](int i) {
                return scenes::cityOrbitCamera(n, (i + scenes::kOrbitFrames / 2) % scenes::kOrbitFrames, vw, h);
            },
            frames);
        return 0;
    }

    sg::OsmesaContext ctx(w, h);
    const int warmup = std::min(20, frames / 4);
    auto pass = [&](sg::ThreadingModel m) {
        sg::ViewerSettings vs;
        vs.threading = m;
        vs.bindContext = [&ctx](bool current) { current ? ctx.makeCurrent() : ctx.release(); };
        vs.historyFrames = size_t(frames + warmup);
        vs.frameRate = 1000.0 / budgetMs;  // the budget's period (a free run: no wait)
        sg::Viewer viewer(scene, vs);
        for (int k = 0; k < views; ++k) {
            sg::View& v = viewer.addView();
            v.lod = lod;
            if (views == 2) v.viewport = {k * vw, 0, vw, h};
        }
        sg::ViewpointSettings cs;
        cs.radius = 0.3;
        sg::ViewpointCollider collider(cs);
        double collideMs = 0.0;
        viewer.onApp([&](const sg::FrameInfo& fi) {
            const auto busyUntil = Clock::now() + std::chrono::microseconds(int64_t(appWorkMs * 1000.0));
            while (Clock::now() < busyUntil) {
            }
            const int i = int(fi.frame);
            if (factory) scenes::setFactoryEye(*site, walk.frames[size_t(i % frames)].workshop);
            viewer.view(0).camera = camera(i);
            if (views == 2)
                viewer.view(1).camera = scenes::cityStreetCamera(std::max(n, 1), i % scenes::kStreetFrames, vw, h);
            if (collide == "none") return;
            // A probe walking the path a frame behind the eye: one swept step per frame.
            const sg::dvec3 from = camera(i).eye(), to = camera(i + 1).eye();
            if (collide == "sync") {
                const auto t0 = Clock::now();
                collider.move(scene, from, to - from);
                collideMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
            } else {
                viewer.isect().move(collider, from, to - from, [](const sg::IsectAnswer&) {});
            }
        });
        Pass p;
        Clock::time_point last{};
        for (int i = 0; i < warmup + frames; ++i) {
            const auto start = Clock::now();
            if (i > warmup) p.period.push_back(std::chrono::duration<double, std::milli>(start - last).count());
            last = start;
            viewer.frame();
            if (i >= warmup) p.isect.push_back(collide == "async" ? viewer.isect().lastMs() : collideMs);
        }
        viewer.flush();
        const sg::FrameHistory& hist = viewer.history();
        for (size_t k = 0; k < hist.size(); ++k) {
            const sg::StageTimes& t = hist.at(k);
            if (t.frame < uint64_t(warmup)) continue;
            p.app.push_back(t.appMs + t.pagerMs + t.updateMs);
            p.cull.push_back(t.cullMs);
            p.draw.push_back(t.drawMs + t.presentMs);
            p.sync.push_back(t.syncMs);
            p.work.push_back(t.workMs);
        }
        if (factory) scenes::setFactoryEye(*site, -1);
        return p;
    };

    std::vector<double> fpsRatio, cullRatio;
    std::vector<Figures> singles, others;
    for (int r = 0; r < rounds; ++r) {
        singles.push_back(figures(pass(sg::ThreadingModel::SingleThreaded), sg::ThreadingModel::SingleThreaded));
        others.push_back(figures(pass(model), model));
        fpsRatio.push_back(singles.back().period / others.back().period);
        cullRatio.push_back(others.back().cull / singles.back().cull);
    }
    auto med = [](const std::vector<Figures>& v, double Figures::*f) {
        std::vector<double> x;
        for (const Figures& g : v) x.push_back(g.*f);
        return median(x);
    };
    Json j;
    j.add("scene", sceneName).addInt("n", factory ? 0 : n).add("path", path).addInt("views", views);
    j.add("threading", sg::threadingModelName(model)).addInt("latency_frames", sg::threadingLatency(model));
    j.add("lod", sg::lodPolicyName(lod))
        .add("collide", collide)
        .add("app_work_ms", appWorkMs)
        .addInt("frames", frames)
        .addInt("rounds", rounds);
    for (auto [name, v] :
         {std::pair<const char*, const std::vector<Figures>*>{"single", &singles}, {"model", &others}}) {
        const std::string p = name;
        j.add(p + "_period_ms", med(*v, &Figures::period));
        j.add(p + "_app_ms", med(*v, &Figures::app));
        j.add(p + "_cull_ms", med(*v, &Figures::cull));
        j.add(p + "_draw_ms", med(*v, &Figures::draw));
        j.add(p + "_sync_ms", med(*v, &Figures::sync));
        j.add(p + "_isect_ms", med(*v, &Figures::isect));
        j.add(p + "_slowest_stage_ms", med(*v, &Figures::slowest));
    }
    j.add("model_period_over_slowest_stage", med(others, &Figures::period) / med(others, &Figures::slowest));
    j.add("fps_ratio_model_over_single", median(fpsRatio));
    j.add("fps_ratio_min", *std::min_element(fpsRatio.begin(), fpsRatio.end()));
    j.add("fps_ratio_max", *std::max_element(fpsRatio.begin(), fpsRatio.end()));
    j.add("cull_wall_ratio_model_over_single", median(cullRatio));
    j.print(a);
    return 0;
}

}  // namespace bench
