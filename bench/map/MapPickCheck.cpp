// The source's answer for a point: each region's rings projected once by the region's own projection (cut at
// its edge), the point projected by the same one, the even-odd rule; the nearest border by segment distance.
#include "MapPickCheck.h"

#include "map/data/MapProjection.h"
#include "map/data/TopoJson.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <stdexcept>

namespace sgmap {
namespace {

using glm::dvec2;
using sg::GeoRegion;
using sg::GeoRing;
using sg::MapProjection;

constexpr double kPi = 3.14159265358979323846;

struct Box2 {
    dvec2 min{std::numeric_limits<double>::max()}, max{-std::numeric_limits<double>::max()};
    void expand(dvec2 p) { min = glm::min(min, p), max = glm::max(max, p); }
    bool contains(dvec2 p) const { return p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y; }
    double distance(dvec2 p) const { return glm::length(glm::max(glm::max(min - p, p - max), dvec2(0.0))); }
};

struct Ring {
    GeoRing points;
    Box2 box;
};

struct TruthRegion {
    std::string key;
    size_t projection = 0;
    std::vector<Ring> rings;
    Box2 box;
};

// Region keys: the id, or the name when the id is empty or shared (Australia and Ashmore share 036).
template <class R>
std::vector<std::string> keysOf(const std::vector<R>& regions) {
    std::map<std::string, int> count;
    for (const R& r : regions) ++count[r.id];
    std::vector<std::string> keys;
    for (const R& r : regions) keys.push_back(r.id.empty() || count[r.id] > 1 ? r.name : r.id);
    return keys;
}

class Truth {
public:
    Truth(const std::vector<GeoRegion>& source, MapProjection (*projectionOf)(const std::string& id)) {
        const auto keys = keysOf(source);
        std::map<std::string, size_t> byDescription;
        for (size_t i = 0; i < source.size(); ++i) {
            const MapProjection p = projectionOf(source[i].id);
            auto [it, added] = byDescription.emplace(p.describe(), projections_.size());
            if (added) projections_.push_back(p);
            TruthRegion t;
            t.key = keys[i];
            t.projection = it->second;
            for (const sg::GeoPolygon& poly : p.projectRegion(source[i]).polygons) {
                t.rings.push_back({poly.outer, {}});
                for (const GeoRing& h : poly.holes) t.rings.push_back({h, {}});
            }
            for (Ring& r : t.rings) {
                for (dvec2 q : r.points) r.box.expand(q);
                t.box.expand(r.box.min), t.box.expand(r.box.max);
            }
            extent_.expand(t.box.min), extent_.expand(t.box.max);
            regions_.push_back(std::move(t));
        }
    }

    // The larger side of the level's bounds (kilometres).
    double extentKm() const { return std::max(extent_.max.x - extent_.min.x, extent_.max.y - extent_.min.y); }

    // The keys of the regions holding the point, and its distance to the nearest border.
    std::vector<std::string> at(double lon, double lat, double& borderKm) const {
        std::vector<dvec2> q;
        for (const MapProjection& p : projections_) q.push_back(p.project(lon, lat));
        std::vector<std::string> in;
        double best = std::numeric_limits<double>::max();
        for (const TruthRegion& t : regions_) {
            const dvec2 p = q[t.projection];
            const bool inBox = t.box.contains(p);
            if (!inBox && t.box.distance(p) >= best) continue;
            bool odd = false;
            for (const Ring& r : t.rings) {
                const bool inRing = r.box.contains(p);
                if (!inRing && r.box.distance(p) >= best) continue;
                const size_t n = r.points.size();
                for (size_t i = 0, j = n - 1; i < n; j = i++) {
                    const dvec2 a = r.points[j], b = r.points[i];
                    if (inRing && (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x))
                        odd = !odd;
                    const dvec2 ab = b - a;
                    const double len2 = glm::dot(ab, ab);
                    const double s = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
                    best = std::min(best, glm::length(p - (a + s * ab)));
                }
            }
            if (odd) in.push_back(t.key);
        }
        borderKm = best;
        return in;
    }

private:
    std::vector<MapProjection> projections_;
    std::vector<TruthRegion> regions_;
    Box2 extent_;
};

MapProjection worldProjection(const std::string&) { return MapProjection::world(); }
MapProjection stateProjection(const std::string& id) { return MapProjection::usState(id.substr(0, 2)); }

// mt19937 is the same everywhere; the standard distributions are not.
class Random {
public:
    explicit Random(uint32_t seed) : g_(seed) {}
    double uniform(double a, double b) { return a + (b - a) * (double(g_()) / 4294967296.0); }

private:
    std::mt19937 g_;
};

// A longitude/latitude box; longitudes may pass 180 (Alaska's, taken about its projection's centre).
struct GeoBox {
    double lon0, lon1, lat0, lat1;
    double area() const { return (lon1 - lon0) * (lat1 - lat0); }
    bool contains(double lon, double lat) const {
        for (double l : {lon - 360.0, lon, lon + 360.0})
            if (l >= lon0 && l <= lon1 && lat >= lat0 && lat <= lat1) return true;
        return false;
    }
};

GeoBox boxOf(const GeoRegion& r, double lon0) {
    GeoBox b{1e9, -1e9, 1e9, -1e9};
    for (const sg::GeoPolygon& p : r.polygons)
        for (const dvec2& q : p.outer) {
            double l = q.x - lon0;
            while (l > 180.0) l -= 360.0;
            while (l < -180.0) l += 360.0;
            b.lon0 = std::min(b.lon0, l + lon0), b.lon1 = std::max(b.lon1, l + lon0);
            b.lat0 = std::min(b.lat0, q.y), b.lat1 = std::max(b.lat1, q.y);
        }
    return b;
}

double wrap180(double l) {
    while (l > 180.0) l -= 360.0;
    while (l < -180.0) l += 360.0;
    return l;
}

void enter(Atlas& atlas, const std::string& id) {
    const int index = atlas.level().findId(id);
    if (index < 0) throw std::runtime_error("checkMapPicks(): no region " + id + " at the " + atlas.level().name);
    if (std::string err = atlas.enter(size_t(index)); !err.empty())
        throw std::runtime_error("checkMapPicks(): entering " + id + ": " + err);
    for (uint64_t frame = 0;; ++frame) {
        const Atlas::Step s = atlas.update({frame, double(frame) / 60.0});
        if (s.entered) return;
        if (!s.error.empty()) throw std::runtime_error("checkMapPicks(): entering " + id + ": " + s.error);
        if (frame > 100000) throw std::runtime_error("checkMapPicks(): " + id + " never entered");
        atlas.pager().waitIdle();
    }
}

MapPickLevel run(Atlas& atlas, const std::string& name, const Truth& truth, const std::vector<dvec2>& points) {
    MapPickLevel out;
    out.level = name;
    out.pixelKm = truth.extentKm() / 1280.0;
    const auto keys = keysOf(atlas.level().regions);
    std::vector<int> got(points.size()), again(points.size());
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    for (size_t i = 0; i < points.size(); ++i) got[i] = atlas.pickGeo(points[i].x, points[i].y);
    const auto t1 = Clock::now();
    for (size_t i = 0; i < points.size(); ++i) again[i] = atlas.pickGeo(points[i].x, points[i].y);
    const auto t2 = Clock::now();
    out.msFirstPass = std::chrono::duration<double, std::milli>(t1 - t0).count();
    out.msPerPick =
        std::chrono::duration<double, std::milli>(t2 - t1).count() / double(std::max<size_t>(1, points.size()));
    if (again != got) throw std::runtime_error("checkMapPicks(): " + name + ": a second pick differs from the first");
    std::set<std::string> hit;
    for (size_t i = 0; i < points.size(); ++i) {
        MapPickMiss m{points[i].x, points[i].y, "none", got[i] < 0 ? "none" : keys[size_t(got[i])], 0.0};
        const auto in = truth.at(m.lon, m.lat, m.borderKm);
        if (!in.empty()) m.expected = in.front(), ++out.inRegion;
        const bool right = in.empty() ? got[i] < 0 : std::find(in.begin(), in.end(), m.got) != in.end();
        const bool near = m.borderKm < out.pixelKm;
        ++out.points;
        ++(near ? out.nearPoints : out.farPoints);
        if (right) ++(near ? out.nearCorrect : out.farCorrect);
        if (!in.empty()) hit.insert(in.front());
        if (!right && near) out.nearWrong.push_back(m);
        if (!right && !near && out.wrong.size() < 5) out.wrong.push_back(m);
    }
    out.regionsHit = int(hit.size());
    std::sort(out.nearWrong.begin(), out.nearWrong.end(),
              [](const MapPickMiss& a, const MapPickMiss& b) { return a.borderKm > b.borderKm; });
    if (out.nearWrong.size() > 5) out.nearWrong.resize(5);
    return out;
}

std::string jsonString(const std::string& s) {
    std::string o = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') o += '\\';
        o += c;
    }
    return o + "\"";
}

std::string jsonMisses(const std::vector<MapPickMiss>& misses) {
    std::string o = "[";
    for (const MapPickMiss& m : misses) {
        char buf[128];
        std::snprintf(buf, sizeof buf, "{\"lon\":%.5f,\"lat\":%.5f,\"border_km\":%.2f,", m.lon, m.lat, m.borderKm);
        o += (o.size() > 1 ? "," : "") + std::string(buf) + "\"expected\":" + jsonString(m.expected) +
             ",\"got\":" + jsonString(m.got) + "}";
    }
    return o + "]";
}

}  // namespace

std::string MapPickLevel::json() const {
    char buf[384];
    std::snprintf(buf, sizeof buf,
                  "\"points\":%d,\"far_points\":%d,\"far_correct\":%d,\"near_points\":%d,\"near_correct\":%d,"
                  "\"in_region\":%d,\"regions_hit\":%d,\"pixel_km\":%.3f,\"ms_first_pass\":%.1f,"
                  "\"ms_per_pick\":%.4f,",
                  points, farPoints, farCorrect, nearPoints, nearCorrect, inRegion, regionsHit, pixelKm, msFirstPass,
                  msPerPick);
    return "{\"level\":" + jsonString(level) + "," + buf + "\"wrong\":" + jsonMisses(wrong) +
           ",\"near_wrong\":" + jsonMisses(nearWrong) + "}";
}

std::vector<MapPickLevel> checkMapPicks(Atlas& atlas, const std::string& sourceDir, int points, uint32_t seed) {
    namespace fs = std::filesystem;
    if (atlas.generated() || atlas.depth() != 1)
        throw std::runtime_error("checkMapPicks(): the atlas must be at the world level of the real data");
    auto world = sg::readTopoJson((fs::path(sourceDir) / "countries-50m.json").string());
    auto us = sg::readTopoJson((fs::path(sourceDir) / "counties-10m.json").string());
    std::vector<MapPickLevel> out;
    Random rng(seed);

    // World: uniform on the sphere (the map is equal-area, so uniform on the map too).
    std::vector<dvec2> p;
    for (int i = 0; i < points; ++i) {
        const double lon = rng.uniform(-180.0, 180.0);
        p.push_back({lon, std::asin(rng.uniform(-1.0, 1.0)) * 180.0 / kPi});
    }
    out.push_back(run(atlas, "world", Truth(world["countries"], worldProjection), p));

    // The U.S.: half the points uniform in the union of the states' boxes (a box drawn by its area, a point
    // kept with the inverse of the number of boxes holding it), half in a box drawn uniformly, so that the
    // small insets (Guam, American Samoa, the Virgin Islands) get points too.
    const std::vector<GeoRegion>& states = us["states"];
    std::vector<GeoBox> boxes;
    double total = 0.0;
    for (const GeoRegion& s : states) total += boxes.emplace_back(boxOf(s, stateProjection(s.id).lon0)).area();
    p.clear();
    while (int(p.size()) < points) {
        const bool byArea = p.size() % 2 == 0;
        size_t b = std::min(boxes.size() - 1, size_t(rng.uniform(0.0, double(boxes.size()))));
        if (byArea) {
            double pick = rng.uniform(0.0, total);
            for (b = 0; b + 1 < boxes.size() && pick >= boxes[b].area(); ++b) pick -= boxes[b].area();
        }
        const double lon = wrap180(rng.uniform(boxes[b].lon0, boxes[b].lon1));
        const double lat = rng.uniform(boxes[b].lat0, boxes[b].lat1);
        int holding = 0;
        for (const GeoBox& g : boxes) holding += g.contains(lon, lat);
        if (!byArea || rng.uniform(0.0, 1.0) * std::max(1, holding) < 1.0) p.push_back({lon, lat});
    }
    enter(atlas, "840");
    out.push_back(run(atlas, "us", Truth(states, stateProjection), p));

    // Texas: its box; the points outside it are in no region of the level.
    std::vector<GeoRegion> counties;
    for (const GeoRegion& c : us["counties"])
        if (c.id.compare(0, 2, "48") == 0) counties.push_back(c);
    const auto texas = std::find_if(states.begin(), states.end(), [](const GeoRegion& s) { return s.id == "48"; });
    if (texas == states.end()) throw std::runtime_error("checkMapPicks(): no state 48 in the source");
    const GeoBox tb = boxOf(*texas, -96.0);
    p.clear();
    for (int i = 0; i < points; ++i) {
        const double lon = rng.uniform(tb.lon0, tb.lon1);
        p.push_back({lon, rng.uniform(tb.lat0, tb.lat1)});
    }
    enter(atlas, "48");
    out.push_back(run(atlas, "state 48", Truth(counties, stateProjection), p));

    atlas.back();
    atlas.back();
    return out;
}

}  // namespace sgmap
