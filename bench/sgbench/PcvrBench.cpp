// sgbench pcvr: the city table of the PCVR conservative-visibility paper (Qi et al. 2000) on the scene built to its
// description (testbed/PcvrCity.h): objects and triangles culled by the object test, triangles the screen-rectangle
// rejection removes after it, frame rate, and the pixels that differ from the unculled render, for center-box with
// and without the rejection (clusters of K triangles, --clusters K1,K2,...) and aabb for reference (with the
// rejection at the default cluster size). Every setting is drawn on every frame, in turn, headless at 1024x768.
#include "sg/cull/CullTraversal.h"
#include "sg/cull/TriangleClusters.h"
#include "sg/gl/KeepFreedMemory.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/io/ImageIO.h"
#include "sgbench/Bench.h"
#include "testbed/PcvrCity.h"

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace bench {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

struct Row {
    std::string name;
    sg::CullSettings set;
    std::unique_ptr<sg::CullTraversal> cull = std::make_unique<sg::CullTraversal>();
    double objectsCulled = 0, trisObject = 0, trisRect = 0, trisDrawn = 0, trisNaive = 0;
    double drawCalls = 0, clustersTested = 0;
    std::vector<double> frameMs, cullMs;
    uint64_t pixels = 0, pixelsMax = 0;
    int framesWithError = 0;
};
}  // namespace

int runPcvr(const Args& a) {
    const int frames = int(a.num("frames", scenes::kPcvrFrames));
    if (frames < 1 || frames > 100000)
        throw std::invalid_argument("sgbench pcvr: --frames " + std::to_string(frames) + " is not in 1..100000");
    const uint64_t seed = uint64_t(a.num("seed", 1));
    const bool pixels = !a.flag("no-pixels");
    std::vector<uint32_t> clusters;
    {
        std::stringstream ss(a.str("clusters", "32"));
        std::string item;
        while (std::getline(ss, item, ',')) {
            char* end = nullptr;
            const long k = std::strtol(item.c_str(), &end, 10);
            if (item.empty() || *end || k < 1 || k > 65536)
                throw std::invalid_argument(
                    "sgbench pcvr: --clusters takes sizes in 1..65536 separated by commas, got '" +
                    a.str("clusters", "") + "'");
            clusters.push_back(uint32_t(k));
        }
    }
    const int w = 1024, h = 768;
    sg::Scene scene(scenes::buildPcvrCity(seed));
    scene.update();
    sg::OsmesaContext ctx(w, h);
    sg::Renderer renderer;
    if (renderer.softwareRasterizer()) sg::keepFreedMemory();  // as a frame loop does (sg/gl/KeepFreedMemory.h)

    std::vector<Row> rows;
    auto addRow = [&](const std::string& name, sg::CullStrategy s, uint32_t k) {
        Row r;
        r.name = name;
        r.set.strategy = s;
        r.set.occlusion.mode = sg::OcclusionMode::Off;  // the paper has none
        r.set.screenRect = k > 0;
        if (k) r.set.screenRectTriangles = k;
        rows.push_back(std::move(r));
    };
    addRow("none", sg::CullStrategy::None, 0);
    addRow("center-box", sg::CullStrategy::CenterBox, 0);
    for (uint32_t k : clusters) addRow("center-box+screen-rect/" + std::to_string(k), sg::CullStrategy::CenterBox, k);
    addRow("aabb", sg::CullStrategy::Aabb, 0);
    const uint32_t byDefault = sg::CullSettings{}.screenRectTriangles;  // aabb's row: the default cluster size
    addRow("aabb+screen-rect/" + std::to_string(byDefault), sg::CullStrategy::Aabb, byDefault);

    sg::DrawList list;
    sg::CullStats st;
    for (int f = 0; f < std::min(frames, 8); ++f)  // warm-up: meshes uploaded, clusters built
        for (Row& r : rows) {
            r.cull->cull(scene, scenes::pcvrCityCamera(f, w, h), r.set, list, st);
            renderer.draw(list, scenes::pcvrCityCamera(f, w, h));
        }
    renderer.finish();
    const double total = scenes::kPcvrTriangles;
    for (int f = 0; f < frames; ++f) {
        const sg::Camera cam = scenes::pcvrCityCamera(f, w, h);
        sg::Image ref;
        for (size_t k = 0; k < rows.size(); ++k) {
            Row& r = rows[k];
            const auto t0 = Clock::now();
            r.cull->cull(scene, cam, r.set, list, st);
            const double cullMs = msSince(t0);
            renderer.draw(list, cam);
            renderer.finish();
            r.frameMs.push_back(msSince(t0));
            r.cullMs.push_back(cullMs);
            const double drawn = double(st.triangles), rect = double(st.culledScreenRectTriangles);
            r.objectsCulled += scenes::kPcvrObjects - double(st.geometries + st.culledScreenRectGeometries);
            r.trisObject += total - drawn - rect;
            r.trisRect += rect;
            r.trisDrawn += drawn;
            r.drawCalls += double(renderer.lastStats().drawCalls);
            r.clustersTested += double(st.screenRectClusters);
            if (!r.set.screenRect && r.set.strategy == sg::CullStrategy::CenterBox) {
                // What the paper's per-triangle test (projected vertices' rectangle) would remove from these.
                const sg::dmat4 vp = cam.projection() * cam.viewRotation();
                for (const sg::DrawItem& it : list.items)
                    r.trisNaive += it.mesh->triangleCount() -
                                   sg::TriangleClusters::keepTrianglesNaive(*it.mesh, vp, sg::dmat4(it.matrix()));
            }
            if (pixels) {
                sg::Image img = renderer.readColor();
                if (k == 0) {
                    ref = std::move(img);
                } else {
                    const uint64_t d = sg::countDifferingPixels(ref, img);
                    r.pixels += d;
                    r.pixelsMax = std::max(r.pixelsMax, d);
                    r.framesWithError += d > 0;
                }
            }
        }
    }

    const double n = frames;
    // The share of what the object test left that the rejection removed, over all frames (the paper's 30%: 1,786 of
    // 5,865 on average).
    auto share = [](const Row& r) { return r.trisRect / std::max(1.0, r.trisRect + r.trisDrawn); };
    if (!a.flag("json")) {
        std::printf("sgbench pcvr: %d frames, 1024x768, %d objects, %u triangles (seed %llu)\n", frames,
                    scenes::kPcvrObjects, scenes::kPcvrTriangles, static_cast<unsigned long long>(seed));
        std::printf(
            "| setting | objects culled | triangles culled (object test) | removed by screen rect (share of rest) | "
            "triangles drawn | draw calls | cull ms | frame ms (fps) | differing pixels (mean, max, frames) |\n");
        std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
        std::printf("| paper (PII 350, software) | 16 | 17,535 | 1,786 (30%%) | | | | (16 fps) | |\n");
    }
    for (const Row& r : rows) {
        const double fm = median(r.frameMs);
        if (a.flag("json")) {
            Json j;
            j.add("command", "pcvr").add("setting", r.name).addInt("frames", frames).addInt("seed", long(seed));
            j.add("objects_culled_mean", r.objectsCulled / n).add("triangles_culled_object_mean", r.trisObject / n);
            j.add("triangles_removed_screen_rect_mean", r.trisRect / n).add("screen_rect_share", share(r));
            if (r.trisNaive > 0) j.add("triangles_removed_per_triangle_test_mean", r.trisNaive / n);
            j.add("triangles_drawn_mean", r.trisDrawn / n).add("draw_calls_mean", r.drawCalls / n);
            j.add("clusters_tested_mean", r.clustersTested / n);
            j.add("cull_ms_median", median(r.cullMs)).add("frame_ms_median", fm).add("fps", 1000.0 / fm);
            if (pixels) {
                j.add("differing_pixels_mean", double(r.pixels) / n).addInt("differing_pixels_max", long(r.pixelsMax));
                j.addInt("frames_with_error", r.framesWithError);
            }
            j.print(a);
            continue;
        }
        char rect[96] = "-";
        if (r.set.screenRect) std::snprintf(rect, sizeof rect, "%.0f (%.0f%%)", r.trisRect / n, 100.0 * share(r));
        char err[96] = "not measured";
        if (pixels)
            std::snprintf(err, sizeof err, "%.0f, %llu, %d", double(r.pixels) / n,
                          static_cast<unsigned long long>(r.pixelsMax), r.framesWithError);
        std::printf("| %s | %.1f | %.0f | %s | %.0f | %.1f | %.3f | %.2f (%.0f) | %s |\n", r.name.c_str(),
                    r.objectsCulled / n, r.trisObject / n, rect, r.trisDrawn / n, r.drawCalls / n, median(r.cullMs), fm,
                    1000.0 / fm, err);
        if (r.trisNaive > 0)  // the paper's own test, per triangle, on what center-box kept: counted, not drawn
            std::printf(
                "| center-box, then the paper's per-triangle rectangles (counted only) | %.1f | %.0f | %.0f (%.0f%%) "
                "| %.0f | | | | |\n",
                r.objectsCulled / n, r.trisObject / n, r.trisNaive / n,
                100.0 * r.trisNaive / std::max(1.0, r.trisDrawn), (r.trisDrawn - r.trisNaive) / n);
    }
    return 0;
}

}  // namespace bench
