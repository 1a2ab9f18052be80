// Viewer: the frame loop as a library type (OpenSceneGraph's osgViewer::Viewer, Performer's pfFrame): one
// call runs a frame of a scene through its stages (events and the application's callbacks, the pager's update,
// update callbacks and Scene::update(), the cull of every view, their draw until finished, the frame-rate
// phase's wait, present), times each stage into a history, feeds the LOD policies what they learn (the budget's
// cost model, stress), and draws a stats overlay when asked. The passes stay callable alone (examples/hello).
#pragma once
#include "sg/gl/Renderer.h"
#include "sg/gl/TextOverlay.h"
#include "sg/paging/Pager.h"
#include "sg/scene/AnimationPlayer.h"
#include "sg/viewer/FrameStats.h"
#include "sg/viewer/IsectStage.h"
#include "sg/viewer/Threading.h"
#include "sg/viewer/View.h"

#include <array>
#include <chrono>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <unordered_set>
#include <vector>

namespace sg {

// A stage's failure, rethrown on the application thread by frame() or flush(): the stage ("events", "app", "pager",
// "update", "cull", "draw", "present", "context"), the frame it ran for and, nested, what it threw
// (std::rethrow_if_nested).
class StageError : public std::runtime_error, public std::nested_exception {
public:
    StageError(std::string stage, uint64_t frame, const std::string& what);
    const std::string& stage() const { return stage_; }
    uint64_t frame() const { return frame_; }

private:
    std::string stage_;
    uint64_t frame_;
};

// How frames are paced (Performer's pfPhase).
enum class FramePhase : uint8_t {
    FreeRun,  // PFPHASE_FREE_RUN: the next frame starts when the last one is done
    Limit,    // PFPHASE_LIMIT: a frame done within its period waits out the rest; a late one is not held further
    Lock,     // PFPHASE_LOCK: frames start on the ticks of the frame rate; a late frame waits for the next tick
};
const char* framePhaseName(FramePhase p);
// Throws std::invalid_argument listing the valid names ("free-run", "limit", "lock").
FramePhase parseFramePhase(const std::string& name);

struct ViewerSettings {
    FramePhase phase = FramePhase::FreeRun;
    double frameRate = 30.0;     // frames a second: the phase's period, and the LOD policies' time (View::lodBudgetMs)
    size_t historyFrames = 120;  // frames of stage times kept (FrameHistory)
    // Wait for the GPU at the end of the draw (glFinish), so that the draw's time is the drawing's, not the
    // submission's; the LOD policies need it and finish a view's draw whatever this says.
    bool finish = true;
    // With a software rasterizer, keep freed memory for the next frame (sg::keepFreedMemory(): process-wide).
    bool keepFreedMemory = true;
    // Seconds for FrameInfo::time; null: a steady clock from the viewer's construction.
    std::function<double()> clock;
    // Read at each frame; a change drains the frames in flight first (flush()).
    ThreadingModel threading = ThreadingModel::SingleThreaded;
    // The models with a draw thread move the GL context there: bindContext(false) releases it from the calling
    // thread, bindContext(true) makes it current on the calling thread (e.g. OsmesaContext::makeCurrent/release,
    // GlfwWindow::makeCurrent/release). Required by those models; a throw is the "context" stage's failure.
    std::function<void(bool current)> bindContext;
    // Run the viewer's animation player (animations()) on the app stage, after the app callbacks, by the step of
    // FrameInfo::time since the last frame (the first frame's step is 0). Off: the application drives its own.
    bool animate = true;
};

class Viewer {
public:
    using FrameCallback = std::function<void(const FrameInfo&)>;
    using Callback = std::function<void()>;

    // Draws with a renderer of its own (needs a current OpenGL 3.3 core context, as sg::Renderer), or with one
    // shared with other viewers of the same context. Throws std::invalid_argument for impossible settings (a frame
    // rate that is not a positive number).
    explicit Viewer(Scene& scene, ViewerSettings settings = {});
    Viewer(Scene& scene, Renderer& shared, ViewerSettings settings = {});
    ~Viewer();
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    // Views are drawn in the order added; a viewer starts with none. References stay valid while the viewer lives.
    View& addView(const Camera& camera = {});
    View& view(size_t i = 0) { return *views_.at(i); }
    const View& view(size_t i = 0) const { return *views_.at(i); }
    size_t viewCount() const { return views_.size(); }

    // The stages' callbacks, run in the order added: events first (a window's pollEvents, input), then the
    // application's (camera, switches); update callbacks run after the pager and before Scene::update() (what
    // depends on details just attached); overlay callbacks after the views' draw (text over the frame, counted in
    // the draw); drawn callbacks once the frame's draw is finished (read its pixels), with the drawn frame's
    // info; present callbacks after them (a window's swapBuffers). Events, app and update callbacks run on the
    // thread that calls frame() and may change the graph; overlay, drawn and present callbacks run on the thread
    // that draws, with the GL context current, and must not touch the graph (docs/architecture.md, Threads). Add
    // callbacks before the frames run, or after flush(): the draw thread reads its lists during frames.
    void onEvents(Callback f) { events_.push_back(std::move(f)); }
    void onApp(FrameCallback f) { app_.push_back(std::move(f)); }
    void onUpdate(FrameCallback f) { update_.push_back(std::move(f)); }
    void onOverlay(Callback f) { overlayCallbacks_.push_back(std::move(f)); }
    void onDrawn(FrameCallback f) { drawn_.push_back(std::move(f)); }
    void onPresent(Callback f) { present_.push_back(std::move(f)); }

    // Paging: a pager of the viewer's own, made for its scene (the load function reads a detail: see sg::Pager),
    // or one owned elsewhere (null: none), updated in the pager stage. Throws as the Pager's constructor. With
    // keepFreedMemory engaged, its pager does not trim (PagerSettings::trimFreedMemory), which would undo it.
    Pager& enablePaging(PageLoadFunction load, PagerSettings settings = {});
    void usePager(Pager* pager);
    Pager* pager() { return pager_; }

    // One frame through every stage; with a threaded model it returns while the last threadingLatency() frames are
    // still culled or drawn. Throws std::invalid_argument for impossible settings (before any stage runs, or the
    // cull's SettingError as it is), and
    // StageError when a stage failed (this frame's, or one in flight): the frames in flight before the failure are
    // drawn first, the threads stop (a later frame() starts them again) and the views keep their last drawn frame.
    void frame();
    // Draws every frame in flight and brings the views' results and the history up to them. Throws as frame().
    void flush();
    // flush(), then the threaded model's threads stop and the GL context comes back to the calling thread
    // (bindContext(true)), for a program that draws with it between frames or shares it with other viewers; the
    // next frame() starts them again. Throws as frame().
    void stopThreads();
    // Frames until done(): a callback (the window's close) calls setDone(). Flushes at the end.
    void run();
    bool done() const { return done_; }
    void setDone(bool d = true) { done_ = d; }

    // The stats overlay: overlayText()'s lines, then the frame rate and each stage's mean over the history ("-"
    // before a frame is in it, rather than a 0 no frame measured; the GPU's time "unknown" where it is not known,
    // StageTimes::gpuTimed), then the figures of the frame it is drawn over (frameFiguresText: its own cull and draw,
    // so the first frame shows its figures too).
    bool overlay = false;
    std::function<std::string()> overlayText;
    std::string statsText() const;
    // The overlay's line of the frame drawn under it, summed over the views: cull time and nodes visited, items and
    // draw calls, triangles, and the shader programs the draw compiled (0 once the scene's are prepared).
    static std::string frameFiguresText(double cullMs, uint64_t nodesVisited, const RenderStats& drawn);
    // The text the overlay drew over the last frame drawn (empty when it drew none); written by the thread that
    // draws: read it between frames (after flush() when pipelined).
    const std::string& overlayDrawn() const { return overlayDrawn_; }

    // Picking and viewpoint collision on a thread of their own (Performer's ISECT).
    IsectStage& isect() { return isect_; }
    // The animations the app stage runs (ViewerSettings::animate): a program adds a file's (GltfScene::animations),
    // plays, pauses, seeks, or drives them from an app callback. Sequences run on FrameInfo::time in Scene::update().
    AnimationPlayer& animations() { return animations_; }

    const FrameHistory& history() const { return history_; }
    const StageTimes& lastFrame() const { return history_.last(); }
    uint64_t frameNumber() const { return frame_; }  // frames started
    uint64_t framesDrawn() const { return drawnFrames_; }
    ViewerSettings& settings() { return settings_; }
    const ViewerSettings& settings() const { return settings_; }
    Renderer& renderer() { return *renderer_; }
    Scene& scene() { return *scene_; }
    // Another scene (the views' traversals start over on it). The frames in flight are drawn first (flush()): a
    // cull of the old scene may still be running. Throws as flush(). A scene's first frame compiles the shader
    // variants its draws can take before drawing (Renderer::prepareVariants with the first view's camera), so that
    // the frames after it compile none (paged details bring theirs: Renderer::prepare).
    void setScene(Scene& scene);

private:
    using Clock = std::chrono::steady_clock;
    struct Packet;
    struct Failure {
        std::string stage;
        uint64_t frame = 0;
        std::exception_ptr error;
    };
    // Construction and settings (Viewer.cpp).
    void init();
    void checkSettings() const;
    // The frame's stages in order (ViewerFrame.cpp).
    std::unique_ptr<Packet> beginPacket();               // numbered, its start and interval timed
    void appAndUpdate(Packet& p, ThreadingModel model);  // ISECT's answers, events, app, update; a failure thrown here
    void cullDrawHere(std::unique_ptr<Packet> p);        // SingleThreaded: cull, draw, wait and present here
    void handToThreads(std::unique_ptr<Packet> p, ThreadingModel model);  // to the pipeline, then the wait
    void appStage(Packet& p, Clock::time_point start, const char*& stage);
    void updateStage(Packet& p);
    void cullSetup(Packet& p);
    // The cull and the draw, on whichever thread the model runs them (ViewerCullDraw.cpp).
    void cullViews(Packet& p, bool parallel);
    void drawPacket(Packet& p);  // on the thread that holds the context
    // The pipeline (ViewerThreads.cpp).
    void startDraw(std::unique_ptr<Packet> p);
    void waitDraw();  // the draw in hand done and retired
    void waitCull();  // the cull in hand (AppCullDraw) done and handed to the draw
    void retire(std::unique_ptr<Packet> p);
    // Threads for the model in use: started at the first frame that needs them, stopped by stop().
    void startThreads();
    void stop();
    std::unique_ptr<Packet> takePacket();
    void recycle(std::unique_ptr<Packet> p);  // an undrawn packet: its uploads are asked again
    // Failures across threads (ViewerErrors.cpp).
    void fail(const char* stage, uint64_t frame);  // records the current exception (the first one wins)
    void rethrowFailure();                         // stop(), then throw the recorded failure
    bool failed();
    bool drawFailed();  // the recorded failure is the draw thread's
    // Pacing (ViewerPacing.cpp).
    double periodMs() const { return 1000.0 / settings_.frameRate; }
    void wait(Clock::time_point start, StageTimes& t);
    double now() const;
    // Paging (ViewerPaging.cpp).
    void pagerStage(Packet& p);           // the pager's update, its uploads wired to the renderer for it
    void lookAhead(Packet& p, size_t k);  // view k's camera observed, and carried ahead
    // Pipelined, the pager's details are uploaded on the draw thread within the pager's budget: the pager asks on
    // the application thread (prepareOnDraw), a packet carries the detail to the draw thread, and the answer comes
    // back with the packet (settleUploads); the pager's next ask of a detail uploaded returns true.
    bool prepareOnDraw(Node& detail, PrepareBudget& budget);
    void dropOnDraw(const Node& detail);
    void settleUploads(Packet& p, bool drawn);

    Scene* scene_;
    std::unique_ptr<Renderer> own_;
    Renderer* renderer_;
    ViewerSettings settings_;
    std::deque<std::unique_ptr<View>> views_;
    std::vector<Callback> events_, overlayCallbacks_, present_;
    std::vector<FrameCallback> app_, update_, drawn_;
    std::unique_ptr<Pager> ownPager_;
    bool keepingFreed_ = false;  // keepFreedMemory() engaged for a software rasterizer
    Pager* pager_ = nullptr;
    std::unique_ptr<TextOverlay> text_;
    std::string overlayDrawn_;       // on the draw stage's thread
    bool variantsPrepared_ = false;  // the scene's variants listed for a frame's draw (on the application thread)
    static constexpr int kOrphanSweepFrames = 8;  // draws between Renderer::releaseOrphans() calls
    int drawsSinceSweep_ = 0;                     // on the draw stage's thread
    FrameHistory history_;
    uint64_t frame_ = 0;
    bool done_ = false;
    Clock::time_point started_ = Clock::now();
    Clock::time_point lastStart_{};
    Clock::time_point tick_{};  // Lock: the tick the last frame started on
    double spentMs_ = 0.0;      // the last frame's time before its draw (app, pager, update, cull)
    uint64_t drawnFrames_ = 0;
    std::array<double, 4> waitMs_{};                 // the phase's wait of the frames in flight, by frame number
    std::vector<ref_ptr<Node>> uploadAsked_;         // asked by the pager, not sent to the draw thread yet
    std::unordered_set<const Node*> uploadPending_;  // asked and not dropped, not uploaded yet
    std::unordered_set<const Node*> uploaded_;       // uploaded: the pager's next ask returns true
    std::vector<ref_ptr<const Node>> uploadForget_;  // dropped after being sent: the renderer lets them go
    PrepareBudget uploadBudget_;

    // The pipeline (models other than SingleThreaded). running_: the model the threads were started for.
    bool threaded_ = false;
    ThreadingModel running_ = ThreadingModel::SingleThreaded;
    std::unique_ptr<class StageThread> drawThread_, cullThread_;
    std::vector<std::unique_ptr<class StageThread>> viewThreads_;
    std::unique_ptr<Packet> drawing_, culling_;  // in the draw thread's and the cull thread's hands
    std::vector<std::unique_ptr<Packet>> spare_;
    std::vector<const Referenced*> dropped_;  // AppCullDraw: what the app stage dropped, freed after the update
    std::mutex failMutex_;
    Failure failure_;
    bool hasFailure_ = false;
    IsectStage isect_;
    AnimationPlayer animations_;
    double lastAnimTime_ = -1.0;  // FrameInfo::time of the last frame animated (-1: none yet)
};

}  // namespace sg
