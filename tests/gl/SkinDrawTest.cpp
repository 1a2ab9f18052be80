// The renderer draws posed items (DrawList::poses): a skinned tube bent at its joints looks as the same tube skinned
// here on the CPU, in double, and drawn as a plain mesh (4 and 8 influences a vertex, classic and textured physical
// materials, both shader modes, a skin past the GPU's joint block); a morphed pose draws its own mesh; occlusion
// queries pass posed items through unqueried.
#include "sg/core/Pose.h"
#include "sg/cull/DrawList.h"
#include "sg/gl/OcclusionQueries.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/gl/internal/Shaders.h"
#include "sg/io/ImageIO.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

using namespace sg;

namespace {

constexpr int kW = 256, kH = 256;
constexpr double kLength = 3.0;              // the tube runs along x from 0 to kLength in its bind pose
constexpr int kRings = 31, kSides = 16;      // 496 vertices, 960 triangles
const dvec3 kAnchor(5000.0, 10.0, -3000.0);  // the first joint in the bent pose: far from the origin
const dvec3 kEye = kAnchor + dvec3(1.2, 1.6, 5.5);
// Pixels that may differ by more than 2/255 a channel (edge rounding): 0.1% of the picture.
constexpr size_t kAllowed = size_t(kW) * kH / 1000;

// A tube of radius 0.3 with UVs (along, around), skinned to `bones` bones of equal length along it: each vertex
// weighted to every bone by a Gaussian of its distance to the bone's middle, bone s in slot s, the slots past the
// bones joint 0 with weight 0. With 6 bones and 8 influences, slots 4 and 5 (the second four) carry weight.
ref_ptr<Mesh> skinnedTube(int bones, int influences) {
    std::vector<vec3> positions, normals;
    std::vector<vec2> uvs;
    std::vector<uint16_t> joints;
    std::vector<float> weights;
    const double bone = kLength / bones;
    for (int r = 0; r < kRings; ++r) {
        const double x = kLength * r / (kRings - 1);
        std::vector<double> w(size_t(influences), 0.0);
        double sum = 0.0;
        for (int b = 0; b < bones; ++b) {
            const double d = (x - (b + 0.5) * bone) / (0.6 * bone);
            w[size_t(b)] = std::exp(-d * d);
            sum += w[size_t(b)];
        }
        for (int s = 0; s < kSides; ++s) {
            const double a = 2.0 * 3.14159265358979 * s / kSides;
            const dvec3 n(0.0, std::cos(a), std::sin(a));
            positions.push_back(vec3(dvec3(x, 0.0, 0.0) + 0.3 * n));
            normals.push_back(vec3(n));
            uvs.push_back(vec2(float(x / kLength), float(s) / kSides));
            for (int k = 0; k < influences; ++k) {
                joints.push_back(uint16_t(k < bones ? k : 0));
                weights.push_back(float(w[size_t(k)] / sum));
            }
        }
    }
    std::vector<uint32_t> indices;
    for (int r = 0; r + 1 < kRings; ++r)
        for (int s = 0; s < kSides; ++s) {
            const uint32_t a = uint32_t(r * kSides + s), b = uint32_t(r * kSides + (s + 1) % kSides);
            const uint32_t c = a + kSides, d = b + kSides;
            indices.insert(indices.end(), {a, b, d, a, d, c});
        }
    auto m = make<Mesh>();
    m->set(std::move(positions), std::move(normals), std::move(indices), std::move(uvs));
    m->setSkinWeights(std::move(joints), std::move(weights), influences);
    return m;
}

// Each bone's joint matrix times its inverse bind matrix, in world coordinates: a chain from kAnchor, each bone
// turned against the one before about a tilted axis. Bone b rests at (b x length, 0, 0), unturned.
std::vector<dmat4> skinMatrices(int bones) {
    const double bone = kLength / bones;
    std::vector<dmat4> out;
    dmat4 world = glm::translate(dmat4(1.0), kAnchor);
    for (int b = 0; b < bones; ++b) {
        if (b > 0) world = world * glm::translate(dmat4(1.0), dvec3(bone, 0.0, 0.0));
        world = world * glm::rotate(dmat4(1.0), 1.1 / bones, glm::normalize(dvec3(0.0, 0.3, 1.0)));
        out.push_back(world * glm::translate(dmat4(1.0), dvec3(-b * bone, 0.0, 0.0)));
    }
    return out;
}

// The pose as the update makes it: the matrices less the anchor, in float.
ref_ptr<Pose> makePose(const std::vector<dmat4>& skin) {
    auto pose = make<Pose>();
    pose->anchor = kAnchor;
    for (const dmat4& m : skin) pose->joints.push_back(glm::mat4x3(mat4(glm::translate(dmat4(1.0), -kAnchor) * m)));
    return pose;
}

// The mesh skinned here, in double, relative to the anchor: positions by the weighted sum of the matrices, normals by
// its inverse transpose.
ref_ptr<Mesh> skinnedOnCpu(const Mesh& m, const std::vector<dmat4>& skin) {
    const size_t k = size_t(m.influences());
    std::vector<vec3> positions, normals;
    for (size_t v = 0; v < m.positions().size(); ++v) {
        dmat4 s(0.0);
        for (size_t i = v * k; i < v * k + k; ++i) s += double(m.weights()[i]) * skin[m.joints()[i]];
        s = glm::translate(dmat4(1.0), -kAnchor) * s;
        positions.push_back(vec3(dvec3(s * dvec4(dvec3(m.positions()[v]), 1.0))));
        normals.push_back(vec3(glm::normalize(glm::transpose(glm::inverse(glm::dmat3(s))) * dvec3(m.normals()[v]))));
    }
    std::vector<uint32_t> indices;
    for (uint32_t i = 0; i < m.indexCount(); ++i) indices.push_back(m.index(i));
    auto out = make<Mesh>();
    out->set(std::move(positions), std::move(normals), std::move(indices), m.uvs());
    return out;
}

// The translation from the eye to `at`: a skinned item's matrix, as the cull makes it.
glm::mat4x3 from(const dvec3& at) { return glm::mat4x3(mat4(glm::translate(dmat4(1.0), at - kEye))); }

struct Item {
    const Mesh* mesh;
    const Material* material;
    glm::mat4x3 model;
    const Pose* pose = nullptr;
};

struct SkinDraw : ::testing::Test {
    OsmesaContext context{kW, kH};
    Renderer renderer;
    Camera camera;

    SkinDraw() {
        camera.setLookAt(kEye, kAnchor + dvec3(1.2, 0.9, 0.0), dvec3(0, 1, 0));
        camera.setPerspective(45.0, 1.0, 0.1, 50.0);
        camera.setViewport(kW, kH);
    }

    Image draw(const std::vector<Item>& items) {
        DrawList list;
        for (const Item& i : items) {
            DrawItem it;
            it.mesh = i.mesh;
            it.material = i.material;
            it.model = i.model;
            if (i.pose) list.poses.push_back({uint32_t(list.items.size()), i.pose});
            list.add(it);
        }
        renderer.draw(list, camera);
        return renderer.readColor();
    }

    // The bent tube skinned by the renderer and skinned here look the same, and not as the unbent one; the figure
    // covers a good part of the picture.
    void expectSkinnedAsOnCpu(int bones, int influences, const Material* mat) {
        const ref_ptr<Mesh> mesh = skinnedTube(bones, influences);
        const std::vector<dmat4> skin = skinMatrices(bones);
        const ref_ptr<Pose> pose = makePose(skin);
        const ref_ptr<Mesh> twin = skinnedOnCpu(*mesh, skin);
        const Image gpu = draw({{mesh.get(), mat, from(kAnchor), pose.get()}});
        EXPECT_EQ(renderer.lastStats().triangles, 960u);
        EXPECT_EQ(renderer.lastStats().instances, 1u);
        const Image cpu = draw({{twin.get(), mat, from(kAnchor)}});
        const Image straight = draw({{mesh.get(), mat, from(kAnchor)}});
        const Image empty = draw({});
        EXPECT_GT(countDifferingPixels(empty, cpu, 2), size_t(kW * kH / 40));
        EXPECT_GT(countDifferingPixels(straight, cpu, 2), size_t(kW * kH / 100));
        EXPECT_LE(countDifferingPixels(gpu, cpu, 2), kAllowed);
    }
};

ref_ptr<Material> texturedPhysical() {
    std::vector<uint8_t> rgba;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const bool light = (x / 2 + y / 2) % 2 == 0;
            rgba.insert(rgba.end(),
                        {uint8_t(light ? 230 : 40), uint8_t(light ? 200 : 90), uint8_t(light ? 60 : 180), 255});
        }
    auto m = make<Material>(vec4(1.0f), make<Texture>(8, 8, std::move(rgba)));
    m->physical = true;
    m->pbr.metallic = 0.1f;
    m->pbr.roughness = 0.5f;
    return m;
}

}  // namespace

TEST_F(SkinDraw, FourInfluencesDrawAsSkinnedOnTheCpu) {
    const auto mat = make<Material>(vec4(0.9f, 0.6f, 0.3f, 1.0f));
    expectSkinnedAsOnCpu(3, 4, mat.get());
    renderer.setLight(DirectionalLight::sun(vec3(0.3f, 1.0f, 0.6f), vec3(0.3f), vec3(0.7f)));
    mat->specular = 0.5f;
    mat->shininess = 20.0f;
    expectSkinnedAsOnCpu(3, 4, mat.get());
}

TEST_F(SkinDraw, EightInfluencesDrawAsSkinnedOnTheCpu) {
    // The second four carry weight: without them the tube's far half would not follow its last two bones.
    const ref_ptr<Mesh> mesh = skinnedTube(6, 8);
    float second = 0.0f;
    for (size_t i = 0; i < mesh->weights().size(); ++i)
        if (i % 8 >= 4) second = std::max(second, mesh->weights()[i]);
    EXPECT_GT(second, 0.5f);
    const auto mat = make<Material>(vec4(0.4f, 0.8f, 0.5f, 1.0f));
    expectSkinnedAsOnCpu(6, 8, mat.get());
}

TEST_F(SkinDraw, TheOneProgramModeSkinsWithAVariant) {
    renderer.setShaderMode(Renderer::ShaderMode::OneProgram);
    const auto mat = make<Material>(vec4(0.9f, 0.6f, 0.3f, 1.0f));
    expectSkinnedAsOnCpu(3, 4, mat.get());
}

TEST_F(SkinDraw, ATexturedPhysicalMaterialDrawsAsOnTheCpu) {
    const ref_ptr<Material> mat = texturedPhysical();
    expectSkinnedAsOnCpu(3, 4, mat.get());
    renderer.setLight(DirectionalLight::sun(vec3(-0.4f, 1.0f, 0.5f), vec3(0.3f), vec3(0.8f)));
    expectSkinnedAsOnCpu(6, 8, mat.get());
}

// A skinned item is drawn alone, its neighbour of the same mesh and material as it is.
TEST_F(SkinDraw, ASkinnedItemBesideAPlainOneOfTheSameMesh) {
    const auto mat = make<Material>(vec4(0.7f, 0.7f, 0.9f, 1.0f));
    const ref_ptr<Mesh> mesh = skinnedTube(3, 4);
    const std::vector<dmat4> skin = skinMatrices(3);
    const ref_ptr<Pose> pose = makePose(skin);
    const ref_ptr<Mesh> twin = skinnedOnCpu(*mesh, skin);
    const dvec3 beside = kAnchor + dvec3(0.0, -1.2, -1.0);
    const Image gpu = draw({{mesh.get(), mat.get(), from(kAnchor), pose.get()}, {mesh.get(), mat.get(), from(beside)}});
    EXPECT_EQ(renderer.lastStats().drawCalls, 2u);
    EXPECT_EQ(renderer.lastStats().instances, 2u);
    const Image cpu = draw({{twin.get(), mat.get(), from(kAnchor)}, {mesh.get(), mat.get(), from(beside)}});
    EXPECT_LE(countDifferingPixels(gpu, cpu, 2), kAllowed);
}

// More joints than the vertex stage's block holds: skinned on the CPU, the same picture.
TEST_F(SkinDraw, ASkinPastTheJointBlockIsSkinnedOnTheCpu) {
    const auto mat = make<Material>(vec4(0.9f, 0.6f, 0.3f, 1.0f));
    const ref_ptr<Mesh> mesh = skinnedTube(3, 4);
    std::vector<dmat4> skin = skinMatrices(3);
    const ref_ptr<Mesh> twin = skinnedOnCpu(*mesh, skin);
    skin.resize(300, dmat4(1.0));  // joints no vertex uses
    const ref_ptr<Pose> pose = makePose(skin);
    const Image gpu = draw({{mesh.get(), mat.get(), from(kAnchor), pose.get()}});
    const Image cpu = draw({{twin.get(), mat.get(), from(kAnchor)}});
    EXPECT_LE(countDifferingPixels(gpu, cpu, 2), kAllowed);
    EXPECT_GT(countDifferingPixels(draw({}), cpu, 2), size_t(kW * kH / 40));
}

// A morphed pose (a mesh, no joints) draws its mesh with the item's matrix, not the item's own mesh.
TEST_F(SkinDraw, AMorphedPoseDrawsItsMesh) {
    const auto mat = make<Material>(vec4(0.9f, 0.6f, 0.3f, 1.0f));
    const ref_ptr<Mesh> thin = skinnedTube(3, 4);
    std::vector<vec3> positions = thin->positions();
    for (vec3& p : positions) p = vec3(p.x, 2.0f * p.y, 2.0f * p.z);  // twice as thick
    std::vector<uint32_t> indices;
    for (uint32_t i = 0; i < thin->indexCount(); ++i) indices.push_back(thin->index(i));
    auto thick = make<Mesh>();
    thick->set(positions, thin->normals(), indices, thin->uvs());
    auto pose = make<Pose>();
    pose->mesh = thick;
    const glm::mat4x3 at = from(kAnchor);
    const Image morphed = draw({{thin.get(), mat.get(), at, pose.get()}});
    const Image direct = draw({{thick.get(), mat.get(), at}});
    const Image own = draw({{thin.get(), mat.get(), at}});
    EXPECT_EQ(countDifferingPixels(morphed, direct, 0), 0u);
    EXPECT_GT(countDifferingPixels(morphed, own, 2), size_t(kW * kH / 100));
}

// A pose naming an item past the list, or a skin whose mesh weights a joint the pose lacks, is refused.
TEST_F(SkinDraw, BadPosesAreRefused) {
    const auto mat = make<Material>();
    const ref_ptr<Mesh> mesh = skinnedTube(3, 4);
    const ref_ptr<Pose> short_ = makePose(skinMatrices(2));
    DrawList list;
    DrawItem it;
    it.mesh = mesh.get();
    it.material = mat.get();
    it.model = from(kAnchor);
    list.add(it);
    list.poses.push_back({0u, short_.get()});
    EXPECT_THROW(renderer.draw(list, camera), std::out_of_range);
    const ref_ptr<Pose> whole = makePose(skinMatrices(3));
    list.poses = {{1u, whole.get()}};
    EXPECT_THROW(renderer.draw(list, camera), std::out_of_range);
}

// Occlusion queries draw a posed item unqueried (its mesh's box is not where the pose puts it), its pose renumbered
// with it.
TEST_F(SkinDraw, OcclusionQueriesPassPosedItemsThrough) {
    const auto mat = make<Material>(vec4(0.9f, 0.6f, 0.3f, 1.0f));
    const ref_ptr<Mesh> mesh = skinnedTube(3, 4);
    const ref_ptr<Pose> pose = makePose(skinMatrices(3));
    DrawList list;
    DrawItem plain, posed;
    plain.mesh = posed.mesh = mesh.get();
    plain.material = posed.material = mat.get();
    plain.model = from(kAnchor + dvec3(0.0, -1.2, -1.0));
    posed.model = from(kAnchor);
    list.add(plain);
    list.add(posed);
    list.poses.push_back({1u, pose.get()});
    renderer.draw(list, camera);
    const Image direct = renderer.readColor();
    OcclusionQueries queries;
    for (int frame = 0; frame < 2; ++frame) {
        queries.draw(renderer, list, camera);
        EXPECT_EQ(queries.lastStats().queries + queries.lastStats().nearEye, 1u);
        ASSERT_EQ(queries.drawn().poses.size(), 1u);
        EXPECT_EQ(queries.drawn().poses[0].first, 1u);
        EXPECT_EQ(queries.drawn().poses[0].second, pose.get());
        EXPECT_EQ(countDifferingPixels(renderer.readColor(), direct, 0), 0u);
    }
}

TEST(SkinVariantSource, SkinningIsAFeatureOfEveryVariant) {
    EXPECT_EQ(canonicalFeatures(kShadeSkin4 | kShadeSkin8 | kShadeLit), kShadeSkin8 | kShadeLit);
    EXPECT_EQ(canonicalFeatures(kShadeOutline | kShadeSkin4 | kShadeLit), kShadeOutline | kShadeSkin4);
    EXPECT_EQ(canonicalFeatures(kShadePbr | kShadeLit | kShadeSkin8), kShadePbr | kShadeLit | kShadeSkin8);
    EXPECT_NE(variantSource(true, kShadeSkin4).find("uJoints[256]"), std::string::npos);
    // The plain variant compiles without the skinning code (its constants are 0).
    EXPECT_NE(variantSource(true, kShadeLit).find("#define SKIN4 0"), std::string::npos);
    EXPECT_NE(variantSource(true, kShadeSkin4).find("#define SKIN4 1"), std::string::npos);
}
