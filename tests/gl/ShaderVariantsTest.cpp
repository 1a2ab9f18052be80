// The renderer's shader variants against the one program that branches on uniforms: the same pixels (at most
// 1/255 per channel, where the compilers order the arithmetic differently) for every combination of features a
// draw can use, under the headlight and a sun, opaque and dissolving; and a variant per combination, built once.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/gl/internal/Shaders.h"
#include "sg/io/ImageIO.h"

#include <gtest/gtest.h>

#include <set>

using namespace sg;

namespace {

constexpr int kW = 256, kH = 256;

// A box with UVs and vertex colours (alpha varying, so that baked light and cut-outs show), split so that the
// colours vary across each face.
ref_ptr<Mesh> colouredBox() {
    const ref_ptr<Mesh> box = makeBoxMesh(dvec3(-0.4), dvec3(0.4), 4);
    std::vector<vec2> uvs;
    std::vector<vec4> colors;
    for (const vec3& p : box->positions()) {
        uvs.emplace_back(p.x + p.z + 0.5f, p.y - p.z + 0.5f);
        colors.emplace_back(0.5f + p.x, 0.5f + p.y, 0.5f + p.z, 0.2f + 0.8f * std::abs(p.x + p.y) / 0.8f);
    }
    std::vector<uint32_t> idx;
    for (uint32_t i = 0; i < box->indexCount(); ++i) idx.push_back(box->index(i));
    auto m = make<Mesh>();
    m->set(box->positions(), box->normals(), std::move(idx), std::move(uvs), std::move(colors));
    return m;
}

ref_ptr<Mesh> plainBox() { return makeBoxMesh(dvec3(-0.4), dvec3(0.4), 4); }

ref_ptr<Texture> checker() {
    std::vector<uint8_t> rgba;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const bool on = (x + y) % 2 == 0;
            rgba.insert(rgba.end(), {uint8_t(on ? 250 : 40), uint8_t(on ? 200 : 90), uint8_t(on ? 60 : 220),
                                     uint8_t(on ? 255 : 90)});
        }
    return make<Texture>(8, 8, std::move(rgba));
}

// Every combination of texture, vertex colours, baked light, unlit, highlight and alpha cutoff: 64 boxes in a
// grid, each turned so that three faces show.
ref_ptr<Group> everyCombination() {
    auto root = make<Group>();
    const ref_ptr<Mesh> coloured = colouredBox(), plain = plainBox();
    const ref_ptr<Texture> tex = checker();
    for (int k = 0; k < 64; ++k) {
        auto mat = make<Material>(vec4(0.9f, 0.8f, 0.7f, 1.0f), (k & 1) ? tex : ref_ptr<Texture>());
        mat->bakedLight = (k & 4) != 0;
        mat->unlit = (k & 8) != 0;
        mat->specular = (k & 16) ? 0.6f : 0.0f;
        mat->shininess = 12.0f;
        mat->alphaCutoff = (k & 32) ? 0.5f : 0.0f;
        const dmat4 at = glm::rotate(
            glm::rotate(glm::translate(dmat4(1.0), dvec3(k % 8 - 3.5, k / 8 - 3.5, 0.0)), 0.6, dvec3(1, 0, 0)), 0.7,
            dvec3(0, 1, 0));
        auto t = make<Transform>(at);
        t->addChild(make<Geometry>((k & 2) ? coloured : plain, mat));
        root->addChild(t);
    }
    return root;
}

Camera front() {
    Camera cam;
    cam.setLookAt(dvec3(0, 0, 11), dvec3(0.0), dvec3(0, 1, 0));
    cam.setPerspective(45.0, 1.0, 0.5, 50.0);
    cam.setViewport(kW, kH);
    return cam;
}

struct ShaderVariants : ::testing::Test {
    OsmesaContext context{kW, kH};
    Renderer renderer;
    Image draw(const DrawList& list, const Camera& cam, Renderer::ShaderMode mode) {
        renderer.setShaderMode(mode);
        renderer.draw(list, cam);
        return renderer.readColor();
    }
};

size_t colours(const Image& img) {
    std::set<uint32_t> seen;
    for (size_t i = 0; i + 3 < img.rgba.size(); i += 4)
        seen.insert(uint32_t(img.rgba[i]) << 16 | uint32_t(img.rgba[i + 1]) << 8 | img.rgba[i + 2]);
    return seen.size();
}

}  // namespace

TEST_F(ShaderVariants, EveryCombinationDrawsThePixelsOfTheOneProgram) {
    Scene scene(everyCombination());
    scene.update();
    const Camera cam = front();
    DrawList list;
    CullStats stats;
    CullTraversal().cull(scene, cam, CullSettings{}, list, stats);
    ASSERT_EQ(list.items.size(), 64u);
    for (const bool sun : {false, true}) {
        renderer.setLight(sun ? DirectionalLight::sun(vec3(0.3f, 0.5f, 0.8f), vec3(0.3f), vec3(0.7f))
                              : DirectionalLight{});
        for (const bool fade : {false, true}) {
            // Dissolving: every other item, both halves of the pattern.
            list.fades.clear();
            if (fade)
                for (uint32_t i = 0; i < 64; i += 2) list.fades.emplace_back(i, i % 4 ? 0.6f : -0.4f);
            const Image one = draw(list, cam, Renderer::ShaderMode::OneProgram);
            const Image variants = draw(list, cam, Renderer::ShaderMode::Variants);
            EXPECT_EQ(countDifferingPixels(one, variants, 1), 0u)
                << (sun ? "sun" : "headlight") << (fade ? ", fading" : "");
            EXPECT_GT(colours(one), 1000u);  // the picture shows what it tests
        }
    }
    // 64 materials x 2 lights x fade: one variant per combination that changes the code, and no more. Under the
    // headlight the highlight does nothing; unlit, neither the light nor the highlight; without vertex colours,
    // baked light does nothing.
    EXPECT_GE(renderer.variantCount(), 40u);
    EXPECT_LE(renderer.variantCount(), 2u * 2u * 2u * 2u * 2u * 2u * 2u * 2u);
    const size_t built = renderer.variantCount();
    draw(list, cam, Renderer::ShaderMode::Variants);
    EXPECT_EQ(renderer.variantCount(), built);  // kept, not built again
}

// The one program is what draws when asked, so that the comparison above compares two things.
TEST_F(ShaderVariants, TheOneProgramIsTheReferenceAndBuildsNoVariant) {
    Scene scene(everyCombination());
    scene.update();
    DrawList list;
    CullStats stats;
    CullTraversal().cull(scene, front(), CullSettings{}, list, stats);
    draw(list, front(), Renderer::ShaderMode::OneProgram);
    EXPECT_EQ(renderer.variantCount(), 0u);
    draw(list, front(), Renderer::ShaderMode::Variants);
    EXPECT_GT(renderer.variantCount(), 8u);
}

TEST(ShaderVariantSource, FeaturesWithoutEffectShareAVariant) {
    EXPECT_EQ(canonicalFeatures(kShadeBaked), 0u);                        // baked light without vertex colours
    EXPECT_EQ(canonicalFeatures(kShadeSun | kShadeSpecular), 0u);         // light on an unlit draw
    EXPECT_EQ(canonicalFeatures(kShadeLit | kShadeSpecular), kShadeLit);  // the headlight draws no highlight
    const uint32_t all = kShadeTexture | kShadeColor | kShadeBaked | kShadeLit | kShadeSun | kShadeSpecular |
                         kShadeAlphaCut | kShadeFade;
    EXPECT_EQ(canonicalFeatures(all), all);
}
