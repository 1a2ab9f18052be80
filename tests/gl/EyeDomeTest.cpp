// Renderer's eye-dome lighting (PointShading::eyeDome): frames drawn with and without it compared pixel by pixel.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <vector>

using namespace sg;

namespace {

constexpr int kW = 96, kH = 72;
const vec4 kClear(51.0f / 255.0f, 102.0f / 255.0f, 153.0f / 255.0f, 1.0f);

// An unlit square of half-size h facing the eye (the +z axis) with its centre at `centre`.
ref_ptr<Node> square(const dvec3& centre, float h, const vec4& colour) {
    auto mesh = make<Mesh>();
    mesh->set({{-h, -h, 0.0f}, {h, -h, 0.0f}, {h, h, 0.0f}, {-h, h, 0.0f}}, {}, {0, 1, 2, 0, 2, 3});
    auto mat = make<Material>(colour);
    mat->unlit = true;
    auto t = make<Transform>(glm::translate(dmat4(1.0), centre));
    t->addChild(make<Geometry>(mesh, mat));
    return t;
}

// The eye at the origin looking down -z.
Camera camera() {
    Camera cam;
    cam.setLookAt(dvec3(0.0), dvec3(0.0, 0.0, -1.0), dvec3(0.0, 1.0, 0.0));
    cam.setPerspective(45.0, double(kW) / kH, 0.1, 100.0);
    cam.setViewport(kW, kH);
    return cam;
}

DrawList cull(const ref_ptr<Node>& root, const Camera& cam) {
    Scene scene(root);
    scene.update();
    DrawList list;
    CullStats stats;
    CullTraversal().cull(scene, cam, CullSettings{}, list, stats);
    return list;
}

int channel(const Image& img, int x, int y, int c) {
    return img.rgba[(size_t(y) * size_t(kW) + size_t(x)) * 4u + size_t(c)];
}

// The largest difference of any channel of any pixel.
int maxDifference(const Image& a, const Image& b) {
    int worst = 0;
    for (size_t i = 0; i < a.rgba.size(); ++i) worst = std::max(worst, std::abs(int(a.rgba[i]) - int(b.rgba[i])));
    return worst;
}

struct EyeDomeTest : ::testing::Test {
    OsmesaContext context{kW, kH};
    Renderer renderer;

    // The frame drawn with eye-dome lighting of `strength` (off when negative).
    Image draw(const DrawList& list, const Camera& cam, float strength) {
        PointShading s;
        s.eyeDome = strength >= 0.0f;
        s.eyeDomeStrength = strength >= 0.0f ? strength : 1.0f;
        renderer.setPointShading(s);
        renderer.draw(list, cam, kClear);
        return renderer.readColor();
    }
};

const Renderer::DepthMode kModes[] = {Renderer::DepthMode::Classic, Renderer::DepthMode::ReverseZ};

}  // namespace

TEST_F(EyeDomeTest, OffByDefault) { EXPECT_FALSE(renderer.pointShading().eyeDome); }

TEST_F(EyeDomeTest, FlatSquareFacingTheEyeAndTheBackgroundAreUnchanged) {
    ASSERT_TRUE(renderer.reverseZSupported());  // llvmpipe: OpenGL 4.5
    // One depth everywhere on the square: no neighbour lies in front of another, and the background is skipped.
    auto root = make<Group>();
    root->addChild(square(dvec3(0.0, 0.0, -10.0), 2.0f, vec4(0.8f, 0.6f, 0.4f, 1.0f)));
    const Camera cam = camera();
    const DrawList list = cull(root, cam);
    ASSERT_EQ(list.items.size(), 1u);
    for (Renderer::DepthMode mode : kModes) {
        renderer.setDepthMode(mode);
        const Image plain = draw(list, cam, -1.0f), shaded = draw(list, cam, 1.0f);
        EXPECT_NE(channel(plain, kW / 2, kH / 2, 0), channel(plain, 0, 0, 0));  // the square is drawn
        EXPECT_LE(maxDifference(plain, shaded), 1) << int(mode);
    }
}

TEST_F(EyeDomeTest, SquareBeforeAWallDarkensTheWallBesideItsSilhouetteOnly) {
    ASSERT_TRUE(renderer.reverseZSupported());
    // A wall 10 m away filling the view, and a square 5 m away in its middle: beside the square's edge the wall
    // pixel has a neighbour (1 px away) at half its distance, log2 1 nearer, so its shade is at most exp(-300 / 8).
    const vec4 wallColour(0.6f, 0.6f, 0.6f, 1.0f), squareColour(1.0f, 0.0f, 0.0f, 1.0f);
    auto root = make<Group>();
    root->addChild(square(dvec3(0.0, 0.0, -10.0), 20.0f, wallColour));
    root->addChild(square(dvec3(0.0, 0.0, -5.0), 1.0f, squareColour));
    const Camera cam = camera();
    const DrawList list = cull(root, cam);
    ASSERT_EQ(list.items.size(), 2u);
    for (Renderer::DepthMode mode : kModes) {
        renderer.setDepthMode(mode);
        const Image plain = draw(list, cam, -1.0f), shaded = draw(list, cam, 1.0f);
        auto onSquare = [&](int x, int y) {  // red, green 0: the square (the wall is grey)
            return x >= 0 && y >= 0 && x < kW && y < kH && channel(plain, x, y, 1) == 0;
        };
        size_t darkened = 0, squarePixels = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                if (onSquare(x, y)) {  // nearer than all its neighbours: unchanged
                    ++squarePixels;
                    EXPECT_LE(std::abs(channel(shaded, x, y, 0) - channel(plain, x, y, 0)), 1) << x << "," << y;
                    continue;
                }
                const int before = channel(plain, x, y, 1), after = channel(shaded, x, y, 1);  // the wall's green
                bool besideEdge = false, nearEdge = false;  // a square pixel 1 px away (4-neighbour), within 2 px
                for (int dy = -2; dy <= 2; ++dy)
                    for (int dx = -2; dx <= 2; ++dx) {
                        if (!onSquare(x + dx, y + dy)) continue;
                        nearEdge = true;
                        besideEdge = besideEdge || std::abs(dx) + std::abs(dy) == 1;
                    }
                if (after < before) ++darkened;
                if (besideEdge) {
                    EXPECT_LT(after, before / 2) << x << "," << y << " mode " << int(mode);
                }
                if (!nearEdge) {
                    EXPECT_LE(std::abs(after - before), 1) << x << "," << y << " mode " << int(mode);
                }
            }
        // The square is about 35 px wide (its half-size 0.2 of the distance, 36 px / tan(22.5 deg) per unit):
        // a ring of well over 4 x 25 wall pixels.
        EXPECT_GT(squarePixels, 25u * 25u);
        EXPECT_GT(darkened, 100u) << int(mode);
    }
}

TEST_F(EyeDomeTest, StrengthZeroChangesNothing) {
    auto root = make<Group>();
    root->addChild(square(dvec3(0.0, 0.0, -10.0), 20.0f, vec4(0.6f, 0.6f, 0.6f, 1.0f)));
    root->addChild(square(dvec3(0.0, 0.0, -5.0), 1.0f, vec4(1.0f, 0.0f, 0.0f, 1.0f)));
    const Camera cam = camera();
    const DrawList list = cull(root, cam);
    for (Renderer::DepthMode mode : kModes) {
        renderer.setDepthMode(mode);
        const Image plain = draw(list, cam, -1.0f), zero = draw(list, cam, 0.0f);
        EXPECT_EQ(plain.rgba, zero.rgba) << int(mode);
    }
}
