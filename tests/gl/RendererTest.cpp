// Renderer and OsmesaContext: headless renders compared pixel by pixel.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/LOD.h"
#include "nodes/Transform.h"
#include "sg/cull/CullTraversal.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/io/ImageIO.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

using namespace sg;

namespace {

constexpr int kW = 160, kH = 120;
// Multiples of 1/255: the clear colour converts to RGBA8 without rounding.
const vec4 kClear(51.0f / 255.0f, 102.0f / 255.0f, 153.0f / 255.0f, 1.0f);
const std::array<int, 4> kClear8{51, 102, 153, 255};

std::array<int, 4> pixel(const Image& img, int x, int y) {
    const uint8_t* p = &img.rgba[(size_t(y) * size_t(img.width) + size_t(x)) * 4u];
    return {p[0], p[1], p[2], p[3]};
}

bool near(const std::array<int, 4>& a, const vec4& c, int tol) {
    for (int i = 0; i < 4; ++i)
        if (std::abs(a[size_t(i)] - int(std::lround(c[i] * 255.0f))) > tol) return false;
    return true;
}

Camera lookingAt(const dvec3& eye, const dvec3& center) {
    Camera cam;
    cam.setLookAt(eye, center, dvec3(0.0, 1.0, 0.0));
    cam.setPerspective(45.0, double(kW) / kH, 0.1, 100.0);
    cam.setViewport(kW, kH);
    return cam;
}

DrawList cull(const ref_ptr<Node>& root, const Camera& cam, bool sort = true) {
    Scene scene(root);
    scene.update();
    DrawList list;
    CullStats stats;
    CullSettings settings;
    settings.sort = sort;
    CullTraversal().cull(scene, cam, settings, list, stats);
    return list;
}

ref_ptr<Group> placed(const ref_ptr<Mesh>& mesh, const ref_ptr<Material>& mat, const dvec3& at) {
    auto t = make<Transform>(glm::translate(dmat4(1.0), at));
    t->addChild(make<Geometry>(mesh, mat));
    return t;
}

// A context and a renderer per test; the renderer is declared last so that it is destroyed while its
// context still exists.
struct RendererTest : ::testing::Test {
    OsmesaContext context{kW, kH};
    Renderer renderer;
};

}  // namespace

TEST_F(RendererTest, EmptyListIsClearColourEverywhere) {
    renderer.draw(DrawList{}, lookingAt(dvec3(0, 0, 5), dvec3(0.0)), kClear);
    const Image img = renderer.readColor();
    ASSERT_EQ(img.width, kW);
    ASSERT_EQ(img.height, kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) ASSERT_EQ(pixel(img, x, y), kClear8) << "at " << x << "," << y;
    EXPECT_EQ(renderer.lastStats().drawCalls, 0u);
    EXPECT_EQ(renderer.lastStats().instances, 0u);
}

TEST_F(RendererTest, BoxAheadCoversCentreAndLeavesCorners) {
    const vec4 red(0.8f, 0.3f, 0.2f, 1.0f);
    auto root = make<Group>();
    root->addChild(make<Geometry>(makeBoxMesh(dvec3(-0.5), dvec3(0.5)), make<Material>(red)));
    const Camera cam = lookingAt(dvec3(0, 0, 5), dvec3(0.0));
    renderer.draw(cull(root, cam), cam, kClear);
    const Image img = renderer.readColor();
    // The front face looks straight at the headlight: ambient 0.35 + diffuse 0.65 = the material colour.
    EXPECT_TRUE(near(pixel(img, kW / 2, kH / 2), red, 2));
    for (auto [x, y] : {std::pair{0, 0}, {kW - 1, 0}, {0, kH - 1}, {kW - 1, kH - 1}})
        EXPECT_EQ(pixel(img, x, y), kClear8) << "corner " << x << "," << y;
    EXPECT_EQ(renderer.lastStats().drawCalls, 1u);
    EXPECT_EQ(renderer.lastStats().triangles, 12u);
}

TEST_F(RendererTest, InstancedRunsGiveTheSameImageWithFewerDrawCalls) {
    // A 6 x 4 grid of two meshes (alternating), one material; spaced so that no two boxes touch.
    auto meshA = makeBoxMesh(dvec3(-0.4), dvec3(0.4));
    auto meshB = makeBoxMesh(dvec3(-0.3, -0.45, -0.3), dvec3(0.3, 0.45, 0.3), 2);
    auto matA = make<Material>(vec4(0.3f, 0.8f, 0.4f, 1.0f));
    auto matB = make<Material>(matA->baseColor);  // same colour, another object: breaks runs
    auto root = make<Group>();
    int k = 0;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 6; ++i, ++k)
            root->addChild(
                placed(k % 2 ? meshB : meshA, matA, dvec3(-3.75 + 1.5 * i, -2.25 + 1.5 * j, -0.7 * (k % 3))));
    const Camera cam = lookingAt(dvec3(1.0, 1.5, 9.0), dvec3(0.0));

    const DrawList sorted = cull(root, cam);  // state order: one run per mesh
    ASSERT_EQ(sorted.items.size(), 24u);
    renderer.draw(sorted, cam, kClear);
    const Image batched = renderer.readColor();
    const RenderStats s1 = renderer.lastStats();

    DrawList single = sorted;  // emission order, materials alternating: every item is its own run
    for (size_t i = 0; i < single.items.size(); ++i) single.items[i].material = (i % 2) ? matB.get() : matA.get();
    single.keepEmissionOrder();
    renderer.draw(single, cam, kClear);
    const Image separate = renderer.readColor();
    const RenderStats s2 = renderer.lastStats();

    EXPECT_EQ(s1.drawCalls, 2u);
    EXPECT_EQ(s2.drawCalls, 24u);
    EXPECT_LT(s1.drawCalls, s2.drawCalls);
    EXPECT_EQ(s1.instances, 24u);
    EXPECT_EQ(s2.instances, 24u);
    EXPECT_EQ(s1.triangles, s2.triangles);
    EXPECT_EQ(countDifferingPixels(batched, separate, 0), 0u);
    Image empty = batched;  // the grid is in view: it covers a good part of the image
    for (size_t i = 0; i < empty.rgba.size(); ++i) empty.rgba[i] = uint8_t(kClear8[i % 4]);
    EXPECT_GT(countDifferingPixels(batched, empty, 0), size_t(kW * kH / 5));
    if (std::getenv("SGKIT_TEST_IMAGES")) savePng("renderer_grid.png", batched);  // to look at by eye
}

TEST_F(RendererTest, MaterialsChangingEveryDrawLookAsTheyDoAlone) {
    // Every item its own material, the shading changing from one draw to the next in every way the renderer
    // tracks (base colour per instance; lit, vertex colours, baked light, highlight, cutoff as uniforms set on
    // change): each box must come out as it does drawn alone, before and after the crowd.
    auto plain = makeBoxMesh(dvec3(-0.4), dvec3(0.4));
    auto coloured = makeBoxMesh(dvec3(-0.4), dvec3(0.4));
    coloured->set(plain->positions(), plain->normals(), {plain->indices16().begin(), plain->indices16().end()}, {},
                  std::vector<vec4>(plain->positions().size(), vec4(0.5f, 1.0f, 0.25f, 0.75f)));
    std::vector<ref_ptr<Material>> mats;
    for (int k = 0; k < 6; ++k) {
        auto m = make<Material>(vec4(0.2f + 0.13f * float(k), 0.9f - 0.1f * float(k), 0.5f, 1.0f));
        m->unlit = k % 3 == 1;
        m->bakedLight = k == 4;
        m->specular = k == 2 ? 0.5f : 0.0f;
        m->alphaCutoff = k == 5 ? 0.1f : 0.0f;
        mats.push_back(m);
    }
    auto root = make<Group>();
    for (int k = 0; k < 12; ++k)
        root->addChild(placed(k % 4 == 3 ? coloured : plain, mats[size_t(k % 6)],
                              dvec3(-3.25 + 1.3 * (k % 6), k < 6 ? 0.7 : -0.7, 0.0)));  // apart on screen
    const Camera cam = lookingAt(dvec3(0.0, 0.0, 9.0), dvec3(0.0));
    DrawList crowd = cull(root, cam);
    crowd.keepEmissionOrder();  // materials alternate: every item is a run of its own
    ASSERT_EQ(crowd.items.size(), 12u);
    renderer.setLight(DirectionalLight::sun(vec3(0.3f, 0.5f, 1.0f), vec3(0.3f), vec3(0.7f)));
    auto alone = [&](size_t i) {
        DrawList one;
        one.items.push_back(crowd.items[i]);
        renderer.draw(one, cam, kClear);
        return renderer.readColor();
    };
    const Image before = alone(7);
    renderer.draw(crowd, cam, kClear);
    ASSERT_EQ(renderer.lastStats().drawCalls, 12u);
    const Image all = renderer.readColor();
    for (size_t i = 0; i < crowd.items.size(); ++i) {
        const Image one = alone(i);
        size_t covered = 0, differing = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                if (pixel(one, x, y) == kClear8) continue;
                ++covered;
                differing += pixel(one, x, y) != pixel(all, x, y);
            }
        EXPECT_GT(covered, 100u) << "item " << i;
        EXPECT_EQ(differing, 0u) << "item " << i;
    }
    EXPECT_EQ(countDifferingPixels(before, alone(7), 0), 0u);
}

TEST_F(RendererTest, SceneTenThousandKilometresAwayRendersLikeAtTheOrigin) {
    auto mesh = makeBoxMesh(dvec3(-0.5), dvec3(0.5), 3);
    auto matA = make<Material>(vec4(0.9f, 0.6f, 0.1f, 1.0f));
    auto matB = make<Material>(vec4(0.2f, 0.5f, 0.9f, 1.0f));
    // Offsets that are not binary fractions, so that the far coordinates do round in double.
    const dvec3 at[3] = {{0.3, 0.1, 0.0}, {-1.7, -0.45, -1.3}, {1.9, 0.6, -2.1}};
    const dvec3 eye(0.4, 1.3, 6.1), center(0.1, 0.2, -0.7);
    auto build = [&](const dvec3& origin) {
        auto root = make<Group>();
        for (int i = 0; i < 3; ++i) root->addChild(placed(mesh, i == 1 ? matB : matA, origin + at[i]));
        return root;
    };
    const dvec3 far(1e7, 1e7, 0.0);

    const Camera camNear = lookingAt(eye, center);
    renderer.draw(cull(build(dvec3(0.0)), camNear), camNear, kClear);
    const Image atOrigin = renderer.readColor();

    const Camera camFar = lookingAt(far + eye, far + center);
    const DrawList farList = cull(build(far), camFar);
    renderer.draw(farList, camFar, kClear);
    const Image away = renderer.readColor();
    if (std::getenv("SGKIT_TEST_IMAGES")) savePng("renderer_far.png", away);

    // Tolerance: 2 pixels. world - eye is computed in double, where 1e7 carries ~2e-9 m of rounding, so
    // an eye-relative float matrix can differ from the origin scene's by one float ulp. That moves an
    // edge by about 1e-7 pixel: only a pixel centre that close to an edge could flip (none does here).
    EXPECT_LE(countDifferingPixels(atOrigin, away, 0), 2u);
    EXPECT_NE(pixel(atOrigin, kW / 2, kH / 2), kClear8);

    // The check has teeth: composing the same matrices in float (world, then minus the eye) loses the
    // offsets below a metre at 1e7 and visibly moves the boxes.
    DrawList naive = farList;
    const mat4 minusEye = mat4(glm::translate(dmat4(1.0), -camFar.eye()));
    for (DrawItem& it : naive.items) {
        const dvec3 world = dvec3(it.model[3]) + camFar.eye();
        it.model = glm::mat4x3(minusEye * mat4(glm::translate(dmat4(1.0), world)));
    }
    renderer.draw(naive, camFar, kClear);
    EXPECT_GT(countDifferingPixels(atOrigin, renderer.readColor(), 0), 100u);
}

TEST_F(RendererTest, DepthIsTheDistanceOnTheBoxAndTheFarValueAtTheCorners) {
    auto root = make<Group>();
    root->addChild(make<Geometry>(makeBoxMesh(dvec3(-0.5), dvec3(0.5)), make<Material>()));
    const Camera cam = lookingAt(dvec3(0, 0, 5), dvec3(0.0));
    const DrawList list = cull(root, cam);
    // The front face is 4.5 from the eye; near 0.1, far 100: reverse-Z stores n (f - z) / (z (f - n)), and
    // the classic buffer one minus that.
    const double n = 0.1, f = 100.0, z = 4.5, reverse = n * (f - z) / (z * (f - n));
    ASSERT_TRUE(renderer.reverseZSupported());  // llvmpipe has GL 4.5
    for (Renderer::DepthMode mode : {Renderer::DepthMode::ReverseZ, Renderer::DepthMode::Classic}) {
        renderer.setDepthMode(mode);
        renderer.draw(list, cam, kClear);
        const std::vector<float> depth = renderer.readDepth();
        ASSERT_EQ(depth.size(), size_t(kW) * kH);
        const bool rev = mode == Renderer::DepthMode::ReverseZ;
        EXPECT_NEAR(depth[size_t(kH / 2) * kW + kW / 2], rev ? reverse : 1.0 - reverse, 1e-6);
        for (auto [x, y] : {std::pair{0, 0}, {kW - 1, 0}, {0, kH - 1}, {kW - 1, kH - 1}})
            EXPECT_EQ(depth[size_t(y) * kW + size_t(x)], rev ? 0.0f : 1.0f) << "corner " << x << "," << y;
    }
}

TEST(OsmesaContextTest, RejectsEmptySizes) {
    EXPECT_THROW(OsmesaContext(0, 10), std::invalid_argument);
    EXPECT_THROW(OsmesaContext(10, -1), std::invalid_argument);
}

TEST_F(RendererTest, ResizedContextRendersAtTheNewSize) {
    context.resize(64, 32);
    Camera cam = lookingAt(dvec3(0, 0, 5), dvec3(0.0));
    cam.setViewport(64, 32);
    renderer.draw(DrawList{}, cam, kClear);
    const Image img = renderer.readColor();
    EXPECT_EQ(img.width, 64);
    EXPECT_EQ(img.height, 32);
    EXPECT_EQ(pixel(img, 63, 31), kClear8);
}

TEST_F(RendererTest, TopRowOfTheImageIsTheTopOfTheView) {
    // A box above the view axis shows in the upper half of the image (rows go top to bottom).
    auto root = make<Group>();
    root->addChild(placed(makeBoxMesh(dvec3(-0.5), dvec3(0.5)), make<Material>(), dvec3(0.0, 1.2, 0.0)));
    const Camera cam = lookingAt(dvec3(0, 0, 5), dvec3(0.0));
    renderer.draw(cull(root, cam), cam, kClear);
    const Image img = renderer.readColor();
    EXPECT_NE(pixel(img, kW / 2, kH / 4), kClear8);
    EXPECT_EQ(pixel(img, kW / 2, 3 * kH / 4), kClear8);
}

TEST_F(RendererTest, UnlitTextureAndVertexColoursMultiply) {
    // One quad facing the camera, with UVs and a vertex colour, under a one-colour texture.
    auto mesh = make<Mesh>();
    const vec4 vc(0.5f, 1.0f, 1.0f, 1.0f);
    mesh->set({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}, {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}},
              {0, 1, 2, 0, 2, 3}, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {vc, vc, vc, vc});
    std::vector<uint8_t> texel;
    for (int i = 0; i < 4 * 4; ++i) texel.insert(texel.end(), {255, 128, 255, 255});
    auto mat = make<Material>(vec4(1.0f, 1.0f, 0.5f, 1.0f), make<Texture>(4, 4, texel));
    mat->unlit = true;
    auto root = make<Group>();
    root->addChild(make<Geometry>(mesh, mat));
    const Camera cam = lookingAt(dvec3(0, 0, 5), dvec3(0.0));
    renderer.draw(cull(root, cam), cam, kClear);
    EXPECT_TRUE(near(pixel(renderer.readColor(), kW / 2, kH / 2), vec4(0.5f, 128.0f / 255.0f, 0.5f, 1.0f), 1));
    EXPECT_EQ(renderer.cachedTextures(), 1u);
}

TEST_F(RendererTest, NormalsFollowNonUniformScale) {
    // A quad with normal (1,1,0)/sqrt2, stretched 3x along y: the true normal becomes (3,1,0)/sqrt10.
    // Seen (and lit) along -x that gives 0.35 + 0.65 * 3/sqrt10; transforming the normal like a position
    // would give 0.35 + 0.65 * 1/sqrt10.
    auto mesh = make<Mesh>();
    const vec3 n = glm::normalize(vec3(1, 1, 0));
    mesh->set({{-0.5f, 0.5f, -1}, {0.5f, -0.5f, -1}, {0.5f, -0.5f, 1}, {-0.5f, 0.5f, 1}}, {n, n, n, n},
              {0, 1, 2, 0, 2, 3});
    auto root = make<Transform>(glm::scale(dmat4(1.0), dvec3(1.0, 3.0, 1.0)));
    root->addChild(make<Geometry>(mesh, make<Material>(vec4(1.0f))));
    const Camera cam = lookingAt(dvec3(5, 0, 0), dvec3(0.0));
    renderer.draw(cull(root, cam), cam, kClear);
    const float expected = 0.35f + 0.65f * 3.0f / std::sqrt(10.0f);
    EXPECT_TRUE(near(pixel(renderer.readColor(), kW / 2, kH / 2), vec4(vec3(expected), 1.0f), 2));
}

TEST_F(RendererTest, MeshesAreUploadedOnceAndReleasedWhenUnused) {
    auto mesh = makeBoxMesh(dvec3(-0.5), dvec3(0.5));
    auto root = make<Group>();
    for (int i = 0; i < 3; ++i) root->addChild(placed(mesh, make<Material>(), dvec3(1.2 * i - 1.2, 0, 0)));
    const Camera cam = lookingAt(dvec3(0, 0, 6), dvec3(0.0));
    const DrawList list = cull(root, cam);
    renderer.draw(list, cam, kClear);
    renderer.draw(list, cam, kClear);
    EXPECT_EQ(renderer.cachedMeshes(), 1u);
    EXPECT_EQ(renderer.lastStats().drawCalls, 3u);  // three materials: three runs
    renderer.draw(DrawList{}, cam, kClear);
    renderer.releaseUnused();
    EXPECT_EQ(renderer.cachedMeshes(), 0u);
}

TEST_F(RendererTest, OrderPastTheItemsThrows) {
    DrawList list;
    list.items.push_back(DrawItem{});
    list.order = {0, 5};
    EXPECT_THROW(renderer.draw(list, lookingAt(dvec3(0, 0, 5), dvec3(0.0))), std::out_of_range);
}

TEST_F(RendererTest, EmptyOrderDrawsTheItemsAndWideIndicesWork) {
    // A box fine enough to need 32-bit indices, in a list without `order`.
    auto mesh = makeBoxMesh(dvec3(-0.5), dvec3(0.5), 110);
    ASSERT_FALSE(mesh->indices32().empty());
    const vec4 red(0.8f, 0.3f, 0.2f, 1.0f);
    auto mat = make<Material>(red);
    const Camera cam = lookingAt(dvec3(0, 0, 5), dvec3(0.0));
    DrawItem item;
    item.mesh = mesh.get();
    item.material = mat.get();
    item.model = glm::mat4x3(glm::translate(dmat4(1.0), -cam.eye()));
    DrawList list;
    list.items.push_back(item);
    renderer.draw(list, cam, kClear);
    EXPECT_EQ(renderer.lastStats().drawCalls, 1u);
    EXPECT_EQ(renderer.lastStats().triangles, uint64_t(mesh->triangleCount()));
    const Image img = renderer.readColor();
    EXPECT_TRUE(near(pixel(img, kW / 2, kH / 2), red, 2));
    EXPECT_EQ(pixel(img, 0, 0), kClear8);
}

// LOD fade on screen: in the band the two levels share the object's pixels with complementary patterns,
// so together they cover exactly what one opaque level covers, in the proportion the band position gives.
TEST_F(RendererTest, LodFadeSharesThePixelsBetweenTheTwoLevels) {
    const vec4 red(1, 0, 0, 1), green(0, 1, 0, 1);
    auto matOf = [](const vec4& c) {
        auto m = make<Material>();
        m->baseColor = c;
        m->unlit = true;
        return m;
    };
    auto mesh = makeBoxMesh(dvec3(-2.0), dvec3(2.0));
    auto lod = make<LOD>();
    lod->addChild(make<Geometry>(mesh, matOf(red)), 0, 10);
    lod->addChild(make<Geometry>(mesh, matOf(green)), 10, 100);
    lod->setCenter(dvec3(0.0));
    lod->setTransition(2.0f);
    Scene scene(lod);
    scene.update();
    auto render = [&](double dist, bool fade) {
        const Camera cam = lookingAt(dvec3(0.3, 0.2, dist), dvec3(0.0));
        CullSettings set;
        set.lodFade = fade;
        DrawList list;
        CullStats stats;
        CullTraversal().cull(scene, cam, set, list, stats);
        list.sort();
        renderer.draw(list, cam, kClear);
        return renderer.readColor();
    };
    for (double dist : {9.5, 10.0, 10.5}) {
        const Image opaque = render(dist, false), faded = render(dist, true);
        int covered = 0, r = 0, g = 0, other = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                const bool in = pixel(opaque, x, y) != kClear8;
                const auto p = pixel(faded, x, y);
                covered += in;
                if (!in)
                    other += p != kClear8;  // nothing outside the object
                else if (near(p, red, 0))
                    ++r;
                else if (near(p, green, 0))
                    ++g;
                else
                    ++other;  // a hole or a blend: neither level
            }
        ASSERT_GT(covered, 1000);
        EXPECT_EQ(other, 0) << dist;
        EXPECT_EQ(r + g, covered) << dist;
        // The detailed (red) share is (11 - dist) / 2: 0.75, 0.5, 0.25, within the pattern's spread.
        EXPECT_NEAR(double(r) / covered, (11.0 - dist) / 2.0, 0.03) << dist;
    }
}

// Alpha cut-out: a quad whose texture is transparent (black underneath) in its left half and red in its
// right half, magnified (16 texels) and minified (256 texels, sampled from the mipmaps).
TEST_F(RendererTest, AlphaCutoffCutsTheTransparentHalfWithoutAFringe) {
    const std::array<int, 3> red{200, 40, 60};
    auto mesh = make<Mesh>();
    mesh->set({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}, {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}},
              {0, 1, 2, 0, 2, 3}, {{0, 0}, {1, 0}, {1, 1}, {0, 1}});
    const Camera cam = lookingAt(dvec3(0, 0, 5), dvec3(0.0));
    auto rgbIs = [](const std::array<int, 4>& p, const std::array<int, 3>& c, int tol) {
        for (size_t i = 0; i < 3; ++i)
            if (std::abs(p[i] - c[i]) > tol) return false;
        return true;
    };
    for (int size : {16, 256}) {
        SCOPED_TRACE(size);
        std::vector<uint8_t> px;
        for (int j = 0; j < size; ++j)
            for (int i = 0; i < size; ++i)
                px.insert(px.end(), i < size / 2 ? std::initializer_list<uint8_t>{0, 0, 0, 0}
                                                 : std::initializer_list<uint8_t>{200, 40, 60, 255});
        auto mat = make<Material>(vec4(1.0f), make<Texture>(size, size, px));
        mat->unlit = true;
        auto root = make<Group>();
        root->addChild(make<Geometry>(mesh, mat));
        const DrawList list = cull(root, cam);

        // Off (the default): the whole quad is drawn, the transparent half with its own hidden colour.
        renderer.draw(list, cam, kClear);
        const Image whole = renderer.readColor();
        EXPECT_TRUE(rgbIs(pixel(whole, kW / 2 - 15, kH / 2), {0, 0, 0}, 0));
        EXPECT_TRUE(rgbIs(pixel(whole, kW / 2 + 15, kH / 2), red, 0));

        mat->alphaCutoff = 0.5f;
        renderer.draw(list, cam, kClear);
        const Image cut = renderer.readColor();
        if (std::getenv("SGKIT_TEST_IMAGES")) savePng("renderer_alphacut_" + std::to_string(size) + ".png", cut);
        EXPECT_EQ(pixel(cut, kW / 2 - 15, kH / 2), kClear8);
        EXPECT_TRUE(rgbIs(pixel(cut, kW / 2 + 15, kH / 2), red, 0));
        // Every pixel is the background exactly or the texture's red: none mixes in the hidden black,
        // also along the cut where filtering and the mipmaps sample both halves.
        int background = 0, texture = 0, other = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                const auto p = pixel(cut, x, y);
                if (p == kClear8)
                    ++background;
                else if (rgbIs(p, red, 2))
                    ++texture;
                else
                    ++other;
            }
        EXPECT_EQ(other, 0);
        // The quad spans about 58 x 58 pixels: half of it is left.
        EXPECT_GT(texture, 1400);
        EXPECT_LT(texture, 1900);
        EXPECT_EQ(background + texture, kW * kH);
        // Off again: the same pixels as the first draw.
        mat->alphaCutoff = 0.0f;
        renderer.draw(list, cam, kClear);
        EXPECT_EQ(countDifferingPixels(whole, renderer.readColor(), 0), 0u);
    }
}

namespace {
// A 20 x 20 quad in the z = 0 plane, normal +z, with vertex colour `c` (for bakedLight: rgb albedo x
// occlusion, alpha sun visibility).
ref_ptr<Group> floorQuad(const ref_ptr<Material>& mat, const vec4& c = vec4(1.0f)) {
    auto mesh = make<Mesh>();
    const vec3 n(0, 0, 1);
    mesh->set({{-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}}, {n, n, n, n}, {0, 1, 2, 0, 2, 3}, {},
              {c, c, c, c});
    auto root = make<Group>();
    root->addChild(make<Geometry>(mesh, mat));
    return root;
}
}  // namespace

TEST_F(RendererTest, SunLightFollowsNDotL) {
    const auto root = floorQuad(make<Material>(vec4(1.0f)));
    const Camera cam = lookingAt(dvec3(0, 0, 5), dvec3(0.0));
    const DrawList list = cull(root, cam);
    // From overhead to grazing, then from below the surface: ambient + color x max(0, n.l).
    for (double deg : {0.0, 30.0, 60.0, 80.0, 120.0}) {
        const double a = glm::radians(deg);
        renderer.setLight(
            DirectionalLight::sun(vec3(float(std::sin(a)), 0.0f, float(std::cos(a))), vec3(0.2f), vec3(0.7f)));
        renderer.draw(list, cam, kClear);
        const float expected = 0.2f + 0.7f * float(std::max(0.0, std::cos(a)));
        EXPECT_TRUE(near(pixel(renderer.readColor(), kW / 2, kH / 2), vec4(vec3(expected), 1.0f), 2))
            << deg << " degrees: " << pixel(renderer.readColor(), kW / 2, kH / 2)[0] << " for " << expected * 255;
    }
}

TEST_F(RendererTest, HighlightWhereTheReflectionMeetsTheEyeOnly) {
    auto shiny = make<Material>(vec4(1.0f));
    shiny->specular = 0.5f;
    shiny->shininess = 400.0f;
    const auto root = floorQuad(shiny);
    // The eye 45 degrees up in -x, looking at the origin: the sun 45 degrees up in +x mirrors into it there.
    const Camera cam = lookingAt(dvec3(-3, 0, 3), dvec3(0.0));
    const DrawList list = cull(root, cam);
    const float diffuse = 0.2f + 0.6f * std::sqrt(0.5f);
    auto brightest = [](const Image& img, int cx, int cy) {
        int best = 0;
        for (int y = cy - 2; y <= cy + 2; ++y)
            for (int x = cx - 2; x <= cx + 2; ++x) best = std::max(best, pixel(img, x, y)[0]);
        return best;
    };
    renderer.setLight(DirectionalLight::sun(vec3(1, 0, 1), vec3(0.2f), vec3(0.6f)));
    renderer.draw(list, cam, kClear);
    Image img = renderer.readColor();
    EXPECT_NEAR(brightest(img, kW / 2, kH / 2), std::lround((diffuse + 0.6f * 0.5f) * 255.0f), 3);
    // Off the mirror direction the highlight is gone: the surface has its diffuse colour.
    EXPECT_TRUE(near(pixel(img, 8, kH / 2), vec4(vec3(diffuse), 1.0f), 2)) << pixel(img, 8, kH / 2)[0];
    EXPECT_TRUE(near(pixel(img, kW / 2, 8), vec4(vec3(diffuse), 1.0f), 2)) << pixel(img, kW / 2, 8)[0];
    // The sun behind the eye lights the surface as much (same n.l) but reflects away from the eye.
    renderer.setLight(DirectionalLight::sun(vec3(-1, 0, 1), vec3(0.2f), vec3(0.6f)));
    renderer.draw(list, cam, kClear);
    img = renderer.readColor();
    EXPECT_TRUE(near(pixel(img, kW / 2, kH / 2), vec4(vec3(diffuse), 1.0f), 2)) << pixel(img, kW / 2, kH / 2)[0];
    // The headlight draws no highlight, whatever the material says.
    renderer.setLight(DirectionalLight{});
    renderer.draw(list, cam, kClear);
    EXPECT_TRUE(
        near(pixel(renderer.readColor(), kW / 2, kH / 2), vec4(vec3(0.35f + 0.65f * std::sqrt(0.5f)), 1.0f), 2));
}

TEST_F(RendererTest, BakedSunVisibilityDimsTheDirectLightAndOcclusionTheColour) {
    auto baked = make<Material>(vec4(1.0f));
    baked->bakedLight = true;
    const Camera cam = lookingAt(dvec3(0, 0, 5), dvec3(0.0));
    renderer.setLight(DirectionalLight::sun(vec3(0, 0, 1), vec3(0.3f), vec3(0.6f)));
    auto centre = [&](const vec4& c) {
        renderer.draw(cull(floorQuad(baked, c), cam), cam, kClear);
        return pixel(renderer.readColor(), kW / 2, kH / 2);
    };
    EXPECT_TRUE(near(centre(vec4(1, 1, 1, 1)), vec4(vec3(0.9f), 1.0f), 2));
    // In full shadow only the ambient term is left; the alpha is visibility, not opacity.
    EXPECT_TRUE(near(centre(vec4(1, 1, 1, 0)), vec4(vec3(0.3f), 1.0f), 2));
    EXPECT_TRUE(near(centre(vec4(1, 1, 1, 0.5f)), vec4(vec3(0.6f), 1.0f), 2));
    // Occlusion (in the colour) scales what the surface reflects.
    EXPECT_TRUE(near(centre(vec4(0.5f, 0.5f, 0.5f, 0)), vec4(vec3(0.15f), 1.0f), 2));
    // A material that is not bakedLight reads the same colours as plain colour with alpha 0 (not cut).
    EXPECT_TRUE(near(pixel(
                         [&] {
                             renderer.draw(cull(floorQuad(make<Material>(vec4(1.0f)), vec4(1, 1, 1, 0)), cam), cam,
                                           kClear);
                             return renderer.readColor();
                         }(),
                         kW / 2, kH / 2),
                     vec4(0.9f, 0.9f, 0.9f, 0.0f), 2));
}

TEST_F(RendererTest, DefaultLightIsTheHeadlightAndComesBackPixelForPixel) {
    EXPECT_TRUE(renderer.light().headlight);
    auto root = make<Group>();
    root->addChild(make<Geometry>(makeBoxMesh(dvec3(-0.5), dvec3(0.5), 2), make<Material>(vec4(0.8f, 0.5f, 0.3f, 1))));
    const Camera cam = lookingAt(dvec3(2, 1.5, 3), dvec3(0.0));
    const DrawList list = cull(root, cam);
    renderer.draw(list, cam, kClear);
    const Image before = renderer.readColor();
    renderer.setLight(DirectionalLight::sun(vec3(0, 1, 0), vec3(0.3f), vec3(0.7f)));
    renderer.draw(list, cam, kClear);
    EXPECT_GT(countDifferingPixels(before, renderer.readColor(), 2), 100u);
    renderer.setLight(DirectionalLight{});
    renderer.draw(list, cam, kClear);
    EXPECT_EQ(countDifferingPixels(before, renderer.readColor(), 0), 0u);
}

TEST_F(RendererTest, SetLightRefusesASunWithoutDirection) {
    for (const vec3& d : {vec3(0.0f), vec3(std::nanf(""), 0.0f, 1.0f)}) {
        try {
            renderer.setLight(DirectionalLight::sun(d, vec3(0.3f), vec3(0.7f)));
            FAIL() << "no exception";
        } catch (const std::invalid_argument& e) {
            EXPECT_EQ(std::string(e.what()).rfind("Renderer::setLight(): ", 0), 0u) << e.what();
        }
    }
    EXPECT_TRUE(renderer.light().headlight);
    EXPECT_NO_THROW(renderer.setLight(DirectionalLight{}));  // the headlight has no direction of its own
}

// DrawList::parts (the screen-rectangle rejection's output): an item drawn in part draws exactly the triangles of its
// ranges, with its own matrix, in both index widths, beside whole items of the same mesh.
TEST_F(RendererTest, PartsDrawTheirRangesLikeAMeshOfJustThoseTriangles) {
    for (int div : {4, 110}) {  // 16-bit and 32-bit indices
        auto mesh = makeBoxMesh(dvec3(-0.5), dvec3(0.5), div);
        const uint32_t tris = mesh->triangleCount();
        // The ranges: the first third and the last sixth of the triangles.
        const uint32_t a = tris / 3, b = tris - tris / 6;
        std::vector<uint32_t> sub;
        for (uint32_t i = 0; i < a * 3; ++i) sub.push_back(mesh->index(i));
        for (uint32_t i = b * 3; i < tris * 3; ++i) sub.push_back(mesh->index(i));
        auto subMesh = make<Mesh>();
        subMesh->set(mesh->positions(), mesh->normals(), sub, mesh->uvs());
        auto mat = make<Material>(vec4(0.3f, 0.8f, 0.4f, 1.0f));
        const Camera cam = lookingAt(dvec3(1.2, 1.5, 4.0), dvec3(0.0));
        auto item = [&](const Mesh* m, const dvec3& at) {
            DrawItem it;
            it.mesh = m;
            it.material = mat.get();
            it.model = glm::mat4x3(glm::translate(dmat4(1.0), at - cam.eye()));
            return it;
        };
        // Reference: a whole box at the left, the sub-mesh at the right, a whole box above.
        DrawList ref;
        ref.items = {item(mesh.get(), dvec3(-0.8, 0, 0)), item(subMesh.get(), dvec3(0.8, 0, 0)),
                     item(mesh.get(), dvec3(0, 1.1, 0))};
        renderer.draw(ref, cam, kClear);
        const Image want = renderer.readColor();
        // The same with the middle item the whole mesh drawn in part: it must not take the first item's matrix,
        // nor batch with the others.
        DrawList got;
        got.items = {item(mesh.get(), dvec3(-0.8, 0, 0)), item(mesh.get(), dvec3(0.8, 0, 0)),
                     item(mesh.get(), dvec3(0, 1.1, 0))};
        got.ranges = {{0, a * 3}, {b * 3, (tris - b) * 3}};
        got.parts = {{1, 0, 2}};
        renderer.draw(got, cam, kClear);
        const Image image = renderer.readColor();
        EXPECT_EQ(countDifferingPixels(want, image, 0), 0u) << "div " << div;
        EXPECT_EQ(renderer.lastStats().triangles, uint64_t(2 * tris + a + (tris - b)));
        EXPECT_EQ(renderer.lastStats().drawCalls, 3u);
        // Not vacuous: the whole box in the middle would differ.
        got.parts.clear();
        renderer.draw(got, cam, kClear);
        EXPECT_GT(countDifferingPixels(want, renderer.readColor(), 0), 100u) << "div " << div;
        // Ranges that cover every triangle, split in three: the whole box's pixels, batched or not.
        got.ranges = {{0, 3 * 5}, {3 * 5, 3 * 7}, {3 * 12, (tris - 12) * 3}};
        got.parts = {{1, 0, 3}};
        renderer.draw(got, cam, kClear);
        const Image split = renderer.readColor();
        got.parts.clear();
        renderer.draw(got, cam, kClear);
        EXPECT_EQ(countDifferingPixels(split, renderer.readColor(), 0), 0u) << "div " << div;
    }
}

TEST_F(RendererTest, PartsPastTheItemsOrTheIndicesThrow) {
    auto mesh = makeBoxMesh(dvec3(-0.5), dvec3(0.5));
    const Camera cam = lookingAt(dvec3(0, 0, 5), dvec3(0.0));
    DrawItem it;
    it.mesh = mesh.get();
    DrawList list;
    list.items.push_back(it);
    list.ranges = {{0, 36}};
    list.parts = {{1, 0, 1}};  // no item 1
    EXPECT_THROW(renderer.draw(list, cam), std::out_of_range);
    list.parts = {{0, 0, 2}};  // past the ranges
    EXPECT_THROW(renderer.draw(list, cam), std::out_of_range);
    list.ranges = {{3, 36}};  // past the mesh's 36 indices
    list.parts = {{0, 0, 1}};
    EXPECT_THROW(renderer.draw(list, cam), std::out_of_range);
    list.ranges = {{0, 36}};
    EXPECT_NO_THROW(renderer.draw(list, cam));
}

// Two views side by side in one framebuffer, in both depth modes: each half holds exactly the pixels and depths of
// its view drawn alone into a framebuffer of the half's size, whatever the framebuffer held before.
TEST_F(RendererTest, ViewsSideBySideLookAsIfDrawnAlone) {
    constexpr int kHalf = kW / 2;
    auto root = make<Group>();
    // Boxes across the middle of both views, so that each view's picture reaches the edge it shares with the other.
    root->addChild(placed(makeBoxMesh(dvec3(-2.0, -0.4, -0.4), dvec3(2.0, 0.4, 0.4)),
                          make<Material>(vec4(0.8f, 0.3f, 0.2f, 1.0f)), dvec3(0.0)));
    root->addChild(placed(makeBoxMesh(dvec3(-0.5), dvec3(0.5), 2), make<Material>(vec4(0.2f, 0.6f, 0.9f, 1.0f)),
                          dvec3(0.3, 0.9, -1.0)));
    auto view = [&](const dvec3& eye) {
        Camera cam;
        cam.setLookAt(eye, dvec3(0.0), dvec3(0.0, 1.0, 0.0));
        cam.setPerspective(45.0, double(kHalf) / kH, 0.1, 100.0);
        cam.setViewport(kHalf, kH);
        return cam;
    };
    const Camera left = view(dvec3(-1.5, 1.0, 4.0)), right = view(dvec3(2.5, -0.8, 3.0));
    const DrawList leftList = cull(root, left), rightList = cull(root, right);
    const vec4 rightClear(204.0f / 255.0f, 153.0f / 255.0f, 51.0f / 255.0f, 1.0f);
    const std::array<int, 4> rightClear8{204, 153, 51, 255};
    for (Renderer::DepthMode mode : {Renderer::DepthMode::Classic, Renderer::DepthMode::ReverseZ}) {
        SCOPED_TRACE(mode == Renderer::DepthMode::Classic ? "classic" : "reverse-z");
        renderer.setDepthMode(mode);
        context.resize(kHalf, kH);
        renderer.draw(leftList, left, kClear);
        const Image leftAlone = renderer.readColor();
        const std::vector<float> leftDepth = renderer.readDepth();
        renderer.draw(rightList, right, rightClear);
        const Image rightAlone = renderer.readColor();
        const std::vector<float> rightDepth = renderer.readDepth();

        context.resize(kW, kH);
        renderer.draw(DrawList{}, lookingAt(dvec3(0, 0, 5), dvec3(0.0)), vec4(1.0f));  // white everywhere first
        renderer.draw(leftList, left, Renderer::Viewport{0, 0, kHalf, kH}, kClear);
        EXPECT_EQ(renderer.readDepth(), leftDepth);  // the current viewport: the left half, at the same place
        renderer.draw(rightList, right, Renderer::Viewport{kHalf, 0, kHalf, kH}, rightClear);
        // Depth within a step of the 24-bit buffer: the rasterizer evaluates depth at window coordinates, which
        // round in their last bit differently kHalf pixels over (the colours do not change).
        const std::vector<float> depth = renderer.readDepth();
        ASSERT_EQ(depth.size(), rightDepth.size());
        for (size_t i = 0; i < depth.size(); ++i) ASSERT_NEAR(depth[i], rightDepth[i], 0x1p-24) << "at " << i;
        const Image both = renderer.readColor(Renderer::Viewport{0, 0, kW, kH});
        ASSERT_EQ(both.width, kW);
        size_t leftDiffering = 0, rightDiffering = 0, leftCovered = 0, rightCovered = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kHalf; ++x) {
                leftDiffering += pixel(both, x, y) != pixel(leftAlone, x, y);
                rightDiffering += pixel(both, kHalf + x, y) != pixel(rightAlone, x, y);
                leftCovered += pixel(leftAlone, x, y) != kClear8;
                rightCovered += pixel(rightAlone, x, y) != rightClear8;
            }
        EXPECT_EQ(leftDiffering, 0u);
        EXPECT_EQ(rightDiffering, 0u);
        // Not vacuous: both views show boxes, against their own clear colours, and along their shared edge.
        EXPECT_GT(leftCovered, 1000u);
        EXPECT_GT(rightCovered, 1000u);
        EXPECT_NE(pixel(leftAlone, kHalf - 1, kH / 2), kClear8);
        EXPECT_NE(pixel(rightAlone, 0, kH / 2), rightClear8);
        EXPECT_EQ(pixel(both, kHalf - 1, 0), kClear8);
        EXPECT_EQ(pixel(both, kHalf, 0), rightClear8);
        if (std::getenv("SGKIT_TEST_IMAGES")) savePng("renderer_two_views.png", both);
    }
}

TEST_F(RendererTest, AViewportWithoutAreaOrPastTheFramebufferThrowsBeforeDrawing) {
    const Camera cam = lookingAt(dvec3(0, 0, 5), dvec3(0.0));
    renderer.draw(DrawList{}, cam, kClear);
    for (const Renderer::Viewport& v :
         {Renderer::Viewport{0, 0, 0, kH}, Renderer::Viewport{0, 0, kW, -1}, Renderer::Viewport{-1, 0, 10, 10},
          Renderer::Viewport{0, -1, 10, 10}, Renderer::Viewport{kW / 2, 0, kW / 2 + 1, kH},
          Renderer::Viewport{0, 1, kW, kH}}) {
        try {
            renderer.draw(DrawList{}, cam, v, vec4(1.0f));
            FAIL() << "no exception for " << v.x << ", " << v.y << ", " << v.width << "x" << v.height;
        } catch (const std::invalid_argument& e) {
            EXPECT_EQ(std::string(e.what()).rfind("Renderer::draw(): viewport ", 0), 0u) << e.what();
        }
    }
    try {
        renderer.draw(DrawList{}, cam, Renderer::Viewport{kW / 2, 0, kW / 2 + 1, kH});
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "Renderer::draw(): viewport (80, 0, 81x120) reaches past the 160x120 framebuffer");
    }
    // Nothing was drawn (the white clear would show), and the framebuffer's whole and its last pixel are fine.
    const Image img = renderer.readColor(Renderer::Viewport{0, 0, kW, kH});
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) ASSERT_EQ(pixel(img, x, y), kClear8) << "at " << x << "," << y;
    EXPECT_NO_THROW(renderer.draw(DrawList{}, cam, Renderer::Viewport{0, 0, kW, kH}));
    EXPECT_NO_THROW(renderer.draw(DrawList{}, cam, Renderer::Viewport{kW - 1, kH - 1, 1, 1}));
    try {
        renderer.readColor(Renderer::Viewport{0, 0, 0, 1});
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()).rfind("Renderer::readColor(): ", 0), 0u) << e.what();
    }
}
