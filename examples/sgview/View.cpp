#include "sgview/View.h"

#include <cstdio>

namespace sgview {

using namespace sg;

namespace {
ViewerSettings viewerSettings(ThreadingModel threading, std::function<void(bool)> bindContext) {
    ViewerSettings s;
    s.threading = threading;
    s.bindContext = std::move(bindContext);
    return s;
}
}  // namespace

View::View(Scene& scene, std::string title, ThreadingModel threading, std::function<void(bool)> bindContext)
    : viewer_(scene, viewerSettings(threading, std::move(bindContext))),
      settings(viewer_.addView().cull),
      view_(viewer_.view()),
      title_(std::move(title)) {
    viewer_.overlayText = [this] { return statsText(fs_); };  // on this thread, as the frame is culled
    viewer_.renderer().setFeatureStyle(style_);
    viewer_.onDrawn([this](const FrameInfo& fi) {
        Picture picture;
        {
            std::lock_guard<std::mutex> lock(pictures_);
            const auto it = wanted_.find(fi.frame);
            if (it == wanted_.end()) return;
            picture = std::move(it->second);
            wanted_.erase(it);
        }
        picture(viewer_.renderer().readColor());
    });
}

void View::setSceneLights(const dvec3& up, std::vector<PunctualLight> lights) {
    DirectionalLight l = viewer_.renderer().light();
    l.up = vec3(up);
    viewer_.renderer().setLight(l);
    viewer_.renderer().setPunctualLights(std::move(lights));
}

void View::frame(const Camera& camera, bool overlay, const FrameStats& fs, Picture picture) {
    if (picture) {
        std::lock_guard<std::mutex> lock(pictures_);
        wanted_[viewer_.frameNumber()] = std::move(picture);  // the number this frame gets
    }
    view_.camera = camera;
    viewer_.overlay = overlay;
    fs_ = fs;
    viewer_.frame();
}

uint64_t culledCount(const CullStats& s) {
    return s.culledFrustum + s.culledSphereSphere + s.culledCenterBox + s.culledSmallFeature + s.culledOcclusion;
}

std::string View::statsText(const FrameStats& fs) const {
    // The figures are the last frame's (the overlay's text is made before this frame is culled): before the first
    // frame there are none, and "-" says so where a 0 would say nothing was drawn (the viewer's line of the frame
    // drawn under the overlay has its own).
    const bool known = viewer_.framesDrawn() > 0;
    const CullStats& c = view_.cullStats();
    const RenderStats& r = view_.renderStats();
    const char* occ = settings.occlusion.mode == OcclusionMode::Off || !known ? ""
                      : c.occlusionRan                                        ? " (ran)"
                      : c.occlusionSkipped                                    ? " (skipped)"
                                                                              : " (none in view)";
    char figures[320] =
        "cull - ms   draw submit - ms\nnodes visited -   culled -\ntriangles -   geometries -   draw calls -";
    if (known) {
        // What was drawn: triangles, and points and lines where there are any (a scan, CAD edges).
        char drawn[160];
        int n = std::snprintf(drawn, sizeof drawn, "triangles %llu", (unsigned long long)r.triangles);
        if (r.points)
            n += std::snprintf(drawn + n, sizeof drawn - size_t(n), "   points %llu", (unsigned long long)r.points);
        if (r.lines) std::snprintf(drawn + n, sizeof drawn - size_t(n), "   lines %llu", (unsigned long long)r.lines);
        std::snprintf(figures, sizeof figures,
                      "cull %.2f ms   draw submit %.2f ms\nnodes visited %llu   culled %llu\n%s   geometries %llu   "
                      "draw calls %llu",
                      c.ms, r.ms, (unsigned long long)c.nodesVisited, (unsigned long long)culledCount(c), drawn,
                      (unsigned long long)r.instances, (unsigned long long)r.drawCalls);
    }
    char buf[512];
    std::snprintf(buf, sizeof buf, "%s  [%s]\n%s\nculling %s [C]   occlusion %s%s [O]", title_.c_str(), fs.mode.c_str(),
                  figures, strategyName(settings.strategy), occlusionModeName(settings.occlusion.mode), occ);
    return fs.panel.empty() ? std::string(buf) : buf + std::string("\n\n") + fs.panel;
}

const char* nextName(CullStrategy& s) {
    s = s == CullStrategy::CenterBox ? CullStrategy::None : CullStrategy(uint8_t(s) + 1);
    return strategyName(s);
}

const char* nextName(OcclusionMode& m) {
    m = m == OcclusionMode::Adaptive ? OcclusionMode::Off : OcclusionMode(uint8_t(m) + 1);
    return occlusionModeName(m);
}

}  // namespace sgview
