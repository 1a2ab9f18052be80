#include "accuracy/Accuracy.h"

#include "scenes/City.h"
#include "scenes/RandomScene.h"

namespace accuracy {

using namespace sg;

Harness::Harness(int w, int h) : w_(w), h_(h), ctx_(w, h), renderer_(std::make_unique<Renderer>()) {}

Image Harness::render(const Scene& scene, const Camera& view, const CullSettings& s) {
    CullStats st;
    cull_.cull(scene, view, s, list_, st);
    renderer_->draw(list_, view);
    return renderer_->readColor();
}

uint64_t Harness::compare(const Scene& scene, const Camera& view, const CullSettings& s, Image* refOut, Image* gotOut) {
    CullSettings off = s;
    off.strategy = CullStrategy::None;
    off.smallFeaturePixels = 0.0;
    const Image ref = render(scene, view, off);
    const Image got = render(scene, view, s);
    const uint64_t d = countDifferingPixels(ref, got);
    if (refOut) *refOut = ref;
    if (gotOut) *gotOut = got;
    return d;
}

std::vector<Result> Harness::run(const Scene& scene, const std::vector<Camera>& views, const std::vector<CullSettings>& settings) {
    std::vector<Result> out(settings.size());
    for (size_t k = 0; k < settings.size(); ++k) {
        out[k].name = strategyName(settings[k].strategy);
        if (settings[k].smallFeaturePixels > 0) out[k].name += "+small-feature";
        out[k].framePixels = double(w_) * h_;
    }
    for (size_t v = 0; v < views.size(); ++v) {
        Camera cam = views[v];
        cam.setViewport(w_, h_);
        CullSettings off;
        off.strategy = CullStrategy::None;
        const Image ref = render(scene, cam, off);
        for (size_t k = 0; k < settings.size(); ++k) {
            const uint64_t d = countDifferingPixels(ref, render(scene, cam, settings[k]));
            Result& r = out[k];
            r.views++;
            r.perView.push_back(d);
            r.differingTotal += d;
            if (d > r.differingMax) {
                r.differingMax = d;
                r.worstView = int(v);
            }
            r.viewsWithError += d > 0;
        }
    }
    return out;
}

std::vector<Camera> cityViews(int n, int count, uint64_t seed, int w, int h) {
    scenes::Rng rng(seed);
    const Box city{dvec3(0, 0, 0), dvec3(20.0 * n, 20.0 * n, 60.0)};
    std::vector<Camera> views;
    for (int k = 0; k < count; ++k) {
        Camera cam = scenes::randomCamera(rng, city, k, w, h);
        switch (k % 8) {
            case 6: {  // street level, looking along a street
                const double x = 20.0 * rng.below(n), y = rng.uniform(0, 20.0 * n), t = rng.uniform(0, 6.283);
                const dvec3 eye(x, y, 1.7);
                cam.setPerspective(60, double(w) / h, 0.5, 3000);
                cam.setLookAt(eye, eye + dvec3(std::sin(t), std::cos(t), rng.uniform(-0.1, 0.3)), dvec3(0, 0, 1));
                break;
            }
            case 7: {  // inside a building
                const int i = rng.below(n), j = rng.below(n);
                const double hgt = scenes::cityHeight(uint32_t(i), uint32_t(j));
                const dvec3 eye(20.0 * i + 10 + rng.uniform(-5, 5), 20.0 * j + 10 + rng.uniform(-5, 5), rng.uniform(0.5, hgt - 0.5));
                cam.setPerspective(rng.uniform(40, 120), double(w) / h, rng.uniform(0.05, 1), 3000);
                cam.setLookAt(eye, eye + dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-0.5, 0.5)), dvec3(0, 0, 1));
                break;
            }
            default: break;
        }
        views.push_back(cam);
    }
    return views;
}

std::vector<Camera> boxViews(const Box& b, int count, uint64_t seed, int w, int h) {
    scenes::Rng rng(seed);
    std::vector<Camera> views;
    for (int k = 0; k < count; ++k) views.push_back(scenes::randomCamera(rng, b, k, w, h));
    return views;
}

}  // namespace accuracy
