// The accuracy harness on `city`, `office` and random graphs: every conservative strategy (and the
// occlusion pass with its conservative cap, tree or map) draws exactly the pixels of the unculled render on every view;
// the approximate ones report their error.
#include "Scaled.h"
#include "nodes/Transform.h"
#include "testbed/Accuracy.h"
#include "testbed/City.h"
#include "testbed/Office.h"
#include "testbed/RandomScene.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

using namespace sg;

namespace {
constexpr int kW = 256, kH = 144, kViews = testutil::scaled(200);

std::vector<CullSettings> strategies() {
    std::vector<CullSettings> s;
    for (auto st : {CullStrategy::Sphere, CullStrategy::Aabb, CullStrategy::SphereSphere, CullStrategy::CenterBox}) {
        CullSettings c;
        c.strategy = st;
        c.occlusion.mode = OcclusionMode::Off;  // the frustum strategies alone (the occlusion tests are below)
        s.push_back(c);
    }
    CullSettings sf;
    sf.smallFeaturePixels = 2.0;
    sf.occlusion.mode = OcclusionMode::Off;
    s.push_back(sf);
    return s;
}

void check(const std::vector<accuracy::Result>& results, const char* scene) {
    for (const auto& r : results) {
        std::printf(
            "[ accuracy ] %-8s %-22s views %d  differing pixels total %llu  max %llu  views with error %d  (%.4f%% of "
            "frames)\n",
            scene, r.name.c_str(), r.views, (unsigned long long)r.differingTotal, (unsigned long long)r.differingMax,
            r.viewsWithError, r.percentOfFrames());
        EXPECT_EQ(r.views, kViews);
        const bool conservative = r.name == "sphere" || r.name == "aabb" || r.name == "sphere-sphere";
        if (conservative) {
            EXPECT_EQ(r.differingTotal, 0u) << r.name << " on " << scene << ": worst view " << r.worstView;
        }
    }
    // centre-box drops partly visible objects: that must show (if it did not, the harness would be blind).
    EXPECT_GT(results[3].differingTotal, 0u) << "center-box showed no error on " << scene;
}

// Occlusion settings: the pass (mode On) with the given cap, or frustum culling alone.
CullSettings occlusion(OcclusionMode mode, OccluderCap cap = OccluderCap::FrontFaces) {
    CullSettings c;
    c.occlusion.mode = mode;
    c.occlusion.method = OcclusionMethod::Tree;  // the map's rows set it
    c.occlusion.measureOnly.cap = cap;
    return c;
}

// The occlusion map (mode On), conservative (opacity 1) or approximate.
CullSettings occlusionMap(double opacity = 1.0) {
    CullSettings c = occlusion(OcclusionMode::EveryFrame);
    c.occlusion.method = OcclusionMethod::Hom;
    c.occlusion.homOpacity = opacity;
    return c;
}

void printOcclusion(const accuracy::Result& r, const char* scene) {
    std::printf(
        "[ accuracy ] %-8s %-22s views %d  differing pixels total %llu  max %llu  views with error %d  (%.4f%% of "
        "frames)"
        "  culled by occlusion %llu (in %d views, tree built in %d)  triangles drawn %llu of %llu\n",
        scene, r.name.c_str(), r.views, (unsigned long long)r.differingTotal, (unsigned long long)r.differingMax,
        r.viewsWithError, r.percentOfFrames(), (unsigned long long)r.culledOcclusionTotal, r.viewsWithOcclusionCulls,
        r.viewsOcclusionRan, (unsigned long long)r.trianglesTotal, (unsigned long long)r.referenceTrianglesTotal);
}

// A view's evidence: its camera and counts, and its reference, culled and difference images (differing
// pixels in red over a dimmed reference) as PNGs in the test's temporary directory.
std::string describeWorst(accuracy::Harness& h, const Scene& scene, const std::vector<Camera>& views,
                          const CullSettings& s, const accuracy::Result& r, const std::string& tag) {
    if (r.worstView < 0) return "no differing view";
    Camera cam = views[size_t(r.worstView)];
    cam.setViewport(kW, kH);
    Image ref, got;
    CullStats st;
    const uint64_t d = h.compare(scene, cam, s, &ref, &got, &st);
    Image diff = ref;
    for (size_t p = 0; p + 3 < diff.rgba.size(); p += 4) {
        const bool differs =
            ref.rgba[p] != got.rgba[p] || ref.rgba[p + 1] != got.rgba[p + 1] || ref.rgba[p + 2] != got.rgba[p + 2];
        for (int c = 0; c < 3; ++c) diff.rgba[p + c] = uint8_t(differs ? (c == 0 ? 255 : 0) : ref.rgba[p + c] / 3);
    }
    const std::string base = ::testing::TempDir() + "accuracy_" + tag + "_view" + std::to_string(r.worstView);
    savePng(base + "_ref.png", ref);
    savePng(base + "_culled.png", got);
    savePng(base + "_diff.png", diff);
    return "worst view " + std::to_string(r.worstView) + " (" + std::to_string(d) + " pixels, " +
           std::to_string(st.culledOcclusion) + " bounds culled by occlusion, " + std::to_string(st.occludersUsed) +
           " occluders used): " + accuracy::describeCamera(cam) + "; images " + base + "_{ref,culled,diff}.png";
}

// The occlusion tree's front-faces cap and the conservative occlusion map draw exactly the reference on
// every view, and are not vacuous: they culled bounds, and fewer triangles were drawn than with frustum
// culling alone. The approximate map's error is reported; it draws at most what the conservative one draws.
void checkFrontFaces(const Scene& scene, const std::vector<Camera>& views, const char* name) {
    accuracy::Harness h(kW, kH);
    const std::vector<CullSettings> settings = {occlusion(OcclusionMode::Off), occlusion(OcclusionMode::EveryFrame),
                                                occlusionMap(), occlusionMap(0.75)};
    const std::vector<accuracy::Result> res = h.run(scene, views, settings);
    for (const auto& r : res) printOcclusion(r, name);
    const accuracy::Result &frustum = res[0], &approx = res[3];
    ASSERT_EQ(frustum.name, "aabb");
    ASSERT_EQ(res[1].name, "aabb+occlusion");
    ASSERT_EQ(res[2].name, "aabb+occlusion-hom");
    ASSERT_EQ(approx.name, "aabb+occlusion-hom-approx");
    for (const auto& r : res) EXPECT_EQ(r.views, int(views.size()));
    EXPECT_EQ(frustum.differingTotal, 0u)
        << name << ": " << describeWorst(h, scene, views, settings[0], frustum, std::string(name) + "_aabb");
    for (size_t k : {size_t(1), size_t(2)}) {
        const accuracy::Result& r = res[k];
        EXPECT_EQ(r.differingTotal, 0u) << r.name << " on " << name << ": "
                                        << describeWorst(h, scene, views, settings[k], r,
                                                         std::string(name) + "_" + r.name);
        EXPECT_GT(r.culledOcclusionTotal, 0u) << r.name << " culled nothing on " << name;
        EXPECT_LT(r.trianglesTotal, frustum.trianglesTotal) << r.name << " on " << name;
    }
    EXPECT_LE(approx.trianglesTotal, res[2].trianglesTotal) << name;
    if (approx.differingTotal > 0)
        std::printf("[ accuracy ] %-8s %s: %s\n", name, approx.name.c_str(),
                    describeWorst(h, scene, views, settings[3], approx, std::string(name) + "_hom_approx").c_str());
}

constexpr int kCityN = 14, kOfficeR = 6;
constexpr uint64_t kCitySeed = 2025, kOfficeSeed = 77;
}  // namespace

TEST(Accuracy, CityConservativeStrategiesAreExact) {
    const int n = 12;
    Scene s(scenes::buildCity({n, false}));
    s.update();
    accuracy::Harness h(kW, kH);
    check(h.run(s, accuracy::cityViews(n, kViews, 2024, kW, kH), strategies()), "city");
}

TEST(Accuracy, RandomGraphConservativeStrategiesAreExact) {
    scenes::RandomSceneOptions o;
    o.objects = 80;
    Scene s(scenes::buildRandomScene(99, o));
    s.update();
    accuracy::Harness h(kW, kH);
    check(h.run(s, accuracy::boxViews(Box{dvec3(-70), dvec3(70)}, kViews, 7, kW, kH), strategies()), "random");
}

TEST(Accuracy, FarFromTheOriginConservativeStrategiesAreExact) {
    // The city 10,000 km from the origin, seen from the same relative views.
    const int n = 8;
    const dvec3 off(1e7, -1e7, 0);
    auto top = make<Transform>(glm::translate(dmat4(1.0), off));
    top->addChild(scenes::buildCity({n, false}));
    Scene s(top);
    s.update();
    std::vector<Camera> views = accuracy::cityViews(n, testutil::scaled(40), 5, kW, kH);
    for (Camera& c : views) c.setView(c.view() * glm::translate(dmat4(1.0), -off));
    accuracy::Harness h(kW, kH);
    for (const auto& r : h.run(s, views, {CullSettings{}}))
        EXPECT_EQ(r.differingTotal, 0u) << "worst view " << r.worstView;
}

TEST(Accuracy, HarnessSeesWhatACullDrops) {
    // Negative control: small-feature culling with a huge threshold drops every object in view; the
    // harness must count those pixels, and count none for the strategy the reference uses itself.
    Scene s(scenes::buildCity({8, false}));
    s.update();
    accuracy::Harness h(kW, kH);
    const Camera cam = scenes::cityOrbitCamera(8, 10, kW, kH);
    CullSettings dropAll;
    dropAll.smallFeaturePixels = 1e9;
    Image ref, got;
    const uint64_t d = h.compare(s, cam, dropAll, &ref, &got);
    EXPECT_GT(d, uint64_t(kW * kH / 20));
    EXPECT_EQ(d, countDifferingPixels(ref, got));
    CullSettings none;
    none.strategy = CullStrategy::None;
    EXPECT_EQ(h.compare(s, cam, none), 0u);
}

TEST(Accuracy, CityOcclusionFrontFacesIsExact) {
    // city (docs/scenes.md) with its box occluders; street-level and aerial views, awkward ones among them.
    Scene s(scenes::buildCity({kCityN, true}));
    s.update();
    checkFrontFaces(s, accuracy::cityOcclusionViews(kCityN, kViews, kCitySeed, kW, kH), "city");
}

TEST(Accuracy, OfficeOcclusionFrontFacesIsExact) {
    // office (docs/scenes.md): walls with door openings as box occluders; views in the rooms, in and through the doors,
    // and from above (no ceiling).
    Scene s(scenes::buildOffice(kOfficeR));
    s.update();
    checkFrontFaces(s, accuracy::officeViews(kOfficeR, kViews, kOfficeSeed, kW, kH), "office");
}

TEST(Accuracy, OcclusionCenterPlaneCapShowsError) {
    // The paper's cap, a plane through the box centre facing the eye, culls what rays grazing an occluder
    // still see between that plane and the box's far silhouette edges. Its error is reported on both scenes
    // and must show on at least one, or the harness could not tell it from the conservative cap. It shows
    // on a few office views in a thousand (past a door jamb at furniture just beyond it; rarer since the tree takes
    // near and large occluders first, the jambs less often): 200 views miss it, so the office gets 10x as many (the
    // first are the ones above); the city keeps the views above.
    const CullSettings centre = occlusion(OcclusionMode::EveryFrame, OccluderCap::CenterPlane);
    uint64_t total = 0;
    auto report = [&](const Scene& scene, const std::vector<Camera>& views, const char* name) {
        accuracy::Harness h(kW, kH);
        const accuracy::Result r = h.run(scene, views, {centre})[0];
        printOcclusion(r, name);
        EXPECT_EQ(r.name, "aabb+occlusion-centre");
        EXPECT_GT(r.culledOcclusionTotal, 0u) << name;
        if (r.differingTotal > 0)
            std::printf("[ accuracy ] %-8s %s: %s\n", name, r.name.c_str(),
                        describeWorst(h, scene, views, centre, r, std::string(name) + "_centre").c_str());
        total += r.differingTotal;
    };
    {
        Scene s(scenes::buildCity({kCityN, true}));
        s.update();
        report(s, accuracy::cityOcclusionViews(kCityN, kViews, kCitySeed, kW, kH), "city");
    }
    {
        Scene s(scenes::buildOffice(kOfficeR));
        s.update();
        report(s, accuracy::officeViews(kOfficeR, 10 * kViews, kOfficeSeed, kW, kH), "office");
    }
    // The error shows on a handful of the 2000 office views; the sanitizer build's quarter may miss it.
    if (testutil::kSanitizerDivisor == 1) {
        EXPECT_GT(total, 0u) << "the centre-plane cap showed no error on city nor on office";
    }
}
