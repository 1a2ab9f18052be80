// View: one view of a Viewer's scene: a camera, a viewport, the cull's settings and how its LOD levels are chosen
// (static ranges, Performer's stress, the time budget), with the cull traversal, draw list, cost model and stress
// scale that are its own from frame to frame.
#pragma once
#include "sg/cull/CullTraversal.h"
#include "sg/gl/Renderer.h"
#include "sg/lod/DrawCostModel.h"
#include "sg/lod/LodStress.h"
#include "sg/paging/CameraMotion.h"

#include <string>
#include <thread>

namespace sg {

// How a view's LOD levels are chosen each frame.
enum class LodPolicy : uint8_t {
    Static,  // the LODs' ranges at CullSettings::lodScale
    Stress,  // Performer's stress: the scale grows while frames run over View::lodBudgetMs, and shrinks back
    Budget,  // Funkhouser and Sequin's budget: the levels that fit View::lodBudgetMs, planned by the cost model
};
const char* lodPolicyName(LodPolicy p);
// Throws std::invalid_argument listing the valid names ("static", "stress", "budget").
LodPolicy parseLodPolicy(const std::string& name);

class View {
public:
    // What the application sets, read at each frame.
    Camera camera;
    // The cull's settings. Stress multiplies lodScale by its scale; the budget enables lodBudget with the view's
    // cost model and the time left of lodBudgetMs (its other values are the library's defaults unless set).
    CullSettings cull;
    LodPolicy lod = LodPolicy::Static;
    // The frame time the LOD policies aim at, ms; 0: the viewer's frame period (1000 / ViewerSettings::frameRate).
    double lodBudgetMs = 0.0;
    // Where it is drawn; an empty one (the default): (0, 0, camera.width(), camera.height()).
    Renderer::Viewport viewport{};
    vec4 clearColor = Renderer::kClearColor;
    bool enabled = true;  // a disabled view is neither culled nor drawn, and its policies learn nothing
    // Paging ahead, when the viewer has a pager: the camera carried this many seconds ahead by its motion over the
    // last frames (sg::CameraMotion) is culled as well, after the view's own cull, and the paged details it would
    // want are asked for below everything the view itself needs (CullControls::prefetchOnly), so that the detail
    // ahead of a moving camera is loading before it shows (a flight over the tiled city: 7-9 frames differing from
    // the city in memory on the way instead of 43-56, for a twentieth more cull; docs/benchmarks.md). Not while
    // the pager is over its byte budget, nor for a camera at rest. 0 (or a negative or NaN value): off (a pager of
    // Command nodes only, as a map's levels entered by command, has nothing to look ahead for).
    double prefetchSeconds = 1.0;

    // Its last frame.
    const DrawList& drawList() const { return list_; }
    const CullStats& cullStats() const { return stats_; }
    // The last frame's look-ahead cull (prefetchSeconds): its requests are pagedRequested; all zero when none ran.
    const CullStats& prefetchStats() const { return prefetchStats_; }
    const CameraMotion& motion() const { return motion_; }
    const RenderStats& renderStats() const { return render_; }
    double cullMs() const { return cullMs_; }
    // The thread that culled it (the threading model's: the frame's thread, the cull thread or one of its own).
    std::thread::id cullThread() const { return cullThread_; }
    double drawMs() const { return drawMs_; }  // submitted and, when timed, finished
    // The draw as the GL timed it (Renderer::gpuMs()), when the viewer finished it; -1 when not known (not finished,
    // no timer queries, or a software rasterizer, whose timer reports a fraction of the draw's time).
    double gpuMs() const { return gpuMs_; }
    // What the policies learn from (kept while the view lives).
    const DrawCostModel& costModel() const { return model_; }
    const LodStress& stress() const { return stress_; }
    // The cull traversal keeps per-view state (hysteresis, the occlusion pass's back-off): one per view.
    CullTraversal& traversal() { return traversal_; }

private:
    friend class Viewer;
    // The settings this frame culls with (the policy applied to `cull`); `spentMs`: the last frame's time before
    // the draw (app, pager, update, cull), which comes off the budget, with the held frame rate's usual miss when
    // `held`.
    CullSettings frameSettings(double periodMs, double spentMs, bool held);
    // What the policies learn from this frame: its draw (when timed) and the frame's work.
    void learn(double workMs, bool timed);
    double budgetMs(double periodMs) const { return lodBudgetMs != 0.0 ? lodBudgetMs : periodMs; }

    CullTraversal traversal_;
    DrawList list_;
    CullStats stats_;
    CameraMotion motion_;     // observed at each frame's cull setup
    CullTraversal prefetch_;  // the look-ahead cull's (its state is not the view's)
    DrawList prefetchList_;   // stays empty
    CullStats prefetchStats_;
    RenderStats render_;
    double cullMs_ = 0.0, drawMs_ = 0.0, gpuMs_ = -1.0;
    std::thread::id cullThread_;
    DrawCostModel model_;
    LodStress stress_;
    double stressBudgetMs_ = 0.0;  // the budget stress_ was made for
    double missMs_ = 0.0;          // the budget's recent overrun of its predicted draw time, smoothed
};

}  // namespace sg
