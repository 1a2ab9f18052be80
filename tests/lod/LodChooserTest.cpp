// LodChooser: every LOD rule the cull, its fast path, the budget's replay and planner and the intersection
// traversal take from it, one test each: ranges by distance and pixel size, the LOD scale, the finest child,
// hysteresis, fade bands, the budget's plan, paged details, the ranges at another scale, frames that scale.
#include "nodes/Geometry.h"
#include "nodes/Group.h"
#include "nodes/LOD.h"
#include "nodes/PagedLOD.h"
#include "sg/lod/internal/LodChooser.h"
#include "sg/scene/Scene.h"

#include <gtest/gtest.h>

#include <vector>

namespace {

using namespace sg;

ref_ptr<Geometry> box() { return make<Geometry>(makeBoxMesh(dvec3(-1.0), dvec3(1.0)), make<Material>()); }

// An LOD at the origin with children shown over [0, 10), [10, 50) and [50, 200).
struct ThreeLevels {
    ref_ptr<Group> root = make<Group>();
    ref_ptr<LOD> lod = make<LOD>();
    Scene scene{root};
    uint32_t entry = 0;
    explicit ThreeLevels(float transition = 0.0f, LOD::Mode mode = LOD::Mode::Distance) {
        lod->setMode(mode);
        if (mode == LOD::Mode::Distance) {
            lod->addChild(box(), 0.0f, 10.0f);
            lod->addChild(box(), 10.0f, 50.0f);
            lod->addChild(box(), 50.0f, 200.0f);
        } else {  // pixel size: the largest first
            lod->addChild(box(), 100.0f, 1e9f);
            lod->addChild(box(), 10.0f, 100.0f);
            lod->addChild(box(), 0.0f, 10.0f);
        }
        lod->setTransition(transition);
        root->addChild(lod);
        scene.update();
        for (uint32_t i = 0; i < scene.image().size(); ++i)
            if (scene.image().kind[i] == NodeKind::LOD) entry = i;
    }
    // The image seen from an eye at `eye` (world coordinates).
    ImageFrame from(const dvec3& eye) const {
        const FlatImage& img = scene.image();
        return ImageFrame::make(img, glm::translate(dmat4(1.0), img.origin - eye));
    }
};

struct Pick {
    uint32_t child;
    float fade;
    bool setsFade;
};

std::vector<Pick> shown(const LodChooser& ch, const ImageFrame& f, uint32_t i, const LodChooser::Known& k = {},
                        uint8_t* first = nullptr) {
    std::vector<Pick> out;
    const uint8_t r = ch.choose(f, i, k, [&](const LodChooser::Shown& s) {
        EXPECT_EQ(s.entry, [&] {  // the entry is the child's: the image's children in order
            uint32_t j = i + 1;
            for (uint32_t c = 0; c < s.child; ++c) j = f.img->end[j];
            return j;
        }());
        out.push_back({s.child, s.fade, s.setsFade});
    });
    if (first) *first = r;
    return out;
}

std::vector<uint32_t> children(const std::vector<Pick>& p) {
    std::vector<uint32_t> c;
    for (const Pick& x : p) c.push_back(x.child);
    return c;
}

Camera camera() {
    Camera cam;
    cam.setViewport(400, 300);
    cam.setPerspective(60.0, 4.0 / 3.0, 0.1, 1000.0);
    cam.setLookAt(dvec3(0, -5, 0), dvec3(0.0), dvec3(0, 0, 1));
    return cam;
}

TEST(LodChooser, DistanceRangesShowTheChildWhoseRangeHoldsTheDistance) {
    ThreeLevels t;
    const LodChooser ch({nullptr});
    EXPECT_EQ(children(shown(ch, t.from(dvec3(0, -5, 0)), t.entry)), std::vector<uint32_t>{0});
    EXPECT_EQ(children(shown(ch, t.from(dvec3(0, -10, 0)), t.entry)), std::vector<uint32_t>{1});  // min inclusive
    EXPECT_EQ(children(shown(ch, t.from(dvec3(30, 0, 40)), t.entry)), std::vector<uint32_t>{2});  // 50
    uint8_t first = 0;
    EXPECT_TRUE(shown(ch, t.from(dvec3(0, -300, 0)), t.entry, {}, &first).empty());  // beyond every range
    EXPECT_EQ(first, LodChooser::kNone);
    EXPECT_DOUBLE_EQ(ch.value(t.from(dvec3(3, -4, 0)), t.entry), 5.0);
}

TEST(LodChooser, TheLodScaleMakesEverythingLookFarther) {
    ThreeLevels t;
    const LodChooser ch({nullptr, 4.0});  // 5 m looks like 20 m
    EXPECT_EQ(children(shown(ch, t.from(dvec3(0, -5, 0)), t.entry)), std::vector<uint32_t>{1});
    EXPECT_DOUBLE_EQ(ch.value(t.from(dvec3(0, -5, 0)), t.entry), 20.0);
}

TEST(LodChooser, PixelSizeRangesMeasureTheBoundOnScreen) {
    ThreeLevels t(0.0f, LOD::Mode::PixelSize);
    const Camera cam = camera();
    const LodChooser ch({&cam});
    const ImageFrame near = t.from(dvec3(0, -5, 0)), far = t.from(dvec3(0, -500, 0));
    const double r = t.scene.image().r[t.entry];
    EXPECT_NEAR(ch.value(near, t.entry), cam.pixelSize(2.0 * r, 5.0), 1e-6 * cam.pixelSize(2.0 * r, 5.0));
    ASSERT_GT(ch.value(near, t.entry), 100.0);
    EXPECT_EQ(children(shown(ch, near, t.entry)), std::vector<uint32_t>{0});
    ASSERT_LT(ch.value(far, t.entry), 10.0);
    EXPECT_EQ(children(shown(ch, far, t.entry)), std::vector<uint32_t>{2});
    // A pixel-size LOD and no view to measure pixels in: the finest child.
    EXPECT_EQ(children(shown(LodChooser({nullptr}), far, t.entry)), std::vector<uint32_t>{0});
}

TEST(LodChooser, TheFinestRuleShowsTheMostDetailedChildAtAnyDistance) {
    ThreeLevels t;
    LodChooser::Rules r;
    r.finest = true;
    EXPECT_EQ(children(shown(LodChooser(r), t.from(dvec3(0, -150, 0)), t.entry)), std::vector<uint32_t>{0});
    ThreeLevels p(0.0f, LOD::Mode::PixelSize);
    EXPECT_EQ(LodChooser::finestChild(p.scene.image(), p.entry), 0);
    EXPECT_EQ(LodChooser::finestChild(t.scene.image(), t.entry), 0);
}

TEST(LodChooser, HysteresisKeepsTheLastChildWithinItsWidenedRange) {
    ThreeLevels t;
    LodChooser::Rules r;
    r.camera = nullptr;
    r.hysteresis = 0.1;  // child 1's [10, 50) widens to [9, 55)
    const LodChooser ch(r);
    LodChooser::Known last1;
    last1.last = 1;
    uint8_t first = 0;
    EXPECT_EQ(children(shown(ch, t.from(dvec3(0, -9.5, 0)), t.entry, last1, &first)), std::vector<uint32_t>{1});
    EXPECT_EQ(first, 1);
    EXPECT_EQ(children(shown(ch, t.from(dvec3(0, -54, 0)), t.entry, last1)), std::vector<uint32_t>{1});
    // Past the widened range the plain ranges decide again.
    EXPECT_EQ(children(shown(ch, t.from(dvec3(0, -8.9, 0)), t.entry, last1, &first)), std::vector<uint32_t>{0});
    EXPECT_EQ(first, 0);
    // Nothing shown last frame: the plain ranges.
    EXPECT_EQ(children(shown(ch, t.from(dvec3(0, -9.5, 0)), t.entry)), std::vector<uint32_t>{0});
    // Without hysteresis the last child is not kept.
    EXPECT_EQ(children(shown(LodChooser({nullptr}), t.from(dvec3(0, -9.5, 0)), t.entry, last1)),
              std::vector<uint32_t>{0});
}

TEST(LodChooser, AFadeBandDissolvesTwoChildrenWithComplementaryShares) {
    ThreeLevels t(4.0f);  // bands [8, 12) and [48, 52)
    LodChooser::Rules r;
    r.fade = true;
    const LodChooser ch(r);
    // Inside the band at 10.5: child 0 fading out, child 1 fading in, shares adding up to exactly 1.
    const std::vector<Pick> band = shown(ch, t.from(dvec3(0, -10.5, 0)), t.entry);
    ASSERT_EQ(band.size(), 2u);
    EXPECT_EQ(band[0].child, 0u);
    EXPECT_EQ(band[1].child, 1u);
    EXPECT_TRUE(band[0].setsFade && band[1].setsFade);
    EXPECT_GT(band[0].fade, 0.0f);  // keeps pattern < its share
    EXPECT_LT(band[1].fade, 0.0f);  // keeps pattern >= 1 - its share
    EXPECT_EQ(band[0].fade + (-band[1].fade), 1.0f);
    EXPECT_FLOAT_EQ(band[0].fade, 1.5f / 4.0f);  // 12 - 10.5 of the band's 4
    // Outside any band: one child, no dissolve.
    const std::vector<Pick> mid = shown(ch, t.from(dvec3(0, -30, 0)), t.entry);
    ASSERT_EQ(mid.size(), 1u);
    EXPECT_EQ(mid[0].fade, 1.0f);
    // The fade off: the band is ignored and the child pops at 10.
    EXPECT_EQ(children(shown(LodChooser({nullptr}), t.from(dvec3(0, -10.5, 0)), t.entry)), std::vector<uint32_t>{1});
}

TEST(LodChooser, TheBudgetsPlanOverridesTheRanges) {
    ThreeLevels t;
    LodChooser::Rules r;
    r.fade = true;
    r.hysteresis = 0.2;
    const LodChooser ch(r);
    LodChooser::Known plan;
    plan.planned = 2;  // the coarsest, though the eye is at 5 m
    plan.last = 0;
    uint8_t first = 0;
    EXPECT_EQ(children(shown(ch, t.from(dvec3(0, -5, 0)), t.entry, plan, &first)), std::vector<uint32_t>{2});
    EXPECT_EQ(first, 2);
    plan.planned = -1;  // left out
    EXPECT_TRUE(shown(ch, t.from(dvec3(0, -5, 0)), t.entry, plan, &first).empty());
    EXPECT_EQ(first, LodChooser::kNone);
}

TEST(LodChooser, APagedDetailIsWantedInItsRangeOrByCommand) {
    auto root = make<Group>();
    auto paged = make<PagedLOD>();
    paged->addChild(box());
    paged->setFile("detail.glb");
    paged->setRange(0.0f, 20.0f);
    root->addChild(paged);
    Scene scene(root);
    scene.update();
    const FlatImage& img = scene.image();
    uint32_t entry = 0;
    for (uint32_t i = 0; i < img.size(); ++i)
        if (img.kind[i] == NodeKind::PagedLOD) entry = i;
    auto from = [&](double y) {
        return ImageFrame::make(img, glm::translate(dmat4(1.0), img.origin - dvec3(0, y, 0)));
    };
    const LodChooser ch({nullptr});
    EXPECT_TRUE(ch.detailWanted(from(-10.0), entry));
    EXPECT_FALSE(ch.detailWanted(from(-30.0), entry));
    EXPECT_FALSE(LodChooser({nullptr, 2.0}).detailWanted(from(-15.0), entry));  // looks like 30 m
    LodChooser::Rules r;
    r.finest = true;
    EXPECT_TRUE(LodChooser(r).detailWanted(from(-30.0), entry));
    paged->setTrigger(PagedLOD::Trigger::Command);
    EXPECT_TRUE(ch.detailWanted(from(-30.0), entry));  // whenever attached
}

TEST(LodChooser, TheRangesAtAnotherScaleWithAndWithoutTheBand) {
    ThreeLevels t(4.0f);
    const Camera cam = camera();
    const LodChooser ch({&cam});
    int first = 0, last = 0;
    ch.shownAt(t.from(dvec3(0, -5, 0)), t.entry, 2.0, false, first, last);  // 10: child 1
    EXPECT_EQ(first, 1);
    EXPECT_EQ(last, 1);
    ch.shownAt(t.from(dvec3(0, -5, 0)), t.entry, 2.0, true, first, last);  // with the band, child 0 too
    EXPECT_EQ(first, 0);
    EXPECT_EQ(last, 1);
    ch.shownAt(t.from(dvec3(0, -5, 0)), t.entry, 100.0, false, first, last);  // 500: none
    EXPECT_EQ(first, -1);
    EXPECT_EQ(last, -1);
}

TEST(LodChooser, AScaledFrameMeasuresDistancesInTheWorld) {
    ThreeLevels t;
    const FlatImage& img = t.scene.image();
    // The image placed by a scale of 10 (an Instance's placement) 100 m in front of the eye: the LOD's centre is
    // 100 m away in the world, though 10 units in image coordinates.
    const dmat4 place = glm::scale(glm::translate(dmat4(1.0), dvec3(0, 100, 0)), dvec3(10.0));
    const ImageFrame f = ImageFrame::make(img, place * glm::translate(dmat4(1.0), img.origin));
    EXPECT_FALSE(f.rigid);
    EXPECT_NEAR(f.scale, 10.0, 1e-9);
    const LodChooser ch({nullptr});
    EXPECT_NEAR(ch.value(f, t.entry), 100.0, 1e-9);
    EXPECT_EQ(children(shown(ch, f, t.entry)), std::vector<uint32_t>{2});
    // A rigid frame gives the same distance taken in image coordinates.
    const ImageFrame g = ImageFrame::make(img, glm::translate(dmat4(1.0), dvec3(0, 100, 0) + img.origin));
    EXPECT_TRUE(g.rigid);
    EXPECT_NEAR(ch.value(g, t.entry), 100.0, 1e-9);
}

}  // namespace
