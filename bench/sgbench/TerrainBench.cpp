// sgbench terrain: the terrain culling paper's two tables (Xu and Li, hierarchical sphere culling) on the
// `terrain` scene, and each of its refinements measured on its own (docs/benchmarks.md, "Terrain").
#include "nodes/Geometry.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/KeepFreedMemory.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sgbench/Bench.h"
#include "testbed/Terrain.h"

#include <chrono>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace bench {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }
// This thread's CPU time: the refinements' culls are short, and on a shared machine wall time mostly measures
// the other processes.
double cpuMs() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

std::vector<int> intList(const std::string& s, const char* opt) {
    std::vector<int> v;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ',')) {
        char* end = nullptr;
        const long x = std::strtol(item.c_str(), &end, 10);
        if (item.empty() || !end || *end)
            throw std::invalid_argument(std::string("sgbench terrain: --") + opt +
                                        " needs numbers separated by commas, got '" + s + "'");
        v.push_back(int(x));
    }
    return v;
}

// The paper's table 1 and 2 rows: nodes and triangles before and after, frames per second before and after.
struct PaperRow {
    int size, fov, nodesBefore, trisBefore, nodesAfter, trisAfter, fpsBefore, fpsAfter;
};
constexpr PaperRow kPaper[] = {
    {1025, 60, 4576, 34331, 2814, 21176, 37, 51},   {1025, 90, 4576, 34331, 3256, 24490, 37, 46},
    {1025, 120, 4576, 34331, 3543, 26657, 37, 46},  {2049, 60, 10510, 78915, 5522, 40781, 18, 33},
    {2049, 90, 10510, 78915, 6435, 48352, 18, 26},  {2049, 120, 10510, 78915, 7549, 56700, 18, 25},
    {4097, 60, 14970, 141789, 8210, 63640, 1, 17},  {4097, 90, 14970, 141789, 9300, 75234, 1, 14},
    {4097, 120, 14970, 141789, 9708, 77490, 1, 11},
};
const PaperRow* paperRow(int size, int fov) {
    for (const PaperRow& r : kPaper)
        if (r.size == size && r.fov == fov) return &r;
    return nullptr;
}
std::string paperNum(const PaperRow* r, int PaperRow::*f) { return r ? std::to_string(r->*f) : "-"; }

// What a cull selected, in the terrain's terms.
struct Counts {
    uint64_t quadNodes = 0;  // quadtree nodes (Groups and tiles) with something drawn below them
    uint64_t tiles = 0;      // tiles drawn (one geometry each: the level their LOD chose)
    uint64_t triangles = 0;
};

class QuadCounter {
public:
    explicit QuadCounter(const sg::Terrain& t) : t_(t), stamp_(t.quad.size(), 0) {
        for (size_t q = 0; q < t.quad.size(); ++q) {
            if (!t.quad[q].tile) continue;
            const sg::Group& lod = *t.quad[q].node;
            for (size_t c = 0; c < lod.numChildren(); ++c)
                tileOf_[static_cast<const sg::Geometry&>(*lod.child(c)).mesh()] = int(q);
        }
    }
    Counts count(const sg::DrawList& list, const sg::CullStats& st) {
        ++now_;
        Counts c;
        c.tiles = st.geometries;
        c.triangles = st.triangles;
        for (const sg::DrawItem& it : list.items) {
            auto f = tileOf_.find(it.mesh);
            for (int q = f == tileOf_.end() ? -1 : f->second; q >= 0 && stamp_[size_t(q)] != now_;
                 q = t_.quad[size_t(q)].parent) {
                stamp_[size_t(q)] = now_;
                ++c.quadNodes;
            }
        }
        return c;
    }

private:
    const sg::Terrain& t_;
    std::unordered_map<const sg::Mesh*, int> tileOf_;
    std::vector<uint32_t> stamp_;
    uint32_t now_ = 0;
};

struct Refinement {
    const char* name;
    sg::CullSettings set;
};

// The paper's starting point (every bound's box against all six planes, each bound on its own) and each
// refinement added to it alone, then the default (plane masking and the eye-inside shortcut, boxes).
std::vector<Refinement> refinements() {
    sg::CullSettings plain;
    plain.strategy = sg::CullStrategy::Aabb;
    plain.measureOnly.planeMasking = false;
    plain.measureOnly.eyeInsideSkip = false;
    plain.occlusion.mode = sg::OcclusionMode::Off;
    std::vector<Refinement> r;
    r.push_back({"plain (boxes, 6 planes)", plain});
    r.push_back({"+ screen radius < 1 px", plain});
    r.back().set.smallFeaturePixels = 1.0;
    r.push_back({"+ eye-inside shortcut", plain});
    r.back().set.measureOnly.eyeInsideSkip = true;
    r.push_back({"+ inside subtrees untested", plain});
    r.back().set.measureOnly.planeMasking = true;
    r.push_back({"+ fewer planes (l, r, far)", plain});
    r.back().set.measureOnly.frustumPlanes = sg::kTerrainPaperPlanes;
    r.push_back({"spheres for boxes", plain});
    r.back().set.strategy = sg::CullStrategy::Sphere;
    r.push_back({"+ frustum sphere pre-test", plain});
    r.back().set.strategy = sg::CullStrategy::SphereSphere;
    r.push_back({"default (boxes, masks, eye)", sg::CullSettings{}});
    // The walk and its tests, not the draw list's sort (the same for the same selection, and most of a cull
    // of thousands of tiles).
    for (Refinement& x : r) x.set.sort = false;
    return r;
}

// The views of one path: the paper's eye turned round the centre (as sgbench pareto's terrain), or low: the eye
// `height` metres above the ground beneath it on a circle of 0.3 times the terrain's width, looking along the circle
// and slightly down.
std::vector<sg::Camera> terrainPath(const scenes::TerrainScene& ts, bool low, int views, int w, int h, double height) {
    std::vector<sg::Camera> out;
    const int n = ts.samplesPerSide;
    const double width = double(n - 1) * ts.spacing;
    for (int v = 0; v < views; ++v) {
        const double a = 2.0 * glm::pi<double>() * v / views;
        sg::Camera cam = scenes::terrainCamera(ts, 60.0, w, h);
        if (!low) {
            cam.setView(cam.view() * glm::rotate(sg::dmat4(1.0), a, sg::dvec3(0, 0, 1)));
        } else {
            const double r = 0.3 * width, x = r * std::cos(a), y = r * std::sin(a);
            const int i = std::clamp(int(std::lround((x - ts.origin.x) / ts.spacing)), 0, n - 1);
            const int j = std::clamp(int(std::lround((y - ts.origin.y) / ts.spacing)), 0, n - 1);
            const sg::dvec3 eye(x, y, double(ts.heights[size_t(j) * size_t(n) + size_t(i)]) + height);
            cam.setPerspective(60.0, double(w) / h, 1.0, 1.0e6);
            cam.setLookAt(eye, eye + sg::dvec3(-std::sin(a), std::cos(a), -0.05), sg::dvec3(0, 0, 1));
        }
        out.push_back(cam);
    }
    return out;
}

// sgbench terrain --occluders: triangles drawn on each path with and without the terrain's occluders
// (TerrainParams::occluders), and what the occlusion pass cost.
int runTerrainOccluders(const Args& a) {
    const int n = int(a.num("sizes", 1025));
    const int views = int(a.num("views", 24));
    const int reps = int(a.num("reps", 5));
    const int blocks = int(a.num("blocks", 2));
    const double height = double(a.num("height", 20));
    const uint32_t seed = uint32_t(a.num("seed", 2002));
    if (views < 1 || reps < 1) throw std::invalid_argument("sgbench terrain: --views and --reps must be at least 1");
    constexpr int kW = 1024, kH = 768;
    scenes::TerrainSceneParams prm;
    prm.terrain.tileSamples = int(a.num("tile", 33));
    prm.spacing = double(a.num("spacing", 10));
    const scenes::TerrainScene plain = scenes::buildTerrainScene(n, seed, prm);
    prm.terrain.occluders = true;
    prm.terrain.occluderBlocks = blocks;
    const auto t0 = Clock::now();
    const scenes::TerrainScene withOcc = scenes::buildTerrainScene(n, seed, prm);
    const double buildS = msSince(t0) / 1000.0;
    sg::Scene sPlain(plain.terrain.root), sOcc(withOcc.terrain.root);
    sPlain.update();
    sOcc.update();
    std::printf(
        "terrain %d^2, tiles of %d^2 samples, %d x %d occluder blocks per tile: built with them in %.2f s; "
        "the low path's eye %.0f m above the ground, 0.3 of the width from the centre\n",
        n, prm.terrain.tileSamples, blocks, blocks, buildS, height);
    std::printf(
        "| path | views | tris (no culling) | tris (frustum, no occluders) | tris (with occluders) | views "
        "using them | occluders used | bounds culled by occlusion | pass ms (median view) | cull ms without "
        "| cull ms with |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (bool low : {false, true}) {
        const std::vector<sg::Camera> cams = terrainPath(withOcc, low, views, kW, kH, height);
        sg::CullSettings none, set;
        none.strategy = sg::CullStrategy::None;
        set.occlusion.mode = sg::OcclusionMode::EveryFrame;
        set.sort = false;
        sg::CullTraversal cull;
        sg::DrawList list;
        uint64_t trisNone = 0, trisPlain = 0, trisOcc = 0, used = 0, culled = 0;
        int using_ = 0;
        std::vector<double> passMs, msPlain, msOcc;
        for (const sg::Camera& cam : cams) {
            sg::CullStats st;
            cull.cull(sPlain, cam, none, list, st);
            trisNone += st.triangles;
            cull.cull(sPlain, cam, set, list, st);
            trisPlain += st.triangles;
            cull.cull(sOcc, cam, set, list, st);
            trisOcc += st.triangles;
            used += st.occludersUsed;
            using_ += st.occludersUsed > 0;
            culled += st.culledOcclusion;
            std::vector<double> p, mp, mo;
            for (int r = 0; r < reps; ++r) {
                double c0 = cpuMs();
                cull.cull(sPlain, cam, set, list, st);
                mp.push_back(cpuMs() - c0);
                c0 = cpuMs();
                cull.cull(sOcc, cam, set, list, st);
                mo.push_back(cpuMs() - c0);
                p.push_back(st.occlusionMs);
            }
            passMs.push_back(median(p));
            msPlain.push_back(median(mp));
            msOcc.push_back(median(mo));
        }
        double sumPlain = 0.0, sumOcc = 0.0;
        for (size_t k = 0; k < cams.size(); ++k) sumPlain += msPlain[k], sumOcc += msOcc[k];
        std::printf("| %s | %d | %llu | %llu | %llu | %d | %llu | %llu | %.3f | %.3f | %.3f |\n",
                    low ? "low" : "paper's eye turned round", views, (unsigned long long)trisNone,
                    (unsigned long long)trisPlain, (unsigned long long)trisOcc, using_, (unsigned long long)used,
                    (unsigned long long)culled, median(passMs), sumPlain / double(views), sumOcc / double(views));
    }
    return 0;
}

}  // namespace

int runTerrain(const Args& a) {
    if (a.flag("occluders")) return runTerrainOccluders(a);
    const std::vector<int> sizes = intList(a.str("sizes", "1025,2049,4097"), "sizes");
    const std::vector<int> fovs = intList(a.str("fov", "60,90,120"), "fov");
    const int frames = int(a.num("frames", 5));
    const int reps = int(a.num("reps", 100));
    const uint32_t seed = uint32_t(a.num("seed", 2002));
    const int tile = int(a.num("tile", 33));
    const long spacing = a.num("spacing", 10);
    const bool draw = !a.flag("no-draw");
    const bool json = a.flag("json");
    if (frames < 1 || reps < 1 || spacing < 1)
        throw std::invalid_argument("sgbench terrain: --frames, --reps and --spacing must be at least 1");
    for (int f : fovs)
        if (f <= 0 || f >= 180)
            throw std::invalid_argument("sgbench terrain: --fov " + std::to_string(f) + " is not in 1..179");

    constexpr int kW = 1024, kH = 768;
    std::unique_ptr<sg::OsmesaContext> ctx;
    std::unique_ptr<sg::Renderer> renderer;
    if (draw) {
        ctx = std::make_unique<sg::OsmesaContext>(kW, kH);
        renderer = std::make_unique<sg::Renderer>();
        if (renderer->softwareRasterizer()) sg::keepFreedMemory();  // as a frame loop does (sg/gl/KeepFreedMemory.h)
    }
    std::ostringstream t1, t2, t3;
    t1 << "| size | fov | nodes before | tris before | nodes after | tris after | paper nodes before | paper tris "
          "before "
          "| paper nodes after | paper tris after |\n|---|---|---|---|---|---|---|---|---|---|\n";
    t2 << "| size | fov | fps before | fps after | ratio | paper fps before | paper fps after |\n"
          "|---|---|---|---|---|---|---|\n";
    t3 << "| size | fov | method | cull ms | ratio | bounds tested | tiles drawn | tris drawn |\n"
          "|---|---|---|---|---|---|---|---|\n";
    char buf[512];
    for (int n : sizes) {
        const auto t0 = Clock::now();
        scenes::TerrainSceneParams prm;
        prm.terrain.tileSamples = tile;
        prm.spacing = double(spacing);
        scenes::TerrainScene ts = scenes::buildTerrainScene(n, seed, prm);
        const double buildS = msSince(t0) / 1000.0;
        sg::Scene scene(ts.terrain.root);
        scene.update();
        QuadCounter qc(ts.terrain);
        if (!json)
            std::printf(
                "terrain %d^2: %zu quadtree nodes (%d^2 tiles of %d^2 samples), built in %.2f s, %.0f MB resident\n", n,
                ts.terrain.quad.size(), ts.terrain.tilesPerSide, tile, buildS, rssMb());
        for (int fov : fovs) {
            const sg::Camera cam = scenes::terrainCamera(ts, fov, kW, kH);
            sg::CullSettings none;
            none.strategy = sg::CullStrategy::None;
            const sg::CullSettings after;
            sg::CullTraversal cull;
            sg::DrawList list;
            sg::CullStats st;
            cull.cull(scene, cam, none, list, st);
            const Counts cb = qc.count(list, st);
            cull.cull(scene, cam, after, list, st);
            const Counts ca = qc.count(list, st);
            const PaperRow* pr = paperRow(n, fov);
            std::snprintf(buf, sizeof buf, "| %d | %d | %llu | %llu | %llu | %llu | %s | %s | %s | %s |\n", n, fov,
                          (unsigned long long)cb.quadNodes, (unsigned long long)cb.triangles,
                          (unsigned long long)ca.quadNodes, (unsigned long long)ca.triangles,
                          paperNum(pr, &PaperRow::nodesBefore).c_str(), paperNum(pr, &PaperRow::trisBefore).c_str(),
                          paperNum(pr, &PaperRow::nodesAfter).c_str(), paperNum(pr, &PaperRow::trisAfter).c_str());
            t1 << buf;
            Json j1;
            j1.add("command", "terrain").add("table", "nodes").addInt("size", n).addInt("fov", fov);
            j1.addInt("quad_nodes", long(ts.terrain.quad.size()))
                .addInt("tiles", long(ts.terrain.tilesPerSide) * ts.terrain.tilesPerSide);
            j1.addInt("nodes_before", long(cb.quadNodes))
                .addInt("tiles_before", long(cb.tiles))
                .addInt("tris_before", long(cb.triangles));
            j1.addInt("nodes_after", long(ca.quadNodes))
                .addInt("tiles_after", long(ca.tiles))
                .addInt("tris_after", long(ca.triangles));
            j1.add("build_s", buildS);
            if (json) std::cout << j1.str() << std::endl;

            if (draw) {
                // Frames drawn through the renderer, finished, before (no culling) and after, interleaved.
                auto frame = [&](const sg::CullSettings& s) {
                    const auto f0 = Clock::now();
                    cull.cull(scene, cam, s, list, st);
                    renderer->draw(list, cam);
                    renderer->finish();
                    return msSince(f0);
                };
                frame(none);  // uploads the meshes
                frame(after);
                std::vector<double> mb, ma;
                for (int f = 0; f < frames; ++f) {
                    mb.push_back(frame(none));
                    ma.push_back(frame(after));
                }
                const double fb = 1000.0 / median(mb), fa = 1000.0 / median(ma);
                std::snprintf(buf, sizeof buf, "| %d | %d | %.1f | %.1f | %.2f | %s | %s |\n", n, fov, fb, fa, fa / fb,
                              paperNum(pr, &PaperRow::fpsBefore).c_str(), paperNum(pr, &PaperRow::fpsAfter).c_str());
                t2 << buf;
                Json j2;
                j2.add("command", "terrain").add("table", "fps").addInt("size", n).addInt("fov", fov);
                j2.add("fps_before", fb)
                    .add("fps_after", fa)
                    .add("frame_ms_before", median(mb))
                    .add("frame_ms_after", median(ma));
                if (json) std::cout << j2.str() << std::endl;
            }

            // Each refinement on its own: cull time (median of interleaved repetitions) and what it tested.
            std::vector<Refinement> rs = refinements();
            std::vector<std::vector<double>> ms(rs.size());
            std::vector<sg::CullStats> sts(rs.size());
            std::vector<sg::CullTraversal> culls(rs.size());
            for (size_t k = 0; k < rs.size(); ++k) culls[k].cull(scene, cam, rs[k].set, list, sts[k]);  // warm-up
            for (int r = 0; r < reps; ++r)
                for (size_t k = 0; k < rs.size(); ++k) {
                    const double c0 = cpuMs();
                    culls[k].cull(scene, cam, rs[k].set, list, sts[k]);
                    ms[k].push_back(cpuMs() - c0);
                }
            const double base = median(ms[0]);
            for (size_t k = 0; k < rs.size(); ++k) {
                const double m = median(ms[k]);
                std::snprintf(buf, sizeof buf, "| %d | %d | %s | %.3f | %.2f | %llu | %llu | %llu |\n", n, fov,
                              rs[k].name, m, m / base, (unsigned long long)sts[k].boundsTested,
                              (unsigned long long)sts[k].geometries, (unsigned long long)sts[k].triangles);
                t3 << buf;
                Json j3;
                j3.add("command", "terrain").add("table", "refinements").addInt("size", n).addInt("fov", fov);
                j3.add("method", rs[k].name).add("cull_ms", m).add("ratio", m / base);
                j3.addInt("bounds_tested", long(sts[k].boundsTested)).addInt("tiles", long(sts[k].geometries));
                j3.addInt("triangles", long(sts[k].triangles));
                if (json) std::cout << j3.str() << std::endl;
            }
        }
        if (renderer) renderer->clear();  // the next size's meshes replace these
    }
    if (!json) {
        std::printf("\nTable 1: quadtree nodes and triangles drawn, without culling (before) and with (after)\n%s",
                    t1.str().c_str());
        if (draw)
            std::printf("\nTable 2: frames per second at %dx%d (OSMesa), before and after\n%s", kW, kH,
                        t2.str().c_str());
        std::printf(
            "\nRefinements: cull CPU time (no sort, median of interleaved runs) against the plain hierarchical box "
            "test (ratio), one at a time\n%s",
            t3.str().c_str());
    }
    return 0;
}

}  // namespace bench
