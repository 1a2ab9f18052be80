// Texture samplers in the renderer: wrapping beyond [0, 1] and the magnification filter, drawn headless and read
// back pixel by pixel, and one GL sampler object per distinct Sampler.
#include "RenderUtil.h"
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>

using namespace sg;

namespace {

// 96 pixels square: a quad over the whole view with UVs from -1 to 2 gives each texel of a 2x2 texture 16 pixels.
constexpr int kW = 96, kH = 96;
using Rgb = std::array<int, 3>;
// Texel (column, row); row 0 is v = 0.
const Rgb kTexel[2][2] = {{{255, 0, 0}, {0, 0, 255}}, {{0, 255, 0}, {255, 255, 0}}};  // [column][row]

ref_ptr<Texture> fourColours(const Sampler& s) {
    std::vector<uint8_t> px(16);
    for (int row = 0; row < 2; ++row)
        for (int col = 0; col < 2; ++col)
            for (int c = 0; c < 4; ++c)
                px[size_t((row * 2 + col) * 4 + c)] = uint8_t(c < 3 ? kTexel[col][row][c] : 255);
    auto t = make<Texture>(2, 2, px);
    t->sampler = s;
    return t;
}

// A quad from x0 to x1 (and -1 to 1 in y) at z = 0, UVs from -1 to 2 along both axes, unlit under the texture:
// the pixels are the texture's values.
ref_ptr<Geometry> quad(float x0, float x1, const ref_ptr<Texture>& tex) {
    auto m = make<Mesh>();
    m->set({{x0, -1, 0}, {x1, -1, 0}, {x1, 1, 0}, {x0, 1, 0}}, std::vector<vec3>(4, vec3(0, 0, 1)), {0, 1, 2, 0, 2, 3},
           {{-1, -1}, {2, -1}, {2, 2}, {-1, 2}});
    auto mat = make<Material>(vec4(1.0f), tex);
    mat->unlit = true;
    return make<Geometry>(m, mat);
}

Sampler sampler(Sampler::Wrap s, Sampler::Wrap t, Sampler::Filter mag = Sampler::Filter::Nearest) {
    Sampler x;
    x.wrapS = s;
    x.wrapT = t;
    x.magFilter = mag;
    x.minFilter = Sampler::Filter::Nearest;
    return x;
}

// The texel (0 or 1) a coordinate well inside a texel reads, as GL defines the wrap modes for a texture of 2.
int texelOf(double u, Sampler::Wrap w) {
    double f = u;
    if (w == Sampler::Wrap::Repeat) f = u - std::floor(u);
    if (w == Sampler::Wrap::ClampToEdge) f = std::min(std::max(u, 0.0), 1.0);
    if (w == Sampler::Wrap::MirroredRepeat) {
        const double a = u - 2.0 * std::floor(u / 2.0);  // in [0, 2): the second unit mirrored
        f = a <= 1.0 ? a : 2.0 - a;
    }
    return std::min(int(f * 2.0), 1);
}

Rgb pixel(const Image& img, int x, int yFromBottom) {
    const uint8_t* p = &img.rgba[(size_t(img.height - 1 - yFromBottom) * size_t(img.width) + size_t(x)) * 4u];
    return {p[0], p[1], p[2]};
}

bool near(const Rgb& a, const Rgb& b, int tol) {
    for (size_t k = 0; k < 3; ++k)
        if (std::abs(a[k] - b[k]) > tol) return false;
    return true;
}

struct SamplerTest : ::testing::Test {
    OsmesaContext context{kW, kH};
    Renderer renderer;
    Camera cam;
    SamplerTest() {
        cam.setLookAt(dvec3(0, 0, 5), dvec3(0.0), dvec3(0, 1, 0));
        cam.setProjection(glm::ortho(-1.0, 1.0, -1.0, 1.0, 0.1, 10.0));  // x and y in [-1, 1] fill the view
        cam.setViewport(kW, kH);
    }
    Image draw(const ref_ptr<Group>& root) { return testutil::drawGraph(renderer, root, cam); }

    // Each 16-pixel square of the whole-view quad, at its centre, shows the texel the wrap modes pick.
    void expectWrap(const Sampler& s) {
        auto root = make<Group>();
        root->addChild(quad(-1, 1, fourColours(s)));
        const Image img = draw(root);
        for (int j = 0; j < 6; ++j)
            for (int i = 0; i < 6; ++i) {
                const int x = 8 + 16 * i, y = 8 + 16 * j;
                const double u = -1.0 + 3.0 * (x + 0.5) / kW, v = -1.0 + 3.0 * (y + 0.5) / kH;
                const Rgb want = kTexel[texelOf(u, s.wrapS)][texelOf(v, s.wrapT)];
                EXPECT_TRUE(near(pixel(img, x, y), want, 1))
                    << "pixel (" << x << ", " << y << ") at uv (" << u << ", " << v << ")";
            }
    }
};

}  // namespace

TEST_F(SamplerTest, TheWrapModesAgreeWithTheirDefinition) {
    // Along u the six squares read texels 0 0 0 1 1 1 (clamp), 0 1 0 1 0 1 (repeat), 1 0 0 1 1 0 (mirrored).
    EXPECT_EQ(texelOf(-0.75, Sampler::Wrap::ClampToEdge), 0);
    EXPECT_EQ(texelOf(1.75, Sampler::Wrap::ClampToEdge), 1);
    EXPECT_EQ(texelOf(-0.75, Sampler::Wrap::Repeat), 0);
    EXPECT_EQ(texelOf(-0.25, Sampler::Wrap::Repeat), 1);
    EXPECT_EQ(texelOf(-0.75, Sampler::Wrap::MirroredRepeat), 1);
    EXPECT_EQ(texelOf(-0.25, Sampler::Wrap::MirroredRepeat), 0);
    EXPECT_EQ(texelOf(1.25, Sampler::Wrap::MirroredRepeat), 1);
    EXPECT_EQ(texelOf(1.75, Sampler::Wrap::MirroredRepeat), 0);
}

TEST_F(SamplerTest, ClampToEdgeStretchesTheEdgeTexels) {
    expectWrap(sampler(Sampler::Wrap::ClampToEdge, Sampler::Wrap::ClampToEdge));
}

TEST_F(SamplerTest, RepeatRepeatsThePattern) { expectWrap(sampler(Sampler::Wrap::Repeat, Sampler::Wrap::Repeat)); }

TEST_F(SamplerTest, MirroredRepeatMirrorsEveryOtherCopy) {
    expectWrap(sampler(Sampler::Wrap::MirroredRepeat, Sampler::Wrap::MirroredRepeat));
}

TEST_F(SamplerTest, EachAxisWrapsByItsOwnMode) {
    expectWrap(sampler(Sampler::Wrap::Repeat, Sampler::Wrap::ClampToEdge));
    expectWrap(sampler(Sampler::Wrap::ClampToEdge, Sampler::Wrap::MirroredRepeat));
}

TEST_F(SamplerTest, NearestMagnificationKeepsTexelsPureWhereLinearMixesThem) {
    // Pixels 47 and 48 lie either side of u = 0.5, the edge between texel columns 0 (red) and 1 (green), in the
    // middle third; row 40 lies at v = 0.2656, in row 0, 1/32 of a texel spacing above its centre.
    const int y = 40;
    auto drawWith = [&](Sampler::Filter mag) {
        auto root = make<Group>();
        root->addChild(quad(-1, 1, fourColours(sampler(Sampler::Wrap::Repeat, Sampler::Wrap::Repeat, mag))));
        return draw(root);
    };
    const Image nearest = drawWith(Sampler::Filter::Nearest);
    EXPECT_TRUE(near(pixel(nearest, 47, y), kTexel[0][0], 1));
    EXPECT_TRUE(near(pixel(nearest, 48, y), kTexel[1][0], 1));
    // Linear at pixel 47: u = 0.484375, 15/32 of the way from column 0's centre to column 1's; v 1/32 of the way
    // from row 0's centre to row 1's: red 17/32 * 31/32 + 15/32 * 1/32 (yellow), green 15/32, blue 17/32 * 1/32.
    const Image linear = drawWith(Sampler::Filter::Linear);
    const double cu = 15.0 / 32.0, rv = 1.0 / 32.0;
    const Rgb mix{int(std::lround(255 * ((1 - cu) * (1 - rv) + cu * rv))), int(std::lround(255 * cu)),
                  int(std::lround(255 * (1 - cu) * rv))};
    EXPECT_TRUE(near(pixel(linear, 47, y), mix, 6)) << pixel(linear, 47, y)[0] << " " << pixel(linear, 47, y)[1];
    EXPECT_FALSE(near(pixel(linear, 47, y), kTexel[0][0], 60));
    EXPECT_FALSE(near(pixel(linear, 48, y), kTexel[1][0], 60));
}

TEST_F(SamplerTest, TwoTexturesInOneFrameEachDrawWithTheirOwnSampler) {
    // Two half-view quads, each with UVs from -1 to 2 over 48 pixels: 8 pixels a texel. Row 40 reads texel row 0.
    auto root = make<Group>();
    const Sampler clamp = sampler(Sampler::Wrap::ClampToEdge, Sampler::Wrap::ClampToEdge);
    const Sampler repeat = sampler(Sampler::Wrap::Repeat, Sampler::Wrap::Repeat);
    root->addChild(quad(-1, 0, fourColours(clamp)));
    root->addChild(quad(0, 1, fourColours(repeat)));
    const Image img = draw(root);
    for (int i = 0; i < 6; ++i) {
        const double u = -1.0 + 3.0 * (4 + 8 * i + 0.5) / 48.0;
        EXPECT_TRUE(near(pixel(img, 4 + 8 * i, 40), kTexel[texelOf(u, clamp.wrapS)][0], 1)) << "left, square " << i;
        EXPECT_TRUE(near(pixel(img, 52 + 8 * i, 40), kTexel[texelOf(u, repeat.wrapS)][0], 1)) << "right, square " << i;
    }
    EXPECT_EQ(renderer.samplerCount(), 2u);
    EXPECT_EQ(renderer.cachedTextures(), 2u);
}

TEST_F(SamplerTest, TexturesWithEqualSamplersShareOneSamplerObject) {
    auto root = make<Group>();
    const Sampler s = sampler(Sampler::Wrap::MirroredRepeat, Sampler::Wrap::ClampToEdge);
    root->addChild(quad(-1, 0, fourColours(s)));
    root->addChild(quad(0, 1, fourColours(s)));
    draw(root);
    EXPECT_EQ(renderer.cachedTextures(), 2u);
    EXPECT_EQ(renderer.samplerCount(), 1u);
    renderer.clear();
    EXPECT_EQ(renderer.samplerCount(), 0u);
}

TEST_F(SamplerTest, TheDefaultSamplerRepeats) {
    // Repeat and trilinear: at the centre of texel (1, 0)'s copy left of u = 0 (pixel 23: u = -0.2656), the
    // colour is that texel's, mixed by 1/32 of a texel at most with its neighbours.
    auto root = make<Group>();
    root->addChild(quad(-1, 1, fourColours(Sampler{})));
    const Image img = draw(root);
    EXPECT_TRUE(near(pixel(img, 23, 40), kTexel[1][0], 24));
    EXPECT_EQ(renderer.samplerCount(), 1u);
}
