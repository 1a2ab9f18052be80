// sgbench tiles --path factory-walk: the factory's laser scan, tiled by `sgtile --points` (an octree of glTF point
// tiles refined ADD), flown from disk along the factory walkthrough (testbed/FactoryWalk.h) through sg::Viewer and its
// pager. Frame times (median, 99th percentile, worst, and the last two over the median) over all frames, over those
// with loads in flight (the pager has something queued, loading or waiting for its upload) and over the quiet rest;
// the resident memory's peak; the tiles loaded.
//
// The path's cameras are used as they are: the factory is +Z up in metres (its cameras' up is (0, 0, 1) and the
// ground's height a function of x and y), and the tiles are assumed to sit in the same frame. factoryscan writes the
// scene's own coordinates, with the LAS offset at the site's minimum corner (which the LAS reader adds back), and
// sgtile writes glTF's +Y up, which loadTileset turns back to +Z. `tileset_in_site` says whether the tileset's centre
// lies in the factory's box; a tileset elsewhere would be flown past, not through.
//
// --settle-check: at K views spread along the path (--views, 4 by default) the paged viewer is held until settled,
// and its picture is compared with that of the same tiles held in memory: a second copy of the tileset, opened in
// the same process, gets loaded exactly the tiles the pager had attached (both graphs walked together), and is drawn
// by a viewer of its own with the same camera and point shading. The cull of both chooses by the same screen-space
// error, so the tiles shown are those the pager selected: every pixel should be equal (`settle_differing_pixels`).
#include "nodes/PagedLOD.h"
#include "sg/io/ImageIO.h"
#include "sgbench/Tiles.h"
#include "testbed/Factory.h"
#include "testbed/FactoryWalk.h"

#include <malloc.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace bench {

namespace {

using Clock = std::chrono::steady_clock;

// Median, 99th percentile and worst of `v` as <prefix>_ms_*, and the last two over the median (how far the hitches
// stand out); null ratios for no frames.
void addFrameTimes(Json& j, const std::string& prefix, const std::vector<double>& v) {
    const double med = median(v), p99 = percentile(v, 0.99), worst = percentile(v, 1.0);
    const double none = std::numeric_limits<double>::quiet_NaN();
    j.addInt(prefix + "_frames", long(v.size()));
    j.add(prefix + "_ms_median", med).add(prefix + "_ms_p99", p99).add(prefix + "_ms_max", worst);
    j.add(prefix + "_p99_over_median", med > 0.0 ? p99 / med : none);
    j.add(prefix + "_max_over_median", med > 0.0 ? worst / med : none);
}

// Loads into `held` the details that `paged` has attached, node for node. Both are graphs of the same tileset, so
// they have the same shape wherever both have the same details. Returns the details loaded; throws
// std::runtime_error where the shapes part (the tileset changed on disk, say).
size_t mirrorDetails(const sg::Node& paged, sg::Node& held, const sg::PageLoadFunction& load) {
    if (paged.kind() != held.kind())
        throw std::runtime_error(std::string("sgbench tiles: the held copy has a ") + sg::kindName(held.kind()) +
                                 " where the paged graph has a " + sg::kindName(paged.kind()));
    size_t loaded = 0;
    if (paged.kind() == sg::NodeKind::PagedLOD) {
        const auto& p = static_cast<const sg::PagedLOD&>(paged);
        auto& h = static_cast<sg::PagedLOD&>(held);
        if (p.detail() && !h.detail()) {
            sg::ref_ptr<sg::Node> d = load(sg::PageSource{h.file(), h.part()});
            h.attachDetail(d, sg::pageBytes(d.get()));
            ++loaded;
        }
    }
    if (paged.numChildren() != held.numChildren())
        throw std::runtime_error("sgbench tiles: the held copy's children differ from the paged graph's (" +
                                 std::to_string(held.numChildren()) + " against " +
                                 std::to_string(paged.numChildren()) + ")");
    for (size_t i = 0; i < paged.numChildren(); ++i) loaded += mirrorDetails(*paged.child(i), *held.child(i), load);
    return loaded;
}

struct HeldResult {
    size_t details = 0;    // loaded into the held copy
    size_t differing = 0;  // pixels
    sg::Image image;
};

// The same tiles as the paged viewer has attached now, held in a second copy of the tileset and drawn once settled
// (two frames: the first uploads) by a viewer of their own with the paged view's camera and point shading.
HeldResult drawHeld(const TilesFlight& t, const sg::Image& paged) {
    HeldResult r;
    sg::Tileset copy = sg::loadTileset(t.file, t.options);
    r.details = mirrorDetails(*t.tileset.root(), *copy.root(), copy.loadFunction());
    sg::Scene scene(copy.root());
    sg::Viewer viewer(scene);
    viewer.renderer().setPointShading(t.viewer.renderer().pointShading());
    sg::View& view = viewer.addView(t.view.camera);
    view.prefetchSeconds = 0.0;  // nothing to page: it holds what it draws
    viewer.frame();
    viewer.frame();
    r.image = viewer.renderer().readColor();
    r.differing = sg::countDifferingPixels(paged, r.image);
    return r;
}

// --settle-check at `views` cameras spread along the path; adds its figures to `j`. True when every view's
// pictures are equal.
bool settleCheck(const Args& a, const TilesFlight& t, const std::vector<sg::Camera>& cams, Json& j) {
    const int views = int(a.num("views", 4)), most = int(a.num("settle-frames", 20000));
    if (views < 1) throw std::invalid_argument("sgbench tiles: --views must be at least 1");
    const std::string png = a.str("png", "");  // a prefix: the pictures of the views that differ are saved
    long unsettled = 0, differingViews = 0, framesMax = 0;
    size_t pixels = 0, pixelsMax = 0, details = 0;
    for (int k = 0; k < views; ++k) {
        const size_t f = std::min(cams.size() - 1, size_t((k + 0.5) * double(cams.size()) / views));
        t.view.camera = cams[f];
        const int frames = settleTiles(t.viewer, t.view, t.pager, most);
        framesMax = std::max(framesMax, long(frames));
        const sg::PagerStats& st = t.pager.stats();
        unsettled += st.queued || st.loading || st.pending || t.view.cullStats().pagedRequested ||
                     t.view.cullStats().pagedCoarse;
        const sg::Image paged = t.viewer.renderer().readColor();
        const HeldResult held = drawHeld(t, paged);
        details += held.details;
        pixels += held.differing;
        pixelsMax = std::max(pixelsMax, held.differing);
        if (held.differing == 0) continue;
        ++differingViews;
        std::fprintf(stderr, "sgbench tiles: view %d (path frame %zu): %zu pixels differ from the held tiles\n", k, f,
                     held.differing);
        if (!png.empty()) {
            sg::savePng(png + std::to_string(k) + "-paged.png", paged);
            sg::savePng(png + std::to_string(k) + "-held.png", held.image);
        }
    }
    j.addInt("settle_views", views).addInt("settle_views_unsettled", unsettled);
    j.addInt("settle_frames_max", framesMax).addInt("settle_held_details", long(details));
    j.addInt("settle_views_differing", differingViews).addInt("settle_differing_pixels", long(pixels));
    j.addInt("settle_differing_pixels_max", long(pixelsMax));
    return differingViews == 0;
}

}  // namespace

sg::PointShading pointShadingFromArgs(const Args& a) {
    sg::PointShading p;
    if (a.flag("point-size")) {
        const std::string s = a.str("point-size", "");
        char* end = nullptr;
        const double v = std::strtod(s.c_str(), &end);
        if (end == s.c_str() || *end || !(v >= 1.0 && v <= 64.0))
            throw std::invalid_argument("sgbench tiles: --point-size wants pixels from 1 to 64, got '" + s + "'");
        p.pointSize = float(v);
    }
    p.round = a.flag("round");
    p.eyeDome = a.flag("edl");
    return p;
}

std::vector<sg::Camera> factoryWalkCameras(int frames, int w, int h, sg::Box& site) {
    std::vector<sg::Camera> cams;
    {
        scenes::Factory f = scenes::buildFactory();
        sg::Scene scene(f.root);
        scene.update();
        const scenes::WalkPath walk = scenes::buildWalkPath(f, scene, frames);
        site = scene.image().box(0);  // every switch's children are in the root's box, as the scan's points
        cams.reserve(walk.frames.size());
        for (const scenes::PathFrame& p : walk.frames) cams.push_back(scenes::pathCamera(p, w, h));
    }
    malloc_trim(0);  // the factory was made for the cameras only: the memory figures are the tileset's
    return cams;
}

int flyFactoryWalk(const Args& a, const TilesFlight& t, const std::vector<sg::Camera>& cams, const sg::Box& site) {
    std::vector<double> all, loading, quiet;
    std::vector<double> points;
    double maxRss = 0.0, maxHeap = 0.0;
    const auto t0 = Clock::now();
    for (const sg::Camera& cam : cams) {
        t.view.camera = cam;
        t.viewer.frame();
        const double ms = t.viewer.lastFrame().workMs;  // the frame's work, without the pacing's wait
        const sg::PagerStats& st = t.pager.stats();
        all.push_back(ms);
        (st.queued > 0 || st.loading > 0 || st.pending > 0 ? loading : quiet).push_back(ms);
        points.push_back(double(t.view.cullStats().points));
        maxRss = std::max(maxRss, rssMb());
        maxHeap = std::max(maxHeap, heapMb());
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    const sg::FlatImage& image = t.viewer.scene().image();
    const bool inSite = image.size() > 0 && site.contains(image.box(0).center());
    if (!inSite)
        std::fprintf(stderr, "sgbench tiles: the tileset's centre is outside the factory site: the path misses it\n");

    Json j;
    j.add("command", "tiles").add("tileset", t.file).add("path", "factory-walk");
    j.addInt("frames", long(cams.size())).addInt("width", t.view.camera.width());
    j.addInt("height", t.view.camera.height());
    const sg::PointShading& ps = t.viewer.renderer().pointShading();
    j.add("point_size", ps.pointSize).addInt("round", ps.round).addInt("edl", ps.eyeDome);
    j.addInt("tileset_in_site", inSite).add("open_ms", t.openMs).add("seconds", seconds);
    addFrameTimes(j, "frame", all);
    addFrameTimes(j, "loading", loading);
    addFrameTimes(j, "quiet", quiet);
    j.add("points_drawn_median", median(points)).add("points_drawn_max", percentile(points, 1.0));
    j.add("rss_mb_start", t.rssStartMb).add("rss_mb_max", maxRss).add("heap_mb_max", maxHeap);
    const sg::PagerStats& st = t.pager.stats();
    j.addInt("loads", long(st.loads)).addInt("unloads", long(st.unloads)).addInt("failures", long(st.failures));
    j.addInt("resident_details", long(st.resident)).add("resident_mb", double(st.bytesResident) / (1 << 20));
    j.addInt("tiles_read", long(t.tileset.counts().tiles)).addInt("contents", long(t.tileset.counts().contents));
    const bool same = !a.flag("settle-check") || settleCheck(a, t, cams, j);
    j.print(a);
    return same ? 0 : 1;
}

}  // namespace bench
