// sgview and features: --pick --json gives each pick as one JSON object with the features and their properties, and
// --style colours and hides the city's buildings exactly as the same scene built by hand draws (the hidden ones
// masked off, the coloured ones in tinted materials); a style that does not parse exits with 2 naming where.
#include "RenderUtil.h"
#include "integration/ProgramRun.h"
#include "nodes/Geometry.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/io/ImageIO.h"
#include "sgview/Pick.h"
#include "sgview/ViewCamera.h"
#include "testbed/City.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <functional>
#include <sstream>

using namespace sg;
namespace fs = std::filesystem;

namespace {

fs::path scratch() { return testDirectory("sgview_features_"); }
ProgramRun runSgview(const std::string& args) { return runProgram(scratch(), "'" SGVIEW_EXE "' " + args); }

const char* kCamera = "-20,-30,90,80,80,0,0,0,1";
Camera cityCamera(const Scene& scene) {
    return sgview::specCamera({dvec3(-20, -30, 90), dvec3(80, 80, 0), dvec3(0, 0, 1)}, sgview::sceneBound(scene), 400,
                              300);
}

// Every node of the graph that is a feature, with its row's height.
void forEachBuilding(Node& n, const std::function<void(Node&, double height)>& f) {
    if (const MeshFeatures* mf = n.features()) {
        const int64_t row = mf->idAt(0, n.featureIndex());
        const int table = mf->sets[0].propertyTable;
        const int h = mf->store->schema.classes[size_t(mf->store->tables()[size_t(table)].classIndex)].find("height");
        f(n, mf->store->value(table, uint64_t(row), h).asNumber());
    }
    for (size_t i = 0; i < n.numChildren(); ++i) forEachBuilding(*n.child(i), f);
}

void forEachGeometry(Node& n, const std::function<void(Geometry&)>& f) {
    if (n.kind() == NodeKind::Geometry) f(static_cast<Geometry&>(n));
    for (size_t i = 0; i < n.numChildren(); ++i) forEachGeometry(*n.child(i), f);
}

std::vector<std::string> lines(const std::string& s) {
    std::vector<std::string> out;
    std::istringstream in(s);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
}

}  // namespace

TEST(SgviewFeatures, PickJsonIsOneObjectAPickWithTheBuildingsProperties) {
    const ProgramRun r = runSgview(std::string("--headless --scene city --n 8 --size 400x300 --out p.png --camera ") +
                                   kCamera + " --pick 200,150 --pick 1,1 --json");
    ASSERT_EQ(r.code, 0) << r.err;
    const std::vector<std::string> out = lines(r.out);
    ASSERT_GE(out.size(), 3u) << r.out;
    const auto hit = nlohmann::json::parse(out[0]), miss = nlohmann::json::parse(out[1]);
    EXPECT_EQ(miss["hit"], false);
    ASSERT_EQ(hit["hit"], true) << out[0];
    EXPECT_EQ(hit["node_path"].back(), "Geometry");
    EXPECT_TRUE(hit["source"].is_null());  // built in, not read from a file
    EXPECT_TRUE(hit["gltf_mesh"].is_null());
    EXPECT_TRUE(hit["triangle"].is_number_unsigned());
    ASSERT_EQ(hit["point"].size(), 3u);
    ASSERT_EQ(hit["features"].size(), 1u) << out[0];
    const auto& f = hit["features"][0];
    EXPECT_EQ(f["class"], "building");
    EXPECT_EQ(f["property_table"], 0);
    // The library's own answer for the same pixel: the same building, the same values.
    Scene scene(scenes::buildCity({8, false, true}));
    scene.update();
    IntersectTraversal picker;
    const sgview::Pick p = sgview::pickAt(picker, scene, cityCamera(scene), 200, 150);
    ASSERT_TRUE(p.hit);
    ASSERT_EQ(p.features.features.size(), 1u);
    const FeatureAtHit& want = p.features.features[0];
    EXPECT_EQ(f["feature_id"], want.featureId);
    const uint32_t id = uint32_t(want.featureId);
    const scenes::CityBuilding b = scenes::cityBuilding(8, id / 8, id % 8);
    EXPECT_EQ(f["properties"]["id"], b.id);
    EXPECT_EQ(f["properties"]["height"], b.height);
    EXPECT_EQ(f["properties"]["floors"], b.floors);
    EXPECT_EQ(f["properties"]["use"], b.use);
    EXPECT_EQ(hit["distance"].get<double>(), p.nearest.distance);
}

TEST(SgviewFeatures, AStyleShowsAndColoursTheBuildingsAsTheSceneBuiltByHand) {
    {
        std::ofstream s(scratch() / "style.json");
        s << R"json({"show": "${height} > 30",
                 "color": {"conditions": [["${use} === 'office'", "color('#ff0000')"], ["true", "color('white')"]]}})json";
    }
    const std::string view = std::string("--headless --scene city --n 8 --size 400x300 --camera ") + kCamera;
    const ProgramRun styled = runSgview(view + " --style style.json --out styled.png");
    ASSERT_EQ(styled.code, 0) << styled.err;
    // By hand: buildings of 30 m or less masked off, offices in a red copy of their material.
    auto root = scenes::buildCity({8, false, true});
    size_t hidden = 0, red = 0;
    forEachBuilding(*root, [&](Node& n, double height) {
        const MeshFeatures& mf = *n.features();
        const int table = mf.sets[0].propertyTable;
        const int use = mf.store->schema.classes[size_t(mf.store->tables()[size_t(table)].classIndex)].find("use");
        const bool office = mf.store->value(table, uint64_t(mf.idAt(0, n.featureIndex())), use).string == "office";
        if (height <= 30.0) {
            n.setNodeMask(0);
            ++hidden;
        } else if (office) {
            forEachGeometry(n, [](Geometry& g) {
                auto m = make<Material>(*g.material());
                m->baseColor *= vec4(1, 0, 0, 1);
                g.setMaterial(m);
            });
            ++red;
        }
    });
    ASSERT_GT(hidden, 0u);
    ASSERT_GT(red, 0u);
    Scene scene(root);
    scene.update();
    OsmesaContext context(400, 300);
    Renderer renderer;
    const Image want = testutil::drawScene(renderer, scene, cityCamera(scene), true);
    EXPECT_EQ(countDifferingPixels(loadPng((scratch() / "styled.png").string()), want), 0u);
    const ProgramRun plain = runSgview(view + " --out plain.png");
    ASSERT_EQ(plain.code, 0) << plain.err;
    EXPECT_GT(countDifferingPixels(loadPng((scratch() / "plain.png").string()), want), 1000u);  // the style shows
}

TEST(SgviewFeatures, AStyleThatDoesNotParseExitsWithTwoNamingTheExpressionAndWhere) {
    {
        std::ofstream s(scratch() / "bad.json");
        s << R"({"show": "${height} > > 30"})";
    }
    const ProgramRun r = runSgview("--headless --scene city --n 4 --style bad.json --out b.png");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.err.find("show"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("${height} > > 30"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("12"), std::string::npos) << r.err;  // the position of the second '>'
}
