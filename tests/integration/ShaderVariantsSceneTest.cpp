// The built-in scenes' accuracy views drawn by the renderer's shader variants and by its one program: the same
// pixels, at most 1/255 a channel (city: plain materials under the headlight; office: rooms; terrain: vertex
// colours and fading LOD tiles).
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "testbed/Accuracy.h"
#include "testbed/City.h"
#include "testbed/Office.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {

constexpr int kW = 200, kH = 150;

void compare(const Scene& scene, const std::vector<Camera>& views, const char* name) {
    OsmesaContext context(kW, kH);
    Renderer renderer;
    CullTraversal cull;
    DrawList list;
    int nonEmpty = 0;
    for (size_t v = 0; v < views.size(); ++v) {
        CullStats stats;
        cull.cull(scene, views[v], CullSettings{}, list, stats);
        renderer.setShaderMode(Renderer::ShaderMode::OneProgram);
        renderer.draw(list, views[v]);
        const Image one = renderer.readColor();
        renderer.setShaderMode(Renderer::ShaderMode::Variants);
        renderer.draw(list, views[v]);
        EXPECT_EQ(countDifferingPixels(one, renderer.readColor(), 1), 0u)
            << name << " view " << v << ": " << accuracy::describeCamera(views[v]);
        nonEmpty += !list.items.empty();
    }
    EXPECT_GT(nonEmpty, int(views.size()) / 2) << name;  // most views show something
}

}  // namespace

TEST(ShaderVariantsScenes, CityViewsAreThePixelsOfTheOneProgram) {
    const int n = 12;
    Scene s(scenes::buildCity({n, false}));
    s.update();
    compare(s, accuracy::cityViews(n, 30, 2024, kW, kH), "city");
}

TEST(ShaderVariantsScenes, OfficeViewsAreThePixelsOfTheOneProgram) {
    const int r = 4;
    Scene s(scenes::buildOffice(r));
    s.update();
    compare(s, accuracy::officeViews(r, 30, 7, kW, kH), "office");
}
