// Viewer's cull and draw stages: each view culled (in parallel with a thread per view), then drawn into its
// viewport with the overlay over them, on whichever thread the threading model runs them.
#include "sg/viewer/Viewer.h"
#include "sg/viewer/internal/FramePacket.h"
#include "sg/viewer/internal/StageClock.h"
#include "sg/viewer/internal/StageThread.h"

#include <algorithm>
#include <atomic>
#include <thread>

namespace sg {

using stageclock::msSince;

namespace {
void add(RenderStats& sum, const RenderStats& r) {
    sum.drawCalls += r.drawCalls;
    sum.instances += r.instances;
    sum.triangles += r.triangles;
    sum.points += r.points;
    sum.lines += r.lines;
    sum.backFacesSkipped += r.backFacesSkipped;
    sum.ms += r.ms;
    sum.programsCompiled += r.programsCompiled;
}
}  // namespace

void Viewer::cullViews(Packet& p, bool parallel) {
    const auto start = Clock::now();
    std::atomic<bool> ok{true};
    auto cullOne = [this, &p, &ok](size_t k) {
        Packet::ViewFrame& vf = p.views[k];
        const auto at = Clock::now();
        vf.cullThread = std::this_thread::get_id();
        try {
            vf.view->traversal_.cull(*scene_, vf.camera, vf.settings, vf.list, vf.stats, vf.controls);
            vf.aheadStats = CullStats{};
            if (vf.ahead)
                vf.view->prefetch_.cull(*scene_, *vf.ahead, vf.settings, vf.view->prefetchList_, vf.aheadStats,
                                        CullControls{vf.controls.imageOfLastUpdate, true});
        } catch (...) {
            fail("cull", p.info.frame);
            ok = false;
        }
        vf.cullMs = msSince(at);
    };
    if (parallel && p.viewCount > 1) {
        while (viewThreads_.size() + 1 < p.viewCount) viewThreads_.push_back(std::make_unique<StageThread>());
        for (size_t k = 1; k < p.viewCount; ++k) viewThreads_[k - 1]->run([&cullOne, k] { cullOne(k); });
        cullOne(0);
        for (size_t k = 1; k < p.viewCount; ++k) viewThreads_[k - 1]->wait();
    } else {
        for (size_t k = 0; k < p.viewCount; ++k) cullOne(k);
    }
    if (threaded_) {
        // Consecutive items mostly share their mesh and material (the lists are sorted by state): a reference each
        // time one changes.
        p.keep.clear();
        for (size_t k = 0; k < p.viewCount; ++k) {
            const Mesh* mesh = nullptr;
            const Material* material = nullptr;
            for (const DrawItem& it : p.views[k].list.items) {
                if (it.mesh != mesh && it.mesh) p.keep.emplace_back(mesh = it.mesh);
                if (it.material != material && it.material) p.keep.emplace_back(material = it.material);
            }
            // A pose is made anew whenever its Geometry moves: the next update may drop the one this list draws.
            for (const auto& pose : p.views[k].list.poses) p.keep.emplace_back(pose.second);
        }
    }
    p.times.cullMs = msSince(start);
    p.culled = ok;
}

// Each view into its viewport; a view whose policy learns from its draw is finished before the next is drawn, so
// that its time is its own. The overlay goes over them all.
void Viewer::drawPacket(Packet& p) {
    const char* stage = "draw";
    try {
        const auto start = Clock::now();
        if (!p.upload.empty() || !p.forget.empty()) {
            PrepareBudget b(p.uploadBudget.ms, p.uploadBudget.objects);
            for (size_t k = 0; k < p.upload.size() && !b.exhausted(); ++k)
                p.uploadDone[k] = renderer_->prepare(*p.upload[k], b);
            for (const auto& d : p.forget) renderer_->forgetPrepare(*d);
        }
        if (p.prepareVariants) {
            renderer_->prepareVariants(p.variantUses, p.views[0].camera);
            p.variantUses.clear();
        }
        double cullMs = 0.0;
        uint64_t nodes = 0;
        RenderStats drawn;          // the views', summed, for the overlay
        int width = 0, height = 0;  // what the views cover, for the overlay
        for (size_t k = 0; k < p.viewCount; ++k) {
            Packet::ViewFrame& vf = p.views[k];
            const auto at = Clock::now();
            if (vf.viewport.width > 0 && vf.viewport.height > 0) {
                renderer_->draw(vf.list, vf.camera, vf.viewport, vf.clear);
                width = std::max(width, vf.viewport.x + vf.viewport.width);
                height = std::max(height, vf.viewport.y + vf.viewport.height);
            } else {
                renderer_->draw(vf.list, vf.camera, vf.clear);
                width = std::max(width, vf.camera.width());
                height = std::max(height, vf.camera.height());
            }
            vf.render = renderer_->lastStats();
            if (vf.finished) renderer_->finish();
            vf.drawMs = msSince(at);
            // A software rasterizer's timer reports a fraction of the draw (llvmpipe: 0.04 ms for a 44 ms draw): not
            // a GPU time to show.
            vf.gpuMs = vf.finished && !renderer_->softwareRasterizer() ? renderer_->gpuMs() : -1.0;
            if (vf.gpuMs >= 0.0) {
                p.times.gpuMs += vf.gpuMs;
                p.times.gpuTimed = true;
            }
            cullMs += vf.cullMs;
            nodes += vf.stats.nodesVisited;
            add(drawn, vf.render);
        }
        overlayDrawn_.clear();
        if (p.drawOverlay && width > 0 && height > 0) {
            if (!text_) text_ = std::make_unique<TextOverlay>();
            overlayDrawn_ = p.overlay + "\n" + frameFiguresText(cullMs, nodes, drawn);
            text_->draw(overlayDrawn_, width, height, width >= 960 && height >= 480 ? 2.0f : 1.0f);
        }
        for (const Callback& f : overlayCallbacks_) f();
        // The GPU copies of what the pager (or the program) dropped: every few frames, as a sweep visits every copy.
        if (++drawsSinceSweep_ == kOrphanSweepFrames) {
            renderer_->releaseOrphans();
            drawsSinceSweep_ = 0;
        }
        if (p.finishAll) renderer_->finish();
        p.times.drawMs = msSince(start);
        stage = "drawn";
        for (const FrameCallback& f : drawn_) f(p.info);
        if (threaded_) {
            stage = "present";
            const auto at = Clock::now();
            for (const Callback& f : present_) f();
            p.times.presentMs = msSince(at);
        }
        p.drawEnd = Clock::now();
        p.drawn = true;
    } catch (...) {
        fail(stage, p.info.frame);
    }
}

}  // namespace sg
