// sgbench accuracy: differing pixels between the unculled and the culled render over K random views.
#include "loaders/gltf/Gltf.h"
#include "sgbench/Bench.h"
#include "testbed/Accuracy.h"
#include "testbed/City.h"
#include "testbed/Office.h"
#include "testbed/RandomScene.h"

#include <stdexcept>

namespace bench {

int runAccuracy(const Args& a) {
    const std::string sceneName = a.str("scene", "city");
    const int views = int(a.num("views", 200));
    const uint64_t seed = uint64_t(a.num("seed", 1));
    const int w = int(a.num("width", 320)), h = int(a.num("height", 180));
    const int n = int(a.num("n", 16));
    const int r = int(a.num("r", 4));
    if (views < 1) throw std::invalid_argument("sgbench accuracy: --views must be at least 1");
    sg::CullSettings set;
    set.strategy = sg::parseStrategy(a.str("strategy", "aabb"));
    set.smallFeaturePixels = double(a.num("small-feature", 0));
    // Occlusion is off unless asked for (the settings' own default is Adaptive).
    set.occlusion.mode = sg::parseOcclusionMode(a.str("occlusion", "off"));
    const std::string cap = a.str("cap", "front");
    if (cap != "front" && cap != "centre")
        throw std::invalid_argument("sgbench accuracy: --cap must be front or centre (got '" + cap + "')");
    set.occlusion.measureOnly.cap = cap == "front" ? sg::OccluderCap::FrontFaces : sg::OccluderCap::CenterPlane;
    const bool occlusion = set.occlusion.mode != sg::OcclusionMode::Off;

    sg::ref_ptr<sg::Node> root;
    std::vector<sg::Camera> cams;
    if (sceneName == "city") {
        if (n < 1) throw std::invalid_argument("sgbench accuracy: --n must be at least 1");
        // With occlusion: the city's occluders (docs/scenes.md), and views where they hide things (streets, low
        // aerial ones).
        root = scenes::buildCity({n, occlusion});
        cams =
            occlusion ? accuracy::cityOcclusionViews(n, views, seed, w, h) : accuracy::cityViews(n, views, seed, w, h);
    } else if (sceneName == "office") {
        if (r < 1) throw std::invalid_argument("sgbench accuracy: --r must be at least 1");
        root = scenes::buildOffice(r);
        cams = accuracy::officeViews(r, views, seed, w, h);
    } else if (sceneName == "random") {
        root = scenes::buildRandomScene(seed);
        cams = accuracy::boxViews(sg::Box{sg::dvec3(-70), sg::dvec3(70)}, views, seed, w, h);
    } else if (sceneName.size() > 4 &&
               (sceneName.rfind(".gltf") == sceneName.size() - 5 || sceneName.rfind(".glb") == sceneName.size() - 4)) {
        root = sg::loadGltf(sceneName).root;  // a sg::LoadError names the file, the JSON path and why
    } else {
        throw std::invalid_argument("sgbench accuracy: --scene " + sceneName +
                                    ": expected city, office, random or a .gltf/.glb file");
    }
    sg::Scene scene(root);
    scene.update();
    if (cams.empty()) {  // a file: views of every kind around its bound
        const sg::Box b = scene.image().size() ? scene.image().box(0) : sg::Box{};
        if (b.empty()) throw std::invalid_argument("sgbench accuracy: " + sceneName + " has nothing to draw");
        cams = accuracy::boxViews(b, views, seed, w, h);
    }
    accuracy::Harness harness(w, h);
    const accuracy::Result res = harness.run(scene, cams, {set})[0];
    // Occlusion counts as conservative only with the front-faces cap.
    const bool conservative = sg::isConservative(set.strategy) && set.smallFeaturePixels == 0 &&
                              (!occlusion || set.occlusion.measureOnly.cap == sg::OccluderCap::FrontFaces);
    Json j;
    j.add("command", "accuracy").add("scene", sceneName).add("strategy", res.name).addInt("seed", long(seed));
    j.addInt("width", w).addInt("height", h).addInt("views", res.views);
    j.addInt("differing_pixels_total", long(res.differingTotal)).addInt("differing_pixels_max", long(res.differingMax));
    j.addInt("views_with_error", res.viewsWithError).add("differing_percent_of_frames", res.percentOfFrames());
    j.add("conservative", conservative ? "yes" : "no");
    // Added with the occlusion pass (after the original keys, whose order is kept).
    if (sceneName == "city") j.addInt("n", n);
    if (sceneName == "office") j.addInt("r", r);
    j.add("occlusion", sg::occlusionModeName(set.occlusion.mode)).add("cap", cap);
    j.addInt("culled_occlusion_total", long(res.culledOcclusionTotal));
    j.addInt("views_with_occlusion_culls", res.viewsWithOcclusionCulls);
    j.addInt("triangles_total", long(res.trianglesTotal))
        .addInt("reference_triangles_total", long(res.referenceTrianglesTotal));
    j.addInt("worst_view", res.worstView);
    j.print(a);
    return 0;
}

}  // namespace bench
