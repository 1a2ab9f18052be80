// Shader variants compiled ahead of the frames that draw them: a scene's before its first frame's draw
// (sg::Viewer, Renderer::prepareVariants), so that no later frame compiles one; and the overlay's first frame and
// the GPU time a software rasterizer cannot give. Headless (OSMesa).
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/Switch.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/viewer/Viewer.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace {

using namespace sg;

constexpr int kW = 96, kH = 64;

Camera lookingAlongY() {
    Camera c;
    c.setViewport(kW, kH);
    c.setPerspective(50.0, double(kW) / kH, 0.1, 100.0);
    c.setLookAt(dvec3(0, -4, 0), dvec3(0.0), dvec3(0, 0, 1));
    return c;
}

// A square facing the camera, with normals and UVs, and vertex colours when asked.
ref_ptr<Mesh> square(bool colours) {
    auto m = make<Mesh>();
    std::vector<vec4> c;
    if (colours) c.assign(4, vec4(1.0f, 0.5f, 0.5f, 1.0f));
    m->set({{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}}, std::vector<vec3>(4, vec3(0, -1, 0)), {0, 1, 2, 0, 2, 3},
           {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, c);
    return m;
}

// Combination k of 32: bit 0 textured, bit 1 vertex colours, bit 2 unlit, bit 3 an alpha cutoff, bit 4 physical
// with a metallic-roughness map.
ref_ptr<Geometry> combination(int k, const ref_ptr<Texture>& tex) {
    auto mat = make<Material>(vec4(0.8f, 0.6f, 0.4f, 1.0f));
    if (k & 1) mat->texture = tex;
    mat->unlit = (k & 4) != 0;
    if (k & 8) mat->alphaCutoff = 0.5f;
    if (k & 16) {
        mat->physical = true;
        mat->pbr.metallic = 0.0f;
        mat->pbr.metallicRoughness.texture = tex;
    }
    return make<Geometry>(square((k & 2) != 0), mat);
}

// The 32 combinations, then points and lines: one shown at a time.
ref_ptr<Switch> combinations() {
    auto tex = make<Texture>(2, 2, std::vector<uint8_t>(16, 200));
    auto sw = make<Switch>();
    for (int k = 0; k < 32; ++k) sw->addChild(combination(k, tex), k == 0);
    auto points = make<Mesh>();
    points->setPoints({{0.0f, 0.0f, 0.0f}, {0.5f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.5f}});
    sw->addChild(make<Geometry>(points, make<Material>()), false);
    auto lines = make<Mesh>();
    lines->setLines({{-1.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}}, {0, 1});
    sw->addChild(make<Geometry>(lines, make<Material>()), false);
    return sw;
}

TEST(ViewerVariants, AfterTheFirstFrameNoFrameCompilesAProgram) {
    OsmesaContext context(kW, kH);
    ref_ptr<Switch> sw = combinations();
    auto root = make<Group>();
    root->addChild(sw);
    Scene scene(root);
    Viewer viewer(scene);
    View& v = viewer.addView(lookingAlongY());
    viewer.frame();
    // Compiled before the first frame's draw: not in it.
    EXPECT_EQ(viewer.renderer().compiledInDraw(), 0u);
    EXPECT_EQ(v.renderStats().programsCompiled, 0u);
    const size_t variants = viewer.renderer().variantCount();
    EXPECT_GE(variants, 10u);  // many combinations take a variant of their own
    for (size_t k = 1; k < sw->numChildren(); ++k) {
        sw->setOnly(k);
        viewer.frame();
        EXPECT_EQ(v.renderStats().instances, 1u) << "combination " << k << " is drawn";
        EXPECT_EQ(v.renderStats().programsCompiled, 0u) << "combination " << k;
    }
    EXPECT_EQ(viewer.renderer().compiledInDraw(), 0u);
    EXPECT_EQ(viewer.renderer().variantCount(), variants);
}

// Without the viewer's preparation, the same frames compile in the draw: what the test above would catch.
TEST(ViewerVariants, ARendererLeftAloneCompilesAtFirstUse) {
    OsmesaContext context(kW, kH);
    Renderer renderer;
    auto item = [](const Geometry& g) {
        DrawItem it;
        it.mesh = g.mesh();
        it.material = g.material();
        it.model = glm::mat4x3(1.0f);
        it.model[3] = vec3(0.0f, 4.0f, 0.0f);  // the square, 4 in front of an eye looking along y
        return it;
    };
    ref_ptr<Switch> sw = combinations();
    Camera cam;
    cam.setViewport(kW, kH);
    cam.setPerspective(50.0, double(kW) / kH, 0.1, 100.0);
    cam.setLookAt(dvec3(0.0), dvec3(0, 1, 0), dvec3(0, 0, 1));
    DrawList list;
    list.items.push_back(item(static_cast<const Geometry&>(*sw->child(0))));
    renderer.draw(list, cam);
    EXPECT_EQ(renderer.lastStats().programsCompiled, 1u);
    EXPECT_EQ(renderer.compiledInDraw(), 1u);
    renderer.draw(list, cam);
    EXPECT_EQ(renderer.lastStats().programsCompiled, 0u);
    // Prepared: the rest compile there, none in the draws.
    const size_t compiled = renderer.prepareVariants(*sw, cam);
    EXPECT_EQ(renderer.variantCount(), compiled + 1);
    for (size_t k = 1; k < sw->numChildren(); ++k) {
        list.items[0] = item(static_cast<const Geometry&>(*sw->child(k)));
        renderer.draw(list, cam);
        EXPECT_EQ(renderer.lastStats().programsCompiled, 0u) << "combination " << k;
    }
    EXPECT_EQ(renderer.compiledInDraw(), 1u);
}

// The first frame's overlay: the history holds no frame yet, so its figures are "-", not 0; the line of the frame it
// is drawn over has this frame's own cull and draw figures.
TEST(ViewerVariants, TheOverlaysFirstFrameShowsFiguresNotZeros) {
    OsmesaContext context(kW, kH);
    auto root = make<Group>();
    root->addChild(combination(0, {}));
    Scene scene(root);
    Viewer viewer(scene);
    viewer.addView(lookingAlongY());
    viewer.overlay = true;
    viewer.frame();
    const std::string text = viewer.overlayDrawn();
    const size_t line = text.find("this frame: cull ");
    ASSERT_NE(line, std::string::npos) << text;
    const std::string history = text.substr(0, line);
    EXPECT_NE(history.find("fps -   frame - ms   work - ms   gpu -\n"), std::string::npos) << text;
    EXPECT_EQ(history.find("0.00"), std::string::npos) << text;
    EXPECT_EQ(text.find("nodes 0 ", line), std::string::npos) << text;
    EXPECT_NE(text.find("  drawn 1  draw calls 1  triangles 2  compiled 0", line), std::string::npos) << text;
    viewer.frame();
    EXPECT_EQ(viewer.overlayDrawn().find("fps -"), std::string::npos) << viewer.overlayDrawn();
}

// llvmpipe's timer reports a fraction of the draw: not shown as the GPU's time.
TEST(ViewerVariants, TheGpuTimeIsUnknownOnASoftwareRasterizer) {
    OsmesaContext context(kW, kH);
    auto root = make<Group>();
    root->addChild(combination(0, {}));
    Scene scene(root);
    Viewer viewer(scene);
    View& v = viewer.addView(lookingAlongY());
    if (!viewer.renderer().softwareRasterizer()) GTEST_SKIP() << "a hardware rasterizer: its GPU time is known";
    viewer.frame();
    viewer.frame();
    EXPECT_EQ(v.gpuMs(), -1.0);
    EXPECT_FALSE(viewer.lastFrame().gpuTimed);
    EXPECT_EQ(viewer.lastFrame().gpuMs, 0.0);
    EXPECT_FALSE(viewer.history().mean().gpuTimed);
    EXPECT_NE(viewer.statsText().find("gpu unknown (software)\n"), std::string::npos) << viewer.statsText();
}

}  // namespace
