#include "testbed/LodRun.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace scenes {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

void checkBudget(double budgetMs, const char* fn) {
    if (!(budgetMs > 0.0 && std::isfinite(budgetMs)))
        throw std::invalid_argument(std::string(fn) + ": budget " + std::to_string(budgetMs) +
                                    " ms is not a positive time");
}
}  // namespace

std::vector<double> timeSameView(sg::Renderer& renderer, sg::Scene& scene, const sg::Camera& cam, int draws) {
    sg::CullTraversal cull;
    sg::DrawList list;
    sg::CullStats st;
    std::vector<double> ms;
    for (int i = 0; i < draws + 3; ++i) {
        const auto t0 = Clock::now();
        cull.cull(scene, cam, sg::CullSettings{}, list, st);
        renderer.draw(list, cam);
        renderer.finish();
        if (i >= 3) ms.push_back(msSince(t0));
    }
    return ms;
}

LodRun::LodRun(sg::Renderer& renderer, const Settings& s) : renderer_(renderer), set_(s) {
    checkBudget(s.budgetMs, "LodRun::LodRun()");
}

const sg::View& LodRun::view() const {
    static const sg::View none;
    return viewer_ ? viewer_->view() : none;
}

const LodFrame& LodRun::frame(sg::Scene& scene, const sg::Camera& cam, const std::function<void()>& prepare) {
    checkBudget(set_.budgetMs, "LodRun::frame()");
    if (!viewer_) {
        viewer_ = std::make_unique<sg::Viewer>(scene, renderer_);
        viewer_->addView();
        viewer_->onApp([this](const sg::FrameInfo&) {
            if (prepare_) prepare_();
        });
        for (const auto& f : setup_) f(*viewer_);
    }
    viewer_->setScene(scene);  // the same scene: nothing happens (another one: the frames in flight are drawn first)
    sg::ViewerSettings& vs = viewer_->settings();
    vs.phase = set_.limitRate ? sg::FramePhase::Limit : sg::FramePhase::FreeRun;
    vs.frameRate = 1000.0 / set_.budgetMs;
    vs.threading = set_.threading;
    vs.bindContext = set_.bindContext;
    sg::View& v = viewer_->view();
    v.camera = cam;
    v.cull = set_.cull;
    v.cull.lodBudget.mayDrop = set_.mayDrop;
    v.lod = set_.method;
    v.lodBudgetMs = set_.budgetMs;
    prepare_ = prepare;
    viewer_->frame();
    prepare_ = nullptr;
    collect();
    return last_;
}

void LodRun::collect() {
    if (!viewer_ || viewer_->framesDrawn() == 0) return;  // threaded: nothing drawn yet
    const sg::View& v = viewer_->view();
    const sg::StageTimes& t = viewer_->lastFrame();
    last_.cullMs = t.appMs + t.pagerMs + t.updateMs + t.cullMs;
    last_.drawMs = t.drawMs;
    last_.gpuMs = v.gpuMs();
    last_.workMs = last_.cullMs + last_.drawMs;
    last_.frameMs = set_.limitRate ? t.frameMs : last_.workMs;
    last_.stats = v.cullStats();
}

const LodFrame& LodRun::flush() {
    if (viewer_) viewer_->flush();
    collect();
    return last_;
}

const LodFrame& LodRun::stopThreads() {
    if (viewer_) viewer_->stopThreads();
    collect();
    return last_;
}

void LodRun::onViewer(std::function<void(sg::Viewer&)> f) {
    if (viewer_) f(*viewer_);
    setup_.push_back(std::move(f));
}

void LodRun::run(sg::Scene& scene, int count, int warmup, const std::function<sg::Camera(int)>& cameraAt,
                 const std::function<void(int)>& prepare, const std::function<void(int, const LodFrame&)>& recorded) {
    auto one = [&](int i) -> const LodFrame& {
        if (!prepare) return frame(scene, cameraAt(i));
        return frame(scene, cameraAt(i), [&] { prepare(i); });
    };
    for (int i = 0; i < std::min(count, warmup); ++i) one(i);
    for (int i = 0; i < count; ++i) {
        one(i);
        // Threaded, frame i is drawn a frame or two later: each record waits for its own frame.
        const LodFrame& f = set_.threading == sg::ThreadingModel::SingleThreaded ? last_ : flush();
        if (recorded) recorded(i, f);
    }
}

}  // namespace scenes
