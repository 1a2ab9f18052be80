// sgbench style: what styling features by their properties costs. The city with its buildings as features
// (CityOptions::features: N=100 is 10,000 of them), culled once for a fixed view over most of it and drawn headless,
// frame by frame three ways in turn (A B C A B C ...): unstyled; with a 3D Tiles style that hides the low buildings
// and colours the rest by height and use; with the colours alone (every building shown: the same items drawn as
// unstyled, so its ratio is the colouring's own cost). Also the restyle (FeatureStyle::setRule to the end of the
// first frame drawn with it), styleTable alone over the whole table, the store's bytes per feature, and the pixels
// the style changed: a style that changes none is a failure.
#include "loaders/tiles/StyleJson.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/KeepFreedMemory.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/style/FeatureStyle.h"
#include "sg/style/StyleTable.h"
#include "sgbench/Bench.h"
#include "testbed/City.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace bench {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// Three colours by height and use: the first condition that holds gives the colour.
constexpr const char* kColorJson =
    R"j({"conditions": [["${height} > 40", "color('#c0392b')"], ["${use} === 'office'", "color('#2980b9')"],)j"
    R"j( ["true", "color('#f1c40f')"]]})j";

// The style as 3D Tiles JSON, read as a viewer reads a style file; `show` adds the rule that hides low buildings.
std::shared_ptr<const sg::Style> cityStyle(bool show) {
    const std::string text =
        std::string("{") + (show ? R"j("show": "${height} > 12", )j" : "") + "\"color\": " + kColorJson + "}";
    std::vector<std::string> warnings;
    auto style = std::make_shared<const sg::Style>(sg::parseStyleJson("sgbench style", text, &warnings));
    if (!warnings.empty()) throw std::runtime_error("sgbench style: the style has warnings: " + warnings[0]);
    return style;
}

// The rule a viewer sets for a style: evaluated over each table the renderer meets.
sg::FeatureStyle::Rule ruleOf(std::shared_ptr<const sg::Style> style) {
    return [style](const sg::PropertyStore& store, int table, std::vector<uint8_t>& rgba) {
        rgba = sg::styleTable(*style, store, table).rgba;
    };
}

// The first node below `n` that is a feature: the city's buildings all read one table of one store.
const sg::MeshFeatures* findFeatures(const sg::Node& n) {
    if (n.features() && n.features()->store && !n.features()->sets.empty()) return n.features();
    for (size_t i = 0; i < n.numChildren(); ++i)
        if (const sg::MeshFeatures* f = findFeatures(*n.child(i))) return f;
    return nullptr;
}

// From beyond the city's south-west corner, high up, looking at its centre: every building in view.
sg::Camera overview(int n, int w, int h) {
    const sg::dvec3 centre(10.0 * n, 10.0 * n, 0.0);
    sg::Camera cam;
    cam.setViewport(w, h);
    cam.setPerspective(60.0, double(w) / double(h), 1.0, 50.0 * n);
    cam.setLookAt(centre + sg::dvec3(-9.0 * n, -9.0 * n, 8.0 * n), centre, sg::dvec3(0, 0, 1));
    return cam;
}

}  // namespace

int runStyle(const Args& a) {
    const int n = int(a.num("n", 100)), frames = int(a.num("frames", 30)), restyles = int(a.num("restyles", 10));
    if (n < 1 || n > 1000)
        throw std::invalid_argument("sgbench style: --n " + std::to_string(n) + " is not in 1..1000");
    if (frames < 1 || restyles < 1)
        throw std::invalid_argument("sgbench style: --frames and --restyles must be at least 1");
    const int w = int(a.num("width", 1280)), h = int(a.num("height", 720));
    if (w < 16 || h < 16) throw std::invalid_argument("sgbench style: --width and --height must be at least 16");

    sg::OsmesaContext ctx(w, h);
    sg::Renderer renderer;
    if (renderer.softwareRasterizer()) sg::keepFreedMemory();  // as a frame loop does (sg/gl/KeepFreedMemory.h)
    scenes::CityOptions opt;
    opt.n = n;
    opt.features = true;
    sg::Scene scene(scenes::buildCity(opt));
    scene.update();
    const sg::MeshFeatures* features = findFeatures(*scene.root());
    if (!features) throw std::runtime_error("sgbench style: the city has no features");
    const sg::PropertyStore& store = *features->store;
    const int table = features->sets[0].propertyTable;
    if (table < 0 || size_t(table) >= store.tables().size())
        throw std::runtime_error("sgbench style: the buildings' feature set has no table");
    const uint64_t rows = store.tables()[size_t(table)].count;

    const sg::Camera cam = overview(n, w, h);
    sg::CullTraversal cull;
    sg::DrawList list;
    sg::CullStats cullStats;
    cull.cull(scene, cam, sg::CullSettings{}, list, cullStats);

    const auto styled = cityStyle(true), colorOnly = cityStyle(false);
    std::array<sg::ref_ptr<sg::FeatureStyle>, 3> ways{nullptr, sg::make<sg::FeatureStyle>(),
                                                      sg::make<sg::FeatureStyle>()};
    ways[1]->setRule(ruleOf(styled));
    ways[2]->setRule(ruleOf(colorOnly));
    auto frame = [&](const sg::ref_ptr<sg::FeatureStyle>& style) {
        renderer.setFeatureStyle(style);
        const auto t0 = Clock::now();
        renderer.draw(list, cam);
        renderer.finish();
        return msSince(t0);
    };

    // Each way once before the timing (uploads, shader variants, the styles' tables), its picture kept.
    std::array<sg::Image, 3> images;
    std::array<uint64_t, 3> items{};
    for (size_t k = 0; k < ways.size(); ++k) {
        frame(ways[k]);
        images[k] = renderer.readColor();
        items[k] = renderer.lastStats().instances;
    }
    std::array<std::vector<double>, 3> ms;
    std::vector<double> styleRatio, colorRatio;
    for (int f = 0; f < frames; ++f) {
        double t[3];
        for (size_t k = 0; k < ways.size(); ++k) ms[k].push_back(t[k] = frame(ways[k]));
        styleRatio.push_back(t[1] / t[0]);
        colorRatio.push_back(t[2] / t[0]);
    }

    // A new rule, then the frame that shows it (its table evaluated inside the draw); and the evaluation alone.
    std::vector<double> restyleMs, tableMs;
    uint64_t hidden = 0;
    for (int r = 0; r < restyles; ++r) {
        renderer.setFeatureStyle(ways[1]);
        const auto t0 = Clock::now();
        ways[1]->setRule(ruleOf(styled));
        renderer.draw(list, cam);
        renderer.finish();
        restyleMs.push_back(msSince(t0));
        const auto t1 = Clock::now();
        const sg::StyledTable st = sg::styleTable(*styled, store, table);
        tableMs.push_back(msSince(t1));
        hidden = 0;
        for (size_t i = 3; i < st.rgba.size(); i += 4) hidden += st.rgba[i] == 0 ? 1 : 0;
    }

    const size_t styledPixels = sg::countDifferingPixels(images[0], images[1], 0);
    const size_t colorPixels = sg::countDifferingPixels(images[0], images[2], 0);
    Json j;
    j.add("command", "style").add("scene", "city").addInt("n", n).addInt("features", long(rows));
    j.addInt("frames", frames).addInt("width", w).addInt("height", h);
    j.addInt("items_unstyled", long(items[0])).addInt("items_styled", long(items[1]));
    j.addInt("items_color_only", long(items[2])).addInt("features_hidden", long(hidden));
    j.add("frame_ms_median_unstyled", median(ms[0])).add("frame_ms_median_styled", median(ms[1]));
    j.add("frame_ms_median_color_only", median(ms[2]));
    j.add("style_ratio", median(styleRatio)).add("color_only_ratio", median(colorRatio));
    j.add("restyle_ms_median", median(restyleMs)).add("style_table_ms_median", median(tableMs));
    j.add("style_table_ms_max", *std::max_element(tableMs.begin(), tableMs.end()));
    j.add("bytes_per_feature", rows ? double(store.bytes()) / double(rows) : 0.0);
    j.addInt("pixels_differing_styled", long(styledPixels)).addInt("pixels_differing_color_only", long(colorPixels));
    j.print(a);
    if (styledPixels == 0 || colorPixels == 0) {
        std::fprintf(stderr, "sgbench style: a style changed no pixel of the picture\n");
        return 1;
    }
    return 0;
}

}  // namespace bench
