// Viewer's stats text: the frame rate and each stage's mean over the history, under the application's lines.
#include "sg/viewer/Viewer.h"

#include <cstdio>

namespace sg {

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
