// sgbench accuracy: differing pixels between the unculled and the culled render over K random views.
#include "accuracy/Accuracy.h"
#include "scenes/City.h"
#include "scenes/RandomScene.h"
#include "sgbench/Bench.h"

#include <iostream>
#include <stdexcept>

namespace bench {

int runAccuracy(const Args& a) {
    const std::string sceneName = a.str("scene", "city");
    const int views = int(a.num("views", 200));
    const uint64_t seed = uint64_t(a.num("seed", 1));
    const int w = int(a.num("width", 320)), h = int(a.num("height", 180));
    const int n = int(a.num("n", 16));
    if (views < 1) throw std::invalid_argument("sgbench accuracy: --views must be at least 1");
    sg::CullSettings set;
    set.strategy = sg::parseStrategy(a.str("strategy", "aabb"));
    set.smallFeaturePixels = double(a.num("small-feature", 0));

    sg::ref_ptr<sg::Node> root;
    std::vector<sg::Camera> cams;
    if (sceneName == "city") {
        root = scenes::buildCity({n, false});
        cams = accuracy::cityViews(n, views, seed, w, h);
    } else if (sceneName == "random") {
        root = scenes::buildRandomScene(seed);
        cams = accuracy::boxViews(sg::Box{sg::dvec3(-70), sg::dvec3(70)}, views, seed, w, h);
    } else {
        throw std::invalid_argument("sgbench accuracy: --scene " + sceneName +
                                    ": only city and random are available (glTF files need the glTF loader)");
    }
    sg::Scene scene(root);
    scene.update();
    accuracy::Harness harness(w, h);
    const accuracy::Result r = harness.run(scene, cams, {set})[0];
    Json j;
    j.add("command", "accuracy").add("scene", sceneName).add("strategy", r.name).addInt("seed", long(seed));
    j.addInt("width", w).addInt("height", h).addInt("views", r.views);
    j.addInt("differing_pixels_total", long(r.differingTotal)).addInt("differing_pixels_max", long(r.differingMax));
    j.addInt("views_with_error", r.viewsWithError).add("differing_percent_of_frames", r.percentOfFrames());
    j.add("conservative", sg::isConservative(set.strategy) && set.smallFeaturePixels == 0 ? "yes" : "no");
    if (a.flag("json"))
        std::cout << j.str() << std::endl;
    else
        std::cout << "sgbench accuracy\n" << j.table();
    return 0;
}

}  // namespace bench
