// The walkthrough's run loop: draws the path's frames with one of three ways of choosing LOD levels
// (static ranges, Performer's stress, the time budget), timing each frame and counting what it drew.
#pragma once
#include "sg/cull/CullTraversal.h"
#include "sg/gl/Renderer.h"
#include "testbed/FactoryWalk.h"
#include "testbed/LodRun.h"

#include <functional>
#include <memory>
#include <vector>

namespace factory {

struct FrameRecord {
    int frame = 0;
    double cullMs = 0.0, drawMs = 0.0;  // cull: the switch update included
    double workMs = 0.0;                // cull + draw until finished
    double frameMs = 0.0;               // workMs, and the wait when the frame rate is held
    double predictedMs = 0.0;           // the budget's plan: its predicted draw time
    uint64_t triangles = 0, vertices = 0, geometries = 0;
    double mae = -1.0;  // against the full-detail render of the same view (0-255), -1 when not compared
};

struct ModeRun {
    sg::LodPolicy mode = sg::LodPolicy::Static;
    double budgetMs = 0.0;
    std::vector<FrameRecord> frames;
};

class Walkthrough {
public:
    // Needs a current OpenGL context of width x height (the renderer's); keeps references to its arguments.
    // Uploads every mesh and texture of the site (all levels, switched-off interiors) before any frame.
    Walkthrough(scenes::Factory& f, sg::Scene& scene, const scenes::WalkPath& path, int width, int height);

    // The whole path once in each of `modes`, interleaved frame by frame (frame i in every mode, then frame
    // i + 1) so that the machine's drift over the run falls on every mode alike; after a warm-up on the first
    // frames of each, so that the stress scale and the draw-cost model have settled. With limitRate the
    // budget and stress hold the frame rate (LodRun::Settings::limitRate). With compare, each frame is also
    // drawn at full detail for image_mae. onFrame(k, i, image) sees mode k's frame i when set (it costs a
    // read-back).
    // The viewers' threading model (--threading) and how they move the context to their draw thread. The three
    // methods share the renderer's one context and each frame is compared with a full-detail picture drawn here,
    // so a threaded run hands the context back after every frame: each frame is drawn on a draw thread, but no
    // two stages overlap.
    void setThreading(sg::ThreadingModel model, std::function<void(bool current)> bindContext) {
        threading_ = model;
        bindContext_ = std::move(bindContext);
    }
    std::vector<ModeRun> run(const std::vector<sg::LodPolicy>& modes, double budgetMs, bool limitRate, bool compare,
                             const std::function<void(size_t, int, const sg::Image&)>& onFrame = nullptr);
    // Path frame `frame` drawn `draws` times with the static settings: the frame times.
    std::vector<double> sameView(int frame, int draws);
    // Path frame `frame` with `set` (Switch state as the path has it): its picture and cull counts.
    sg::Image render(int frame, const sg::CullSettings& set, sg::CullStats& stats);
    sg::Renderer& renderer() { return renderer_; }

private:
    void showWorkshop(int workshop);
    scenes::Factory& f_;
    sg::Scene& scene_;
    const scenes::WalkPath& path_;
    int width_, height_;
    int shown_ = -1;
    sg::ThreadingModel threading_ = sg::ThreadingModel::SingleThreaded;
    std::function<void(bool current)> bindContext_;
    sg::Renderer renderer_;
    sg::CullTraversal refCull_;
    sg::DrawList list_;
};

}  // namespace factory
