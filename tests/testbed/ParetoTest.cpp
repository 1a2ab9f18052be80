// sgbench pareto's core on a tiny office: the front on hand-made points, the invariants of a measured table (the
// reference and the conservative methods exact, a method that culls everything caught), the CSV's columns.
#include "sg/gl/OsmesaContext.h"
#include "testbed/City.h"
#include "testbed/Office.h"
#include "testbed/Pareto.h"

#include <gtest/gtest.h>

#include <sstream>

namespace {

size_t fields(const std::string& line) {
    size_t n = 1;
    for (char c : line) n += c == ',';
    return n;
}

TEST(ParetoFront, HandMadePoints) {
    //                 a    b    c    d    e    f    g
    const std::vector<double> t = {10, 5, 6, 7, 5, 12, 6};
    const std::vector<double> e = {0, 100, 50, 100, 100, 0, 50};
    const std::vector<bool> on = pareto::paretoFront(t, e);
    // d: b is faster and as wrong; f: a is faster and as exact. b and e tie (neither is faster), so do c and g.
    EXPECT_EQ(on, (std::vector<bool>{true, true, true, false, true, false, true}));
    EXPECT_EQ(pareto::paretoFront({}, {}), std::vector<bool>{});
    EXPECT_THROW(pareto::paretoFront({1, 2}, {1}), std::invalid_argument);
}

TEST(ParetoFront, MarksPerSceneAndNamesWhatBeatsTheDefault) {
    std::vector<pareto::Row> rows(4);
    rows[0] = {"a", "fast"};
    rows[0].frameMs = 1;
    rows[1] = {"a", "default"};
    rows[1].isDefault = true;
    rows[1].frameMs = 2;
    rows[2] = {"b", "default"};  // another scene: "fast" on scene a does not beat it
    rows[2].isDefault = true;
    rows[2].frameMs = 2;
    rows[3] = {"b", "slow"};
    rows[3].frameMs = 3;
    pareto::markFront(rows);
    EXPECT_TRUE(rows[0].onFront);
    EXPECT_FALSE(rows[1].onFront);
    EXPECT_TRUE(rows[2].onFront);
    EXPECT_FALSE(rows[3].onFront);
    const std::vector<pareto::OffFront> off = pareto::defaultOffFront(rows, 0.05);
    ASSERT_EQ(off.size(), 1u);
    EXPECT_EQ(off[0].scene, "a");
    EXPECT_TRUE(off[0].beyondNoise);  // 1 ms against 2
    EXPECT_NE(off[0].text.find("a: the default"), std::string::npos) << off[0].text;
    EXPECT_NE(off[0].text.find("fast"), std::string::npos) << off[0].text;
    EXPECT_FALSE(pareto::defaultOffFront(rows, 0.6)[0].beyondNoise);  // 50% faster is within a 60% tolerance
    // Frame by frame: "fast" wins the medians by half but loses on most frames (the views' costs cancel).
    rows[0].frames = {1, 10, 10, 10};
    rows[1].frames = {9, 9, 9, 9};
    const std::vector<pareto::OffFront> paired = pareto::defaultOffFront(rows, 0.05);
    ASSERT_EQ(paired.size(), 1u);
    EXPECT_FALSE(paired[0].beyondNoise) << paired[0].text;
    EXPECT_NE(paired[0].text.find("faster in 1 of 4"), std::string::npos) << paired[0].text;
}

TEST(ParetoMethods, SelectsByNameAndRejectsUnknown) {
    const auto all = pareto::methods();
    const auto some = pareto::selectMethods(all, "hom,none");
    ASSERT_EQ(some.size(), 2u);
    EXPECT_EQ(some[0].name, "none");  // the table's order
    EXPECT_EQ(some[1].name, "hom");
    EXPECT_EQ(pareto::selectMethods(all, "").size(), all.size());
    try {
        pareto::selectMethods(all, "none,spheres");
        FAIL() << "no throw";
    } catch (const std::invalid_argument& ex) {
        EXPECT_NE(std::string(ex.what()).find("'spheres'"), std::string::npos) << ex.what();
    }
    int defaults = 0;
    for (const auto& m : all) defaults += m.isDefault;
    EXPECT_EQ(defaults, 1);
    // The occlusion queries' row: a frame late, so not conservative.
    const auto q = pareto::selectMethods(all, "gpu-query");
    ASSERT_EQ(q.size(), 1u);
    EXPECT_TRUE(q[0].gpuQueries);
    EXPECT_FALSE(q[0].conservative);
    EXPECT_EQ(q[0].cull.strategy, sg::CullStrategy::Aabb);
}

TEST(Pareto, TinyOfficeInvariantsAndCsv) {
    const int w = 160, h = 90;
    sg::OsmesaContext ctx(w, h);
    sg::Renderer renderer;
    sg::Scene scene(scenes::buildOffice(2));
    scene.update();
    pareto::SceneViews sv;
    sv.name = "office-2";
    sv.scene = &scene;
    for (int f : {0, 80, 160}) sv.views.push_back(scenes::officeWalkCamera(2, f, w, h));
    std::vector<pareto::Method> methods = pareto::methods();
    // Culls every geometry: the error measures must see it.
    pareto::Method everything{"cull-everything", {}, sg::LodPolicy::Static, false, false, false, false};
    everything.cull.smallFeaturePixels = 1e6;
    methods.push_back(everything);
    const std::vector<pareto::Row> rows = pareto::measure(renderer, sv, methods, pareto::Options{});

    size_t lodOnly = 0;
    for (const auto& m : methods) lodOnly += m.needsLods;
    ASSERT_EQ(rows.size(), methods.size() - lodOnly);  // the office has no LODs
    double noneObjects = 0;
    for (const pareto::Row& r : rows) {
        EXPECT_EQ(r.views, 3);
        EXPECT_GT(r.frameMs, 0.0) << r.method;
        EXPECT_GE(r.frameMs, r.cullMs) << r.method;
        if (r.method == "none") {
            noneObjects = r.objects;
            EXPECT_DOUBLE_EQ(r.frameRatio, 1.0);
        }
        if (r.conservative) {
            EXPECT_EQ(r.errorPixels, 0.0) << r.method;
            EXPECT_EQ(r.wronglyCulledTotal, 0u) << r.method;
        }
    }
    ASSERT_GT(noneObjects, 0.0);
    for (const pareto::Row& r : rows) EXPECT_LE(r.objects, noneObjects) << r.method;
    const pareto::Row& all = rows.back();
    ASSERT_EQ(all.method, "cull-everything");
    EXPECT_EQ(all.objects, 0.0);
    EXPECT_GT(all.errorPercent, 10.0);
    EXPECT_GE(all.wronglyCulled, 3.0);  // at least walls, floor and some furniture in every view
    EXPECT_EQ(all.viewsWithError, 3);

    std::istringstream csv(pareto::csv(rows));
    std::string line;
    ASSERT_TRUE(std::getline(csv, line));
    EXPECT_EQ(line, pareto::csvHeader());
    EXPECT_EQ(fields(line), 20u);
    for (const char* col :
         {"scene", "method", "frame_ms_median", "error_pixels_mean", "wrongly_culled_mean", "on_front"})
        EXPECT_NE(line.find(col), std::string::npos) << col;
    size_t n = 0;
    while (std::getline(csv, line)) {
        EXPECT_EQ(fields(line), 20u) << line;
        EXPECT_EQ(line.rfind("office-2,", 0), 0u) << line;
        ++n;
    }
    EXPECT_EQ(n, rows.size());
    const std::string md = pareto::markdown(rows);
    EXPECT_NE(md.find("### office-2 (3 views at 160x90"), std::string::npos) << md;
    const std::string gp = pareto::gnuplotScript(rows, "x.png");
    EXPECT_NE(gp.find("set output 'x.png'"), std::string::npos);
}

// Far from a small city every building is drawn at its coarse level: another mesh at the same place, which the
// error counts in pixels but not as a wrongly culled geometry.
TEST(Pareto, CoarseLevelsAreNotWronglyCulled) {
    const int w = 160, h = 90;
    sg::OsmesaContext ctx(w, h);
    sg::Renderer renderer;
    sg::Scene scene(scenes::buildCity({3, false}));
    scene.update();
    pareto::SceneViews sv;
    sv.name = "city-3";
    sv.scene = &scene;
    sv.hasLods = true;
    sg::Camera cam;
    cam.setPerspective(20, double(w) / h, 1, 3000);
    cam.setLookAt(sg::dvec3(30, -400, 100), sg::dvec3(30, 30, 0), sg::dvec3(0, 0, 1));
    cam.setViewport(w, h);
    sv.views = {cam};
    const auto rows = pareto::measure(renderer, sv, pareto::selectMethods(pareto::methods(), "none,aabb"), {});
    ASSERT_EQ(rows.size(), 2u);
    for (const pareto::Row& r : rows) {
        EXPECT_EQ(r.objects, 18.0) << r.method;         // 9 buildings, 9 cars
        EXPECT_EQ(r.triangles, 18.0 * 12) << r.method;  // every building at its 12-triangle level
        EXPECT_EQ(r.wronglyCulledTotal, 0u) << r.method;
    }
}

// Along a street of a small city the buildings hide most of the others: from the second view on (the first has no
// answer yet) the queries leave out what the frustum alone draws, with their own state from view to view.
TEST(Pareto, GpuQueriesDrawFewerTrianglesThanTheFrustum) {
    const int w = 160, h = 90, n = 6;
    sg::OsmesaContext ctx(w, h);
    sg::Renderer renderer;
    sg::Scene scene(scenes::buildCity({n, false}));
    scene.update();
    pareto::SceneViews sv;
    sv.name = "city-6";
    sv.scene = &scene;
    sv.hasLods = true;
    sv.views = {scenes::cityStreetCamera(n, 40, w, h), scenes::cityStreetCamera(n, 41, w, h),
                scenes::cityStreetCamera(n, 42, w, h)};
    const auto rows = pareto::measure(renderer, sv, pareto::selectMethods(pareto::methods(), "aabb,gpu-query"), {});
    ASSERT_EQ(rows.size(), 2u);
    const pareto::Row& aabb = rows[0];
    const pareto::Row& gpu = rows[1];
    ASSERT_EQ(aabb.method, "aabb");
    ASSERT_EQ(gpu.method, "gpu-query");
    EXPECT_FALSE(gpu.conservative);
    EXPECT_LT(gpu.triangles, aabb.triangles);
    EXPECT_LT(gpu.objects, aabb.objects);
    EXPECT_GT(gpu.queries, 0.0);
    EXPECT_EQ(aabb.queries, 0.0);
    // Every view's items are queried: those in the frustum.
    EXPECT_LE(gpu.queries, aabb.objects);
}

}  // namespace
