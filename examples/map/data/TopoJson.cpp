// readTopoJson: the topology's arcs decoded once (delta decoding and the transform), then each
// GeometryCollection's polygons stitched from them.
#include "map/data/TopoJson.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

namespace sg {
namespace {

using nlohmann::json;

// GeometryCollections inside a region's geometry are read recursively: a file may not nest them deeper.
constexpr int kMaxNesting = 64;

struct Decoder {
    const std::string& file;
    std::vector<std::vector<glm::dvec2>> arcs;

    [[noreturn]] void bad(const std::string& path, const std::string& why) const { throw LoadError(file, path, why); }

    const json& member(const json& o, const char* key, const std::string& path) const {
        auto it = o.find(key);
        if (it == o.end()) bad(path, std::string("has no \"") + key + "\"");
        return *it;
    }
    const json& array(const json& v, const std::string& path) const {
        if (!v.is_array()) bad(path, "must be an array");
        return v;
    }
    double number(const json& v, const std::string& path) const {
        if (!v.is_number()) bad(path, "must be a number");
        const double d = v.get<double>();
        if (!std::isfinite(d)) bad(path, "must be finite");
        return d;
    }
    glm::dvec2 pair(const json& v, const std::string& path) const {
        if (!v.is_array() || v.size() < 2) bad(path, "must be an array of two numbers");
        return {number(v[0], path + "[0]"), number(v[1], path + "[1]")};
    }

    void decodeArcs(const json& topo) {
        bool quantized = false;
        glm::dvec2 scale{1.0}, translate{0.0};
        if (auto t = topo.find("transform"); t != topo.end()) {
            if (!t->is_object()) bad("transform", "must be an object");
            scale = pair(member(*t, "scale", "transform"), "transform.scale");
            translate = pair(member(*t, "translate", "transform"), "transform.translate");
            if (scale.x == 0.0 || scale.y == 0.0) bad("transform.scale", "must not be zero");
            quantized = true;
        }
        const json& a = array(member(topo, "arcs", ""), "arcs");
        arcs.resize(a.size());
        for (size_t i = 0; i < a.size(); ++i) {
            const std::string path = "arcs[" + std::to_string(i) + "]";
            const json& arc = array(a[i], path);
            if (arc.size() < 2) bad(path, "an arc needs at least two positions");
            auto& out = arcs[i];
            out.reserve(arc.size());
            glm::dvec2 q{0.0};
            for (size_t k = 0; k < arc.size(); ++k) {
                const glm::dvec2 p = pair(arc[k], path + "[" + std::to_string(k) + "]");
                q = quantized ? q + p : p;  // quantized arcs are delta-encoded
                const glm::dvec2 v = q * scale + translate;
                if (!std::isfinite(v.x) || !std::isfinite(v.y))
                    bad(path + "[" + std::to_string(k) + "]", "decodes to a non-finite position");
                out.push_back(v);
            }
        }
    }

    // A ring from arc indices; ~i (negative) is arc i reversed. Consecutive arcs share their end points.
    GeoRing ring(const json& indices, const std::string& path) const {
        array(indices, path);
        GeoRing r;
        for (size_t k = 0; k < indices.size(); ++k) {
            const std::string ip = path + "[" + std::to_string(k) + "]";
            if (!indices[k].is_number_integer()) bad(ip, "an arc index must be an integer");
            const long long i = indices[k].get<long long>();
            const long long a = i < 0 ? ~i : i;
            if (a >= (long long)arcs.size())
                bad(ip,
                    "arc index " + std::to_string(i) + " is out of range (" + std::to_string(arcs.size()) + " arcs)");
            const auto& arc = arcs[size_t(a)];
            const size_t n = arc.size();
            for (size_t j = 0; j < n; ++j) {
                const glm::dvec2& p = i < 0 ? arc[n - 1 - j] : arc[j];
                if (r.empty() || r.back() != p) r.push_back(p);
            }
        }
        while (r.size() > 1 && r.front() == r.back()) r.pop_back();
        return r;
    }

    GeoPolygon polygon(const json& rings, const std::string& path) const {
        array(rings, path);
        GeoPolygon p;
        for (size_t k = 0; k < rings.size(); ++k) {
            GeoRing r = ring(rings[k], path + "[" + std::to_string(k) + "]");
            if (r.size() < 3) continue;  // a ring without area adds nothing
            if (k == 0)
                p.outer = std::move(r);
            else
                p.holes.push_back(std::move(r));
        }
        return p;
    }

    void geometry(const json& g, const std::string& path, GeoRegion& region, int depth = 0) const {
        if (!g.is_object()) bad(path, "must be an object");
        if (depth > kMaxNesting) bad(path, "collections nested deeper than " + std::to_string(kMaxNesting));
        const json& type = member(g, "type", path);
        if (type.is_null()) return;  // a null geometry: a region without shape
        if (!type.is_string()) bad(path + ".type", "must be a string");
        const std::string t = type.get<std::string>();
        auto add = [&](GeoPolygon p) {
            if (!p.outer.empty()) region.polygons.push_back(std::move(p));
        };
        if (t == "Polygon") {
            add(polygon(member(g, "arcs", path), path + ".arcs"));
        } else if (t == "MultiPolygon") {
            const json& polys = array(member(g, "arcs", path), path + ".arcs");
            for (size_t k = 0; k < polys.size(); ++k) add(polygon(polys[k], path + ".arcs[" + std::to_string(k) + "]"));
        } else if (t == "GeometryCollection") {
            const json& gs = array(member(g, "geometries", path), path + ".geometries");
            for (size_t k = 0; k < gs.size(); ++k)
                geometry(gs[k], path + ".geometries[" + std::to_string(k) + "]", region, depth + 1);
        } else if (t != "Point" && t != "MultiPoint" && t != "LineString" && t != "MultiLineString") {
            bad(path + ".type", "unknown geometry type '" + t + "'");
        }
    }

    GeoRegion region(const json& g, const std::string& path) const {
        GeoRegion r;
        if (!g.is_object()) bad(path, "must be an object");
        if (auto id = g.find("id"); id != g.end()) {
            if (id->is_string())
                r.id = id->get<std::string>();
            else if (id->is_number_integer())
                r.id = std::to_string(id->get<long long>());
            else if (id->is_number())
                r.id = json(id->get<double>()).dump();
            else if (!id->is_null())
                bad(path + ".id", "must be a string or a number");
        }
        if (auto props = g.find("properties"); props != g.end() && !props->is_null()) {
            if (!props->is_object()) bad(path + ".properties", "must be an object");
            if (auto name = props->find("name"); name != props->end() && !name->is_null()) {
                if (!name->is_string()) bad(path + ".properties.name", "must be a string");
                r.name = name->get<std::string>();
            }
        }
        geometry(g, path, r);
        return r;
    }
};

}  // namespace

std::map<std::string, std::vector<GeoRegion>> parseTopoJson(const std::string& name, const std::string& text) {
    json topo;
    try {
        topo = json::parse(text);
    } catch (const json::exception& e) {
        throw LoadError(name, "", std::string("not valid JSON: ") + e.what());
    }
    Decoder d{name, {}};
    if (!topo.is_object()) d.bad("", "a topology must be a JSON object");
    const json& type = d.member(topo, "type", "");
    if (!type.is_string() || type.get<std::string>() != "Topology") d.bad("type", "must be \"Topology\"");
    d.decodeArcs(topo);
    const json& objects = d.member(topo, "objects", "");
    if (!objects.is_object()) d.bad("objects", "must be an object");
    std::map<std::string, std::vector<GeoRegion>> out;
    for (auto it = objects.begin(); it != objects.end(); ++it) {
        const std::string path = "objects." + it.key();
        const json& o = it.value();
        if (!o.is_object()) d.bad(path, "must be an object");
        auto t = o.find("type");
        if (t == o.end() || !t->is_string() || t->get<std::string>() != "GeometryCollection") continue;
        const json& gs = d.array(d.member(o, "geometries", path), path + ".geometries");
        auto& regions = out[it.key()];
        regions.reserve(gs.size());
        for (size_t k = 0; k < gs.size(); ++k)
            regions.push_back(d.region(gs[k], path + ".geometries[" + std::to_string(k) + "]"));
    }
    return out;
}

std::map<std::string, std::vector<GeoRegion>> readTopoJson(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw LoadError(path, "", "cannot be opened");
    std::ostringstream s;
    s << in.rdbuf();
    return parseTopoJson(path, s.str());
}

}  // namespace sg
