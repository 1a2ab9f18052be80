// glTF morph targets: displacements and default weights read into the Mesh, a node's weights on Geometries of its
// own, sparse and quantized targets, Meshes not shared across other targets, bad targets and weights refused naming
// their JSON path, and the morphing cube of Debian's assimp-testmodels.
#include "GltfDoc.h"
#include "GltfTestUtil.h"
#include "OutsideTools.h"

#include "loaders/gltf/Gltf.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace {

using namespace sg;
using json = nlohmann::json;
using gltftest::bytesOf;

constexpr int kFloat = 5126, kByte = 5120, kShort = 5122, kUShort = 5123;
const std::string kPrim = "meshes[0].primitives[0]";

// One triangle on nodes[0]; primitives[0] has POSITION (accessor `pos`) and the targets the test adds.
struct Doc : gltftest::GltfDoc {
    int pos = -1;
    template <class T>
    int data(const std::vector<T>& v, int comp, size_t count, const char* type, bool normalized = false) {
        return accessor(view(bytesOf(v)), comp, count, type, normalized);
    }
    json& prim(size_t k = 0) { return j["meshes"][0]["primitives"][k]; }
    int vectors(const std::vector<float>& v) { return data(v, kFloat, v.size() / 3, "VEC3"); }

    Doc() {
        pos = vectors({0, 0, 0, 1, 0, 0, 0, 1, 0});
        j["meshes"][0]["primitives"] = json::array({{{"attributes", {{"POSITION", pos}}}}});
    }
    // Two targets: POSITION +z and NORMAL +y/2 on every vertex, then POSITION +x; mesh weights 0.5 and 0.25.
    void twoTargets() {
        const int up = vectors({0, 0, 1, 0, 0, 1, 0, 0, 1}), n = vectors({0, 0.5f, 0, 0, 0.5f, 0, 0, 0.5f, 0}),
                  x = vectors({1, 0, 0, 1, 0, 0, 1, 0, 0});
        prim()["targets"] = json::array({{{"POSITION", up}, {"NORMAL", n}}, {{"POSITION", x}}});
        j["meshes"][0]["weights"] = json::array({0.5, 0.25});
    }
};

const Geometry* geometryBelow(const Node& n, size_t k = 0) {
    return n.numChildren() > k ? dynamic_cast<const Geometry*>(n.child(k)) : nullptr;
}

void expectRefused(Doc& d, const std::string& path, const std::string& what) {
    const auto [p, reason] = d.refusal();
    EXPECT_EQ(p, path) << reason;
    EXPECT_NE(reason.find(what), std::string::npos) << reason;
}

TEST(GltfMorph, TargetsAndDefaultWeights) {
    Doc d;
    d.twoTargets();
    const GltfScene s = d.load();
    ASSERT_EQ(s.root->numChildren(), 1u);
    const Geometry* g = geometryBelow(*s.root->child(0));
    ASSERT_NE(g, nullptr);
    const Mesh& m = *g->mesh();
    ASSERT_EQ(m.morphTargets().size(), 2u);
    const MorphTarget &a = m.morphTargets()[0], &b = m.morphTargets()[1];
    EXPECT_EQ(a.positions, std::vector<vec3>(3, vec3(0, 0, 1)));
    EXPECT_EQ(a.normals, std::vector<vec3>(3, vec3(0, 0.5f, 0)));
    EXPECT_TRUE(a.tangents.empty());
    EXPECT_EQ(b.positions, std::vector<vec3>(3, vec3(1, 0, 0)));
    EXPECT_TRUE(b.normals.empty());
    EXPECT_EQ(m.defaultWeights, (std::vector<float>{0.5f, 0.25f}));
    EXPECT_EQ(g->morphWeights(), (std::vector<float>{0.5f, 0.25f}));
    EXPECT_TRUE(g->posed());
    EXPECT_TRUE(s.warnings.empty()) << s.warnings[0];
}

TEST(GltfMorph, NodeWeightsOverrideAndEachNodeHasItsOwnGeometry) {
    Doc d;
    d.twoTargets();
    d.j["nodes"].push_back({{"mesh", 0}, {"weights", {1.0, 0.0}}});
    d.j["scenes"][0]["nodes"] = json::array({0, 1});
    const GltfScene s = d.load();
    ASSERT_EQ(s.root->numChildren(), 2u);
    const Geometry *g0 = geometryBelow(*s.root->child(0)), *g1 = geometryBelow(*s.root->child(1));
    ASSERT_TRUE(g0 && g1);
    EXPECT_NE(g0, g1);                  // each node's weights are its own
    EXPECT_EQ(g0->mesh(), g1->mesh());  // the mesh is shared
    EXPECT_EQ(g0->morphWeights(), (std::vector<float>{0.5f, 0.25f}));
    EXPECT_EQ(g1->morphWeights(), (std::vector<float>{1.0f, 0.0f}));
}

TEST(GltfMorph, ASparseTargetIsReadDense) {
    Doc d;
    const int idx = d.view(bytesOf(std::vector<uint16_t>{2})),
              values = d.view(bytesOf(std::vector<float>{0.5f, 0.5f, 0}));
    d.j["accessors"].push_back({{"componentType", kFloat},
                                {"count", 3},
                                {"type", "VEC3"},
                                {"sparse",
                                 {{"count", 1},
                                  {"indices", {{"bufferView", idx}, {"componentType", kUShort}}},
                                  {"values", {{"bufferView", values}}}}}});
    d.prim()["targets"] = json::array({{{"POSITION", d.j["accessors"].size() - 1}}});
    const GltfScene s = d.load();
    const Geometry* g = geometryBelow(*s.root->child(0));
    ASSERT_TRUE(g && g->mesh()->morphTargets().size() == 1);
    EXPECT_EQ(g->mesh()->morphTargets()[0].positions, (std::vector<vec3>{vec3(0), vec3(0), vec3(0.5f, 0.5f, 0)}));
    EXPECT_TRUE(g->morphWeights().empty());  // neither the node nor the mesh gives weights: zeros
}

// KHR_mesh_quantization: a POSITION target of normalized shorts and a NORMAL target of normalized bytes, each element
// padded to 4-byte alignment.
TEST(GltfMorph, QuantizedTargets) {
    Doc d;
    d.uses("KHR_mesh_quantization", true);
    const int pv = d.view(bytesOf(std::vector<int16_t>{32767, 0, -32767, 0, 0, 0, 0, 0, 0, 16384, 0, 0}), 8);
    const int nv = d.view(bytesOf(std::vector<int8_t>{127, 0, 0, 0, 0, -127, 0, 0, 0, 0, 127, 0}), 4);
    const int p = d.accessor(pv, kShort, 3, "VEC3", true), n = d.accessor(nv, kByte, 3, "VEC3", true);
    d.prim()["targets"] = json::array({{{"POSITION", p}, {"NORMAL", n}}});
    const GltfScene s = d.load();
    const Geometry* g = geometryBelow(*s.root->child(0));
    ASSERT_TRUE(g && g->mesh()->morphTargets().size() == 1);
    const MorphTarget& t = g->mesh()->morphTargets()[0];
    EXPECT_EQ(t.positions[0], vec3(1, 0, -1));
    EXPECT_EQ(t.positions[1], vec3(0));
    EXPECT_NEAR(t.positions[2].y, 16384.0f / 32767.0f, 1e-7);
    EXPECT_EQ(t.normals[0], vec3(1, 0, 0));
    EXPECT_EQ(t.normals[1], vec3(0, -1, 0));
    EXPECT_EQ(t.normals[2], vec3(0, 0, 1));
}

TEST(GltfMorph, QuantizedTargetsWithoutTheExtensionAreRefused) {
    Doc d;
    const int pv = d.view(bytesOf(std::vector<int16_t>(12, 0)), 8);
    d.prim()["targets"] = json::array({{{"POSITION", d.accessor(pv, kShort, 3, "VEC3", true)}}});
    expectRefused(d, kPrim + ".targets[0].POSITION", "is not VEC3 of floats");
}

TEST(GltfMorph, PrimitivesDifferingOnlyInTargetsDoNotShareAMesh) {
    Doc d;
    const int a = d.vectors({0, 0, 1, 0, 0, 1, 0, 0, 1}), b = d.vectors({1, 0, 0, 1, 0, 0, 1, 0, 0});
    auto prim = [&](int target) {
        return json{{"attributes", {{"POSITION", d.pos}}}, {"targets", {{{"POSITION", target}}}}};
    };
    d.j["meshes"][0]["primitives"] = json::array({prim(a), prim(b), prim(a)});
    const GltfScene s = d.load();
    const Node& node = *s.root->child(0);
    ASSERT_EQ(node.numChildren(), 3u);
    const Geometry *g0 = geometryBelow(node, 0), *g1 = geometryBelow(node, 1), *g2 = geometryBelow(node, 2);
    ASSERT_TRUE(g0 && g1 && g2);
    EXPECT_NE(g0->mesh(), g1->mesh());
    EXPECT_EQ(g0->mesh(), g2->mesh());  // the same accessors, targets included: one Mesh
    EXPECT_EQ(g1->mesh()->morphTargets()[0].positions[0], vec3(1, 0, 0));
}

TEST(GltfMorph, ATargetOfAnotherCountIsRefused) {
    Doc d;
    d.prim()["targets"] = json::array({{{"POSITION", d.vectors({0, 0, 1, 0, 0, 1})}}});
    expectRefused(d, kPrim + ".targets[0].POSITION", "count 2 differs from the primitive's 3 vertices");
}

TEST(GltfMorph, ATargetNamingAMissingAccessorIsRefused) {
    Doc d;
    d.prim()["targets"] = json::array({{{"POSITION", 42}}});
    expectRefused(d, kPrim + ".targets[0].POSITION", "accessor 42 does not exist");
}

TEST(GltfMorph, PrimitivesOfDifferentTargetCountsAreRefused) {
    Doc d;
    d.twoTargets();
    d.j["meshes"][0]["primitives"].push_back({{"attributes", {{"POSITION", d.pos}}}, {"targets", json::array()}});
    d.j["meshes"][0]["primitives"][1]["targets"].push_back({{"POSITION", d.pos}});
    expectRefused(d, "meshes[0].primitives[1].targets", "1 morph targets, primitives[0] has 2");
}

TEST(GltfMorph, NodeWeightsOfAnotherLengthAreRefused) {
    Doc d;
    d.twoTargets();
    d.j["nodes"][0]["weights"] = json::array({1.0});
    expectRefused(d, "nodes[0].weights", "1 weights for the 2 morph targets");
}

TEST(GltfMorph, MeshWeightsOfAnotherLengthAreRefused) {
    Doc d;
    d.twoTargets();
    d.j["meshes"][0]["weights"] = json::array({1.0, 0.0, 0.0});
    expectRefused(d, "meshes[0].weights", "3 weights for 2 morph targets");
}

// AnimatedMorphCube (Khronos' sample, in Debian's assimp-testmodels): two targets of positions, normals and tangents.
TEST(GltfMorph, ThirdPartyAnimatedMorphCubeHasItsTargets) {
    const std::string file =
        "/usr/share/assimp/models/glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf";
    if (!std::filesystem::exists(file)) SG_SKIP_OR_FAIL(file << " absent: install assimp-testmodels");
    const GltfScene s = loadGltf(file);
    ASSERT_EQ(s.root->numChildren(), 1u);
    const Geometry* g = geometryBelow(*s.root->child(0));
    ASSERT_NE(g, nullptr);
    const Mesh& m = *g->mesh();
    ASSERT_EQ(m.morphTargets().size(), 2u);
    for (const MorphTarget& t : m.morphTargets()) {
        EXPECT_EQ(t.positions.size(), m.positions().size());
        EXPECT_EQ(t.normals.size(), m.positions().size());
        EXPECT_EQ(t.tangents.size(), m.positions().size());
    }
    EXPECT_EQ(m.defaultWeights, (std::vector<float>{0.0f, 0.0f}));
    EXPECT_EQ(g->morphWeights(), (std::vector<float>{0.0f, 0.0f}));
}

}  // namespace
