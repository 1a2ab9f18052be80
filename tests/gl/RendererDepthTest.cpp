// Renderer depth range: near/far 1e7 with reverse-Z, surfaces 1e-4 of their distance apart at 1e6 m.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace sg;

namespace {

constexpr int kW = 96, kH = 72;
constexpr double kNear = 0.1, kFar = 1e6;  // the ratio of the issue: 1e7
const vec4 kClear(0.2f, 0.4f, 0.6f, 1.0f), kNearColour(1.0f, 0.0f, 0.0f, 1.0f), kFarColour(0.0f, 0.0f, 1.0f, 1.0f);

// A square of half-size h in the plane through `centre` perpendicular to `dir`: large enough to fill the view.
ref_ptr<Node> facingSquare(const dvec3& centre, const dvec3& dir, double h, const vec4& colour) {
    auto mesh = make<Mesh>();
    const float s = float(h);
    mesh->set({{-s, -s, 0.0f}, {s, -s, 0.0f}, {s, s, 0.0f}, {-s, s, 0.0f}}, {}, {0, 1, 2, 0, 2, 3});
    auto mat = make<Material>(colour);
    mat->unlit = true;
    const dvec3 u = glm::normalize(glm::cross(dir, std::abs(dir.y) < 0.9 ? dvec3(0, 1, 0) : dvec3(1, 0, 0)));
    const dvec3 v = glm::cross(dir, u);
    dmat4 m(1.0);
    m[0] = dvec4(u, 0.0);
    m[1] = dvec4(v, 0.0);
    m[2] = dvec4(dir, 0.0);
    m[3] = dvec4(centre, 1.0);
    auto t = make<Transform>(m);
    t->addChild(make<Geometry>(mesh, mat));
    return t;
}

struct Pair {
    ref_ptr<Group> root;  // the draw list points into it
    Camera cam;
    DrawList list;  // items 0 (the far square) and 1 (the near one), unsorted
};

Camera camera(const dvec3& eye, const dvec3& dir) {
    Camera cam;
    cam.setLookAt(eye, eye + dir, std::abs(dir.y) < 0.9 ? dvec3(0, 1, 0) : dvec3(1, 0, 0));
    cam.setPerspective(45.0, double(kW) / kH, kNear, kFar);
    cam.setViewport(kW, kH);
    return cam;
}

Pair culled(const ref_ptr<Group>& root, const Camera& cam) {
    Pair p{root, cam, {}};
    Scene scene(root);
    scene.update();
    CullSettings settings;
    settings.sort = false;
    CullStats stats;
    CullTraversal().cull(scene, cam, settings, p.list, stats);
    return p;
}

// The eye at `eye` looking along `dir`; squares through the points at distances d - gap and d on that line
// (gap = 1e-4 d), far one first, facing the eye or turned by `tilt` radians about a line across the view.
Pair squaresAhead(const dvec3& eye, const dvec3& dir, double d, double tilt = 0.0) {
    const double gap = 1e-4 * d, h = 2.0 * d;
    auto root = make<Group>();
    const dvec3 up = std::abs(dir.y) < 0.9 ? dvec3(0, 1, 0) : dvec3(1, 0, 0);
    const dvec3 normal = std::cos(tilt) * dir + std::sin(tilt) * glm::normalize(glm::cross(dir, up));
    root->addChild(facingSquare(eye + dir * d, normal, h, kFarColour));
    root->addChild(facingSquare(eye + dir * (d - gap), normal, h, kNearColour));
    return culled(root, camera(eye, dir));
}

// Pixels that do not show the near square's colour (with `sky`: that show the far one's), with the far square
// drawn first and then last.
size_t wrongPixels(Renderer& r, Pair& p, const char* what, bool sky = false) {
    size_t wrong = 0;
    EXPECT_EQ(p.list.items.size(), 2u) << what;
    for (const std::vector<uint32_t>& order : {std::vector<uint32_t>{0, 1}, std::vector<uint32_t>{1, 0}}) {
        p.list.order = order;
        r.draw(p.list, p.cam, kClear);
        const Image img = r.readColor();
        for (size_t i = 0; i < img.rgba.size(); i += 4)
            if (sky ? img.rgba[i + 2] == 255 : img.rgba[i] != 255 || img.rgba[i + 1] != 0 || img.rgba[i + 2] != 0)
                ++wrong;
        for (float z : r.readDepth()) EXPECT_TRUE(std::isfinite(z) && z >= 0.0f && z <= 1.0f) << what << ": " << z;
    }
    return wrong;
}

struct RendererDepthTest : ::testing::Test {
    OsmesaContext context{kW, kH};
    Renderer renderer;
};

}  // namespace

TEST_F(RendererDepthTest, AutoIsTheDefaultWhereTheContextHasClipControl) {
    ASSERT_TRUE(renderer.reverseZSupported());  // llvmpipe: OpenGL 4.5
    EXPECT_EQ(renderer.depthMode(), Renderer::DepthMode::Auto);
    renderer.setDepthMode(Renderer::DepthMode::Classic);
    EXPECT_EQ(renderer.depthMode(), Renderer::DepthMode::Classic);
}

TEST_F(RendererDepthTest, AutoReversesOnlyLongRanges) {
    // An empty frame's depth is the clear value: 1 with Classic, 0 with ReverseZ (the far plane).
    auto clearDepth = [&](double zNear, double zFar) {
        Camera cam;
        cam.setPerspective(45.0, double(kW) / kH, zNear, zFar);
        cam.setViewport(kW, kH);
        renderer.draw(DrawList{}, cam, kClear);
        return renderer.readDepth().at(0);
    };
    EXPECT_EQ(clearDepth(1.0, 1000.0), 1.0f);    // ratio 1e3: Classic, no copy
    EXPECT_EQ(clearDepth(0.1, 1e6), 0.0f);       // 1e7: ReverseZ
    EXPECT_EQ(clearDepth(1.0, 1.0001e4), 0.0f);  // just past kAutoReverseRatio
    renderer.setDepthMode(Renderer::DepthMode::ReverseZ);
    EXPECT_EQ(clearDepth(1.0, 1000.0), 0.0f);
}

TEST_F(RendererDepthTest, ReverseZProjectionMapsNearToOneAndFarToZeroWithoutNaN) {
    Camera cam;
    cam.setPerspective(45.0, 4.0 / 3.0, kNear, kFar);
    const dmat4 p = cam.reverseZProjection();
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) EXPECT_TRUE(std::isfinite(p[c][r]));
    auto depth = [&](double z) {
        const dvec4 clip = p * dvec4(0.0, 0.0, -z, 1.0);
        return clip.z / clip.w;
    };
    EXPECT_NEAR(depth(kNear), 1.0, 1e-12);
    EXPECT_NEAR(depth(kFar), 0.0, 1e-12);
    // The float depth of 1e6 - 200 m and 1e6 - 100 m: apart by many float steps (about 1.5e-11 and 5e-12).
    const float a = float(depth(kFar - 200.0)), b = float(depth(kFar - 100.0));
    EXPECT_GT(a, b);
    EXPECT_GT(b, 0.0f);
    EXPECT_GT((a - b) / (std::nextafter(a, 1.0f) - a), 1000.0f);
}

TEST_F(RendererDepthTest, NoFightingOneTenThousandthApartAtAMillionMetres) {
    // Along the view axis from the origin, and from an eye a million metres out looking along a skew
    // direction (camera-relative matrices).
    Pair axis = squaresAhead(dvec3(0.0), dvec3(0, 0, -1), kFar - 200.0);
    Pair skew = squaresAhead(dvec3(6e5, -8e5, 0.0), glm::normalize(dvec3(1.0, 0.5, -2.0)), kFar - 200.0);
    EXPECT_EQ(wrongPixels(renderer, axis, "axis"), 0u);
    EXPECT_EQ(wrongPixels(renderer, skew, "skew"), 0u);

    // The test has teeth: a 24-bit depth buffer steps by z^2 / (near 2^24), 600 km here, and cannot tell
    // the squares apart: both round to the far plane's depth, and fail against the cleared one.
    renderer.setDepthMode(Renderer::DepthMode::Classic);
    EXPECT_GT(wrongPixels(renderer, axis, "axis, classic"), size_t(kW * kH) / 2);
    EXPECT_GT(wrongPixels(renderer, skew, "skew, classic"), size_t(kW * kH) / 2);
}

TEST_F(RendererDepthTest, NoFightingOneTenThousandthApartAtAHundredKilometresTurned) {
    // Nearer, and turned 45 degrees so that the depth varies across the view (from 70 to 260 km, short of
    // the far plane): the classic buffer's steps are 3 to 40 km there, and rounding picks the winner.
    Pair p = squaresAhead(dvec3(0.0), glm::normalize(dvec3(0.0, -0.3, -1.0)), 1e5, glm::radians(45.0));
    EXPECT_EQ(wrongPixels(renderer, p, "reverse"), 0u);
    renderer.setDepthMode(Renderer::DepthMode::Classic);
    EXPECT_GT(wrongPixels(renderer, p, "classic"), size_t(kW * kH) / 4);
}

TEST_F(RendererDepthTest, NoFightingOnGroundFromUnderTheEyeToTheHorizon) {
    // Two grounds 0.1 m apart seen from 1 km up: 1e-4 of the distance along every ray, out to the far
    // plane. Each is one square of two triangles reaching behind the eye, so the GPU interpolates depth
    // from the near plane's 1 to the horizon's 0 across a triangle: no fighting on llvmpipe either.
    auto root = make<Group>();
    root->addChild(facingSquare(dvec3(0.0, -0.1, 0.0), dvec3(0, 1, 0), kFar, kFarColour));
    root->addChild(facingSquare(dvec3(0.0), dvec3(0, 1, 0), kFar, kNearColour));
    Pair p = culled(root, camera(dvec3(0.0, 1000.0, 0.0), glm::normalize(dvec3(0.0, -0.2, -1.0))));
    EXPECT_EQ(wrongPixels(renderer, p, "reverse", true), 0u);
    renderer.setDepthMode(Renderer::DepthMode::Classic);
    EXPECT_GT(wrongPixels(renderer, p, "classic", true), size_t(kW * kH) / 4);
}
