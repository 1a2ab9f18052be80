// sgmaptess: the map's triangulators compared on the real data (docs/map.md): sgkit's ear clipping
// (map/data/Triangulate.h) against the GLU tessellator, on every country, state and county polygon as the
// converter triangulates it (cut at the projection's edge, in degrees). Prints per level the time of each
// (the triangulation calls alone, best of three, runs interleaved) and its failures: regions whose triangle area (in
// the map's plane) differs from the polygon area by over 1e-6, or that get no triangles.
#include "map/data/MapProjection.h"
#include "map/data/TopoJson.h"
#include "map/data/Triangulate.h"

#include <GL/glu.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <string>
#include <vector>

using namespace sg;

namespace {

struct Region {
    std::vector<GeoPolygon> raw;     // cut at the edge
    std::vector<GeoPolygon> simple;  // and self-crossings split into loops
    MapProjection projection;
    double area = 0.0;  // of `simple` in the map's plane: the reference
};

double tri(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
    return ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y)) / 2.0;
}

double planeArea(const std::vector<GeoPolygon>& ps, const MapProjection& p) {
    double a = 0.0;
    for (GeoPolygon q : ps) {
        for (auto& v : q.outer) v = p.projectRelative(v.x, v.y);
        for (auto& h : q.holes)
            for (auto& v : h) v = p.projectRelative(v.x, v.y);
        a += polygonArea(q);
    }
    return a;
}

using Clock = std::chrono::steady_clock;

// Triangle area in the map's plane of the ear clipper's output; -1 when it gives no triangle. `seconds`
// grows by the time of the triangulation alone.
double earArea(const std::vector<GeoPolygon>& ps, const MapProjection& proj, size_t& triangles, double& seconds) {
    double a = 0.0;
    size_t n = 0;
    for (const GeoPolygon& p : ps) {
        std::vector<glm::dvec2> v;
        for (const auto& q : p.outer) v.push_back(proj.projectRelative(q.x, q.y));
        for (const auto& h : p.holes)
            for (const auto& q : h) v.push_back(proj.projectRelative(q.x, q.y));
        const auto t0 = Clock::now();
        const auto t = triangulatePolygon(p);
        seconds += std::chrono::duration<double>(Clock::now() - t0).count();
        for (size_t k = 0; k + 2 < t.size(); k += 3) a += tri(v[t[k]], v[t[k + 1]], v[t[k + 2]]);
        n += t.size() / 3;
    }
    triangles += n;
    return n ? a : -1.0;
}

struct GluContext {
    std::deque<std::array<double, 3>> added;  // vertices GLU makes at crossings
    std::vector<const double*> out;
    bool error = false;
};
void GLAPIENTRY onVertex(void* v, void* ctx) { static_cast<GluContext*>(ctx)->out.push_back(static_cast<double*>(v)); }
void GLAPIENTRY onEdgeFlag(GLboolean, void*) {}  // its presence makes GLU emit separate triangles only
void GLAPIENTRY onError(GLenum, void* ctx) { static_cast<GluContext*>(ctx)->error = true; }
void GLAPIENTRY onCombine(GLdouble c[3], void* [4], GLfloat[4], void** out, void* ctx) {
    auto* g = static_cast<GluContext*>(ctx);
    g->added.push_back({c[0], c[1], c[2]});
    *out = g->added.back().data();
}

double gluArea(GLUtesselator* tess, const std::vector<GeoPolygon>& ps, const MapProjection& proj, size_t& triangles,
               size_t& errors, double& seconds) {
    double a = 0.0;
    size_t n = 0;
    for (const GeoPolygon& p : ps) {
        GluContext g;
        std::vector<std::array<double, 3>> v;
        for (const auto& q : p.outer) v.push_back({q.x, q.y, 0.0});
        for (const auto& h : p.holes)
            for (const auto& q : h) v.push_back({q.x, q.y, 0.0});
        const auto t0 = Clock::now();
        gluTessBeginPolygon(tess, &g);
        size_t k = 0;
        auto contour = [&](const GeoRing& r) {
            gluTessBeginContour(tess);
            for (size_t i = 0; i < r.size(); ++i, ++k) gluTessVertex(tess, v[k].data(), v[k].data());
            gluTessEndContour(tess);
        };
        contour(p.outer);
        for (const auto& h : p.holes) contour(h);
        gluTessEndPolygon(tess);
        seconds += std::chrono::duration<double>(Clock::now() - t0).count();
        errors += g.error;
        for (size_t t = 0; t + 2 < g.out.size(); t += 3) {
            const glm::dvec2 a0 = proj.projectRelative(g.out[t][0], g.out[t][1]);
            const glm::dvec2 a1 = proj.projectRelative(g.out[t + 1][0], g.out[t + 1][1]);
            const glm::dvec2 a2 = proj.projectRelative(g.out[t + 2][0], g.out[t + 2][1]);
            a += tri(a0, a1, a2);
        }
        n += g.out.size() / 3;
    }
    triangles += n;
    return n ? std::abs(a) : -1.0;
}

struct Result {
    double seconds = 1e30;
    size_t failures = 0, triangles = 0, errors = 0;
    double worst = 0.0;
};

void count(Result& r, double got, double want) {
    const double err = want > 0.0 ? (got < 0.0 ? 1.0 : std::abs(got - want) / want) : 0.0;
    r.worst = std::max(r.worst, err);
    if (err > 1e-6) ++r.failures;
}

void compare(const char* name, const std::vector<Region>& regions) {
    GLUtesselator* tess = gluNewTess();
    gluTessCallback(tess, GLU_TESS_VERTEX_DATA, reinterpret_cast<void(GLAPIENTRY*)()>(&onVertex));
    gluTessCallback(tess, GLU_TESS_EDGE_FLAG_DATA, reinterpret_cast<void(GLAPIENTRY*)()>(&onEdgeFlag));
    gluTessCallback(tess, GLU_TESS_ERROR_DATA, reinterpret_cast<void(GLAPIENTRY*)()>(&onError));
    gluTessCallback(tess, GLU_TESS_COMBINE_DATA, reinterpret_cast<void(GLAPIENTRY*)()>(&onCombine));
    gluTessProperty(tess, GLU_TESS_WINDING_RULE, GLU_TESS_WINDING_ODD);
    gluTessNormal(tess, 0, 0, 1);
    Result ear, earSimple, glu;
    size_t points = 0, polygons = 0;
    for (const Region& r : regions)
        for (const auto& p : r.raw) {
            ++polygons;
            points += p.outer.size();
            for (const auto& h : p.holes) points += h.size();
        }
    for (int run = 0; run < 3; ++run) {
        auto timed = [&](Result& res, auto fn) {
            Result now;
            now.seconds = 0.0;
            for (const Region& r : regions) count(now, fn(r, now), r.area);
            now.seconds = std::min(now.seconds, res.seconds);
            res = now;
        };
        timed(ear, [&](const Region& r, Result& n) { return earArea(r.raw, r.projection, n.triangles, n.seconds); });
        timed(glu, [&](const Region& r, Result& n) {
            return gluArea(tess, r.raw, r.projection, n.triangles, n.errors, n.seconds);
        });
        timed(earSimple,
              [&](const Region& r, Result& n) { return earArea(r.simple, r.projection, n.triangles, n.seconds); });
    }
    gluDeleteTess(tess);
    auto row = [&](const char* who, const Result& r) {
        std::printf("| %-9s | %-26s | %8.1f | %8zu | %5zu | %9.2g | %6zu |\n", name, who, r.seconds * 1e3, r.triangles,
                    r.failures, r.worst, r.errors);
    };
    std::printf("| %-9s | %zu regions, %zu polygons, %zu points |\n", name, regions.size(), polygons, points);
    row("ear clipping", ear);
    row("ear clipping, loops split", earSimple);
    row("GLU tessellator (odd)", glu);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: sgmaptess SOURCE_DIR (countries-50m.json and counties-10m.json)\n");
        return 2;
    }
    try {
        const std::string dir = argv[1];
        auto world = readTopoJson(dir + "/countries-50m.json");
        auto us = readTopoJson(dir + "/counties-10m.json");
        auto prepare = [](const std::vector<GeoRegion>& in, auto projectionOf) {
            std::vector<Region> out;
            for (const GeoRegion& g : in) {
                Region r;
                r.projection = projectionOf(g);
                r.raw = r.projection.cutAtEdge(g).polygons;
                for (const auto& p : r.raw)
                    for (auto& q : splitSelfCrossings(p)) r.simple.push_back(std::move(q));
                r.area = planeArea(r.simple, r.projection);
                out.push_back(std::move(r));
            }
            return out;
        };
        auto byState = [](const GeoRegion& g) { return MapProjection::usState(g.id.substr(0, 2)); };
        std::printf(
            "| level     | triangulator               | ms       | triangles | fails | worst err | GLU errors |\n");
        compare("countries", prepare(world.at("countries"), [](const GeoRegion&) { return MapProjection::world(); }));
        compare("states", prepare(us.at("states"), byState));
        compare("counties", prepare(us.at("counties"), byState));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sgmaptess: %s\n", e.what());
        return 1;
    }
}
