// sgbench occlusion: an occlusion method (--method tree, hom, hom-approx, each alone or after a PVS table, or the
// PVS alone) on city's street path, office's walk or the factory's walkthrough (docs/scenes.md). Per frame, in one run
// and alternating: no culling (the scene's total), frustum culling alone, frustum + occlusion; triangles drawn by each,
// cull and pass times, the whole frame drawn headless (1280x720), and with --pixels the pixels that differ from the
// unculled render.
#include "loaders/gltf/Gltf.h"
#include "loaders/tiles/Tileset.h"
#include "nodes/Occluder.h"
#include "nodes/Transform.h"
#include "sg/build/GeneratedOccluders.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/KeepFreedMemory.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/io/ImageIO.h"
#include "sgbench/Bench.h"
#include "testbed/City.h"
#include "testbed/Factory.h"
#include "testbed/FactoryWalk.h"
#include "testbed/Office.h"

#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>

namespace bench {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// The city as tiles written by sgtile, paged in: occluders made from each load as it is read (on the loader threads,
// as TilesetOptions::generateOccluders does; here with their figures summed), or the built city's authored ones placed
// beside the tiles (the yardstick for the triangles drawn: a coarse tile is not surely inside them).
struct TiledCity {
    sg::Tileset ts;
    sg::ref_ptr<sg::Group> root = sg::make<sg::Group>();
    std::optional<sg::OccluderGenSettings> generate;
    std::unique_ptr<sg::Pager> pager;
    std::mutex m;
    sg::OccluderGenStats made;  // the loads', summed
    long loads = 0;
    uint64_t frame = 0;

    explicit TiledCity(const std::string& file) : ts(sg::loadTileset(file)) { root->addChild(ts.root()); }

    size_t addAuthored(int n) {
        size_t k = 0;
        std::function<void(const sg::Node&, const sg::dmat4&)> walk = [&](const sg::Node& nd, const sg::dmat4& w) {
            if (nd.kind() == sg::NodeKind::Occluder) {
                const auto& o = static_cast<const sg::Occluder&>(nd);
                auto c = sg::make<sg::Occluder>();
                if (o.shape() == sg::Occluder::Shape::Box)
                    c->setBox(o.box());
                else
                    c->setPolygon(o.polygon());
                auto t = sg::make<sg::Transform>(w);
                t->addChild(c);
                root->addChild(t);
                ++k;
                return;
            }
            const sg::dmat4 cw =
                nd.kind() == sg::NodeKind::Transform ? static_cast<const sg::Transform&>(nd).apply(w) : w;
            for (size_t c = 0; c < nd.numChildren(); ++c) walk(*nd.child(c), cw);
        };
        walk(*scenes::buildCity({n, true}), sg::dmat4(1.0));
        return k;
    }

    void startPaging(sg::Scene& scene) {
        sg::PagerSettings ps;
        ps.maxResidentBytes = size_t(8) << 30;  // the views' tiles stay: no view waits for an eviction
        pager = std::make_unique<sg::Pager>(
            scene,
            [this, load = ts.loadFunction()](const sg::PageSource& source) {
                sg::ref_ptr<sg::Node> d = load(source);
                sg::OccluderGenStats st;
                if (generate && d) st = sg::generateOccluders(*d, *generate);
                std::lock_guard<std::mutex> lock(m);
                made.geometries += st.geometries, made.meshes += st.meshes, made.meshTriangles += st.meshTriangles;
                made.sceneTriangles += st.sceneTriangles, made.boxes += st.boxes, made.polygons += st.polygons;
                made.lods += st.lods, made.minor += st.minor, made.enclosed += st.enclosed, made.skipped += st.skipped;
                made.ms += st.ms;
                ++loads;
                return d;
            },
            ps);
    }

    // Frames at the view, culled with culling off, until every tile it wants is attached.
    void settle(sg::Scene& scene, const sg::Camera& cam, sg::CullTraversal& cull, const sg::CullSettings& none) {
        sg::DrawList list;
        sg::CullStats st;
        for (int k = 0; k < 1000; ++k) {
            ++frame;
            const sg::FrameInfo fi{frame, double(frame)};
            pager->update(fi);
            scene.update(fi);
            cull.cull(scene, cam, none, list, st);
            const sg::PagerStats& ps = pager->stats();
            if (ps.queued == 0 && ps.loading == 0 && st.pagedRequested == 0 && st.pagedCoarse == 0) return;
            pager->waitIdle();
        }
        throw std::runtime_error("sgbench occlusion: a view of the tileset never settles");
    }
};
}  // namespace

int runOcclusion(const Args& a) {
    const std::string sceneName = a.str("scene", "city");
    const bool city = sceneName == "city", factory = sceneName == "factory";
    if (!city && !factory && sceneName != "office")
        throw std::invalid_argument("sgbench occlusion: --scene must be city, office or factory (got '" + sceneName +
                                    "')");
    const int n = int(a.num(city ? "n" : "r", city ? 100 : 8));
    if (n < 1 || n > 1000)
        throw std::invalid_argument("sgbench occlusion: the scene size " + std::to_string(n) + " is not in 1..1000");
    const std::string path = a.str("path", city ? "street" : "walk");
    if (city ? (path != "street" && path != "orbit") : path != "walk")
        throw std::invalid_argument(
            "sgbench occlusion: --path must be street or orbit for city, walk for office and "
            "the factory (got '" +
            path + "')");
    // --gltf FILE: the city read from a glTF file written by sgview --save (its --n gives the path), in place of the
    // built-in one.
    const std::string gltfFile = a.str("gltf", "");
    if (!gltfFile.empty() && !city)
        throw std::invalid_argument("sgbench occlusion: --gltf is a city saved by sgview --save: use --scene city");
    // --tileset FILE: the city written as tiles by sgtile (its --n gives the path), each view drawn once every tile it
    // wants is loaded (settled with culling off, so that every cull of the view sees the same tiles).
    const std::string tilesetFile = a.str("tileset", "");
    if (!tilesetFile.empty() && (!city || !gltfFile.empty()))
        throw std::invalid_argument("sgbench occlusion: --tileset is a city written by sgtile: use --scene city");
    const bool draw = !a.flag("no-draw");
    const bool pixels = draw && a.flag("pixels");
    const int every = int(a.num("every", 1));  // every k-th frame of the path
    if (every < 1) throw std::invalid_argument("sgbench occlusion: --every must be at least 1");

    sg::CullSettings frustum;
    frustum.occlusion.mode = sg::OcclusionMode::Off;
    sg::CullSettings occl = frustum;
    occl.occlusion.mode = sg::parseOcclusionMode(a.str("occlusion", "every-frame"));
    if (occl.occlusion.mode == sg::OcclusionMode::Off)
        throw std::invalid_argument("sgbench occlusion: --occlusion must be every-frame or adaptive");
    const std::string cap = a.str("cap", "front");
    if (cap != "front" && cap != "centre")
        throw std::invalid_argument("sgbench occlusion: --cap must be front or centre");
    occl.occlusion.measureOnly.cap = cap == "front" ? sg::OccluderCap::FrontFaces : sg::OccluderCap::CenterPlane;
    // --method: tree, hom or hom-approx, each alone or after the PVS ("pvs+tree"), or the PVS alone ("pvs").
    const std::string method = a.str("method", "tree");
    const bool usesPvs = method.rfind("pvs", 0) == 0;
    const std::string occlusionMethod = method == "pvs" ? "tree" : usesPvs ? method.substr(4) : method;
    if ((method != "pvs" && method.rfind("pvs+", 0) != 0 && usesPvs) ||
        (occlusionMethod != "tree" && occlusionMethod != "hom" && occlusionMethod != "hom-approx"))
        throw std::invalid_argument(
            "sgbench occlusion: --method must be tree, hom, hom-approx, pvs, pvs+tree, pvs+hom or pvs+hom-approx (got "
            "'" +
            method + "')");
    const bool hom = occlusionMethod != "tree";
    occl.occlusion.method = sg::OcclusionMethod::Tree;
    if (hom) {
        occl.occlusion.method = sg::OcclusionMethod::Hom;
        // The approximate map: a pyramid pixel three quarters covered counts as covered (--hom-opacity, %).
        occl.occlusion.homOpacity = occlusionMethod == "hom" ? 1.0 : double(a.num("hom-opacity", 75)) / 100.0;
        occl.occlusion.homWidth = occl.occlusion.homHeight = int(a.num("hom-size", 256));
        occl.occlusion.homMaxOccluders = uint32_t(a.num("max-occluders", occl.occlusion.homMaxOccluders));
        occl.occlusion.homObbLevels = int(a.num("obb-levels", 0));
    }
    occl.occlusion.maxOccluders = uint32_t(a.num("max-occluders", occl.occlusion.maxOccluders));
    occl.occlusion.minOccluderPixels = double(a.num("min-pixels", long(occl.occlusion.minOccluderPixels)));
    occl.occlusion.measureOnly.screenSplits = int(a.num("splits", 0));
    sg::CullSettings none = frustum;
    none.strategy = sg::CullStrategy::None;

    // The factory: its walkthrough's path (outside, into a workshop and along its machines, out, round the site,
    // up), 240 frames, each drawn with the Switch state of its eye; no baked lighting (the same for every render).
    scenes::Factory site;
    scenes::WalkPath walk;
    sg::ref_ptr<sg::Node> root;
    std::unique_ptr<TiledCity> tiles;
    if (factory) {
        site = scenes::buildFactory();
        root = site.root;
    } else if (!gltfFile.empty()) {
        // A city saved by sgview --save (+Y up): turned back to +Z up under a Transform, so the path's cameras fit.
        auto up = sg::make<sg::Transform>(glm::rotate(sg::dmat4(1.0), glm::half_pi<double>(), sg::dvec3(1, 0, 0)));
        up->addChild(sg::loadGltf(gltfFile).root);
        root = up;
    } else if (!tilesetFile.empty()) {
        tiles = std::make_unique<TiledCity>(tilesetFile);
        root = tiles->root;
    } else {
        root = city ? scenes::buildCity({n, true}) : scenes::buildOffice(n);
    }
    // --occluders generated: the authored occluders removed and occluders made from the geometry instead
    // (sg/build/GeneratedOccluders.h), the time to make them reported.
    const std::string occluders = a.str("occluders", "authored");
    if (occluders != "authored" && occluders != "generated")
        throw std::invalid_argument("sgbench occlusion: --occluders must be authored or generated (got '" + occluders +
                                    "')");
    sg::OccluderGenStats gen;
    size_t authored = 0;
    sg::OccluderGenSettings gs;
    gs.voxels = uint32_t(a.num("voxels", gs.voxels));
    gs.maxBoxes = uint32_t(a.num("max-boxes", gs.maxBoxes));
    gs.maxPolygons = uint32_t(a.num("max-polygons", gs.maxPolygons));
    gs.minMajorShare = double(a.num("major-percent", long(gs.minMajorShare * 100))) / 100.0;
    if (tiles && occluders == "generated") {
        tiles->generate = gs;  // each tile's, as it is read
        gen = sg::generateOccluders(*root, gs);
    } else if (tiles) {
        authored = tiles->addAuthored(n);
    } else if (occluders == "generated") {
        authored = sg::removeOccluders(*root);
        gen = sg::generateOccluders(*root, gs);
    }
    sg::Scene scene(root);
    scene.update();
    if (tiles) tiles->startPaging(scene);
    if (factory) walk = scenes::buildWalkPath(site, scene, 240);
    std::vector<sg::Camera> cams;
    std::vector<int> workshops;  // the factory's Switch state per camera
    const int frames = factory ? int(walk.frames.size())
                       : city  ? (path == "street" ? scenes::kStreetFrames : scenes::kOrbitFrames)
                               : scenes::kWalkFrames;
    for (int f = 0; f < frames; f += every) {
        if (factory) {
            cams.push_back(scenes::pathCamera(walk.frames[size_t(f)], 1280, 720));
            workshops.push_back(walk.frames[size_t(f)].workshop);
        } else {
            cams.push_back(city ? (path == "street" ? scenes::cityStreetCamera(n, f) : scenes::cityOrbitCamera(n, f))
                                : scenes::officeWalkCamera(n, f));
        }
    }
    int shown = -2;                                     // the workshop the factory's switches show
    sg::CullTraversal cullNone, cullFrustum, cullOccl;  // one per setting: Adaptive keeps state per view
    sg::DrawList list;
    sg::CullStats st;
    auto prepare = [&](size_t view) {
        if (tiles) tiles->settle(scene, cams[view], cullNone, none);
        if (!factory || workshops[view] == shown) return;
        scenes::setFactoryEye(site, shown = workshops[view]);
        scene.update();
    };

    // A PVS table for the path's cells (2 m: in the office larger cells span doorways and hide little), built
    // first (untimed), culls before the frustum, alone or with an occlusion method.
    sg::PvsTable pvs;
    double pvsBuildMs = 0.0, culledPvs = 0.0;
    if (usesPvs) {
        if (factory) throw std::invalid_argument("sgbench occlusion: the PVS methods are for city and office");
        sg::PvsBuilder::Stats ps;
        sg::PvsBuilder::Options po = pvsPathOptions(city, n, cams);
        po.cellSize = sg::dvec3(double(a.num("cell-size", 2)), double(a.num("cell-size", 2)), 2.0);
        po.maxOccluders = uint32_t(a.num("pvs-occluders", 50));
        pvs = sg::PvsBuilder::build(scene, po, &ps);
        pvsBuildMs = ps.ms;
        occl.pvs = &pvs;
        if (method == "pvs") occl.occlusion.mode = sg::OcclusionMode::Off;
    }

    std::unique_ptr<sg::OsmesaContext> ctx;
    std::unique_ptr<sg::Renderer> renderer;
    if (draw) {
        ctx = std::make_unique<sg::OsmesaContext>(1280, 720);
        renderer = std::make_unique<sg::Renderer>();
        if (renderer->softwareRasterizer()) sg::keepFreedMemory();  // as a frame loop does (sg/gl/KeepFreedMemory.h)
    }
    // One frame: cull (+ draw, finished); returns the whole frame's time.
    auto frame = [&](sg::CullTraversal& t, const sg::Camera& cam, const sg::CullSettings& s) {
        const auto t0 = Clock::now();
        t.cull(scene, cam, s, list, st);
        if (draw) {
            renderer->draw(list, cam);
            renderer->finish();
        }
        return msSince(t0);
    };
    if (draw) {  // uploads every mesh before timing
        prepare(0);
        frame(cullNone, cams[0], none);
    }

    // --ideal: the exact visible set, for reference. Each geometry the frustum leaves is drawn in a
    // colour of its own, unlit; the colours in the image name the geometries that show.
    const bool ideal = draw && a.flag("ideal");
    std::vector<sg::ref_ptr<sg::Material>> ids;
    sg::DrawList idList;
    auto visibleTriangles = [&](const sg::Camera& cam) {
        cullFrustum.cull(scene, cam, frustum, idList, st);
        while (ids.size() < idList.items.size()) {
            const uint32_t k = uint32_t(ids.size()) + 1;
            auto m = sg::make<sg::Material>(sg::vec4(float(k & 255) / 255.0f, float((k >> 8) & 255) / 255.0f,
                                                     float((k >> 16) & 255) / 255.0f, 1.0f));
            m->unlit = true;
            ids.push_back(m);
        }
        for (size_t i = 0; i < idList.items.size(); ++i) idList.items[i].material = ids[i].get();
        idList.order.clear();
        renderer->draw(idList, cam, sg::vec4(0, 0, 0, 1));
        const sg::Image img = renderer->readColor();
        std::vector<char> seen(idList.items.size() + 1, 0);
        for (size_t p = 0; p + 3 < img.rgba.size(); p += 4) {
            const uint32_t k = img.rgba[p] | (img.rgba[p + 1] << 8) | (img.rgba[p + 2] << 16);
            if (k && k <= idList.items.size()) seen[k] = 1;
        }
        double tris = 0;
        for (size_t i = 0; i < idList.items.size(); ++i)
            if (seen[i + 1]) tris += double(idList.items[i].mesh->triangleCount());
        return tris;
    };
    double trisIdeal = 0;

    std::vector<double> cullF, cullO, passO, frameF, frameO, speedup;
    double candidates = 0, total = 0, trisF = 0, trisO = 0, used = 0, nodes = 0, psplits = 0, bsplits = 0, culled = 0,
           tests = 0, ran = 0, differing = 0, viewsWithError = 0, culledObb = 0;
    for (size_t view = 0; view < cams.size(); ++view) {
        const sg::Camera& cam = cams[view];
        prepare(view);
        cullNone.cull(scene, cam, none, list, st);
        total += double(st.triangles);
        const double fF = frame(cullFrustum, cam, frustum);
        cullF.push_back(st.ms);
        trisF += double(st.triangles);
        const double fO = frame(cullOccl, cam, occl);
        cullO.push_back(st.ms);
        passO.push_back(st.occlusionMs);
        trisO += double(st.triangles);
        used += double(st.occludersUsed);
        candidates += double(st.occluderCandidates);
        nodes += double(st.occlusionTreeNodes);
        psplits += double(st.occlusionPolygonSplits);
        bsplits += double(st.occlusionBoxSplits);
        culled += double(st.culledOcclusion);
        culledObb += double(st.culledObb);
        tests += double(st.occlusionTests);
        ran += st.occlusionRan;
        culledPvs += double(st.culledPvs);
        if (pixels) {
            const sg::Image got = renderer->readColor();
            cullNone.cull(scene, cam, none, list, st);
            renderer->draw(list, cam);
            const size_t d = sg::countDifferingPixels(renderer->readColor(), got);
            differing += double(d);
            viewsWithError += d > 0;
        }
        if (ideal) trisIdeal += visibleTriangles(cam);
        frameF.push_back(fF);
        frameO.push_back(fO);
        speedup.push_back(fF / fO);
    }
    const double k = double(cams.size());
    if (tiles) {  // the loads' occluders with the root tile's
        std::lock_guard<std::mutex> lock(tiles->m);
        const sg::OccluderGenStats& l = tiles->made;
        gen.geometries += l.geometries, gen.meshes += l.meshes, gen.meshTriangles += l.meshTriangles;
        gen.sceneTriangles += l.sceneTriangles, gen.boxes += l.boxes, gen.polygons += l.polygons, gen.ms += l.ms;
    }
    Json j;
    j.add("command", "occlusion").add("scene", sceneName).add("path", path);
    if (!gltfFile.empty()) j.add("gltf", gltfFile);
    if (tiles) j.add("tileset", tilesetFile).addInt("tiles_loaded", long(tiles->loads));
    if (!factory) j.addInt(city ? "n" : "r", n);
    j.add("occluders", occluders);
    if (occluders == "generated")
        j.addInt("authored_removed", long(authored))
            .add("generate_ms", gen.ms)
            .addInt("generated_boxes", long(gen.boxes))
            .addInt("generated_polygons", long(gen.polygons))
            .addInt("generated_polygons_enclosed", long(gen.enclosed))
            .addInt("generated_lods", long(gen.lods))
            .addInt("meshes_analysed", long(gen.meshes))
            .addInt("mesh_triangles", long(gen.meshTriangles))
            .addInt("scene_triangles", long(gen.sceneTriangles))
            .add("ms_per_million_mesh_triangles", gen.ms * 1e6 / std::max(1.0, double(gen.meshTriangles)))
            .add("ms_per_million_scene_triangles", gen.ms * 1e6 / std::max(1.0, double(gen.sceneTriangles)));
    j.add("occlusion", sg::occlusionModeName(occl.occlusion.mode)).add("cap", cap).addInt("frames", long(cams.size()));
    j.add("method", method);
    if (hom)
        j.add("hom_opacity", occl.occlusion.homOpacity)
            .addInt("hom_size", occl.occlusion.homWidth)
            .addInt("obb_levels", occl.occlusion.homObbLevels)
            .add("culled_obb_mean", culledObb / double(cams.size()));
    if (usesPvs) j.add("pvs_build_ms", pvsBuildMs).add("culled_pvs_mean", culledPvs / double(cams.size()));
    if (pixels) j.add("differing_pixels_total", differing).add("views_with_error", viewsWithError);
    j.addInt("max_occluders", long(hom ? occl.occlusion.homMaxOccluders : occl.occlusion.maxOccluders))
        .addInt("splits", occl.occlusion.measureOnly.screenSplits);
    j.add("triangles_total", total / k)
        .add("triangles_frustum_mean", trisF / k)
        .add("triangles_occlusion_mean", trisO / k);
    j.add("frustum_percent", 100.0 * trisF / total).add("occlusion_percent", 100.0 * trisO / total);
    j.add("occlusion_over_frustum", trisO / trisF);
    if (ideal) j.add("triangles_visible_mean", trisIdeal / k).add("visible_percent", 100.0 * trisIdeal / total);
    j.add("occlusion_ms_median", median(passO)).add("occlusion_ms_p95", percentile(passO, 0.95));
    j.add("cull_ms_median_frustum", median(cullF)).add("cull_ms_median_occlusion", median(cullO));
    if (draw) {
        j.add("frame_ms_median_frustum", median(frameF)).add("frame_ms_median_occlusion", median(frameO));
        j.add("frame_speedup_median", median(speedup));
    }
    j.add("pass_ran_share", ran / k)
        .add("occluder_candidates_mean", candidates / k)
        .add("occluders_used_mean", used / k)
        .add("tree_nodes_mean", nodes / k);
    j.add("polygon_splits_mean", psplits / k).add("box_splits_mean", bsplits / k);
    j.add("occlusion_tests_mean", tests / k).add("culled_occlusion_mean", culled / k);
    j.print(a);
    return 0;
}

}  // namespace bench
