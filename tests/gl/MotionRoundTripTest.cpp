// A saved animated scene draws the frames it drew before it was saved (but for a pixel or two where floats round): the
// test figure (skinned, walking; 4 and 8 joints a vertex, linear and cubic rotations), posed at several times before
// saveGltf and after loadGltf, each drawn headless through the renderer's skinning.
#include "RenderUtil.h"
#include "loaders/gltf/Gltf.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/io/ImageIO.h"
#include "sg/scene/AnimationPlayer.h"
#include "testbed/Figure.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>

using namespace sg;

namespace {

constexpr int kW = 200, kH = 240;

Camera camera() {
    Camera c;
    c.setViewport(kW, kH);
    c.setPerspective(45.0, double(kW) / kH, 0.1, 50.0);
    c.setLookAt(dvec3(1.5, 1.2, 4.0), dvec3(0.0, 0.9, 0.0), dvec3(0, 1, 0));
    return c;
}

// The pictures of `root` at each time, its animations played by a player of their own.
std::vector<Image> posed(Renderer& r, const ref_ptr<Node>& root, const std::vector<ref_ptr<Animation>>& anims,
                         const std::vector<double>& times) {
    Scene scene(root);
    AnimationPlayer player;
    for (const auto& a : anims) player.play(player.add(a));
    std::vector<Image> out;
    for (double t : times) {
        for (size_t i = 0; i < player.size(); ++i) player.seek(i, t);
        player.apply();
        scene.update();
        out.push_back(testutil::drawScene(r, scene, camera(), true));
    }
    return out;
}

TEST(MotionRoundTrip, ASavedAnimatedSceneDrawsTheSameFrames) {
    OsmesaContext ctx(kW, kH);
    Renderer renderer;
    const std::vector<double> times = {0.0, 0.2, 0.45, 0.8};
    for (int variant = 0; variant < 2; ++variant) {
        SCOPED_TRACE(variant ? "8 joints, cubic" : "4 joints, linear");
        scenes::FigureOptions opt;
        opt.influences = variant ? 8 : 4;
        opt.cubic = variant == 1;
        const scenes::Figure f = scenes::makeFigure(opt);
        const std::vector<Image> before = posed(renderer, f.root, {f.walk}, times);
        EXPECT_GT(countDifferingPixels(before[0], before[2]), 100u);  // it walks
        const std::string path = (std::filesystem::temp_directory_path() /
                                  ("sgkit_motion_" + std::to_string(::getpid()) + (variant ? ".gltf" : ".glb")))
                                     .string();
        GltfSaveOptions so;
        so.animations = {f.walk};
        saveGltf(*f.root, path, so);
        const GltfScene g = loadGltf(path);
        std::remove(path.c_str());
        ASSERT_EQ(g.animations.size(), 1u);
        const std::vector<Image> after = posed(renderer, g.root, g.animations, times);
        // The file holds the inverse bind matrices as floats (glTF's MAT4 accessor), the figure's are doubles: its
        // vertices move by about 1e-7 of their size, which tips a rasterizer's edge test at a pixel or two.
        for (size_t k = 0; k < times.size(); ++k)
            EXPECT_LE(countDifferingPixels(before[k], after[k]), size_t(kW * kH / 2000)) << "t " << times[k];
    }
}

}  // namespace
