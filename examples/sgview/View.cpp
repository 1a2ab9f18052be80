#include "sgview/View.h"

#include "sg/gl/KeepFreedMemory.h"

#include <cstdio>

namespace sgview {

using namespace sg;

View::View(const Scene& scene, std::string title) : scene_(scene), title_(std::move(title)) {
    if (renderer_.softwareRasterizer()) keepFreedMemory();  // as a frame loop does (sg/gl/KeepFreedMemory.h)
}

void View::frame(const Camera& camera, bool overlay, const FrameStats& fs) {
    cullStats_ = CullStats{};
    cull_.cull(scene_, camera, settings, list_, cullStats_);
    renderer_.draw(list_, camera);
    // Font pixels doubled where the panel (about 330 x 70 font pixels) leaves room for the scene.
    const float scale = camera.width() >= 960 && camera.height() >= 480 ? 2.0f : 1.0f;
    if (overlay) overlay_.draw(statsText(fs), camera.width(), camera.height(), scale);
}

uint64_t culledCount(const CullStats& s) {
    return s.culledFrustum + s.culledSphereSphere + s.culledCenterBox + s.culledSmallFeature + s.culledOcclusion;
}

std::string View::statsText(const FrameStats& fs) const {
    const CullStats& c = cullStats_;
    const RenderStats& r = renderer_.lastStats();
    const char* occ = settings.occlusion.mode == OcclusionMode::Off ? ""
                      : c.occlusionRan                              ? " (ran)"
                      : c.occlusionSkipped                          ? " (skipped)"
                                                                    : " (none in view)";
    char fps[32] = "-";
    if (fs.fps > 0.0) std::snprintf(fps, sizeof fps, "%.1f", fs.fps);
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "%s  [%s]\n"
                  "fps %s   cull %.2f ms   draw %.2f ms\n"
                  "nodes visited %llu   culled %llu\n"
                  "triangles %llu   geometries %llu   draw calls %llu\n"
                  "culling %s [C]   occlusion %s%s [O]",
                  title_.c_str(), fs.mode.c_str(), fps, c.ms, r.ms, (unsigned long long)c.nodesVisited,
                  (unsigned long long)culledCount(c), (unsigned long long)r.triangles, (unsigned long long)r.instances,
                  (unsigned long long)r.drawCalls, strategyName(settings.strategy),
                  occlusionModeName(settings.occlusion.mode), occ);
    return buf;
}

const char* nextName(CullStrategy& s) {
    s = s == CullStrategy::CenterBox ? CullStrategy::None : CullStrategy(uint8_t(s) + 1);
    return strategyName(s);
}

const char* nextName(OcclusionMode& m) {
    m = m == OcclusionMode::Auto ? OcclusionMode::Off : OcclusionMode(uint8_t(m) + 1);
    return occlusionModeName(m);
}

}  // namespace sgview
