// The map projections: Equal Earth and Albers keep areas (a projected lon/lat cell against the sphere's
// formula), known values, the U.S. insets placed clear of the conterminous states, and rings crossing the
// antimeridian (decoded from TopoJSON) or going round a pole cut so that no piece spans the map.
#include "map/data/MapProjection.h"
#include "map/data/TopoJson.h"
#include "map/data/Triangulate.h"

#include <gtest/gtest.h>
#include <glm/common.hpp>

#include <cmath>

using namespace sg;

namespace {

constexpr double kR = MapProjection::kEarthRadiusKm;
constexpr double kDeg = M_PI / 180.0;

// The projected area of the cell [lon0, lon1] x [lat0, lat1], its edges sampled finely (meridians curve).
double cellArea(const MapProjection& p, double lon0, double lon1, double lat0, double lat1) {
    GeoRing r;
    const int n = 400;
    for (int k = 0; k < n; ++k) r.push_back(p.project(lon0 + (lon1 - lon0) * k / n, lat0));
    for (int k = 0; k < n; ++k) r.push_back(p.project(lon1, lat0 + (lat1 - lat0) * k / n));
    for (int k = 0; k < n; ++k) r.push_back(p.project(lon1 - (lon1 - lon0) * k / n, lat1));
    for (int k = 0; k < n; ++k) r.push_back(p.project(lon0, lat1 - (lat1 - lat0) * k / n));
    return std::abs(ringArea(r));
}
double sphereCell(double lon0, double lon1, double lat0, double lat1) {
    return kR * kR * (lon1 - lon0) * kDeg * (std::sin(lat1 * kDeg) - std::sin(lat0 * kDeg));
}

struct Box2 {
    glm::dvec2 lo{1e300}, hi{-1e300};
    void add(const glm::dvec2& p) { lo = glm::min(lo, p), hi = glm::max(hi, p); }
    bool intersects(const Box2& o) const {
        return lo.x <= o.hi.x && o.lo.x <= hi.x && lo.y <= o.hi.y && o.lo.y <= hi.y;
    }
};

Box2 bounds(const MapProjection& p, std::initializer_list<glm::dvec2> lonLat) {
    Box2 b;
    for (const auto& q : lonLat) b.add(p.project(q.x, q.y));
    return b;
}

}  // namespace

TEST(MapProjection, EqualEarthKeepsAreasAndKnownValues) {
    const MapProjection w = MapProjection::world();
    EXPECT_NEAR(glm::length(w.project(0, 0)), 0.0, 1e-9);
    // x at (180, 0): 2 sqrt(3) pi / (3 A1) R (the equator's half length).
    EXPECT_NEAR(w.project(180, 0).x, 2 * std::sqrt(3.0) * M_PI / (3 * 1.340264) * kR, 1e-6);
    EXPECT_NEAR(w.project(-180, 0).x, -w.project(180, 0).x, 1e-9);
    EXPECT_GT(w.project(0, 60).y, 0.0);
    for (double lat : {-75.0, -30.0, 0.0, 20.0, 55.0, 80.0}) {
        const double a = cellArea(w, 10, 13, lat, lat + 3), s = sphereCell(10, 13, lat, lat + 3);
        EXPECT_NEAR(a, s, 1e-5 * s) << "latitude " << lat;
    }
}

TEST(MapProjection, AlbersKeepsAreasOverTheUnitedStates) {
    const MapProjection us = MapProjection::usState("48");
    EXPECT_EQ(us.kind, MapProjection::Kind::Albers);
    EXPECT_EQ(us.parallel1, 29.5);
    EXPECT_EQ(us.parallel2, 45.5);
    EXPECT_NEAR(glm::length(us.project(-96, 37.5)), 0.0, 1e-9) << "the origin";
    for (const glm::dvec2 c : {glm::dvec2(-124, 45), glm::dvec2(-100, 30), glm::dvec2(-75, 40)}) {
        const double a = cellArea(us, c.x, c.x + 2, c.y, c.y + 2), s = sphereCell(c.x, c.x + 2, c.y, c.y + 2);
        EXPECT_NEAR(a, s, 1e-5 * s);
    }
    // Alaska is drawn at 0.35: its plane areas are 0.35^2 of the true ones.
    const MapProjection ak = MapProjection::usState("02");
    EXPECT_DOUBLE_EQ(ak.areaFactor(), 0.35 * 0.35);
    const double a = cellArea(ak, -150, -148, 62, 64) / ak.areaFactor(), s = sphereCell(-150, -148, 62, 64);
    EXPECT_NEAR(a, s, 1e-5 * s);
}

TEST(MapProjection, InsetsLieClearOfTheConterminousStatesAndOfEachOther) {
    // The southern conterminous states by a few extreme points each (the real data's test checks every state).
    const MapProjection l48 = MapProjection::usState("06");
    const Box2 south[] = {
        bounds(l48, {{-124.4, 42.0}, {-114.1, 34.3}, {-117.1, 32.5}}),                               // California
        bounds(l48, {{-114.8, 32.5}, {-109.0, 37.0}, {-109.0, 31.3}, {-103.0, 32.0}}),               // AZ, NM
        bounds(l48, {{-106.6, 32.0}, {-97.4, 25.8}, {-93.5, 29.7}, {-103.0, 36.5}, {-94.0, 33.6}}),  // Texas
        bounds(l48, {{-94.0, 33.0}, {-89.0, 29.0}, {-88.4, 30.2}, {-85.0, 31.0}}),                   // LA to AL
        bounds(l48, {{-87.6, 31.0}, {-80.0, 26.7}, {-81.8, 24.5}, {-80.0, 25.1}}),                   // Florida
    };
    struct Inset {
        const char* fips;
        std::initializer_list<glm::dvec2> extremes;
    };
    const Inset insets[] = {
        {"02", {{-141.0, 60.0}, {-141.0, 69.6}, {-156.8, 71.4}, {-168.1, 65.6}, {-179.1, 51.2}, {172.4, 52.9}}},
        {"15", {{-154.8, 19.5}, {-160.3, 22.0}, {-155.6, 18.9}}},
        {"72", {{-67.3, 18.4}, {-65.2, 18.3}, {-66.0, 17.9}}},
        {"66", {{144.6, 13.2}, {145.0, 13.7}, {145.9, 20.6}}},  // with the Northern Marianas (69)
        {"60", {{-170.9, -14.4}, {-168.1, -14.5}, {-169.4, -14.2}}},
    };
    std::vector<Box2> placed;
    for (const Inset& in : insets) {
        const Box2 b = bounds(MapProjection::usState(in.fips), in.extremes);
        for (const Box2& s : south) EXPECT_FALSE(b.intersects(s)) << in.fips << " overlaps a conterminous state";
        for (const Box2& o : placed) EXPECT_FALSE(b.intersects(o)) << in.fips << " overlaps another inset";
        placed.push_back(b);
    }
    EXPECT_EQ(MapProjection::usState("69").offset, MapProjection::usState("66").offset);
    EXPECT_EQ(MapProjection::usState("78").offset, MapProjection::usState("72").offset);
}

TEST(MapProjection, RingsAcrossTheAntimeridianAreCutThere) {
    // A TopoJSON island from 170E across 180 to 170W (arc in absolute coordinates), with a lake straddling 180.
    const char* text = R"({"type": "Topology", "objects": {"o": {"type": "GeometryCollection", "geometries": [
        {"type": "Polygon", "id": "242", "arcs": [[0], [1]]}]}},
        "arcs": [[[170, -20], [-170, -20], [-170, -10], [170, -10], [170, -20]],
                 [[178, -16], [178, -14], [-178, -14], [-178, -16], [178, -16]]]})";
    const GeoRegion r = parseTopoJson("fiji.json", text).at("o")[0];
    ASSERT_EQ(r.polygons[0].outer[1].x, -170.0) << "decoded as given";
    const MapProjection w = MapProjection::world();
    const GeoRegion cut = w.cutAtEdge(r);
    ASSERT_EQ(cut.polygons.size(), 2u) << "one piece each side of 180";
    const GeoRegion plane = w.projectRegion(r);
    const double width = 2 * w.project(180, 0).x;
    double area = 0.0;
    for (const GeoPolygon& p : plane.polygons) {
        double lo = p.outer[0].x, hi = lo;
        for (const auto& q : p.outer) lo = std::min(lo, q.x), hi = std::max(hi, q.x);
        EXPECT_LT(hi - lo, 0.05 * width) << "a piece spans the map";
        EXPECT_EQ(p.holes.size(), 1u) << "the lake is cut too";
        area += polygonArea(p);
    }
    // The island is 20 x 10 degrees less a 4 x 2 lake, on straight parallels (meridian edges sampled coarsely).
    const double expected = sphereCell(170, 190, -20, -10) - sphereCell(178, 182, -16, -14);
    EXPECT_NEAR(area, expected, 2e-3 * expected);
    // In the U.S. projection (centred at 96W) the same ring is not cut: 180 is far from its edge.
    EXPECT_EQ(MapProjection::usState("02").cutAtEdge(r).polygons.size(), 1u);
}

TEST(MapProjection, ARingAroundAPoleIsClosedAlongThePoleLine) {
    // Antarctica's shape: a ring along 80S all the way round, as the source gives it (no closing edge).
    GeoRegion r;
    GeoPolygon p;
    for (int lon = -180; lon < 180; lon += 10) p.outer.push_back({double(lon), -80.0});
    r.polygons.push_back(p);
    const MapProjection w = MapProjection::world();
    const GeoRegion plane = w.projectRegion(r);
    double area = 0.0;
    for (const auto& q : plane.polygons) area += polygonArea(q);
    const double cap = 2 * M_PI * kR * kR * (1 - std::sin(80 * kDeg));
    EXPECT_NEAR(area, cap, 1e-2 * cap);
}

TEST(MapProjection, APolygonAroundAPoleWithItsCoastAsAHoleIsTheBandBetweenThem) {
    // world-atlas's Antarctica, spherical: the outer ring a small circle at 89.999S, the coast (here 70S) a hole.
    GeoRegion r;
    GeoPolygon p;
    for (int lon = 180; lon > -180; lon -= 5) p.outer.push_back({double(lon), -89.999});
    GeoRing coast;
    for (int lon = -180; lon < 180; lon += 5) coast.push_back({double(lon), -70.0});
    p.holes.push_back(coast);
    r.polygons.push_back(p);
    const GeoRegion plane = MapProjection::world().projectRegion(r);
    double area = 0.0;
    for (const auto& q : plane.polygons) area += polygonArea(q);
    const double band = 2 * M_PI * kR * kR * (std::sin(89.999 * kDeg) - std::sin(70 * kDeg));
    EXPECT_NEAR(area, band, 1e-2 * band);
}

TEST(MapProjection, TheUnitedStatesProjectionAtAPointIsItsInsets) {
    auto same = [](const MapProjection& a, const MapProjection& b) {
        return a.lon0 == b.lon0 && a.lat0 == b.lat0 && a.scale == b.scale && a.offset == b.offset;
    };
    EXPECT_TRUE(same(MapProjection::usAt(-95.4, 29.8), MapProjection::usState("48"))) << "Houston";
    EXPECT_TRUE(same(MapProjection::usAt(-149.9, 61.2), MapProjection::usState("02"))) << "Anchorage";
    EXPECT_TRUE(same(MapProjection::usAt(173.2, 52.9), MapProjection::usState("02"))) << "Attu, west of 180";
    EXPECT_TRUE(same(MapProjection::usAt(-157.9, 21.3), MapProjection::usState("15"))) << "Honolulu";
    EXPECT_TRUE(same(MapProjection::usAt(-66.1, 18.4), MapProjection::usState("72"))) << "San Juan";
    EXPECT_TRUE(same(MapProjection::usAt(-64.9, 18.3), MapProjection::usState("78"))) << "Charlotte Amalie";
    EXPECT_TRUE(same(MapProjection::usAt(144.8, 13.5), MapProjection::usState("66"))) << "Hagatna";
    EXPECT_TRUE(same(MapProjection::usAt(145.7, 15.2), MapProjection::usState("69"))) << "Saipan";
    EXPECT_TRUE(same(MapProjection::usAt(-170.7, -14.3), MapProjection::usState("60"))) << "Pago Pago";
    EXPECT_TRUE(same(MapProjection::usAt(-122.3, 47.6), MapProjection::usState("53"))) << "Seattle";
}
