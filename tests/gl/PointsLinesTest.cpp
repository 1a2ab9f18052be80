// Renderer: points, lines and outlines drawn headless and read back pixel by pixel.
#include "sg/cull/DrawList.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <vector>

using namespace sg;

namespace {

constexpr int kW = 160, kH = 120;
// Multiples of 1/255: the clear colour converts to RGBA8 without rounding.
const vec4 kClear(51.0f / 255.0f, 102.0f / 255.0f, 153.0f / 255.0f, 1.0f);
const std::array<int, 4> kClear8{51, 102, 153, 255};
const vec4 kRed(1.0f, 0.0f, 0.0f, 1.0f);
const std::array<int, 4> kRed8{255, 0, 0, 255};
const std::array<int, 4> kBlack8{0, 0, 0, 255};

// x from the left, y from the bottom (as GL's window coordinates); readColor's rows run top to bottom.
std::array<int, 4> pixel(const Image& img, int x, int y) {
    const uint8_t* p = &img.rgba[(size_t(kH - 1 - y) * size_t(img.width) + size_t(x)) * 4u];
    return {p[0], p[1], p[2], p[3]};
}

int countColour(const Image& img, const std::array<int, 4>& c) {
    int n = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) n += pixel(img, x, y) == c ? 1 : 0;
    return n;
}

// Orthographic, one world unit a pixel: the world point (x, y, 0) lies at window coordinates (x, y).
Camera pixelCamera() {
    Camera cam;
    cam.setLookAt(dvec3(0.0, 0.0, 5.0), dvec3(0.0), dvec3(0.0, 1.0, 0.0));
    cam.setProjection(glm::ortho(0.0, double(kW), 0.0, double(kH), 0.1, 100.0));
    cam.setViewport(kW, kH);
    return cam;
}

Camera perspectiveCamera(const dvec3& eye, const dvec3& center, double fovy) {
    Camera cam;
    cam.setLookAt(eye, center, dvec3(0.0, 1.0, 0.0));
    cam.setPerspective(fovy, double(kW) / kH, 0.1, 100.0);
    cam.setViewport(kW, kH);
    return cam;
}

// An item placed by `model`, its matrix made eye-relative as the cull makes it.
DrawItem item(const Mesh& mesh, const Material& mat, const Camera& cam, const dmat4& model = dmat4(1.0)) {
    DrawItem it;
    it.mesh = &mesh;
    it.material = &mat;
    it.model = glm::mat4x3(mat4(glm::translate(dmat4(1.0), -cam.eye()) * model));
    return it;
}

ref_ptr<Material> unlit(const vec4& colour) {
    auto m = make<Material>(colour);
    m->unlit = true;
    return m;
}

struct PointsLinesTest : ::testing::Test {
    OsmesaContext context{kW, kH};
    Renderer renderer;  // last: destroyed while its context lives

    Image draw(const DrawList& list, const Camera& cam) {
        renderer.draw(list, cam, kClear);
        return renderer.readColor();
    }
};

}  // namespace

TEST_F(PointsLinesTest, PointSizesCoverSquaresOfThatManyPixels) {
    const Camera cam = pixelCamera();
    auto mesh = make<Mesh>();
    mesh->setPoints({{80.5f, 60.5f, 0.0f}});  // the centre of pixel (80, 60)
    auto mat = unlit(kRed);
    DrawList list;
    list.items.push_back(item(*mesh, *mat, cam));
    for (int size : {1, 3, 7}) {
        PointShading ps;
        ps.pointSize = float(size);
        renderer.setPointShading(ps);
        const Image img = draw(list, cam);
        EXPECT_EQ(countColour(img, kRed8), size * size) << "size " << size;
        const int h = size / 2;  // the square runs from pixel 80 - h to 80 + h
        EXPECT_EQ(pixel(img, 80 - h, 60 - h), kRed8) << "size " << size;
        EXPECT_EQ(pixel(img, 80 + h, 60 + h), kRed8) << "size " << size;
        EXPECT_EQ(pixel(img, 80 + h + 1, 60), kClear8) << "size " << size;
        EXPECT_EQ(pixel(img, 80 - h - 1, 60), kClear8) << "size " << size;
        EXPECT_EQ(renderer.lastStats().points, 1u);
    }
}

TEST_F(PointsLinesTest, RoundPointsAreDiscsInsideTheSquare) {
    const Camera cam = pixelCamera();
    auto mesh = make<Mesh>();
    mesh->setPoints({{80.5f, 60.5f, 0.0f}});
    auto mat = unlit(kRed);
    DrawList list;
    list.items.push_back(item(*mesh, *mat, cam));
    PointShading ps;
    ps.pointSize = 9.0f;  // pixels 76 to 84 either way
    renderer.setPointShading(ps);
    EXPECT_EQ(countColour(draw(list, cam), kRed8), 81);
    ps.round = true;
    renderer.setPointShading(ps);
    const Image img = draw(list, cam);
    // Pixel centres at offsets (i, j), |i|, |j| <= 4, from the point's centre lie in the disc of radius 4.5 when
    // i^2 + j^2 <= 20: 9 + 2 x 9 + 2 x 9 + 2 x 7 + 2 x 5 = 69 of them.
    EXPECT_EQ(countColour(img, kRed8), 69);
    EXPECT_EQ(pixel(img, 80, 60), kRed8);
    EXPECT_EQ(pixel(img, 76, 60), kRed8);
    for (auto [x, y] : {std::pair{76, 56}, {84, 56}, {76, 64}, {84, 64}})
        EXPECT_EQ(pixel(img, x, y), kClear8) << "corner " << x << "," << y;
}

TEST_F(PointsLinesTest, AttenuatedPointsHalveAtTwiceTheDistance) {
    // A 90-degree view: the projection's [1][1] is 1, so a length 1 at distance d spans 60 / d pixels (kH / 2).
    const Camera cam = perspectiveCamera(dvec3(0.0), dvec3(0.0, 0.0, -1.0), 90.0);
    auto mesh = make<Mesh>();
    mesh->setPoints({{0.0f, 0.0f, 0.0f}});
    mesh->setPointSpacing(1.0f);
    auto mat = unlit(kRed);
    PointShading ps;
    ps.pointSize = 1.0f;
    ps.attenuate = true;
    ps.maxPointSize = 64.0f;
    renderer.setPointShading(ps);
    auto sideAt = [&](double distance) {
        DrawList list;
        list.items.push_back(item(*mesh, *mat, cam, glm::translate(dmat4(1.0), dvec3(0.0, 0.0, -distance))));
        return std::sqrt(double(countColour(draw(list, cam), kRed8)));
    };
    const double atSix = sideAt(6.0), atTwelve = sideAt(12.0);  // 10 and 5 pixels
    EXPECT_NEAR(atSix, 10.0, 1.0);
    EXPECT_NEAR(atTwelve, 5.0, 1.0);
    EXPECT_NEAR(atTwelve, atSix / 2.0, 1.0);
    // Clamped to maxPointSize: spacing 4 at distance 6 would be 40 pixels.
    ps.maxPointSize = 8.0f;
    renderer.setPointShading(ps);
    mesh->setPointSpacing(4.0f);
    EXPECT_NEAR(sideAt(6.0), 8.0, 1.0);
    // A mesh without a spacing keeps pointSize (3 or 4 pixels: the point's centre is on pixel edges).
    ps.pointSize = 3.0f;
    renderer.setPointShading(ps);
    mesh->setPointSpacing(0.0f);
    EXPECT_NEAR(sideAt(6.0), 3.0, 1.0);
}

TEST_F(PointsLinesTest, LinesCoverTheirWidthInColumns) {
    const Camera cam = pixelCamera();
    auto mesh = make<Mesh>();
    mesh->setLines({{80.5f, 20.0f, 0.0f}, {80.5f, 100.0f, 0.0f}}, {0, 1});  // down the middle of column 80
    auto mat = unlit(kRed);
    DrawList list;
    list.items.push_back(item(*mesh, *mat, cam));
    PointShading ps;
    renderer.setPointShading(ps);  // width 1
    Image img = draw(list, cam);
    for (int y : {30, 60, 90}) {
        EXPECT_EQ(pixel(img, 80, y), kRed8) << y;
        EXPECT_EQ(pixel(img, 79, y), kClear8) << y;
        EXPECT_EQ(pixel(img, 81, y), kClear8) << y;
    }
    EXPECT_EQ(renderer.lastStats().lines, 1u);
    ps.lineWidth = 3.0f;
    renderer.setPointShading(ps);
    img = draw(list, cam);
    for (int y : {30, 60, 90}) {
        for (int x : {79, 80, 81}) EXPECT_EQ(pixel(img, x, y), kRed8) << x << "," << y;
        EXPECT_EQ(pixel(img, 78, y), kClear8) << y;
        EXPECT_EQ(pixel(img, 82, y), kClear8) << y;
    }
}

// The geometry stage that widens lines where glLineWidth cannot (a window's forward-compatible context) draws what
// glLineWidth draws, whichever way the segments run and whichever way their quads wind under a single-sided material.
TEST_F(PointsLinesTest, WideLinesFromTheGeometryStageCoverWhatGlLineWidthCovers) {
    const Camera cam = pixelCamera();
    auto mesh = make<Mesh>();
    mesh->setLines({{80.5f, 20.0f, 0.0f},
                    {80.5f, 100.0f, 0.0f},
                    {20.0f, 20.0f, 0.0f},
                    {60.0f, 100.0f, 0.0f},
                    {150.0f, 20.0f, 0.0f},
                    {100.0f, 100.0f, 0.0f},
                    {100.0f, 60.5f, 0.0f},
                    {20.0f, 60.5f, 0.0f}},
                   {0, 1, 2, 3, 4, 5, 6, 7});
    auto mat = unlit(kRed);
    mat->doubleSided = false;  // culls back faces: a line's quad has none
    DrawList list;
    list.items.push_back(item(*mesh, *mat, cam));
    PointShading ps;
    ps.lineWidth = 3.0f;
    renderer.setPointShading(ps);
    const Image byWidth = draw(list, cam);
    renderer.setWideLines(Renderer::WideLines::GeometryStage);
    const Image byStage = draw(list, cam);
    const int a = countColour(byWidth, kRed8), b = countColour(byStage, kRed8);
    EXPECT_GT(a, 4 * 60 * 3 / 2);
    EXPECT_NEAR(double(b), double(a), 0.1 * a);  // the ends of the segments are squared off differently
    for (int y : {30, 60, 90})
        for (int x : {79, 80, 81}) EXPECT_EQ(pixel(byStage, x, y), kRed8) << x << "," << y;
    EXPECT_EQ(pixel(byStage, 82, 30), kClear8);
}

TEST_F(PointsLinesTest, OutlineShowsOverItsFacesInBothDepthModesAndHidesBehindABox) {
    // A square turned 60 degrees away (its depth changes fast across the screen), its four sides and its diagonal
    // outlined: the diagonal lies inside the face, where a z-fight would show.
    const std::vector<vec3> corners{{-1.0f, -1.0f, 0.0f}, {1.0f, -1.0f, 0.0f}, {1.0f, 1.0f, 0.0f}, {-1.0f, 1.0f, 0.0f}};
    const std::vector<uint32_t> edges{0, 1, 1, 2, 2, 3, 3, 0, 0, 2};
    auto face = make<Mesh>();
    face->set(corners, {}, {0, 1, 2, 0, 2, 3});
    face->setOutline(edges);
    auto lines = make<Mesh>();  // the same edges alone: the pixels the outline must cover
    lines->setLines(corners, edges);
    auto grey = unlit(vec4(0.8f, 0.8f, 0.8f, 1.0f)), black = unlit(vec4(0.0f, 0.0f, 0.0f, 1.0f)), red = unlit(kRed);
    auto box = makeBoxMesh(dvec3(-2.0, -2.0, 1.5), dvec3(2.0, 2.0, 2.5));  // between the eye and the square
    const dmat4 turn = glm::rotate(dmat4(1.0), glm::radians(60.0), dvec3(0.0, 1.0, 0.0));
    std::vector<Renderer::DepthMode> modes{Renderer::DepthMode::Classic};
    if (renderer.reverseZSupported()) modes.push_back(Renderer::DepthMode::ReverseZ);
    for (Renderer::DepthMode mode : modes) {
        renderer.setDepthMode(mode);
        const Camera cam = perspectiveCamera(dvec3(0.0, 0.0, 5.0), dvec3(0.0), 45.0);
        DrawList reference;
        reference.items.push_back(item(*lines, *black, cam, turn));
        const Image edgesAlone = draw(reference, cam);
        const int edgePixels = countColour(edgesAlone, kBlack8);
        ASSERT_GT(edgePixels, 100);

        DrawList outlined;
        outlined.items.push_back(item(*face, *grey, cam, turn));
        const Image img = draw(outlined, cam);
        EXPECT_EQ(renderer.lastStats().lines, 5u);
        EXPECT_EQ(renderer.lastStats().triangles, 2u);
        int missing = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x)
                if (pixel(edgesAlone, x, y) == kBlack8 && pixel(img, x, y) != kBlack8) ++missing;
        EXPECT_EQ(missing, 0) << "depth mode " << int(mode);
        EXPECT_EQ(countColour(img, kBlack8), edgePixels) << "depth mode " << int(mode);
        EXPECT_GT(countColour(img, {204, 204, 204, 255}), 500) << "the face shows between its edges";

        DrawList hidden;
        hidden.items.push_back(item(*box, *red, cam));
        hidden.items.push_back(item(*face, *grey, cam, turn));
        EXPECT_EQ(countColour(draw(hidden, cam), kBlack8), 0) << "depth mode " << int(mode);
    }
}

TEST_F(PointsLinesTest, StatsCountPointsAndLines) {
    const Camera cam = perspectiveCamera(dvec3(0.0, 0.0, 5.0), dvec3(0.0), 45.0);
    auto points = make<Mesh>();
    points->setPoints({{0.0f, 0.0f, 0.0f}, {0.5f, 0.0f, 0.0f}, {0.0f, 0.5f, 0.0f}});
    auto lines = make<Mesh>();
    lines->setLines({{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 0.0f}}, {0, 1, 1, 2});
    auto box = makeBoxMesh(dvec3(-0.5), dvec3(0.5));
    box->setOutline({0, 1, 1, 2, 2, 3, 3, 0});
    auto mat = unlit(kRed);
    DrawList list;
    list.items.push_back(item(*points, *mat, cam));
    list.items.push_back(item(*points, *mat, cam, glm::translate(dmat4(1.0), dvec3(-1.0, 0.0, 0.0))));
    list.items.push_back(item(*lines, *mat, cam));
    list.items.push_back(item(*box, *mat, cam));
    renderer.draw(list, cam, kClear);
    const RenderStats& s = renderer.lastStats();
    EXPECT_EQ(s.points, 6u);      // 3 points, 2 instances
    EXPECT_EQ(s.lines, 2u + 4u);  // the line mesh's 2 segments and the box's 4 outline edges
    EXPECT_EQ(s.triangles, 12u);
    EXPECT_EQ(s.instances, 4u);
    EXPECT_EQ(s.drawCalls, 4u);  // the points' run, the lines, the box's faces and its outline
}
