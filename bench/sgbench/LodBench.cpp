// sgbench lod: frame time against a budget, and image error against full detail, for three ways of
// choosing LOD levels: static ranges, Performer's stress (one range scale driven by the load), and the
// time budget (every visible LOD planned together with a draw-cost model fitted online). Headless,
// 1280x720, the city's orbit or street path or the factory's orbit (docs/scenes.md); each frame's image is
// compared with the same view at full detail.
#include "nodes/LOD.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/KeepFreedMemory.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sgbench/Bench.h"
#include "testbed/BackgroundLoad.h"
#include "testbed/City.h"
#include "testbed/Factory.h"
#include "testbed/LodRun.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace bench {

void setLevelErrorsToZero(sg::Node& n) {
    if (n.kind() == sg::NodeKind::LOD) {
        auto& lod = static_cast<sg::LOD&>(n);
        for (size_t k = 0; k < lod.numChildren(); ++k) lod.setError(k, 0.0f);
    }
    for (size_t k = 0; k < n.numChildren(); ++k) setLevelErrorsToZero(*n.child(k));
}

int runLod(const Args& a) {
    const std::string sceneName = a.str("scene", "city");
    if (sceneName != "city" && sceneName != "factory")
        throw std::invalid_argument("sgbench lod: --scene must be city or factory (got '" + sceneName + "')");
    const int n = int(a.num("n", 100));
    if (n < 1 || n > 1000) throw std::invalid_argument("sgbench lod: --n " + std::to_string(n) + " is not in 1..1000");
    const std::string path = a.str("path", "orbit");
    if (path != "orbit" && path != "street") throw std::invalid_argument("sgbench lod: --path must be orbit or street");
    if (sceneName == "factory" && path != "orbit")
        throw std::invalid_argument("sgbench lod: the factory has only the orbit path (got --path " + path + ")");
    if (sceneName == "factory" && a.flag("guess-accuracy"))
        throw std::invalid_argument("sgbench lod: --guess-accuracy is for the city (the factory's errors are known)");
    const double budget = double(a.num("budget-ms", 33));
    if (!(budget > 0)) throw std::invalid_argument("sgbench lod: --budget-ms must be positive");
    const std::string method = a.str("method", "budget");
    if (method != "static" && method != "stress" && method != "budget")
        throw std::invalid_argument("sgbench lod: --method must be static, stress or budget (got '" + method + "')");
    const int every = int(a.num("every", 1));
    if (every < 1) throw std::invalid_argument("sgbench lod: --every must be at least 1");

    const bool factory = sceneName == "factory";
    // The factory's levels carry the simplifier's errors (sg::makeLod); --n does not apply to it.
    sg::ref_ptr<sg::Node> root = factory ? sg::ref_ptr<sg::Node>(scenes::buildFactory().root)
                                         : sg::ref_ptr<sg::Node>(scenes::buildCity({n, false}));
    // The city's two levels are the same box (10 x 10 quads per face, or one): their geometric error is 0,
    // which tells the budget that the coarse level shows the same. --guess-accuracy leaves the errors unset
    // (the budget then values levels by their triangle counts).
    if (!factory && !a.flag("guess-accuracy")) setLevelErrorsToZero(*root);
    sg::Scene scene(root);
    scene.update();
    std::vector<sg::Camera> cams;
    const int frames = factory           ? scenes::kFactoryOrbitFrames
                       : path == "orbit" ? scenes::kOrbitFrames
                                         : scenes::kStreetFrames;
    for (int f = 0; f < frames; f += every) {
        const int view = a.flag("same-view") ? 0 : f;
        cams.push_back(factory           ? scenes::factoryOrbitCamera(view)
                       : path == "orbit" ? scenes::cityOrbitCamera(n, view)
                                         : scenes::cityStreetCamera(n, view));
    }

    sg::OsmesaContext ctx(1280, 720);
    sg::Renderer renderer;
    if (renderer.softwareRasterizer()) sg::keepFreedMemory();  // as a frame loop does (sg/gl/KeepFreedMemory.h)
    // The renderer's depth strategy (reverse-z where the context allows it, by default): what it costs.
    const std::string depth = a.str("depth", "default");
    if (depth == "classic")
        renderer.setDepthMode(sg::Renderer::DepthMode::Classic);
    else if (depth == "reverse-z")
        renderer.setDepthMode(sg::Renderer::DepthMode::ReverseZ);
    else if (depth != "default")
        throw std::invalid_argument("sgbench lod: --depth must be default, classic or reverse-z (got '" + depth + "')");
    sg::CullTraversal refCull;
    sg::DrawList list;
    sg::CullSettings full;  // the reference: every LOD at its finest level
    full.lodScale = 1e-9;
    // The budget may leave out what stress at its coarsest leaves out (LodRun's default); --no-drop: never.
    const bool mayDrop = !a.flag("no-drop");
    // The budget's deadband (LodBudgetSettings::keepOver, keepUnder), in percent; the library's by default.
    sg::CullSettings base;
    base.lodBudget.keepOver = double(a.num("keep-over-pct", long(base.lodBudget.keepOver * 100.0 + 0.5))) / 100.0;
    base.lodBudget.keepUnder = double(a.num("keep-under-pct", long(base.lodBudget.keepUnder * 100.0 + 0.5))) / 100.0;
    scenes::LodRun run(renderer, {sg::parseLodPolicy(method), budget, mayDrop, base});
    // The load runs from before the same-view draws to the end, so that both see the same machine.
    const scenes::BackgroundLoad load(scenes::BackgroundLoad::parse(a.str("background-load", "none")));
    renderer.draw(list, cams[0]);  // uploads

    // The machine's own spread: the first view drawn again and again with the static ranges.
    const std::vector<double> same = scenes::timeSameView(renderer, scene, cams[0], int(a.num("jitter-draws", 60)));
    const double sameMedian = median(same);
    std::vector<double> sameDev;
    for (double t : same) sameDev.push_back(std::abs(t - sameMedian));

    std::vector<double> total, dev, select, predErr, draw, gpu;
    double mae = 0, pct = 0, tris = 0, dropped = 0, changed = 0, kept = 0, flicker = 0, levels[4] = {};
    const bool sameView = a.flag("same-view");
    sg::Image previous;
    int flickerFrames = 0;
    const int count = int(cams.size());
    // Warm-up: one pass over the path, so that stress and the model settle on it.
    run.run(
        scene, count, count, [&](int i) { return cams[size_t(i)]; }, nullptr,
        [&](int i, const scenes::LodFrame& f) {
            const sg::CullStats& st = f.stats;
            const double t = f.frameMs;
            if (a.flag("trace"))
                std::fprintf(stderr,
                             "frame %6.2f cull %5.2f draw %6.2f predicted %6.2f tris %7llu items %5llu lods %5llu "
                             "dropped %5llu changed %5llu kept %llu budget %6.2f\n",
                             t, f.cullMs, f.drawMs, st.lodPredictedMs, (unsigned long long)st.triangles,
                             (unsigned long long)st.geometries, (unsigned long long)st.lodObjects,
                             (unsigned long long)st.lodDropped, (unsigned long long)st.lodChanged,
                             (unsigned long long)st.lodPlansKept, st.lodBudgetMs);
            total.push_back(t);
            draw.push_back(f.drawMs);
            if (f.gpuMs >= 0.0) gpu.push_back(f.gpuMs);
            dev.push_back(std::abs(t - budget));
            select.push_back(st.lodSelectMs);
            if (method == "budget") predErr.push_back(std::abs(f.drawMs - st.lodPredictedMs));  // before drawing
            tris += double(st.triangles);
            dropped += double(st.lodDropped);
            changed += double(st.lodChanged);
            kept += double(st.lodPlansKept);
            for (int l = 0; l < 4; ++l) levels[l] += double(st.lodLevels[l]);
            const sg::Image got = renderer.readColor();
            const sg::Camera& cam = cams[size_t(i)];
            sg::CullStats rs;
            refCull.cull(scene, cam, full, list, rs);
            renderer.draw(list, cam);
            const sg::Image ref = renderer.readColor();
            mae += sg::meanAbsoluteError(got, ref);
            pct += 100.0 * double(sg::countDifferingPixels(got, ref)) / double(got.width * got.height);
            // On a still view every pixel that differs from the frame before is flicker.
            if (sameView && !previous.rgba.empty()) {
                flicker += 100.0 * double(sg::countDifferingPixels(got, previous)) / double(got.width * got.height);
                ++flickerFrames;
            }
            if (sameView) previous = got;
        });
    const double k = double(cams.size());
    double mean = 0;
    for (double t : total) mean += t / k;
    Json j;
    j.add("command", "lod")
        .add("scene", sceneName)
        .addInt("n", factory ? 0 : n)
        .add("path", path)
        .add("method", method);
    j.add("budget_ms", budget)
        .addInt("frames", long(cams.size()))
        .add("may_drop", mayDrop && method == "budget" ? "yes" : "no");
    j.add("level_errors", a.flag("guess-accuracy") ? "guessed" : "known")
        .add("same_view", a.flag("same-view") ? "yes" : "no");
    j.add("depth", renderer.depthMode() == sg::Renderer::DepthMode::ReverseZ ? "reverse-z" : "classic");
    j.add("frame_ms_mean", mean).add("frame_ms_median", median(total)).add("frame_ms_p95", percentile(total, 0.95));
    j.add("frame_ms_max", percentile(total, 1.0)).add("budget_abs_dev_p95_ms", percentile(dev, 0.95));
    j.add("draw_ms_median", median(draw));                  // the CPU's, until finished
    if (!gpu.empty()) j.add("gpu_ms_median", median(gpu));  // the GL's own (GL_TIME_ELAPSED)
    j.add("image_mae", mae / k).add("image_pct_differing", pct / k);
    if (flickerFrames > 0) j.add("flicker_pct_differing", flicker / flickerFrames);  // from the frame before
    if (load.kind() != scenes::BackgroundLoad::Kind::None)
        j.add("background_load", scenes::BackgroundLoad::name(load.kind()));
    if (!same.empty())
        j.add("same_view_jitter_p95_ms", percentile(sameDev, 0.95))
            .add("same_view_median_ms", sameMedian)
            .add("same_view_jitter_p95_ratio", percentile(sameDev, 0.95) / sameMedian);
    j.add("select_ms_median", median(select)).add("triangles_mean", tris / k).add("dropped_mean", dropped / k);
    if (!predErr.empty()) {
        j.add("model_abs_error_ms_median", median(predErr));
        // Levels shown otherwise than last frame (the budget keeps each LOD's history): with --same-view, flicker.
        j.add("level_changes_per_frame", changed / k);
        j.add("plans_kept_pct", 100.0 * kept / k);
        for (int l = 0; l < 2; ++l)
            j.add("level" + std::to_string(l) + "_mean", levels[l] / k);  // the city and the factory have two
    }
    j.print(a);
    return 0;
}

}  // namespace bench
