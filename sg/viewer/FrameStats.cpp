#include "sg/viewer/FrameStats.h"

#include <algorithm>
#include <cmath>

namespace sg {

void FrameHistory::push(const StageTimes& t) {
    if (frames_.size() < capacity_) {
        frames_.push_back(t);
        return;
    }
    frames_[head_] = t;
    head_ = (head_ + 1) % capacity_;
}

const StageTimes& FrameHistory::last() const {
    static const StageTimes none;
    return frames_.empty() ? none : at(frames_.size() - 1);
}

StageTimes FrameHistory::mean() const {
    StageTimes m;
    if (frames_.empty()) return m;
    size_t timed = 0;
    for (const StageTimes& t : frames_) {
        m.appMs += t.appMs, m.pagerMs += t.pagerMs, m.updateMs += t.updateMs, m.cullMs += t.cullMs;
        m.drawMs += t.drawMs, m.waitMs += t.waitMs, m.presentMs += t.presentMs, m.workMs += t.workMs;
        m.frameMs += t.frameMs, m.intervalMs += t.intervalMs;
        if (t.gpuTimed) m.gpuMs += t.gpuMs, ++timed;
    }
    const double n = double(frames_.size());
    m.gpuTimed = timed > 0;
    if (timed) m.gpuMs /= double(timed);
    m.appMs /= n, m.pagerMs /= n, m.updateMs /= n, m.cullMs /= n, m.drawMs /= n, m.waitMs /= n;
    m.presentMs /= n, m.workMs /= n, m.frameMs /= n, m.intervalMs /= n;
    m.frame = last().frame;
    return m;
}

double FrameHistory::rate() const {
    double ms = 0.0;
    for (const StageTimes& t : frames_) ms += t.intervalMs;
    return ms > 0.0 ? 1000.0 * double(frames_.size()) / ms : 0.0;
}

double FrameHistory::percentile(double StageTimes::*stage, double p) const {
    if (frames_.empty()) return 0.0;
    std::vector<double> v;
    v.reserve(frames_.size());
    for (const StageTimes& t : frames_) v.push_back(t.*stage);
    std::sort(v.begin(), v.end());
    const double q = std::clamp(std::isfinite(p) ? p : 100.0, 0.0, 100.0) / 100.0;
    return v[std::min(v.size() - 1, size_t(std::ceil(q * double(v.size()))) - (q > 0.0 ? 1 : 0))];
}

}  // namespace sg
