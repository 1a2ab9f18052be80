// glTF animations and KHR_animation_pointer as the loader reads them, from files written here: samplers as floats,
// channels bound to the nodes built, material, light and camera pointers, and the LoadErrors of bad animations.
#include "GltfDoc.h"

#include "loaders/gltf/Gltf.h"
#include "nodes/Geometry.h"
#include "nodes/Transform.h"
#include "sg/scene/AnimationPlayer.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

using namespace sg;
using gltftest::bytesOf;
using nlohmann::json;

namespace {

constexpr int kFloat = 5126, kShort = 5122;
const char* const kPointer = "KHR_animation_pointer";

// One node over a one-triangle mesh (with material 0, all white, when asked), and the test's keys as accessors.
struct AnimDoc : gltftest::GltfDoc {
    explicit AnimDoc(const char* primitives = R"([{"attributes": {"POSITION": 0}}])") : GltfDoc(primitives) {
        floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
    }
    int floats(const std::vector<float>& v, const char* type, size_t count) {
        return accessor(view(bytesOf(v)), kFloat, count, type);
    }
    // An animation of one sampler and one channel on `target` (JSON); returns its index.
    size_t animate(int input, int output, const char* target, const char* interpolation = "LINEAR") {
        json a = json::parse(R"({"samplers": [{}], "channels": [{"sampler": 0}]})");
        a["samplers"][0]["input"] = input;
        a["samplers"][0]["output"] = output;
        a["samplers"][0]["interpolation"] = interpolation;
        a["channels"][0]["target"] = json::parse(target);
        j["animations"].push_back(a);
        return j["animations"].size() - 1;
    }
};

std::string pointerTarget(const std::string& pointer) {
    return R"({"path": "pointer", "extensions": {"KHR_animation_pointer": {"pointer": ")" + pointer + R"("}}})";
}

bool hasWarning(const GltfScene& s, const std::string& part) {
    for (const std::string& w : s.warnings)
        if (w.find(part) != std::string::npos) return true;
    return false;
}

}  // namespace

TEST(GltfAnimation, TranslationLinearBoundToTheNodesTransform) {
    AnimDoc d;
    d.animate(d.floats({0, 1}, "SCALAR", 2), d.floats({0, 0, 0, 2, 4, 6}, "VEC3", 2),
              R"({"node": 0, "path": "translation"})");
    const GltfScene s = d.load();
    ASSERT_EQ(s.animations.size(), 1u);
    const Animation& a = *s.animations[0];
    ASSERT_EQ(a.samplers.size(), 1u);
    ASSERT_EQ(a.channels.size(), 1u);
    EXPECT_EQ(a.samplers[0].times, (std::vector<float>{0, 1}));
    EXPECT_EQ(a.samplers[0].values, (std::vector<float>{0, 0, 0, 2, 4, 6}));
    EXPECT_EQ(a.samplers[0].width, 3u);
    EXPECT_EQ(a.samplers[0].interpolation, Interpolation::Linear);
    EXPECT_EQ(a.channels[0].sampler, 0u);
    EXPECT_EQ(a.channels[0].path, AnimationPath::Translation);
    ASSERT_EQ(s.root->child(0)->kind(), NodeKind::Transform);
    EXPECT_EQ(a.channels[0].node.get(), s.root->child(0));
    EXPECT_EQ(s.animatedLights, nullptr);
    EXPECT_EQ(s.animatedCameras, nullptr);
}

TEST(GltfAnimation, RotationStep) {
    AnimDoc d;
    d.animate(d.floats({0.5f, 1.5f}, "SCALAR", 2), d.floats({0, 0, 0, 1, 0, 0, 1, 0}, "VEC4", 2),
              R"({"node": 0, "path": "rotation"})", "STEP");
    const GltfScene s = d.load();
    ASSERT_EQ(s.animations.size(), 1u);
    const Animation& a = *s.animations[0];
    ASSERT_EQ(a.channels.size(), 1u);
    EXPECT_EQ(a.channels[0].path, AnimationPath::Rotation);
    EXPECT_EQ(a.samplers[0].interpolation, Interpolation::Step);
    EXPECT_EQ(a.samplers[0].width, 4u);
    EXPECT_EQ(a.samplers[0].times, (std::vector<float>{0.5f, 1.5f}));
    EXPECT_EQ(a.samplers[0].values, (std::vector<float>{0, 0, 0, 1, 0, 0, 1, 0}));
}

TEST(GltfAnimation, CubicSplineHoldsThreeValuesAKey) {
    AnimDoc d;
    std::vector<float> v(18);
    for (size_t k = 0; k < v.size(); ++k) v[k] = float(k);
    d.animate(d.floats({0, 1}, "SCALAR", 2), d.floats(v, "VEC3", 6), R"({"node": 0, "path": "scale"})", "CUBICSPLINE");
    const GltfScene s = d.load();
    ASSERT_EQ(s.animations.size(), 1u);
    const AnimationSampler& smp = s.animations[0]->samplers[0];
    EXPECT_EQ(smp.interpolation, Interpolation::CubicSpline);
    EXPECT_EQ(smp.width, 3u);
    EXPECT_EQ(smp.values, v);
    EXPECT_EQ(s.animations[0]->channels[0].path, AnimationPath::Scale);

    AnimDoc two;  // two keys of a spline need 6 outputs (in-tangent, value, out-tangent each), not 2
    two.animate(two.floats({0, 1}, "SCALAR", 2), two.floats({0, 0, 0, 1, 1, 1}, "VEC3", 2),
                R"({"node": 0, "path": "scale"})", "CUBICSPLINE");
    EXPECT_EQ(two.refusal().first, "animations[0].samplers[0].output");
}

TEST(GltfAnimation, NormalizedShortRotationsAreConverted) {
    AnimDoc d;
    // glTF: max(c / 32767, -1).
    const std::vector<int16_t> q{0, 0, 32767, -32767, 0, -32768, 0, 32767};
    const int out = d.accessor(d.view(bytesOf(q)), kShort, 2, "VEC4", true);
    d.animate(d.floats({0, 1}, "SCALAR", 2), out, R"({"node": 0, "path": "rotation"})");
    const GltfScene s = d.load();
    ASSERT_EQ(s.animations.size(), 1u);
    EXPECT_EQ(s.animations[0]->samplers[0].values, (std::vector<float>{0, 0, 1, -1, 0, -1, 0, 1}));

    AnimDoc plain;  // integers that are not normalized make no rotation
    const int raw = plain.accessor(plain.view(bytesOf(q)), kShort, 2, "VEC4", false);
    plain.animate(plain.floats({0, 1}, "SCALAR", 2), raw, R"({"node": 0, "path": "rotation"})");
    EXPECT_EQ(plain.refusal().first, "animations[0].samplers[0].output");
}

TEST(GltfAnimation, WeightsDriveTheNodesGeometries) {
    AnimDoc d(R"([{"attributes": {"POSITION": 0}, "targets": [{"POSITION": 0}, {"POSITION": 0}]}])");
    d.animate(d.floats({0, 1}, "SCALAR", 2), d.floats({0, 1, 1, 0}, "SCALAR", 4), R"({"node": 0, "path": "weights"})");
    const GltfScene s = d.load();
    ASSERT_EQ(s.animations.size(), 1u);
    const Animation& a = *s.animations[0];
    ASSERT_EQ(a.channels.size(), 1u);  // one primitive: one Geometry
    EXPECT_EQ(a.channels[0].path, AnimationPath::Weights);
    EXPECT_EQ(a.samplers[0].width, 2u);  // the mesh's two targets
    Node* node = s.root->child(0);
    ASSERT_EQ(node->numChildren(), 1u);
    EXPECT_EQ(node->child(0)->kind(), NodeKind::Geometry);
    EXPECT_EQ(a.channels[0].node.get(), node->child(0));
}

TEST(GltfAnimation, TwoAnimationsInTheFilesOrder) {
    AnimDoc d;
    const int in = d.floats({0, 2}, "SCALAR", 2);
    d.animate(in, d.floats({0, 0, 0, 1, 1, 1}, "VEC3", 2), R"({"node": 0, "path": "translation"})");
    d.animate(in, d.floats({1, 1, 1, 2, 2, 2}, "VEC3", 2), R"({"node": 0, "path": "scale"})");
    d.j["animations"][0]["name"] = "walk";
    d.j["animations"][1]["name"] = "grow";
    const GltfScene s = d.load();
    ASSERT_EQ(s.animations.size(), 2u);
    EXPECT_EQ(s.animations[0]->name, "walk");
    EXPECT_EQ(s.animations[1]->name, "grow");
    EXPECT_EQ(s.animations[0]->channels[0].path, AnimationPath::Translation);
    EXPECT_EQ(s.animations[1]->channels[0].path, AnimationPath::Scale);
    EXPECT_EQ(s.animations[1]->samplers[0].values, (std::vector<float>{1, 1, 1, 2, 2, 2}));
}

TEST(GltfAnimation, MaterialPointerGivesTheGeometryAChangedCopy) {
    AnimDoc d(R"([{"attributes": {"POSITION": 0}, "material": 0}])");
    d.j["materials"] = json::parse(R"([{"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1]}}])");
    d.uses(kPointer, true);  // required: still loaded
    const std::string pointer = "/materials/0/pbrMetallicRoughness/baseColorFactor";
    d.animate(d.floats({0, 1}, "SCALAR", 2), d.floats({1, 0, 0, 1, 0, 0, 1, 1}, "VEC4", 2),
              pointerTarget(pointer).c_str());
    const GltfScene s = d.load(true);  // a .glb: its channels are read again from the JSON chunk
    ASSERT_EQ(s.animations.size(), 1u);
    ASSERT_EQ(s.animations[0]->channels.size(), 1u);
    EXPECT_EQ(s.animations[0]->channels[0].path, AnimationPath::Property);
    EXPECT_EQ(s.animations[0]->channels[0].target, pointer);
    auto* g = static_cast<Geometry*>(s.root->child(0)->child(0));
    const ref_ptr<Material> before(g->material());
    ASSERT_TRUE(before);

    AnimationPlayer player;
    player.add(s.animations[0]);
    player.play(0);
    player.advance(0.5);
    const Material* after = g->material();
    ASSERT_NE(after, before.get());
    EXPECT_NEAR(after->baseColor.r, 0.5f, 1e-6f);
    EXPECT_NEAR(after->baseColor.g, 0.0f, 1e-6f);
    EXPECT_NEAR(after->baseColor.b, 0.5f, 1e-6f);
    EXPECT_NEAR(after->baseColor.a, 1.0f, 1e-6f);
    EXPECT_TRUE(after->physical);
    EXPECT_NE(after->id(), before->id());
    EXPECT_EQ(before->baseColor, vec4(1.0f));  // the file's material is not changed in place
}

TEST(GltfAnimation, LightAndCameraPointersMoveTheirCopies) {
    AnimDoc d;
    d.uses(kPointer, false);
    d.uses("KHR_lights_punctual", false);
    d.j["cameras"] = json::parse(R"([{"type": "perspective", "perspective": {"yfov": 1.0, "znear": 0.1}}])");
    d.j["nodes"][0]["camera"] = 0;
    d.j["extensions"]["KHR_lights_punctual"]["lights"] = json::parse(R"([{"type": "point", "intensity": 2}])");
    d.j["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0;
    const int in = d.floats({0, 2}, "SCALAR", 2);
    d.animate(in, d.floats({1.0f, 1.5f}, "SCALAR", 2), pointerTarget("/cameras/0/perspective/yfov").c_str());
    d.animate(in, d.floats({2, 6}, "SCALAR", 2),
              pointerTarget("/extensions/KHR_lights_punctual/lights/0/intensity").c_str());
    const GltfScene s = d.load();
    ASSERT_EQ(s.animations.size(), 2u);
    ASSERT_TRUE(s.animatedCameras);
    ASSERT_TRUE(s.animatedLights);
    ASSERT_EQ(s.animatedCameras->size(), 1u);
    ASSERT_EQ(s.animatedLights->size(), 1u);
    ASSERT_EQ(s.animations[0]->channels.size(), 1u);
    ASSERT_EQ(s.animations[1]->channels.size(), 1u);

    const double yfov = 1.5, intensity = 6.0;
    s.animations[0]->channels[0].set(&yfov, 1);
    s.animations[1]->channels[0].set(&intensity, 1);
    EXPECT_NEAR((*s.animatedCameras)[0].yfovDegrees, 1.5 * 180.0 / 3.14159265358979323846, 1e-9);
    EXPECT_FLOAT_EQ((*s.animatedLights)[0].intensity, 6.0f);
    EXPECT_NEAR(s.cameras[0].yfovDegrees, 180.0 / 3.14159265358979323846, 1e-9);  // the scene's own lists stay
    EXPECT_FLOAT_EQ(s.lights[0].intensity, 2.0f);
}

TEST(GltfAnimation, UnsupportedPointerIsSkippedWithAWarning) {
    AnimDoc d(R"([{"attributes": {"POSITION": 0}, "material": 0}])");
    d.j["materials"] = json::parse(R"([{}])");
    d.uses(kPointer, false);
    d.animate(d.floats({0, 1}, "SCALAR", 2), d.floats({1, 2}, "SCALAR", 2),
              pointerTarget("/materials/0/normalTexture/scale").c_str());
    const GltfScene s = d.load();
    ASSERT_EQ(s.animations.size(), 1u);
    EXPECT_TRUE(s.animations[0]->channels.empty());
    EXPECT_TRUE(hasWarning(s, "animations[0].channels[0].target.extensions.KHR_animation_pointer.pointer"));
}

TEST(GltfAnimation, BadAnimationsAreRefusedNamingThePath) {
    const char* translation = R"({"node": 0, "path": "translation"})";
    {
        AnimDoc d;  // a node that does not exist
        d.animate(d.floats({0, 1}, "SCALAR", 2), d.floats({0, 0, 0, 1, 1, 1}, "VEC3", 2),
                  R"({"node": 5, "path": "translation"})");
        EXPECT_EQ(d.refusal().first, "animations[0].channels[0].target.node");
    }
    {
        AnimDoc d;  // times that do not increase
        d.animate(d.floats({0, 1, 1}, "SCALAR", 3), d.floats({0, 0, 0, 1, 1, 1, 2, 2, 2}, "VEC3", 3), translation);
        EXPECT_EQ(d.refusal().first, "animations[0].samplers[0].input");
    }
    {
        AnimDoc d;  // 3 keys, 2 values
        d.animate(d.floats({0, 1, 2}, "SCALAR", 3), d.floats({0, 0, 0, 1, 1, 1}, "VEC3", 2), translation);
        EXPECT_EQ(d.refusal().first, "animations[0].samplers[0].output");
    }
    {
        AnimDoc d;  // a sampler past the animation's
        d.animate(d.floats({0, 1}, "SCALAR", 2), d.floats({0, 0, 0, 1, 1, 1}, "VEC3", 2), translation);
        d.j["animations"][0]["channels"][0]["sampler"] = 3;
        EXPECT_EQ(d.refusal().first, "animations[0].channels[0].sampler");
    }
    {
        AnimDoc d;  // a translation of VEC4s
        d.animate(d.floats({0, 1}, "SCALAR", 2), d.floats({0, 0, 0, 0, 1, 1, 1, 1}, "VEC4", 2), translation);
        EXPECT_EQ(d.refusal().first, "animations[0].samplers[0].output");
    }
    {
        AnimDoc d;  // a pointer to a node that does not exist
        d.uses(kPointer, false);
        d.animate(d.floats({0, 1}, "SCALAR", 2), d.floats({0, 0, 0, 1, 1, 1}, "VEC3", 2),
                  pointerTarget("/nodes/7/translation").c_str());
        EXPECT_EQ(d.refusal().first, "animations[0].channels[0].target.extensions.KHR_animation_pointer.pointer");
    }
}
