// glTF round trip in pixels: a scene and its copy saved to .glb and loaded back render identically.
#include "GltfTestUtil.h"

#include "loaders/Gltf.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/io/ImageIO.h"
#include "testbed/RandomScene.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {

constexpr int kW = 160, kH = 120;

Image render(Renderer& r, const ref_ptr<Node>& root, const Camera& cam) {
    Scene scene(root);
    scene.update();
    DrawList list;
    CullStats stats;
    CullSettings settings;
    settings.sort = false;  // emission order: the same graph order in both, whatever the pointers
    CullTraversal().cull(scene, cam, settings, list, stats);
    r.draw(list, cam);
    return r.readColor();
}

void expectSamePixels(const ref_ptr<Node>& original, const Box& bounds, uint64_t seed, const std::string& file) {
    saveGltf(*original, file);
    const GltfScene loaded = loadGltf(file);
    OsmesaContext context(kW, kH);
    Renderer renderer;
    scenes::Rng rng(seed);
    size_t covered = 0;
    for (int k = 0; k < 12; ++k) {
        const Camera cam = scenes::randomCamera(rng, bounds, k, kW, kH);
        const Image a = render(renderer, original, cam);
        const Image b = render(renderer, loaded.root, cam);
        EXPECT_EQ(countDifferingPixels(a, b, 0), 0u) << "view " << k;
        Image clear = a;  // how much of the view the scene covers: the test must see something
        for (size_t i = 0; i < clear.rgba.size(); i += 4)
            std::copy(a.rgba.begin(), a.rgba.begin() + 4, clear.rgba.begin() + long(i));
        covered += countDifferingPixels(a, clear, 0);
    }
    EXPECT_GT(covered, size_t(kW * kH / 2));  // a few views see much of the scene
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
