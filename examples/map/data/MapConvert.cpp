// buildMapLevel / convertMapData / generateFallbackMap: regions to prisms (top face from the triangulator,
// one wall quad per ring edge), levels written through saveGltf with the region properties in extras.
#include "map/data/MapConvert.h"

#include "map/data/MapProjection.h"
#include "map/data/TopoJson.h"
#include "map/data/Triangulate.h"
#include "nodes/Geometry.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <unordered_map>

namespace sg {
namespace {

// A stable pastel colour per region id, so that neighbours differ and a file looks the same on every run.
vec4 regionColor(const std::string& id, size_t index) {
    uint32_t h = 2166136261u;
    for (char c : id) h = (h ^ uint8_t(c)) * 16777619u;
    if (id.empty()) h ^= uint32_t(index) * 2654435761u;
    const float r = 0.45f + 0.45f * float(h & 255u) / 255.0f;
    const float g = 0.45f + 0.45f * float((h >> 8) & 255u) / 255.0f;
    const float b = 0.45f + 0.45f * float((h >> 16) & 255u) / 255.0f;
    return {r, g, b, 1.0f};
}

// Twice the signed area of a triangle of the plane.
double cross2(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
    return (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
}

// Turned over: clockwise by more than rounding (a triangle whose points lie on a straight line stays).
bool facesDown(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
    const glm::dvec2 u = b - a, v = c - a;
    return cross2(a, b, c) < -1e-12 * (glm::dot(u, u) + glm::dot(v, v));
}

// Triangles cut in degrees, their points then projected: a straight run of a border along a parallel (or an
// Equal Earth meridian) is cut as flat ears, and where the projected run bends into the region those ears are
// turned over. Their areas cancel, but the triangle beside the last of them reaches the chord, outside the ring
// (up to 12 km beyond the Alaska-Yukon border on the world level, over Canada's own prism). Flipping the edge a
// turned-over triangle shares with a neighbour, when both new triangles face up, covers the ring exactly; the
// signed area, and so the area check, is unchanged. Returns how many stay turned over.
size_t untwist(std::vector<uint32_t>& tri, const std::vector<glm::dvec2>& pts) {
    const size_t n = tri.size() / 3;
    auto key = [](uint32_t a, uint32_t b) { return uint64_t(a) << 32 | b; };
    auto turned = [&](size_t t) { return facesDown(pts[tri[3 * t]], pts[tri[3 * t + 1]], pts[tri[3 * t + 2]]); };
    std::vector<size_t> todo;
    for (size_t t = 0; t < n; ++t)
        if (turned(t)) todo.push_back(t);
    if (todo.empty()) return 0;
    std::unordered_map<uint64_t, size_t> edge;  // directed edge -> its triangle
    for (size_t t = 0; t < n; ++t)
        for (int k = 0; k < 3; ++k) edge[key(tri[3 * t + k], tri[3 * t + (k + 1) % 3])] = t;
    while (!todo.empty()) {
        std::vector<size_t> left;
        for (size_t t : todo) {
            if (!turned(t)) continue;
            bool flipped = false;
            for (int k = 0; k < 3 && !flipped; ++k) {
                const uint32_t u = tri[3 * t + k], v = tri[3 * t + (k + 1) % 3], w = tri[3 * t + (k + 2) % 3];
                const auto it = edge.find(key(v, u));
                if (it == edge.end()) continue;
                const size_t s = it->second;
                uint32_t x = tri[3 * s];
                for (int j = 0; j < 3; ++j)
                    if (tri[3 * s + j] != u && tri[3 * s + j] != v) x = tri[3 * s + j];
                // (u, v, w) and (v, u, x) become (u, x, w) and (x, v, w).
                if (x == w || cross2(pts[u], pts[x], pts[w]) <= 0.0 || cross2(pts[x], pts[v], pts[w]) <= 0.0) continue;
                tri[3 * t] = u, tri[3 * t + 1] = x, tri[3 * t + 2] = w;
                tri[3 * s] = x, tri[3 * s + 1] = v, tri[3 * s + 2] = w;
                edge.erase(key(u, v));
                edge.erase(key(v, u));
                edge[key(u, x)] = t, edge[key(x, w)] = t, edge[key(w, u)] = t;
                edge[key(x, v)] = s, edge[key(v, w)] = s, edge[key(w, x)] = s;
                flipped = true;
            }
            if (!flipped) left.push_back(t);
        }
        if (left.size() == todo.size()) break;
        todo = std::move(left);
    }
    size_t stay = 0;
    for (size_t t = 0; t < n; ++t) stay += turned(t);
    return stay;
}

// The signed area of triangles of the plane.
double signedArea(const std::vector<uint32_t>& tri, const std::vector<glm::dvec2>& pts) {
    double a = 0.0;
    for (size_t k = 0; k + 2 < tri.size(); k += 3) a += cross2(pts[tri[k]], pts[tri[k + 1]], pts[tri[k + 2]]) / 2.0;
    return a;
}

struct PrismBuilder {
    std::vector<vec3> positions, normals;
    std::vector<uint32_t> indices;
    double triangleArea = 0.0;
    size_t topTriangles = 0;
    size_t turnedOver = 0;     // top triangles facing down in the map's plane (covering outside the ring)
    double polygonArea = 0.0;  // of the polygons in the map's plane

    // `p` in the plane it is triangulated in; `project` (when given) takes its points to the map's plane.
    void polygon(const GeoPolygon& src, float height, const MapProjection* project) {
        GeoPolygon p = src;
        if (project) {
            for (auto& q : p.outer) q = project->projectRelative(q.x, q.y);
            for (auto& h : p.holes)
                for (auto& q : h) q = project->projectRelative(q.x, q.y);
        }
        const uint32_t base = uint32_t(positions.size());
        std::vector<const GeoRing*> rings{&p.outer};
        for (const auto& h : p.holes) rings.push_back(&h);
        std::vector<glm::dvec2> pts;
        for (const GeoRing* r : rings)
            for (const auto& q : *r) {
                pts.push_back(q);
                positions.push_back(vec3(float(q.x), float(q.y), height));
                normals.push_back(vec3(0, 0, 1));
            }
        std::vector<uint32_t> tri = triangulatePolygon(src);
        size_t down = untwist(tri, pts);
        if (down > 0 && project) {
            // What flips cannot mend: the polygon triangulated in the map's plane, where its runs are bent,
            // kept when it covers the polygon's area with every triangle facing up.
            std::vector<uint32_t> again = triangulatePolygon(p);
            const double area = sg::polygonArea(p);
            if (untwist(again, pts) == 0 && std::abs(signedArea(again, pts) - area) <= 1e-9 * std::abs(area))
                tri = std::move(again), down = 0;
        }
        turnedOver += down;
        topTriangles += tri.size() / 3;
        polygonArea += sg::polygonArea(p);
        for (size_t k = 0; k + 2 < tri.size(); k += 3) {
            const glm::dvec2 a = pts[tri[k]], b = pts[tri[k + 1]], c = pts[tri[k + 2]];
            triangleArea += ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y)) / 2.0;
            for (int j = 0; j < 3; ++j) indices.push_back(base + tri[k + size_t(j)]);
        }
        // Walls: outward for the outer ring (made counter-clockwise) and into each hole (made clockwise).
        for (size_t r = 0; r < rings.size(); ++r) {
            const GeoRing& ring = *rings[r];
            const bool ccw = ringArea(ring) > 0.0;
            const bool flip = (r == 0) != ccw;
            const size_t n = ring.size();
            for (size_t i = 0; i < n; ++i) {
                glm::dvec2 a = ring[i], b = ring[(i + 1) % n];
                if (flip) std::swap(a, b);
                const glm::dvec2 d = b - a;
                const double len = std::sqrt(d.x * d.x + d.y * d.y);
                if (len == 0.0) continue;
                const vec3 nrm(float(d.y / len), float(-d.x / len), 0.0f);
                const uint32_t v = uint32_t(positions.size());
                positions.push_back(vec3(float(a.x), float(a.y), 0.0f));
                positions.push_back(vec3(float(b.x), float(b.y), 0.0f));
                positions.push_back(vec3(float(b.x), float(b.y), height));
                positions.push_back(vec3(float(a.x), float(a.y), height));
                for (int j = 0; j < 4; ++j) normals.push_back(nrm);
                for (uint32_t j : {0u, 1u, 2u, 0u, 2u, 3u}) indices.push_back(v + j);
            }
        }
    }
};

GeoRegion projected(GeoRegion r, const MapProjection& p) {
    for (auto& poly : r.polygons) {
        for (auto& q : poly.outer) q = p.projectRelative(q.x, q.y);
        for (auto& h : poly.holes)
            for (auto& q : h) q = p.projectRelative(q.x, q.y);
    }
    return r;
}

double regionArea(const GeoRegion& r) {
    double a = 0.0;
    for (const auto& p : r.polygons) a += polygonArea(p);
    return a;
}

void accumulate(MapConvertReport& rep, const MapLevel& level, const std::string& file) {
    ++rep.files;
    rep.regions += level.regions;
    rep.emptyRegions += level.emptyRegions;
    rep.triangles += level.triangles;
    for (const auto& p : level.problems) rep.problems.push_back(file + ": " + p);
    for (const auto& p : level.withoutArea) rep.withoutArea.push_back(file + ": " + p);
    if (level.maxAreaError >= rep.maxAreaError) {
        rep.maxAreaError = level.maxAreaError;
        rep.worst = file + ": " + level.worstRegion;
    }
}

std::string stateOf(const std::string& countyId) { return countyId.substr(0, std::min<size_t>(2, countyId.size())); }

}  // namespace

MapLevel buildMapLevel(const std::vector<GeoRegion>& regions, const std::vector<double>& trueAreas,
                       const MapLevelOptions& options, const std::vector<MapProjection>& projections) {
    if (!projections.empty() && projections.size() != regions.size())
        throw std::invalid_argument("buildMapLevel(): one projection per region is needed (" +
                                    std::to_string(regions.size()) + " regions, " + std::to_string(projections.size()) +
                                    " projections)");
    if (trueAreas.size() != regions.size())
        throw std::invalid_argument("buildMapLevel(): one true area per region is needed (" +
                                    std::to_string(regions.size()) + " regions, " + std::to_string(trueAreas.size()) +
                                    " areas)");
    MapLevel level;
    level.root = make<Group>();
    double maxArea = 0.0;
    for (double a : trueAreas) maxArea = std::max(maxArea, a);
    for (size_t i = 0; i < regions.size(); ++i) {
        const GeoRegion& r = regions[i];
        double h = options.height;
        if (options.heightEncodesArea && maxArea > 0.0)
            h *= 0.25 + 0.75 * std::sqrt(std::max(0.0, trueAreas[i]) / maxArea);
        PrismBuilder b;
        const MapProjection* proj = projections.empty() ? nullptr : &projections[i];
        for (const GeoPolygon& p : r.polygons) b.polygon(p, float(h), proj);
        const double polyArea = b.polygonArea;
        const double err = polyArea > 0.0 ? std::abs(b.triangleArea - polyArea) / polyArea : 0.0;
        const std::string label = r.id.empty() ? r.name : r.id;
        if (err > 1e-6) level.problems.push_back(label + ": area off by " + std::to_string(err));
        if (b.turnedOver > 0)
            level.problems.push_back(label + ": " + std::to_string(b.turnedOver) +
                                     " top triangles turned over in the map's plane");
        if (err >= level.maxAreaError) {
            level.maxAreaError = err;
            level.worstRegion = label;
        }
        auto mesh = make<Mesh>();
        const size_t topTriangles = b.topTriangles;
        mesh->set(std::move(b.positions), std::move(b.normals), std::move(b.indices));
        auto g = make<Geometry>(mesh, make<Material>(regionColor(r.id, i)));
        g->setName(r.name.empty() ? r.id : r.name);
        GltfProperties props;
        props.strings["id"] = r.id;
        props.strings["name"] = r.name;
        props.strings["kind"] = options.kind;
        props.numbers["area_km2"] = trueAreas[i];
        if (auto c = options.children.find(r.id); c != options.children.end() && !r.id.empty())
            props.strings["child"] = c->second;
        level.properties[g.get()] = std::move(props);
        level.root->addChild(g);
        ++level.regions;
        if (polyArea <= 0.0) {
            level.withoutArea.push_back(label + (r.name.empty() ? "" : " (" + r.name + ")") +
                                        ": no area in the source data, kept without a top face");
        } else if (topTriangles == 0) {
            ++level.emptyRegions;
            level.problems.push_back(label + ": no triangles");
        }
        level.triangles += mesh->triangleCount();
    }
    return level;
}

void writeMapLevel(const MapLevel& level, const std::string& path, const GltfProperties& scene) {
    GltfSaveOptions o;
    o.sceneProperties = scene;
    // sgkit's frame, not glTF's +Y up: the map's plane is XY (x east, y north, kilometres), prisms rise along +Z.
    o.sceneProperties.strings.emplace("up", "+Z");
    o.sceneProperties.strings.emplace("units", "km");
    o.nodeProperties = [&](const Node& n) {
        auto it = level.properties.find(&n);
        return it == level.properties.end() ? GltfProperties{} : it->second;
    };
    saveGltf(*level.root, path, o);
}

MapConvertReport convertMapData(const std::string& inDir, const std::string& outDir, const MapLevelOptions& base) {
    namespace fs = std::filesystem;
    const auto t0 = std::chrono::steady_clock::now();
    MapConvertReport rep;
    auto world = readTopoJson((fs::path(inDir) / "countries-50m.json").string());
    auto us = readTopoJson((fs::path(inDir) / "counties-10m.json").string());
    for (const char* key : {"countries"})
        if (!world.count(key)) throw LoadError(inDir + "/countries-50m.json", "objects", "has no \"countries\"");
    for (const char* key : {"states", "counties"})
        if (!us.count(key))
            throw LoadError(inDir + "/counties-10m.json", "objects", std::string("has no \"") + key + "\"");
    fs::create_directories(fs::path(outDir) / "states");

    std::vector<double> areas;
    std::vector<MapProjection> projections;
    // Regions cut at their projection's edge (still in degrees), their projections and true areas.
    auto project = [&](const std::vector<GeoRegion>& in, auto projectionOf) {
        std::vector<GeoRegion> out;
        areas.clear();
        projections.clear();
        for (const GeoRegion& r : in) {
            const MapProjection& p = projections.emplace_back(projectionOf(r));
            GeoRegion cut = p.cutAtEdge(r);
            std::vector<GeoPolygon> simple;
            for (const GeoPolygon& poly : cut.polygons)
                for (GeoPolygon& q : splitSelfCrossings(poly)) simple.push_back(std::move(q));
            cut.polygons = std::move(simple);
            areas.push_back(regionArea(projected(cut, p)) / p.areaFactor());
            out.push_back(std::move(cut));
        }
        return out;
    };

    // World: countries, the United States leading to the U.S. file.
    MapLevelOptions wo = base;
    wo.kind = "country";
    wo.height = base.height * 8.0;
    wo.children = {{"840", "us.glb"}};
    const auto worldCut = project(world["countries"], [](const GeoRegion&) { return MapProjection::world(); });
    MapLevel wl = buildMapLevel(worldCut, areas, wo, projections);
    writeMapLevel(wl, (fs::path(outDir) / "world.glb").string(),
                  {{{"level", "world"}, {"projection", MapProjection::world().describe()}}, {}});
    accumulate(rep, wl, "world.glb");

    // The U.S.: states and territories, each leading to its counties' file.
    MapLevelOptions so = base;
    so.kind = "state";
    so.height = base.height * 2.0;
    std::map<std::string, std::vector<GeoRegion>> countiesByState;
    for (const GeoRegion& c : us["counties"]) countiesByState[stateOf(c.id)].push_back(c);
    for (const GeoRegion& s : us["states"])
        if (countiesByState.count(s.id)) so.children[s.id] = "states/" + s.id + ".glb";
    auto byState = [](const GeoRegion& r) { return MapProjection::usState(stateOf(r.id)); };
    const auto stateCut = project(us["states"], byState);
    MapLevel sl = buildMapLevel(stateCut, areas, so, projections);
    writeMapLevel(
        sl, (fs::path(outDir) / "us.glb").string(),
        {{{"level", "us"}, {"parent", "840"}, {"projection", "albers-usa (see each region's state file)"}}, {}});
    accumulate(rep, sl, "us.glb");

    // Each state: its counties, in the U.S. file's coordinates (so they sit on the state's prism).
    MapLevelOptions co = base;
    co.kind = "county";
    for (const GeoRegion& s : us["states"]) {
        auto it = countiesByState.find(s.id);
        if (it == countiesByState.end()) continue;
        const auto cut = project(it->second, byState);
        MapLevel cl = buildMapLevel(cut, areas, co, projections);
        const std::string file = "states/" + s.id + ".glb";
        writeMapLevel(cl, (fs::path(outDir) / file).string(),
                      {{{"level", "state"},
                        {"parent", s.id},
                        {"name", s.name},
                        {"projection", MapProjection::usState(s.id).describe()}},
                       {}});
        accumulate(rep, cl, file);
    }
    rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return rep;
}

namespace {

// Deterministic on every platform (std's distributions are not): mt19937's raw output scaled.
struct Random {
    std::mt19937 g;
    explicit Random(uint32_t seed) : g(seed) {}
    double uniform(double a, double b) { return a + (b - a) * (double(g()) / 4294967296.0); }
};

// Splits the box into n cells by random cuts across the longer side, each cell's boundary made wavy by
// points shared with its neighbours (a cut's points depend only on the cut), so that cells tile the box.
struct Cell {
    glm::dvec2 lo, hi;
};
void splitBox(const Cell& c, int n, Random& rnd, std::vector<Cell>& out) {
    if (n <= 1) {
        out.push_back(c);
        return;
    }
    const int left = n / 2;
    const double f = double(left) / n * rnd.uniform(0.8, 1.2);
    const glm::dvec2 size = c.hi - c.lo;
    Cell a = c, b = c;
    if (size.x >= size.y) {
        a.hi.x = b.lo.x = c.lo.x + size.x * std::clamp(f, 0.2, 0.8);
    } else {
        a.hi.y = b.lo.y = c.lo.y + size.y * std::clamp(f, 0.2, 0.8);
    }
    splitBox(a, left, rnd, out);
    splitBox(b, n - left, rnd, out);
}

// A cell as a polygon: its box, with a square hole (a lake) in every third cell and an island polygon in
// every fifth, so that the generated map has holes and multipolygons like the real one.
GeoRegion cellRegion(const Cell& c, size_t i, std::string id, std::string name) {
    GeoRegion r;
    r.id = std::move(id);
    r.name = std::move(name);
    const glm::dvec2 lo = c.lo, hi = c.hi, s = hi - lo;
    GeoPolygon p;
    p.outer = {lo, {hi.x, lo.y}, hi, {lo.x, hi.y}};
    if (i % 3 == 0) {
        const glm::dvec2 m = lo + s * 0.5, e = s * 0.1;
        p.holes.push_back({m - e, {m.x - e.x, m.y + e.y}, m + e, {m.x + e.x, m.y - e.y}});
        if (i % 5 == 0) {
            GeoPolygon island;
            const glm::dvec2 f = s * 0.04;
            island.outer = {m - f, {m.x + f.x, m.y - f.y}, m + f, {m.x - f.x, m.y + f.y}};
            r.polygons.push_back(island);
        }
    }
    r.polygons.insert(r.polygons.begin(), std::move(p));
    return r;
}

std::string pad(size_t v, int width) {
    std::string s = std::to_string(v);
    return std::string(size_t(std::max(0, width - int(s.size()))), '0') + s;
}

}  // namespace

MapConvertReport generateFallbackMap(const std::string& outDir, uint32_t seed) {
    namespace fs = std::filesystem;
    const auto t0 = std::chrono::steady_clock::now();
    MapConvertReport rep;
    Random rnd(seed);
    fs::create_directories(fs::path(outDir) / "states");
    auto areasOf = [](const std::vector<GeoRegion>& rs) {
        std::vector<double> a;
        for (const auto& r : rs) a.push_back(regionArea(r));
        return a;
    };
    const GltfProperties generated{{{"source", "generated"}}, {{"seed", double(seed)}}};
    auto sceneProps = [&](std::map<std::string, std::string> s) {
        GltfProperties p = generated;
        p.strings.insert(s.begin(), s.end());
        return p;
    };

    std::vector<Cell> cells;
    splitBox({{-16000.0, -8000.0}, {16000.0, 8000.0}}, 40, rnd, cells);
    std::vector<GeoRegion> countries;
    for (size_t i = 0; i < cells.size(); ++i)
        countries.push_back(cellRegion(cells[i], i + 1, i == 7 ? "840" : pad(900 + i, 3),
                                       i == 7 ? "United States" : "Country " + std::to_string(i)));
    MapLevelOptions wo;
    wo.kind = "country";
    wo.height = 80.0;
    wo.children = {{"840", "us.glb"}};
    MapLevel wl = buildMapLevel(countries, areasOf(countries), wo);
    writeMapLevel(wl, (fs::path(outDir) / "world.glb").string(), sceneProps({{"level", "world"}}));
    accumulate(rep, wl, "world.glb");

    cells.clear();
    splitBox({{-2400.0, -1500.0}, {2400.0, 1500.0}}, 12, rnd, cells);
    std::vector<GeoRegion> states;
    MapLevelOptions so;
    so.kind = "state";
    so.height = 20.0;
    std::vector<Cell> stateCells = cells;
    for (size_t i = 0; i < stateCells.size(); ++i) {
        const std::string id = pad(i + 1, 2);
        states.push_back(cellRegion(stateCells[i], 1, id, "State " + id));  // states without lakes: counties tile them
        so.children[id] = "states/" + id + ".glb";
    }
    MapLevel sl = buildMapLevel(states, areasOf(states), so);
    writeMapLevel(sl, (fs::path(outDir) / "us.glb").string(), sceneProps({{"level", "us"}, {"parent", "840"}}));
    accumulate(rep, sl, "us.glb");

    MapLevelOptions co;
    co.kind = "county";
    co.height = 10.0;
    for (size_t i = 0; i < stateCells.size(); ++i) {
        const std::string sid = pad(i + 1, 2);
        cells.clear();
        splitBox(stateCells[i], 6 + int(rnd.uniform(0.0, 10.0)), rnd, cells);
        std::vector<GeoRegion> counties;
        for (size_t k = 0; k < cells.size(); ++k) {
            const std::string cid = sid + pad(2 * k + 1, 3);
            counties.push_back(cellRegion(cells[k], k + 1, cid, "County " + cid));
        }
        MapLevel cl = buildMapLevel(counties, areasOf(counties), co);
        const std::string file = "states/" + sid + ".glb";
        writeMapLevel(cl, (fs::path(outDir) / file).string(),
                      sceneProps({{"level", "state"}, {"parent", sid}, {"name", "State " + sid}}));
        accumulate(rep, cl, file);
    }
    rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return rep;
}

}  // namespace sg
