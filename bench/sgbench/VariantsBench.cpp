// sgbench variants: a scene that switches to a material never drawn before, one a frame: 32 combinations of texture,
// vertex colours, unlit, alpha cutoff and physical (with a metallic-roughness map), then points and lines, a Switch
// showing one at a time, each frame culled, drawn and finished. Twice, each with a renderer of its own: as drawn
// (each variant compiled in the frame that first draws it) and prepared (Renderer::prepareVariants of the scene
// first, as sg::Viewer does before a scene's first frame). The target: no frame over 1.5x the median.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Switch.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/scene/Scene.h"
#include "sgbench/Bench.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>
#include <vector>

namespace bench {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

sg::ref_ptr<sg::Mesh> square(bool colours) {
    auto m = sg::make<sg::Mesh>();
    std::vector<sg::vec4> c;
    if (colours) c.assign(4, sg::vec4(1.0f, 0.5f, 0.5f, 1.0f));
    m->set({{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}}, std::vector<sg::vec3>(4, sg::vec3(0, -1, 0)),
           {0, 1, 2, 0, 2, 3}, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, c);
    return m;
}

// Combination k: bit 0 textured, bit 1 vertex colours, bit 2 unlit, bit 3 an alpha cutoff, bit 4 physical; 32 and
// 33 points and lines.
sg::ref_ptr<sg::Switch> combinations() {
    auto tex = sg::make<sg::Texture>(64, 64, std::vector<uint8_t>(64 * 64 * 4, 200));
    auto sw = sg::make<sg::Switch>();
    for (int k = 0; k < 32; ++k) {
        auto mat = sg::make<sg::Material>(sg::vec4(0.8f, 0.6f, 0.4f, 1.0f));
        if (k & 1) mat->texture = tex;
        mat->unlit = (k & 4) != 0;
        if (k & 8) mat->alphaCutoff = 0.5f;
        if (k & 16) {
            mat->physical = true;
            mat->pbr.metallic = 0.0f;
            mat->pbr.metallicRoughness.texture = tex;
        }
        sw->addChild(sg::make<sg::Geometry>(square((k & 2) != 0), mat), k == 0);
    }
    auto points = sg::make<sg::Mesh>();
    points->setPoints({{0.0f, 0.0f, 0.0f}, {0.5f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.5f}});
    sw->addChild(sg::make<sg::Geometry>(points, sg::make<sg::Material>()), false);
    auto lines = sg::make<sg::Mesh>();
    lines->setLines({{-1.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}}, {0, 1});
    sw->addChild(sg::make<sg::Geometry>(lines, sg::make<sg::Material>()), false);
    return sw;
}

struct Run {
    std::vector<double> ms;     // each frame's: cull, draw, finished
    std::vector<double> again;  // the same combinations shown again, in the same order: what each costs drawn warm
    std::vector<double> third;  // and a third time: how much a warm frame varies from one showing to the next
    double prepareMs = 0.0;
    uint64_t compiledInDraw = 0;
};

Run run(bool prepare, const sg::Camera& cam) {
    sg::ref_ptr<sg::Switch> sw = combinations();
    auto root = sg::make<sg::Group>();
    root->addChild(sw);
    sg::Scene scene(root);
    sg::Renderer renderer;
    sg::CullTraversal cull;
    sg::DrawList list;
    sg::CullStats st;
    Run r;
    if (prepare) {
        const auto t = Clock::now();
        renderer.prepareVariants(*root, cam);
        renderer.finish();
        r.prepareMs = msSince(t);
    }
    for (std::vector<double>* pass : {&r.ms, &r.again, &r.third}) {
        for (size_t k = 0; k < sw->numChildren(); ++k) {
            sw->setOnly(k);
            const auto t = Clock::now();
            scene.update();
            cull.cull(scene, cam, sg::CullSettings{}, list, st);
            renderer.draw(list, cam);
            renderer.finish();
            pass->push_back(msSince(t));
        }
        if (pass == &r.ms) r.compiledInDraw = renderer.compiledInDraw();  // the first showings' compiles
    }
    return r;
}

void report(Json& j, const std::string& name, const Run& r) {
    const auto slowest = std::max_element(r.ms.begin(), r.ms.end());
    const double med = median(r.ms), worst = *slowest;
    j.add(name + "_frame_ms_median", med).add(name + "_frame_ms_max", worst);
    j.addInt(name + "_slowest_combination", long(slowest - r.ms.begin()));  // which frame: what it first drew
    j.add(name + "_max_over_median", med > 0.0 ? worst / med : 0.0);
    j.addInt(name + "_compiled_in_draw", long(r.compiledInDraw));
    // The combinations differ in cost (a textured physical square fills slower than an unlit one), so the first
    // use is also set against the same combination drawn again: how much its first frame costs over its next.
    std::vector<double> ratio, warm;
    for (size_t k = 0; k < r.ms.size(); ++k) {
        ratio.push_back(r.again[k] > 0.0 ? r.ms[k] / r.again[k] : 0.0);
        warm.push_back(r.again[k] > 0.0 ? r.third[k] / r.again[k] : 0.0);
    }
    const auto worstFirst = std::max_element(ratio.begin(), ratio.end());
    j.add(name + "_first_over_again_max", *worstFirst).add(name + "_first_over_again_median", median(ratio));
    j.addInt(name + "_first_over_again_worst", long(worstFirst - ratio.begin()));
    j.add(name + "_third_over_again_max", *std::max_element(warm.begin(), warm.end()));
    j.add(name + "_again_max_over_median", *std::max_element(r.again.begin(), r.again.end()) / median(r.again));
}

}  // namespace

int runVariants(const Args& a) {
    const int w = int(a.num("width", 640)), h = int(a.num("height", 480));
    if (w < 1 || h < 1 || w > 8192 || h > 8192)
        throw std::invalid_argument("sgbench variants: --width and --height must be in 1..8192");
    sg::OsmesaContext context(w, h);
    sg::Camera cam;
    cam.setViewport(w, h);
    cam.setPerspective(50.0, double(w) / double(h), 0.1, 100.0);
    cam.setLookAt(sg::dvec3(0, -3, 0), sg::dvec3(0.0), sg::dvec3(0, 0, 1));
    const Run drawn = run(false, cam);
    const Run prepared = run(true, cam);
    Json j;
    j.add("command", "variants").addInt("combinations", long(drawn.ms.size())).addInt("width", w).addInt("height", h);
    report(j, "drawn", drawn);
    report(j, "prepared", prepared);
    j.add("prepare_ms", prepared.prepareMs);
    j.print(a);
    return 0;
}

}  // namespace bench
