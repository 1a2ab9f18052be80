// Viewer's frame: its stages in order on the application thread (events and app, pager, update, the views' cull
// settings), then the cull and the draw here or handed to the pipeline's threads.
#include "sg/viewer/Viewer.h"
#include "sg/viewer/internal/FramePacket.h"
#include "sg/viewer/internal/StageClock.h"
#include "sg/viewer/internal/StageThread.h"

namespace sg {

using stageclock::ms;
using stageclock::msSince;

void Viewer::frame() {
    checkSettings();
    const ThreadingModel model = settings_.threading;
    if (threaded_ && model != running_) {
        flush();
        stop();
    }
    if (!threaded_ && model != ThreadingModel::SingleThreaded) startThreads();

    std::unique_ptr<Packet> p = beginPacket();
    appAndUpdate(*p, model);
    isect_.start(*scene_, p->info.frame);
    cullSetup(*p);
    if (!threaded_)
        cullDrawHere(std::move(p));
    else
        handToThreads(std::move(p), model);
}

std::unique_ptr<Viewer::Packet> Viewer::beginPacket() {
    const auto start = Clock::now();
    std::unique_ptr<Packet> p = takePacket();
    p->start = start;
    p->times = StageTimes{};
    p->times.frame = frame_;
    p->times.intervalMs = frame_ ? ms(start - lastStart_) : 0.0;
    p->culled = p->drawn = false;
    lastStart_ = start;
    p->info = FrameInfo{frame_, now()};
    ++frame_;
    return p;
}

void Viewer::appAndUpdate(Packet& p, ThreadingModel model) {
    const char* stage = "isect";
    try {
        isect_.finish();  // last frame's answers, before anything writes the scene
        if (model == ThreadingModel::AppCullDraw) {
            // The last frame's cull may still point at what the callbacks drop: freed after the update.
            DeferredRelease hold;
            struct Take {
                DeferredRelease& hold;
                std::vector<const Referenced*>& into;
                ~Take() { into = hold.take(); }
            } take{hold, dropped_};
            appStage(p, p.start, stage);
        } else {
            appStage(p, p.start, stage);
        }
        if (model == ThreadingModel::AppCullDraw) waitCull();  // the image may be written once the cull is done
        stage = "update";
        updateStage(p);
        releaseNow(dropped_);  // the image no longer points at them, and no cull runs
    } catch (...) {
        fail(stage, p.info.frame);
    }
    if (failed()) rethrowFailure();
}

void Viewer::cullDrawHere(std::unique_ptr<Packet> p) {
    const Clock::time_point start = p->start;
    cullViews(*p, false);
    if (!failed()) drawPacket(*p);
    if (failed()) rethrowFailure();
    p->times.workMs = msSince(start);
    spentMs_ = p->times.appMs + p->times.pagerMs + p->times.updateMs + p->times.cullMs;
    wait(start, p->times);
    const auto at = Clock::now();
    try {
        for (const Callback& f : present_) f();
    } catch (...) {
        fail("present", p->info.frame);
        rethrowFailure();
    }
    p->times.presentMs = msSince(at);
    p->times.frameMs = msSince(start);
    if (p->info.frame == 0) p->times.intervalMs = p->times.frameMs;
    retire(std::move(p));
}

void Viewer::handToThreads(std::unique_ptr<Packet> p, ThreadingModel model) {
    const Clock::time_point start = p->start;
    if (model == ThreadingModel::AppCullDraw) {
        culling_ = std::move(p);
        cullThread_->run([this] { cullViews(*culling_, false); });
    } else {
        cullViews(*p, model == ThreadingModel::CullThreadPerView);
        const auto at = Clock::now();
        if (!failed()) waitDraw();  // the last frame's draw done: this one goes to the draw thread
        p->times.syncMs += msSince(at);
        if (failed()) {
            recycle(std::move(p));
            rethrowFailure();
        }
        startDraw(std::move(p));
    }
    StageTimes waited;
    wait(start, waited);
    waitMs_[(frame_ - 1) % waitMs_.size()] = waited.waitMs;
}

void Viewer::run() {
    while (!done_) frame();
    flush();
}

void Viewer::appStage(Packet& p, Clock::time_point start, const char*& stage) {
    stage = "events";
    for (const Callback& f : events_) f();
    stage = "app";
    for (const FrameCallback& f : app_) f(p.info);
    if (settings_.animate) {  // after the callbacks, which may play, pause or seek; a throw is the app stage's
        const double time = p.info.time;
        animations_.advance(lastAnimTime_ < 0.0 ? 0.0 : time - lastAnimTime_);
        lastAnimTime_ = time;
    } else {
        lastAnimTime_ = -1.0;  // turned on again: no jump by the time it was off
    }
    p.times.appMs = msSince(start);
}

// The pager, update callbacks and Scene::update(): on the application thread while no cull runs (the cull of the
// last frame is done in every model before this).
void Viewer::updateStage(Packet& p) {
    auto at = Clock::now();
    pagerStage(p);
    p.times.pagerMs = msSince(at);
    at = Clock::now();
    for (const FrameCallback& f : update_) f(p.info);
    scene_->update(p.info);
    p.times.updateMs = msSince(at);
}

// The views' settings for this frame, on the application thread (the policies read what the views learnt).
void Viewer::cullSetup(Packet& p) {
    const bool held = settings_.phase != FramePhase::FreeRun;
    // Pipelined, the draw overlaps the next frames' app and cull: it has the whole period.
    const double spent = threaded_ ? 0.0 : spentMs_;
    p.viewCount = 0;
    for (const auto& v : views_) {
        if (!v->enabled) continue;
        if (p.views.size() == p.viewCount) p.views.emplace_back();
        Packet::ViewFrame& vf = p.views[p.viewCount++];
        vf.view = v.get();
        vf.camera = v->camera;
        vf.settings = v->frameSettings(periodMs(), spent, held);
        // AppCullDraw: Scene::update() ran just before this cull is handed over (the image is current), and the
        // next app stage may write the graph's dirty marks while it runs: the cull must not read them.
        vf.controls.imageOfLastUpdate = running_ == ThreadingModel::AppCullDraw && threaded_;
        vf.viewport = v->viewport;
        vf.clear = v->clearColor;
        vf.finished = v->lod != LodPolicy::Static || settings_.finish;
        lookAhead(p, p.viewCount - 1);
    }
    p.upload = std::move(uploadAsked_);
    uploadAsked_.clear();
    p.uploadDone.assign(p.upload.size(), 0);
    p.forget = std::move(uploadForget_);
    uploadForget_.clear();
    p.uploadBudget = uploadBudget_;
    p.finishAll = settings_.finish;
    p.drawOverlay = overlay;
    p.overlay = overlay ? statsText() : std::string();
    // The graph is read here, on the application thread, where no stage writes it; the draw thread compiles.
    p.prepareVariants = !variantsPrepared_ && p.viewCount > 0;
    p.variantUses.clear();
    if (p.prepareVariants) {
        p.variantUses = Renderer::drawUses(*scene_->root());
        variantsPrepared_ = true;
    }
}

}  // namespace sg
