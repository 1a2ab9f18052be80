#include "testbed/LodRun.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <thread>

namespace scenes {

namespace {
using Clock = std::chrono::steady_clock;
constexpr double kMissFrames = 10.0;    // the budget's miss is smoothed over about this many frames
constexpr double kMaxMissShare = 0.2;   // and comes off its plan up to this share of the budget
constexpr double kOverrunShare = 0.15;  // the most an upgrade worth four times the usual may overrun the plan
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// Sleeps to within half a millisecond of `t` (a sleep can overrun by a tenth of one), then spins the rest:
// a frame rate held to a tenth of a millisecond, at the cost of a spin the renderer's threads never share.
void waitUntil(Clock::time_point t) {
    const auto early = t - std::chrono::microseconds(500);
    if (Clock::now() < early) std::this_thread::sleep_until(early);
    while (Clock::now() < t) {
    }
}

sg::LodStress::Params stressFor(double budgetMs) {
    if (!(budgetMs > 0.0 && std::isfinite(budgetMs)))
        throw std::invalid_argument("LodRun::LodRun(): budget " + std::to_string(budgetMs) +
                                    " ms is not a positive time");
    sg::LodStress::Params p;
    p.budgetMs = budgetMs;
    return p;
}
}  // namespace

const char* lodMethodName(LodMethod m) {
    switch (m) {
        case LodMethod::Static: return "static";
        case LodMethod::Stress: return "stress";
        case LodMethod::Budget: return "budget";
    }
    return "?";
}

LodMethod parseLodMethod(const std::string& name) {
    for (LodMethod m : {LodMethod::Static, LodMethod::Stress, LodMethod::Budget})
        if (name == lodMethodName(m)) return m;
    throw std::invalid_argument("parseLodMethod(): '" + name + "' is not a method (static, stress, budget)");
}

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

LodRun::LodRun(sg::Renderer& renderer, const Settings& s)
    : renderer_(renderer), set_(s), stress_(stressFor(s.budgetMs)) {}

const LodFrame& LodRun::frame(sg::Scene& scene, const sg::Camera& cam, const std::function<void()>& prepare) {
    if (!(set_.budgetMs > 0.0) || !std::isfinite(set_.budgetMs))
        throw std::invalid_argument("LodRun::frame(): the budget is not a positive number of milliseconds");
    sg::CullSettings set = set_.cull;
    if (set_.method == LodMethod::Stress) set.lodScale = stress_.scale();
    if (set_.method == LodMethod::Budget) {
        set.lodBudget.enabled = true;
        set.lodBudget.model = &model_;
        // The cull's own time comes off, and with a held frame rate the plan's usual miss.
        set.lodBudget.budgetMs =
            std::max(1.0, set_.budgetMs - last_.cullMs -
                              (set_.limitRate ? std::min(missMs_, kMaxMissShare * set_.budgetMs) : 0.0));
        set.lodBudget.mayDrop = set_.mayDrop;
        set.lodBudget.coarsestScale = stress_.params().maxScale;  // never a worse picture than stress's
        set.lodBudget.finestScale = set.lodScale;    // never finer than the ranges (at a pixel's error): no one sees it
        set.lodBudget.overrunShare = kOverrunShare;  // a frame late anyway still buys the detail it needs most
    }
    const auto t0 = Clock::now();
    if (prepare) prepare();
    cull_.cull(scene, cam, set, list_, last_.stats);
    last_.cullMs = msSince(t0);
    const auto t1 = Clock::now();
    renderer_.draw(list_, cam);
    renderer_.finish();
    last_.drawMs = msSince(t1);
    last_.workMs = last_.cullMs + last_.drawMs;
    if (set_.method == LodMethod::Stress) stress_.update(last_.workMs);
    const sg::CullStats& st = last_.stats;
    model_.update({double(st.triangles), double(st.geometries), st.lodPixels}, last_.drawMs);
    // The plan's own prediction against the measured time: the loop closes on what the budget planned
    // (a frame with no LOD in view was not planned).
    if (set_.method == LodMethod::Budget && st.lodObjects > 0) {
        model_.correct(st.lodPredictedMs, last_.drawMs);
        missMs_ += (std::max(0.0, last_.drawMs - st.lodPredictedMs) - missMs_) / kMissFrames;  // overruns only
    }
    if (set_.limitRate)
        waitUntil(
            t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double, std::milli>(set_.budgetMs)));
    last_.frameMs = set_.limitRate ? msSince(t0) : last_.workMs;
    return last_;
}

void LodRun::run(sg::Scene& scene, int count, int warmup, const std::function<sg::Camera(int)>& cameraAt,
                 const std::function<void(int)>& prepare, const std::function<void(int, const LodFrame&)>& recorded) {
    auto one = [&](int i) -> const LodFrame& {
        if (!prepare) return frame(scene, cameraAt(i));
        return frame(scene, cameraAt(i), [&] { prepare(i); });
    };
    for (int i = 0; i < std::min(count, warmup); ++i) one(i);
    for (int i = 0; i < count; ++i) {
        const LodFrame& f = one(i);
        if (recorded) recorded(i, f);
    }
}

}  // namespace scenes
