// View: one sgview frame (cull, draw, stats overlay) over a current GL context; the window and the headless
// mode both draw through it.
#pragma once
#include "sg/cull/CullTraversal.h"
#include "sg/gl/Renderer.h"
#include "sg/gl/TextOverlay.h"

#include <string>

namespace sgview {

struct FrameStats {
    double fps = 0.0;  // measured by the caller over recent frames (0: not known yet)
    std::string mode;  // navigation mode, or "headless"
};

class View {
public:
    // Needs a current OpenGL 3.3 core context; same exceptions as sg::Renderer and sg::TextOverlay.
    View(const sg::Scene& scene, std::string title);

    // Culls the (updated) scene with `settings` and draws it; then the stats overlay when `overlay` is set.
    void frame(const sg::Camera& camera, bool overlay, const FrameStats& fs);
    sg::Image read() const { return renderer_.readColor(); }
    void finish() const { renderer_.finish(); }

    sg::CullSettings settings;
    const sg::CullStats& cullStats() const { return cullStats_; }
    const sg::RenderStats& renderStats() const { return renderer_.lastStats(); }
    // The overlay's lines for the last frame.
    std::string statsText(const FrameStats& fs) const;

private:
    const sg::Scene& scene_;
    std::string title_;
    sg::CullTraversal cull_;
    sg::DrawList list_;
    sg::CullStats cullStats_;
    sg::Renderer renderer_;
    sg::TextOverlay overlay_;
};

// Bounds culled by any test (frustum, the sphere and centre pre-tests, small features, occlusion).
uint64_t culledCount(const sg::CullStats& s);
const char* nextName(sg::CullStrategy& s);   // cycles none, sphere, aabb, sphere-sphere, center-box
const char* nextName(sg::OcclusionMode& m);  // cycles off, tree, auto

}  // namespace sgview
