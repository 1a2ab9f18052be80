// Equal Earth (Šavrič, Patterson, Jenny 2018) and Albers equal-area conic on the authalic sphere, and the
// antimeridian cut done on unwrapped longitudes before projecting.
#include "map/data/MapProjection.h"

#include "map/data/Triangulate.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace sg {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

double wrap180(double l) {
    while (l > 180.0) l -= 360.0;
    while (l < -180.0) l += 360.0;
    return l;
}

// Sutherland-Hodgman against x <= c (keepBelow) or x >= c: exact for the area a convex cut leaves.
GeoRing clip(const GeoRing& r, double c, bool keepBelow) {
    GeoRing out;
    const size_t n = r.size();
    auto in = [&](const glm::dvec2& p) { return keepBelow ? p.x <= c : p.x >= c; };
    for (size_t i = 0; i < n; ++i) {
        const glm::dvec2& cur = r[i];
        const glm::dvec2& prev = r[(i + n - 1) % n];
        const bool ci = in(cur), pi = in(prev);
        if (ci != pi) {
            const double t = (c - prev.x) / (cur.x - prev.x);
            out.push_back({c, prev.y + t * (cur.y - prev.y)});
        }
        if (ci) out.push_back(cur);
    }
    GeoRing dedup;
    for (const auto& p : out)
        if (dedup.empty() || dedup.back() != p) dedup.push_back(p);
    while (dedup.size() > 1 && dedup.front() == dedup.back()) dedup.pop_back();
    return dedup;
}

// True when the ring turns once around a pole (its longitude steps, each taken the short way, add to 360).
bool aroundPole(const GeoRing& ring) {
    double turn = 0.0;
    for (size_t i = 0; i < ring.size(); ++i) {
        double d = ring[(i + 1) % ring.size()].x - ring[i].x;
        while (d > 180.0) d -= 360.0;
        while (d < -180.0) d += 360.0;
        turn += d;
    }
    return std::abs(turn) > 180.0;
}

double meanLatitude(const GeoRing& ring) {
    double m = 0.0;
    for (const auto& p : ring) m += p.y;
    return ring.empty() ? 0.0 : m / double(ring.size());
}

// Longitudes relative to lon0, made continuous along the ring (a step over 180 degrees is a crossing of
// the edge). Returns true when the ring needed it. A ring around a pole is closed along the latitude
// `closeAt` (the pole when NaN: the pole is a line in the projections here).
bool unwrap(const GeoRing& ring, double lon0, GeoRing& out, double closeAt = std::nan("")) {
    out.clear();
    out.reserve(ring.size() + 4);
    double shift = 0.0, prev = 0.0;
    bool moved = false;
    for (size_t i = 0; i < ring.size(); ++i) {
        const double l = wrap180(ring[i].x - lon0);
        if (i > 0) {
            if (l + shift - prev > 180.0) shift -= 360.0, moved = true;
            if (l + shift - prev < -180.0) shift += 360.0, moved = true;
        }
        prev = l + shift;
        out.push_back({prev, ring[i].y});
    }
    if (out.empty()) return false;
    // The closing edge: a net turn of 360 degrees means the ring goes around a pole.
    const double first = out.front().x;
    double close = first;
    while (close - prev > 180.0) close -= 360.0;
    while (close - prev < -180.0) close += 360.0;
    if (close != first) {
        const double pole = std::isnan(closeAt) ? (meanLatitude(ring) < 0.0 ? -90.0 : 90.0) : closeAt;
        const double lat = out.front().y;
        out.push_back({close, lat});
        out.push_back({close, pole});
        out.push_back({first, pole});
        moved = true;
    }
    return moved;
}

}  // namespace

MapProjection MapProjection::world() { return MapProjection{}; }

MapProjection MapProjection::usState(const std::string& fips) {
    MapProjection p;
    p.kind = Kind::Albers;
    auto set = [&](double lon0, double lat0, double p1, double p2, double scale, glm::dvec2 offset) {
        p.lon0 = lon0, p.lat0 = lat0, p.parallel1 = p1, p.parallel2 = p2, p.scale = scale, p.offset = offset;
    };
    // Insets below the conterminous states (which reach x -2350..2250 km, y -1343 km at Key West): Alaska
    // under California and Arizona, Hawaii and American Samoa beside it, Guam and the Northern Marianas in the
    // Gulf of Mexico, Puerto Rico and the Virgin Islands south of Florida.
    if (fips == "02")
        set(-154.0, 50.0, 55.0, 65.0, 0.35, {-1650.0, -1850.0});
    else if (fips == "15")
        set(-157.0, 3.0, 8.0, 18.0, 1.0, {-650.0, -3650.0});
    else if (fips == "60")
        set(-170.0, -14.0, -14.5, -14.0, 1.0, {-200.0, -1600.0});
    else if (fips == "66" || fips == "69")
        set(145.5, 15.0, 13.0, 20.0, 1.0, {400.0, -1650.0});
    else if (fips == "72" || fips == "78")
        set(-66.0, 18.0, 17.5, 18.5, 1.0, {1700.0, -1550.0});
    else
        set(-96.0, 37.5, 29.5, 45.5, 1.0, {0.0, 0.0});
    return p;
}

MapProjection MapProjection::usAt(double lon, double lat) {
    lon = wrap180(lon);
    auto in = [&](double lon0, double lon1, double lat0, double lat1) {
        return lon >= lon0 && lon <= lon1 && lat >= lat0 && lat <= lat1;
    };
    if (lat > 50.0 && (lon < -129.0 || lon > 170.0)) return usState("02");
    if (in(-179.0, -154.0, 18.0, 29.0)) return usState("15");
    if (in(-68.0, -64.0, 17.0, 19.0)) return usState("72");
    if (in(144.0, 147.0, 13.0, 21.0)) return usState("66");
    if (in(-172.0, -168.0, -15.0, -10.0)) return usState("60");
    return usState("48");
}

glm::dvec2 MapProjection::project(double lonDegrees, double latDegrees) const {
    return projectRelative(wrap180(lonDegrees - lon0), latDegrees);
}

glm::dvec2 MapProjection::projectRelative(double dLonDegrees, double latDegrees) const {
    const double lambda = dLonDegrees * kDeg;
    const double phi = std::clamp(latDegrees, -90.0, 90.0) * kDeg;
    const double R = kEarthRadiusKm;
    glm::dvec2 xy;
    if (kind == Kind::EqualEarth) {
        constexpr double A1 = 1.340264, A2 = -0.081106, A3 = 0.000893, A4 = 0.003796;
        const double theta = std::asin(std::sqrt(3.0) / 2.0 * std::sin(phi));
        const double t2 = theta * theta, t6 = t2 * t2 * t2;
        xy.x = 2.0 * std::sqrt(3.0) * lambda * std::cos(theta) /
               (3.0 * (9.0 * A4 * t6 * t2 + 7.0 * A3 * t6 + 3.0 * A2 * t2 + A1));
        xy.y = theta * (A1 + A2 * t2 + t6 * (A3 + A4 * t2));
        xy *= R;
    } else {
        const double p1 = parallel1 * kDeg, p2 = parallel2 * kDeg, p0 = lat0 * kDeg;
        const double n = (std::sin(p1) + std::sin(p2)) / 2.0;
        const double C = std::cos(p1) * std::cos(p1) + 2.0 * n * std::sin(p1);
        const double rho0 = R * std::sqrt(std::max(0.0, C - 2.0 * n * std::sin(p0))) / n;
        const double rho = R * std::sqrt(std::max(0.0, C - 2.0 * n * std::sin(phi))) / n;
        const double th = n * lambda;
        xy = {rho * std::sin(th), rho0 - rho * std::cos(th)};
    }
    return xy * scale + offset;
}

GeoRegion MapProjection::cutAtEdge(const GeoRegion& in) const {
    GeoRegion out;
    out.id = in.id;
    out.name = in.name;
    GeoRing u;
    for (const GeoPolygon& given : in.polygons) {
        // Spherical polygons around a pole (world-atlas's Antarctica): the outer ring a small circle about the
        // pole, the coast a hole in it, the region between them. In the plane, that is the coast closed along
        // the small circle's latitude.
        const GeoPolygon* poly = &given;
        GeoPolygon polar;
        double closeAt = std::nan("");
        if (aroundPole(given.outer)) {
            for (size_t k = 0; k < given.holes.size(); ++k)
                if (aroundPole(given.holes[k])) {
                    polar.outer = given.holes[k];
                    for (size_t j = 0; j < given.holes.size(); ++j)
                        if (j != k) polar.holes.push_back(given.holes[j]);
                    closeAt = meanLatitude(given.outer);
                    poly = &polar;
                    break;
                }
        }
        bool cut = unwrap(poly->outer, lon0, u, closeAt);
        GeoPolygon rel{u, {}};
        for (const GeoRing& h : poly->holes) {
            cut = unwrap(h, lon0, u) || cut;
            // Put the hole on the same turn as its outer ring.
            const double d = std::round((rel.outer.front().x - u.front().x) / 360.0) * 360.0;
            for (auto& p : u) p.x += d;
            rel.holes.push_back(u);
        }
        double lo = rel.outer.front().x, hi = lo;
        for (const auto& p : rel.outer) lo = std::min(lo, p.x), hi = std::max(hi, p.x);
        if (!cut && lo >= -180.0 && hi <= 180.0) {
            out.polygons.push_back(std::move(rel));
            continue;
        }
        // One piece per turn of the globe the unwrapped ring reaches, shifted back into [-180, 180].
        for (int k = int(std::floor((lo + 180.0) / 360.0)); k <= int(std::floor((hi + 180.0) / 360.0)); ++k) {
            const double a = -180.0 + 360.0 * k, b = 180.0 + 360.0 * k;
            auto piece = [&](const GeoRing& r) {
                GeoRing c = clip(clip(r, a, false), b, true);
                for (auto& p : c) p.x -= 360.0 * k;
                return c;
            };
            GeoRing o = piece(rel.outer);
            if (o.size() < 3 || ringArea(o) == 0.0) continue;  // the ring only touches this side's edge
            GeoPolygon pp{std::move(o), {}};
            for (const auto& h : rel.holes) {
                GeoRing c = piece(h);
                if (c.size() >= 3) pp.holes.push_back(std::move(c));
            }
            out.polygons.push_back(std::move(pp));
        }
    }
    return out;
}

GeoRegion MapProjection::projectRegion(const GeoRegion& lonLat) const {
    GeoRegion r = cutAtEdge(lonLat);
    auto plain = [&](GeoRing& ring) {
        for (auto& p : ring) p = projectRelative(p.x, p.y);
    };
    for (auto& poly : r.polygons) {
        plain(poly.outer);
        for (auto& h : poly.holes) plain(h);
    }
    return r;
}

std::string MapProjection::describe() const {
    std::ostringstream s;
    if (kind == Kind::EqualEarth)
        s << "equal-earth lon0=" << lon0;
    else
        s << "albers lon0=" << lon0 << " lat0=" << lat0 << " parallels=" << parallel1 << "," << parallel2;
    s << " scale=" << scale << " offset=" << offset.x << "," << offset.y;
    return s.str();
}

}  // namespace sg
