// Viewer: the frame loop as a library type (OpenSceneGraph's osgViewer::Viewer, Performer's pfFrame): one
// call runs a frame of a scene through its stages (events and the application's callbacks, the pager's update,
// update callbacks and Scene::update(), the cull of every view, their draw until finished, the frame-rate
// phase's wait, present), times each stage into a history, feeds the LOD policies what they learn (the budget's
// cost model, stress), and draws a stats overlay when asked. The passes stay callable alone (examples/hello).
#pragma once
#include "sg/gl/Renderer.h"
#include "sg/gl/TextOverlay.h"
#include "sg/paging/Pager.h"
#include "sg/viewer/FrameStats.h"
#include "sg/viewer/View.h"

#include <chrono>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace sg {

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
    // the draw); present callbacks after the draw is finished (a window's swapBuffers).
    void onEvents(Callback f) { events_.push_back(std::move(f)); }
    void onApp(FrameCallback f) { app_.push_back(std::move(f)); }
    void onUpdate(FrameCallback f) { update_.push_back(std::move(f)); }
    void onOverlay(Callback f) { overlayCallbacks_.push_back(std::move(f)); }
    void onPresent(Callback f) { present_.push_back(std::move(f)); }

    // Paging: a pager of the viewer's own, made for its scene (the load function reads a detail: see sg::Pager),
    // or one owned elsewhere (null: none), updated in the pager stage. Throws as the Pager's constructor. With
    // keepFreedMemory engaged, its pager does not trim (PagerSettings::trimFreedMemory), which would undo it.
    Pager& enablePaging(PageLoadFunction load, PagerSettings settings = {});
    void usePager(Pager* pager);
    Pager* pager() { return pager_; }

    // One frame through every stage. Throws what a stage throws (bad settings, a stale scene), the frame left
    // where it stopped: the views keep their last complete results.
    void frame();
    // Frames until done(): a callback (the window's close) calls setDone().
    void run();
    bool done() const { return done_; }
    void setDone(bool d = true) { done_ = d; }

    // The stats overlay: overlayText()'s lines, then the frame rate and each stage's mean over the history.
    bool overlay = false;
    std::function<std::string()> overlayText;
    std::string statsText() const;

    const FrameHistory& history() const { return history_; }
    const StageTimes& lastFrame() const { return history_.last(); }
    uint64_t frameNumber() const { return frame_; }
    ViewerSettings& settings() { return settings_; }
    const ViewerSettings& settings() const { return settings_; }
    Renderer& renderer() { return *renderer_; }
    Scene& scene() { return *scene_; }
    // Another scene (the views' traversals start over on it).
    void setScene(Scene& scene) { scene_ = &scene; }

private:
    using Clock = std::chrono::steady_clock;
    void init();
    double periodMs() const { return 1000.0 / settings_.frameRate; }
    void cullViews(StageTimes& t);
    void drawViews(StageTimes& t);
    void wait(Clock::time_point start, StageTimes& t);
    double now() const;

    Scene* scene_;
    std::unique_ptr<Renderer> own_;
    Renderer* renderer_;
    ViewerSettings settings_;
    std::deque<std::unique_ptr<View>> views_;
    std::vector<Callback> events_, overlayCallbacks_, present_;
    std::vector<FrameCallback> app_, update_;
    std::unique_ptr<Pager> ownPager_;
    bool keepingFreed_ = false;  // keepFreedMemory() engaged for a software rasterizer
    Pager* pager_ = nullptr;
    std::unique_ptr<TextOverlay> text_;
    FrameHistory history_;
    uint64_t frame_ = 0;
    bool done_ = false;
    Clock::time_point started_ = Clock::now();
    Clock::time_point lastStart_{};
    Clock::time_point tick_{};  // Lock: the tick the last frame started on
    double spentMs_ = 0.0;      // the last frame's time before its draw (app, pager, update, cull)
};

}  // namespace sg
