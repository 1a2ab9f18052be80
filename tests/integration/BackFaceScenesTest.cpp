// The built-in scenes' accuracy views drawn with the renderer's back-face culling (Renderer::setBackFaceCulling)
// and without it: the same pixels but for ties at silhouette edges (tests/BackFaceCompare.h), with the culling counted
// where the scene has solids in front of the eye (city: closed boxes seen from the street and above; office: rooms the
// eye stands in, walls it passes close to).
#include "BackFaceCompare.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "testbed/Accuracy.h"
#include "testbed/City.h"
#include "testbed/Office.h"

#include <gtest/gtest.h>

using namespace sg;

namespace {

constexpr int kW = 200, kH = 150;

// Items drawn without their back faces over all views.
uint64_t compare(const Scene& scene, const std::vector<Camera>& views, const char* name) {
    OsmesaContext context(kW, kH);
    Renderer renderer;
    CullTraversal cull;
    DrawList list;
    uint64_t skipped = 0;
    for (size_t v = 0; v < views.size(); ++v) {
        CullStats stats;
        cull.cull(scene, views[v], CullSettings{}, list, stats);
        renderer.setBackFaceCulling(false);
        renderer.draw(list, views[v]);
        const Image all = renderer.readColor();
        const std::vector<float> allDepth = renderer.readDepth();
        renderer.setBackFaceCulling(true);
        renderer.draw(list, views[v]);
        skipped += renderer.lastStats().backFacesSkipped;
        const testutil::BackFaceDiff d =
            testutil::compareBackFaces(all, allDepth, renderer.readColor(), renderer.readDepth());
        EXPECT_EQ(d.wrong, 0u) << name << " view " << v << ": " << accuracy::describeCamera(views[v]);
        EXPECT_LE(d.ties, size_t(kW * kH) / 200) << name << " view " << v;
    }
    return skipped;
}

}  // namespace

TEST(BackFaceScenes, CityViewsDrawTheSamePixels) {
    const int n = 12;
    Scene s(scenes::buildCity({n, false}));
    s.update();
    EXPECT_GT(compare(s, accuracy::cityViews(n, 30, 2024, kW, kH), "city"), 100u);
}

TEST(BackFaceScenes, OfficeViewsDrawTheSamePixels) {
    const int r = 4;
    Scene s(scenes::buildOffice(r));
    s.update();
    compare(s, accuracy::officeViews(r, 30, 7, kW, kH), "office");
}
