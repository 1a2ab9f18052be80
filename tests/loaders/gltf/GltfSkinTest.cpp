// glTF skins: joints bound to the Transforms built for them, inverse binds read, 4 and 8 influences of each component
// type, weights normalised with a warning, skinned Geometries beside their skeleton, bad skins refused naming their
// JSON path, and the skinned model of Debian's assimp-testmodels.
#include "GltfDoc.h"
#include "GltfTestUtil.h"
#include "OutsideTools.h"

#include "loaders/gltf/Gltf.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Transform.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace {

using namespace sg;
using json = nlohmann::json;
using gltftest::bytesOf;

constexpr int kFloat = 5126, kUByte = 5121, kUShort = 5123;
const std::string kPrim = "meshes[0].primitives[0]";

// One triangle on nodes[0] "body", skinned by skins[0] over nodes[1] "hip" (at x = 1) and its child nodes[2] "knee"
// (at y = 2 below it); the scene's roots are nodes 0 and 1.
struct Doc : gltftest::GltfDoc {
    template <class T>
    int data(const std::vector<T>& v, int comp, size_t count, const char* type, bool normalized = false) {
        return accessor(view(bytesOf(v)), comp, count, type, normalized);
    }
    json& attributes() { return j["meshes"][0]["primitives"][0]["attributes"]; }

    explicit Doc(bool inverseBinds = true) {
        const int pos = data(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0}, kFloat, 3, "VEC3");
        j["meshes"][0]["primitives"] = json::array({{{"attributes", {{"POSITION", pos}}}}});
        j["nodes"][0] = {{"name", "body"}, {"mesh", 0}, {"skin", 0}};
        j["nodes"].push_back({{"name", "hip"}, {"translation", {1, 0, 0}}, {"children", json::array({2})}});
        j["nodes"].push_back({{"name", "knee"}, {"translation", {0, 2, 0}}});
        j["scenes"][0]["nodes"] = json::array({0, 1});
        json skin = {{"joints", json::array({1, 2})}};
        if (inverseBinds) {  // the inverses of the joints' world matrices: translations by (-1, 0, 0), (-1, -2, 0)
            std::vector<float> ib = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, 0,  0, 1,
                                     1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, -2, 0, 1};
            skin["inverseBindMatrices"] = data(ib, kFloat, 2, "MAT4");
        }
        j["skins"] = json::array({skin});
    }
    // JOINTS_n of unsigned bytes and WEIGHTS_n of floats, four a vertex.
    void influences(int set, const std::vector<uint8_t>& joints, const std::vector<float>& weights) {
        attributes()["JOINTS_" + std::to_string(set)] = data(joints, kUByte, joints.size() / 4, "VEC4");
        attributes()["WEIGHTS_" + std::to_string(set)] = data(weights, kFloat, weights.size() / 4, "VEC4");
    }
};

// The scene root's direct child Geometry (where skinned Geometries go), or null.
const Geometry* skinnedGeometry(const Node& root) {
    for (size_t i = 0; i < root.numChildren(); ++i)
        if (auto g = dynamic_cast<const Geometry*>(root.child(i))) return g;
    return nullptr;
}

bool warned(const GltfScene& s, const std::string& path, const std::string& what) {
    for (const std::string& w : s.warnings)
        if (w.rfind(path + ":", 0) == 0 && w.find(what) != std::string::npos) return true;
    return false;
}

TEST(GltfSkin, TwoJointsBindTheBuiltTransformsAndTheInverseBindsAreRead) {
    Doc d;
    d.influences(0, {0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0}, {1, 0, 0, 0, 0.5f, 0.5f, 0, 0, 1, 0, 0, 0});
    const GltfScene s = d.load();
    const Node& root = *s.root;
    ASSERT_EQ(root.numChildren(), 3u);  // body, hip, and body's skinned Geometry
    const Node* body = gltftest::findByName(const_cast<Node&>(root), "body");
    const Node* hip = gltftest::findByName(const_cast<Node&>(root), "hip");
    ASSERT_TRUE(body && hip);
    EXPECT_EQ(body->kind(), NodeKind::Transform);
    EXPECT_EQ(body->numChildren(), 0u);  // its Geometry is not below it: glTF ignores a skinned node's transform
    ASSERT_EQ(hip->numChildren(), 1u);
    const Geometry* g = skinnedGeometry(root);
    ASSERT_NE(g, nullptr);
    EXPECT_EQ(g->name(), "body");
    ASSERT_NE(g->skin(), nullptr);
    ASSERT_EQ(g->skin()->size(), 2u);
    EXPECT_EQ(g->skin()->joints()[0].get(), hip);
    EXPECT_EQ(g->skin()->joints()[1].get(), hip->child(0));
    EXPECT_EQ(g->skin()->inverseBind()[0][3], dvec4(-1, 0, 0, 1));
    EXPECT_EQ(g->skin()->inverseBind()[1][3], dvec4(-1, -2, 0, 1));
    EXPECT_EQ(g->skin()->inverseBind()[1][1], dvec4(0, 1, 0, 0));
    const Mesh& m = *g->mesh();
    EXPECT_EQ(m.influences(), 4);
    EXPECT_EQ(m.joints(), (std::vector<uint16_t>{0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0}));
    EXPECT_EQ(m.weights(), (std::vector<float>{1, 0, 0, 0, 0.5f, 0.5f, 0, 0, 1, 0, 0, 0}));
    EXPECT_EQ(m.maxJoint(), 1u);
    EXPECT_TRUE(s.warnings.empty()) << s.warnings[0];
}

TEST(GltfSkin, NoInverseBindMatricesAreIdentities) {
    Doc d(false);
    d.influences(0, {0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0}, {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
    const GltfScene s = d.load();  // holds the graph
    const Geometry* g = skinnedGeometry(*s.root);
    ASSERT_TRUE(g && g->skin());
    EXPECT_EQ(g->skin()->inverseBind(), std::vector<dmat4>(2, dmat4(1.0)));
}

TEST(GltfSkin, EightInfluencesOfUnsignedShortJoints) {
    Doc d;
    d.attributes()["JOINTS_0"] = d.data(std::vector<uint16_t>(12, 0), kUShort, 3, "VEC4");
    d.attributes()["WEIGHTS_0"] = d.data(std::vector<float>{0.25f, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, kFloat, 3, "VEC4");
    d.attributes()["JOINTS_1"] = d.data(std::vector<uint16_t>{1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, kUShort, 3, "VEC4");
    d.attributes()["WEIGHTS_1"] = d.data(std::vector<float>{0.75f, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, kFloat, 3, "VEC4");
    const GltfScene s = d.load();
    const Geometry* g = skinnedGeometry(*s.root);
    ASSERT_TRUE(g && g->skin());
    const Mesh& m = *g->mesh();
    EXPECT_EQ(m.influences(), 8);
    ASSERT_EQ(m.joints().size(), 24u);
    EXPECT_EQ(m.joints()[4], 1);  // vertex 0's fifth influence: JOINTS_1's first
    EXPECT_EQ(m.weights()[0], 0.25f);
    EXPECT_EQ(m.weights()[4], 0.75f);
    EXPECT_EQ(m.weights()[8], 1.0f);  // vertex 1
    EXPECT_EQ(m.maxJoint(), 1u);
    EXPECT_TRUE(s.warnings.empty()) << s.warnings[0];
}

TEST(GltfSkin, NormalizedUnsignedByteWeights) {
    Doc d;
    d.attributes()["JOINTS_0"] = d.data(std::vector<uint8_t>{0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0}, kUByte, 3, "VEC4");
    d.attributes()["WEIGHTS_0"] =
        d.data(std::vector<uint8_t>{255, 0, 0, 0, 128, 127, 0, 0, 0, 255, 0, 0}, kUByte, 3, "VEC4", true);
    const GltfScene s = d.load();
    const Geometry* g = skinnedGeometry(*s.root);
    ASSERT_TRUE(g && g->skin());
    const std::vector<float>& w = g->mesh()->weights();
    EXPECT_EQ(w[0], 1.0f);
    EXPECT_NEAR(w[4], 128.0f / 255.0f, 1e-6);
    EXPECT_NEAR(w[5], 127.0f / 255.0f, 1e-6);
    EXPECT_EQ(w[9], 1.0f);
    EXPECT_TRUE(s.warnings.empty()) << s.warnings[0];  // 128/255 + 127/255 is one
}

TEST(GltfSkin, WeightsNotSummingToOneAreNormalisedWithAWarning) {
    Doc d;
    d.influences(0, {0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0}, {0.5f, 0.25f, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0});
    const GltfScene s = d.load();
    const Geometry* g = skinnedGeometry(*s.root);
    ASSERT_TRUE(g && g->skin());
    EXPECT_NEAR(g->mesh()->weights()[0], 2.0f / 3.0f, 1e-6);
    EXPECT_NEAR(g->mesh()->weights()[1], 1.0f / 3.0f, 1e-6);
    EXPECT_EQ(g->mesh()->weights()[4], 1.0f);
    EXPECT_TRUE(warned(s, kPrim + ".attributes.WEIGHTS_0", "1 vertex")) << ::testing::PrintToString(s.warnings);
}

TEST(GltfSkin, AJointNotBuiltLeavesTheMeshUnskinnedBelowItsNode) {
    Doc d;
    d.influences(0, std::vector<uint8_t>(12, 0), {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
    d.j["nodes"].push_back({{"name", "elsewhere"}});  // nodes[3]: not in the scene
    d.j["skins"][0]["joints"][1] = 3;
    const GltfScene s = d.load();
    EXPECT_TRUE(warned(s, "skins[0].joints[1]", "not built")) << ::testing::PrintToString(s.warnings);
    EXPECT_EQ(skinnedGeometry(*s.root), nullptr);
    const Node* body = gltftest::findByName(*s.root, "body");
    ASSERT_TRUE(body && body->numChildren() == 1);
    const auto* g = dynamic_cast<const Geometry*>(body->child(0));
    ASSERT_NE(g, nullptr);
    EXPECT_EQ(g->skin(), nullptr);
}

TEST(GltfSkin, ASkinnedNodeWithoutJointsIsDrawnUnskinnedWithAWarning) {
    Doc d;  // no JOINTS_0 or WEIGHTS_0
    const GltfScene s = d.load();
    EXPECT_TRUE(warned(s, kPrim, "drawn unskinned")) << ::testing::PrintToString(s.warnings);
    const Node* body = gltftest::findByName(*s.root, "body");
    ASSERT_TRUE(body && body->numChildren() == 1);
    EXPECT_EQ(static_cast<const Geometry*>(body->child(0))->skin(), nullptr);
}

// The LoadError's path, and whether its reason holds `what`.
void expectRefused(Doc& d, const std::string& path, const std::string& what) {
    const auto [p, reason] = d.refusal();
    EXPECT_EQ(p, path) << reason;
    EXPECT_NE(reason.find(what), std::string::npos) << reason;
}

TEST(GltfSkin, AJointIndexPastTheSkinsJointsIsRefused) {
    Doc d;
    d.influences(0, {0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, {0.5f, 0.5f, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
    expectRefused(d, kPrim + ".attributes.JOINTS_0", "joint 2 of vertex 0 is past the 2 joints");
}

TEST(GltfSkin, AJointNamingAMissingNodeIsRefused) {
    Doc d;
    d.influences(0, std::vector<uint8_t>(12, 0), {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
    d.j["skins"][0]["joints"][1] = 7;
    expectRefused(d, "skins[0].joints[1]", "node 7 does not exist");
}

TEST(GltfSkin, InverseBindMatricesOfAnotherCountAreRefused) {
    Doc d;
    d.influences(0, std::vector<uint8_t>(12, 0), {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
    d.j["accessors"][d.j["skins"][0]["inverseBindMatrices"].get<size_t>()]["count"] = 1;
    expectRefused(d, "skins[0].inverseBindMatrices", "count 1 differs from the skin's 2 joints");
}

TEST(GltfSkin, AJointWithTwoParentsIsRefused) {
    Doc d;
    d.influences(0, std::vector<uint8_t>(12, 0), {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
    d.j["nodes"].push_back({{"children", json::array({2})}});  // nodes[3], a second parent of the knee
    d.j["scenes"][0]["nodes"].push_back(3);
    expectRefused(d, "skins[0].joints[1]", "two parents");
}

TEST(GltfSkin, JointsInACycleAreRefused) {
    Doc d;
    d.influences(0, std::vector<uint8_t>(12, 0), {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
    d.j["nodes"][2]["children"] = json::array({1});  // knee over hip over knee
    d.j["scenes"][0]["nodes"] = json::array({0});
    expectRefused(d, "skins[0].joints[0]", "cycle");
}

TEST(GltfSkin, JointsWithoutWeightsAreRefused) {
    Doc d;
    d.attributes()["JOINTS_0"] = d.data(std::vector<uint8_t>(12, 0), kUByte, 3, "VEC4");
    expectRefused(d, kPrim + ".attributes.JOINTS_0", "needs WEIGHTS_0");
}

// simple_skin (the glTF tutorial's, in Debian's assimp-testmodels): a joint is a child of the skinned node itself.
TEST(GltfSkin, ThirdPartySimpleSkinLoadsSkinned) {
    const std::string file = "/usr/share/assimp/models/glTF2/simple_skin/simple_skin.gltf";
    if (!std::filesystem::exists(file)) SG_SKIP_OR_FAIL(file << " absent: install assimp-testmodels");
    const GltfScene s = loadGltf(file);
    const Geometry* g = skinnedGeometry(*s.root);
    ASSERT_TRUE(g && g->skin());
    ASSERT_EQ(g->skin()->size(), 2u);
    EXPECT_EQ(g->skin()->inverseBind()[1][3], dvec4(-0.5, -1, 0, 1));
    EXPECT_EQ(g->mesh()->influences(), 4);
    EXPECT_EQ(g->mesh()->positions().size(), 10u);
    EXPECT_EQ(g->mesh()->maxJoint(), 1u);
    // The first joint is below the skinned node's Transform, which no longer holds the Geometry.
    ASSERT_EQ(s.root->numChildren(), 2u);
    const Node& body = *s.root->child(0);
    ASSERT_EQ(body.numChildren(), 1u);
    EXPECT_EQ(body.child(0), g->skin()->joints()[0].get());
}

}  // namespace
