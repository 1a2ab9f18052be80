#include "sg/viewer/Viewer.h"

#include "sg/gl/KeepFreedMemory.h"
#include "sg/viewer/internal/StageThread.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <optional>
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

namespace {
const EnumName<FramePhase> kFramePhases[] = {
    {FramePhase::FreeRun, "free-run"}, {FramePhase::Limit, "limit"}, {FramePhase::Lock, "lock"}};
}  // namespace

const char* framePhaseName(FramePhase p) { return enumName(kFramePhases, p); }
FramePhase parseFramePhase(const std::string& name) {
    return parseEnum(kFramePhases, name, "parseFramePhase()", "a frame phase");
}

StageError::StageError(std::string stage, uint64_t frame, const std::string& what)
    : std::runtime_error("Viewer: the " + stage + " stage failed on frame " + std::to_string(frame) + ": " + what),
      stage_(std::move(stage)),
      frame_(frame) {}

// One frame on its way through the stages: what the cull made of each view, and what its draw reads. The thread that
// holds it is the only one that touches it; it is handed over through StageThread, which orders the writes.
struct Viewer::Packet {
    FrameInfo info;
    StageTimes times;
    Clock::time_point start;
    struct ViewFrame {
        View* view = nullptr;
        Camera camera;
        CullSettings settings;
        Renderer::Viewport viewport{};
        vec4 clear{0.0f};
        bool finished = false;  // finished after its draw (timed)
        DrawList list;
        CullStats stats;
        // The look-ahead cull, when View::prefetchSeconds asks for one and the camera moves.
        std::optional<Camera> ahead;
        CullSettings aheadSettings;
        CullStats aheadStats;
        RenderStats render;
        double cullMs = 0.0, drawMs = 0.0, gpuMs = -1.0;
    };
    std::vector<ViewFrame> views;
    size_t viewCount = 0;  // views[0, viewCount) are this frame's (the rest are kept for their lists' memory)
    // The meshes and materials the lists point at, held while the frame is in flight: the app stage of a later frame
    // may drop them from the graph (or the pager unload them) before this frame's draw is done.
    std::vector<ref_ptr<const Referenced>> keep;
    bool finishAll = true;  // ViewerSettings::finish, as it was when the frame started
    bool drawOverlay = false;
    std::string overlay;  // the stats text, made on the application thread (it reads the history)
    bool culled = false, drawn = false;
    Clock::time_point drawEnd;
    // The pager's details to upload on the draw thread within the budget, whether each got done, and those the
    // pager dropped after asking (pipelined models: Viewer::prepareOnDraw).
    std::vector<ref_ptr<Node>> upload;
    std::vector<char> uploadDone;
    std::vector<ref_ptr<const Node>> forget;
    PrepareBudget uploadBudget;
};

Viewer::Viewer(Scene& scene, ViewerSettings settings)
    : scene_(&scene), own_(std::make_unique<Renderer>()), renderer_(own_.get()), settings_(std::move(settings)) {
    init();
}

Viewer::Viewer(Scene& scene, Renderer& shared, ViewerSettings settings)
    : scene_(&scene), renderer_(&shared), settings_(std::move(settings)) {
    init();
}

// What is in the threads' hands finishes (not drawn further), then the threads stop and the context comes back here
// for the renderer's destructor.
Viewer::~Viewer() {
    if (cullThread_) cullThread_->wait();
    releaseNow(dropped_);
    if (drawThread_) drawThread_->wait();
    culling_.reset();
    drawing_.reset();
    stop();
}

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

void Viewer::checkSettings() const {
    checkRate(settings_.frameRate, "Viewer::frame()");
    if (settings_.threading != ThreadingModel::SingleThreaded && !settings_.bindContext)
        throw std::invalid_argument(std::string("Viewer::frame(): the ") + threadingModelName(settings_.threading) +
                                    " threading model draws on a thread of its own and needs "
                                    "ViewerSettings::bindContext to move the GL context there");
}

void Viewer::fail(const char* stage, uint64_t frame) {
    std::lock_guard<std::mutex> lock(failMutex_);
    if (hasFailure_) return;
    failure_ = Failure{stage, frame, std::current_exception()};
    hasFailure_ = true;
}

bool Viewer::failed() {
    std::lock_guard<std::mutex> lock(failMutex_);
    return hasFailure_;
}

std::unique_ptr<Viewer::Packet> Viewer::takePacket() {
    if (spare_.empty()) return std::make_unique<Packet>();
    std::unique_ptr<Packet> p = std::move(spare_.back());
    spare_.pop_back();
    return p;
}

void Viewer::frame() {
    checkSettings();
    const ThreadingModel model = settings_.threading;
    if (threaded_ && model != running_) {
        flush();
        stop();
    }
    if (!threaded_ && model != ThreadingModel::SingleThreaded) startThreads();

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
            appStage(*p, start, stage);
        } else {
            appStage(*p, start, stage);
        }
        if (model == ThreadingModel::AppCullDraw) waitCull();  // the image may be written once the cull is done
        stage = "update";
        updateStage(*p);
        releaseNow(dropped_);  // the image no longer points at them, and no cull runs
    } catch (...) {
        fail(stage, p->info.frame);
    }
    if (failed()) rethrowFailure();
    isect_.start(*scene_, p->info.frame);
    cullSetup(*p);

    if (!threaded_) {
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
        return;
    }
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

void Viewer::setScene(Scene& scene) {
    if (&scene == scene_) return;
    flush();
    scene_ = &scene;
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
    p.times.appMs = msSince(start);
}

// The pager, update callbacks and Scene::update(): on the application thread while no cull runs (the cull of the
// last frame is done in every model before this).
void Viewer::updateStage(Packet& p) {
    auto at = Clock::now();
    if (pager_) {
        // A pager without a prepare function of its own has its details uploaded by the renderer within the
        // pager's budget before they are attached (Renderer::prepare), for this update only: the pager may
        // outlive the viewer. Only where the renderer's context is current here (SingleThreaded): with a draw
        // thread, a detail is uploaded at its first draw.
        const bool wire = !pager_->prepare();
        if (wire && !threaded_)
            pager_->setPrepare([r = renderer_](Node& d, PrepareBudget& b) { return r->prepare(d, b); },
                               [r = renderer_](const Node& d) { r->forgetPrepare(d); });
        else if (wire)
            pager_->setPrepare([this](Node& d, PrepareBudget& b) { return prepareOnDraw(d, b); },
                               [this](const Node& d) { dropOnDraw(d); });
        try {
            pager_->update(p.info);
        } catch (...) {
            if (wire) pager_->setPrepare({});
            fail("pager", p.info.frame);
            throw;
        }
        if (wire) pager_->setPrepare({});
    }
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
        vf.settings.imageOfLastUpdate = running_ == ThreadingModel::AppCullDraw && threaded_;
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
}

// The view's camera observed, and carried ahead for the look-ahead cull when the view asks for one, the viewer has a
// pager with room in its byte budget, and the camera moves. That cull draws nothing and tests only frustum and LOD:
// no occlusion (an occluder may have moved out of the way by then), no PVS, no budget or hysteresis (the plain
// ranges say what will be wanted there), no screen rectangles.
void Viewer::lookAhead(Packet& p, size_t k) {
    Packet::ViewFrame& vf = p.views[k];
    View& v = *vf.view;
    v.motion_.observe(vf.camera, p.info.time);
    vf.ahead.reset();
    if (!(v.prefetchSeconds > 0.0) || !pager_ || pager_->stats().overBudget) return;
    vf.ahead = v.motion_.predict(vf.camera, v.prefetchSeconds);
    if (!vf.ahead) return;
    CullSettings& s = vf.aheadSettings;
    s = vf.settings;
    s.prefetchOnly = true;
    s.sort = false;
    s.occlusion.mode = OcclusionMode::Off;
    s.pvs = nullptr;
    s.lodBudget.enabled = false;
    s.lodHysteresis = 0.0;
    s.screenRect = false;
}

void Viewer::cullViews(Packet& p, bool parallel) {
    const auto start = Clock::now();
    std::atomic<bool> ok{true};
    auto cullOne = [this, &p, &ok](size_t k) {
        Packet::ViewFrame& vf = p.views[k];
        const auto at = Clock::now();
        try {
            vf.view->traversal_.cull(*scene_, vf.camera, vf.settings, vf.list, vf.stats);
            vf.aheadStats = CullStats{};
            if (vf.ahead)
                vf.view->prefetch_.cull(*scene_, *vf.ahead, vf.aheadSettings, vf.view->prefetchList_, vf.aheadStats);
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
            vf.gpuMs = vf.finished ? renderer_->gpuMs() : -1.0;
            if (vf.gpuMs >= 0.0) p.times.gpuMs += vf.gpuMs;
        }
        if (p.drawOverlay && width > 0 && height > 0) {
            if (!text_) text_ = std::make_unique<TextOverlay>();
            text_->draw(p.overlay, width, height, width >= 960 && height >= 480 ? 2.0f : 1.0f);
        }
        for (const Callback& f : overlayCallbacks_) f();
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

void Viewer::startDraw(std::unique_ptr<Packet> p) {
    drawing_ = std::move(p);
    drawThread_->run([this] { drawPacket(*drawing_); });
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

bool Viewer::drawFailed() {
    std::lock_guard<std::mutex> lock(failMutex_);
    static const char* const drawStages[] = {"draw", "drawn", "present", "context"};
    return hasFailure_ && std::any_of(std::begin(drawStages), std::end(drawStages),
                                      [&](const char* st) { return failure_.stage == st; });
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
    p->keep.clear();
    spare_.push_back(std::move(p));
}

bool Viewer::prepareOnDraw(Node& detail, PrepareBudget& budget) {
    if (uploaded_.erase(&detail)) return true;
    if (uploadPending_.insert(&detail).second) uploadAsked_.emplace_back(&detail);
    uploadBudget_ = PrepareBudget(budget.ms, budget.objects);
    return false;
}

void Viewer::dropOnDraw(const Node& detail) {
    uploaded_.erase(&detail);
    if (!uploadPending_.erase(&detail)) return;
    const auto asked = std::find_if(uploadAsked_.begin(), uploadAsked_.end(),
                                    [&](const ref_ptr<Node>& d) { return d.get() == &detail; });
    if (asked != uploadAsked_.end())
        uploadAsked_.erase(asked);
    else
        uploadForget_.emplace_back(&detail);  // sent: the renderer may hold a list for it
}

// What the draw thread uploaded becomes the pager's "done"; what it did not is asked again with the next frame.
void Viewer::settleUploads(Packet& p, bool drawn) {
    for (size_t k = 0; k < p.upload.size(); ++k) {
        const Node* d = p.upload[k].get();
        if (!uploadPending_.count(d)) continue;  // dropped meanwhile
        if (drawn && p.uploadDone[k]) {
            uploadPending_.erase(d);
            uploaded_.insert(d);
        } else {
            uploadAsked_.push_back(p.upload[k]);
        }
    }
    p.upload.clear();
    p.forget.clear();
}

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

// The frames in flight before the failure are drawn when they can be (not behind a failed draw), the threads stop,
// and the first failure is thrown here with its stage named.
void Viewer::rethrowFailure() {
    if (threaded_) {
        waitCull();
        waitDraw();
        stop();
    }
    releaseNow(dropped_);  // no cull runs now
    Failure f;
    {
        std::lock_guard<std::mutex> lock(failMutex_);
        f = failure_;
        failure_ = Failure{};
        hasFailure_ = false;
    }
    std::string what = "unknown exception";
    try {
        std::rethrow_exception(f.error);
    } catch (const SettingError&) {
        throw;  // an impossible setting is refused by name as it is, whichever stage met it
    } catch (const std::exception& e) {
        what = e.what();
    } catch (...) {
    }
    try {
        std::rethrow_exception(f.error);
    } catch (...) {
        throw StageError(f.stage, f.frame, what);  // nests the original
    }
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
