// glTF's physical materials and KHR_lights_punctual as the loader reads them, from hand-written files.
#include "GltfTestUtil.h"

#include "loaders/gltf/Gltf.h"
#include "nodes/Geometry.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace sg;
using gltftest::Doc;

namespace {

// A 1x1 RGBA PNG, for materials that need an image.
const char* const kPng =
    "data:image/png;base64,"
    "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR4nGP43+DwHwAHAAK/K9fH4gAAAABJRU5ErkJggg==";

Geometry* firstGeometry(Node& n) {
    if (n.kind() == NodeKind::Geometry) return static_cast<Geometry*>(&n);
    for (size_t i = 0; i < n.numChildren(); ++i)
        if (Geometry* g = firstGeometry(*n.child(i))) return g;
    return nullptr;
}

bool hasWarning(const GltfScene& s, const std::string& part) {
    for (const std::string& w : s.warnings)
        if (w.find(part) != std::string::npos) return true;
    return false;
}

}  // namespace

TEST(GltfMaterials, MetallicRoughnessFactorsMapsAndTextureTransform) {
    Doc d;
    d.json = std::string(R"("scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
        "images": [{"uri": ")") +
             kPng + R"("}], "textures": [{"source": 0}],
        "extensionsUsed": ["KHR_texture_transform", "KHR_materials_emissive_strength"],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.25, 1, 0.5], "metallicFactor": 0.3,
            "roughnessFactor": 0.7, "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform":
                {"offset": [0.25, -0.5], "rotation": 0.5, "scale": [2, 3], "texCoord": 1}}},
            "metallicRoughnessTexture": {"index": 0}},
          "normalTexture": {"index": 0, "scale": 0.5}, "occlusionTexture": {"index": 0, "strength": 0.25},
          "emissiveTexture": {"index": 0}, "emissiveFactor": [1, 0.5, 0.25],
          "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}},
          "alphaMode": "BLEND", "doubleSided": true}])";
    const GltfScene s = d.load();
    Geometry* g = firstGeometry(*s.root);
    ASSERT_NE(g, nullptr);
    const Material& m = *g->material();
    EXPECT_TRUE(m.physical);
    EXPECT_EQ(m.baseColor, vec4(0.5f, 0.25f, 1.0f, 0.5f));
    EXPECT_FLOAT_EQ(m.pbr.metallic, 0.3f);
    EXPECT_FLOAT_EQ(m.pbr.roughness, 0.7f);
    EXPECT_TRUE(m.texture && m.pbr.metallicRoughness.texture && m.pbr.normal.texture && m.pbr.occlusion.texture &&
                m.pbr.emissive.texture);
    EXPECT_FLOAT_EQ(m.pbr.normalScale, 0.5f);
    EXPECT_FLOAT_EQ(m.pbr.occlusionStrength, 0.25f);
    EXPECT_EQ(m.pbr.emissiveFactor, vec3(4.0f, 2.0f, 1.0f));
    EXPECT_TRUE(m.blend);
    EXPECT_TRUE(m.doubleSided);
    EXPECT_EQ(m.texCoord, 1);  // the extension's texCoord overrides the reference's
    // u' = sx u cos r + sy v sin r + ox, v' = -sx u sin r + sy v cos r + oy (as three.js and cesium-native apply it).
    for (const vec2 uv : {vec2(0, 0), vec2(1, 0), vec2(0, 1), vec2(0.3f, 0.8f)}) {
        const double c = std::cos(0.5), s = std::sin(0.5);
        const vec2 got = vec2(m.textureTransform * vec3(uv, 1.0f));
        EXPECT_NEAR(got.x, 2 * uv.x * c + 3 * uv.y * s + 0.25, 1e-6);
        EXPECT_NEAR(got.y, -2 * uv.x * s + 3 * uv.y * c - 0.5, 1e-6);
    }
}

TEST(GltfMaterials, DefaultsAreSingleSidedOpaqueAndUnlitIsKept) {
    Doc d;
    d.json = R"("scenes": [{"nodes": [0, 1]}], "nodes": [{"mesh": 0}, {"mesh": 1}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]},
                   {"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 1}]}],
        "extensionsUsed": ["KHR_materials_unlit"],
        "materials": [{}, {"extensions": {"KHR_materials_unlit": {}}, "alphaMode": "MASK", "alphaCutoff": 0.25}])";
    const GltfScene s = d.load();
    const Material& plain = *firstGeometry(*s.root->child(0))->material();
    const Material& unlit = *firstGeometry(*s.root->child(1))->material();
    EXPECT_TRUE(plain.physical);
    EXPECT_FALSE(plain.doubleSided);
    EXPECT_FALSE(plain.blend);
    EXPECT_FLOAT_EQ(plain.pbr.metallic, 1.0f);  // glTF's defaults
    EXPECT_FLOAT_EQ(plain.pbr.roughness, 1.0f);
    EXPECT_TRUE(unlit.unlit);
    EXPECT_FLOAT_EQ(unlit.alphaCutoff, 0.25f);
}

TEST(GltfMaterials, PunctualLightsArePlacedByTheirNodes) {
    Doc d;
    // The spot's node is turned a quarter about X (its -Z to -Y, straight down) under a parent at (1, 2, 3).
    d.json = R"("scenes": [{"nodes": [0, 1, 3]}],
        "nodes": [{"extensions": {"KHR_lights_punctual": {"light": 0}}},
                  {"translation": [1, 2, 3], "children": [2]},
                  {"rotation": [-0.7071067811865476, 0, 0, 0.7071067811865476], "translation": [0, 4, 0],
                   "extensions": {"KHR_lights_punctual": {"light": 2}}},
                  {"translation": [-5, 0, 0], "extensions": {"KHR_lights_punctual": {"light": 1}}}],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "directional", "color": [1, 0.5, 0.25], "intensity": 3},
            {"type": "point", "intensity": 20, "range": 7},
            {"type": "spot", "intensity": 50, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}}]}})";
    const GltfScene s = d.load();
    ASSERT_EQ(s.lights.size(), 3u) << (s.warnings.empty() ? "" : s.warnings.front());
    const PunctualLight& sun = s.lights[0];
    EXPECT_EQ(sun.type, PunctualLight::Type::Directional);
    EXPECT_EQ(sun.direction, vec3(0, 0, -1));
    EXPECT_EQ(sun.color, vec3(1.0f, 0.5f, 0.25f));
    EXPECT_FLOAT_EQ(sun.intensity, 3.0f);
    const PunctualLight& spot = s.lights[1];  // nodes in scene order, depth first
    EXPECT_EQ(spot.type, PunctualLight::Type::Spot);
    EXPECT_NEAR(spot.position.x, 1.0, 1e-12);
    EXPECT_NEAR(spot.position.y, 6.0, 1e-12);
    EXPECT_NEAR(spot.position.z, 3.0, 1e-12);
    EXPECT_NEAR(spot.direction.y, -1.0f, 1e-6f);
    EXPECT_FLOAT_EQ(spot.innerConeAngle, 0.2f);
    EXPECT_FLOAT_EQ(spot.outerConeAngle, 0.5f);
    const PunctualLight& point = s.lights[2];
    EXPECT_EQ(point.type, PunctualLight::Type::Point);
    EXPECT_EQ(point.position, dvec3(-5, 0, 0));
    EXPECT_FLOAT_EQ(point.range, 7.0f);
    EXPECT_EQ(point.color, vec3(1.0f));
}

TEST(GltfMaterials, LightsOutsideTheExtensionsRangesAreWarningsNotRefusals) {
    Doc d;
    d.json = R"("scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [{"extensions": {"KHR_lights_punctual": {"light": 0}}},
                  {"extensions": {"KHR_lights_punctual": {"light": 1}}},
                  {"extensions": {"KHR_lights_punctual": {"light": 7}}},
                  {"extensions": {"KHR_lights_punctual": {"light": 2}}}],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "area"},
            {"type": "spot", "spot": {"innerConeAngle": 0.6, "outerConeAngle": 0.5}},
            {"type": "point", "intensity": -1}]}})";
    const GltfScene s = d.load();
    EXPECT_TRUE(s.lights.empty());
    EXPECT_TRUE(hasWarning(s, "lights[0]: unknown type 'area'"));
    EXPECT_TRUE(hasWarning(s, "lights[1]: spot cone"));
    EXPECT_TRUE(hasWarning(s, "nodes[2].extensions.KHR_lights_punctual.light: not the index of a light"));
    EXPECT_TRUE(hasWarning(s, "lights[2]: intensity"));
}
