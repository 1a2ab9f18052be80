// The ear-clipping triangulator on the faults real boundary data has (slivers, repeated and collinear points,
// rings touching themselves and each other, holes touching the outer ring, clockwise input) and on random
// polygons with holes: the triangles' area equals the polygon's, every triangle turns counter-clockwise, and
// sample points inside the polygon are covered exactly once, points outside not at all.
#include "map/data/Triangulate.h"

#include <gtest/gtest.h>
#include <glm/common.hpp>

#include <cmath>
#include <random>

using namespace sg;

namespace {

using P = glm::dvec2;

double cross(const P& a, const P& b, const P& c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

std::vector<P> points(const GeoPolygon& p) {
    std::vector<P> v = p.outer;
    for (const auto& h : p.holes) v.insert(v.end(), h.begin(), h.end());
    return v;
}

bool insideRing(const GeoRing& r, const P& q) {
    bool in = false;
    for (size_t i = 0, j = r.size() - 1; i < r.size(); j = i++)
        if ((r[i].y > q.y) != (r[j].y > q.y) && q.x < (r[j].x - r[i].x) * (q.y - r[i].y) / (r[j].y - r[i].y) + r[i].x)
            in = !in;
    return in;
}
bool insidePolygon(const GeoPolygon& p, const P& q) {
    if (!insideRing(p.outer, q)) return false;
    for (const auto& h : p.holes)
        if (insideRing(h, q)) return false;
    return true;
}

// Area equality, orientation, and coverage at `samples` random points of the bounding box.
void expectExactCover(const GeoPolygon& poly, const std::string& what, int samples = 2000) {
    SCOPED_TRACE(what);
    const std::vector<uint32_t> t = triangulatePolygon(poly);
    const std::vector<P> v = points(poly);
    ASSERT_EQ(t.size() % 3, 0u);
    double sum = 0.0;
    for (size_t k = 0; k < t.size(); k += 3) {
        ASSERT_LT(t[k + 2], v.size());
        const double a = cross(v[t[k]], v[t[k + 1]], v[t[k + 2]]) / 2.0;
        EXPECT_GE(a, 0.0) << "triangle " << k / 3 << " turns clockwise";
        sum += a;
    }
    const double area = polygonArea(poly);
    ASSERT_GT(area, 0.0);
    EXPECT_NEAR(sum, area, 1e-9 * area);
    P lo = v[0], hi = v[0];
    for (const P& p : v) lo = glm::min(lo, p), hi = glm::max(hi, p);
    std::mt19937 rng(5);
    int wrong = 0;
    for (int s = 0; s < samples; ++s) {
        const P q(lo.x + (hi.x - lo.x) * (rng() / 4294967296.0), lo.y + (hi.y - lo.y) * (rng() / 4294967296.0));
        int cover = 0;
        for (size_t k = 0; k < t.size(); k += 3) {
            const P &a = v[t[k]], &b = v[t[k + 1]], &c = v[t[k + 2]];
            if (cross(a, b, q) > 0 && cross(b, c, q) > 0 && cross(c, a, q) > 0) ++cover;
        }
        if (cover != (insidePolygon(poly, q) ? 1 : 0)) ++wrong;
    }
    EXPECT_EQ(wrong, 0) << "sample points covered by the wrong number of triangles";
}

GeoRing square(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }
GeoRing reversed(GeoRing r) { return GeoRing(r.rbegin(), r.rend()); }

}  // namespace

TEST(Triangulate, SimpleConvexAndConcavePolygonsInEitherOrientation) {
    expectExactCover({square(0, 0, 1, 1), {}}, "square");
    expectExactCover({reversed(square(0, 0, 1, 1)), {}}, "clockwise square");
    // A comb: five teeth, reflex vertices between them.
    GeoRing comb{{0, 0}, {10, 0}, {10, 5}};
    for (int k = 4; k >= 0; --k) {
        comb.push_back({2.0 * k + 2, 5});
        comb.push_back({2.0 * k + 1.5, 9});
        comb.push_back({2.0 * k + 1, 5});
    }
    comb.push_back({0, 5});
    expectExactCover({comb, {}}, "comb");
    expectExactCover({reversed(comb), {}}, "clockwise comb");
}

TEST(Triangulate, HolesIncludingHolesTouchingTheOuterRingAndEachOther) {
    expectExactCover({square(0, 0, 10, 10), {square(2, 2, 4, 4), square(6, 6, 8, 8)}}, "two holes");
    expectExactCover({square(0, 0, 10, 10), {reversed(square(2, 2, 4, 4))}}, "counter-clockwise hole");
    // A hole whose corner lies on the outer ring's edge, and one sharing a vertex with the outer ring.
    expectExactCover({square(0, 0, 10, 10), {{{0, 5}, {3, 3}, {3, 7}}}}, "hole touching an edge");
    expectExactCover({square(0, 0, 10, 10), {{{10, 10}, {7, 8}, {8, 7}}}}, "hole touching a corner");
    // Two holes touching at a point.
    expectExactCover({square(0, 0, 10, 10), {square(2, 2, 5, 5), square(5, 5, 8, 8)}}, "holes touching");
    // Holes sharing an edge.
    expectExactCover({square(0, 0, 10, 10), {square(2, 2, 5, 5), square(5, 2, 8, 5)}}, "holes sharing an edge");
}

TEST(Triangulate, RepeatedAndCollinearPointsAndSlivers) {
    GeoRing r{{0, 0}, {0, 0}, {5, 0}, {10, 0}, {10, 0}, {10, 10}, {10, 10}, {5, 10}, {0, 10}, {0, 5}};
    expectExactCover({r, {}}, "repeated and collinear points");
    // A long sliver spike: a triangle 1e-7 wide on a square.
    GeoRing spike{{0, 0}, {1, 0}, {1, 0.5}, {100, 0.5 + 1e-7}, {1, 0.5 + 2e-7}, {1, 1}, {0, 1}};
    expectExactCover({spike, {}}, "sliver", 500);
    // A spike going straight out and back (zero width): no area, no triangle across the square.
    GeoRing back{{0, 0}, {1, 0}, {1, 0.5}, {3, 0.5}, {1, 0.5}, {1, 1}, {0, 1}};
    expectExactCover({back, {}}, "zero-width spike");
    // A thin polygon: a 1000:1 needle.
    expectExactCover({{{0, 0}, {1000, 0.5}, {1000, 1}, {0, 1}}, {}}, "needle", 500);
}

TEST(Triangulate, RingsTouchingThemselves) {
    // The outer ring visits (5,5) twice: two lobes meeting at a point (a pinch, not a crossing).
    GeoRing pinch{{0, 0}, {5, 5}, {10, 0}, {10, 10}, {5, 5}, {0, 10}};
    GeoPolygon p{pinch, {}};
    const auto t = triangulatePolygon(p);
    double sum = 0.0;
    const auto v = points(p);
    for (size_t k = 0; k < t.size(); k += 3) sum += cross(v[t[k]], v[t[k + 1]], v[t[k + 2]]) / 2.0;
    EXPECT_NEAR(sum, 50.0, 1e-9) << "two triangles of 25";
    // A keyhole: the outer ring runs in to enclose a lake through a zero-width channel.
    GeoRing keyhole{{0, 0}, {10, 0}, {10, 10}, {5, 10}, {5, 7},  {7, 7},
                    {7, 3}, {3, 3},  {3, 7},   {5, 7},  {5, 10}, {0, 10}};
    expectExactCover({keyhole, {}}, "keyhole");
}

TEST(Triangulate, SelfCrossingRingsAreSplitIntoLoops) {
    // A bow tie: the ring crosses itself at (5,5); its signed area is 0, its region two triangles of 25.
    const GeoPolygon bow{{{0, 0}, {10, 10}, {10, 0}, {0, 10}}, {}};
    EXPECT_NEAR(polygonArea(bow), 0.0, 1e-12);
    const auto parts = splitSelfCrossings(bow);
    ASSERT_EQ(parts.size(), 2u);
    double area = 0.0;
    for (const auto& p : parts) {
        area += polygonArea(p);
        expectExactCover(p, "bow-tie loop", 300);
    }
    EXPECT_NEAR(area, 50.0, 1e-9);
    // A ring without crossings comes back unchanged.
    const GeoPolygon sq{square(0, 0, 1, 1), {square(0.2, 0.2, 0.4, 0.4)}};
    const auto same = splitSelfCrossings(sq);
    ASSERT_EQ(same.size(), 1u);
    EXPECT_EQ(same[0].outer, sq.outer);
    EXPECT_EQ(same[0].holes.size(), 1u);
}

TEST(Triangulate, RandomStarPolygonsWithHoles) {
    std::mt19937 rng(11);
    auto u = [&] { return rng() / 4294967296.0; };
    for (int c = 0; c < 60; ++c) {
        GeoPolygon p;
        const int n = 5 + int(u() * 120);
        for (int k = 0; k < n; ++k) {
            const double a = 2 * M_PI * k / n, r = 50 + 50 * u();
            p.outer.push_back(
                {std::round(r * std::cos(a)), std::round(r * std::sin(a))});  // on a grid, like quantized data
        }
        // Holes inside the inner radius, on a ring of cells that do not overlap.
        const int holes = int(u() * 4);
        for (int h = 0; h < holes; ++h) {
            const double a = 2 * M_PI * h / 4 + 0.3, cx = 25 * std::cos(a), cy = 25 * std::sin(a);
            p.holes.push_back(square(std::round(cx - 5), std::round(cy - 5), std::round(cx + 5), std::round(cy + 5)));
        }
        GeoRing dedup;
        for (const auto& q : p.outer)
            if (dedup.empty() || dedup.back() != q) dedup.push_back(q);
        p.outer = dedup;
        expectExactCover(p, "random star " + std::to_string(c), 300);
    }
}
