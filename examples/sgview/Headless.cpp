#include "sg/io/ImageIO.h"
#include "sgview/EglContext.h"
#include "sgview/Modes.h"
#include "sgview/Pick.h"
#include "sgview/View.h"
#include "sgview/ViewCamera.h"

#include <cstdio>

namespace sgview {

using namespace sg;

int runHeadless(const Options& o, Scene& scene, const LoadedScene& loaded) {
    EglContext context(o.width, o.height);
    View view(scene, loaded.title, o.threading,
              [&context](bool current) { current ? context.makeCurrent() : context.release(); });
    view.setSceneLights(loaded.up, loaded.lights);
    view.setPointShading(o.points);
    if (loaded.styleRule) view.featureStyle().setRule(loaded.styleRule);
    view.settings.strategy = o.strategy;
    view.settings.occlusion.mode = o.occlusion;
    const Camera camera = startCamera(o, sceneBound(scene), loaded.up);
    const FrameStats fs{"headless", ""};
    double cullMs = 0.0, drawMs = 0.0;
    if (loaded.pageLoad) view.enablePaging(loaded.pageLoad);
    const std::string animating = startAnimations(view.animations(), loaded, o);
    if (!animating.empty()) std::printf("sgview: %s\n", animating.c_str());
    int frames = 0;
    // The stats are the frame drawn last's: threaded, frames drawn together at the end show only the last one's,
    // so the means are over the frames seen.
    uint64_t seen = 0, counted = 0;
    auto count = [&] {
        if (view.viewer().framesDrawn() == seen) return;
        seen = view.viewer().framesDrawn();
        ++counted;
        cullMs += view.cullStats().ms;
        drawMs += view.renderStats().ms;
    };
    for (int f = 0; f < o.frames; ++f, ++frames) {
        view.frame(camera, o.overlay && f == o.frames - 1, fs);  // updated, drawn and finished
        if (f + 1 == o.frames) view.flush();
        count();
    }
    // A tileset: the picture is of the settled view, every tile it asks for loaded (a tile that failed is not
    // asked for again until its back-off passes; the frames are bounded all the same).
    for (sg::Pager* p = view.pager(); p && frames < o.frames + 100000 &&
                                      (view.cullStats().pagedRequested > 0 || p->stats().queued > 0 ||
                                       p->stats().loading > 0 || p->stats().pending > 0);
         ++frames) {
        p->waitIdle();
        view.frame(camera, o.overlay, fs);
        view.flush();  // threaded: what this frame asked the pager for is known once it is drawn
    }
    savePng(o.out, view.read());
    // The overlay's text, as drawn over the picture: readable where the picture is not read by eye.
    if (o.overlay) std::printf("sgview: overlay:\n%s\n", view.viewer().overlayDrawn().c_str());
    IntersectTraversal picker;
    for (const auto& [x, y] : o.picks)
        std::printf("%s\n", pickReport(picker, scene, camera, x, y, o.json, &view.featureStyle()).c_str());
    const dvec3 e = camera.eye();
    // The threading model the viewer ran and what occlusion culled in the last frame: what --threading and
    // --auto-occluders changed, where the picture must not change.
    std::printf(
        "sgview: wrote %s (%dx%d), %d frame%s: cull %.2f ms, draw %.2f ms, %llu geometries, %llu triangles, "
        "%llu points, %llu line segments; "
        "eye (%g, %g, %g); threading %s, %llu culled by occlusion\n",
        o.out.c_str(), o.width, o.height, frames, frames == 1 ? "" : "s", cullMs / double(counted),
        drawMs / double(counted), (unsigned long long)view.renderStats().instances,
        (unsigned long long)view.renderStats().triangles, (unsigned long long)view.renderStats().points,
        (unsigned long long)view.renderStats().lines, e.x, e.y, e.z,
        threadingModelName(view.viewer().settings().threading), (unsigned long long)view.cullStats().culledOcclusion);
    return 0;
}

}  // namespace sgview
