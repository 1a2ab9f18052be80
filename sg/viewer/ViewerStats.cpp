// Viewer's stats text: the frame rate and each stage's mean over the history, under the application's lines, and
// the line of the frame the overlay is drawn over.
#include "sg/viewer/Viewer.h"

#include <cstdio>

namespace sg {

namespace {
// A figure, or "-" when no frame has measured it yet (a 0 would say the frame took no time).
std::string figure(double v, bool known) {
    if (!known) return "-";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", v);
    return buf;
}
}  // namespace

std::string Viewer::statsText() const {
    const StageTimes m = history_.mean();
    const bool any = history_.size() > 0;
    // The GL's own time of the draws: on a software rasterizer its timer reports a fraction of the draw
    // (StageTimes::gpuTimed), and the draw's time is the CPU's, shown as draw.
    const std::string gpu = !any                              ? "-"
                            : m.gpuTimed                      ? figure(m.gpuMs, true) + " ms"
                            : renderer_->softwareRasterizer() ? "unknown (software)"
                                                              : "unknown";
    const auto f = [any](double v) { return figure(v, any); };
    const std::string line = "fps " + figure(history_.rate(), any && history_.rate() > 0.0) + "   frame " +
                             f(m.frameMs) + " ms   work " + f(m.workMs) + " ms   gpu " + gpu + "\napp " + f(m.appMs) +
                             "  pager " + f(m.pagerMs) + "  update " + f(m.updateMs) + "  cull " + f(m.cullMs) +
                             "  draw " + f(m.drawMs) + "  wait " + f(m.waitMs);
    const std::string more = overlayText ? overlayText() : std::string();
    return more.empty() ? line : more + "\n" + line;
}

std::string Viewer::frameFiguresText(double cullMs, uint64_t nodesVisited, const RenderStats& drawn) {
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "this frame: cull %.2f ms  nodes %llu  drawn %llu  draw calls %llu  triangles %llu  compiled %llu",
                  cullMs, (unsigned long long)nodesVisited, (unsigned long long)drawn.instances,
                  (unsigned long long)drawn.drawCalls, (unsigned long long)drawn.triangles,
                  (unsigned long long)drawn.programsCompiled);
    return buf;
}

}  // namespace sg
