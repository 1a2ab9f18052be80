// The map's session drawn headless (OSMesa): script commands and their result lines, entering by zooming in,
// the picked region highlighted in the picture, and on the real data (when converted) the walk from the world to
// a Texas county.
#include "OutsideTools.h"
#include "map/MapTestData.h"
#include "map/OsmesaDisplay.h"
#include "map/Session.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

using namespace sgmap;
using namespace maptest;

namespace {

constexpr int kW = 320, kH = 180;

std::vector<std::string> run(Session& s, const std::string& script) {
    std::istringstream in(script);
    std::ostringstream out;
    s.runScript(in, out);
    std::vector<std::string> lines;
    std::istringstream back(out.str());
    for (std::string l; std::getline(back, l);) lines.push_back(l);
    return lines;
}

bool startsWith(const std::string& s, const std::string& p) { return s.compare(0, p.size(), p) == 0; }

size_t differingBytes(const sg::Image& a, const sg::Image& b) {
    size_t n = a.rgba.size() == b.rgba.size() ? 0 : a.rgba.size() + b.rgba.size();
    for (size_t i = 0; i < std::min(a.rgba.size(), b.rgba.size()); ++i) n += a.rgba[i] != b.rgba[i];
    return n;
}

// The RGB of pixel (x, y).
std::array<int, 3> pixel(const sg::Image& img, int x, int y) {
    const uint8_t* p = &img.rgba[size_t(4 * (y * img.width + x))];
    return {p[0], p[1], p[2]};
}

}  // namespace

TEST(MapSession, EachCommandPrintsOneResultLine) {
    Atlas atlas(generatedDir());
    OsmesaDisplay display(kW, kH);
    Session s(atlas, display, kW, kH);
    const std::vector<std::string> out = run(s,
                                             "# a comment\n"
                                             "\n"
                                             "enter 840\n"
                                             "pick 160 90\n"
                                             "enter 999\n"
                                             "zoom two\n"
                                             "fly away\n"
                                             "back\n"
                                             "back\n"
                                             "stats\n"
                                             "wait\n");
    ASSERT_EQ(out.size(), 9u);
    EXPECT_TRUE(startsWith(out[0], "us\t840\tUnited States\t")) << out[0];
    EXPECT_TRUE(startsWith(out[1], "state\t")) << out[1];  // the state under the centre, not the country
    EXPECT_TRUE(startsWith(out[2], "error\tno region with id 999")) << out[2];
    EXPECT_TRUE(startsWith(out[3], "error\tzoom: not a number")) << out[3];
    EXPECT_TRUE(startsWith(out[4], "error\tunknown command: fly")) << out[4];
    EXPECT_EQ(out[5], "world");
    EXPECT_TRUE(startsWith(out[6], "error\tat the world level")) << out[6];
    EXPECT_TRUE(startsWith(out[7], "level world\t")) << out[7];
    EXPECT_NE(out[7].find("loads 1\tunloads 1"), std::string::npos) << out[7];
    EXPECT_TRUE(startsWith(out[8], "idle\t")) << out[8];
}

TEST(MapSession, ExtremeViewsAndCountsLeaveTheMapUsable) {
    Atlas atlas(generatedDir());
    OsmesaDisplay display(kW, kH);
    Session s(atlas, display, kW, kH);
    for (const char* line : {"zoom 1e300", "pick 160 90", "goto 0 0 1e300", "pick 160 90", "goto 1e300 -1e300 100",
                             "pick 160 90", "zoom 1e-300", "pick 160 90"})
        EXPECT_FALSE(startsWith(s.command(line), "error")) << line;
    EXPECT_TRUE(std::isfinite(s.view().distance));
    EXPECT_LE(s.view().distance, MapView::kMaxDistance);
    EXPECT_TRUE(startsWith(s.command("frames 1e12"), "error\tframes: the count")) << "no endless loop";
    EXPECT_TRUE(startsWith(s.command("enter 840"), "us\t840")) << "the map still works";
}

TEST(MapSession, ZoomingInEntersTheRegionUnderTheCentre) {
    Atlas atlas(generatedDir());
    OsmesaDisplay display(kW, kH);
    Session s(atlas, display, kW, kH);
    const int us = atlas.level().findId("840");
    const sg::dvec3 p = insidePoint(atlas, size_t(us));
    std::ostringstream go;
    go << "goto " << p.x << " " << p.y << " 40000";
    EXPECT_FALSE(s.command(go.str()).empty());
    EXPECT_EQ(atlas.entering(), -1);  // from that high the country is small
    EXPECT_LT(s.coverage(us), 0.5);
    std::string line;
    int zooms = 0;
    while (atlas.entering() < 0 && zooms < 20) {
        line = s.command("zoom 1.25");
        ++zooms;
    }
    ASSERT_GE(atlas.entering(), 0) << line;
    EXPECT_NE(line.find("entering\tcountry\t840"), std::string::npos) << line;
    EXPECT_GT(s.coverage(us), 0.5);
    EXPECT_TRUE(startsWith(s.command("wait"), "idle")) << line;
    EXPECT_EQ(atlas.level().name, "us");
}

TEST(MapSession, ThePickedRegionIsDrawnHighlighted) {
    Atlas atlas(generatedDir());
    OsmesaDisplay display(kW, kH);
    Session s(atlas, display, kW, kH);
    s.overlay = false;
    ASSERT_TRUE(startsWith(s.command("enter 840"), "us\t840"));
    s.frame();
    const sg::Image before = display.read();
    const std::string picked = s.command("pick 160 90");
    ASSERT_TRUE(startsWith(picked, "state\t")) << picked;
    s.frame();
    const sg::Image after = display.read();
    // The region at the pick is drawn in the highlight (yellow) instead of its own colour; a region far from
    // it is drawn as before.
    const auto a = pixel(before, 160, 90), b = pixel(after, 160, 90);
    EXPECT_NE(a, b);
    EXPECT_GT(b[0], b[2] + 60);  // yellow: red and green well over blue
    EXPECT_GT(b[1], b[2] + 40);
    // Picking the sea clears it: the picture is the one before, pixel for pixel.
    EXPECT_EQ(s.command("pick 0 0"), "none");
    s.frame();
    const sg::Image cleared = display.read();
    EXPECT_EQ(differingBytes(cleared, before), 0u);
}

TEST(MapSession, AStatesCountiesAreDrawnAsOneMeshAndPickedOneByOne) {
    Atlas atlas(generatedDir());
    OsmesaDisplay display(kW, kH);
    Session s(atlas, display, kW, kH);
    s.overlay = false;
    ASSERT_TRUE(startsWith(s.command("enter 840"), "us\t840"));
    const size_t states = atlas.level().regions.size();
    ASSERT_TRUE(startsWith(s.command("enter 01"), "state\t01"));
    ASSERT_NE(atlas.level().merged, nullptr);
    const size_t counties = atlas.level().regions.size();
    ASSERT_GT(counties, 3u);
    s.frame();
    // The other states and the counties' one mesh: no county geometry is drawn on its own.
    EXPECT_LE(display.renderer().lastStats().instances, states);
    const sg::Image before = display.read();
    const std::string picked = s.command("pick 160 90");
    ASSERT_TRUE(startsWith(picked, "county\t01")) << picked;
    s.frame();
    const sg::Image after = display.read();
    const auto b = pixel(after, 160, 90);
    EXPECT_GT(b[0], b[2] + 60);  // the county under the pick drawn yellow
    EXPECT_GT(b[1], b[2] + 40);
    EXPECT_GT(differingBytes(after, before), 0u);
    EXPECT_EQ(s.command("pick 0 0"), "none");
    s.frame();
    const sg::Image cleared = display.read();
    EXPECT_EQ(differingBytes(cleared, before), 0u);
}

TEST(MapSession, RealDataFromTheWorldToATexasCounty) {
    if (!haveReal()) SG_SKIP_OR_FAIL("the real map is not converted (cmake --build <dir> --target map-data)");
    Atlas atlas(realDir());
    OsmesaDisplay display(kW, kH);
    Session s(atlas, display, kW, kH);
    const std::vector<std::string> out = run(s,
                                             "pickgeo -98.5 39.5\n"
                                             "pickgeo 2.35 48.85\n"
                                             "enter 840\n"
                                             "pickgeo -99.5 31.5\n"
                                             "pickgeo -149.9 61.2\n"
                                             "pickgeo -157.86 21.31\n"
                                             "pickgeo 2.35 48.85\n"
                                             "enter 48\n"
                                             "pickgeo -95.37 29.76\n"
                                             "pickgeo -97.74 30.27\n"
                                             "pickgeo -97.5 35.5\n"
                                             "back\n"
                                             "back\n");
    ASSERT_EQ(out.size(), 13u);
    EXPECT_TRUE(startsWith(out[0], "country\t840\t")) << out[0];
    EXPECT_EQ(out[1], "country\t250\tFrance");
    EXPECT_TRUE(startsWith(out[2], "us\t840\t")) << out[2];
    EXPECT_EQ(out[3], "state\t48\tTexas");
    EXPECT_EQ(out[4], "state\t02\tAlaska");  // Anchorage, on the inset
    EXPECT_EQ(out[5], "state\t15\tHawaii");  // Honolulu
    EXPECT_EQ(out[6], "none");               // France is not drawn inside the U.S.
    EXPECT_TRUE(startsWith(out[7], "state\t48\tTexas\t")) << out[7];
    EXPECT_EQ(out[8], "county\t48201\tHarris");
    EXPECT_EQ(out[9], "county\t48453\tTravis");
    EXPECT_EQ(out[10], "none");  // Oklahoma City: a state around Texas, not of this level
    EXPECT_EQ(out[11], "us\t840");
    EXPECT_EQ(out[12], "world");
}

// The map's levels drawn by the renderer's shader variants and by its one program: the same pixels (at most 1/255
// a channel), world, United States and a state's counties with a highlighted one.
TEST(MapSession, TheShaderVariantsDrawTheMapAsTheOneProgramDoes) {
    Atlas atlas(generatedDir());
    OsmesaDisplay display(kW, kH);
    Session s(atlas, display, kW, kH);
    s.overlay = false;
    const auto both = [&](const char* where) {
        display.renderer().setShaderMode(sg::Renderer::ShaderMode::OneProgram);
        s.frame();
        const sg::Image one = display.read();
        display.renderer().setShaderMode(sg::Renderer::ShaderMode::Variants);
        s.frame();
        const sg::Image variants = display.read();
        EXPECT_EQ(sg::countDifferingPixels(one, variants, 1), 0u) << where;
        EXPECT_GT(differingBytes(one, sg::Image{one.width, one.height, std::vector<uint8_t>(one.rgba.size())}), 0u);
    };
    both("world");
    ASSERT_TRUE(startsWith(s.command("enter 840"), "us\t840"));
    both("united states");
    ASSERT_TRUE(startsWith(s.command("enter 01"), "state\t01"));
    ASSERT_TRUE(startsWith(s.command("pick 160 90"), "county\t01"));
    both("a state's counties, one picked");
    EXPECT_GT(display.renderer().variantCount(), 0u);
}
