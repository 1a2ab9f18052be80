#include "sg/viewer/Viewer.h"

#include "sg/gl/KeepFreedMemory.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <thread>

namespace sg {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }
double ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }
Clock::duration toDuration(double ms) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double, std::milli>(ms));
}

// Sleeps to within half a millisecond of `t` (a sleep can overrun by a tenth of one), then spins the rest: a
// frame rate held to a tenth of a millisecond, at the cost of a spin the renderer's threads never share.
void waitUntil(Clock::time_point t) {
    const auto early = t - std::chrono::microseconds(500);
    if (Clock::now() < early) std::this_thread::sleep_until(early);
    while (Clock::now() < t) {
    }
}

void checkRate(double rate, const char* fn) {
    if (!(rate > 0.0 && std::isfinite(rate)))
        throw std::invalid_argument(std::string(fn) + ": frameRate " + std::to_string(rate) +
                                    " is not a positive number of frames a second");
}
}  // namespace

const char* framePhaseName(FramePhase p) {
    switch (p) {
        case FramePhase::FreeRun: return "free-run";
        case FramePhase::Limit: return "limit";
        case FramePhase::Lock: return "lock";
    }
    return "?";
}

FramePhase parseFramePhase(const std::string& name) {
    for (FramePhase p : {FramePhase::FreeRun, FramePhase::Limit, FramePhase::Lock})
        if (name == framePhaseName(p)) return p;
    throw std::invalid_argument("parseFramePhase(): '" + name + "' is not a frame phase (free-run, limit, lock)");
}

Viewer::Viewer(Scene& scene, ViewerSettings settings)
    : scene_(&scene), own_(std::make_unique<Renderer>()), renderer_(own_.get()), settings_(std::move(settings)) {
    init();
}

Viewer::Viewer(Scene& scene, Renderer& shared, ViewerSettings settings)
    : scene_(&scene), renderer_(&shared), settings_(std::move(settings)) {
    init();
}

Viewer::~Viewer() = default;

void Viewer::init() {
    checkRate(settings_.frameRate, "Viewer::Viewer()");
    history_ = FrameHistory(settings_.historyFrames);
    keepingFreed_ = settings_.keepFreedMemory && renderer_->softwareRasterizer();
    if (keepingFreed_) keepFreedMemory();
}

View& Viewer::addView(const Camera& camera) {
    views_.push_back(std::make_unique<View>());
    views_.back()->camera = camera;
    return *views_.back();
}

Pager& Viewer::enablePaging(PageLoadFunction load, PagerSettings settings) {
    pager_ = nullptr;
    ownPager_.reset();                                    // the old one's thread stops first
    if (keepingFreed_) settings.trimFreedMemory = false;  // the rasterizer's frames keep the memory they free
    ownPager_ = std::make_unique<Pager>(*scene_, std::move(load), settings);
    pager_ = ownPager_.get();
    return *pager_;
}

void Viewer::usePager(Pager* pager) {
    if (pager != ownPager_.get()) ownPager_.reset();
    pager_ = pager;
}

double Viewer::now() const {
    return settings_.clock ? settings_.clock() : std::chrono::duration<double>(Clock::now() - started_).count();
}

void Viewer::frame() {
    checkRate(settings_.frameRate, "Viewer::frame()");
    const auto start = Clock::now();
    StageTimes t;
    t.frame = frame_;
    t.intervalMs = frame_ ? ms(start - lastStart_) : 0.0;
    lastStart_ = start;
    const FrameInfo info{frame_, now()};

    for (const Callback& f : events_) f();
    for (const FrameCallback& f : app_) f(info);
    t.appMs = msSince(start);
    auto at = Clock::now();
    if (pager_) {
        // A pager without a prepare function of its own has its details uploaded by the renderer within the
        // pager's budget before they are attached (Renderer::prepare), for this update only: the pager may
        // outlive the viewer.
        const bool wire = !pager_->prepare();
        if (wire)
            pager_->setPrepare([r = renderer_](Node& d, PrepareBudget& b) { return r->prepare(d, b); },
                               [r = renderer_](const Node& d) { r->forgetPrepare(d); });
        try {
            pager_->update(info);
        } catch (...) {
            if (wire) pager_->setPrepare({});
            throw;
        }
        if (wire) pager_->setPrepare({});
    }
    t.pagerMs = msSince(at);
    at = Clock::now();
    for (const FrameCallback& f : update_) f(info);
    scene_->update(info);
    t.updateMs = msSince(at);
    cullViews(t);
    drawViews(t);
    t.workMs = msSince(start);
    for (const auto& v : views_)
        if (v->enabled) v->learn(t.workMs, v->lod != LodPolicy::Static || settings_.finish);
    spentMs_ = t.appMs + t.pagerMs + t.updateMs + t.cullMs;
    wait(start, t);
    at = Clock::now();
    for (const Callback& f : present_) f();
    t.presentMs = msSince(at);
    t.frameMs = msSince(start);
    if (frame_ == 0) t.intervalMs = t.frameMs;
    history_.push(t);
    ++frame_;
}

void Viewer::run() {
    while (!done_) frame();
}

void Viewer::cullViews(StageTimes& t) {
    const auto start = Clock::now();
    const bool held = settings_.phase != FramePhase::FreeRun;
    for (const auto& v : views_) {
        if (!v->enabled) continue;
        const auto at = Clock::now();
        const CullSettings set = v->frameSettings(periodMs(), spentMs_, held);
        v->traversal_.cull(*scene_, v->camera, set, v->list_, v->stats_);
        v->cullMs_ = msSince(at);
    }
    t.cullMs = msSince(start);
}

// Each view into its viewport; a view whose policy learns from its draw is finished before the next is drawn, so
// that its time is its own. The overlay goes over them all.
void Viewer::drawViews(StageTimes& t) {
    const auto start = Clock::now();
    int width = 0, height = 0;  // what the views cover, for the overlay
    for (const auto& v : views_) {
        if (!v->enabled) continue;
        const auto at = Clock::now();
        if (v->viewport.width > 0 && v->viewport.height > 0) {
            renderer_->draw(v->list_, v->camera, v->viewport, v->clearColor);
            width = std::max(width, v->viewport.x + v->viewport.width);
            height = std::max(height, v->viewport.y + v->viewport.height);
        } else {
            renderer_->draw(v->list_, v->camera, v->clearColor);
            width = std::max(width, v->camera.width());
            height = std::max(height, v->camera.height());
        }
        v->render_ = renderer_->lastStats();
        const bool finished = v->lod != LodPolicy::Static || settings_.finish;
        if (finished) renderer_->finish();
        v->drawMs_ = msSince(at);
        v->gpuMs_ = finished ? renderer_->gpuMs() : -1.0;
        if (v->gpuMs_ >= 0.0) t.gpuMs += v->gpuMs_;
    }
    if (overlay && width > 0 && height > 0) {
        if (!text_) text_ = std::make_unique<TextOverlay>();
        text_->draw(statsText(), width, height, width >= 960 && height >= 480 ? 2.0f : 1.0f);
    }
    for (const Callback& f : overlayCallbacks_) f();
    if (settings_.finish) renderer_->finish();
    t.drawMs = msSince(start);
}

// The phase's wait, counted only when there is one (a free run, or a frame late for its limit, waits not at all).
void Viewer::wait(Clock::time_point start, StageTimes& t) {
    const auto at = Clock::now();
    const Clock::duration period = toDuration(periodMs());
    Clock::time_point until = at;
    if (settings_.phase == FramePhase::Limit) {
        until = start + period;
    } else if (settings_.phase == FramePhase::Lock) {
        // The ticks run from the first locked frame's start; a frame waits for the first tick after its work.
        if (tick_ == Clock::time_point{} || start - tick_ > 4 * period) tick_ = start;
        until = tick_ + period;
        while (until < at) until += period;
        tick_ = until;
    }
    if (until <= at) return;
    waitUntil(until);
    t.waitMs = msSince(at);
}

std::string Viewer::statsText() const {
    const StageTimes m = history_.mean();
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "fps %.1f   frame %.2f ms   work %.2f ms   gpu %.2f ms\n"
                  "app %.2f  pager %.2f  update %.2f  cull %.2f  draw %.2f  wait %.2f",
                  history_.rate(), m.frameMs, m.workMs, m.gpuMs, m.appMs, m.pagerMs, m.updateMs, m.cullMs, m.drawMs,
                  m.waitMs);
    const std::string more = overlayText ? overlayText() : std::string();
    return more.empty() ? std::string(buf) : more + "\n" + buf;
}

}  // namespace sg
