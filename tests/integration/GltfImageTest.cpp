// glTF round trip in pixels: a scene and its copy saved to .glb and loaded back render identically.
#include "GltfTestUtil.h"
#include "RenderUtil.h"

#include "loaders/gltf/Gltf.h"
#include "nodes/Instance.h"
#include "nodes/LOD.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/io/ImageIO.h"
#include "testbed/RandomScene.h"

#include <gtest/gtest.h>
#include <fstream>
#include <glm/gtc/quaternion.hpp>

using namespace sg;

namespace {

constexpr int kW = 160, kH = 120;

// a and b draw the same pixels from twelve random views, and the views see much of the scene.
void expectSamePixels(const ref_ptr<Node>& a, const ref_ptr<Node>& b, const Box& bounds, uint64_t seed) {
    OsmesaContext context(kW, kH);
    Renderer renderer;
    scenes::Rng rng(seed);
    size_t covered = 0;
    for (int k = 0; k < 12; ++k) {
        const Camera cam = scenes::randomCamera(rng, bounds, k, kW, kH);
        const Image ia = testutil::drawGraph(renderer, a, cam);
        const Image ib = testutil::drawGraph(renderer, b, cam);
        EXPECT_EQ(countDifferingPixels(ia, ib, 0), 0u) << "view " << k;
        Image clear = ia;  // how much of the view the scene covers: the test must see something
        for (size_t i = 0; i < clear.rgba.size(); i += 4)
            std::copy(ia.rgba.begin(), ia.rgba.begin() + 4, clear.rgba.begin() + long(i));
        covered += countDifferingPixels(ia, clear, 0);
    }
    EXPECT_GT(covered, size_t(kW * kH / 2));  // a few views see much of the scene
}

void expectSamePixels(const ref_ptr<Node>& original, const Box& bounds, uint64_t seed, const std::string& file) {
    saveGltf(*original, file);
    expectSamePixels(original, loadGltf(file).root, bounds, seed);
}

}  // namespace

TEST(GltfImage, RandomSceneRendersTheSameAfterARoundTrip) {
    expectSamePixels(scenes::buildRandomScene(11), Box{dvec3(-70), dvec3(70)}, 5,
                     ::testing::TempDir() + "sgkit_img_random.glb");
}

TEST(GltfImage, EveryKindSceneRendersTheSameAfterARoundTrip) {
    expectSamePixels(gltftest::allKindsScene(), Box{dvec3(-15), dvec3(15)}, 6,
                     ::testing::TempDir() + "sgkit_img_kinds.glb");
}

// EXT_mesh_gpu_instancing: a field of Instances whose translation, rotation and scale are floats (so the file holds
// them exactly) draws the same pixels written as one instanced node as written as Instance nodes.
TEST(GltfImage, InstancedFileRendersLikeTheSameSceneWrittenWithoutInstancing) {
    scenes::Rng rng(21);
    auto box = sg::make<Geometry>(makeBoxMesh(dvec3(-1), dvec3(1)), sg::make<Material>(vec4(0.7f, 0.5f, 0.2f, 1.0f)));
    auto field = sg::make<Transform>(glm::translate(dmat4(1.0), dvec3(0.5, 0, 0)));
    for (int i = 0; i < 40; ++i) {
        const glm::dquat q(float(rng.uniform(-1, 1)), float(rng.uniform(-1, 1)), float(rng.uniform(-1, 1)),
                           float(rng.uniform(-1, 1)));
        const dvec3 t(float(rng.uniform(-12, 12)), float(rng.uniform(-12, 12)), float(rng.uniform(-12, 12)));
        const dvec3 s(float(rng.uniform(0.5, 2)), float(rng.uniform(0.5, 2)), float(rng.uniform(0.5, 2)));
        field->addChild(
            sg::make<Instance>(box, glm::scale(glm::translate(dmat4(1.0), t) * glm::mat4_cast(q / glm::length(q)), s)));
    }
    auto root = sg::make<Group>();
    root->addChild(field);
    const std::string instanced = ::testing::TempDir() + "sgkit_img_instanced.glb";
    const std::string plain = ::testing::TempDir() + "sgkit_img_not_instanced.glb";
    saveGltf(*root, instanced);
    GltfSaveOptions off;
    off.gpuInstancing = false;
    saveGltf(*root, plain, off);
    auto text = [](const std::string& f) {
        std::ifstream in(f, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    ASSERT_NE(text(instanced).find("EXT_mesh_gpu_instancing"), std::string::npos);
    ASSERT_EQ(text(plain).find("EXT_mesh_gpu_instancing"), std::string::npos);
    const GltfScene a = loadGltf(instanced), b = loadGltf(plain);
    // The 40 placements, in two groups of nearby ones (more than 32 are grouped for the cull).
    const Node& read = *a.root->child(0);
    ASSERT_EQ(read.numChildren(), 2u);
    size_t placed = 0;
    for (size_t g = 0; g < 2; ++g)
        for (size_t i = 0; i < read.child(g)->numChildren(); ++i)
            placed += read.child(g)->child(i)->kind() == NodeKind::Instance;
    ASSERT_EQ(placed, 40u);
    expectSamePixels(a.root, b.root, Box{dvec3(-15), dvec3(15)}, 8);
    expectSamePixels(root, a.root, Box{dvec3(-15), dvec3(15)}, 8);
}

// Instanced LODs (an LOD of one level placed again and again, as the tile writer makes them): each placement
// switches at its own distance, read back as written, and the instances grouped by place draw the same pixels.
TEST(GltfImage, InstancedLodsSwitchEachAtItsOwnDistanceAfterARoundTrip) {
    scenes::Rng rng(23);
    auto field = sg::make<Group>();
    std::vector<ref_ptr<LOD>> lods;
    for (int k = 0; k < 3; ++k) {
        auto box = sg::make<Geometry>(makeBoxMesh(dvec3(-0.4, -0.4, 0), dvec3(0.4, 0.4, 0.5 + k)),
                                      sg::make<Material>(vec4(0.2f + 0.3f * float(k), 0.6f, 0.3f, 1.0f)));
        auto lod = sg::make<LOD>();
        lod->setCenter(dvec3(0, 0, 0.25 + 0.5 * k));
        lod->addChild(box, 2.0f * float(k), 14.0f + 3.0f * float(k));  // the far ones drop out, near ones too
        lods.push_back(lod);
    }
    for (int x = -12; x <= 12; ++x)
        for (int y = -12; y <= 12; ++y)
            field->addChild(
                sg::make<Instance>(lods[size_t(x + y + 24) % 3], glm::translate(dmat4(1.0), dvec3(x, y, 0.0))));
    auto root = sg::make<Group>();
    root->addChild(field);
    const std::string file = ::testing::TempDir() + "sgkit_img_instanced_lods.glb";
    saveGltf(*root, file);
    const GltfScene read = loadGltf(file);
    expectSamePixels(root, read.root, Box{dvec3(-13, -13, 0), dvec3(13, 13, 3)}, 9);
    // The ranges matter in these views: without them the field draws differently.
    auto unswitched = sg::make<Group>();
    for (size_t i = 0; i < field->numChildren(); ++i) {
        const auto& in = static_cast<const Instance&>(*field->child(i));
        unswitched->addChild(sg::make<Instance>(ref_ptr<Node>(in.prototype()->child(0)), in.matrix()));
    }
    OsmesaContext context(kW, kH);
    Renderer renderer;
    scenes::Rng views(9);
    size_t differ = 0;
    for (int k = 0; k < 12; ++k) {
        const Camera cam = scenes::randomCamera(views, Box{dvec3(-13, -13, 0), dvec3(13, 13, 3)}, k, kW, kH);
        differ += countDifferingPixels(testutil::drawGraph(renderer, read.root, cam),
                                       testutil::drawGraph(renderer, unswitched, cam), 0);
    }
    EXPECT_GT(differ, 1000u);
}
