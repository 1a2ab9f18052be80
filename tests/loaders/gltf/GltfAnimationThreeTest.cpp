// The pose is exact: node matrices and morph weights at 20 times of every animation of the test files, the test
// figure and Debian's animated glTF files equal those of an independent implementation, three.js's AnimationMixer run
// under node on the same file (tests/loaders/gltf/three_pose.mjs), to 1e-5 of the matrix's size.
#include "GltfDoc.h"
#include "OutsideTools.h"
#include "loaders/gltf/Gltf.h"
#include "nodes/Geometry.h"
#include "sg/scene/AnimationPlayer.h"
#include "sg/scene/Posing.h"
#include "testbed/Figure.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

using namespace sg;
using json = nlohmann::json;
namespace fs = std::filesystem;

constexpr int kTimes = 20;

using testutil::npmModules;

std::string threeMissing() {
    if (npmModules().empty() || !fs::exists(npmModules() / "three"))
        return "three absent from '" + npmModules().string() +
               "': build the tiles-tools target or set SGKIT_NPM_MODULES";
    if (std::system("node --version > /dev/null 2>&1") != 0) return "node is not installed";
    return {};
}

// three.js's poses of the file's animations (three_pose.mjs's output).
json threePoses(const std::string& file) {
    const std::string out =
        (fs::temp_directory_path() / ("sgkit_three_" + std::to_string(::getpid()) + ".json")).string();
    const std::string cmd = "node '" SGKIT_SOURCE_DIR "/tests/loaders/gltf/three_pose.mjs' '" + npmModules().string() +
                            "' '" + file + "' " + std::to_string(kTimes) + " > '" + out + "' 2>&1";
    const int status = std::system(cmd.c_str());
    std::ifstream in(out);
    std::stringstream text;
    text << in.rdbuf();
    std::remove(out.c_str());
    EXPECT_EQ(status, 0) << text.str();
    if (status != 0) return {};
    return json::parse(text.str());
}

const Geometry* firstGeometry(const Node& n) {
    if (n.kind() == NodeKind::Geometry) return static_cast<const Geometry*>(&n);
    for (size_t i = 0; i < n.numChildren(); ++i)
        if (const Geometry* g = firstGeometry(*n.child(i))) return g;
    return nullptr;
}

// Plays each animation of `file` alone with sgkit's player and compares every node and morph weight with three.js.
void expectSamePoses(const std::string& file, size_t expectAnimations) {
    const json three = threePoses(file);
    ASSERT_TRUE(three.contains("animations")) << file;
    ASSERT_EQ(three["animations"].size(), expectAnimations) << file;
    for (size_t a = 0; a < three["animations"].size(); ++a) {
        const json& ta = three["animations"][a];
        const GltfScene s = loadGltf(file);  // a fresh graph for each animation: rest poses as the file has them
        ASSERT_EQ(s.animations.size(), expectAnimations) << file;
        AnimationPlayer player;
        for (const auto& anim : s.animations) player.add(anim);
        player.setLoop(a, LoopMode::Once);
        player.play(a);
        EXPECT_NEAR(s.animations[a]->duration(), ta["duration"].get<double>(), 1e-6) << file;
        size_t compared = 0;
        for (size_t k = 0; k < ta["times"].size(); ++k) {
            const double t = ta["times"][k].get<double>();
            player.seek(a, t);
            player.apply();
            for (auto it = ta["nodes"].begin(); it != ta["nodes"].end(); ++it) {
                const size_t i = std::stoul(it.key());
                ASSERT_LT(i, s.nodes.size()) << file;
                if (!s.nodes[i]) continue;  // a node sgkit folds away (none in these files)
                const dmat4 ours = worldMatrix(*s.nodes[i]);
                const json& theirs = it.value()[k];
                double size = 1.0, worst = 0.0;
                for (int e = 0; e < 16; ++e) size = std::max(size, std::abs(theirs[size_t(e)].get<double>()));
                for (int e = 0; e < 16; ++e)
                    worst = std::max(worst, std::abs(ours[e / 4][e % 4] - theirs[size_t(e)].get<double>()));
                EXPECT_LE(worst, 1e-5 * size) << file << " animation " << a << " node " << i << " t " << t;
                ++compared;
            }
            for (auto it = ta["weights"].begin(); it != ta["weights"].end(); ++it) {
                const size_t i = std::stoul(it.key());
                const Geometry* g = i < s.nodes.size() && s.nodes[i] ? firstGeometry(*s.nodes[i]) : nullptr;
                ASSERT_NE(g, nullptr) << file << " node " << i << " has morph weights in three.js, no Geometry here";
                const json& theirs = it.value()[k];
                std::vector<float> w = g->morphWeights();
                if (w.empty() && g->mesh()) w = g->mesh()->defaultWeights;
                w.resize(theirs.size(), 0.0f);
                for (size_t e = 0; e < theirs.size(); ++e)
                    EXPECT_NEAR(w[e], theirs[e].get<double>(), 1e-5)
                        << file << " animation " << a << " node " << i << " weight " << e << " t " << t;
                ++compared;
            }
        }
        EXPECT_GT(compared, size_t(0)) << file;
    }
}

// A file of its own: a chain of three nodes moved by every path and interpolation, rotations whose keys change sign
// (the shorter arc), and a mesh's two morph targets weighted by a cubic spline.
std::string interpolationsFile() {
    gltftest::GltfDoc doc(R"([{"attributes": {"POSITION": 0}, "targets": [{"POSITION": 1}, {"POSITION": 2}]}])");
    const std::vector<float> tri = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::vector<float> d1 = {0, 0, 1, 0, 0, 1, 0, 0, 1}, d2 = {1, 0, 0, 0, 1, 0, 0, 0, 0};
    for (const auto* v : {&tri, &d1, &d2}) {
        const int a = doc.accessor(doc.view(gltftest::bytesOf(*v)), 5126, 3, "VEC3");
        doc.j["accessors"][size_t(a)]["min"] = {0, 0, 0};
        doc.j["accessors"][size_t(a)]["max"] = {1, 1, 1};
    }
    doc.j["nodes"] = json::parse(R"([{"children": [1], "translation": [1, 2, 3]}, {"children": [2], "scale": [2, 2, 2]},
        {"children": [3], "rotation": [0, 0, 0, 1]}, {"mesh": 0, "translation": [0, 1, 0]}])");
    auto floats = [&](const std::vector<float>& v, const char* type, size_t count) {
        const int a = doc.accessor(doc.view(gltftest::bytesOf(v)), 5126, count, type);
        if (std::string(type) == "SCALAR") {
            doc.j["accessors"][size_t(a)]["min"] = {v.front()};
            doc.j["accessors"][size_t(a)]["max"] = {v.back()};
        }
        return a;
    };
    const int t3 = floats({0.0f, 0.7f, 2.0f}, "SCALAR", 3);
    const int t4 = floats({0.25f, 0.5f, 1.0f, 1.75f}, "SCALAR", 4);
    const float h = 0.70710678f;
    // LINEAR translation; CUBICSPLINE rotation (in-tangent, value, out-tangent a key); STEP scale; LINEAR rotation
    // whose second and fourth keys are negated (the same rotations: the player must take the shorter arc).
    const int tr = floats({0, 0, 0, 2, 0, 1, -1, 3, 0}, "VEC3", 3);
    const int rc = floats({0, 0, 0,    0, 0, 0, 0, 1, 0, 0, 1,    0,  //
                           0, 0, 0.5f, 0, 0, 0, h, h, 0, 0, 0.3f, 0,  //
                           0, 0, -1,   0, 0, 0, 1, 0, 0, 0, 0,    0},
                          "VEC4", 9);
    const int sc = floats({1, 1, 1, 2, 1, 1, 1, 3, 1, 0.5f, 0.5f, 0.5f}, "VEC3", 4);
    const int rl = floats({0, 0, 0, 1, 0, -h, 0, -h, 0, 1, 0, 0, 0, 0, -h, -h}, "VEC4", 4);
    const int wc = floats({0, 0, 0, 0, 1, 0,          //
                           1, -1, 0.5f, 0.25f, 0, 0,  //
                           0, 0, 0, 1, 0, 0},
                          "SCALAR", 18);
    doc.j["animations"] = json::array();
    doc.j["animations"].push_back(json::parse(R"({"name": "all", "samplers": [], "channels": []})"));
    json& an = doc.j["animations"][0];
    auto add = [&](int in, int out, const char* interp, int node, const char* path) {
        an["samplers"].push_back({{"input", in}, {"output", out}, {"interpolation", interp}});
        an["channels"].push_back(
            {{"sampler", an["samplers"].size() - 1}, {"target", {{"node", node}, {"path", path}}}});
    };
    add(t3, tr, "LINEAR", 0, "translation");
    add(t3, rc, "CUBICSPLINE", 1, "rotation");
    add(t4, sc, "STEP", 1, "scale");
    add(t4, rl, "LINEAR", 2, "rotation");
    add(t3, wc, "CUBICSPLINE", 3, "weights");
    doc.j["animations"].push_back(json::parse(R"({"name": "second", "samplers": [], "channels": []})"));
    json& second = doc.j["animations"][1];
    second["samplers"].push_back({{"input", t4}, {"output", sc}, {"interpolation", "LINEAR"}});
    second["channels"].push_back({{"sampler", 0}, {"target", {{"node", 3}, {"path", "scale"}}}});
    doc.j["scenes"][0]["nodes"] = {0};
    const std::string path =
        (fs::temp_directory_path() / ("sgkit_interp_" + std::to_string(::getpid()) + ".gltf")).string();
    std::ofstream(path) << doc.text();
    return path;
}

TEST(GltfAnimationThree, EveryInterpolationAndPathPosesAsThreeJsDoes) {
    if (const std::string why = threeMissing(); !why.empty()) SG_SKIP_OR_FAIL(why);
    const std::string file = interpolationsFile();
    expectSamePoses(file, 2);
    std::remove(file.c_str());
}

TEST(GltfAnimationThree, TheFigureWalksAsThreeJsWalksIt) {
    if (const std::string why = threeMissing(); !why.empty()) SG_SKIP_OR_FAIL(why);
    for (bool cubic : {false, true}) {
        scenes::FigureOptions opt;
        opt.cubic = cubic;
        opt.stepBob = cubic;
        const scenes::Figure f = scenes::makeFigure(opt);
        const std::string path =
            (fs::temp_directory_path() / ("sgkit_figure_" + std::to_string(::getpid()) + ".glb")).string();
        GltfSaveOptions so;
        so.animations.push_back(f.walk);
        saveGltf(*f.root, path, so);
        expectSamePoses(path, 1);
        std::remove(path.c_str());
    }
}

TEST(GltfAnimationThree, DebiansAnimatedFilesPoseAsThreeJsPosesThem) {
    const std::string dir = "/usr/share/assimp/models/glTF2/";
    const std::string skin = dir + "simple_skin/simple_skin.gltf";
    const std::string morph = dir + "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf";
    if (!fs::exists(skin) || !fs::exists(morph)) SG_SKIP_OR_FAIL(skin << " absent: install assimp-testmodels");
    if (const std::string why = threeMissing(); !why.empty()) SG_SKIP_OR_FAIL(why);
    expectSamePoses(skin, 1);
    expectSamePoses(morph, 1);
}

}  // namespace
