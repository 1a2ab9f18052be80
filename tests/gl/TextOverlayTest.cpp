// TextOverlay, headless with OSMesa: the text changes pixels inside its panel only, writes the ink colour there,
// scales with `scale`, and leaves the GL state the renderer expects (a second frame draws the same picture).
#include "sg/cull/DrawList.h"
#include "sg/gl/OsmesaContext.h"
#include "sg/gl/Renderer.h"
#include "sg/gl/TextOverlay.h"

#include <gtest/gtest.h>

#include <cstring>

using namespace sg;

namespace {

constexpr int kW = 320, kH = 200;

Camera screen() {
    Camera cam;
    cam.setViewport(kW, kH);
    cam.setPerspective(60.0, double(kW) / kH, 0.1, 100.0);
    cam.setLookAt(dvec3(0, 0, 5), dvec3(0), dvec3(0, 1, 0));
    return cam;
}

struct Drawn {
    size_t inside = 0, outside = 0, ink = 0;
};

// The pixels `text` changed on a cleared frame, inside and outside the panel panelSize() gives.
Drawn drawOver(Renderer& r, TextOverlay& overlay, const std::string& text, float scale, Image* out = nullptr) {
    const DrawList empty;
    r.draw(empty, screen());
    const Image plain = r.readColor();
    overlay.draw(text, kW, kH, scale);
    const Image over = r.readColor();
    if (out) *out = over;
    int pw = 0, ph = 0;
    TextOverlay::panelSize(text, scale, pw, ph);
    Drawn d;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const size_t i = (size_t(y) * kW + size_t(x)) * 4;
            const bool differs = std::memcmp(&plain.rgba[i], &over.rgba[i], 3) != 0;
            (x < pw && y < ph ? d.inside : d.outside) += differs;
            d.ink += over.rgba[i] == 255 && over.rgba[i + 1] > 230 && over.rgba[i + 2] > 140 && over.rgba[i + 2] < 170;
        }
    return d;
}

TEST(TextOverlay, DrawsInkOnItsPanelAndNothingElse) {
    OsmesaContext ctx(kW, kH);
    Renderer r;
    TextOverlay overlay;
    int pw = 0, ph = 0;
    TextOverlay::panelSize("fps 60\nW/A/S/D", 1.0f, pw, ph);
    EXPECT_GT(pw, 40);
    EXPECT_GT(ph, 20);
    const Drawn d = drawOver(r, overlay, "fps 60\nW/A/S/D", 1.0f);
    EXPECT_EQ(d.outside, 0u);
    EXPECT_GT(d.inside, size_t(pw * ph / 2));  // the translucent panel darkens all it covers
    EXPECT_GT(d.ink, size_t(50));              // the letters, in the ink colour
    // Twice the scale: a panel twice as wide and high, four times the ink.
    int pw2 = 0, ph2 = 0;
    TextOverlay::panelSize("fps 60\nW/A/S/D", 2.0f, pw2, ph2);
    EXPECT_NEAR(pw2, 2 * pw, 2);
    EXPECT_NEAR(ph2, 2 * ph, 2);
    const Drawn d2 = drawOver(r, overlay, "fps 60\nW/A/S/D", 2.0f);
    EXPECT_EQ(d2.outside, 0u);
    EXPECT_NEAR(double(d2.ink), 4.0 * double(d.ink), 0.1 * 4.0 * double(d.ink));
}

TEST(TextOverlay, OtherTextOtherPixelsSameTextSamePixels) {
    OsmesaContext ctx(kW, kH);
    Renderer r;
    TextOverlay overlay;
    Image a, b, c;
    drawOver(r, overlay, "mode static", 1.0f, &a);
    drawOver(r, overlay, "mode budget", 1.0f, &b);
    drawOver(r, overlay, "mode static", 1.0f, &c);  // after a frame of the renderer and the overlay's state
    EXPECT_NE(a.rgba, b.rgba);
    EXPECT_EQ(a.rgba, c.rgba);
}

}  // namespace
