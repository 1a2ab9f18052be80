// FrameStats: where a frame's time went, stage by stage (Performer's pfFrameStats, OpenSceneGraph's viewer
// stats), and the recent frames' times kept for the overlay, the frame rate and a program's report.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace sg {

// One frame's stages, milliseconds. workMs is everything but the wait; frameMs the whole frame, wait included;
// intervalMs the time from the last frame's start to this one's (what the frame rate is made of). Pipelined
// (ThreadingModel other than SingleThreaded), workMs is the slowest stage's time and frameMs the frame's latency:
// from its start to the end of its draw and present.
struct StageTimes {
    uint64_t frame = 0;
    double appMs = 0.0;     // events and the application's callbacks
    double pagerMs = 0.0;   // the pager's update: requests queued, details attached and unloaded
    double updateMs = 0.0;  // update callbacks after the pager, and Scene::update()
    double cullMs = 0.0;    // every view's cull
    double drawMs = 0.0;    // every view's draw and the overlay, until finished (ViewerSettings::finish)
    // The views' draws as the GL timed them, when gpuTimed; 0 otherwise.
    double gpuMs = 0.0;
    // Whether gpuMs is known: the draws finished (ViewerSettings::finish, or a LOD policy), timer queries, and a
    // hardware rasterizer (a software one's timer reports a fraction of the draw: llvmpipe 0.04 ms for a 44 ms
    // draw). In FrameHistory::mean(): some frame's is, and gpuMs is the mean of those that are.
    bool gpuTimed = false;
    double waitMs = 0.0;     // the frame-rate phase's wait (FramePhase::Limit, Lock)
    double presentMs = 0.0;  // present callbacks (a window's buffer swap)
    double syncMs = 0.0;     // pipelined models: the application thread's wait for the last frame's cull or draw
    double workMs = 0.0;
    double frameMs = 0.0;
    double intervalMs = 0.0;
};

// The last `capacity` frames' stage times, oldest first.
class FrameHistory {
public:
    explicit FrameHistory(size_t capacity = 120) : capacity_(capacity ? capacity : 1) {}
    void push(const StageTimes& t);
    void clear() { frames_.clear(), head_ = 0; }
    size_t size() const { return frames_.size(); }
    size_t capacity() const { return capacity_; }
    // Frame k of those kept, 0 the oldest; last() the newest (a zero frame when none is kept).
    const StageTimes& at(size_t k) const { return frames_[(head_ + k) % frames_.size()]; }
    const StageTimes& last() const;
    // Each stage's mean over the frames kept; frame holds the newest frame's number.
    StageTimes mean() const;
    // Frames a second over the frames kept: their count over the sum of their intervals (0 with none).
    double rate() const;
    // The p-th percentile (0..100) of one stage over the frames kept, e.g. percentile(&StageTimes::frameMs, 95).
    double percentile(double StageTimes::*stage, double p) const;

private:
    size_t capacity_;
    size_t head_ = 0;  // the oldest frame's index once full
    std::vector<StageTimes> frames_;
};

}  // namespace sg
