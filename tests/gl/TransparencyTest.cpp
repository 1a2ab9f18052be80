// Blended materials (glTF's alphaMode BLEND): drawn after the opaque items, farthest first, depth-tested without
// writing depth, composited as "over" on the framebuffer's (sRGB) values.
#include "RenderUtil.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

using namespace sg;

namespace {

constexpr int kW = 120, kH = 90;
const vec4 kClear(0.2f, 0.2f, 0.2f, 1.0f);

// A square of side 2s facing +Z at depth z, centred on (cx, cy); tilt turns it about Y.
ref_ptr<Mesh> square(float s, float z, float tilt = 0.0f) {
    const float dx = s * std::cos(tilt), dz = s * std::sin(tilt);
    auto m = make<Mesh>();
    m->set({{-dx, -s, z + dz}, {dx, -s, z - dz}, {dx, s, z - dz}, {-dx, s, z + dz}},
           std::vector<vec3>(4, vec3(0, 0, 1)), {0, 1, 2, 0, 2, 3});
    return m;
}

// Unlit physical materials write their base colour as sRGB: the expected pixels are easy to work out.
ref_ptr<Material> flat(const vec3& linear, float alpha, bool blend) {
    auto m = make<Material>(vec4(linear, alpha));
    m->physical = true;
    m->unlit = true;
    m->blend = blend;
    return m;
}

double toSrgb(double c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055; }

// a over b, per channel, on 0..1 sRGB values.
std::array<double, 3> over(const std::array<double, 3>& a, double alpha, const std::array<double, 3>& b) {
    return {a[0] * alpha + b[0] * (1 - alpha), a[1] * alpha + b[1] * (1 - alpha), a[2] * alpha + b[2] * (1 - alpha)};
}
std::array<double, 3> srgb(const vec3& c) { return {toSrgb(c.r), toSrgb(c.g), toSrgb(c.b)}; }

int maxDiff(const Image& img, int x, int y, const std::array<double, 3>& want) {
    const uint8_t* p = &img.rgba[(size_t(y) * kW + size_t(x)) * 4u];
    int d = 0;
    for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(int(p[k]) - int(std::lround(want[size_t(k)] * 255.0))));
    return d;
}

struct TransparencyTest : ::testing::Test {
    OsmesaContext context{kW, kH};
    Renderer renderer;
    Camera cam;
    TransparencyTest() {
        cam.setLookAt(dvec3(0, 0, 5), dvec3(0.0), dvec3(0, 1, 0));
        cam.setPerspective(45.0, double(kW) / kH, 0.1, 100.0);
        cam.setViewport(kW, kH);
    }
    Image draw(const ref_ptr<Group>& root) { return testutil::drawGraph(renderer, root, cam, true, kClear); }
};

const vec3 kRed(0.8f, 0.05f, 0.05f), kBlue(0.05f, 0.1f, 0.9f), kGreen(0.1f, 0.7f, 0.1f);

}  // namespace

TEST_F(TransparencyTest, BlendedSquaresCompositeBackToFrontWhateverTheirOrderInTheGraph) {
    const std::array<double, 3> bg{kClear.r, kClear.g, kClear.b};         // the clear colour is written as it is
    const auto want = over(srgb(kRed), 0.5, over(srgb(kBlue), 0.6, bg));  // red (near) over blue over the clear
    for (bool nearFirst : {true, false}) {
        auto root = make<Group>();
        auto nearSq = make<Geometry>(square(1.0f, 0.5f), flat(kRed, 0.5f, true));
        auto farSq = make<Geometry>(square(1.0f, -0.5f), flat(kBlue, 0.6f, true));
        root->addChild(nearFirst ? nearSq : farSq);
        root->addChild(nearFirst ? farSq : nearSq);
        const Image img = draw(root);
        EXPECT_LE(maxDiff(img, kW / 2, kH / 2, want), 2) << (nearFirst ? "near first" : "far first");
    }
}

TEST_F(TransparencyTest, OpaqueInFrontHidesBlendedBehindItAndBlendedInFrontTintsIt) {
    auto root = make<Group>();
    // An opaque green square across the middle, a blended red one behind it and a blended blue one in front of
    // its right half: depth is tested, so the red shows only outside the green; the blue tints the green.
    root->addChild(make<Geometry>(square(0.6f, 0.0f), flat(kGreen, 1.0f, false)));
    root->addChild(make<Geometry>(square(1.4f, -1.0f), flat(kRed, 0.5f, true)));
    auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(0.6, 0.0, 1.0)));
    t->addChild(make<Geometry>(square(0.3f, 0.0f), flat(kBlue, 0.5f, true)));
    root->addChild(t);
    const Image img = draw(root);
    const int cx = kW / 2, cy = kH / 2;
    const std::array<double, 3> bg{kClear.r, kClear.g, kClear.b};        // the clear colour is written as it is
    EXPECT_LE(maxDiff(img, cx - 8, cy, srgb(kGreen)), 2);                // green, red hidden
    EXPECT_LE(maxDiff(img, cx, cy + 19, over(srgb(kRed), 0.5, bg)), 2);  // red beyond the green
    EXPECT_LE(maxDiff(img, cx + 10, cy, over(srgb(kBlue), 0.5, srgb(kGreen))), 2);  // blue over green
}

TEST_F(TransparencyTest, BlendedItemsWriteNoDepth) {
    // Two blended squares crossing: the one tilted about Y has its centre nearer, so it is drawn last, and its
    // right half lies behind the upright one. With depth writes off that half still blends over the upright
    // square; had the upright square written depth, it would be missing there.
    auto root = make<Group>();
    root->addChild(make<Geometry>(square(1.0f, 0.0f), flat(kRed, 0.5f, true)));
    auto t = make<Transform>(glm::translate(dmat4(1.0), dvec3(0.0, 0.0, 0.05)));
    t->addChild(make<Geometry>(square(1.0f, 0.0f, 0.6f), flat(kBlue, 0.5f, true)));
    root->addChild(t);
    const Image img = draw(root);
    const std::array<double, 3> bg{kClear.r, kClear.g, kClear.b};  // the clear colour is written as it is
    const auto both = over(srgb(kBlue), 0.5, over(srgb(kRed), 0.5, bg));
    EXPECT_LE(maxDiff(img, kW / 2 - 12, kH / 2, both), 2);  // the tilted square in front
    EXPECT_LE(maxDiff(img, kW / 2 + 12, kH / 2, both), 2);  // behind the upright one, blended all the same
}
