// saveGltf's motion: skins, morph targets and animations written and read back (loadGltf) as they were, and what
// glTF cannot hold left out with a warning; KHR_animation_pointer channels and animated Transforms as the file has
// them.
#include "GltfMotionScene.h"

#include "loaders/gltf/Gltf.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

using namespace sg;
using namespace gltftest;
using json = nlohmann::json;

namespace {

std::string tempPath(const std::string& name) { return ::testing::TempDir() + "sgkit_gltf_motion_" + name; }

std::string readText(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

// The JSON of a .gltf, or of a .glb's JSON chunk (its lengths checked against the file).
json fileJson(const std::string& path) {
    const std::string bytes = readText(path);
    if (path.substr(path.size() - 4) != ".glb") return json::parse(bytes);
    uint32_t total = 0, length = 0;
    EXPECT_GE(bytes.size(), 20u);
    if (bytes.size() < 20) return {};
    std::memcpy(&total, bytes.data() + 8, 4);
    std::memcpy(&length, bytes.data() + 12, 4);
    EXPECT_EQ(total, bytes.size());
    EXPECT_EQ(length % 4, 0u);
    EXPECT_LE(20 + size_t(length), bytes.size());
    return json::parse(bytes.substr(20, length));
}

const Node* findNamed(const Node& n, const std::string& name) {
    if (n.name() == name) return &n;
    for (size_t i = 0; i < n.numChildren(); ++i)
        if (const Node* c = n.child(i))
            if (const Node* f = findNamed(*c, name)) return f;
    return nullptr;
}

std::string joined(const std::vector<std::string>& v) {
    std::string s;
    for (const std::string& x : v) s += x + "\n";
    return s;
}

void expectSkinned(const GltfScene& s, const std::string& name, int influences) {
    SCOPED_TRACE(name);
    const auto* g = static_cast<const Geometry*>(findNamed(*s.root, name));
    ASSERT_TRUE(g);
    ASSERT_EQ(g->kind(), NodeKind::Geometry);
    const Skin* skin = g->skin();
    ASSERT_TRUE(skin);
    ASSERT_EQ(skin->size(), 8u);
    ASSERT_EQ(skin->inverseBind().size(), 8u);
    for (int k = 0; k < 8; ++k) {
        EXPECT_EQ(skin->joints()[size_t(k)].get(), findNamed(*s.root, "joint" + std::to_string(k))) << k;
        EXPECT_EQ(skin->inverseBind()[size_t(k)], glm::translate(dmat4(1.0), dvec3(0, -k, 0))) << k;
    }
    ASSERT_TRUE(g->mesh());
    EXPECT_EQ(g->mesh()->influences(), influences);
    EXPECT_EQ(g->mesh()->joints(), motionJoints(influences));
    EXPECT_EQ(g->mesh()->weights(), motionWeights(influences));
}

TEST(GltfMotionRoundTrip, SkinsMorphTargetsAndAnimationsSurvive) {
    for (const char* ext : {".glb", ".gltf"}) {
        SCOPED_TRACE(ext);
        const MotionScene scene = motionScene();
        std::vector<std::string> warnings;
        GltfSaveOptions options;
        options.animations = {scene.animation};
        options.warnings = &warnings;
        const std::string path = tempPath(std::string("scene") + ext);
        saveGltf(*scene.root, path, options);
        EXPECT_TRUE(warnings.empty()) << joined(warnings);
        const GltfScene s = loadGltf(path);

        expectSkinned(s, "skinned4", 4);
        expectSkinned(s, "skinned8", 8);

        const auto* morphed = static_cast<const Geometry*>(findNamed(*s.root, "morphed"));
        ASSERT_TRUE(morphed && morphed->kind() == NodeKind::Geometry && morphed->mesh());
        const std::vector<MorphTarget>& targets = morphed->mesh()->morphTargets();
        const std::vector<MorphTarget> expected = motionTargets();
        ASSERT_EQ(targets.size(), 2u);
        for (size_t t = 0; t < 2; ++t) {
            EXPECT_EQ(targets[t].positions, expected[t].positions) << t;
            EXPECT_EQ(targets[t].normals, expected[t].normals) << t;
        }
        EXPECT_EQ(morphed->mesh()->defaultWeights, (std::vector<float>{0.25f, 0.5f}));
        EXPECT_EQ(morphed->morphWeights(), (std::vector<float>{0.5f, 0.75f}));
        ASSERT_TRUE(findNamed(*s.root, "holder"));
        EXPECT_EQ(findNamed(*findNamed(*s.root, "holder"), "morphed"), morphed);  // where it was

        ASSERT_EQ(s.animations.size(), 1u);
        const Animation& a = *s.animations[0];
        EXPECT_EQ(a.name, "motion");
        const Animation& was = *scene.animation;
        ASSERT_EQ(a.channels.size(), was.channels.size());
        for (size_t i = 0; i < a.channels.size(); ++i) {
            SCOPED_TRACE("channel " + std::to_string(i));
            const AnimationChannel& c = a.channels[i];
            EXPECT_EQ(c.path, was.channels[i].path);
            EXPECT_EQ(c.node.get(), findNamed(*s.root, was.channels[i].node->name()));
            ASSERT_LT(c.sampler, a.samplers.size());
            const AnimationSampler& got = a.samplers[c.sampler];
            const AnimationSampler& want = was.samplers[was.channels[i].sampler];
            EXPECT_EQ(got.times, want.times);
            EXPECT_EQ(got.values, want.values);
            EXPECT_EQ(got.width, want.width);
            EXPECT_EQ(got.interpolation, want.interpolation);
        }
    }
}

// A skin with a joint outside the graph written goes out without its skin (and the mesh without JOINTS/WEIGHTS,
// which glTF pairs with a skin); a channel on a node not written is left out, and an animation left without
// channels with it.
TEST(GltfMotionRoundTrip, WhatIsNotWrittenIsLeftOutWithAWarning) {
    MotionScene scene = motionScene();
    auto outside = make<Transform>(glm::translate(dmat4(1.0), dvec3(0, 1, 0)));
    outside->setName("outside");
    std::vector<ref_ptr<Node>> joints(scene.joints.begin(), scene.joints.end());
    joints[7] = outside;
    auto skin = make<Skin>(joints);
    skin->name = "partial";
    scene.skinned8->setSkin(skin);
    auto lost = make<Animation>();
    lost->name = "lost";
    lost->samplers.push_back(scene.animation->samplers[0]);
    AnimationChannel c;
    c.path = AnimationPath::Translation;
    c.node = outside;
    lost->channels.push_back(c);

    std::vector<std::string> warnings;
    GltfSaveOptions options;
    options.animations = {scene.animation, lost};
    options.warnings = &warnings;
    const std::string path = tempPath("partial.gltf");
    saveGltf(*scene.root, path, options);
    const std::string all = joined(warnings);
    EXPECT_NE(all.find("skin 'partial': joints[7] ('outside') is not below the root written"), std::string::npos)
        << all;
    EXPECT_NE(all.find("animations[1] 'lost'.channels[0]: its node 'outside' is not below the root written"),
              std::string::npos)
        << all;

    json j = fileJson(path);                // not const: a missing member reads as null
    ASSERT_EQ(j["animations"].size(), 1u);  // "motion" alone
    EXPECT_EQ(j["animations"][0]["name"], "motion");
    ASSERT_EQ(j["skins"].size(), 1u);  // the full skeleton of skinned4
    for (json& n : j["nodes"]) {
        if (n.value("name", "") == "skinned8") {
            EXPECT_FALSE(n.contains("skin"));
            ASSERT_TRUE(n.contains("mesh"));
            json& attributes = j["meshes"][n["mesh"].get<size_t>()]["primitives"][0]["attributes"];
            EXPECT_FALSE(attributes.contains("JOINTS_0"));
            EXPECT_FALSE(attributes.contains("WEIGHTS_0"));
        } else if (n.value("name", "") == "skinned4") {
            EXPECT_EQ(n["skin"], 0);
            json& attributes = j["meshes"][n["mesh"].get<size_t>()]["primitives"][0]["attributes"];
            EXPECT_TRUE(attributes.contains("JOINTS_0") && attributes.contains("WEIGHTS_0"));
            EXPECT_FALSE(attributes.contains("JOINTS_1"));
        }
    }
}

// A property channel whose target is a pointer goes out as KHR_animation_pointer (no node, path "pointer"); one
// without is left out. An animated Transform is written as translation, rotation and scale, never as a matrix.
TEST(GltfMotionRoundTrip, PointersAndAnimatedTransformsAsGltfWantsThem) {
    MotionScene scene = motionScene();
    scene.joints[2]->setMatrix(
        glm::scale(glm::rotate(glm::translate(dmat4(1.0), dvec3(0, 1, 0)), 0.5, dvec3(0, 0, 1)), dvec3(2.0)));
    AnimationSampler colour;
    colour.times = {0, 1};
    colour.values = {1, 1, 1, 1, 1, 0, 0, 1};
    colour.width = 4;
    scene.animation->samplers.push_back(colour);
    for (const char* target : {"/materials/0/pbrMetallicRoughness/baseColorFactor", "a setter without a pointer"}) {
        AnimationChannel c;
        c.sampler = uint32_t(scene.animation->samplers.size() - 1);
        c.path = AnimationPath::Property;
        c.set = [](const double*, uint32_t) {};
        c.target = target;
        scene.animation->channels.push_back(c);
    }
    for (const char* ext : {".gltf", ".glb"}) {
        SCOPED_TRACE(ext);
        std::vector<std::string> warnings;
        GltfSaveOptions options;
        options.animations = {scene.animation};
        options.warnings = &warnings;
        const std::string path = tempPath(std::string("pointer") + ext);
        saveGltf(*scene.root, path, options);
        ASSERT_EQ(warnings.size(), 1u) << joined(warnings);
        EXPECT_NE(warnings[0].find("channels[5]: a property channel without a KHR_animation_pointer"),
                  std::string::npos)
            << warnings[0];
        json j = fileJson(path);  // not const: a missing member reads as null
        EXPECT_NE(std::find(j["extensionsUsed"].begin(), j["extensionsUsed"].end(), "KHR_animation_pointer"),
                  j["extensionsUsed"].end());
        json& channels = j["animations"][0]["channels"];
        ASSERT_EQ(channels.size(), 5u);
        json& target = channels[4]["target"];
        EXPECT_FALSE(target.contains("node")) << target;
        EXPECT_EQ(target["path"], "pointer");
        EXPECT_EQ(target["extensions"]["KHR_animation_pointer"]["pointer"],
                  "/materials/0/pbrMetallicRoughness/baseColorFactor");
        for (size_t k = 0; k < 4; ++k) EXPECT_TRUE(channels[k]["target"].contains("node")) << k;
        json& sampler = j["animations"][0]["samplers"][channels[4]["sampler"].get<size_t>()];
        EXPECT_EQ(j["accessors"][sampler["output"].get<size_t>()]["type"], "VEC4");
        for (json& n : j["nodes"])
            if (n.value("name", "") == "joint2") {
                EXPECT_FALSE(n.contains("matrix")) << n;
                ASSERT_TRUE(n.contains("rotation") && n.contains("scale") && n.contains("translation")) << n;
                EXPECT_NEAR(n["rotation"][2].get<double>(), std::sin(0.25), 1e-6);
                EXPECT_NEAR(n["rotation"][3].get<double>(), std::cos(0.25), 1e-6);
                EXPECT_NEAR(n["scale"][0].get<double>(), 2.0, 1e-6);
                EXPECT_EQ(n["translation"][1], 1.0);
            }
    }
}

}  // namespace
