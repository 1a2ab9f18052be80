// sgbench tiles: a 3D Tiles tileset (the city written by sgtile) flown through sg::Viewer with its pager, from
// disk or HTTP: frame times while loads are in flight, the process's resident memory, the pager's figures. With
// --baseline the same city held in memory is flown by a second viewer in the same process, frame for frame
// (interleaved): the ratio of their frame times, and the pixels where the tiles' frame differs from it (0 once
// settled: nothing queued, loading or waiting, and nothing asked for). One line per frame to --csv for the plot.
// --path factory-walk flies a point tileset of the factory's scan instead (TilesWalk.cpp); --point-size, --round
// and --edl shade the points on every path.
#include "loaders/net/HttpCache.h"
#include "loaders/tiles/Tileset.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/io/ImageIO.h"
#include "sg/viewer/Viewer.h"
#include "sgbench/Bench.h"
#include "sgbench/Tiles.h"
#include "testbed/City.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>

namespace bench {

namespace {

using Clock = std::chrono::steady_clock;

// The city's orbit (docs/scenes.md) at angle `a`, or a low flight along the middle street, 30 m up, looking
// ahead and swaying: `t` in [0, 1] along it.
sg::Camera flightCamera(const std::string& path, int n, double t, int w, int h) {
    sg::Camera cam;
    cam.setViewport(w, h);
    cam.setPerspective(60.0, double(w) / h, 1.0, 3000.0);
    const double c = 10.0 * n;
    if (path == "orbit") {
        const double a = 2.0 * M_PI * t;
        const sg::dvec3 eye(c + 5.0 * n * std::cos(a), c + 5.0 * n * std::sin(a), 40.0);
        cam.setLookAt(eye, eye + glm::normalize(sg::dvec3(-std::sin(a), std::cos(a), -0.15)), sg::dvec3(0, 0, 1));
    } else {
        const double yaw = 0.5 * std::sin(2.0 * M_PI * t * 8.0);
        const sg::dvec3 eye(20.0 * (n / 2), 20.0 * n * t, 30.0);
        cam.setLookAt(eye, eye + sg::dvec3(std::sin(yaw), std::cos(yaw), -0.1), sg::dvec3(0, 0, 1));
    }
    return cam;
}

// Jumps between views spread over the city, 60 m up, each held until settled: the time from a teleport to a
// settled frame, and tiles loaded a second over the whole run (the loads' throughput with --loaders K).
// What the reads did over http(s): requests, cache hits, connections, HTTP/2, bytes as sent and as read.
void addCounters(Json& j, const sg::ResourceCounters* c) {
    if (!c) return;
    j.addInt("requests", long(c->requests)).addInt("cache_hits", long(c->cacheHits));
    j.addInt("revalidated", long(c->revalidated)).addInt("connections", long(c->connections));
    j.addInt("http2_responses", long(c->http2)).add("mb_on_wire", double(c->bytesOnWire) / (1 << 20));
    j.add("mb_read", double(c->bytes) / (1 << 20));
}

int teleport(const Args& a, const std::string& file, int n, int w, int h, sg::Viewer& viewer, sg::View& view,
             sg::Pager& pager, const sg::Tileset& ts, const sg::ResourceCounters* counters) {
    const int views = int(a.num("views", 6));
    std::vector<double> settleMs;
    long frames = 0;
    const auto t0 = Clock::now();
    for (int k = 0; k < views; ++k) {
        const double fx = 0.15 + 0.7 * std::fmod(0.618034 * (k + 1), 1.0),
                     fy = 0.15 + 0.7 * std::fmod(0.381966 * (k + 1), 1.0);
        const sg::dvec3 eye(20.0 * n * fx, 20.0 * n * fy, 60.0);
        const double yaw = 1.1 * k;
        view.camera.setViewport(w, h);
        view.camera.setPerspective(60.0, double(w) / h, 1.0, 3000.0);
        view.camera.setLookAt(eye, eye + sg::dvec3(std::sin(yaw), std::cos(yaw), -0.3), sg::dvec3(0, 0, 1));
        const auto s = Clock::now();
        frames += settleTiles(viewer, view, pager, 20000);
        settleMs.push_back(std::chrono::duration<double, std::milli>(Clock::now() - s).count());
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    const sg::PagerStats& st = pager.stats();
    Json j;
    j.add("command", "tiles").add("tileset", file).add("path", "teleport").addInt("n", n).addInt("views", views);
    j.addInt("loaders", long(pager.settings().loaderThreads)).addInt("frames", frames).add("seconds", seconds);
    j.add("settle_ms_median", median(settleMs)).add("settle_ms_max", percentile(settleMs, 1.0));
    j.addInt("loads", long(st.loads)).add("loads_per_s", double(st.loads) / seconds);
    j.add("load_ms_total", st.totalLoadMs).addInt("failures", long(st.failures));
    j.addInt("meshes_shared", long(ts.counts().sharedMeshes)).add("rss_mb", rssMb());
    addCounters(j, counters);
    j.print(a);
    return 0;
}

}  // namespace

int settleTiles(sg::Viewer& viewer, sg::View& view, sg::Pager& pager, int most) {
    for (int f = 1; f <= most; ++f) {
        viewer.frame();
        const sg::PagerStats& st = pager.stats();
        if (st.queued == 0 && st.loading == 0 && st.pending == 0 && view.cullStats().pagedRequested == 0 &&
            view.cullStats().pagedCoarse == 0)
            return f;
    }
    return most;
}

int runTiles(const Args& a) {
    const std::string file = a.str("tileset", "");
    if (file.empty()) throw std::invalid_argument("sgbench tiles: --tileset PATH/tileset.json (written by sgtile)");
    const int n = int(a.num("n", 1000)), frames = int(a.num("frames", 2400));
    const int w = int(a.num("width", 1280)), h = int(a.num("height", 720));
    const std::string path = a.str("path", "orbit");
    if (path != "orbit" && path != "low" && path != "teleport" && path != "factory-walk" && path != "loads")
        throw std::invalid_argument("sgbench tiles: --path orbit|low|teleport|factory-walk|loads");
    if (n < 1 || frames < 1) throw std::invalid_argument("sgbench tiles: --n and --frames must be at least 1");
    const bool reference = a.flag("baseline");
    const bool walk = path == "factory-walk";
    if (walk && reference)
        throw std::invalid_argument("sgbench tiles: --baseline is the city's; factory-walk has none");
    sg::TilesetOptions to;
    to.shareMeshes = a.num("share-meshes", 1) != 0;
    // Over http(s): a request header (a token), the authorities to trust, a disk cache file.
    if (a.flag("header")) to.resource.headers = {a.str("header", "")};
    to.resource.caFile = a.str("ca-file", "");
    if (a.flag("cache")) to.resource.cache = std::make_shared<sg::HttpCache>(a.str("cache", ""));
    sg::ResourceCounters counters;
    to.resource.counters = &counters;
    if (path == "loads") return measureTileLoads(a, file, to);
    sg::Box site;
    const std::vector<sg::Camera> walkCams = walk ? factoryWalkCameras(frames, w, h, site) : std::vector<sg::Camera>{};

    sg::OsmesaContext context(w, h);
    const double rss0 = rssMb();
    auto t0 = Clock::now();
    sg::Tileset ts = sg::loadTileset(file, to);
    const double openMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    sg::Scene scene(ts.root());
    // Frames paced as a display would pace them (--fps, FramePhase::Limit): the loads have the time a real flight
    // gives them. A frame's time below is its work, without the wait.
    sg::ViewerSettings vs;
    vs.phase = sg::FramePhase::Limit;
    vs.frameRate = double(a.num("fps", 30));
    vs.keepFreedMemory = a.num("keep-freed-memory", 1) != 0;
    sg::Viewer viewer(scene, vs);
    sg::View& view = viewer.addView();
    if (a.flag("prefetch")) view.prefetchSeconds = std::stod(a.str("prefetch", "0"));  // look-ahead, s (0: off)
    sg::PagerSettings ps;
    ps.loaderThreads = size_t(a.num("loaders", long(ps.loaderThreads)));
    ps.loaderNice = int(a.num("loader-nice", ps.loaderNice));
    ps.freeOnLoaderThread = true;  // a tileset's details share no node with the rest of the graph
    // The pager's byte budget of attached details (their meshes; the renderer's copies come on top of it).
    if (a.flag("resident-mb")) ps.maxResidentBytes = size_t(a.num("resident-mb", 512)) << 20;
    sg::Pager& pager = viewer.enablePaging(ts.loadFunction(), ps);
    viewer.renderer().setPointShading(pointShadingFromArgs(a));

    // The baseline: the city held in memory, flown by a viewer of its own in the same context.
    std::unique_ptr<sg::Scene> refScene;
    std::unique_ptr<sg::Viewer> refViewer;
    if (reference) {
        refScene = std::make_unique<sg::Scene>(scenes::buildCity({n, false}));
        refViewer = std::make_unique<sg::Viewer>(*refScene);
        refViewer->addView();
        refViewer->renderer().setPointShading(viewer.renderer().pointShading());
    }

    if (path == "teleport") return teleport(a, file, n, w, h, viewer, view, pager, ts, &counters);
    if (walk) return flyFactoryWalk(a, TilesFlight{file, to, ts, viewer, view, pager, openMs, rss0}, walkCams, site);

    std::ofstream csv;
    if (a.flag("csv")) csv.open(a.str("csv", ""));
    if (csv)
        csv << "frame,ms,loading,queued,pending,loads,resident_mb,rss_mb,differing_pixels,settled,pager_ms,prepare_ms,"
               "update_ms,cull_ms,draw_ms,uploaded_objects\n";
    std::vector<double> all, loading, base;
    std::vector<sg::StageTimes> stages;
    double maxRss = 0.0;
    long settled = 0, settledDiffering = 0, loadingFrames = 0, loadingDiffering = 0;
    double loadingPixels = 0.0;
    long prefetchRequests = 0, enrouteDiffering = 0;
    double enroutePixels = 0.0;
    bool reachedSettled = false;
    const MemoryParts openParts = memoryParts();  // the tileset open, no tile loaded
    MemoryParts peakParts;
    double peakResidentMb = 0.0;
    t0 = Clock::now();
    for (int f = 0; f < frames; ++f) {
        view.camera = flightCamera(path, n, double(f) / frames, w, h);
        viewer.frame();
        const double ms = viewer.lastFrame().workMs;
        stages.push_back(viewer.lastFrame());
        prefetchRequests += long(view.prefetchStats().pagedRequested);
        const sg::PagerStats& st = pager.stats();
        const bool busy = st.queued > 0 || st.loading > 0 || st.pending > 0;
        const bool done = !busy && view.cullStats().pagedRequested == 0 && view.cullStats().pagedCoarse == 0;
        all.push_back(ms);
        if (busy) loading.push_back(ms);
        const double rss = rssMb();
        if (rss > maxRss + 8.0 || (f == 0 && rss > maxRss)) {  // a new peak: what holds it (reading smaps costs ~1 ms)
            peakParts = memoryParts();
            peakResidentMb = double(st.bytesResident) / (1 << 20);
        }
        maxRss = std::max(maxRss, rss);
        long differing = -1;
        if (reference) {
            const sg::Image got = viewer.renderer().readColor();
            refViewer->view().camera = view.camera;
            refViewer->frame();
            base.push_back(refViewer->lastFrame().workMs);
            differing = long(sg::countDifferingPixels(got, refViewer->renderer().readColor()));
            if (done) reachedSettled = true;
            if (reachedSettled) {  // en route: after the first view settled (the start's load aside)
                enrouteDiffering += differing > 0;
                enroutePixels += double(differing);
            }
            if (done) {
                ++settled;
                settledDiffering += differing > 0;
            } else {
                ++loadingFrames;
                loadingDiffering += differing > 0;
                loadingPixels += double(differing);
            }
        }
        if (csv)
            csv << f << "," << ms << "," << st.loading << "," << st.queued << "," << st.pending << "," << st.loads
                << "," << double(st.bytesResident) / (1 << 20) << "," << rssMb() << "," << differing << "," << done
                << "," << stages.back().pagerMs << "," << st.frame.prepareMs << "," << stages.back().updateMs << ","
                << stages.back().cullMs << "," << stages.back().drawMs << "," << st.frame.uploadedObjects << "\n";
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();

    Json j;
    j.add("command", "tiles").add("tileset", file).add("path", path).addInt("n", n).addInt("frames", frames);
    j.add("open_ms", openMs).add("seconds", seconds).add("prefetch_s", view.prefetchSeconds);
    j.addInt("prefetch_requests", prefetchRequests);
    j.add("frame_ms_median", median(all))
        .add("frame_ms_p99", percentile(all, 0.99))
        .add("frame_ms_max", percentile(all, 1.0));
    j.addInt("frames_loading", long(loading.size()));
    // Where the slow frames' time went: over the frames past 1.5x the median, each stage's mean excess over its
    // own median (the stage that makes the hitches).
    const double slow = 1.5 * median(all);
    auto excess = [&](double sg::StageTimes::*stage) {
        std::vector<double> v;
        for (const sg::StageTimes& t : stages) v.push_back(t.*stage);
        const double m = median(v);
        double sum = 0.0;
        long count = 0;
        for (const sg::StageTimes& t : stages)
            if (t.workMs > slow) sum += t.*stage - m, ++count;
        return count ? sum / double(count) : 0.0;
    };
    long slowFrames = 0;
    for (double ms : all) slowFrames += ms > slow;
    j.addInt("slow_frames", slowFrames);
    j.add("slow_excess_ms_pager", excess(&sg::StageTimes::pagerMs))
        .add("slow_excess_ms_update", excess(&sg::StageTimes::updateMs))
        .add("slow_excess_ms_cull", excess(&sg::StageTimes::cullMs))
        .add("slow_excess_ms_draw", excess(&sg::StageTimes::drawMs));
    j.add("loading_ms_median", median(loading)).add("loading_ms_p99", percentile(loading, 0.99));
    j.add("rss_mb_start", rss0).add("rss_mb_max", maxRss);
    addMemoryParts(j, "mem_open", openParts);
    addMemoryParts(j, "mem_peak", peakParts);
    j.add("mem_peak_tiles_resident_mb", peakResidentMb);
    addMemoryParts(j, "mem_end", memoryParts());
    const sg::PagerStats& st = pager.stats();
    j.addInt("loads", long(st.loads)).addInt("unloads", long(st.unloads)).addInt("failures", long(st.failures));
    j.addInt("cancelled", long(st.cancelled)).add("loads_per_s", double(st.loads) / seconds);
    j.addInt("tiles_read", long(ts.counts().tiles)).addInt("contents", long(ts.counts().contents));
    j.addInt("meshes_shared", long(ts.counts().sharedMeshes)).addInt("meshes_pooled", long(ts.counts().pooledMeshes));
    addCounters(j, &counters);
    if (reference) {
        j.add("baseline_ms_median", median(base)).add("ratio_median", median(all) / median(base));
        j.add("baseline_ms_p99", percentile(base, 0.99)).add("baseline_ms_max", percentile(base, 1.0));
        j.addInt("settled_frames", settled).addInt("settled_frames_differing", settledDiffering);
        j.addInt("loading_frames", loadingFrames).addInt("loading_frames_differing", loadingDiffering);
        j.add("loading_differing_pixels_mean", loadingFrames ? loadingPixels / double(loadingFrames) : 0.0);
        j.addInt("enroute_frames_differing", enrouteDiffering).add("enroute_differing_pixels", enroutePixels);
    }
    j.print(a);
    return reference && settledDiffering > 0 ? 1 : 0;
}

}  // namespace bench
