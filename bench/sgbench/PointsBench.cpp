// sgbench points: what drawing points costs on this machine, beside triangles. One surface (a rolling heightfield
// seen from above one corner, filling the view) as N points, and as a grid of N triangles; the same cull, drawn
// headless, frame by frame in turn (A B C D E A B ...): points 1 px squares; 3 px discs; 3 px discs with eye-dome
// lighting; the triangles; the triangles with eye-dome lighting. Points (triangles) per second are N over the median
// frame; eye-dome lighting's cost per pixel is its frames' extra time over the picture's pixels.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/KeepFreedMemory.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sgbench/Bench.h"
#include "testbed/Rng.h"

#include <array>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace bench {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

constexpr double kSize = 100.0;  // the surface's side, metres
constexpr int kTiles = 4;        // 4 x 4 geometries, as a point tile pyramid's leaves would be

double height(double x, double y) { return 3.0 * std::sin(x * 0.15) * std::cos(y * 0.11) + 0.02 * x; }
sg::vec4 colorAt(double z) {
    const float t = float((z + 4.0) / 8.0);
    return {0.3f + 0.6f * t, 0.5f, 0.9f - 0.6f * t, 1.0f};
}

// The surface as `count` random points in kTiles^2 geometries.
sg::ref_ptr<sg::Node> pointSurface(uint64_t count) {
    scenes::Rng rng(7);
    auto root = sg::make<sg::Group>();
    const double tile = kSize / kTiles;
    const uint64_t per = count / (kTiles * kTiles);
    for (int ty = 0; ty < kTiles; ++ty)
        for (int tx = 0; tx < kTiles; ++tx) {
            std::vector<sg::vec3> pos;
            std::vector<sg::vec4> col;
            pos.reserve(per);
            col.reserve(per);
            for (uint64_t i = 0; i < per; ++i) {
                const double x = (tx + rng.uniform()) * tile, y = (ty + rng.uniform()) * tile, z = height(x, y);
                pos.emplace_back(float(x), float(y), float(z));
                col.push_back(colorAt(z));
            }
            auto m = sg::make<sg::Mesh>();
            m->setPoints(std::move(pos), std::move(col));
            m->setPointSpacing(float(kSize / std::sqrt(double(count))));
            root->addChild(sg::make<sg::Geometry>(m, sg::make<sg::Material>()));
        }
    return root;
}

// The same surface as about `count` triangles in kTiles^2 grids, coloured as the points.
sg::ref_ptr<sg::Node> triangleSurface(uint64_t count) {
    auto root = sg::make<sg::Group>();
    const int q = std::max(1, int(std::sqrt(double(count) / (2.0 * kTiles * kTiles))));  // quads a tile's side
    const double tile = kSize / kTiles, step = tile / q;
    for (int ty = 0; ty < kTiles; ++ty)
        for (int tx = 0; tx < kTiles; ++tx) {
            std::vector<sg::vec3> pos, nrm;
            std::vector<sg::vec4> col;
            std::vector<uint32_t> idx;
            for (int j = 0; j <= q; ++j)
                for (int i = 0; i <= q; ++i) {
                    const double x = tx * tile + i * step, y = ty * tile + j * step, z = height(x, y);
                    pos.emplace_back(float(x), float(y), float(z));
                    nrm.emplace_back(0.0f, 0.0f, 1.0f);
                    col.push_back(colorAt(z));
                }
            for (int j = 0; j < q; ++j)
                for (int i = 0; i < q; ++i) {
                    const uint32_t a = uint32_t(j * (q + 1) + i), b = a + 1, c = a + uint32_t(q + 1), d = c + 1;
                    idx.insert(idx.end(), {a, b, d, a, d, c});
                }
            auto m = sg::make<sg::Mesh>();
            m->set(std::move(pos), std::move(nrm), std::move(idx), {}, std::move(col));
            root->addChild(sg::make<sg::Geometry>(m, sg::make<sg::Material>()));
        }
    return root;
}

sg::Camera overview(int w, int h) {
    sg::Camera cam;
    cam.setViewport(w, h);
    cam.setPerspective(50.0, double(w) / double(h), 1.0, 1000.0);
    cam.setLookAt(sg::dvec3(-20.0, -20.0, 60.0), sg::dvec3(55.0, 55.0, 0.0), sg::dvec3(0, 0, 1));
    return cam;
}

struct Way {
    const char* name;
    bool points;
    float size;
    bool round, eyeDome;
};

}  // namespace

int runPoints(const Args& a) {
    const long count = a.num("count", 1000000), frames = a.num("frames", 20);
    if (count < 16 || count > 200000000)
        throw std::invalid_argument("sgbench points: --count " + std::to_string(count) + " is not in 16..200000000");
    if (frames < 1) throw std::invalid_argument("sgbench points: --frames must be at least 1");
    const int w = int(a.num("width", 1280)), h = int(a.num("height", 720));
    if (w < 16 || h < 16) throw std::invalid_argument("sgbench points: --width and --height must be at least 16");

    sg::OsmesaContext ctx(w, h);
    sg::Renderer renderer;
    if (renderer.softwareRasterizer()) sg::keepFreedMemory();
    sg::Scene points(pointSurface(uint64_t(count))), triangles(triangleSurface(uint64_t(count)));
    points.update();
    triangles.update();
    const sg::Camera cam = overview(w, h);
    sg::CullTraversal cull;
    sg::DrawList pointList, triangleList;
    sg::CullStats ps, ts;
    cull.cull(points, cam, sg::CullSettings{}, pointList, ps);
    cull.cull(triangles, cam, sg::CullSettings{}, triangleList, ts);

    const std::array<Way, 5> ways{{{"points_1px", true, 1.0f, false, false},
                                   {"points_3px_round", true, 3.0f, true, false},
                                   {"points_3px_round_edl", true, 3.0f, true, true},
                                   {"triangles", false, 1.0f, false, false},
                                   {"triangles_edl", false, 1.0f, false, true}}};
    auto frame = [&](const Way& way) {
        sg::PointShading p;
        p.pointSize = way.size;
        p.round = way.round;
        p.eyeDome = way.eyeDome;
        renderer.setPointShading(p);
        const auto t0 = Clock::now();
        renderer.draw(way.points ? pointList : triangleList, cam);
        renderer.finish();
        return msSince(t0);
    };
    std::array<sg::Image, ways.size()> images;
    for (size_t k = 0; k < ways.size(); ++k) {  // uploads and shader variants before the timing
        frame(ways[k]);
        images[k] = renderer.readColor();
    }
    std::array<std::vector<double>, ways.size()> ms;
    std::vector<double> edlPoints, edlTriangles, pointsVsTriangles;
    for (long f = 0; f < frames; ++f) {
        std::array<double, ways.size()> t{};
        for (size_t k = 0; k < ways.size(); ++k) ms[k].push_back(t[k] = frame(ways[k]));
        edlPoints.push_back(t[2] - t[1]);
        edlTriangles.push_back(t[4] - t[3]);
        pointsVsTriangles.push_back(t[0] / t[3]);
    }

    const double pixels = double(w) * double(h);
    Json j;
    j.add("command", "points").addInt("points", long(ps.points)).addInt("triangles", long(ts.triangles));
    j.addInt("frames", frames).addInt("width", w).addInt("height", h);
    for (size_t k = 0; k < ways.size(); ++k) {
        const double med = median(ms[k]);
        const double n = double(ways[k].points ? ps.points : ts.triangles);
        j.add(std::string("frame_ms_median_") + ways[k].name, med);
        j.add(std::string(ways[k].points ? "points" : "triangles") + "_per_s_" + ways[k].name, n / (med / 1000.0));
    }
    j.add("points_1px_over_triangles_frame", median(pointsVsTriangles));
    j.add("edl_ns_per_pixel_points", median(edlPoints) * 1e6 / pixels);
    j.add("edl_ns_per_pixel_triangles", median(edlTriangles) * 1e6 / pixels);
    j.addInt("pixels_differing_edl", long(sg::countDifferingPixels(images[1], images[2], 0)));
    j.print(a);
    if (sg::countDifferingPixels(images[1], images[2], 0) == 0) {
        std::fprintf(stderr, "sgbench points: eye-dome lighting changed no pixel\n");
        return 1;
    }
    return 0;
}

}  // namespace bench
