// Viewer's pipeline: the threads of the threading models (a draw thread, a cull thread, a cull thread per view),
// the frames handed between them as packets, and a drawn frame's results brought back to the application thread.
#include "sg/viewer/Viewer.h"
#include "sg/viewer/internal/FramePacket.h"
#include "sg/viewer/internal/StageClock.h"
#include "sg/viewer/internal/StageThread.h"

#include <algorithm>

namespace sg {

using stageclock::ms;
using stageclock::msSince;

void Viewer::startThreads() {
    running_ = settings_.threading;
    try {
        settings_.bindContext(false);
    } catch (...) {
        fail("context", frame_);
        rethrowFailure();
    }
    threaded_ = true;
    drawThread_ = std::make_unique<StageThread>();
    drawThread_->run([this] {
        try {
            settings_.bindContext(true);
        } catch (...) {
            fail("context", frame_);
        }
    });
    drawThread_->wait();
    if (running_ == ThreadingModel::AppCullDraw) cullThread_ = std::make_unique<StageThread>();
    if (failed()) rethrowFailure();
}

// The frames in flight must be done (flush(), or dropped); the context comes back to this thread.
void Viewer::stop() {
    if (isect_.thread_) isect_.thread_->wait();
    if (!threaded_) return;
    viewThreads_.clear();
    cullThread_.reset();
    // Uploads asked of the draw thread start again with the next model (the pager asks again).
    uploadAsked_.clear();
    uploadPending_.clear();
    uploaded_.clear();
    if (drawThread_) {
        drawThread_->run([this] {
            try {
                settings_.bindContext(false);
            } catch (...) {
                fail("context", frame_);
            }
        });
        drawThread_.reset();
    }
    threaded_ = false;
    try {
        settings_.bindContext(true);
        for (const auto& d : uploadForget_) renderer_->forgetPrepare(*d);
    } catch (...) {
        fail("context", frame_);
    }
    uploadForget_.clear();
}

void Viewer::flush() {
    if (threaded_) {
        waitCull();
        waitDraw();
        if (failed()) rethrowFailure();
    }
    try {
        isect_.finish();
    } catch (...) {
        fail("isect", frame_);
        rethrowFailure();
    }
}

void Viewer::stopThreads() {
    flush();
    stop();
    if (failed()) rethrowFailure();  // the context could not be moved
}

std::unique_ptr<Viewer::Packet> Viewer::takePacket() {
    if (spare_.empty()) return std::make_unique<Packet>();
    std::unique_ptr<Packet> p = std::move(spare_.back());
    spare_.pop_back();
    return p;
}

void Viewer::startDraw(std::unique_ptr<Packet> p) {
    drawing_ = std::move(p);
    drawThread_->run([this] { drawPacket(*drawing_); });
}

void Viewer::waitCull() {
    if (!culling_) return;
    const auto at = Clock::now();
    cullThread_->wait();
    std::unique_ptr<Packet> p = std::move(culling_);
    if (p->culled) waitDraw();
    p->times.syncMs += msSince(at);
    if (!p->culled || drawFailed()) {  // nothing to draw, or no draw thread to draw it
        recycle(std::move(p));
        return;
    }
    startDraw(std::move(p));
}

void Viewer::waitDraw() {
    if (!drawing_) return;
    drawThread_->wait();
    std::unique_ptr<Packet> p = std::move(drawing_);
    if (!p->drawn) {
        recycle(std::move(p));
        return;
    }
    Packet& q = *p;
    // Pipelined, the frame's work is its slowest stage's (what the period is made of), its time its latency.
    const double appSide = q.times.appMs + q.times.pagerMs + q.times.updateMs +
                           (running_ == ThreadingModel::AppCullDraw ? 0.0 : q.times.cullMs);
    q.times.workMs = std::max(
        {appSide, running_ == ThreadingModel::AppCullDraw ? q.times.cullMs : 0.0, q.times.drawMs + q.times.presentMs});
    q.times.waitMs = waitMs_[q.info.frame % waitMs_.size()];
    q.times.frameMs = ms(q.drawEnd - q.start);
    if (q.info.frame == 0) q.times.intervalMs = q.times.frameMs;
    retire(std::move(p));
}

// A drawn frame's results reach its views and the history (on the application thread).
void Viewer::retire(std::unique_ptr<Packet> p) {
    for (size_t k = 0; k < p->viewCount; ++k) {
        Packet::ViewFrame& vf = p->views[k];
        View& v = *vf.view;
        std::swap(v.list_, vf.list);
        v.stats_ = vf.stats;
        v.prefetchStats_ = vf.aheadStats;
        v.render_ = vf.render;
        v.cullMs_ = vf.cullMs;
        v.cullThread_ = vf.cullThread;
        v.drawMs_ = vf.drawMs;
        v.gpuMs_ = vf.gpuMs;
        if (v.enabled) v.learn(p->times.workMs, vf.finished);
    }
    history_.push(p->times);
    ++drawnFrames_;
    settleUploads(*p, true);
    p->keep.clear();
    spare_.push_back(std::move(p));
}

void Viewer::recycle(std::unique_ptr<Packet> p) {
    settleUploads(*p, false);
    if (p->prepareVariants) variantsPrepared_ = false;  // asked again with the next frame
    p->variantUses.clear();
    p->keep.clear();
    spare_.push_back(std::move(p));
}

}  // namespace sg
