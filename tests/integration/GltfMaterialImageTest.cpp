// glTF's materials in pixels: KHR_texture_transform on Khronos' own test model, normal maps (the file's tangents or
// generated ones), and physical materials written by saveGltf and read back.
#include "GltfTestUtil.h"
#include "OutsideTools.h"
#include "RenderUtil.h"

#include "loaders/gltf/Gltf.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/io/ImageIO.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <functional>

using namespace sg;

namespace {

constexpr int kW = 200, kH = 150;

struct Frame {
    OsmesaContext context{kW, kH};
    Renderer renderer;
    Image draw(const ref_ptr<Node>& root, const Camera& cam) { return testutil::drawGraph(renderer, root, cam); }
};

Camera lookingAt(const dvec3& eye, const dvec3& center, const dvec3& up = dvec3(0, 1, 0)) {
    Camera cam;
    cam.setLookAt(eye, center, up);
    cam.setPerspective(45.0, double(kW) / kH, 0.1, 100.0);
    cam.setViewport(kW, kH);
    return cam;
}

void forEachGeometry(Node& n, const std::function<void(Geometry&)>& f) {
    if (auto* g = dynamic_cast<Geometry*>(&n)) f(*g);
    for (size_t i = 0; i < n.numChildren(); ++i) forEachGeometry(*n.child(i), f);
}

const char* const kTextureTransformModel = "/usr/share/assimp/models/glTF2/textureTransform/TextureTransformTest.gltf";

}  // namespace

TEST(GltfMaterialImage, TextureTransformDrawsAsUvsTransformedBeforehand) {
    // Khronos' KHR_texture_transform test model (offset, rotation, scale and all three): drawn as loaded, and as
    // a copy whose UVs carry the transform themselves (the material's cleared). The same pixels, and not those
    // of the model with its transforms ignored (which shows its "error" marks).
    if (!std::filesystem::exists(kTextureTransformModel)) SG_SKIP_OR_FAIL(kTextureTransformModel << " missing");
    const GltfScene loaded = loadGltf(kTextureTransformModel);
    const ref_ptr<Node> baked = loadGltf(kTextureTransformModel).root;
    const ref_ptr<Node> ignored = loadGltf(kTextureTransformModel).root;
    size_t transformed = 0;
    forEachGeometry(*baked, [&](Geometry& g) {
        const Material& m = *g.material();
        if (m.textureTransform == mat3(1.0f)) return;
        ++transformed;
        const Mesh& old = *g.mesh();
        std::vector<vec2> uvs = old.uvs();
        for (vec2& uv : uvs) uv = vec2(m.textureTransform * vec3(uv, 1.0f));
        std::vector<uint32_t> idx(old.indexCount());
        for (size_t i = 0; i < idx.size(); ++i) idx[i] = old.index(i);
        auto mesh = make<Mesh>();
        mesh->set(old.positions(), old.normals(), std::move(idx), std::move(uvs), old.colors());
        auto plain = m.copy();
        plain->textureTransform = mat3(1.0f);
        g.setMesh(mesh);
        g.setMaterial(plain);
    });
    forEachGeometry(*ignored, [](Geometry& g) {
        auto plain = g.material()->copy();
        plain->textureTransform = mat3(1.0f);
        g.setMaterial(plain);
    });
    EXPECT_EQ(transformed, 6u);  // the six transformed squares
    Frame f;
    const Camera cam = lookingAt(dvec3(0.0, 0.0, 3.6), dvec3(0.0));
    const Image a = f.draw(loaded.root, cam), b = f.draw(baked, cam), c = f.draw(ignored, cam);
    if (std::getenv("SGKIT_TEST_IMAGES")) savePng("texture_transform.png", a);
    EXPECT_LE(countDifferingPixels(a, b, 1), size_t(kW * kH / 2000));  // texel rounding on a few edges
    EXPECT_GT(countDifferingPixels(a, c, 8), size_t(kW * kH / 20));
}

namespace {

// A floor facing +Y, u along +X and v along -Z (so the tangent is +X and the bitangent, n x t, is -Z: w = +1).
ref_ptr<Mesh> floorQuad(const vec3& normal, bool withTangents) {
    auto m = make<Mesh>();
    m->set({{-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1}}, std::vector<vec3>(4, normal), {0, 1, 2, 0, 2, 3},
           {{0, 0}, {1, 0}, {1, 1}, {0, 1}});
    if (withTangents) m->setSurface(std::vector<vec4>(4, vec4(1, 0, 0, 1)), {});
    return m;
}

ref_ptr<Material> rough(const vec3& base) {
    auto m = make<Material>(vec4(base, 1.0f));
    m->physical = true;
    m->pbr.metallic = 0.0f;
    m->pbr.roughness = 0.6f;
    return m;
}

}  // namespace

TEST(GltfMaterialImage, NormalMapTiltsTheShadingNormalAsTheTangentFrameSays) {
    // A normal map of one texel value on a flat floor shades as a floor whose vertex normals are that value
    // taken through the tangent frame (t, n x t, n); with the tangents generated from the UVs as well.
    const vec3 tn = glm::normalize(vec3(0.35f, -0.25f, 0.9f));
    const auto texel = [](float c) { return uint8_t(std::lround((c * 0.5f + 0.5f) * 255.0f)); };
    const uint8_t rgba[4] = {texel(tn.x), texel(tn.y), texel(tn.z), 255};
    std::vector<uint8_t> pixels;
    for (int i = 0; i < 16; ++i) pixels.insert(pixels.end(), rgba, rgba + 4);
    const vec3 decoded = vec3(rgba[0], rgba[1], rgba[2]) / 255.0f * 2.0f - 1.0f;  // what the shader reads
    const vec3 tilted =
        glm::normalize(vec3(1, 0, 0) * decoded.x + vec3(0, 0, -1) * decoded.y + vec3(0, 1, 0) * decoded.z);

    const vec3 base(0.7f, 0.6f, 0.5f);
    auto mapped = rough(base);
    mapped->pbr.normal.texture = make<Texture>(4, 4, pixels);
    auto generated = floorQuad(vec3(0, 1, 0), false);
    generated->setSurface(generateTangents(*generated, 0), {});
    ASSERT_EQ(generated->tangents().size(), 4u);
    for (const vec4& t : generated->tangents()) {
        EXPECT_NEAR(t.x, 1.0f, 1e-5f);
        EXPECT_NEAR(t.w, 1.0f, 0.0f);
    }
    Frame f;
    f.renderer.setLight(DirectionalLight::sun(vec3(-0.4f, 0.7f, 0.3f), vec3(0.1f), vec3(0.8f)));
    const Camera cam = lookingAt(dvec3(0.3, 2.2, 1.6), dvec3(0.0));
    const Image reference = f.draw(make<Geometry>(floorQuad(tilted, false), rough(base)), cam);
    const Image fromFile = f.draw(make<Geometry>(floorQuad(vec3(0, 1, 0), true), mapped), cam);
    const Image fromUvs = f.draw(make<Geometry>(generated, mapped), cam);
    const Image flat = f.draw(make<Geometry>(floorQuad(vec3(0, 1, 0), false), rough(base)), cam);
    if (std::getenv("SGKIT_TEST_IMAGES")) savePng("normal_map.png", fromFile);
    EXPECT_EQ(countDifferingPixels(reference, fromFile, 2), 0u);
    EXPECT_EQ(countDifferingPixels(reference, fromUvs, 2), 0u);
    EXPECT_GT(countDifferingPixels(reference, flat, 6), size_t(kW * kH / 4));  // the tilt shows
}

TEST(GltfMaterialImage, PhysicalMaterialsRoundTripThroughSaveGltf) {
    // Every field of a physical material, and blending, double-sidedness and the second UV set, written and read
    // back: the same pixels, lit by a sun and a sky.
    const auto texture = [](int seed) {
        std::vector<uint8_t> px;
        for (int i = 0; i < 64; ++i)
            for (int k = 0; k < 4; ++k) px.push_back(uint8_t(k == 3 ? 255 : (i * 37 + k * 91 + seed * 53) % 256));
        return make<Texture>(8, 8, px);
    };
    auto root = make<Group>();
    for (int k = 0; k < 4; ++k) {
        auto mesh = make<Mesh>();
        const float x = -3.0f + 2.0f * k;
        mesh->set({{x - 0.9f, 0, 0.9f}, {x + 0.9f, 0, 0.9f}, {x + 0.9f, 0.3f, -0.9f}, {x - 0.9f, 0.3f, -0.9f}},
                  std::vector<vec3>(4, glm::normalize(vec3(0, 1, 0.33f))), {0, 1, 2, 0, 2, 3},
                  {{0, 0}, {2, 0}, {2, 2}, {0, 2}});
        mesh->setSurface(std::vector<vec4>(4, vec4(1, 0, 0, 1)), {{0, 0}, {1, 0}, {1, 1}, {0, 1}});
        auto m = make<Material>(vec4(0.9f, 0.8f - 0.1f * k, 0.6f, k == 3 ? 0.6f : 1.0f), texture(k));
        m->physical = true;
        m->pbr.metallic = 0.25f * k;
        m->pbr.roughness = 0.3f + 0.15f * k;
        m->pbr.metallicRoughness.texture = texture(10 + k);
        m->pbr.metallicRoughness.texCoord = 1;
        m->pbr.normal.texture = texture(20 + k);
        m->pbr.normalScale = 0.5f;
        m->pbr.occlusion.texture = texture(30 + k);
        m->pbr.occlusionStrength = 0.7f;
        m->pbr.emissive.texture = texture(40 + k);
        m->pbr.emissiveFactor = vec3(0.2f, 0.1f * k, 1.5f);  // above 1: KHR_materials_emissive_strength
        m->textureTransform = glm::mat3(glm::vec3(0.8f, 0.3f, 0.0f), glm::vec3(-0.3f, 0.8f, 0.0f),
                                        glm::vec3(0.1f, -0.2f, 1.0f));  // rotation, scale and offset
        m->blend = k == 3;
        m->doubleSided = k % 2 == 0;
        root->addChild(make<Geometry>(mesh, m));
    }
    const std::string file = ::testing::TempDir() + "physical_round_trip.glb";
    saveGltf(*root, file);
    const GltfScene back = loadGltf(file);
    EXPECT_TRUE(back.warnings.empty()) << back.warnings.front();
    Frame f;
    f.renderer.setLight(DirectionalLight::sun(vec3(0.3f, 0.8f, 0.4f), vec3(0.25f), vec3(0.7f)));
    size_t covered = 0;
    for (const dvec3& eye : {dvec3(0.5, 4.0, 5.0), dvec3(-2.0, 3.0, -4.0), dvec3(4.0, -2.0, 3.0)}) {
        const Camera cam = lookingAt(eye, dvec3(0.0));
        const Image a = f.draw(root, cam), b = f.draw(back.root, cam);
        EXPECT_EQ(countDifferingPixels(a, b, 1), 0u) << "from " << eye.x << "," << eye.y << "," << eye.z;
        const Image none = f.draw(make<Group>(), cam);
        covered += countDifferingPixels(a, none, 0);
    }
    EXPECT_GT(covered, size_t(kW * kH / 4));  // the three views together
}

TEST(GltfMaterialImage, OcclusionPackedInTheMetallicRoughnessTextureDrawsAsTwoMaps) {
    // glTF's "ORM" packing (occlusion in R of the metallic-roughness texture, one image) is sampled once: the same
    // pixels as the occlusion given as a texture of its own with the same texels.
    std::vector<uint8_t> px;
    for (int i = 0; i < 64; ++i)
        px.insert(px.end(), {uint8_t(40 + i * 3), uint8_t(60 + (i * 7) % 180), uint8_t((i * 13) % 256), 255});
    const auto orm = make<Texture>(8, 8, px);
    const auto material = [&](const ref_ptr<Texture>& occlusion) {
        auto m = rough(vec3(0.8f, 0.7f, 0.6f));
        m->pbr.metallicRoughness.texture = orm;
        m->pbr.occlusion.texture = occlusion;
        m->pbr.occlusionStrength = 0.9f;
        return m;
    };
    Frame f;
    f.renderer.setLight(DirectionalLight::sun(vec3(0.3f, 0.8f, 0.4f), vec3(0.6f), vec3(0.5f)));
    const Camera cam = lookingAt(dvec3(0.3, 2.2, 1.6), dvec3(0.0));
    const Image packed = f.draw(make<Geometry>(floorQuad(vec3(0, 1, 0), false), material(orm)), cam);
    const Image separate =
        f.draw(make<Geometry>(floorQuad(vec3(0, 1, 0), false), material(make<Texture>(8, 8, px))), cam);
    const Image without = f.draw(make<Geometry>(floorQuad(vec3(0, 1, 0), false), material(nullptr)), cam);
    EXPECT_EQ(countDifferingPixels(packed, separate, 0), 0u);
    EXPECT_GT(countDifferingPixels(packed, without, 4), size_t(kW * kH / 4));  // the occlusion shows
}
