// LodRun: the LOD methods (static ranges, Performer's stress, the time budget) run frame by frame through an
// sg::Viewer, as sgbench lod, sgbench pareto and the factory walkthrough compare them: each frame culled, drawn
// and finished, timed, and the method fed the measured time (the stress scale, the budget's draw-cost model)
// before the next frame is chosen.
#pragma once
#include "sg/cull/CullTraversal.h"
#include "sg/gl/Renderer.h"
#include "sg/lod/DrawCostModel.h"
#include "sg/lod/LodStress.h"
#include "sg/viewer/Viewer.h"

#include <functional>
#include <string>
#include <vector>

namespace scenes {

// The machine's own spread: `cam`'s view of `scene` culled with the static ranges, drawn and finished `draws`
// times (after three untimed draws that upload the meshes); the frame times, ms.
std::vector<double> timeSameView(sg::Renderer& renderer, sg::Scene& scene, const sg::Camera& cam, int draws);

// One frame as the method drew it.
struct LodFrame {
    double cullMs = 0.0, drawMs = 0.0;  // cull: prepare() included
    double gpuMs = -1.0;                // the draw as the GL timed it (-1: no timer queries)
    double workMs = 0.0;                // cull + draw until finished
    double frameMs = 0.0;               // workMs, and with Settings::limitRate the wait for the frame time
    sg::CullStats stats;                // lodPredictedMs, lodDropped... for the budget
};

class LodRun {
public:
    struct Settings {
        sg::LodPolicy method = sg::LodPolicy::Budget;
        double budgetMs = 33.0;  // the frame time aimed at: stress's load is measured against it too
        // LodBudgetSettings::mayDrop: with the budget's coarsest bound at stress's largest scale, the budget
        // leaves out only what stress at its coarsest leaves out, and only when the rest does not fit.
        bool mayDrop = true;
        sg::CullSettings cull;  // what every frame starts from (strategy, occlusion); the method sets its LOD part
        // A fixed frame rate (Performer's PFPHASE_LIMIT): a frame whose work ends before budgetMs waits out
        // the rest, so frames come at most 1000 / budgetMs a second and a cheap view does not run ahead; a
        // late frame is not held further. The methods learn from the work, not from the wait. The budget
        // then plans for budgetMs less its recent overrun (the smoothed max(0, measured - predicted) draw
        // time, at most a fifth of the budget): a frame planned a little short waits, one planned to the
        // edge runs over half the time.
        bool limitRate = false;
        // The viewer's threading model and how it moves the GL context (ViewerSettings::threading, bindContext).
        // Threaded, frame() returns with threadingLatency() frames in flight: what it reports is of the frame
        // drawn last, and the picture is the renderer's only on the draw thread (onViewer's drawn callbacks)
        // or after stopThreads().
        sg::ThreadingModel threading = sg::ThreadingModel::SingleThreaded;
        std::function<void(bool current)> bindContext = {};
    };
    // Draws with `renderer` (its context current), through a viewer of its own made at the first frame. Throws
    // std::invalid_argument for a budget that is not a positive number of milliseconds.
    LodRun(sg::Renderer& renderer, const Settings& s);

    // One frame of `scene` seen by `cam`: prepare() (the scene's state for the frame, e.g. switches) and the
    // cull, then the draw until finished; the method learns from the measured times. The picture stays in
    // the renderer's buffer until the next draw. Threaded: the frame drawn last, if any (drawn() counts them).
    const LodFrame& frame(sg::Scene& scene, const sg::Camera& cam, const std::function<void()>& prepare = nullptr);
    // The frames in flight drawn; last() is then the last frame's.
    const LodFrame& flush();
    // flush(), and the GL context back on the calling thread (sg::Viewer::stopThreads()): to draw or read with
    // the renderer here, or to let another LodRun's viewer draw with it. The next frame() takes it again.
    const LodFrame& stopThreads();
    const LodFrame& last() const { return last_; }
    uint64_t drawn() const { return viewer_ ? viewer_->framesDrawn() : 0; }
    // Runs `f` on the viewer when it is made (at the first frame), or now if it is: its callbacks (drawn, overlay,
    // present), which run on the draw thread when threaded.
    void onViewer(std::function<void(sg::Viewer&)> f);

    // frames(0 .. count): the first `warmup` of them once untimed (the stress scale and the model settle
    // on the path), then all of them, each handed to recorded(i, frame) right after it is drawn (threaded: the
    // timed frames are flushed one by one, so that each record is its own frame's).
    // cameraAt(i) is frame i's camera; prepare(i), when set, runs in frame i before its cull.
    void run(sg::Scene& scene, int count, int warmup, const std::function<sg::Camera(int)>& cameraAt,
             const std::function<void(int)>& prepare, const std::function<void(int, const LodFrame&)>& recorded);

    const Settings& settings() const { return set_; }
    // Changed between frames (a viewer's keys): the next frame uses them; the model and the stress scale go on.
    Settings& settings() { return set_; }
    const sg::DrawList& list() const { return view().drawList(); }
    const sg::DrawCostModel& model() const { return view().costModel(); }
    const sg::LodStress& stress() const { return view().stress(); }

private:
    const sg::View& view() const;
    void collect();  // last_ from the viewer's last drawn frame
    sg::Renderer& renderer_;
    std::vector<std::function<void(sg::Viewer&)>> setup_;
    Settings set_;
    std::unique_ptr<sg::Viewer> viewer_;
    std::function<void()> prepare_;  // this frame's, run in the viewer's app stage
    LodFrame last_;
};

}  // namespace scenes
