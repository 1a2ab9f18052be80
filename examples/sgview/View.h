// View: one sgview frame (update, cull, draw, the stats overlay) through an sg::Viewer over a current GL context;
// the window and the headless mode both draw through it.
#pragma once
#include "sg/viewer/Viewer.h"

#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>

namespace sgview {

struct FrameStats {
    std::string mode;   // navigation mode, or "headless"
    std::string panel;  // the picked feature's properties, a line each (shown under the stats)
};

class View {
    mutable sg::Viewer viewer_;  // first: the members below refer to it

public:
    using Picture = std::function<void(const sg::Image&)>;
    // Needs a current OpenGL 3.3 core context; same exceptions as sg::Renderer and sg::TextOverlay. A threaded
    // model draws on a thread of its own, where bindContext moves the context (sg::ViewerSettings).
    View(sg::Scene& scene, std::string title, sg::ThreadingModel threading = sg::ThreadingModel::SingleThreaded,
         std::function<void(bool current)> bindContext = nullptr);

    // One frame of the scene seen by `camera` (updated, culled with `settings`, drawn and finished); then the
    // stats overlay when `overlay` is set. picture, when set, is handed the frame's picture where it is drawn,
    // once it is (the draw thread when threaded: it must not touch the scene). Threaded, the frame is still in
    // flight when this returns, and the stats below are of the frame drawn last.
    void frame(const sg::Camera& camera, bool overlay, const FrameStats& fs, Picture picture = nullptr);
    // The frames in flight drawn.
    void flush() { viewer_.flush(); }
    // Called after each frame's draw where it is drawn: a window's swap.
    void onPresent(std::function<void()> f) { viewer_.onPresent(std::move(f)); }
    // The scene's up axis (the sky of physical materials' ambient light) and its punctual lights (at most
    // sg::Renderer::kMaxLights).
    void setSceneLights(const sg::dvec3& up, std::vector<sg::PunctualLight> lights);
    // How points and lines are drawn (sg::Renderer::setPointShading), before the first frame.
    void setPointShading(const sg::PointShading& p) { viewer_.renderer().setPointShading(p); }
    // The last frame's picture, read here: the frames in flight drawn and the context back on this thread (an
    // offscreen buffer: a window's is undefined after its swap).
    sg::Image read() {
        viewer_.stopThreads();
        return viewer_.renderer().readColor();
    }

    sg::CullSettings& settings;  // the view's
    const sg::CullStats& cullStats() const { return view_.cullStats(); }
    const sg::RenderStats& renderStats() const { return view_.renderStats(); }
    const sg::Viewer& viewer() const { return viewer_; }
    // The animations the frames play (the viewer's app stage advances them).
    sg::AnimationPlayer& animations() { return viewer_.animations(); }
    // A tileset's tiles, loaded as the frames need them (sg::Viewer's pager stage).
    // Pages a tileset: its loads make graphs of their own (no node shared with the rest), so details are freed
    // on a loader thread too.
    void enablePaging(sg::PageLoadFunction load) {
        sg::PagerSettings ps;
        ps.freeOnLoaderThread = true;
        viewer_.enablePaging(std::move(load), ps);
    }
    sg::Pager* pager() const { return viewer_.pager(); }
    // The per-feature colours the view is drawn with (sg::Renderer::setFeatureStyle): a style's rule, a click's
    // highlight. Thread-safe: any thread may change it between or during frames.
    sg::FeatureStyle& featureStyle() const { return *style_; }
    // The overlay's lines for the last frame (the viewer's stage times follow them).
    std::string statsText(const FrameStats& fs) const;

private:
    sg::ref_ptr<sg::FeatureStyle> style_ = sg::make<sg::FeatureStyle>();
    sg::View& view_;
    std::string title_;
    FrameStats fs_;
    std::mutex pictures_;                 // frame(..., picture) hands them to the draw side
    std::map<uint64_t, Picture> wanted_;  // by frame number
};

// Bounds culled by any test (frustum, the sphere and centre pre-tests, small features, occlusion).
uint64_t culledCount(const sg::CullStats& s);
const char* nextName(sg::CullStrategy& s);   // cycles none, sphere, aabb, sphere-sphere, center-box
const char* nextName(sg::OcclusionMode& m);  // cycles off, every-frame, adaptive

}  // namespace sgview
